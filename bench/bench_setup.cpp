/// \file bench_setup.cpp
/// Scene set-up, which users wait for too: building the cloth (grid, springs in colours, pins) and
/// constructing the integrators (for the implicit one: sparsity pattern, scatter map and symbolic
/// analysis of the solver, see bench_implicit.cpp).

#include "bench_common.hpp"

namespace drape_bench {
namespace {

void setup_cloth(benchmark::State& st) {
  const drape::ClothSpec<double> spec = scene_spec(int(st.range(0)));
  for (auto _ : st) {
    drape::Cloth<double> cloth(spec);
    benchmark::DoNotOptimize(cloth.springs().a().data());
  }
  st.counters["nodes"] = double(spec.nx * spec.ny);
}

void setup_rk2(benchmark::State& st) {
  const drape::ClothSpec<double> spec = scene_spec(int(st.range(0)));
  for (auto _ : st) {
    drape::Cloth<double> cloth(spec);
    drape::Rk2<double> rk2(cloth, {drape::IntegratorOptions{}.dt, 2});
    benchmark::DoNotOptimize(&rk2);
  }
  st.counters["nodes"] = double(spec.nx * spec.ny);
}

const bool registered = [] {
  sized(benchmark::RegisterBenchmark("setup/what=cloth", setup_cloth), serial, benchmark::kMillisecond);
  sized(benchmark::RegisterBenchmark("setup/what=cloth+rk2", setup_rk2), serial, benchmark::kMillisecond);
  return true;
}();

}  // namespace
}  // namespace drape_bench
