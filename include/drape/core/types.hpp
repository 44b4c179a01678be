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

/// Read-only `3 x n` node data as a function argument: binds without a copy to a `Matrix3X` and to
/// an `Eigen::Map` of contiguous memory (e.g. an array the caller owns); anything else (an
/// expression, a block of a larger matrix) is evaluated into a temporary first.
template <class Scalar>
using ConstRef3X = Eigen::Ref<const Matrix3X<Scalar>, 0, Eigen::OuterStride<3>>;
/// Writable `3 x n` node data as a function argument: a `Matrix3X` or a `Map` of contiguous memory.
template <class Scalar>
using Ref3X = Eigen::Ref<Matrix3X<Scalar>, 0, Eigen::OuterStride<3>>;

/// Flat `3n` view of `3 x n` node data (no copy).
template <class Scalar>
Eigen::Map<VectorX<Scalar>> flat(Matrix3X<Scalar>& m) {
  return {m.data(), m.size()};
}
template <class Scalar>
Eigen::Map<const VectorX<Scalar>> flat(const Matrix3X<Scalar>& m) {
  return {m.data(), m.size()};
}

namespace detail {
/// `T` in a parameter list without taking part in template argument deduction (std::type_identity
/// of C++20), so `f(const Cloth<S>&, ConstRef3X<S>)` deduces S from the cloth alone.
template <class T>
struct NonDeduced {
  using type = T;
};
template <class T>
using NonDeducedT = typename NonDeduced<T>::type;
}  // namespace detail

}  // namespace drape
