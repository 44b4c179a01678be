#pragma once
// Shared helpers for drape's tests.

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"

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

/// Central differences (step 1e-6) of the total force (springs, gravity, force terms) at time `t`
/// with respect to positions (`wrt_x`) or velocities, dense.
inline Eigen::MatrixXd fd_jacobian(const Cloth<double>& cloth, const Matrix3X<double>& x, const Matrix3X<double>& v,
                                   bool wrt_x, double t = 0) {
  ForceAssembler<double> forces(cloth, 1);
  Eigen::MatrixXd j(x.size(), x.size());
  Matrix3X<double> fp(3, cloth.node_count()), fm(3, cloth.node_count());
  const double h = 1e-6;
  for (Index k = 0; k < x.size(); ++k) {
    Matrix3X<double> xp = x, xm = x, vp = v, vm = v;
    (wrt_x ? xp : vp).data()[k] += h;
    (wrt_x ? xm : vm).data()[k] -= h;
    forces.force(xp, vp, t, fp);
    forces.force(xm, vm, t, fm);
    j.col(k) = (flat(fp) - flat(fm)) / (2 * h);
  }
  return j;
}

/// Largest entry of |a - b| over max(1, largest entry of |b|).
inline double max_relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

/// Largest |m_i (v_end - v_start) - dt f(x_end, v_end)| over the free nodes (N s): how far the
/// step from `start` to `end` is from satisfying the backward Euler equations.
inline double backward_euler_residual(const Cloth<double>& cloth, const State<double>& start, const State<double>& end,
                                      double dt) {
  Matrix3X<double> f(3, cloth.node_count());
  ForceAssembler<double>(cloth, 1).force(end.positions, end.velocities, end.time, f);
  double worst = 0;
  for (int i = 0; i < cloth.node_count(); ++i)
    if (!cloth.pins().is_pinned(i))
      worst = std::max(
          worst, (cloth.grid().masses()[i] * (end.velocities.col(i) - start.velocities.col(i)) - dt * f.col(i)).norm());
  return worst;
}

}  // namespace drape::test
