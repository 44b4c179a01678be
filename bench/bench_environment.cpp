/// \file bench_environment.cpp
/// The cost of the environment in the implicit step (dt = 1/60, cg + multigrid, Spd, 2 threads):
/// the hanging cloth alone (`env=none`); in air: linear drag in a steady wind (`env=drag`), the
/// same in gusts (`env=drag_gusts`), per-triangle aerodynamic drag and lift in a steady wind
/// (`env=aerodynamic`), and all of them in gusts (`env=air`); with 8 analytic colliders out of its
/// reach (`env=colliders8`: the detection cost alone) and with one of them under the falling cloth
/// (`env=colliders8_touching`: contacts in the solve). Each next to `env=none` in the same run, so
/// the overhead is a ratio.

#include <algorithm>
#include <map>
#include <memory>
#include <utility>
#include <string>

#include "bench_common.hpp"
#include "drape/contact/collider.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/physics/air.hpp"

namespace drape_bench {
namespace {

using drape::Collider;
using drape::Vec3;

enum class Environment { None, Drag, DragGusts, Aerodynamic, Air, Colliders, Touching };

/// The benchmark scene's spec at size n with the environment `env`.
drape::ClothSpec<double> environment_spec(int n, Environment env) {
  drape::ClothSpec<double> spec = scene_spec(n);
  const double side = (n - 1) * spec.spacing;  // the cloth hangs in x-y from y = 0, x in [0, side]
  if (env == Environment::Drag || env == Environment::DragGusts || env == Environment::Aerodynamic ||
      env == Environment::Air) {
    drape::AirSettings air;
    air.wind = {4, 0, 3};
    if (env == Environment::DragGusts || env == Environment::Air) air.gusts.amplitude = 2;
    if (env != Environment::Aerodynamic) air.drag = 0.005;
    if (env == Environment::Aerodynamic || env == Environment::Air) {
      air.aerodynamics.drag_coefficient = 1.0;
      air.aerodynamics.lift_coefficient = 0.3;
    }
    const drape::Grid<double> grid(n, n, spec.spacing, spec.node_mass);
    spec.force_terms = drape::air_force_terms<double>(air, grid.triangles());
  }
  if (env == Environment::Colliders || env == Environment::Touching) {
    // The warm cloth is falling from its flat start at y = 0 (x, z in [0, side]): colliders over
    // it and a floor far below are out of its reach during the timed window; the broad phase
    // still has to rule out every node against each of them every step.
    const double c = 0.5 * side, up = 0.5 + 0.1 * side;
    spec.colliders.push_back(Collider<double>::plane(Vec3<double>(0, -3 * side - 1, 0), Vec3<double>(0, 1, 0)));
    spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(0.25 * side, up, c), 0.2 * side));
    spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(0.75 * side, up, c), 0.2 * side));
    spec.colliders.push_back(Collider<double>::capsule(Vec3<double>(0, up, 0), Vec3<double>(side, up, 0), 0.1 * side));
    spec.colliders.push_back(
        Collider<double>::capsule(Vec3<double>(0, up, side), Vec3<double>(side, up, side), 0.1 * side));
    spec.colliders.push_back(
        Collider<double>::box(Vec3<double>(c, up + 0.2 * side, c), Vec3<double>(0.3 * side, 0.1 * side, 0.3 * side)));
    spec.colliders.push_back(Collider<double>::box(Vec3<double>(c, up, -c),
                                                   Vec3<double>(0.3 * side, 0.1 * side, 0.3 * side),
                                                   drape::Mat3<double>::Identity(), 0.02 * side));
    if (env == Environment::Touching)  // under the middle of the falling cloth
      spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(c, -0.25 * side, c), 0.2 * side));
    else
      spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(c, up, 1.5 * side), 0.1 * side));
  }
  return spec;
}

const char* label(Environment env) {
  switch (env) {
    case Environment::None: return "none";
    case Environment::Drag: return "drag";
    case Environment::DragGusts: return "drag_gusts";
    case Environment::Aerodynamic: return "aerodynamic";
    case Environment::Air: return "air";
    case Environment::Colliders: return "colliders8";
    case Environment::Touching: return "colliders8_touching";
  }
  return "";
}

void environment_step(benchmark::State& st, Environment env) {
  const int n = int(st.range(0));
  static std::map<std::pair<int, Environment>, Scene> cache;
  auto it = cache.find({n, env});
  if (it == cache.end()) {
    Scene sc;
    sc.cloth = std::make_unique<drape::Cloth<double>>(environment_spec(n, env));
    sc.warm = scene(n).warm;  // the plain cloth's warm state: the same start for every environment
    sc.compressed_fraction = scene(n).compressed_fraction;
    it = cache.emplace(std::make_pair(n, env), std::move(sc)).first;
  }
  const Scene& sc = it->second;
  drape::ImplicitOptions options;
  options.dt = 1.0 / 60.0;
  options.threads = int(st.range(1));
  drape::ImplicitEuler<double> integrator(*sc.cloth, options);
  long long contacts = 0, solves = 0, steps = 0;
  run_steps(
      st, sc, implicit_window,
      [&](drape::State<double>& s) {
        const drape::StepStatus status = integrator.step(s);
        contacts += integrator.contact_report().contacts;
        solves += std::max(1, integrator.contact_report().rounds);
        ++steps;
        return status;
      },
      true);
  st.counters["contacts"] = steps ? double(contacts) / double(steps) : 0.0;
  st.counters["solves"] = steps ? double(solves) / double(steps) : 0.0;
}

const bool registered = [] {
  for (const Environment env : {Environment::None, Environment::Drag, Environment::DragGusts, Environment::Aerodynamic,
                                Environment::Air, Environment::Colliders, Environment::Touching})
    sized(benchmark::RegisterBenchmark((std::string("environment_step/drape/env=") + label(env)).c_str(),
                                       environment_step, env),
          two, benchmark::kMillisecond, 129, headline_min_time);
  return true;
}();

}  // namespace
}  // namespace drape_bench
