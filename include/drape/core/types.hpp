#pragma once
/// \file types.hpp
/// Eigen aliases used throughout drape. Node data is stored column-per-node (`3 x n`), so the flat
/// view of the same memory is the `3n` vector `(x0, y0, z0, x1, y1, z1, ...)` used by the solvers.

#include <Eigen/Core>

namespace drape {

using Index = Eigen::Index;

template <class Scalar>
using Vec3 = Eigen::Matrix<Scalar, 3, 1>;
template <class Scalar>
using Mat3 = Eigen::Matrix<Scalar, 3, 3>;
/// `3 x n` node data: positions, velocities, forces.
template <class Scalar>
using Matrix3X = Eigen::Matrix<Scalar, 3, Eigen::Dynamic>;
template <class Scalar>
using VectorX = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

/// Flat `3n` view of `3 x n` node data (no copy).
template <class Scalar>
Eigen::Map<VectorX<Scalar>> flat(Matrix3X<Scalar>& m) {
  return {m.data(), m.size()};
}
template <class Scalar>
Eigen::Map<const VectorX<Scalar>> flat(const Matrix3X<Scalar>& m) {
  return {m.data(), m.size()};
}

}  // namespace drape
