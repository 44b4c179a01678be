/// \file body_contact.cpp
/// The body's share of the implicit step in the shawl scenes (scenes/shawl.toml: a shawl dropped on
/// the body mesh, 13,776 triangles; scenes/shawl_arms.toml: the body lowering its arms by key
/// frames), at cloths of about n x n vertices: the scene file's settings with the edge length that
/// gives the shawl the vertex density of an n x n grid over its 1.2 m square.
///
/// Each scene and n is advanced once, untimed, to t = 1 s (the shawl has landed; the arms are
/// moving); each repetition then starts a new integrator there and times S implicit steps one by one (dt = 1/60, the scene's solver, T threads). After
/// each, the contact handling of that step against the colliders is replayed on a second handler
/// from the same inputs and timed: detection into the solve's constraints (constrain(), which
/// also bounds the colliders and, for the moving body, interpolates its key frames and refits its
/// swept-box tree), one revise() per solve of the step with the step's final solution, the
/// response with friction (respond()) and the end-of-step check (keep_clear()). The share is the
/// replay's time over the step's. The handler is serial, so its share grows with the threads.
/// Also the refit alone: the moving body's two key-frame surfaces interpolated and the swept boxes
/// refitted (MeshSweep::update), per step. Medians over R repetitions; prints a markdown table
/// (docs/contact.md).
///
///   build/bench/drape_body_contact [n ...] [--steps S] [--threads T] [--repetitions R] [--scenes DIR]
///
/// Defaults: n = 33 65 129, S = 30, T = 2, R = 3, DIR = the source tree's scenes/.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "drape/collision/mesh_sweep.hpp"
#include "drape/contact/contact_handler.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/scene_file/build_scene.hpp"
#include "drape/scene_file/command_line.hpp"
#include "tool_text.hpp"

namespace {

struct Options {
  std::vector<int> sizes;
  int steps = 30, threads = 2, repetitions = 3;
  std::string scenes = DRAPE_BENCH_SCENES_DIR;
};

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Run {
  double step = 0, contact = 0, share = 0, refit = 0;
  int nodes = 0, contacts = 0, failures = 0;
};

/// The scene's settings with the edge length of an n x n grid's vertex density over its square.
drape::scene_file::Settings settings_at(const Options& o, const std::string& scene, int n) {
  const double side = 1.2;  // m, both shawl scenes
  // Equilateral triangles of edge e hold 2 / (sqrt(3) e^2) vertices per square metre.
  const double edge = side / (n - 1) * std::sqrt(2 / std::sqrt(3.0));
  drape::scene_file::Settings s =
      drape::scene_file::read_settings(o.scenes + "/" + scene + ".toml", {"--edge-length", std::to_string(edge)});
  s.stepping.threads = o.threads;
  return s;
}

/// The scene's state at t = 1 s, untimed.
drape::Stated advanced(const drape::Clothd& cloth, const drape::Stated& start, const drape::ImplicitOptions& options,
                       Run& out) {
  drape::ImplicitEuler<double> integrator(cloth, options);
  drape::Stated s = start;
  const int steps = int(std::lround(1.0 / options.dt));
  for (int k = 0; k < steps; ++k)
    if (!integrator.step(s).ok()) ++out.failures;
  return s;
}

/// One repetition from `from`: S steps, each followed by the replay of its contact handling.
void run_once(const drape::Clothd& cloth, const drape::Stated& from, const drape::ImplicitOptions& options,
              const Options& o, std::vector<double>& steps, std::vector<double>& contacts, Run& out) {
  drape::ImplicitEuler<double> integrator(cloth, options);
  drape::Stated s = from;
  drape::ContactHandler<double> handler(cloth.colliders(), cloth.contact_thickness(), cloth.masses());
  const std::vector<int>& row_of_node = integrator.assembler().row_of_node();
  const std::vector<std::uint8_t>& pinned = integrator.pins().mask();
  double step_time = 0, contact_time = 0;
  long long in_contact = 0;
  for (int k = 0; k < o.steps; ++k) {
    const drape::Stated before = s;
    Clock::time_point t0 = Clock::now();
    if (!integrator.step(s).ok()) ++out.failures;
    step_time += seconds_since(t0);
    in_contact += integrator.contact_report().contacts;
    // The step's result before its contact response: x + dt (v + dv), v + dv.
    const drape::LinearSystem<double>& system = integrator.system();
    const drape::VectorX<double>& dv = integrator.dv();
    drape::Matrix3X<double> x_new = before.positions, v_new = before.velocities;
    for (drape::Index i = 0; i < x_new.cols(); ++i) {
      const int row = row_of_node[std::size_t(i)];
      if (row < 0) continue;
      v_new.col(i) += dv.segment<3>(3 * row);
      x_new.col(i) += options.dt * v_new.col(i);
    }
    drape::ConstraintFilter<double> filter(system.constraints.rows());
    const int solves = std::max(1, integrator.contact_report().rounds);
    t0 = Clock::now();
    handler.constrain(before.positions, before.velocities, before.time, options.dt, row_of_node, filter);
    for (int r = 0; r < solves; ++r)
      handler.revise(system, dv, before.positions, before.velocities, options.dt, row_of_node, filter);
    handler.respond(before.positions, before.velocities, before.time, options.dt, x_new, v_new, pinned);
    handler.keep_clear(x_new, v_new, pinned);
    contact_time += seconds_since(t0);
  }
  steps.push_back(step_time / o.steps);
  contacts.push_back(contact_time / o.steps);
  out.contacts = int(in_contact / o.steps);
}

/// The moving body's refit per step: both key-frame surfaces interpolated, the swept boxes refitted.
double refit_time(const drape::Clothd& cloth, double dt) {
  for (const drape::Colliderd& collider : cloth.colliders()) {
    if (!collider.deforms()) continue;
    drape::Matrix3X<double> a, b;
    collider.mesh_positions(1.0, a);
    drape::MeshSweep<double> sweep(collider.mesh()->triangles(), a);
    const int count = 200;
    const Clock::time_point t0 = Clock::now();
    for (int k = 0; k < count; ++k) {
      const double t = 1.0 + k * dt;
      collider.mesh_positions(t, a);
      collider.mesh_positions(t + dt, b);
      sweep.update(a, b);
    }
    return seconds_since(t0) / count;
  }
  return 0;
}

Run measure(const Options& o, const std::string& scene, int n) {
  const drape::scene_file::Settings s = settings_at(o, scene, n);
  const drape::scene_file::PreparedScene prepared = drape::scene_file::prepare_scene(s);
  const drape::Clothd cloth = drape::scene_file::make_cloth(s, prepared.first);
  Run out;
  out.nodes = int(cloth.node_count());
  std::vector<double> steps, contacts, shares, refits;
  const drape::Stated from = advanced(cloth, prepared.start, s.stepping, out);
  for (int r = 0; r < o.repetitions; ++r) {
    run_once(cloth, from, s.stepping, o, steps, contacts, out);
    shares.push_back(contacts.back() / steps.back());
    refits.push_back(refit_time(cloth, s.stepping.dt));
  }
  out.step = median(steps);
  out.contact = median(contacts);
  out.share = median(shares);
  out.refit = median(refits);
  return out;
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](int& target) {
      if (i + 1 >= argc) return false;
      target = std::atoi(argv[++i]);
      return target > 0;
    };
    if (a == "--steps" || a == "--threads" || a == "--repetitions") {
      int& target = a == "--steps" ? o.steps : a == "--threads" ? o.threads : o.repetitions;
      if (!value(target)) return false;
    } else if (a == "--scenes" && i + 1 < argc) {
      o.scenes = argv[++i];
    } else {
      const int n = std::atoi(a.c_str());
      if (n < 9) return false;
      o.sizes.push_back(n);
    }
  }
  if (o.sizes.empty()) o.sizes = {33, 65, 129};
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: drape_body_contact [n >= 9 ...] [--steps S] [--threads T] [--repetitions R] [--scenes DIR]\n");
    return 2;
  }
  std::printf("| scene | n | vertices | contacts | implicit step | body contact | share | refit |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
  int failures = 0;
  for (const char* scene : {"shawl", "shawl_arms"})
    for (const int n : o.sizes) {
      const Run r = measure(o, scene, n);
      failures += r.failures;
      std::printf("| %s | %d | %d | %d | %s | %s | %.1f%% | %s |\n", scene, n, r.nodes, r.contacts,
                  drape_bench::duration(r.step).c_str(), drape_bench::duration(r.contact).c_str(), 100 * r.share,
                  r.refit > 0 ? drape_bench::duration(r.refit).c_str() : "-");
      std::fflush(stdout);
    }
  std::printf("\n%d threads, median of %d repetitions of %d steps from t = 1 s; failed steps: %d\n", o.threads,
              o.repetitions, o.steps, failures);
  return failures == 0 ? 0 : 1;
}
