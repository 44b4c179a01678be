/// \file bench_forces.cpp
/// Force assembly and the RK2 step at the default dt: drape (1 and 2 threads) against the textbook
/// baseline (baseline.hpp); the symplectic Euler step at the same dt (`symplectic_step`). The
/// `impl=drape-sse2` rows run the same steps with the AVX2 spring pass switched off
/// (platform/instruction_set.hpp): the gain of the run-time dispatch, measured in the same run.

#include "baseline.hpp"
#include "bench_common.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/platform/instruction_set.hpp"

namespace drape_bench {
namespace {

void force_assembly_drape(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  const drape::ForceAssembler<double> forces(*sc.cloth, int(st.range(1)));
  drape::Matrix3X<double> f(3, sc.cloth->node_count());
  for (auto _ : st) {
    forces.force(sc.warm.positions, sc.warm.velocities, sc.warm.time, f);
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  st.counters["threads_used"] = forces.threads();
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

void force_assembly_baseline(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  const std::vector<Spring> springs = baseline_springs(*sc.cloth);
  for (auto _ : st) {
    Matrix3X f = baseline_forces(*sc.cloth, springs, sc.warm.positions, sc.warm.velocities);
    benchmark::DoNotOptimize(f.data());
    benchmark::ClobberMemory();
  }
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->springs().size());
}

/// Runs the baseline (SSE2) versions of the hot loops while it lives.
void rk2_step_drape(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  drape::Rk2<double> rk2(*sc.cloth, {drape::IntegratorOptions{}.dt, int(st.range(1))});  // the default dt
  run_steps(st, sc, rk2_window, [&](drape::State<double>& s) { return rk2.step(s); });
  st.counters["threads_used"] = rk2.forces().threads();
}

// The same scene and dt as rk2_step: one force pass per step instead of two.
void symplectic_step_drape(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  drape::SymplecticEuler<double> stepper(*sc.cloth, {drape::IntegratorOptions{}.dt, int(st.range(1))});
  run_steps(st, sc, rk2_window, [&](drape::State<double>& s) { return stepper.step(s); });
  st.counters["threads_used"] = stepper.forces().threads();
}

void rk2_step_drape_sse2(benchmark::State& st) {
  const BaselineInstructionSet sse2;
  rk2_step_drape(st);
}

void symplectic_step_drape_sse2(benchmark::State& st) {
  const BaselineInstructionSet sse2;
  symplectic_step_drape(st);
}

void rk2_step_baseline(benchmark::State& st) {
  const Scene& sc = scene(int(st.range(0)));
  BaselineRk2 rk2(*sc.cloth);
  const double dt = drape::IntegratorOptions{}.dt;
  run_steps(st, sc, rk2_window, [&](drape::State<double>& s) { return rk2.step(s, dt); });
}

const bool registered = [] {
  sized(benchmark::RegisterBenchmark("force_assembly/impl=drape", force_assembly_drape), one_and_two,
        benchmark::kMicrosecond);
  sized(benchmark::RegisterBenchmark("force_assembly/impl=baseline", force_assembly_baseline), serial,
        benchmark::kMicrosecond);
  sized(benchmark::RegisterBenchmark("rk2_step/impl=drape", rk2_step_drape), one_and_two, benchmark::kMicrosecond, 257,
        headline_min_time);
  sized(benchmark::RegisterBenchmark("rk2_step/impl=baseline", rk2_step_baseline), serial, benchmark::kMicrosecond, 257,
        headline_min_time);
  sized(benchmark::RegisterBenchmark("symplectic_step/impl=drape", symplectic_step_drape), one_and_two,
        benchmark::kMicrosecond, 257, headline_min_time);
  sized(benchmark::RegisterBenchmark("rk2_step/impl=drape-sse2", rk2_step_drape_sse2), one_and_two,
        benchmark::kMicrosecond, 257, headline_min_time);
  sized(benchmark::RegisterBenchmark("symplectic_step/impl=drape-sse2", symplectic_step_drape_sse2), one_and_two,
        benchmark::kMicrosecond, 257, headline_min_time);
  return true;
}();

}  // namespace
}  // namespace drape_bench
