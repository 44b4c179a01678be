#pragma once
// Test panels for the panel mesher (garment/panel_mesher.hpp), shared by its test
// (test_panel_mesher.cpp) and the tool that measures it (bench/panel_meshing.cpp): outlines of
// lines and elliptic arcs sampled at about an edge length, the named panels, and what a panel mesh
// measures (angles, edge lengths, vertex count, how near the outline its interior vertices come).

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drape/garment/panel_mesher.hpp"

namespace panel_outlines {

constexpr double pi = 3.14159265358979323846;
using Point = Eigen::Vector2d;

/// A piece of outline: a curve c(t), t in [0, 1], and its length.
struct Piece {
  std::function<Point(double)> at;
  double length;
};

inline Piece line(const Point& a, const Point& b) { return {[=](double t) { return Point(a + t * (b - a)); }, (b - a).norm()}; }

/// The elliptic arc (centre, radii rx and ry) from one angle to another (degrees), sampled evenly in
/// the angle: its segments vary in length along an ellipse, as a sampled curve's may.
inline Piece arc(const Point& centre, double rx, double ry, double from_degrees, double to_degrees) {
  const double a0 = from_degrees * pi / 180, a1 = to_degrees * pi / 180;
  const auto at = [=](double t) {
    const double a = a0 + t * (a1 - a0);
    return Point(centre.x() + rx * std::cos(a), centre.y() + ry * std::sin(a));
  };
  double length = 0;
  for (int i = 0; i < 1000; ++i) length += (at((i + 1) / 1000.0) - at(i / 1000.0)).norm();
  return {at, length};
}

/// The closed outline of `pieces` (each starting where the one before ends), each cut into
/// round(length / h) segments (one at least).
inline Eigen::Matrix2Xd sample(const std::vector<Piece>& pieces, double h) {
  std::vector<Point> points;
  for (const Piece& piece : pieces) {
    const int n = std::max(1, static_cast<int>(std::lround(piece.length / h)));
    for (int i = 0; i < n; ++i) points.push_back(piece.at(double(i) / n));
  }
  Eigen::Matrix2Xd out(2, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = points[i];
  return out;
}

inline Eigen::Matrix2Xd reversed(const Eigen::Matrix2Xd& outline) { return outline.rowwise().reverse(); }

inline std::vector<Piece> polygon(const std::vector<Point>& corners) {
  std::vector<Piece> out;
  for (std::size_t i = 0; i < corners.size(); ++i) out.push_back(line(corners[i], corners[(i + 1) % corners.size()]));
  return out;
}

inline std::vector<Piece> square(double side) { return polygon({{0, 0}, {side, 0}, {side, side}, {0, side}}); }
inline std::vector<Piece> l_shape(double side) {
  return polygon({{0, 0}, {side, 0}, {side, side / 2}, {side / 2, side / 2}, {side / 2, side}, {0, side}});
}
inline std::vector<Piece> disk(double radius) { return {arc({0, 0}, radius, radius, 0, 360)}; }
/// A star of `tips` tips: outer radius 0.3 m, inner 0.1 m, so each tip is 30 degrees and each
/// notch between two tips a reflex corner of 258 degrees.
inline std::vector<Piece> star(int tips, double outer, double inner) {
  std::vector<Point> corners;
  for (int k = 0; k < 2 * tips; ++k) {
    const double a = pi * k / tips, r = k % 2 == 0 ? outer : inner;
    corners.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return polygon(corners);
}
/// A T-shirt front, 50 cm wide and 68 cm tall: hem, sides, armholes (quarter ellipses bulging
/// in), shoulders, a scooped neckline (half an ellipse down to 10 cm below the shoulders).
inline std::vector<Piece> tshirt_front() {
  return {line({-0.25, 0}, {0.25, 0}),          line({0.25, 0}, {0.25, 0.45}),
          arc({0.25, 0.65}, 0.06, 0.20, -90, -180), line({0.19, 0.65}, {0.08, 0.68}),
          arc({0, 0.68}, 0.08, 0.10, 0, -180),      line({-0.08, 0.68}, {-0.19, 0.65}),
          arc({-0.25, 0.65}, 0.06, 0.20, 0, -90),   line({-0.25, 0.45}, {-0.25, 0})};
}
inline std::vector<Piece> rectangle(double width, double height) { return polygon({{0, 0}, {width, 0}, {width, height}, {0, height}}); }

inline double shoelace_area(const Eigen::Matrix2Xd& outline) {
  double twice = 0;
  for (Eigen::Index k = 0; k < outline.cols(); ++k) {
    const Eigen::Index next = (k + 1) % outline.cols();
    twice += outline(0, k) * outline(1, next) - outline(0, next) * outline(1, k);
  }
  return 0.5 * twice;
}

/// The interior angle at each outline point (degrees), whichever way the outline runs.
inline std::vector<double> corner_angles(const Eigen::Matrix2Xd& outline) {
  const Eigen::Index m = outline.cols();
  const double turn = shoelace_area(outline) > 0 ? 1 : -1;
  std::vector<double> out;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Point ahead = outline.col((k + 1) % m) - outline.col(k), back = outline.col((k + m - 1) % m) - outline.col(k);
    const double a = std::atan2(turn * (ahead.x() * back.y() - ahead.y() * back.x()), ahead.dot(back)) * 180 / pi;
    out.push_back(a < 0 ? a + 360 : a);
  }
  return out;
}

inline double point_segment_distance(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

/// Corners sharper than this (degrees) bound the angles of the triangles at them.
constexpr double sharp_corner = 60;

/// What a panel mesh measures; lengths in edge lengths h.
struct Measures {
  double min_angle = 180;                    // degrees, over all triangles
  double min_angle_off_sharp_corners = 180;  // over the triangles with no corner sharper than sharp_corner
  double sharpest_corner = 360;              // the outline's smallest interior angle
  double shortest_edge = 0, edge_5 = 0, median_edge = 0, edge_95 = 0, longest_edge = 0;  // percentiles 0, 5, 50, 95, 100
  double nearest_interior_vertex = 1;       // to the outline, up to h
  double triangles_per_ideal = 0;            // triangles / (area / (sqrt(3)/4 h^2))
};

/// The measures of a valid panel mesh of `outline` at edge length h.
inline Measures measure(const Eigen::Matrix2Xd& outline, const drape::PanelMesh& panel, double h) {
  const Eigen::Index m = outline.cols(), n = panel.rest.cols(), t_count = panel.triangles.cols();
  const std::vector<double> corner = corner_angles(outline);
  Measures out;
  out.sharpest_corner = *std::min_element(corner.begin(), corner.end());
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index t = 0; t < t_count; ++t) {
    bool at_sharp_corner = false;
    double smallest = 180;
    for (int k = 0; k < 3; ++k) {
      const int a = panel.triangles(k, t), b = panel.triangles((k + 1) % 3, t), c = panel.triangles((k + 2) % 3, t);
      if (a < m && corner[static_cast<std::size_t>(a)] < sharp_corner) at_sharp_corner = true;
      const Point u = panel.rest.col(b) - panel.rest.col(a), w = panel.rest.col(c) - panel.rest.col(a);
      smallest = std::min(smallest, std::atan2(std::abs(u.x() * w.y() - u.y() * w.x()), u.dot(w)) * 180 / pi);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
    out.min_angle = std::min(out.min_angle, smallest);
    if (!at_sharp_corner) out.min_angle_off_sharp_corners = std::min(out.min_angle_off_sharp_corners, smallest);
  }
  std::vector<double> lengths;
  for (const auto& e : edges) lengths.push_back((panel.rest.col(e.first.first) - panel.rest.col(e.first.second)).norm() / h);
  std::sort(lengths.begin(), lengths.end());
  const auto percentile = [&](std::size_t p) { return lengths[(lengths.size() - 1) * p / 100]; };
  out.shortest_edge = lengths.front();
  out.edge_5 = percentile(5);
  out.median_edge = percentile(50);
  out.edge_95 = percentile(95);
  out.longest_edge = lengths.back();
  // The nearest interior vertex to the outline, up to h: segments bucketed in cells of h, each in
  // the cells within h of its bounding box.
  const Point lo = outline.rowwise().minCoeff(), hi = outline.rowwise().maxCoeff();
  const Eigen::Index columns = static_cast<Eigen::Index>((hi.x() - lo.x()) / h) + 1,
                     rows = static_cast<Eigen::Index>((hi.y() - lo.y()) / h) + 1;
  const auto cell = [&](const Point& p, Eigen::Index grow) {
    const auto clamp = [](double v, Eigen::Index count) {
      return std::min(count - 1, std::max(Eigen::Index(0), static_cast<Eigen::Index>(std::floor(v))));
    };
    return std::pair<Eigen::Index, Eigen::Index>(clamp((p.x() - lo.x()) / h + double(grow), columns),
                                                 clamp((p.y() - lo.y()) / h + double(grow), rows));
  };
  std::vector<std::vector<Eigen::Index>> near(static_cast<std::size_t>(columns * rows));
  for (Eigen::Index k = 0; k < m; ++k) {
    const Point a = outline.col(k), b = outline.col((k + 1) % m);
    const auto first = cell(a.cwiseMin(b), -1), last = cell(a.cwiseMax(b), 1);
    for (Eigen::Index y = first.second; y <= last.second; ++y)
      for (Eigen::Index x = first.first; x <= last.first; ++x) near[static_cast<std::size_t>(y * columns + x)].push_back(k);
  }
  out.nearest_interior_vertex = 1;
  for (Eigen::Index v = m; v < n; ++v) {
    const auto c = cell(panel.rest.col(v), 0);
    for (Eigen::Index k : near[static_cast<std::size_t>(c.second * columns + c.first)])
      out.nearest_interior_vertex =
          std::min(out.nearest_interior_vertex,
                   point_segment_distance(panel.rest.col(v), outline.col(k), outline.col((k + 1) % m)) / h);
  }
  out.triangles_per_ideal = double(t_count) / (std::abs(shoelace_area(outline)) / (std::sqrt(3.0) / 4 * h * h));
  return out;
}

}  // namespace panel_outlines
