#pragma once
/// \file pattern_curves.hpp
/// The curves of a sewing pattern's edges (drape's garments.md, "Sewing patterns"): a straight
/// segment, a quadratic or cubic Bezier curve and a circular arc, in the flat plane of a panel,
/// each from its start point (u = 0) to its end point (u = 1).
///
/// - Bezier control points are absolute points of the panel plane. A GarmentCode pattern gives them
///   relative to the edge (relative_to_absolute()).
/// - A circle arc is GarmentCode's (and SVG's) `[radius, large_arc, right]`: of the two circles of
///   that radius through both ends, and the two arcs of each, the one that turns counter-clockwise
///   (seen from +z of the panel plane, x right, y up) from start to end when `right` is set,
///   clockwise otherwise, and sweeps more than half a turn when `large_arc` is set. Small arcs
///   therefore bulge to the right of the direction start -> end when `right` is set, to the left
///   otherwise. A radius below half the chord is taken as half the chord (a half circle), as SVG
///   does. u is proportional to the angle (and to arc length).
/// - Lengths are integrated to a relative accuracy of 1e-12 (exact for straight segments and arcs);
///   points at equal arc length are found to 1e-12 of the curve's length.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace drape {

enum class CurveType { Straight, Quadratic, Cubic, Circle };

/// The shape of an edge between its two end points.
struct CurveShape {
  CurveType type = CurveType::Straight;
  /// Bezier control points, absolute in the panel plane (m): control[0] for a quadratic curve,
  /// control[0] then control[1] for a cubic one.
  std::array<Eigen::Vector2d, 2> control{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  /// Circle: radius (m), > 0.
  double radius = 0;
  /// Circle: the arc sweeps more than half a turn.
  bool large_arc = false;
  /// Circle: the arc turns counter-clockwise from start to end (a small arc bulges to the right).
  bool right = false;
};

/// GarmentCode's relative point (pygarment/pattern/utils.py, rel_to_abs_2d): `t` along the edge
/// from start (0) to end (1), `s` across it towards the left of the direction start -> end (the
/// edge vector turned a quarter counter-clockwise), both in edge lengths:
/// `start + t (end - start) + s perp(end - start)` with `perp(x, y) = (-y, x)`.
inline Eigen::Vector2d relative_to_absolute(const Eigen::Vector2d& start, const Eigen::Vector2d& end, double t,
                                            double s) {
  const Eigen::Vector2d edge = end - start;
  return start + t * edge + s * Eigen::Vector2d(-edge.y(), edge.x());
}

/// A circle arc in centre form: the point at u is centre + radius (cos a, sin a), a = start_angle + u sweep.
struct CircleArc {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0;
  double start_angle = 0;  ///< radians
  double sweep = 0;        ///< radians, > 0 counter-clockwise; |sweep| in (0, 2 pi)
};

/// The centre form of the arc `[radius, large_arc, right]` from `start` to `end` (which differ).
inline CircleArc circle_arc(const Eigen::Vector2d& start, const Eigen::Vector2d& end, double radius, bool large_arc,
                     bool right);

/// The point at parameter u in [0, 1]: exactly `start` at 0 and `end` at 1.
inline Eigen::Vector2d curve_point(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                            double u);

/// d/du of curve_point().
inline Eigen::Vector2d curve_derivative(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                                 double u);

/// The arc length between parameters u0 <= u1 (m).
inline double curve_length(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                    double u0 = 0, double u1 = 1);

/// The parameters of `segments` + 1 points at equal arc length along the curve: 0, ..., 1.
inline std::vector<double> equal_length_parameters(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                            const CurveShape& shape, int segments);

// ---------------------------------------------------------------------------------------------------

namespace detail {

constexpr double pattern_pi = 3.14159265358979323846;

/// 10-point Gauss-Legendre rule on [a, b].
template <class F>
double gauss_legendre_10(const F& f, double a, double b) {
  static constexpr std::array<double, 5> node = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                                 0.8650633666889845, 0.9739065285171717};
  static constexpr std::array<double, 5> weight = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                                   0.1494513491505806, 0.0666713443086881};
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0;
  for (std::size_t k = 0; k < node.size(); ++k) sum += weight[k] * (f(mid - half * node[k]) + f(mid + half * node[k]));
  return sum * half;
}

/// Adaptive Gauss-Legendre: halves an interval until the rule on it agrees with the rule on its
/// halves to `tolerance` (shared out between the halves). `budget` bounds the number of intervals.
template <class F>
double adaptive_integral(const F& f, double a, double b, double whole, double tolerance, int depth, int& budget) {
  const double mid = 0.5 * (a + b);
  const double left = gauss_legendre_10(f, a, mid), right = gauss_legendre_10(f, mid, b);
  const double halves = left + right;
  // Not finite, resolved, too deep or out of budget: take the finer value.
  if (!std::isfinite(halves) || std::abs(halves - whole) <= tolerance || depth >= 40 || --budget <= 0) return halves;
  return adaptive_integral(f, a, mid, left, 0.5 * tolerance, depth + 1, budget) +
         adaptive_integral(f, mid, b, right, 0.5 * tolerance, depth + 1, budget);
}

/// The length of the control polygon: an upper bound of a Bezier curve's length (its scale).
inline double control_polygon_length(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                     const CurveShape& shape) {
  if (shape.type == CurveType::Quadratic) return (shape.control[0] - start).norm() + (end - shape.control[0]).norm();
  if (shape.type == CurveType::Cubic)
    return (shape.control[0] - start).norm() + (shape.control[1] - shape.control[0]).norm() +
           (end - shape.control[1]).norm();
  return (end - start).norm();
}

inline double bezier_length(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                            double u0, double u1) {
  if (!(u1 > u0)) return 0;
  const auto speed = [&](double u) { return curve_derivative(start, end, shape, u).norm(); };
  const double tolerance = 1e-13 * control_polygon_length(start, end, shape) * (u1 - u0);
  int budget = 4096;
  return adaptive_integral(speed, u0, u1, gauss_legendre_10(speed, u0, u1), tolerance, 0, budget);
}

}  // namespace detail

inline CircleArc circle_arc(const Eigen::Vector2d& start, const Eigen::Vector2d& end, double radius, bool large_arc,
                            bool right) {
  const Eigen::Vector2d chord = end - start;
  const double half = 0.5 * chord.norm();
  const double r = std::max(radius, half);
  // The centre lies off the chord's middle by d, to the left of start -> end when the arc turns
  // counter-clockwise (`right`) and is small, or turns clockwise and is large (SVG's rule: the
  // centre's sign is + when large_arc != sweep, with sweep = right: GarmentCode's boxmeshgen.py).
  const double d = std::sqrt(std::max(0.0, r * r - half * half));
  Eigen::Vector2d left = Eigen::Vector2d::Zero();
  if (half > 0) left = Eigen::Vector2d(-chord.y(), chord.x()) / (2 * half);
  CircleArc arc;
  arc.radius = r;
  arc.centre = 0.5 * (start + end) + ((right != large_arc) ? d : -d) * left;
  arc.start_angle = std::atan2(start.y() - arc.centre.y(), start.x() - arc.centre.x());
  const double small = 2 * std::asin(std::min(1.0, half / r));
  const double angle = large_arc ? 2 * detail::pattern_pi - small : small;
  arc.sweep = right ? angle : -angle;
  return arc;
}

inline Eigen::Vector2d curve_point(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                                   double u) {
  if (u <= 0) return start;
  if (u >= 1) return end;
  const double v = 1 - u;
  switch (shape.type) {
    case CurveType::Straight:
      return v * start + u * end;
    case CurveType::Quadratic:
      return v * v * start + 2 * u * v * shape.control[0] + u * u * end;
    case CurveType::Cubic:
      return v * v * v * start + 3 * u * v * v * shape.control[0] + 3 * u * u * v * shape.control[1] + u * u * u * end;
    case CurveType::Circle: {
      const CircleArc arc = circle_arc(start, end, shape.radius, shape.large_arc, shape.right);
      const double a = arc.start_angle + u * arc.sweep;
      return arc.centre + arc.radius * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
  }
  return start;
}

inline Eigen::Vector2d curve_derivative(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                        const CurveShape& shape, double u) {
  const double v = 1 - u;
  switch (shape.type) {
    case CurveType::Straight:
      return end - start;
    case CurveType::Quadratic:
      return 2 * v * (shape.control[0] - start) + 2 * u * (end - shape.control[0]);
    case CurveType::Cubic:
      return 3 * v * v * (shape.control[0] - start) + 6 * u * v * (shape.control[1] - shape.control[0]) +
             3 * u * u * (end - shape.control[1]);
    case CurveType::Circle: {
      const CircleArc arc = circle_arc(start, end, shape.radius, shape.large_arc, shape.right);
      const double a = arc.start_angle + u * arc.sweep;
      return arc.radius * arc.sweep * Eigen::Vector2d(-std::sin(a), std::cos(a));
    }
  }
  return end - start;
}

inline double curve_length(const Eigen::Vector2d& start, const Eigen::Vector2d& end, const CurveShape& shape,
                           double u0, double u1) {
  u0 = std::clamp(u0, 0.0, 1.0);
  u1 = std::clamp(u1, 0.0, 1.0);
  if (!(u1 > u0)) return 0;
  switch (shape.type) {
    case CurveType::Straight:
      return (u1 - u0) * (end - start).norm();
    case CurveType::Circle: {
      const CircleArc arc = circle_arc(start, end, shape.radius, shape.large_arc, shape.right);
      return (u1 - u0) * arc.radius * std::abs(arc.sweep);
    }
    case CurveType::Quadratic:
    case CurveType::Cubic:
      return detail::bezier_length(start, end, shape, u0, u1);
  }
  return 0;
}

inline std::vector<double> equal_length_parameters(const Eigen::Vector2d& start, const Eigen::Vector2d& end,
                                                   const CurveShape& shape, int segments) {
  segments = std::max(segments, 1);
  std::vector<double> u(static_cast<std::size_t>(segments) + 1);
  for (int k = 0; k <= segments; ++k) u[std::size_t(k)] = double(k) / segments;
  if (shape.type == CurveType::Straight || shape.type == CurveType::Circle || segments == 1) return u;

  // Bezier: cumulative lengths at 64 equal steps of u, then each target length solved for inside
  // its step by Newton's method on the length, kept inside the step by bisection.
  constexpr int steps = 64;
  std::array<double, steps + 1> cumulative{};
  for (int j = 0; j < steps; ++j)
    cumulative[std::size_t(j) + 1] =
        cumulative[std::size_t(j)] + detail::bezier_length(start, end, shape, double(j) / steps, double(j + 1) / steps);
  const double total = cumulative[steps];
  if (!(total > 0) || !std::isfinite(total)) return u;
  const double tolerance = 1e-12 * total;
  int step = 0;
  for (int k = 1; k < segments; ++k) {
    const double target = total * k / segments;
    while (step < steps - 1 && cumulative[std::size_t(step) + 1] < target) ++step;
    double lo = double(step) / steps, hi = double(step + 1) / steps;
    const double base = cumulative[std::size_t(step)];
    double x = lo + (hi - lo) * std::clamp((target - base) / (cumulative[std::size_t(step) + 1] - base), 0.0, 1.0);
    if (!std::isfinite(x)) x = 0.5 * (lo + hi);
    for (int iteration = 0; iteration < 60; ++iteration) {
      const double f = base + detail::bezier_length(start, end, shape, double(step) / steps, x) - target;
      if (std::abs(f) <= tolerance) break;
      if (f > 0)
        hi = x;
      else
        lo = x;
      const double speed = curve_derivative(start, end, shape, x).norm();
      double next = speed > 0 ? x - f / speed : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      x = next;
    }
    u[std::size_t(k)] = x;
  }
  return u;
}

}  // namespace drape
