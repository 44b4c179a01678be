/// \file garment_cost.cpp
/// What the T-shirt's time is spent on (scenes/shirt.toml: GarmentCode's T-shirt sewn onto the
/// female SMPL body, implicit Euler at dt = 1/60 with CHOLMOD, 2.5 s, seams, ramped gravity,
/// self-collision on), at several edge lengths: the scene file's settings read through the
/// scene-file library with `--edge-length` over them, T threads.
///
/// **The whole run**, as drape-render steps it. The set-up: the scene file read (the pattern read,
/// meshed and sewn, the body's OBJ read), prepare_scene() and a drape::ClothScene of the scene's
/// cloth (the body's tree, the self-collision hierarchy, CHOLMOD's analysis). Then every step from
/// placement to the scene's duration, each timed: the run's wall time is their sum, the step time
/// their median. Also the steps in which self-collision needed its fail-safe and those it left
/// with a pair crossing, the kinetic energy at the end and whether every step returned ok.
///
/// **The split of a step**, from the run's state at t = F s (default 1.25: the seams closed at
/// 1 s, gravity on since 1.2 s), over S steps. ClothScene steps one cloth with self-collision
/// as three phases: the integrator's step (assembly, contacts as constraints of the solve, the
/// solves, the collider response and the end-of-step check; self-collision off in the cloth),
/// then the scene's self-collision handler on the whole result, then the colliders' end-of-step
/// check again, alternating with self-collision while the check pushes nodes out
/// (SelfCollisionHandler::respond_and_keep_clear). The tool takes these phases itself in that
/// order, on a new integrator and handler from the state at F, and times each; a ClothScene
/// stepped beside it from the same state (untimed) must give the same positions and velocities
/// bit for bit, and the output says whether it did.
/// - **self-collision**: the handler's passes (proximity, continuous tests with impulses,
///   impact zones when needed), timed where they run.
/// - **body contact**: the contact handling inside the integrator's step, replayed after it on a
///   second handler from the same inputs as bench/body_contact.cpp does (detection into the
///   solve's constraints with the body's bounds, one revise() per solve of the step with its
///   final solution, the response, the end-of-step check), plus the scene's end-of-step checks
///   after self-collision, timed where they run.
/// - **assembly**: JacobianAssembler::assemble_system() replayed on a second assembler and
///   system from the step's start state (springs, dihedral bending, seams, ramped gravity).
/// - **seams** (part of the assembly): the seam term's SeamSprings::add_force_and_derivatives()
///   at the step's start state, written into a copy of the system through a sink that finds and
///   updates the blocks and right-hand side as the assembly's does; the mean of 10 calls.
/// - **solve**: the step's linear solves replayed on a second solver of the scene's kind
///   (analysed once): the replayed system with the step's final contact constraints, solved as
///   many times as the step solved (contact rounds); CHOLMOD refactorises at every solve.
/// - **rest**: the integrator's step minus its replayed assembly, solve and contact handling
///   (the update x += dt v, copies, and the replays' differences from the real phases).
/// Each column is its time summed over the S steps and divided by S (the mean per step), so the
/// parts add up to the step and each share is of the time spent; the counts (solves, nodes in
/// contact with the body, self-collision proximity pairs) are medians over the steps, with the
/// number of steps in which self-collision needed its fail-safe (impact zones) and of those in
/// which the fail-safe gave up with a pair still crossing (SelfCollisionReport::unresolved). The
/// assembly uses the T threads; CHOLMOD (OpenBLAS pinned to one thread), the contacts and
/// self-collision are serial.
///
/// R runs of both (each split from its own run's state); every figure is the median over them.
///
///   build/release/bench/drape_garment_cost [edge_cm ...] [--runs R] [--steps S] [--from F]
///                                          [--threads T] [--scenes DIR]
///
/// Defaults: edge 1.0 1.25 1.5 2.0 cm, R = 1, S = 30, F = 1.25, T = 2, DIR = the source tree's
/// scenes/. Prints markdown tables (docs/garments.md, "Cost").

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "drape/contact/contact_handler.hpp"
#include "drape/contact/self_collision.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/seam_springs.hpp"
#include "drape/scene/cloth_scene.hpp"
#include "drape/scene_file/build_scene.hpp"
#include "drape/scene_file/command_line.hpp"
#include "tool_text.hpp"

namespace {

struct Options {
  std::vector<double> edges_cm;
  int runs = 1, steps = 30, threads = 2;
  double from = 1.25;
  std::string scenes = DRAPE_BENCH_SCENES_DIR;
};

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// One edge length's measurements.
struct Result {
  double edge_cm = 0;
  int vertices = 0, triangles = 0, seam_pairs = 0, steps = 0;
  double setup = 0, run = 0, step = 0, kinetic = 0;
  double run_zone_steps = 0, run_unresolved_steps = 0;  // over the run: fail-safe ran; crossings left
  bool ok = true;
  // The split: means per step over the sampled steps.
  double split_step = 0, assembly = 0, seams = 0, solve = 0, contact = 0, self = 0, rest = 0;
  double solves = 0, contacts = 0, proximity = 0;  // medians over the sampled steps
  double zone_steps = 0, unresolved_steps = 0;     // sampled steps: fail-safe ran; crossings left
  int sampled = 0;
  bool split_ok = true, same_as_scene = true;
};

double mean(const std::vector<double>& v) {
  double sum = 0;
  for (const double x : v) sum += x;
  return v.empty() ? 0 : sum / double(v.size());
}

drape::scene_file::Settings settings_at(const Options& o, double edge_cm) {
  drape::scene_file::Settings s =
      drape::scene_file::read_settings(o.scenes + "/shirt.toml", {"--edge-length", std::to_string(edge_cm / 100)});
  s.stepping.threads = o.threads;
  return s;
}

/// The first seam term of the cloth (the garment's SeamSprings), or null.
const drape::SeamSprings<double>* seam_term(const drape::Clothd& cloth) {
  for (const auto& term : cloth.force_terms())
    if (const auto* seams = dynamic_cast<const drape::SeamSprings<double>*>(term.get())) return seams;
  return nullptr;
}

/// A force term's derivative blocks into an implicit system, as the assembly writes them:
/// A -= dt dfdv + dt^2 dfdx on the block found in the pattern, b += dt^2 dfdx v.
class SystemSink final : public drape::ForceDerivatives<double> {
 public:
  SystemSink(drape::LinearSystem<double>& system, const std::vector<int>& row_of_node,
             const drape::Matrix3X<double>& v, double dt)
      : m_system(system), m_row_of_node(row_of_node), m_v(v), m_dt(dt) {}
  bool symmetric() const override { return true; }
  void add(int a, int b, const drape::Mat3<double>& dfdx, const drape::Mat3<double>& dfdv) override {
    const int ra = m_row_of_node[std::size_t(a)], rb = m_row_of_node[std::size_t(b)];
    if (ra < 0) return;
    m_system.rhs.segment<3>(3 * ra) += m_dt * m_dt * (dfdx * m_v.col(b));
    if (rb < 0) return;
    const int block = ra == rb ? m_system.matrix.diagonal()[std::size_t(ra)] : m_system.matrix.find(ra, rb);
    if (block >= 0) m_system.matrix.block(block) -= m_dt * dfdv + m_dt * m_dt * dfdx;
  }

 private:
  drape::LinearSystem<double>& m_system;
  const std::vector<int>& m_row_of_node;
  const drape::Matrix3X<double>& m_v;
  double m_dt;
};

/// The whole run of one edge length, as drape-render steps it, into `out`: each step's time
/// appended to `steps`, and the state at o.from into `from`.
void whole_run(const Options& o, const drape::scene_file::Settings& s, Result& out, std::vector<double>& steps,
               drape::Stated& from) {
  Clock::time_point t0 = Clock::now();
  drape::scene_file::PreparedScene prepared = drape::scene_file::prepare_scene(s);
  drape::ClothScene<double> scene(prepared.specs, s.integrator, s.stepping, s.cloth.self_collision);
  scene.state(0) = std::move(prepared.start);
  out.setup = seconds_since(t0);
  const double dt = s.stepping.dt;
  const int count = int(std::llround(s.time.duration / dt));
  const int from_step = int(std::llround(o.from / dt));
  out.vertices = int(scene.cloth(0).node_count());
  out.triangles = int(scene.cloth(0).triangles().size());
  const drape::SeamSprings<double>* seams = seam_term(scene.cloth(0));
  out.seam_pairs = seams ? int(seams->pairs().size()) : 0;
  out.steps = count;
  for (int k = 0; k < count; ++k) {
    if (k == from_step) from = scene.state(0);
    t0 = Clock::now();
    const drape::StepStatus status = scene.step();
    const double t = seconds_since(t0);
    out.run += t;
    steps.push_back(t);
    if (!status.ok()) {
      out.ok = false;
      std::fprintf(stderr, "edge %.3g cm: step %d failed: %s\n", out.edge_cm, k, drape::to_string(status.error));
      return;
    }
    if (scene.collision_report().failsafe()) ++out.run_zone_steps;
    if (scene.collision_report().unresolved > 0) ++out.run_unresolved_steps;
  }
  out.kinetic = drape::kinetic_energy(scene.cloth(0), scene.state(0));
}

/// The split of S steps from `from`, the phases as ClothScene takes them (file comment).
void split(const Options& o, const drape::scene_file::Settings& s, const drape::Stated& from, Result& out) {
  const drape::scene_file::PreparedScene prepared = drape::scene_file::prepare_scene(s);
  const drape::ImplicitOptions& options = s.stepping;
  const double dt = options.dt;
  // The cloth and handler as ClothScene makes them for one cloth with collisions on.
  drape::ClothSpecd spec = prepared.specs.front();
  spec.self_collision.enabled = false;
  const drape::Clothd cloth(spec);
  drape::SelfCollisionSettings<double> collisions = s.cloth.self_collision;
  for (const std::array<int, 2>& p : cloth.self_collision().joined_nodes) collisions.joined_nodes.push_back(p);
  drape::SelfCollisionHandler<double> self(collisions, cloth.contact_thickness(), cloth.triangles(), cloth.masses(),
                                           cloth.start_positions());
  drape::ImplicitEuler<double> integrator(cloth, options);
  drape::Stated state = from;
  // The same steps by ClothScene itself (untimed): the phases above must give its bits.
  drape::ClothScene<double> check(prepared.specs, s.integrator, options, s.cloth.self_collision);
  check.state(0) = from;
  // Replays: a second contact handler, assembler, system and solver.
  drape::ContactHandler<double> contacts(cloth.colliders(), cloth.contact_thickness(), cloth.masses());
  drape::JacobianAssembler<double> assembler(cloth, options.pin_treatment, options.threads);
  drape::LinearSystem<double> system = assembler.make_system();
  drape::LinearSystem<double> seam_system = assembler.make_system();
  std::unique_ptr<drape::LinearSolver<double>> solver =
      drape::make_linear_solver<double>(options.solver, options.iterative_settings());
  solver->analyze(system);
  drape::VectorX<double> dv = drape::VectorX<double>::Zero(system.size());
  drape::Matrix3X<double> seam_force = drape::Matrix3X<double>::Zero(3, cloth.node_count());
  const drape::SeamSprings<double>* seams = seam_term(cloth);
  const std::vector<int>& row_of_node = integrator.assembler().row_of_node();
  const std::vector<std::uint8_t>& pinned = integrator.pins().mask();

  std::vector<double> steps, assemblies, seam_times, solve_times, contact_times, self_times, rests;
  std::vector<double> solve_counts, contact_counts, proximity_counts;
  for (int k = 0; k < o.steps; ++k) {
    const drape::Stated before = state;
    // The three phases of ClothScene::step() for one cloth, each timed.
    Clock::time_point t0 = Clock::now();
    const drape::StepStatus status = integrator.step(state);
    const double t_integrator = seconds_since(t0);
    if (!status.ok()) {
      out.split_ok = false;
      break;
    }
    double t_clear = 0;
    t0 = Clock::now();
    self.respond_and_keep_clear(
        before.positions, dt, state.positions, state.velocities, pinned,
        [&](int i) { return integrator.contact_handler().hold(i); },
        [&](drape::Ref3X<double> x1, drape::Ref3X<double> v1) {
          const Clock::time_point t1 = Clock::now();
          const int pushed = integrator.keep_clear(x1, v1);
          t_clear += seconds_since(t1);
          return pushed;
        });
    const double t_self = seconds_since(t0) - t_clear;
    if (!check.step().ok() || check.state(0).positions != state.positions ||
        check.state(0).velocities != state.velocities)
      out.same_as_scene = false;

    // Replay: the assembly from the step's start state.
    t0 = Clock::now();
    assembler.assemble_system(before.positions, before.velocities, before.time, dt, options.jacobian, system);
    const double t_assembly = seconds_since(t0);
    // Replay: the seam term alone (10 calls), into a copy of the system.
    double t_seams = 0;
    if (seams) {
      constexpr int calls = 10;
      seam_system.matrix = system.matrix;
      seam_system.rhs = system.rhs;
      SystemSink sink(seam_system, row_of_node, before.velocities, dt);
      t0 = Clock::now();
      for (int c = 0; c < calls; ++c)
        seams->add_force_and_derivatives(before.positions, before.velocities, before.time, seam_force, sink);
      t_seams = seconds_since(t0) / calls;
    }
    // Replay: the step's solves with its final contact constraints.
    const int solves = std::max(1, integrator.contact_report().rounds);
    system.constraints = integrator.system().constraints;
    t0 = Clock::now();
    for (int r = 0; r < solves; ++r)
      if (!solver->solve(system, dv).ok()) out.split_ok = false;
    const double t_solve = seconds_since(t0);
    // Replay: the contact handling, from the step's result before its response (x + dt (v + dv)).
    const drape::VectorX<double>& step_dv = integrator.dv();
    drape::Matrix3X<double> x_new = before.positions, v_new = before.velocities;
    for (drape::Index i = 0; i < x_new.cols(); ++i) {
      const int row = row_of_node[std::size_t(i)];
      if (row < 0) continue;
      v_new.col(i) += step_dv.segment<3>(3 * row);
      x_new.col(i) += dt * v_new.col(i);
    }
    drape::ConstraintFilter<double> filter(integrator.system().constraints.rows());
    t0 = Clock::now();
    contacts.constrain(before.positions, before.velocities, before.time, dt, row_of_node, filter);
    for (int r = 0; r < solves; ++r)
      contacts.revise(integrator.system(), step_dv, before.positions, before.velocities, dt, row_of_node, filter);
    contacts.respond(before.positions, before.velocities, before.time, dt, x_new, v_new, pinned);
    contacts.keep_clear(x_new, v_new, pinned);
    const double t_contact = seconds_since(t0);

    steps.push_back(t_integrator + t_self + t_clear);
    assemblies.push_back(t_assembly);
    seam_times.push_back(t_seams);
    solve_times.push_back(t_solve);
    contact_times.push_back(t_contact + t_clear);
    self_times.push_back(t_self);
    rests.push_back(t_integrator - t_assembly - t_solve - t_contact);
    solve_counts.push_back(solves);
    contact_counts.push_back(integrator.contact_report().contacts);
    proximity_counts.push_back(self.report().proximity_pairs);
    if (self.report().failsafe()) ++out.zone_steps;
    if (self.report().unresolved > 0) ++out.unresolved_steps;
  }
  out.sampled = int(steps.size());
  out.split_step = mean(steps);
  out.assembly = mean(assemblies);
  out.seams = mean(seam_times);
  out.solve = mean(solve_times);
  out.contact = mean(contact_times);
  out.self = mean(self_times);
  out.rest = mean(rests);
  out.solves = median(solve_counts);
  out.contacts = median(contact_counts);
  out.proximity = median(proximity_counts);
}

Result measure(const Options& o, double edge_cm) {
  const Clock::time_point t0 = Clock::now();
  const drape::scene_file::Settings s = settings_at(o, edge_cm);
  const double reading = seconds_since(t0);
  if (s.integrator != drape::IntegratorKind::Implicit || s.cloth.colliders.empty() || !s.cloth.self_collision.enabled)
    throw std::runtime_error("shirt.toml: the tool needs the implicit integrator, a collider and self-collision");
  if (!(o.from + s.stepping.dt < s.time.duration))
    throw std::runtime_error("--from " + std::to_string(o.from) + ": the split must start before the scene ends");
  std::vector<Result> parts;
  std::vector<double> steps;
  for (int r = 0; r < o.runs; ++r) {
    Result part;
    part.edge_cm = edge_cm;
    drape::Stated from;
    whole_run(o, s, part, steps, from);
    if (part.ok) split(o, s, from, part);
    parts.push_back(part);
    if (!part.ok) break;
  }
  Result out = parts.front();
  for (const Result& part : parts) {
    out.ok = out.ok && part.ok;
    out.split_ok = out.split_ok && part.split_ok;
    out.same_as_scene = out.same_as_scene && part.same_as_scene;
  }
  for (double Result::*field :
       {&Result::setup, &Result::run, &Result::kinetic, &Result::run_zone_steps, &Result::run_unresolved_steps,
        &Result::split_step, &Result::assembly, &Result::seams, &Result::solve, &Result::contact, &Result::self,
        &Result::rest, &Result::solves, &Result::contacts, &Result::proximity, &Result::zone_steps,
        &Result::unresolved_steps}) {
    std::vector<double> v;
    for (const Result& part : parts) v.push_back(part.*field);
    out.*field = median(v);
  }
  out.setup += reading;
  out.step = median(steps);
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
    if (a == "--runs" || a == "--steps" || a == "--threads") {
      int& target = a == "--runs" ? o.runs : a == "--steps" ? o.steps : o.threads;
      if (!value(target)) return false;
    } else if (a == "--from" && i + 1 < argc) {
      o.from = std::atof(argv[++i]);
      if (!(o.from >= 0)) return false;
    } else if (a == "--scenes" && i + 1 < argc) {
      o.scenes = argv[++i];
    } else {
      const double edge = std::atof(a.c_str());
      if (!(edge >= 0.5 && edge <= 10)) return false;
      o.edges_cm.push_back(edge);
    }
  }
  if (o.edges_cm.empty()) o.edges_cm = {1.0, 1.25, 1.5, 2.0};
  return true;
}

/// "12.6 ms (37%)": a part and its share of the whole; the rest may come out below zero.
std::string share(double part, double whole) {
  char text[64];
  const std::string time = part < 0 ? "-" + drape_bench::duration(-part) : drape_bench::duration(part);
  std::snprintf(text, sizeof text, "%s (%.0f%%)", time.c_str(), 100 * part / whole);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: drape_garment_cost [edge_cm in [0.5, 10] ...] [--runs R] [--steps S] [--from F] "
                 "[--threads T] [--scenes DIR]\n");
    return 2;
  }
  std::vector<Result> results;
  for (const double edge : o.edges_cm) {
    try {
      results.push_back(measure(o, edge));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "edge %.3g cm: %s\n", edge, e.what());
      return 1;
    }
    const Result& r = results.back();
    std::fprintf(stderr, "edge %.3g cm: %d vertices, run %s\n", edge, r.vertices, drape_bench::duration(r.run).c_str());
  }
  std::printf("| edge | vertices | triangles | seam pairs | steps | set-up | run (2.5 s simulated) | step (median) | "
              "fail-safe steps (crossings left) | kinetic energy at the end | ok |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const Result& r : results)
    std::printf("| %.3g cm | %d | %d | %d | %d | %s | %s | %s | %.0f (%.0f) | %.2g J | %s |\n", r.edge_cm, r.vertices,
                r.triangles, r.seam_pairs, r.steps, drape_bench::duration(r.setup).c_str(),
                drape_bench::duration(r.run).c_str(), drape_bench::duration(r.step).c_str(), r.run_zone_steps,
                r.run_unresolved_steps, r.kinetic, r.ok ? "ok" : "**failed**");
  std::printf("\n| edge | step (mean) | assembly | of which seams | solve (solves) | body contact (nodes) | "
              "self-collision (pairs; fail-safe steps, crossings left) | rest |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  bool all_ok = true, all_same = true;
  for (const Result& r : results) {
    all_ok = all_ok && r.ok && r.split_ok;
    all_same = all_same && r.same_as_scene;
    if (r.sampled == 0) {
      std::printf("| %.3g cm | - | - | - | - | - | - | - |\n", r.edge_cm);
      continue;
    }
    std::printf("| %.3g cm | %s | %s | %s | %s (%.0f) | %s (%.0f) | %s (%.0f; %.0f, %.0f) | %s |\n", r.edge_cm,
                drape_bench::duration(r.split_step).c_str(), share(r.assembly, r.split_step).c_str(),
                share(r.seams, r.split_step).c_str(), share(r.solve, r.split_step).c_str(), r.solves,
                share(r.contact, r.split_step).c_str(), r.contacts, share(r.self, r.split_step).c_str(), r.proximity,
                r.zone_steps, r.unresolved_steps, share(r.rest, r.split_step).c_str());
  }
  std::printf("\n%d threads; median of %d run(s); step (median): over the run's steps; fail-safe steps: steps in "
              "which self-collision moved impact zones, crossings left: of which it gave up with a pair still "
              "crossing; split: means per step over %d steps from t = %.3g s; the split's steps give ClothScene's "
              "bits: %s\n",
              o.threads, o.runs, o.steps, o.from, all_same ? "yes" : "**no**");
  return all_ok && all_same ? 0 : 1;
}
