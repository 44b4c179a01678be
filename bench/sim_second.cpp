/// \file sim_second.cpp
/// Wall time per simulated second: the cost a user pays for a second of cloth, whichever
/// integrator they pick. Each explicit integrator (RK2, symplectic Euler) runs at its largest
/// stable dt, found first by the bisection of stable_dt.cpp (a 5 s run, to 2%); the implicit step
/// at dt = 1/60 and 1/30. Each run starts from the flat cloth, simulates `--seconds` (default 5,
/// the stability run's length) and is timed whole (stepping only, not the set-up); the median of
/// `--repetitions` runs is reported, with steps per simulated second and the mean step time.
///
///   build/bench/bench/drape_sim_second [n ...] [--reference] [--threads T] [--repetitions R]
///                                      [--seconds S]
///
/// Scene: the default cloth (docs/parameters.md), two corners pinned, n x n nodes (default 33);
/// `--reference`: the soft reference constants (ks 1000 / 1000 / 100 N/m, kd 1 / 1 /
/// 0.1 N s/m). Threads: 2 by default (the bisection runs on 1 thread: stability does not depend
/// on it). Prints a markdown table.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "drape/integrators/make_integrator.hpp"
#include "stability.hpp"
#include "tool_text.hpp"

namespace {

struct Timed {
  double seconds_per_simulated_second = 0;  // median wall time / simulated time
  long steps = 0;
  int failed_at = -1;  // first failed step, -1 if none
};

Timed time_runs(const drape::Cloth<double>& cloth, drape::IntegratorKind kind, double dt, int threads, double simulated,
                int repetitions) {
  Timed out;
  out.steps = std::lround(simulated / dt);
  std::vector<double> walls;
  for (int r = 0; r < repetitions; ++r) {
    drape::ImplicitOptions options;
    options.dt = dt;
    options.threads = threads;
    auto stepper = drape::make_integrator(cloth, kind, options);
    drape::State<double> s = cloth.initial_state();
    const auto start = std::chrono::steady_clock::now();
    for (long k = 0; k < out.steps; ++k)
      if (!stepper->step(s).ok()) {
        out.failed_at = int(k);
        return out;
      }
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(walls.begin(), walls.end());
  out.seconds_per_simulated_second = walls[walls.size() / 2] / (double(out.steps) * dt);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  bool reference = false;
  int threads = 2, repetitions = 3;
  double simulated = 5.0;
  std::vector<int> sizes;
  for (int k = 1; k < argc; ++k) {
    const bool has_value = k + 1 < argc;
    if (std::strcmp(argv[k], "--reference") == 0) {
      reference = true;
    } else if (std::strcmp(argv[k], "--threads") == 0 && has_value) {
      threads = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--repetitions") == 0 && has_value) {
      repetitions = std::atoi(argv[++k]);
    } else if (std::strcmp(argv[k], "--seconds") == 0 && has_value) {
      simulated = std::atof(argv[++k]);
    } else {
      sizes.push_back(std::atoi(argv[k]));
    }
  }
  if (sizes.empty()) sizes.push_back(33);
  if (threads < 1 || repetitions < 1 || !(simulated > 0) ||
      std::any_of(sizes.begin(), sizes.end(), [](int n) { return n < 2; })) {
    std::fprintf(stderr, "drape_sim_second: sizes >= 2, --threads >= 1, --repetitions >= 1, --seconds > 0\n");
    return 2;
  }
  std::printf("%s constants, %d thread(s), median of %d runs of %g simulated s from the flat cloth\n\n",
              reference ? "reference" : "default", threads, repetitions, simulated);
  std::printf("| n x n | integrator | dt | steps per simulated s | wall time per simulated s | per step |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const int n : sizes) {
    drape::ClothSpec<double> spec;
    spec.nx = spec.ny = n;
    if (reference) spec.springs = {{1000, 1}, {1000, 1}, {100, 0.1}};
    const drape::Cloth<double> cloth(spec);
    struct Row {
      drape::IntegratorKind kind;
      double dt;
      const char* how;
    };
    std::vector<Row> rows;
    for (const drape::IntegratorKind kind : {drape::IntegratorKind::Rk2, drape::IntegratorKind::Symplectic})
      rows.push_back({kind, drape_bench::largest_stable_dt(cloth, kind), "largest stable"});
    rows.push_back({drape::IntegratorKind::Implicit, 1.0 / 60, "1/60"});
    rows.push_back({drape::IntegratorKind::Implicit, 1.0 / 30, "1/30"});
    for (const Row& row : rows) {
      const Timed t = time_runs(cloth, row.kind, row.dt, threads, simulated, repetitions);
      char dt_text[64];
      std::snprintf(dt_text, sizeof dt_text, "%.3g ms (%s)", row.dt * 1e3, row.how);
      if (t.failed_at >= 0) {
        std::printf("| %d | %s | %s | %.0f | step %d failed | - |\n", n, drape::to_string(row.kind), dt_text,
                    1 / row.dt, t.failed_at);
        continue;
      }
      std::printf("| %d | %s | %s | %.0f | %s | %s |\n", n, drape::to_string(row.kind), dt_text, 1 / row.dt,
                  drape_bench::duration(t.seconds_per_simulated_second).c_str(),
                  drape_bench::duration(t.seconds_per_simulated_second * row.dt).c_str());
      std::fflush(stdout);
    }
  }
}
