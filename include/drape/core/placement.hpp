#pragma once
/// \file placement.hpp
/// Where a cloth starts: its flat grid (grid.hpp: in the x-z plane, node 0 at the origin) turned
/// and moved as a rigid body. Several cloths in one scene each have their own.

#include <Eigen/Geometry>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar = double>
struct Placement {
  /// m: where the grid's node 0 goes.
  Vec3<Scalar> position = Vec3<Scalar>::Zero();
  /// Degrees about the x, then the y, then the z axis (fixed axes: R = Rz Ry Rx).
  Vec3<Scalar> rotation_degrees = Vec3<Scalar>::Zero();

  bool is_identity() const { return position.isZero(0) && rotation_degrees.isZero(0); }

  Mat3<Scalar> rotation() const {
    const Scalar to_radians = Scalar(3.14159265358979323846) / Scalar(180);
    using Turn = Eigen::AngleAxis<Scalar>;
    return (Turn(rotation_degrees.z() * to_radians, Vec3<Scalar>::UnitZ()) *
            Turn(rotation_degrees.y() * to_radians, Vec3<Scalar>::UnitY()) *
            Turn(rotation_degrees.x() * to_radians, Vec3<Scalar>::UnitX()))
        .toRotationMatrix();
  }

  /// The grid's positions `x` (3 x n) placed; exactly `x` for the identity placement.
  Matrix3X<Scalar> apply(const Matrix3X<Scalar>& x) const {
    if (is_identity()) return x;
    return (rotation() * x).colwise() + position;
  }

  /// \throws InvalidParameter naming `placement.position` or `placement.rotation` if not finite.
  void validate() const {
    if (!position.allFinite()) detail::fail_argument("placement.position", "a non-finite value", "finite metres");
    if (!rotation_degrees.allFinite())
      detail::fail_argument("placement.rotation", "a non-finite value", "finite degrees");
  }
};

}  // namespace drape
