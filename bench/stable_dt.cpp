/// \file stable_dt.cpp
/// The largest time step at which each explicit integrator (RK2, symplectic Euler) runs a scene
/// for 5 s without diverging (stability.hpp says how it is found and what counts as stable).
///
///   build/bench/bench/drape_stable_dt [n ...] [--reference]
///
/// Scene: the default cloth (docs/parameters.md), two corners pinned, n x n nodes (default 33);
/// `--reference`: the soft reference constants (ks 1000 / 1000 / 100 N/m, kd 1 / 1 /
/// 0.1 N s/m) used to compare with other simulators. One thread (the result does not depend on it).

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "stability.hpp"

int main(int argc, char** argv) {
  bool reference = false;
  std::vector<int> sizes;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--reference") == 0)
      reference = true;
    else
      sizes.push_back(std::atoi(argv[k]));
  }
  if (sizes.empty()) sizes.push_back(33);
  for (const int n : sizes) {
    drape::ClothSpec<double> spec;
    spec.nx = spec.ny = n;
    if (reference) spec.springs = {{1000, 1}, {1000, 1}, {100, 0.1}};
    const drape::Cloth<double> cloth(spec);
    for (const drape::IntegratorKind kind : {drape::IntegratorKind::Rk2, drape::IntegratorKind::Symplectic})
      std::printf("%d x %d, %s constants, %s: largest stable dt %.3g ms\n", n, n, reference ? "reference" : "default",
                  drape::to_string(kind), drape_bench::largest_stable_dt(cloth, kind) * 1e3);
  }
}
