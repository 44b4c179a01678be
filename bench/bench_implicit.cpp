/// \file bench_implicit.cpp
/// The implicit integrator's families: Jacobian (system) assembly, the system mat-vec, linear solve
/// per solver, the full implicit step per solver and Jacobian variant at dt = 0.01 and 1/60, and
/// the implicit set-up, each next to the textbook baseline (baseline.hpp). Also the start-up accuracy check that the
/// figures are compared at equal accuracy (check_accuracy()).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <sstream>

#include "baseline.hpp"
#include "bench_common.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/solvers/enable_ldlt.hpp"  // opt-in solvers (solver_registry.hpp): measured and
#include "drape/solvers/enable_lu.hpp"    // ldlt is the reference of the accuracy check

namespace drape_bench {
namespace {

using drape::ImplicitEuler;
using drape::ImplicitOptions;
using drape::JacobianVariant;

struct TimeStep {
  const char* label;  ///< as it appears in benchmark names ('/' is the name separator)
  double dt;
};
constexpr TimeStep time_steps[] = {{"0.01", 0.01}, {"1_60", 1.0 / 60.0}};

/// A linear solver as the benchmarks run it: the library's solver and, for cg, its preconditioner.
struct SolverSetup {
  drape::LinearSolverKind solver;
  drape::PreconditionerKind preconditioner = ImplicitOptions{}.preconditioner;

  bool available() const { return drape::solver_available(solver); }
  bool iterative() const { return drape::solver_info(solver).capabilities.iterative; }
  /// The benchmark-name fragment: `/solver=cg/preconditioner=multigrid`, `/solver=cholmod`.
  std::string name() const {
    std::string out = std::string("/solver=") + drape::to_string(solver);
    if (solver == drape::LinearSolverKind::Cg) out += std::string("/preconditioner=") + drape::to_string(preconditioner);
    return out;
  }
  /// Largest grid of the direct solvers' benchmarks (see step_plans).
  int max_n() const {
    using K = drape::LinearSolverKind;
    return solver == K::Ldlt || solver == K::Lu ? 65 : solver == K::Umfpack ? 129 : 257;
  }
};

using Kind = drape::LinearSolverKind;
/// Every solver measured; cg with block Jacobi (the default before multigrid) is kept as the
/// reference that shows what the multigrid preconditioner buys.
const SolverSetup solver_setups[] = {
    {Kind::Cg, drape::PreconditionerKind::Multigrid}, {Kind::Cg, drape::PreconditionerKind::MultigridFloat},
    {Kind::Cg, drape::PreconditionerKind::BlockJacobi},
    {Kind::Bicgstab}, {Kind::Cholmod}, {Kind::Umfpack}, {Kind::Ldlt}, {Kind::Lu}};

/// What the implicit-step family runs. The default (cg, Spd) gets both time steps and 1 and 2
/// threads; the other solvers and variants run at dt = 1/60 on 2 threads for comparison. Eigen's
/// simplicial LDLT and SparseLU stop at 65 x 65 and UMFPACK at 129 x 129: one of their steps takes
/// tens of seconds at 257 x 257 (measured: a 257 x 257 solve took 27 s with either), which would
/// make the suite run for an hour without telling anything new.
struct StepPlan {
  SolverSetup setup;
  JacobianVariant jacobian;
  bool both_time_steps;
  const std::vector<int>* threads;
};
const StepPlan step_plans[] = {
    {{Kind::Cg, drape::PreconditionerKind::Multigrid}, JacobianVariant::Spd, true, &one_and_two},
    {{Kind::Cg, drape::PreconditionerKind::MultigridFloat}, JacobianVariant::Spd, true, &one_and_two},
    {{Kind::Cg, drape::PreconditionerKind::Multigrid}, JacobianVariant::Symmetric, false, &two},
    {{Kind::Cg, drape::PreconditionerKind::BlockJacobi}, JacobianVariant::Spd, false, &one_and_two},
    {{Kind::Bicgstab}, JacobianVariant::Spd, false, &two},
    {{Kind::Bicgstab}, JacobianVariant::Exact, false, &two},
    {{Kind::Cholmod}, JacobianVariant::Spd, true, &two},
    {{Kind::Umfpack}, JacobianVariant::Exact, false, &two},
    {{Kind::Ldlt}, JacobianVariant::Spd, false, &two},
    {{Kind::Lu}, JacobianVariant::Exact, false, &two},
};

ImplicitOptions options(const SolverSetup& setup, JacobianVariant jacobian, int threads, double dt) {
  ImplicitOptions o;  // defaults: tolerance 1e-6, iteration cap, eliminated pins
  o.dt = dt;
  o.solver = setup.solver;
  o.preconditioner = setup.preconditioner;
  o.jacobian = jacobian;
  o.threads = threads;
  return o;
}

std::string name(const char* family, const std::string& impl, const std::string& rest = "") {
  return std::string(family) + "/impl=" + impl + rest;
}

// ---- system (Jacobian) assembly ------------------------------------------------------------------

void jacobian_assembly_drape(benchmark::State& st, JacobianVariant jacobian) {
  const Scene& sc = scene(int(st.range(0)));
  const drape::JacobianAssembler<double> assembler(*sc.cloth, drape::PinTreatment::Eliminate, int(st.range(1)));
  drape::LinearSystem<double> system = assembler.make_system();
  for (auto _ : st) {
    assembler.assemble_system(sc.warm.positions, sc.warm.velocities, sc.warm.time, 1.0 / 60.0, jacobian, system);
    benchmark::DoNotOptimize(system.matrix.values());
    benchmark::DoNotOptimize(system.rhs.data());
    benchmark::ClobberMemory();
  }
  st.counters["threads_used"] = assembler.threads();
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

void jacobian_assembly_baseline(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  const BaselineImplicit baseline(*sc.cloth);
  BaselineImplicit::SparseMatrix a;
  BaselineImplicit::Vector rhs;
  for (auto _ : st) {
    baseline.assemble(sc.warm.positions, sc.warm.velocities, 1.0 / 60.0, a, rhs);
    benchmark::DoNotOptimize(a.valuePtr());
    benchmark::DoNotOptimize(rhs.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

// ---- linear solve ----------------------------------------------------------------------------------

/// The system of the second implicit step (default variant) from the warm state, and the first
/// step's solution as the warm start: exactly what the solver sees inside a running simulation.
struct SolveCase {
  drape::LinearSystem<double> system;
  drape::VectorX<double> warm_start;
};

const SolveCase& solve_case(const Scene& sc, double dt) {
  static std::map<std::pair<int, double>, SolveCase> cache;  // built once per process
  const std::pair<int, double> key(sc.cloth->node_count(), dt);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  ImplicitOptions defaults;
  defaults.dt = dt;
  ImplicitEuler<double> integrator(*sc.cloth, defaults);
  drape::State<double> s = sc.warm;
  integrator.step(s);
  SolveCase c;
  c.warm_start = integrator.dv();
  integrator.step(s);
  c.system = integrator.system();
  return cache.emplace(key, std::move(c)).first->second;
}

void linear_solve_drape(benchmark::State& st, const SolverSetup& setup, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  const SolveCase& c = solve_case(sc, dt);
  const drape::IterativeSettings settings =
      options(setup, JacobianVariant::Spd, int(st.range(1)), dt).iterative_settings();
  auto linear_solver = drape::make_linear_solver<double>(setup.solver, settings);
  linear_solver->analyze(c.system);
  drape::VectorX<double> x = c.warm_start;
  long long iterations = 0, failures = 0;
  double residual_max = 0;
  for (auto _ : st) {
    x = c.warm_start;
    const drape::SolveStatus r = linear_solver->solve(c.system, x);
    benchmark::DoNotOptimize(x.data());
    benchmark::ClobberMemory();
    iterations += r.iterations;
    residual_max = std::max(residual_max, r.residual);
    if (!r.ok()) ++failures;
  }
  st.counters["cg_iterations"] = double(iterations) / double(st.iterations());
  st.counters["residual_max"] = residual_max;
  st.counters["failures"] = double(failures);
  st.counters["nodes"] = double(sc.cloth->node_count());
}

void linear_solve_baseline(benchmark::State& st, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  const BaselineImplicit baseline(*sc.cloth);
  BaselineImplicit::SparseMatrix a;
  BaselineImplicit::Vector rhs, dv;
  baseline.assemble(sc.warm.positions, sc.warm.velocities, dt, a, rhs);
  long long failures = 0;
  for (auto _ : st) {
    if (!BaselineImplicit::solve(a, rhs, dv)) ++failures;
    benchmark::DoNotOptimize(dv.data());
    benchmark::ClobberMemory();
  }
  st.counters["failures"] = double(failures);
  st.counters["nodes"] = double(sc.cloth->node_count());
}

// ---- system mat-vec -------------------------------------------------------------------------------

/// y = A x with the system of linear_solve (default variant, dt = 1/60), the kernel of every CG
/// iteration: drape's per-spring edge form (PCG's product, on one thread and on a team) and block
/// CSR (the block rows) against the baseline's scalar CSC matrix times a vector.
void matvec_drape(benchmark::State& st, bool edges) {
  const Scene& sc = scene(int(st.range(0)));
  drape::LinearSystem<double> system = solve_case(sc, 1.0 / 60.0).system;
  if (!edges) system.edges.invalidate();  // blocks only
  const drape::VectorX<double> x = drape::VectorX<double>::Random(system.size());
  drape::VectorX<double> y(system.size());
  const int threads = int(st.range(1));
  for (auto _ : st) {
    system.multiply(x.data(), y.data(), threads);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

void matvec_baseline(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  const BaselineImplicit baseline(*sc.cloth);
  BaselineImplicit::SparseMatrix a;
  BaselineImplicit::Vector rhs;
  baseline.assemble(sc.warm.positions, sc.warm.velocities, 1.0 / 60.0, a, rhs);
  const BaselineImplicit::Vector x = BaselineImplicit::Vector::Random(a.cols());
  BaselineImplicit::Vector y(a.rows());
  for (auto _ : st) {
    y.noalias() = a * x;
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

// ---- full implicit step ------------------------------------------------------------------------------

void implicit_step_drape(benchmark::State& st, const SolverSetup& setup, JacobianVariant jacobian, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  ImplicitEuler<double> integrator(*sc.cloth, options(setup, jacobian, int(st.range(1)), dt));
  run_steps(st, sc, implicit_window, [&](drape::State<double>& s) { return integrator.step(s); }, setup.iterative());
  st.counters["threads_used"] = integrator.assembler().threads();
}

// The default solver without the AVX2 edge product and residual (BaselineInstructionSet).
void implicit_step_drape_sse2(benchmark::State& st, const SolverSetup& setup, JacobianVariant jacobian, double dt) {
  const BaselineInstructionSet sse2;
  implicit_step_drape(st, setup, jacobian, dt);
}

void implicit_step_baseline(benchmark::State& st, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  BaselineImplicit baseline(*sc.cloth);
  run_steps(st, sc, implicit_window, [&](drape::State<double>& s) { return baseline.step(s, dt); });
}

// ---- set-up ------------------------------------------------------------------------------------------

void setup_implicit(benchmark::State& st, const SolverSetup& setup) {
  const drape::ClothSpec<double> spec = scene_spec(int(st.range(0)));
  for (auto _ : st) {
    drape::Cloth<double> cloth(spec);
    ImplicitEuler<double> integrator(cloth, options(setup, JacobianVariant::Spd, 2, 1.0 / 60.0));
    benchmark::DoNotOptimize(&integrator);
  }
  st.counters["nodes"] = double(spec.nx * spec.ny);
}

const bool registered = [] {
  using benchmark::RegisterBenchmark;
  const ImplicitOptions defaults;
  const auto dt_label = [](const TimeStep& ts) { return std::string("/dt=") + ts.label; };
  for (JacobianVariant j : {JacobianVariant::Exact, JacobianVariant::Symmetric, JacobianVariant::Spd})
    sized(RegisterBenchmark(name("jacobian_assembly", "drape", std::string("/jacobian=") + drape::to_string(j)).c_str(),
                            jacobian_assembly_drape, j),
          one_and_two, benchmark::kMillisecond);
  sized(RegisterBenchmark(name("jacobian_assembly", "baseline").c_str(), jacobian_assembly_baseline), serial,
        benchmark::kMillisecond);

  sized(RegisterBenchmark(name("matvec", "drape", "/form=edges").c_str(), matvec_drape, true), one_and_two,
        benchmark::kMicrosecond);
  sized(RegisterBenchmark(name("matvec", "drape", "/form=blocks").c_str(), matvec_drape, false), one_and_two,
        benchmark::kMicrosecond);
  sized(RegisterBenchmark(name("matvec", "baseline").c_str(), matvec_baseline), serial, benchmark::kMicrosecond);

  for (const SolverSetup& setup : solver_setups) {
    if (!setup.available()) continue;
    for (const TimeStep& ts : time_steps) {
      if (ts.dt != 1.0 / 60.0 && setup.solver != defaults.solver) continue;
      const double dt = ts.dt;
      sized(RegisterBenchmark(name("linear_solve", "drape", setup.name() + "/jacobian=spd" + dt_label(ts)).c_str(),
                              linear_solve_drape, setup, dt),
            setup.iterative() ? one_and_two : two, benchmark::kMillisecond, setup.max_n());
    }
  }
  // The baseline's solve and step take ~30 s at 257 x 257: there only the step at dt = 1/60, once.
  for (const TimeStep& ts : time_steps)
    sized(RegisterBenchmark(name("linear_solve", "baseline", dt_label(ts)).c_str(), linear_solve_baseline, ts.dt),
          serial, benchmark::kMillisecond, 129);

  for (const StepPlan& p : step_plans) {
    if (!p.setup.available()) continue;
    for (const TimeStep& ts : time_steps) {
      if (!p.both_time_steps && ts.dt != 1.0 / 60.0) continue;
      const std::string rest = p.setup.name() + "/jacobian=" + drape::to_string(p.jacobian) + dt_label(ts);
      const bool headline = p.setup.solver == defaults.solver && p.setup.preconditioner == defaults.preconditioner &&
                            p.jacobian == defaults.jacobian;
      sized(RegisterBenchmark(name("implicit_step", "drape", rest).c_str(), implicit_step_drape, p.setup, p.jacobian,
                              ts.dt),
            *p.threads, benchmark::kMillisecond, p.setup.max_n(), headline ? headline_min_time : quick_min_time);
      if (headline && ts.dt == 1.0 / 60.0)
        sized(RegisterBenchmark(name("implicit_step", "drape-sse2", rest).c_str(), implicit_step_drape_sse2, p.setup,
                                p.jacobian, ts.dt),
              *p.threads, benchmark::kMillisecond, p.setup.max_n(), headline_min_time);
    }
  }
  for (const TimeStep& ts : time_steps)
    sized(RegisterBenchmark(name("implicit_step", "baseline", dt_label(ts)).c_str(), implicit_step_baseline, ts.dt),
          serial, benchmark::kMillisecond, 129, headline_min_time);
  RegisterBenchmark(name("implicit_step", "baseline", "/dt=1_60").c_str(), implicit_step_baseline, 1.0 / 60.0)
      ->ArgNames({"n"})
      ->Args({257})
      ->Unit(benchmark::kMillisecond)
      ->Iterations(1)
      ->Repetitions(1);

  for (const SolverSetup& setup : solver_setups)
    if (setup.available())
      sized(RegisterBenchmark(("setup/what=cloth+implicit" + setup.name()).c_str(), setup_implicit, setup), serial,
            benchmark::kMillisecond, setup.max_n());
  return true;
}();

double relative_difference(const drape::VectorX<double>& a, const drape::VectorX<double>& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

/// dv of one step of `integrator` from `state`, expanded to all 3n DOFs (pinned: 0).
drape::VectorX<double> full_dv(ImplicitEuler<double>& integrator, const drape::State<double>& state,
                               drape::StepStatus& status) {
  drape::State<double> s = state;
  status = integrator.step(s);
  drape::VectorX<double> dv = drape::VectorX<double>::Zero(3 * state.node_count());
  const std::vector<int>& node_of_row = integrator.assembler().node_of_row();
  for (std::size_t r = 0; r < node_of_row.size(); ++r)
    dv.segment<3>(3 * node_of_row[r]) = integrator.dv().segment<3>(3 * drape::Index(r));
  return dv;
}

}  // namespace

std::string check_accuracy() {
  std::ostringstream text;
  const ImplicitOptions defaults;
  const SolverSetup direct{drape::solver_available(Kind::Cholmod) ? Kind::Cholmod : Kind::Ldlt};
  const SolverSetup default_setup{defaults.solver, defaults.preconditioner};
  bool ok = true;
  text.precision(1);
  text << std::scientific;
  text << "Accuracy (checked by `drape_bench` at start-up, from the warm states; it refuses to run if a check "
          "fails): the default solver `"
       << drape::to_string(defaults.solver) << "` (" << drape::to_string(defaults.preconditioner) << " preconditioner, "
       << drape::to_string(defaults.jacobian) << " Jacobian) stops at relative residual "
       << defaults.tolerance << "; its first step's dv differs from the `" << drape::to_string(direct.solver)
       << "` direct solve of the same "
       << "system by (relative 2-norm) ";
  std::string sep;
  for (int n : grid_sizes) {
    const Scene& sc = scene(n);
    for (const TimeStep& ts : time_steps) {
      ImplicitEuler<double> cg(*sc.cloth, options(default_setup, defaults.jacobian, 0, ts.dt));
      ImplicitEuler<double> reference(*sc.cloth, options(direct, defaults.jacobian, 0, ts.dt));
      drape::StepStatus s_cg, s_ref;
      const drape::VectorX<double> dv_cg = full_dv(cg, sc.warm, s_cg);
      const drape::VectorX<double> dv_ref = full_dv(reference, sc.warm, s_ref);
      const double diff = relative_difference(dv_cg, dv_ref);
      text << sep << diff << " (" << n << " x " << n << ", dt = " << (ts.dt == 0.01 ? "0.01" : "1/60") << ")";
      sep = ", ";
      if (!s_cg.ok() || !s_ref.ok() || !(diff < 1e-3)) {
        std::fprintf(stderr, "drape_bench: accuracy check failed at %d x %d, dt %g: %s/%s, difference %g\n", n, n,
                     ts.dt, drape::to_string(s_cg.error), drape::to_string(s_ref.error), diff);
        ok = false;
      }
    }
  }
  // The baseline must simulate the same physics: its step equals drape's with the same Jacobian
  // (Symmetric) and a direct solve, and its RK2 step equals drape's.
  text << ". The textbook baseline's implicit dv differs from drape's `ldlt` with the same (Symmetric) Jacobian by ";
  sep = "";
  std::ostringstream rk2_text;
  rk2_text.precision(1);
  rk2_text << std::scientific;
  for (int n : {33, 65}) {
    const Scene& sc = scene(n);
    for (const TimeStep& ts : time_steps) {
      ImplicitEuler<double> ldlt(*sc.cloth, options({Kind::Ldlt}, JacobianVariant::Symmetric, 0, ts.dt));
      drape::StepStatus status;
      const drape::VectorX<double> dv = full_dv(ldlt, sc.warm, status);
      const drape::VectorX<double> dv_base = BaselineImplicit(*sc.cloth).step_dv(sc.warm, ts.dt);
      const double diff = dv_base.size() ? relative_difference(dv_base, dv) : 1.0;
      text << sep << diff << " (" << n << " x " << n << ", dt = " << (ts.dt == 0.01 ? "0.01" : "1/60") << ")";
      sep = ", ";
      if (!status.ok() || !(diff < 1e-9)) {
        std::fprintf(stderr, "drape_bench: baseline implicit disagrees with drape at %d x %d: %g\n", n, n, diff);
        ok = false;
      }
    }
    drape::State<double> a = sc.warm, b = sc.warm;
    const double dt = drape::IntegratorOptions{}.dt;
    drape::Rk2<double>(*sc.cloth, {dt, 1}).step(a);
    BaselineRk2(*sc.cloth).step(b, dt);
    const double diff = std::max(relative_difference(drape::flat(b.positions), drape::flat(a.positions)),
                                 relative_difference(drape::flat(b.velocities), drape::flat(a.velocities)));
    rk2_text << (n == 33 ? "" : ", ") << diff << " (" << n << " x " << n << ")";
    if (!(diff < 1e-12)) {
      std::fprintf(stderr, "drape_bench: baseline RK2 disagrees with drape at %d x %d: %g\n", n, n, diff);
      ok = false;
    }
  }
  text << "; its RK2 step differs from drape's by " << rk2_text.str();
  text << ".";
  if (!ok) std::exit(2);
  return text.str();
}

}  // namespace drape_bench
