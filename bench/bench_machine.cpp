/// \file bench_machine.cpp
/// The machine's streaming memory bandwidth (STREAM triad a = b + s c over arrays far larger than
/// the last-level cache), so docs/benchmarks.md can say which steps are memory-bound: a CG
/// iteration at 257 x 257 streams the whole system matrix (~62 MB) once.

#include <vector>

#include <benchmark/benchmark.h>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace drape_bench {
namespace {

void stream_triad(benchmark::State& st) {
  const long n = 8L << 20;  // 8 Mi doubles = 64 MiB per array, 192 MiB in all
  const int threads = int(st.range(0));
  std::vector<double> a(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n), 1.0),
      c(static_cast<std::size_t>(n), 2.0);
  double* pa = a.data();
  const double* pb = b.data();
  const double* pc = c.data();
  for (auto _ : st) {
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (long i = 0; i < n; ++i) pa[i] = pb[i] + 3.0 * pc[i];
    benchmark::DoNotOptimize(pa);
    benchmark::ClobberMemory();
  }
  (void)threads;
  st.SetBytesProcessed(st.iterations() * 3 * n * long(sizeof(double)));
}

const bool registered = [] {
  benchmark::RegisterBenchmark("machine/what=stream_triad", stream_triad)
      ->ArgNames({"threads"})
      ->Arg(1)
      ->Arg(2)
      ->Unit(benchmark::kMillisecond)
      ->MinTime(0.2);
  return true;
}();

}  // namespace
}  // namespace drape_bench
