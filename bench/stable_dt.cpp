/// \file stable_dt.cpp
/// The largest time step at which each explicit integrator (RK2, symplectic Euler) runs a scene
/// for 5 s without diverging, found by bisection (to 2%) on a log scale between 10 us and 20 ms.
/// A run is stable if every step succeeds and every node stays within 5 cloth sides of the origin
/// (the cloth hangs from its pins; a diverging run leaves that box within a few steps). Bisection
/// assumes stability is monotonic in dt, which held wherever we probed by hand.
///
///   build/bench/bench/drape_stable_dt [n ...] [--reference]
///
/// Scene: the default cloth (docs/parameters.md), two corners pinned, n x n nodes (default 33);
/// `--reference`: the soft reference constants of issue 14 (ks 1000 / 1000 / 100 N/m, kd 1 / 1 /
/// 0.1 N s/m) used to compare with other simulators. One thread (the result does not depend on it).

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "drape/integrators/make_integrator.hpp"

namespace {

bool stable(const drape::Cloth<double>& cloth, drape::IntegratorKind kind, double dt, double seconds, double box) {
  drape::ImplicitOptions options;
  options.dt = dt;
  options.threads = 1;
  auto stepper = drape::make_integrator(cloth, kind, options);
  drape::State<double> s = cloth.initial_state();
  const long steps = std::lround(seconds / dt);
  for (long k = 0; k < steps; ++k)
    if (!stepper->step(s).ok() || !(s.positions.cwiseAbs().maxCoeff() < box)) return false;
  return true;
}

}  // namespace

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
    const double box = 5 * (n - 1) * spec.spacing;
    for (const drape::IntegratorKind kind : {drape::IntegratorKind::Rk2, drape::IntegratorKind::Symplectic}) {
      double lo = 1e-5, hi = 0.02;
      while (hi / lo > 1.02) {
        const double mid = std::sqrt(lo * hi);
        (stable(cloth, kind, mid, 5.0, box) ? lo : hi) = mid;
      }
      std::printf("%d x %d, %s constants, %s: largest stable dt %.3g ms\n", n, n, reference ? "reference" : "default",
                  drape::to_string(kind), lo * 1e3);
    }
  }
}
