#pragma once
/// \file stability.hpp
/// The largest time step at which an explicit integrator runs a scene for 5 s without diverging,
/// by bisection (to 2%) on a log scale between 10 us and 20 ms. A run is stable if every step
/// succeeds and every node stays within 5 cloth sides of the origin (the cloth hangs from its
/// pins; a diverging run leaves that box within a few steps). Bisection assumes stability is
/// monotonic in dt, which held wherever we probed by hand. One thread (stability does not depend
/// on the thread count). Used by stable_dt.cpp and sim_second.cpp.

#include <algorithm>
#include <cmath>

#include "drape/integrators/make_integrator.hpp"

namespace drape_bench {

inline bool stable(const drape::Cloth<double>& cloth, drape::IntegratorKind kind, double dt, double seconds) {
  const double box = 5 * (std::max(cloth.grid().nx(), cloth.grid().ny()) - 1) * cloth.grid().spacing();
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

inline double largest_stable_dt(const drape::Cloth<double>& cloth, drape::IntegratorKind kind) {
  double lo = 1e-5, hi = 0.02;
  while (hi / lo > 1.02) {
    const double mid = std::sqrt(lo * hi);
    (stable(cloth, kind, mid, 5.0) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace drape_bench
