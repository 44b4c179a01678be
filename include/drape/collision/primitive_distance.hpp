#pragma once
/// \file primitive_distance.hpp
/// Closest points between the primitives of a triangle mesh: a point and a triangle, two segments.
/// Cloth self-collision measures every vertex-triangle and edge-edge proximity with these, and the
/// weights they return say how a repulsion is shared among the primitives' vertices.
///
/// Degenerate input (a zero-area triangle, a zero-length segment, parallel segments) gives the
/// correct distance and valid weights, never a division by zero. The distance is accurate to a few
/// eps of the coordinates; where the closest points are ill-conditioned (near-parallel segments, a
/// sliver of a triangle) any pair of nearly closest points may come back. Float input is computed
/// in double: this scalar code costs the same in both.

#include <algorithm>
#include <array>
#include <limits>
#include <type_traits>

#include <Eigen/Geometry>

#include "drape/core/types.hpp"

namespace drape {

/// The point of a triangle abc closest to a query point is w0 a + w1 b + w2 c.
template <class Scalar>
struct PointTriangleClosest {
  Scalar distance_squared;
  Vec3<Scalar> weights;  ///< barycentric: each >= 0, summing to 1
};

/// The point of the closed triangle abc closest to p. A zero-area triangle (collinear or
/// coincident corners) is the union of its edges and is treated as such.
template <class Scalar>
PointTriangleClosest<Scalar> closest_point_on_triangle(const Vec3<Scalar>& p, const Vec3<Scalar>& a,
                                                       const Vec3<Scalar>& b, const Vec3<Scalar>& c);

/// The closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of two segments.
template <class Scalar>
struct SegmentClosest {
  Scalar distance_squared;
  Scalar s;  ///< in [0, 1]
  Scalar t;  ///< in [0, 1]
};

/// The closest points of the closed segments p0 p1 and q0 q1. Parallel segments, whose closest
/// pairs are not unique, get one of them; a zero-length segment is a point.
template <class Scalar>
SegmentClosest<Scalar> closest_points_on_segments(const Vec3<Scalar>& p0, const Vec3<Scalar>& p1,
                                                  const Vec3<Scalar>& q0, const Vec3<Scalar>& q1);

// ---------------------------------------------------------------------------------------------

namespace detail {

/// The type the geometry is computed in: double for float input, the input type otherwise.
template <class Scalar>
using PreciseScalar = std::conditional_t<std::is_same_v<Scalar, float>, double, Scalar>;

/// Parameter in [0, 1] of the point of the segment a + s ab closest to p (0 if ab is zero).
template <class Real>
Real closest_on_segment(const Vec3<Real>& p, const Vec3<Real>& a, const Vec3<Real>& ab) {
  const Real length_squared = ab.squaredNorm();
  if (!(length_squared > 0)) return Real(0);
  return std::clamp(ab.dot(p - a) / length_squared, Real(0), Real(1));
}

}  // namespace detail

template <class Scalar>
PointTriangleClosest<Scalar> closest_point_on_triangle(const Vec3<Scalar>& p, const Vec3<Scalar>& a,
                                                       const Vec3<Scalar>& b, const Vec3<Scalar>& c) {
  using Real = detail::PreciseScalar<Scalar>;
  const std::array<Vec3<Real>, 3> corner = {a.template cast<Real>(), b.template cast<Real>(), c.template cast<Real>()};
  const Vec3<Real> x = p.template cast<Real>();
  const Vec3<Real> ab = corner[1] - corner[0], ac = corner[2] - corner[0], ap = x - corner[0];
  const Vec3<Real> normal = ab.cross(ac);
  const Real normal_squared = normal.squaredNorm();

  Real best = std::numeric_limits<Real>::infinity();
  Vec3<Real> weights(1, 0, 0);
  const auto consider = [&](const Vec3<Real>& w) {
    const Real d2 = (w[0] * corner[0] + w[1] * corner[1] + w[2] * corner[2] - x).squaredNorm();
    if (d2 < best) {
      best = d2;
      weights = w;
    }
  };

  // The projection onto the plane, if it falls inside. Its weights come from p directly: the
  // normal component of ap drops out of both cross products.
  if (normal_squared > 0) {
    const Real wb = ap.cross(ac).dot(normal) / normal_squared;
    const Real wc = ab.cross(ap).dot(normal) / normal_squared;
    const Real wa = 1 - wb - wc;
    if (wa >= 0 && wb >= 0 && wc >= 0) {
      consider(Vec3<Real>(wa, wb, wc));
      // The weights' rounding error grows like eps / sin(angle at a); past a sliver the edges are
      // computed too and the better point is kept.
      const Real sliver = 64 * std::numeric_limits<Real>::epsilon();
      if (normal_squared > sliver * ab.squaredNorm() * ac.squaredNorm())
        return {Scalar(best), weights.template cast<Scalar>()};
    }
  }
  // Outside the face (or no face at all): the closest point is on an edge.
  for (int e = 0; e < 3; ++e) {
    const int from = e, to = (e + 1) % 3;
    const Real s = detail::closest_on_segment(x, corner[from], Vec3<Real>(corner[to] - corner[from]));
    Vec3<Real> w = Vec3<Real>::Zero();
    w[from] = 1 - s;
    w[to] = s;
    consider(w);
  }
  return {Scalar(best), weights.template cast<Scalar>()};
}

template <class Scalar>
SegmentClosest<Scalar> closest_points_on_segments(const Vec3<Scalar>& p0, const Vec3<Scalar>& p1,
                                                  const Vec3<Scalar>& q0, const Vec3<Scalar>& q1) {
  using Real = detail::PreciseScalar<Scalar>;
  const Vec3<Real> p = p0.template cast<Real>(), q = q0.template cast<Real>();
  const Vec3<Real> dp = p1.template cast<Real>() - p, dq = q1.template cast<Real>() - q;

  Real best = std::numeric_limits<Real>::infinity(), best_s = 0, best_t = 0;
  const auto consider = [&](Real s, Real t) {
    const Real d2 = (p + s * dp - q - t * dq).squaredNorm();
    if (d2 < best) {
      best = d2;
      best_s = s;
      best_t = t;
    }
  };

  // The distance is convex on [0, 1]^2: its minimum is the stationary point if that lies inside,
  // else on the boundary, where one parameter is 0 or 1 and the other a point's projection. Every
  // candidate is a pair of points on the segments and the smallest distance wins.
  // The stationary point: s minimises the distance from p(s) to q's line, |w0 + s w1| with w0 =
  // (p - q) x u, w1 = dp x u (u along q), then t projects p(s) onto q. Written so, rounding perturbs
  // the distance by ~eps |p - q| for every s: near-parallel segments, whose s is ill-conditioned,
  // still get a point of near-minimal distance (the normal equations of the squared distance
  // would perturb its square instead, an error of ~sqrt(eps) in the distance).
  const Real length_q = dq.norm();
  if (length_q > 0) {
    const Vec3<Real> along_q = dq / length_q;
    const Vec3<Real> w0 = (p - q).cross(along_q), w1 = dp.cross(along_q);
    const Real w1_squared = w1.squaredNorm();
    if (w1_squared > 0) {
      const Real s = std::clamp(-w0.dot(w1) / w1_squared, Real(0), Real(1));
      consider(s, detail::closest_on_segment(Vec3<Real>(p + s * dp), q, dq));
    }
  }
  consider(Real(0), detail::closest_on_segment(p, q, dq));
  consider(Real(1), detail::closest_on_segment(Vec3<Real>(p + dp), q, dq));
  consider(detail::closest_on_segment(q, p, dp), Real(0));
  consider(detail::closest_on_segment(Vec3<Real>(q + dq), p, dp), Real(1));
  return {Scalar(best), Scalar(best_s), Scalar(best_t)};
}

}  // namespace drape
