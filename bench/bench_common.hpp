#pragma once
/// \file bench_common.hpp
/// Scenes, representative timed states and counters shared by every benchmark family.
///
/// Timed state: the default scene (both corners pinned, ClothSpec defaults, nx = ny = N) after a
/// warm-up of `warm_up_time` simulated seconds, so the cloth is falling and swinging and springs
/// near the pins are compressed (counted in the `compressed` counter), not the flat start. A
/// benchmark then steps on from that state and every `window` steps resets to it (outside the
/// timer), so the timed steps always sample the same stretch of motion however many iterations the
/// library decides to run: a cloth left to come to rest would make every solver look fast.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "drape/core/instruction_set_choice.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/model/cloth.hpp"

namespace drape_bench {

/// Grid sizes (nodes per side) of every family.
inline constexpr int grid_sizes[] = {33, 65, 129, 257};
/// Simulated time of the warm-up (s).
inline constexpr double warm_up_time = 0.5;
/// Steps per reset window: 0.5 s of simulated motion for RK2 at its default dt, 30 implicit steps
/// (0.5 s at dt = 1/60, 0.3 s at dt = 0.01).
inline constexpr int rk2_window = 1000;
inline constexpr int implicit_window = 30;

inline drape::ClothSpec<double> scene_spec(int n) {
  drape::ClothSpec<double> spec;  // the default scene: 0.1 m, 0.03 kg, g = 10, default springs, two corners
  spec.nx = n;
  spec.ny = n;
  return spec;
}

/// A cloth and its warmed-up state, built once per grid size and process.
struct Scene {
  std::unique_ptr<drape::Cloth<double>> cloth;
  drape::State<double> warm;
  double compressed_fraction = 0;  ///< springs shorter than rest in `warm`
  double max_speed = 0;            ///< m/s in `warm`
};

/// Fraction of springs shorter than their rest length.
inline double compressed_fraction(const drape::Cloth<double>& cloth, const drape::Matrix3X<double>& x) {
  const drape::SpringSet<double>& sp = cloth.springs();
  int compressed = 0;
  for (int s = 0; s < sp.size(); ++s)
    if ((x.col(sp.b()[s]) - x.col(sp.a()[s])).norm() < sp.rest_length()[s]) ++compressed;
  return double(compressed) / double(sp.size());
}

/// Advances `state` by `warm_up_time` (defined in bench_main.cpp: uses drape's implicit
/// integrator when it is available, RK2 at its default dt otherwise).
void warm_up(const drape::Cloth<double>& cloth, drape::State<double>& state);
extern const char* const warm_up_method;

/// Checks, before anything is timed, that the default iterative solve agrees with a direct solve
/// and that the baseline simulates the same physics as drape; returns the measured differences as
/// a sentence for docs/benchmarks.md, or exits with status 2 if a check fails (bench_implicit.cpp).
std::string check_accuracy();

inline const Scene& scene(int n) {
  static std::map<int, Scene> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  Scene sc;
  sc.cloth = std::make_unique<drape::Cloth<double>>(scene_spec(n));
  sc.warm = sc.cloth->initial_state();
  warm_up(*sc.cloth, sc.warm);
  sc.compressed_fraction = compressed_fraction(*sc.cloth, sc.warm.positions);
  sc.max_speed = sc.warm.velocities.colwise().norm().maxCoeff();
  return cache.emplace(n, std::move(sc)).first->second;
}

/// Switches drape's AVX2 loops off while it lives (`impl=drape-sse2` rows: the same step without
/// the run-time dispatch, platform/instruction_set.hpp).
struct BaselineInstructionSet {
  drape::InstructionSet saved = drape::instruction_set();
  BaselineInstructionSet() { drape::use_instruction_set(drape::InstructionSet::Baseline); }
  ~BaselineInstructionSet() { drape::use_instruction_set(saved); }
  BaselineInstructionSet(const BaselineInstructionSet&) = delete;
  BaselineInstructionSet& operator=(const BaselineInstructionSet&) = delete;
};

/// Names are `family/key=value/.../n:N/threads:T`; scripts/bench_report.py parses them.
/// Minimum timed seconds per repetition: `quick_min_time` for most families; the families the
/// targets are read from get `headline_min_time`, so a 0.2 s step at 257 x 257 is averaged over
/// several steps instead of timed once (single steps there varied by 1.5x on the shared machine).
inline constexpr double quick_min_time = 0.1;
inline constexpr double headline_min_time = 1.0;

/// Adds the grid sizes up to `max_n` as arguments, each with the thread counts `threads`
/// (empty: not a threaded benchmark, no thread argument).
inline benchmark::internal::Benchmark* sized(benchmark::internal::Benchmark* b, const std::vector<int>& threads,
                                             benchmark::TimeUnit unit, int max_n = 257,
                                             double min_time = quick_min_time) {
  b->Unit(unit)->MinTime(min_time);
  if (!threads.empty()) {
    b->ArgNames({"n", "threads"});
    for (int n : grid_sizes)
      for (int t : threads)
        if (n <= max_n) b->Args({n, t});
  } else {
    b->ArgNames({"n"});
    for (int n : grid_sizes)
      if (n <= max_n) b->Args({n});
  }
  return b;
}
/// Thread-count sets for sized().
inline const std::vector<int> serial = {};
inline const std::vector<int> one_and_two = {1, 2};
inline const std::vector<int> two = {2};

/// Runs `step(state)` once per benchmark iteration from the scene's warm state, resetting to it
/// every `window` steps outside the timer, and records solver counters:
/// `cg_iterations` (mean per step), `residual_max` (largest relative residual), `failures`.
/// With `prime`, every (re)start also takes one untimed step first, so a warm-started iterative
/// solver always starts from the previous step's solution, as it does in a running simulation.
template <class StepFn>
void run_steps(benchmark::State& st, const Scene& sc, int window, StepFn&& step, bool prime = false) {
  drape::State<double> s = sc.warm;
  if (prime) step(s);
  int k = 0;
  long long steps = 0, iterations = 0, failures = 0;
  double residual_max = 0;
  for (auto _ : st) {
    if (k == window) {
      st.PauseTiming();
      s = sc.warm;
      if (prime) step(s);
      k = 0;
      st.ResumeTiming();
    }
    const drape::StepStatus r = step(s);
    benchmark::DoNotOptimize(s.positions.data());
    benchmark::ClobberMemory();
    ++k;
    ++steps;
    iterations += r.iterations;
    if (r.residual > residual_max) residual_max = r.residual;
    if (!r.ok()) ++failures;
  }
  st.counters["cg_iterations"] = steps ? double(iterations) / double(steps) : 0.0;
  st.counters["residual_max"] = residual_max;
  st.counters["failures"] = double(failures);
  st.counters["compressed"] = sc.compressed_fraction;
  st.counters["nodes"] = double(sc.cloth->node_count());
  st.SetItemsProcessed(st.iterations() * sc.cloth->node_count());
}

}  // namespace drape_bench
