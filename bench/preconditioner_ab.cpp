/// \file preconditioner_ab.cpp
/// Two preconditioners of the default implicit solver timed against each other in one process,
/// interleaved round by round so that the machine's drift hits both alike: the benchmark scene
/// (N x N, both corners pinned, dt = 1/60), each round a fresh integrator per preconditioner,
/// 5 warm-up steps, then `steps` timed steps. Prints the median step time of each, the median of
/// the per-round ratios (second / first) and the CG iterations of each (docs/performance.md).
///
///   build/bench/bench/drape_preconditioner_ab [N=33] [threads=1] [rounds=11] [steps=60]
///                                             [first=multigrid] [second=multigrid-float]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 33;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 11;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 60;
  drape::PreconditionerKind kinds[2] = {drape::PreconditionerKind::Multigrid, drape::PreconditionerKind::MultigridFloat};
  for (int k = 0; k < 2; ++k)
    if (argc > 5 + k && !drape::try_parse(argv[5 + k], kinds[k])) {
      std::fprintf(stderr, "preconditioner: '%s', expected %s\n", argv[5 + k],
                   drape::joined_names<drape::PreconditionerKind>().c_str());
      return 2;
    }
  if (n < 3 || threads < 1 || rounds < 1 || steps < 1) {
    std::fprintf(stderr, "usage: %s [N >= 3] [threads >= 1] [rounds >= 1] [steps >= 1] [first] [second]\n", argv[0]);
    return 2;
  }
  drape::ClothSpec<double> spec;
  spec.nx = spec.ny = n;
  const drape::Cloth<double> cloth(spec);
  std::vector<double> ms[2], ratio;
  long iterations[2] = {0, 0};
  for (int round = 0; round < rounds; ++round) {
    for (int k = 0; k < 2; ++k) {
      drape::ImplicitOptions options;
      options.dt = 1.0 / 60;
      options.threads = threads;
      options.preconditioner = kinds[k];
      drape::ImplicitEuler<double> integrator(cloth, options);
      drape::State<double> state = cloth.initial_state();
      for (int i = 0; i < 5; ++i) integrator.step(state);
      const auto start = std::chrono::steady_clock::now();
      for (int i = 0; i < steps; ++i) {
        const drape::StepStatus status = integrator.step(state);
        if (!status.ok()) {
          std::fprintf(stderr, "%s: step failed: %s\n", drape::to_string(kinds[k]), drape::to_string(status.error));
          return 1;
        }
        iterations[k] += status.iterations;
      }
      ms[k].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() /
                      steps);
    }
    ratio.push_back(ms[1].back() / ms[0].back());
  }
  std::printf("%d x %d, %d thread(s), %d rounds of %d steps: %s %.3f ms, %s %.3f ms per step; median ratio %.3f; "
              "CG iterations %ld and %ld\n",
              n, n, threads, rounds, steps, drape::to_string(kinds[0]), median(ms[0]), drape::to_string(kinds[1]),
              median(ms[1]), median(ratio), iterations[0], iterations[1]);
}
