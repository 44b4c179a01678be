#pragma once
// Shared helpers for drape's tests.

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "drape/core/cloth.hpp"

namespace drape::test {

/// `|a - b| <= eps * max(1, |a|, |b|)`: relative for large values, absolute near zero.
template <class S>
bool close(S a, S b, S eps) {
  return std::abs(a - b) <= eps * std::max({S(1), std::abs(a), std::abs(b)});
}

/// A small cloth with every spring category active, gravity off unless asked for.
template <class S>
ClothSpec<S> small_spec(int n = 5, S gravity = S(0)) {
  ClothSpec<S> spec;
  spec.nx = n;
  spec.ny = n;
  spec.gravity = gravity;
  spec.springs = {{S(300), S(0)}, {S(200), S(0)}, {S(50), S(0)}};
  return spec;
}

/// Rest positions displaced by up to `amplitude * spacing` in every direction: springs end up both
/// stretched and compressed.
template <class S>
Matrix3X<S> jiggled_positions(const Cloth<S>& cloth, S amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3X<S> x = cloth.grid().rest_positions();
  for (Index i = 0; i < x.size(); ++i) x.data()[i] += S(u(rng) * double(amplitude * cloth.grid().spacing()));
  return x;
}

template <class S>
Matrix3X<S> random_velocities(int n, S amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3X<S> v(3, n);
  for (Index i = 0; i < v.size(); ++i) v.data()[i] = S(amplitude * u(rng));
  return v;
}

}  // namespace drape::test
