/// \file amg_cost.cpp
/// What each preconditioner of CG costs on the implicit step's system, the algebraic multigrid's
/// set-up included: the default cloth's material refined to n x n nodes over the same 3.2 m square
/// (as drape_refinement scales it), two corners pinned, simulated for 0.5 s at dt = 1/60 from the
/// flat cloth at rest; then the next step's system (spd Jacobian, pins eliminated) and per
/// preconditioner: analyze() (for amg and amg-float: aggregation, every pattern and the first
/// values), one update (values only, every step), one application z = B r, and CG from zero to the
/// integrator's default tolerance: iterations and time (the update included, as in a step). Median
/// of R repetitions.
/// Prints a markdown table (docs/amg.md).
///
///   build/bench/drape_amg_cost [n ...] [--threads T] [--repetitions R]
///
/// Defaults: n = 33 65 129, T = 1, R = 5.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/solvers/make_preconditioner.hpp"
#include "drape/solvers/pcg.hpp"
#include "refined_cloth.hpp"
#include "tool_text.hpp"

namespace {

/// Median wall time of `repetitions` calls of `body`, in seconds.
double median_seconds(int repetitions, const std::function<void()>& body) {
  std::vector<double> t;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    body();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

int usage(const char* problem) {
  std::fprintf(stderr,
               "drape_amg_cost: %s\nusage: drape_amg_cost [n ...] [--threads T] [--repetitions R]\n"
               "  n >= 3 nodes per side (default 33 65 129), T >= 1 (default 1), R >= 1 (default 5)\n",
               problem);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  int threads = 1, repetitions = 5;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--threads" || arg == "--repetitions") {
      if (k + 1 >= argc) return usage((arg + " needs a value").c_str());
      const int value = std::atoi(argv[++k]);
      if (value < 1) return usage((arg + ": expected an integer >= 1").c_str());
      (arg == "--threads" ? threads : repetitions) = value;
    } else {
      const int n = std::atoi(arg.c_str());
      if (n < 3) return usage(("size '" + arg + "': expected an integer >= 3").c_str());
      sizes.push_back(n);
    }
  }
  if (sizes.empty()) sizes = {33, 65, 129};
  const drape::ImplicitOptions defaults;
  std::printf(
      "The step after 0.5 s of the default cloth refined to n x n over 3.2 m (dt = 1/60, spd, pins eliminated), "
      "%d thread(s), median of %d; CG from zero to tolerance %g\n\n",
      threads, repetitions, defaults.tolerance);
  std::printf(
      "| n x n | preconditioner | levels (block rows) | analyze | update | apply | CG iterations | CG solve |\n"
      "|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  for (const int n : sizes) {
    const drape::Cloth<double> cloth(drape_bench::refined_default_spec(n));
    drape::ImplicitOptions options;
    options.dt = 1.0 / 60;
    options.threads = threads;
    drape::ImplicitEuler<double> integrator(cloth, options);
    drape::State<double> state = cloth.initial_state();
    for (int k = 0; k < 30; ++k)
      if (!integrator.step(state).ok()) {
        std::printf("| %d | the trajectory failed at step %d | | | | | | |\n", n, k);
        return 1;
      }
    drape::JacobianAssembler<double> assembler(cloth, drape::PinTreatment::Eliminate, threads);
    drape::LinearSystem<double> system = assembler.make_system();
    assembler.assemble_system(state.positions, state.velocities, state.time, options.dt, drape::JacobianVariant::Spd,
                              system);
    const drape::VectorX<double> r = drape::VectorX<double>::Ones(system.size());
    drape::VectorX<double> z(system.size());
    for (const drape::PreconditionerKind kind :
         {drape::PreconditionerKind::AlgebraicMultigrid, drape::PreconditionerKind::AlgebraicMultigridFloat,
          drape::PreconditionerKind::Multigrid, drape::PreconditionerKind::MultigridFloat,
          drape::PreconditionerKind::BlockJacobi}) {
      std::unique_ptr<drape::Preconditioner<double>> p = drape::make_preconditioner<double>(kind);
      const double analyze = median_seconds(repetitions, [&] { p->analyze(system); });
      const double update =
          median_seconds(repetitions, [&] { drape::run_in_team(threads, [&] { p->update_in_team(system); }); });
      const double apply = median_seconds(
          repetitions, [&] { drape::run_in_team(threads, [&] { p->apply_in_team(r.data(), z.data()); }); });
      std::string levels = "-";
      if (const auto* amg = dynamic_cast<const drape::AlgebraicMultigrid<double>*>(p.get())) {
        levels.clear();
        for (const int rows : amg->level_rows()) levels += (levels.empty() ? "" : ", ") + std::to_string(rows);
        char complexity[48];
        std::snprintf(complexity, sizeof complexity, " (operator complexity %.2f)", amg->operator_complexity());
        levels += complexity;
      } else if (const auto* mg = dynamic_cast<const drape::MultigridPreconditioner<double>*>(p.get())) {
        levels.clear();
        for (const int rows : mg->level_rows()) levels += (levels.empty() ? "" : ", ") + std::to_string(rows);
      }
      drape::IterativeSettings settings = options.iterative_settings();
      settings.preconditioner = kind;
      drape::PcgSolver<double> cg(settings);
      cg.analyze(system);
      drape::SolveStatus status;
      drape::VectorX<double> x(system.size());
      const double solve = median_seconds(repetitions, [&] {
        x.setZero();
        status = cg.solve(system, x);
      });
      std::printf("| %d | %s | %s | %s | %s | %s | %d%s | %s |\n", n, drape::to_string(kind), levels.c_str(),
                  drape_bench::duration(analyze).c_str(), drape_bench::duration(update).c_str(),
                  drape_bench::duration(apply).c_str(), status.iterations, status.ok() ? "" : " (failed)",
                  drape_bench::duration(solve).c_str());
      std::fflush(stdout);
    }
  }
  return 0;
}
