// Determinism: the same inputs and thread count give bit-identical states after many steps, for
// RK2 and implicit Euler, with 1 and with 2 threads; and what 1 vs 2 threads give.
#include <catch2/catch.hpp>

#include <cstring>
#include <functional>

#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/model/cloth.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/enable_ldlt.hpp"  // opt-in solver used below

using namespace drape;

namespace {

/// Bitwise equality (NaN == NaN, -0 != +0): what "reproducible" means for a resumed or re-run
/// simulation.
bool same_bits(const Matrix3X<double>& a, const Matrix3X<double>& b) {
  return a.cols() == b.cols() && std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
}
bool same_bits(const Stated& a, const Stated& b) {
  return same_bits(a.positions, b.positions) && same_bits(a.velocities, b.velocities) &&
         std::memcmp(&a.time, &b.time, sizeof a.time) == 0;
}

/// The course model's scene (33 x 33, two corners), run `steps` steps of the integrator's dt from
/// rest; every step must succeed.
Stated run(Integrator<double>& integrator, const Clothd& cloth, int steps) {
  Stated s = cloth.initial_state();
  for (int k = 0; k < steps; ++k) {
    const StepStatus status = integrator.step(s);
    REQUIRE(status.ok());
  }
  return s;
}

/// 48 x 48 nodes: 13.5k springs, enough work for both assemblers to use 2 threads (the Jacobian
/// assembly stays on one below 8192 springs; the default 33 x 33 cloth has 6.2k).
ClothSpecd threaded_spec() {
  ClothSpecd spec;
  spec.nx = 48;
  spec.ny = 48;
  return spec;
}

Stated run_rk2(const Clothd& cloth, int threads, int steps) {
  Rk2<double> rk2(cloth, {IntegratorOptions{}.dt, threads});  // the default dt
  // The point of the 2-thread runs is lost if the assembler quietly falls back to one thread.
  REQUIRE(rk2.forces().threads() == std::min(threads, max_threads()));
  return run(rk2, cloth, steps);
}

Stated run_implicit(const Clothd& cloth, int threads, int steps, const std::string& solver = "cg") {
  ImplicitOptions o;
  o.dt = 1.0 / 60;
  o.threads = threads;
  o.solver = parse<LinearSolverKind>(solver);
  ImplicitEuler<double> ie(cloth, o);
  REQUIRE(ie.assembler().threads() == std::min(threads, max_threads()));
  return run(ie, cloth, steps);
}

double max_abs_difference(const Stated& a, const Stated& b) {
  return std::max((a.positions - b.positions).cwiseAbs().maxCoeff(), (a.velocities - b.velocities).cwiseAbs().maxCoeff());
}

}  // namespace

TEST_CASE("RK2: same inputs and thread count give bit-identical states after 500 steps", "[reliability][determinism]") {
  const Clothd cloth{threaded_spec()};
  for (int threads : {1, 2}) {
    if (threads > max_threads()) {
      WARN("only " << max_threads() << " thread(s) available: the 2-thread run is skipped");
      continue;
    }
    INFO(threads << " thread(s)");
    const Stated a = run_rk2(cloth, threads, 500);  // 0.25 s: the free corners have fallen ~0.3 m and are moving
    const Stated b = run_rk2(cloth, threads, 500);
    REQUIRE(a.positions.allFinite());
    REQUIRE((a.positions - cloth.initial_state().positions).cwiseAbs().maxCoeff() > 0.1);  // it really moved
    REQUIRE(same_bits(a, b));
  }
}

TEST_CASE("implicit Euler: same inputs and thread count give bit-identical states after 30 steps",
          "[reliability][determinism]") {
  const Clothd cloth{threaded_spec()};
  // cg: the solver whose reductions run in parallel (ldlt's factorisation is serial).
  for (const std::string solver : {"cg"}) {
    for (int threads : {1, 2}) {
      if (threads > max_threads()) continue;
      INFO(solver << ", " << threads << " thread(s)");
      const Stated a = run_implicit(cloth, threads, 30, solver);  // 0.5 s at 1/60 s
      const Stated b = run_implicit(cloth, threads, 30, solver);
      REQUIRE(a.positions.allFinite());
      REQUIRE(same_bits(a, b));
    }
  }
}

TEST_CASE("RK2 with 1 and 2 threads agree bit for bit", "[reliability][determinism]") {
  if (max_threads() < 2) {
    WARN("only one thread available: nothing to compare");
    return;
  }
  // Every spring force is computed by one thread, and each node sums its springs' forces in
  // blocks of fixed size and a fixed order whatever the thread count (no atomics or reductions),
  // so the thread count cannot change a bit.
  for (const ClothSpecd& spec : {ClothSpecd{}, threaded_spec()}) {  // the default 33 x 33 and 48 x 48
    const Clothd cloth{spec};
    REQUIRE(same_bits(run_rk2(cloth, 1, 500), run_rk2(cloth, 2, 500)));
  }
}

TEST_CASE("implicit Euler with 1 and 2 threads: how far apart", "[reliability][determinism]") {
  if (max_threads() < 2) {
    WARN("only one thread available: nothing to compare");
    return;
  }
  const Clothd cloth{threaded_spec()};
  // The assembly writes each block from one thread in a fixed order and ldlt's factorisation is
  // serial: 1 and 2 threads agree bitwise. On 48 x 48 PCG itself stays on one thread (below
  // 2 x 3000 block rows), so cg agrees too.
  REQUIRE(same_bits(run_implicit(cloth, 1, 10, "ldlt"), run_implicit(cloth, 2, 10, "ldlt")));
  REQUIRE(same_bits(run_implicit(cloth, 1, 10, "cg"), run_implicit(cloth, 2, 10, "cg")));
}

TEST_CASE("threaded PCG: reproducible for a given thread count; 1 vs 2 threads differ in the last bits",
          "[reliability][determinism]") {
  if (max_threads() < 2) {
    WARN("only one thread available: nothing to compare");
    return;
  }
  // 80 x 80: 6398 free block rows, enough for PCG to use 2 threads.
  ClothSpecd spec;
  spec.nx = spec.ny = 80;
  const Clothd cloth(spec);
  REQUIRE(cloth.node_count() - 2 >= 2 * PcgSolver<double>::min_rows_per_thread);
  const int steps = 5;
  const Stated two_a = run_implicit(cloth, 2, steps), two_b = run_implicit(cloth, 2, steps);
  REQUIRE(same_bits(two_a, two_b));
  // Its dot products add per-thread partial sums in thread order: deterministic for a thread count,
  // but 2 threads sum in another order than 1, so the trajectories differ by rounding.
  const Stated one = run_implicit(cloth, 1, steps);
  const double diff = max_abs_difference(one, two_a);
  UNSCOPED_INFO("cg on 80 x 80, 1 vs 2 threads after " << steps << " steps: max |difference| = " << diff);
  CHECK(diff < 1e-6);  // rounding, far below the solver's tolerance effect on a step
}
