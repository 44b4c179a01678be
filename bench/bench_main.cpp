/// \file bench_main.cpp
/// Entry point of drape_bench: records how the numbers were produced in the JSON context, warns
/// when OpenBLAS may spin threads against drape's own, and defines the warm-up of the timed states.

#include <cstdio>
#include <cstdlib>
#include <string>

#include <Eigen/Core>

#include "bench_common.hpp"
#include "drape/config.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/platform/team.hpp"

namespace drape_bench {

const char* const warm_up_method = "drape RK2 at its default dt = 0.5 ms";

void warm_up(const drape::Cloth<double>& cloth, drape::State<double>& state) {
  // One thread: bitwise the same as 2 threads, and immune to a busy machine.
  drape::Rk2<double> rk2(cloth, {drape::IntegratorOptions{}.dt, 1});
  const int steps = int(warm_up_time / rk2.dt() + 0.5);
  for (int k = 0; k < steps; ++k)
    if (!rk2.step(state)) {
      std::fprintf(stderr, "drape_bench: warm-up diverged at step %d of %d for %d nodes\n", k, steps,
                   cloth.node_count());
      std::exit(1);
    }
}

}  // namespace drape_bench

int main(int argc, char** argv) {
  const char* blas_threads = std::getenv("OPENBLAS_NUM_THREADS");
  if (!blas_threads || std::string(blas_threads) != "1")
    std::fprintf(stderr,
                 "drape_bench: warning: OPENBLAS_NUM_THREADS is not 1; OpenBLAS's spinning threads can slow "
                 "drape's parallel loops 100x (docs/benchmarks.md). scripts/bench.sh sets it.\n");
  benchmark::AddCustomContext("drape_version", std::to_string(DRAPE_VERSION_MAJOR) + "." +
                                                   std::to_string(DRAPE_VERSION_MINOR) + "." +
                                                   std::to_string(DRAPE_VERSION_PATCH));
  benchmark::AddCustomContext("compiler", DRAPE_BENCH_COMPILER);
  benchmark::AddCustomContext("cxx_flags", DRAPE_BENCH_CXX_FLAGS);
  benchmark::AddCustomContext("openmp", DRAPE_BENCH_OPENMP ? "yes" : "no");
  benchmark::AddCustomContext("max_threads", std::to_string(drape::max_threads()));
  benchmark::AddCustomContext("eigen_version", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                                   std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                                   std::to_string(EIGEN_MINOR_VERSION));
  benchmark::AddCustomContext("openblas_num_threads", blas_threads ? blas_threads : "unset");
  benchmark::AddCustomContext("warm_up_time_s", std::to_string(drape_bench::warm_up_time));
  benchmark::AddCustomContext("warm_up_method", drape_bench::warm_up_method);
  benchmark::AddCustomContext("rk2_window", std::to_string(drape_bench::rk2_window));
  benchmark::AddCustomContext("implicit_window", std::to_string(drape_bench::implicit_window));
  const drape::ImplicitOptions defaults;
  benchmark::AddCustomContext("default_solver", drape::to_string(defaults.solver));
  benchmark::AddCustomContext("default_preconditioner", drape::to_string(defaults.preconditioner));
  benchmark::AddCustomContext("default_jacobian", drape::to_string(defaults.jacobian));
  benchmark::AddCustomContext("default_tolerance", std::to_string(defaults.tolerance));
  bool listing = false;
  for (int i = 1; i < argc; ++i) listing = listing || std::string(argv[i]).rfind("--benchmark_list_tests", 0) == 0;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // DRAPE_BENCH_SKIP_CHECK=1 skips the start-up accuracy check (quick experiments only).
  const char* skip = std::getenv("DRAPE_BENCH_SKIP_CHECK");
  if (!listing && !(skip && std::string(skip) == "1"))
    benchmark::AddCustomContext("accuracy", drape_bench::check_accuracy());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
