#pragma once
/// \file continuous_collision.hpp
/// Continuous collision tests for cloth self-collision (Bridson, Fedkiw & Anderson 2002): over one
/// time step every point moves on a straight line from its start to its end position, time t in
/// [0, 1] across the step, and a test returns the earliest t at which a vertex and a triangle, or two
/// edges, come within `tolerance` of each other, so a vertex passing through a triangle or two edges
/// passing through each other are caught when they first touch.
///
/// What the tests promise, for any input (coplanar motion, parallel edges, zero-area triangles,
/// contact at t = 0 or t = 1, tiny or large motion, float or double):
///  - never late: no time before the returned one brings the pair within `tolerance`; `nullopt`
///    means the distance stays above `tolerance` during the whole step;
///  - never far: at the returned time the distance is at most 2 tolerance + 3 r, where r = 64 eps
///    max|coordinate| bounds the rounding (eps of double: float input is computed in double). A
///    false positive is a near contact, never a pair far apart.
/// `tolerance` is a distance: a small one (1e-6 of the cloth's size) makes the test a crossing
/// test; the cloth's thickness makes it a minimum-separation test.
///
/// Method: a search over time that excludes whole intervals, rather than root finding on the
/// coplanarity cubic. The cubic method finds the times at which the four points are coplanar and
/// tests the distance there; a cubic that vanishes identically (coplanar motion), a double root (a
/// grazing vertex), near-parallel edges and the rounding of both steps each need their own repair,
/// and each is where such codes miss crossings. Here every exclusion is a lower bound of the
/// distance that holds for any input, widened by the rounding bound; an interval is dropped when
/// one of them stays above `tolerance` across it:
///  - the convex hull: the gap between a point of one primitive and a point of the other is affine
///    in time and in each primitive's barycentric coordinates, so every gap during [t0, t1] is a
///    convex combination of the gaps between the primitives' corners at t0 and at t1 (6 vectors
///    for a vertex and a triangle, 8 for two edges; the bound of inclusion-based tests such as Wang
///    et al., ACM TOG 2021). The interval is apart if all of those are beyond `tolerance` along one
///    direction: a coordinate axis, or one taken from the closest points (primitive_distance.hpp)
///    at t0 or at the interval's middle;
///  - the same bound at t0 or at the middle, less the fastest relative motion of two corners times
///    the time to the interval's ends;
///  - the distance to the triangle's plane (between the edges' lines), |f| / |N| with f the
///    coplanarity cubic and N the normal, bounded over the interval by their Bernstein
///    coefficients: this drops a vertex closing in slowly on a fast-turning triangle.
/// Intervals are halved depth first, the earlier half first, so all time before the interval at
/// hand has been excluded when it is examined; its start is the answer if the pair is within
/// `tolerance` there, or if the interval cannot be excluded, is so short that the pair moves less
/// than the tolerance across it, and the pair is within 2 tolerance + 2 r at its start (this
/// check, on the closest points' distance, is what makes the answer never far).
///
/// Cost: a pair clearly apart takes one interval, a crossing a dozen to a few dozen (randomized
/// tests, which seek hard cases: 12 on average, 99.5% within 64). The search examines at most 2048;
/// if it runs out it returns the start of the interval at hand, which is never late but may be
/// early. That takes a tangential approach with a tolerance far below the motion (edges turning
/// parallel as they meet, the tolerance 1e-6 of the step's motion) or a tolerance near sqrt(eps)
/// max|coordinate|: 3 queries in 100000 of those tests. Non-finite input is reported as a contact
/// at t = 0.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

#include "drape/config.hpp"
#include "drape/core/types.hpp"
#include "drape/collision/primitive_distance.hpp"

namespace drape {

/// Points (p, a, b, c) at the start and end of the step: the earliest t in [0, 1] at which p is
/// within `tolerance` (>= 0) of the triangle abc, or nullopt if it never is.
template <class Scalar>
std::optional<Scalar> vertex_triangle_impact(const std::array<Vec3<Scalar>, 4>& start,
                                             const std::array<Vec3<Scalar>, 4>& end, Scalar tolerance);

/// Points (p0, p1, q0, q1) at the start and end of the step: the earliest t in [0, 1] at which the
/// segments p0 p1 and q0 q1 are within `tolerance` (>= 0) of each other, or nullopt if never.
template <class Scalar>
std::optional<Scalar> edge_edge_impact(const std::array<Vec3<Scalar>, 4>& start, const std::array<Vec3<Scalar>, 4>& end,
                                       Scalar tolerance);

// ---------------------------------------------------------------------------------------------

namespace detail {

enum class ImpactPair : std::uint8_t { VertexTriangle, EdgeEdge };

/// The intervals a search may examine before it gives its conservative answer.
inline constexpr int max_impact_intervals = 2048;

/// What an impact search found, and what it cost (the tests look at the cost).
template <class Real>
struct ImpactSearch {
  std::optional<Real> time;
  int intervals = 0;       ///< time intervals examined
  bool exhausted = false;  ///< ran out of intervals: time is the start of the one at hand, maybe early
};

/// The gaps between the pair's corners: p minus each corner of the triangle (and the first again,
/// to fill the array), or each end of p minus each end of q. Every gap between the two primitives
/// is a convex combination of these.
template <class Real>
std::array<Vec3<Real>, 4> corner_gaps(ImpactPair pair, const std::array<Vec3<Real>, 4>& x) {
  if (pair == ImpactPair::VertexTriangle) return {x[0] - x[1], x[0] - x[2], x[0] - x[3], x[0] - x[1]};
  return {x[0] - x[2], x[0] - x[3], x[1] - x[2], x[1] - x[3]};
}

/// The pair at one time: its distance (from the closest points, an upper bound up to rounding)
/// and unit directions along which to bound it from below (zero where undefined).
template <class Real>
struct Probe {
  Real distance;
  std::array<Vec3<Real>, 4> directions;
};

/// The directions: the gap between the closest points, and the gap made exactly perpendicular to
/// each edge (each of the triangle's; p's, q's, both). Closest points a distance d apart are known
/// to a few eps of the coordinates, so the gap's direction only to ~eps |x| / d, and along far
/// corners that error would spoil the bound; with the closest point inside an edge, the gap made
/// perpendicular to that edge is exact where it matters, and the bound is the distance up to
/// rounding. (Across a face or between the edges' lines the coplanarity test below is exact.)
template <class Real>
Probe<Real> probe(ImpactPair pair, const std::array<Vec3<Real>, 4>& x) {
  const auto unit = [](const Vec3<Real>& v) -> Vec3<Real> {
    const Real length = v.norm();
    return length > 0 ? Vec3<Real>(v / length) : Vec3<Real>::Zero();
  };
  const auto across = [&](const Vec3<Real>& v, const Vec3<Real>& edge) -> Vec3<Real> {
    const Vec3<Real> along = unit(edge);
    return v - v.dot(along) * along;
  };
  Probe<Real> result;
  Vec3<Real> gap;
  if (pair == ImpactPair::VertexTriangle) {
    const Vec3<Real> w = closest_point_on_triangle(x[0], x[1], x[2], x[3]).weights;
    gap = x[0] - (w[0] * x[1] + w[1] * x[2] + w[2] * x[3]);
    for (std::size_t e = 0; e < 3; ++e) result.directions[e + 1] = unit(across(gap, x[e + 1] - x[(e + 1) % 3 + 1]));
  } else {
    const SegmentClosest<Real> c = closest_points_on_segments(x[0], x[1], x[2], x[3]);
    gap = x[0] + c.s * (x[1] - x[0]) - x[2] - c.t * (x[3] - x[2]);
    result.directions[1] = unit(across(gap, x[1] - x[0]));
    result.directions[2] = unit(across(gap, x[3] - x[2]));
    result.directions[3] = unit(across(across(gap, x[1] - x[0]), x[3] - x[2]));
  }
  result.distance = gap.norm();
  result.directions[0] = unit(gap);
  return result;
}

/// The least of the corner gaps along the better of the probe's directions: a lower bound of the
/// pair's distance (every gap is a convex combination of the corner gaps), whatever the accuracy
/// of the directions.
template <class Real>
Real distance_below(const Probe<Real>& sample, const std::array<Vec3<Real>, 4>& gaps, std::size_t corners) {
  Real best = -std::numeric_limits<Real>::infinity();
  for (const Vec3<Real>& direction : sample.directions) {
    Real least = std::numeric_limits<Real>::infinity();
    for (std::size_t k = 0; k < corners; ++k) least = std::min(least, direction.dot(gaps[k]));
    best = std::max(best, least);
  }
  return best;
}

/// The signed volume f = A . (B x C) spanned by the pair (A = p - a, B = b - a, C = c - a; or
/// A = p0 - q0, B = p1 - p0, C = q1 - q0), the normal N = B x C and their rates: |f| / |N| is the
/// distance from the vertex to the triangle's plane, or between the edges' lines, and bounds the
/// pair's distance from below.
template <class Real>
struct Coplanarity {
  Real volume, volume_rate;
  Vec3<Real> normal, normal_rate;
  Real longest;  ///< max(|A|, |B|, |C|), for the rounding bound
};

template <class Real>
Coplanarity<Real> coplanarity(ImpactPair pair, const std::array<Vec3<Real>, 4>& x,
                              const std::array<Vec3<Real>, 4>& velocity) {
  const std::array<std::size_t, 6> ends = pair == ImpactPair::VertexTriangle
                                              ? std::array<std::size_t, 6>{0, 1, 2, 1, 3, 1}
                                              : std::array<std::size_t, 6>{0, 2, 1, 0, 3, 2};
  const auto difference = [&](const std::array<Vec3<Real>, 4>& y, std::size_t k) -> Vec3<Real> {
    return y[ends[2 * k]] - y[ends[2 * k + 1]];
  };
  const Vec3<Real> a = difference(x, 0), b = difference(x, 1), c = difference(x, 2);
  const Vec3<Real> da = difference(velocity, 0), db = difference(velocity, 1), dc = difference(velocity, 2);
  const Vec3<Real> normal = b.cross(c), normal_rate = db.cross(c) + b.cross(dc);
  return {a.dot(normal), da.dot(normal) + a.dot(normal_rate), normal, normal_rate,
          std::max({a.norm(), b.norm(), c.norm()})};
}

/// The earliest t in [0, 1] at which the pair is within `tolerance`; `rounding` (64 eps
/// max|coordinate|) bounds the error of a position, a distance, a corner gap and its product with
/// a unit vector.
template <class Real>
ImpactSearch<Real> first_impact(ImpactPair pair, const std::array<Vec3<Real>, 4>& start,
                                const std::array<Vec3<Real>, 4>& end, Real tolerance, Real rounding,
                                int max_intervals = max_impact_intervals) {
  std::array<Vec3<Real>, 4> velocity;
  for (std::size_t i = 0; i < 4; ++i) velocity[i] = end[i] - start[i];
  const auto at = [&](Real t) {
    std::array<Vec3<Real>, 4> x;
    for (std::size_t i = 0; i < 4; ++i) x[i] = start[i] + t * velocity[i];
    return x;
  };
  // The distance changes no faster than the fastest relative motion of two corners.
  const std::array<Vec3<Real>, 4> corner_velocity = corner_gaps(pair, velocity);
  Real speed = 0;
  for (const Vec3<Real>& v : corner_velocity) speed = std::max(speed, v.norm());
  // Across an interval this short the pair moves less than the tolerance.
  const Real shortest = speed > 0 ? std::max(tolerance, rounding) / speed : Real(1);
  const Real reach = tolerance + rounding;
  const Real eps = std::numeric_limits<Real>::epsilon();
  const std::size_t corners = pair == ImpactPair::VertexTriangle ? 3 : 4;

  // Depth first, each interval split in two: the stack holds one interval per level, and intervals
  // stop shrinking at `shortest` (at least ~10 eps), at the mantissa or at the stack's capacity.
  constexpr int capacity = 128;
  std::array<std::array<Real, 2>, capacity> stack;
  int size = 0;
  stack[size++] = {Real(0), Real(1)};
  ImpactSearch<Real> search;
  while (size > 0) {
    const auto [t0, t1] = stack[--size];
    if (search.intervals == max_intervals) {
      search.exhausted = true;
      search.time = t0;
      return search;
    }
    ++search.intervals;
    const Real width = t1 - t0;
    const std::array<Vec3<Real>, 4> x0 = at(t0), x1 = at(t1);
    const Probe<Real> first = probe(pair, x0);
    if (first.distance <= tolerance) {  // all time before t0 is excluded
      search.time = t0;
      return search;
    }
    // Every exclusion below rests on lower bounds of the distance, never on the closest points'
    // distance, which near-parallel edges or a sliver may overestimate.
    const std::array<Vec3<Real>, 4> from = corner_gaps(pair, x0), to = corner_gaps(pair, x1);
    if (distance_below(first, from, corners) - width * speed > reach) continue;  // cannot close in time

    // Every gap in the interval lies in the convex hull of the corner gaps at its two ends: apart
    // if all of those are beyond the reach along some direction (a coordinate axis, a probe's).
    const auto apart_along = [&](const std::array<Vec3<Real>, 4>& directions) {
      for (const Vec3<Real>& direction : directions) {
        bool apart = true;
        for (std::size_t k = 0; k < corners && apart; ++k)
          apart = direction.dot(from[k]) > reach && direction.dot(to[k]) > reach;
        if (apart) return true;
      }
      return false;
    };
    Vec3<Real> low = from[0], high = from[0];
    for (std::size_t k = 0; k < corners; ++k) {
      low = low.cwiseMin(from[k]).cwiseMin(to[k]);
      high = high.cwiseMax(from[k]).cwiseMax(to[k]);
    }
    if ((low.array() > reach).any() || (high.array() < -reach).any() || apart_along(first.directions)) continue;

    // Apart from the triangle's plane (the edges' lines) all along: the signed volume, a cubic in
    // t, keeps its sign with margin between its Bernstein coefficients on the interval. This is
    // what excludes a vertex closing in slowly on a fast-turning triangle.
    const Coplanarity<Real> v0 = coplanarity(pair, x0, velocity), v1 = coplanarity(pair, x1, velocity);
    const std::array<Real, 4> volume = {v0.volume, v0.volume + width * v0.volume_rate / 3,
                                        v1.volume - width * v1.volume_rate / 3, v1.volume};
    // |N| on the interval is at most its largest Bernstein control point (N is quadratic in t).
    const Real normal_bound = std::max(
        {v0.normal.norm(), Vec3<Real>(v0.normal + Real(0.5) * width * v0.normal_rate).norm(), v1.normal.norm()});
    const Real longest = std::max(v0.longest, v1.longest);
    const Real margin = tolerance * (normal_bound + 8 * eps * longest * longest) +
                        (8 * rounding + 128 * eps * longest) * longest * longest;
    if (*std::min_element(volume.begin(), volume.end()) > margin ||
        *std::max_element(volume.begin(), volume.end()) < -margin)
      continue;

    // Not excluded, and so short that the pair moves less than the tolerance across it: t0 is the
    // answer if the pair is close there (within 2 tolerance + 2 rounding). If it is not, the lower
    // bounds were loose (their directions are uncertain when the closest points are this close),
    // and halving goes on: the bounds soon exclude the rest. An interval that cannot be halved is
    // taken as it is, which is never late.
    const Real middle = Real(0.5) * (t0 + t1);
    if ((width <= shortest && first.distance <= reach + width * speed) || !(middle > t0 && middle < t1) ||
        size + 2 > capacity) {
      search.time = t0;
      return search;
    }
    const std::array<Vec3<Real>, 4> x_middle = at(middle);
    const Probe<Real> halfway = probe(pair, x_middle);
    if (distance_below(halfway, corner_gaps(pair, x_middle), corners) - Real(0.5) * width * speed > reach ||
        apart_along(halfway.directions))
      continue;
    stack[size++] = {middle, t1};  // popped last
    stack[size++] = {t0, middle};
  }
  return search;
}

/// The search on input of any scalar type: in the precise type, with the rounding bound for that
/// input.
template <class Scalar>
ImpactSearch<PreciseScalar<Scalar>> impact_search(ImpactPair pair, const std::array<Vec3<Scalar>, 4>& start,
                                                  const std::array<Vec3<Scalar>, 4>& end, Scalar tolerance,
                                                  int max_intervals = max_impact_intervals) {
  using Real = PreciseScalar<Scalar>;
  DRAPE_ASSERT(tolerance >= 0, "impact test: tolerance must be >= 0");
  std::array<Vec3<Real>, 4> from, to;
  bool finite = std::isfinite(tolerance);
  Real largest = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    from[i] = start[i].template cast<Real>();
    to[i] = end[i].template cast<Real>();
    finite = finite && from[i].allFinite() && to[i].allFinite();
    if (finite) largest = std::max({largest, from[i].cwiseAbs().maxCoeff(), to[i].cwiseAbs().maxCoeff()});
  }
  if (!finite) {
    ImpactSearch<Real> contact;
    contact.time = Real(0);
    return contact;
  }
  // A position at time t rounds by about 3 eps max|coordinate|, a corner gap by 8, its product
  // with a unit vector by about 25; the unit vector's own length error scales the tolerance.
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real rounding = 64 * eps * largest;
  const Real tolerance_rounded_up = std::max(Real(tolerance), Real(0)) * (1 + 16 * eps);
  return first_impact(pair, from, to, tolerance_rounded_up, rounding, max_intervals);
}

/// The largest Scalar not above t (t >= 0): a time is never rounded to later.
template <class Scalar, class Real>
Scalar round_down(Real t) {
  Scalar down = Scalar(t);
  if (Real(down) > t) down = std::nextafter(down, Scalar(0));
  return down;
}

template <class Scalar>
std::optional<Scalar> first_impact_time(ImpactPair pair, const std::array<Vec3<Scalar>, 4>& start,
                                        const std::array<Vec3<Scalar>, 4>& end, Scalar tolerance) {
  const auto search = impact_search(pair, start, end, tolerance);
  if (!search.time) return std::nullopt;
  return round_down<Scalar>(*search.time);
}

}  // namespace detail

template <class Scalar>
std::optional<Scalar> vertex_triangle_impact(const std::array<Vec3<Scalar>, 4>& start,
                                             const std::array<Vec3<Scalar>, 4>& end, Scalar tolerance) {
  return detail::first_impact_time(detail::ImpactPair::VertexTriangle, start, end, tolerance);
}

template <class Scalar>
std::optional<Scalar> edge_edge_impact(const std::array<Vec3<Scalar>, 4>& start, const std::array<Vec3<Scalar>, 4>& end,
                                       Scalar tolerance) {
  return detail::first_impact_time(detail::ImpactPair::EdgeEdge, start, end, tolerance);
}

}  // namespace drape
