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

/// What the implicit-step family runs. The default (cg, Spd) gets both time steps and 1 and 2
/// threads; the other solvers and variants run at dt = 1/60 on 2 threads for comparison. Eigen's
/// simplicial LDLT and SparseLU stop at 65 x 65 and UMFPACK at 129 x 129: one of their steps takes
/// tens of seconds at 257 x 257 (measured: a 257 x 257 solve took 27 s with either), which would
/// make the suite run for an hour without telling anything new.
struct StepPlan {
  const char* solver;
  JacobianVariant jacobian;
  bool both_time_steps;
  const std::vector<int>* threads;
  int max_n;
};
const StepPlan step_plans[] = {
    {"cg", JacobianVariant::Spd, true, &one_and_two, 257},
    {"cg", JacobianVariant::Symmetric, false, &two, 257},
    {"cg-jacobi", JacobianVariant::Spd, false, &one_and_two, 257},
    {"bicgstab", JacobianVariant::Spd, false, &two, 257},
    {"bicgstab", JacobianVariant::Exact, false, &two, 257},
    {"cholmod", JacobianVariant::Spd, true, &two, 257},
    {"umfpack", JacobianVariant::Exact, false, &two, 129},
    {"ldlt", JacobianVariant::Spd, false, &two, 65},
    {"lu", JacobianVariant::Exact, false, &two, 65},
};
/// Largest grid of the direct solvers' linear-solve and set-up benchmarks (see step_plans).
int max_n_of(const std::string& solver) {
  return solver == "ldlt" || solver == "lu" ? 65 : solver == "umfpack" ? 129 : 257;
}

/// "cg-jacobi" is cg with the block-Jacobi preconditioner (the default before multigrid), kept as
/// the reference that shows what the multigrid preconditioner buys.
std::string solver_name(const std::string& solver) { return solver == "cg-jacobi" ? "cg" : solver; }

bool available(const std::string& solver) {
  const std::vector<std::string> names = drape::available_solvers();
  return std::find(names.begin(), names.end(), solver_name(solver)) != names.end();
}
bool iterative(const std::string& solver) { return solver_name(solver) == "cg" || solver == "bicgstab"; }

ImplicitOptions options(const std::string& solver, JacobianVariant jacobian, int threads) {
  ImplicitOptions o;  // defaults: tolerance 1e-6, iteration cap, eliminated pins
  o.solver = solver_name(solver);
  if (solver == "cg-jacobi") o.preconditioner = drape::Preconditioner::BlockJacobi;
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
  drape::BlockSparseMatrix<double> a = assembler.make_matrix();
  drape::VectorX<double> rhs(a.size());
  for (auto _ : st) {
    assembler.assemble_system(sc.warm.positions, sc.warm.velocities, 1.0 / 60.0, jacobian, a, rhs);
    benchmark::DoNotOptimize(a.values());
    benchmark::DoNotOptimize(rhs.data());
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
  drape::BlockSparseMatrix<double> a;
  drape::VectorX<double> b, warm_start;
  drape::GridLayout layout;  // for the multigrid preconditioner
};

const SolveCase& solve_case(const Scene& sc, double dt) {
  static std::map<std::pair<int, double>, SolveCase> cache;  // built once per process
  const std::pair<int, double> key(sc.cloth->node_count(), dt);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  ImplicitEuler<double> integrator(*sc.cloth, ImplicitOptions{});
  drape::State<double> s = sc.warm;
  integrator.step(s, dt);
  SolveCase c;
  c.warm_start = integrator.dv();
  integrator.step(s, dt);
  c.a = integrator.system_matrix();
  c.b = integrator.rhs();
  c.layout = {sc.cloth->grid().nx(), sc.cloth->grid().ny(), integrator.assembler().row_of_node()};
  return cache.emplace(key, std::move(c)).first->second;
}

void linear_solve_drape(benchmark::State& st, const std::string& solver, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  const SolveCase& c = solve_case(sc, dt);
  drape::IterativeSettings settings;
  settings.tolerance = ImplicitOptions{}.tolerance;
  settings.max_iterations = ImplicitOptions{}.max_iterations;
  settings.threads = int(st.range(1));
  settings.preconditioner =
      solver == "cg-jacobi" ? drape::Preconditioner::BlockJacobi : ImplicitOptions{}.preconditioner;
  auto linear_solver = drape::make_linear_solver<double>(solver_name(solver), settings);
  linear_solver->set_grid_layout(c.layout);
  linear_solver->analyze(c.a);
  drape::VectorX<double> x = c.warm_start;
  long long iterations = 0, failures = 0;
  double residual_max = 0;
  for (auto _ : st) {
    x = c.warm_start;
    const drape::StepStatus r = linear_solver->solve(c.a, c.b, x);
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
/// iteration: drape's per-spring edge form (what PCG uses on one thread) and block CSR (what
/// it uses with a team) against the baseline's scalar CSC matrix times a vector.
void matvec_drape(benchmark::State& st, bool edges) {
  const Scene& sc = scene(int(st.range(0)));
  drape::BlockSparseMatrix<double> a = solve_case(sc, 1.0 / 60.0).a;
  if (!edges) a.set_edge_form({}, {0}, {});  // blocks only
  const drape::VectorX<double> x = drape::VectorX<double>::Random(a.size());
  drape::VectorX<double> y(a.size());
  const int threads = int(st.range(1));
  for (auto _ : st) {
    a.multiply(x.data(), y.data(), threads);
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

void implicit_step_drape(benchmark::State& st, const std::string& solver, JacobianVariant jacobian, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  ImplicitEuler<double> integrator(*sc.cloth, options(solver, jacobian, int(st.range(1))));
  run_steps(st, sc, implicit_window, [&](drape::State<double>& s) { return integrator.step(s, dt); },
            iterative(solver));
  st.counters["threads_used"] = integrator.assembler().threads();
}

void implicit_step_baseline(benchmark::State& st, double dt) {
  const Scene& sc = scene(int(st.range(0)));
  BaselineImplicit baseline(*sc.cloth);
  run_steps(st, sc, implicit_window, [&](drape::State<double>& s) { return baseline.step(s, dt); });
}

// ---- set-up ------------------------------------------------------------------------------------------

void setup_implicit(benchmark::State& st, const std::string& solver) {
  const drape::ClothSpec<double> spec = scene_spec(int(st.range(0)));
  for (auto _ : st) {
    drape::Cloth<double> cloth(spec);
    ImplicitEuler<double> integrator(cloth, options(solver, JacobianVariant::Spd, 2));
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

  for (const std::string solver : {"cg", "cg-jacobi", "bicgstab", "cholmod", "umfpack", "ldlt", "lu"}) {
    if (!available(solver)) continue;
    for (const TimeStep& ts : time_steps) {
      if (ts.dt != 1.0 / 60.0 && solver != defaults.solver) continue;
      const double dt = ts.dt;
      sized(RegisterBenchmark(name("linear_solve", "drape", "/solver=" + solver + "/jacobian=spd" + dt_label(ts)).c_str(),
                              linear_solve_drape, solver, dt),
            iterative(solver) ? one_and_two : two, benchmark::kMillisecond, max_n_of(solver));
    }
  }
  // The baseline's solve and step take ~30 s at 257 x 257: there only the step at dt = 1/60, once.
  for (const TimeStep& ts : time_steps)
    sized(RegisterBenchmark(name("linear_solve", "baseline", dt_label(ts)).c_str(), linear_solve_baseline, ts.dt),
          serial, benchmark::kMillisecond, 129);

  for (const StepPlan& p : step_plans) {
    if (!available(p.solver)) continue;
    for (const TimeStep& ts : time_steps) {
      if (!p.both_time_steps && ts.dt != 1.0 / 60.0) continue;
      const std::string rest = std::string("/solver=") + p.solver + "/jacobian=" + drape::to_string(p.jacobian) + dt_label(ts);
      sized(RegisterBenchmark(name("implicit_step", "drape", rest).c_str(), implicit_step_drape, std::string(p.solver),
                              p.jacobian, ts.dt),
            *p.threads, benchmark::kMillisecond, p.max_n,
            p.solver == defaults.solver && p.jacobian == defaults.jacobian ? headline_min_time : quick_min_time);
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

  for (const std::string solver : {"cg", "cg-jacobi", "bicgstab", "cholmod", "umfpack", "ldlt", "lu"})
    if (available(solver))
      sized(RegisterBenchmark(("setup/what=cloth+implicit/solver=" + solver).c_str(), setup_implicit, solver), serial,
            benchmark::kMillisecond, max_n_of(solver));
  return true;
}();

double relative_difference(const drape::VectorX<double>& a, const drape::VectorX<double>& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

/// dv of one step of `integrator` from `state`, expanded to all 3n DOFs (pinned: 0).
drape::VectorX<double> full_dv(ImplicitEuler<double>& integrator, const drape::State<double>& state, double dt,
                               drape::StepStatus& status) {
  drape::State<double> s = state;
  status = integrator.step(s, dt);
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
  const std::string direct = available("cholmod") ? "cholmod" : "ldlt";
  bool ok = true;
  text.precision(1);
  text << std::scientific;
  text << "Accuracy (checked by `drape_bench` at start-up, from the warm states; it refuses to run if a check "
          "fails): the default solver `"
       << defaults.solver << "` (" << drape::to_string(defaults.jacobian) << " Jacobian) stops at relative residual "
       << defaults.tolerance << "; its first step's dv differs from the `" << direct << "` direct solve of the same "
       << "system by (relative 2-norm) ";
  std::string sep;
  for (int n : grid_sizes) {
    const Scene& sc = scene(n);
    for (const TimeStep& ts : time_steps) {
      ImplicitEuler<double> cg(*sc.cloth, options(defaults.solver, defaults.jacobian, 0));
      ImplicitEuler<double> reference(*sc.cloth, options(direct, defaults.jacobian, 0));
      drape::StepStatus s_cg, s_ref;
      const drape::VectorX<double> dv_cg = full_dv(cg, sc.warm, ts.dt, s_cg);
      const drape::VectorX<double> dv_ref = full_dv(reference, sc.warm, ts.dt, s_ref);
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
      ImplicitEuler<double> ldlt(*sc.cloth, options("ldlt", JacobianVariant::Symmetric, 0));
      drape::StepStatus status;
      const drape::VectorX<double> dv = full_dv(ldlt, sc.warm, ts.dt, status);
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
    drape::Rk2<double>(*sc.cloth, 1).step(a, drape::ClothSpec<double>::default_dt());
    BaselineRk2(*sc.cloth).step(b, drape::ClothSpec<double>::default_dt());
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
