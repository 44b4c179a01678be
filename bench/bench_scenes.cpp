/// \file bench_scenes.cpp
/// The example scenes with colliders, air and moving pins (scenes/*.toml) as benchmarks of the
/// implicit step (dt = 1/60, cg + multigrid, Spd, 2 threads) in each scene's own situation:
///  - `scene_step/drape/scene=drop_on_sphere`: a free cloth on a sphere standing on a floor
///    (scenes/drop_on_sphere.toml), timed from t = 1.0 s, when it lies draped over the sphere;
///  - `scene=tablecloth`: a free cloth on a rounded box turned 45 degrees, on a floor
///    (scenes/tablecloth.toml), from t = 1.0 s, lying on the table and hanging over its edges;
///  - `scene=flag`: a flag pinned along its edge i = 0 in gusty wind with linear drag and
///    per-triangle aerodynamic drag and lift (scenes/flag.toml), from t = 1.0 s;
///  - `scene=curtain`: a curtain hanging from rings that slide along key-frame paths
///    (scenes/curtain.toml), from t = 2.0 s, half a second into the draw (1.5 s to 3.5 s), so the
///    rings move during the whole timed window.
/// And `contact_detection/drape/scene=drop_on_sphere`: the contact handling of one implicit step of
/// the drop alone (ContactHandler's constrain(), one revise(), respond() and keep_clear(), serial), which grows
/// linearly in the nodes.
///
/// Sizes: n = 33, 65, 129, n x n nodes. This is a benchmark of cost, not of physics: at every n the
/// cloth keeps the scene's physical size (spacing = side / (n - 1)) and total mass (node mass =
/// total / n^2) and the scene's spring constants (so the cloth gets stiffer per unit of mass as n
/// grows, and its motion differs a little from size to size). Colliders, pin paths and the wind
/// stay in metres, seconds and m/s as in the scene files. Exceptions, each at its scene below: the
/// flag's linear drag per node scales with the node mass (the same drag per unit of area); the
/// curtain is n x n nodes (1.6 x 1.6 m instead of the file's 41 x 31 nodes, 1.6 x 1.2 m, so that
/// every family has n^2 nodes as scripts/bench_report.py assumes) and has 9 rings instead of 11.
///
/// Each (scene, n) is advanced once, untimed, from its flat start to its timed moment (drape's
/// implicit step at the same settings, on 1 thread: immune to a busy machine), and cached; a benchmark
/// then steps on from that state and resets to it every `implicit_window` steps (run_steps), so
/// the timed window is 0.5 s of the scene from that moment. Counters as environment_step:
/// `contacts` (nodes in contact per step), `solves` (linear solves per step: more than 1 when the
/// contact set changes), `cg_iterations` (per step, all solves), `failures`, and `warm_failures`
/// (failed steps of the untimed advance; 0 in a sound run).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench_common.hpp"
#include "drape/contact/collider.hpp"
#include "drape/contact/contact_handler.hpp"
#include "drape/core/pin_path.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/physics/air.hpp"

namespace drape_bench {
namespace {

using drape::Collider;
using drape::Vec3;

constexpr double scene_dt = 1.0 / 60.0;

enum class SceneKind { DropOnSphere, Tablecloth, Flag, Curtain };

const char* label(SceneKind kind) {
  switch (kind) {
    case SceneKind::DropOnSphere: return "drop_on_sphere";
    case SceneKind::Tablecloth: return "tablecloth";
    case SceneKind::Flag: return "flag";
    case SceneKind::Curtain: return "curtain";
  }
  return "";
}

/// A scene at n x n nodes: the cloth, the pins that follow paths (set on each integrator: they
/// belong to its PinSet, not to the cloth) and the simulated time of the timed moment.
struct SceneSetup {
  drape::ClothSpec<double> spec;
  std::vector<std::pair<int, drape::PinPath<double>>> moving_pins;
  double timed_from = 1.0;  ///< s
};

/// n x n nodes spanning `side` metres with `total_mass` kilograms in all (see the file comment).
void scale_grid(drape::ClothSpec<double>& spec, int n, double side, double total_mass) {
  spec.nx = n;
  spec.ny = n;
  spec.spacing = side / (n - 1);
  spec.node_mass = total_mass / (double(n) * n);
}

/// The light cloth of the drop, the tablecloth and the curtain (structural, shear, bend).
constexpr drape::SpringCoefficients<double> light_springs{{2000.0, 0.1}, {500.0, 0.05}, {2.0, 0.01}};

Collider<double> floor_at(double height, double friction) {
  return Collider<double>::plane(Vec3<double>(0, height, 0), Vec3<double>(0, 1, 0)).set_friction(friction, friction);
}

SceneSetup make_scene(SceneKind kind, int n) {
  SceneSetup s;
  drape::ClothSpec<double>& spec = s.spec;
  spec.gravity = 10;
  spec.contact_thickness = 0.005;
  spec.pinned_nodes = std::vector<int>{};  // pins = [] in every file but the flag's
  switch (kind) {
    case SceneKind::DropOnSphere:
      // scenes/drop_on_sphere.toml: 33 x 33 nodes 5 cm apart (1.6 m), 0.5 g each; released flat
      // 0.2 m above a sphere of radius 0.4 m under its centre, on a floor at y = -1; friction 0.1.
      scale_grid(spec, n, 1.6, 33 * 33 * 0.0005);
      spec.springs = light_springs;
      spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(0.8, -0.6, 0.8), 0.4).set_friction(0.1, 0.1));
      spec.colliders.push_back(floor_at(-1.0, 0.1));
      s.timed_from = 1.0;
      break;
    case SceneKind::Tablecloth:
      // scenes/tablecloth.toml: 41 x 41 nodes 4 cm apart (1.6 m), 0.3 g each; released flat 0.1 m
      // above a box 0.9 x 0.7 x 0.9 m turned 45 degrees about y, edges rounded 8 cm, on a floor at
      // y = -0.8; friction 0.15 static / 0.1 kinetic on the table, 0.3 on the floor.
      scale_grid(spec, n, 1.6, 41 * 41 * 0.0003);
      spec.springs = light_springs;
      spec.colliders.push_back(
          Collider<double>::box(
              Vec3<double>(0.8, -0.45, 0.8), Vec3<double>(0.45, 0.35, 0.45),
              Eigen::AngleAxisd(0.25 * 3.14159265358979323846, Vec3<double>::UnitY()).toRotationMatrix(), 0.08)
              .set_friction(0.15, 0.1));
      spec.colliders.push_back(floor_at(-0.8, 0.3));
      s.timed_from = 1.0;
      break;
    case SceneKind::Flag: {
      // scenes/flag.toml: the default 33 x 33 cloth (3.2 m, default springs) at a third of its mass
      // (0.01 kg per node), pinned along i = 0; wind 8 m/s along +x with gusts of 3 m/s (period
      // 1.5 s, wavelength 6 m, 4 waves, seed 42), linear drag 0.002 N s/m per node (here scaled
      // with the node mass), aerodynamic drag 1.2 and lift 0.5 at air density 1.2.
      scale_grid(spec, n, 3.2, 33 * 33 * 0.01);
      std::vector<int> pole;
      for (int j = 0; j < n; ++j) pole.push_back(j * n);
      spec.pinned_nodes = pole;
      drape::AirSettings air;
      air.wind = {8, 0, 0};
      air.drag = 0.002 * (33.0 * 33.0) / (double(n) * n);
      air.aerodynamics.density = 1.2;
      air.aerodynamics.drag_coefficient = 1.2;
      air.aerodynamics.lift_coefficient = 0.5;
      air.gusts.amplitude = 3;
      air.gusts.period = 1.5;
      air.gusts.wavelength = 6;
      air.gusts.waves = 4;
      air.gusts.seed = 42;
      const drape::Grid<double> grid(spec.nx, spec.ny, spec.spacing, spec.node_mass);
      spec.force_terms = drape::air_force_terms<double>(air, grid.triangles());
      s.timed_from = 1.0;
      break;
    }
    case SceneKind::Curtain: {
      // scenes/curtain.toml: 41 x 31 nodes 4 cm apart (1.6 x 1.2 m), 0.5 g each, hanging from 11
      // rings (top row j = 0, every 4th node, 0.16 m apart). The ring at x = 0 holds; from 1.5 s to
      // 3.5 s the others slide along smooth key-frame paths to 0.375 of their distance from it
      // (16 cm -> 6 cm apart), alternately 5 cm in front of and behind the rail. Here: n x n nodes,
      // 1.6 m wide and tall (see the file comment), the file's total mass; (n - 1) is 32, 64, 128,
      // not a multiple of 10, so 9 rings every (n - 1) / 8 nodes, 0.2 m apart (every 4th node at
      // n = 33, as in the file), each drawn to 0.375 of its distance (to 7.5 cm apart, the same
      // 0.6 m gathered width as the file's). The file releases the leading ring at 4.5 s, after
      // the timed window (2.0 s to 2.5 s): not modelled.
      scale_grid(spec, n, 1.6, 41 * 31 * 0.0005);
      spec.springs = light_springs;
      constexpr int rings = 9;
      const int every = (n - 1) / (rings - 1);
      for (int k = 0; k < rings; ++k) {
        const int node = k * every;  // (i = k * every, j = 0)
        if (k == 0) {
          s.moving_pins.emplace_back(node, drape::PinPath<double>());  // holds still
          continue;
        }
        const double x0 = k * every * spec.spacing;
        const Vec3<double> start(x0, 0, 0), end(0.375 * x0, 0, k % 2 == 1 ? 0.05 : -0.05);
        s.moving_pins.emplace_back(
            node, drape::PinPath<double>::keyframes({1.5, 3.5}, {start, end}, drape::Interpolation::Smooth));
      }
      s.timed_from = 2.0;
      break;
    }
  }
  return s;
}

drape::ImplicitOptions scene_options(int threads) {
  drape::ImplicitOptions options;  // cg + multigrid, Spd
  options.dt = scene_dt;
  options.threads = threads;
  return options;
}

/// A scene at one size, advanced to its timed moment.
struct SceneCase {
  Scene scene;
  std::vector<std::pair<int, drape::PinPath<double>>> moving_pins;
  int warm_failures = 0;

  std::unique_ptr<drape::ImplicitEuler<double>> integrator(int threads) const {
    auto integrator = std::make_unique<drape::ImplicitEuler<double>>(*scene.cloth, scene_options(threads));
    for (const auto& [node, path] : moving_pins) integrator->pins().pin(node, path);
    return integrator;
  }
};

const SceneCase& scene_case(SceneKind kind, int n) {
  static std::map<std::pair<SceneKind, int>, SceneCase> cache;
  auto it = cache.find({kind, n});
  if (it != cache.end()) return it->second;
  SceneSetup setup = make_scene(kind, n);
  SceneCase c;
  c.scene.cloth = std::make_unique<drape::Cloth<double>>(setup.spec);
  c.moving_pins = std::move(setup.moving_pins);
  c.scene.warm = c.scene.cloth->initial_state();
  // One thread: bitwise the same as 2, and immune to a busy machine (as warm_up()).
  const auto integrator = c.integrator(1);
  const int steps = int(std::lround(setup.timed_from / scene_dt));
  for (int k = 0; k < steps; ++k)
    if (!integrator->step(c.scene.warm)) ++c.warm_failures;
  if (c.warm_failures > 0 || !c.scene.warm.all_finite())
    std::fprintf(stderr, "drape_bench: scene %s at n = %d: %d of %d steps to t = %g s failed\n", label(kind), n,
                 c.warm_failures, steps, setup.timed_from);
  c.scene.compressed_fraction = compressed_fraction(*c.scene.cloth, c.scene.warm.positions);
  c.scene.max_speed = c.scene.warm.velocities.colwise().norm().maxCoeff();
  return cache.emplace(std::make_pair(kind, n), std::move(c)).first->second;
}

void scene_step(benchmark::State& st, SceneKind kind) {
  const SceneCase& c = scene_case(kind, int(st.range(0)));
  const auto integrator = c.integrator(int(st.range(1)));
  long long contacts = 0, solves = 0, steps = 0;
  run_steps(
      st, c.scene, implicit_window,
      [&](drape::State<double>& s) {
        const drape::StepStatus status = integrator->step(s);
        contacts += integrator->contact_report().contacts;
        solves += std::max(1, integrator->contact_report().rounds);
        ++steps;
        return status;
      },
      true);
  st.counters["contacts"] = steps ? double(contacts) / double(steps) : 0.0;
  st.counters["solves"] = steps ? double(solves) / double(steps) : 0.0;
  st.counters["warm_failures"] = double(c.warm_failures);
}

/// The inputs of the contact handling of one implicit step of the drop from its timed moment:
/// the step's system and solution (revise()) and its result before the contact response
/// (respond()).
struct ContactInputs {
  std::unique_ptr<drape::ImplicitEuler<double>> integrator;  // holds the step's system
  drape::VectorX<double> dv;
  drape::Matrix3X<double> x_new, v_new;  // x + dt (v + dv), v + dv: the result respond() corrects
  int failures = 0;
};

const ContactInputs& contact_inputs(int n) {
  static std::map<int, ContactInputs> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const SceneCase& c = scene_case(SceneKind::DropOnSphere, n);
  ContactInputs in;
  in.integrator = c.integrator(1);
  drape::State<double> end = c.scene.warm;
  if (!in.integrator->step(end)) ++in.failures;
  in.dv = in.integrator->dv();
  const std::vector<int>& row_of_node = in.integrator->assembler().row_of_node();
  const drape::State<double>& start = c.scene.warm;
  in.x_new = start.positions;
  in.v_new = start.velocities;
  for (int i = 0; i < c.scene.cloth->node_count(); ++i) {
    const int row = row_of_node[std::size_t(i)];
    if (row < 0) continue;
    in.v_new.col(i) += in.dv.segment<3>(3 * row);
    in.x_new.col(i) = start.positions.col(i) + scene_dt * in.v_new.col(i);
  }
  return cache.emplace(n, std::move(in)).first->second;
}

/// The contact handling of the drop's implicit step alone: detection of every node against the
/// sphere and the floor (broad phase, swept test) into the solve's constraints (constrain()), one
/// round of impulses and newly reached nodes (revise(); the step may run more, see
/// scene_step's `solves`), and the contact response with friction and the end-of-step check
/// (respond(), keep_clear()). Serial (the handler is). Each iteration also copies the step's result into the
/// buffers respond() corrects in place (48 bytes per node: about 2% of the time at every n).
void contact_detection(benchmark::State& st) {
  const int n = int(st.range(0));
  const SceneCase& c = scene_case(SceneKind::DropOnSphere, n);
  const ContactInputs& in = contact_inputs(n);
  const drape::Cloth<double>& cloth = *c.scene.cloth;
  const drape::LinearSystem<double>& system = in.integrator->system();
  const std::vector<int>& row_of_node = in.integrator->assembler().row_of_node();
  const std::vector<std::uint8_t>& pinned = in.integrator->pins().mask();
  const drape::State<double>& s = c.scene.warm;
  drape::ContactHandler<double> handler(cloth.colliders(), cloth.contact_thickness(), cloth.grid().masses());
  drape::ConstraintFilter<double> filter(system.constraints.rows());
  drape::Matrix3X<double> x_new = in.x_new, v_new = in.v_new;
  long long contacts = 0, steps = 0;
  for (auto _ : st) {
    handler.constrain(s.positions, s.velocities, s.time, scene_dt, row_of_node, filter);
    handler.revise(system, in.dv, s.positions, s.velocities, scene_dt, row_of_node, filter);
    x_new = in.x_new;
    v_new = in.v_new;
    handler.respond(s.positions, s.velocities, s.time, scene_dt, x_new, v_new, pinned);
    handler.keep_clear(x_new, v_new, pinned);
    benchmark::DoNotOptimize(x_new.data());
    benchmark::ClobberMemory();
    contacts += handler.report().contacts;
    ++steps;
  }
  st.counters["contacts"] = steps ? double(contacts) / double(steps) : 0.0;
  st.counters["failures"] = double(in.failures + c.warm_failures);
  st.counters["nodes"] = double(cloth.node_count());
  st.SetItemsProcessed(st.iterations() * cloth.node_count());
}

const bool registered = [] {
  for (const SceneKind kind : {SceneKind::DropOnSphere, SceneKind::Tablecloth, SceneKind::Flag, SceneKind::Curtain})
    sized(
        benchmark::RegisterBenchmark((std::string("scene_step/drape/scene=") + label(kind)).c_str(), scene_step, kind),
        two, benchmark::kMillisecond, 129, quick_min_time);
  sized(benchmark::RegisterBenchmark("contact_detection/drape/scene=drop_on_sphere", contact_detection), serial,
        benchmark::kMicrosecond, 129, quick_min_time);
  return true;
}();

}  // namespace
}  // namespace drape_bench
