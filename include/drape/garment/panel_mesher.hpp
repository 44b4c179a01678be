#pragma once
/// \file panel_mesher.hpp
/// A garment panel meshed: a flat sewing-pattern piece, a simple polygon in the plane (metres,
/// convex or not, no holes) given by its outline already sampled at about the target edge length
/// h, filled with near-equilateral triangles of edge about h. The outline is kept exactly: its
/// points are the mesh's first vertices, in the given order and bit for bit, and the mesh's
/// boundary edges are exactly its consecutive segments, so two panels whose seam edges were
/// sampled with the same vertex count meet vertex to vertex. drape's panel_meshing.md has the
/// method, its guarantees and the measured angles and times.
///
/// The method (core/detail/planar_triangulation.hpp does the triangulating, all in double):
/// 1. Interior vertices on the equilateral triangular lattice of spacing h (rows along x), kept
///    when inside the polygon and at least panel_clearance = 0.6 h from every outline segment (and
///    0.45 of the segment's length from one longer than 4/3 h); of four placements of the lattice
///    (shifted by quarters of a row height) the one that keeps the most vertices.
/// 2. The Delaunay triangulation of the outline and the lattice points; each outline segment that
///    is not an edge of it is recovered by flipping the edges that cross it; the segments are
///    constrained, the mesh is flipped to the constrained Delaunay triangulation, and the triangles
///    outside the polygon are removed.
/// 3. Refinement (after Ruppert; Shewchuk 2002), no outline segment split: the circumcentre of a
///    triangle whose smallest angle is below 30 degrees is inserted, unless it is not reached from
///    the triangle without crossing the outline or lies within 0.4 of the circle's radius (and
///    within 0.6 h) of the outline.
/// 4. Smoothing (6 passes): each interior vertex moves only where the smallest angle of its
///    triangles grows, the mesh flipped to Delaunay after each pass; outline points never move and
///    outline segments are never flipped (they bound the mesh). Then refinement once more.
///
/// Vertices: the outline's, the lattice's along a Hilbert curve (near in memory when near in the
/// plane), then those refinement inserted. The outline may run counter-clockwise or clockwise:
/// nothing depends on its direction, the mesh is the same either way (to round-off), and the
/// triangles always run counter-clockwise in the plane (x right, y up).
///
/// Guarantees: the outline exactly as given (above); a disk (manifold, Euler characteristic 1,
/// consistently oriented) whose area is the polygon's to round-off; every triangle with an angle
/// below 30 degrees is one that refinement must leave, its circumcentre beyond the outline or
/// within 0.4 of its radius of it: away from the outline every angle is 30 degrees or more. At the
/// outline the angles depend on its corners (a corner's angle bounds its triangles') and on its
/// sampling; drape's panel_meshing.md has the figures measured (32 degrees at worst off corners
/// sharper than 60 on its test panels, outlines sampled 0.3 h to 1.9 h apart).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drape/core/cloth_mesh.hpp"
// The mesh generators: their planar triangulation (core/detail/planar_triangulation.hpp, a part of
// them), smoothing passes and vertex cap.
#include "drape/core/mesh_generators.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// A meshed panel in its own plane.
struct PanelMesh {
  /// m, 2 x n: every vertex; the first outline_count are the outline's points in its order.
  Eigen::Matrix2Xd rest;
  /// 3 x t vertex ids, counter-clockwise in the plane.
  Eigen::Matrix3Xi triangles;
  /// How many of the first vertices are the outline's.
  int outline_count = 0;
};

/// The panel whose outline is `outline` (2 x m, metres, a closed loop: the last point joins the
/// first), meshed at `edge_length` (see the file comment).
///
/// \throws InvalidParameter naming the problem and the element: edge_length not finite and > 0;
/// fewer than 3 points; a non-finite point (`outline[k]`); a point equal to the one before it; a
/// segment longer than panel_longest_segment = 2 edge lengths or shorter than
/// panel_shortest_segment = 1/20 of one (`outline segment k`); more than max_generated_vertices
/// vertices (the outline's points and area / (sqrt(3)/2 edge_length^2) interior ones); two segments
/// that meet other than neighbours at their shared point (a self-intersecting or self-touching
/// outline: both segments named).
inline PanelMesh mesh_panel(const Eigen::Matrix2Xd& outline, double edge_length);

/// The panel as a cloth mesh: rest shape its 2D pattern coordinates (`rest_uv`), positions (x, y, 0)
/// until placed, the triangles as they are (counter-clockwise seen from +z, the front), and the
/// group "outline" (vertices 0 .. outline_count - 1, in order).
template <class Scalar = double>
ClothMesh<Scalar> panel_cloth_mesh(const PanelMesh& panel);

// ---------------------------------------------------------------------------------------------

namespace detail {

/// Lattice vertices stay at least this many edge lengths from every outline segment.
constexpr double panel_clearance = 0.6;
/// ... and at least this fraction of the segment's length (more than panel_clearance h from a
/// segment longer than 4/3 h), so that the triangle on a long segment is not flat.
constexpr double panel_long_segment_clearance = 0.45;
/// How many placements of the lattice are tried (shifted by a fraction of a row height).
constexpr int panel_lattice_placements = 4;
/// Refinement inserts the circumcentre of a triangle whose smallest angle is below this (degrees)
/// ...
constexpr double panel_refinement_angle = 30.0;
/// ... unless it lies nearer an outline segment than this fraction of the circle's radius (or
/// than panel_clearance edge lengths).
constexpr double panel_refinement_clearance = 0.4;
/// The outline's segments, in edge lengths: at most this long ...
constexpr double panel_longest_segment = 2.0;
/// ... and at least this long.
constexpr double panel_shortest_segment = 1.0 / 20;

/// `outline segment k (outline[k] to outline[k + 1])`, the last one ending at outline[0].
inline std::string panel_segment_name(Index k, Index m) {
  return "outline segment " + to_text(k) + " (outline[" + to_text(k) + "] to outline[" + to_text((k + 1) % m) + "])";
}

/// The outline's segments bucketed on a uniform grid, each with its clearance: segment k in every
/// cell that its bounding box, grown by clearance[k], overlaps.
class SegmentGrid {
 public:
  SegmentGrid(const std::vector<Point2>& loop, std::vector<double> clearance, double cell_size)
      : m_loop(loop), m_clearance(std::move(clearance)) {
    Point2 lo = loop[0], hi = loop[0];
    for (const Point2& p : loop) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double reach = *std::max_element(m_clearance.begin(), m_clearance.end());
    m_origin = lo - Point2::Constant(reach);
    const Point2 extent = hi - lo + Point2::Constant(2 * reach);
    m_cell = std::max(cell_size, extent.maxCoeff() / 1024);
    m_columns = 1 + static_cast<int>(extent.x() / m_cell);
    m_rows = 1 + static_cast<int>(extent.y() / m_cell);
    std::vector<std::array<int, 4>> boxes(loop.size());
    std::vector<int> count(static_cast<std::size_t>(m_columns) * static_cast<std::size_t>(m_rows) + 1, 0);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Point2 &p = loop[k], &q = loop[(k + 1) % loop.size()];
      const std::array<int, 2> a = cell_of(p.cwiseMin(q) - Point2::Constant(m_clearance[k])),
                               b = cell_of(p.cwiseMax(q) + Point2::Constant(m_clearance[k]));
      boxes[k] = {a[0], a[1], b[0], b[1]};
      for (int y = a[1]; y <= b[1]; ++y)
        for (int x = a[0]; x <= b[0]; ++x) ++count[cell_id(x, y) + 1];
    }
    std::partial_sum(count.begin(), count.end(), count.begin());
    m_start = count;
    m_items.resize(static_cast<std::size_t>(count.back()));
    for (std::size_t k = 0; k < loop.size(); ++k)
      for (int y = boxes[k][1]; y <= boxes[k][3]; ++y)
        for (int x = boxes[k][0]; x <= boxes[k][2]; ++x) m_items[static_cast<std::size_t>(count[cell_id(x, y)]++)] = int(k);
  }

  /// The cell holding p, clamped to the grid.
  std::array<int, 2> cell_of(const Point2& p) const {
    const auto clamp = [](double v, int n) { return std::min(n - 1, std::max(0, static_cast<int>(std::floor(v)))); };
    return {clamp((p.x() - m_origin.x()) / m_cell, m_columns), clamp((p.y() - m_origin.y()) / m_cell, m_rows)};
  }
  /// The segments bucketed in cell (x, y).
  template <class Visit>
  void for_each_in(int x, int y, Visit&& visit) const {
    const std::size_t c = cell_id(x, y);
    for (int s = m_start[c]; s < m_start[c + 1]; ++s) visit(m_items[static_cast<std::size_t>(s)]);
  }
  /// Whether p is at least its clearance from every segment.
  bool clear(const Point2& p) const {
    const std::array<int, 2> c = cell_of(p);
    bool out = true;
    for_each_in(c[0], c[1], [&](int k) {
      out = out && distance(p, k) >= m_clearance[static_cast<std::size_t>(k)];
    });
    return out;
  }
  /// The distance from p to the nearest segment, or `beyond` if none is nearer; `beyond` at most
  /// the smallest clearance.
  double distance_within(const Point2& p, double beyond) const {
    const std::array<int, 2> c = cell_of(p);
    double nearest = beyond;
    for_each_in(c[0], c[1], [&](int k) { nearest = std::min(nearest, distance(p, k)); });
    return nearest;
  }

 private:
  std::size_t cell_id(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(m_columns) + static_cast<std::size_t>(x);
  }

  double distance(const Point2& p, int k) const {
    const Point2 &a = m_loop[static_cast<std::size_t>(k)], &b = m_loop[(static_cast<std::size_t>(k) + 1) % m_loop.size()];
    const Point2 ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (a + t * ab - p).norm();
  }

  const std::vector<Point2>& m_loop;
  std::vector<double> m_clearance;
  Point2 m_origin;
  double m_cell = 1;
  int m_columns = 1, m_rows = 1;
  std::vector<int> m_start, m_items;
};

/// Throws unless the outline is a simple polygon: neighbouring segments meet only at their shared
/// point (no fold back along the same line), other segments not at all. Names the offending pair
/// of the lowest first segment (and of it, the lowest second).
inline void require_simple_outline(const std::vector<Point2>& loop, const SegmentGrid& grid) {
  const std::size_t m = loop.size();
  for (std::size_t i = 0; i < m; ++i) {
    const Point2 &a = loop[i], &b = loop[(i + 1) % m], &c = loop[(i + 2) % m];
    std::size_t first = m;
    // The next segment folds back onto this one: collinear, turning round at b.
    if (orientation(a, b, c) == 0 && (a - b).dot(c - b) > 0) first = (i + 1) % m;
    const std::array<int, 2> lo = grid.cell_of(a.cwiseMin(b)), hi = grid.cell_of(a.cwiseMax(b));
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x)
        grid.for_each_in(x, y, [&](int k) {
          const std::size_t j = static_cast<std::size_t>(k);
          if (j <= i + 1 || j >= first || (i == 0 && j == m - 1)) return;  // itself, neighbours, or after one found
          if (segments_meet(a, b, loop[j], loop[(j + 1) % m])) first = j;
        });
    if (first < m)
      fail_argument("outline",
                    panel_segment_name(Index(i), Index(m)) + " and " + panel_segment_name(Index(first), Index(m)) +
                        " meet",
                    "a simple closed polygon: each segment meets only its two neighbours, at their shared points");
  }
}

/// Throws for what mesh_panel refuses (its \throws), the self-intersection test last.
inline void require_panel_outline(const Eigen::Matrix2Xd& outline, double edge_length) {
  require_positive_finite("edge_length", edge_length);
  const Index m = outline.cols();
  if (m < 3) fail_argument("outline", to_text(m) + " points", "a closed polygon of at least 3 points");
  const auto point_text = [&](Index k) {
    return "(" + to_text(outline(0, k)) + ", " + to_text(outline(1, k)) + ")";
  };
  for (Index k = 0; k < m; ++k)
    if (!outline.col(k).allFinite())
      fail_argument("outline[" + to_text(k) + "]", point_text(k), "finite coordinates (m)");
  const double longest = panel_longest_segment * edge_length, shortest = panel_shortest_segment * edge_length;
  for (Index k = 0; k < m; ++k) {
    const Index next = (k + 1) % m;
    if (outline.col(k) == outline.col(next))
      fail_argument("outline[" + to_text(next) + "]", point_text(next) + ", the same point as outline[" + to_text(k) + "]",
                    "each point apart from the one before it");
    const double length = (outline.col(next) - outline.col(k)).norm();
    if (!(length <= longest && length >= shortest))
      fail_argument(panel_segment_name(k, m), "length " + to_text(length),
                    "[edge_length / 20, 2 edge_length] = [" + to_text(shortest) + ", " + to_text(longest) +
                        "]: an outline sampled at about edge_length = " + to_text(edge_length));
  }
  double twice_area = 0;
  for (Index k = 0; k < m; ++k) {
    const Index next = (k + 1) % m;
    twice_area += outline(0, k) * outline(1, next) - outline(0, next) * outline(1, k);
  }
  const double vertices = double(m) + std::abs(0.5 * twice_area) / (std::sqrt(3.0) / 2 * edge_length * edge_length);
  if (vertices > double(max_generated_vertices))
    fail_argument("outline area / edge_length^2",
                  to_text(std::abs(0.5 * twice_area) / (edge_length * edge_length)),
                  "a panel of at most " + to_text(max_generated_vertices) + " vertices (about " +
                      to_text(std::llround(vertices)) + " asked)");
}

/// The lattice vertices of step 1: inside the polygon, at least panel_clearance edge lengths from
/// every segment; row by row (rows along x, a row `shift` row heights above the bounding box's
/// centre).
inline std::vector<Point2> panel_lattice(const std::vector<Point2>& loop, double h, double shift,
                                         const SegmentGrid& near) {
  const std::size_t m = loop.size();
  Point2 lo = loop[0], hi = loop[0];
  for (const Point2& p : loop) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double row_height = h * std::sqrt(3.0) / 2, clearance = panel_clearance * h;
  const Point2 centre = 0.5 * (lo + hi) + Point2(0, shift * row_height);
  const long long first_row = static_cast<long long>(std::ceil((lo.y() - centre.y()) / row_height)),
                  last_row = static_cast<long long>(std::floor((hi.y() - centre.y()) / row_height));
  const long long row_count = std::max(0LL, last_row - first_row + 1);
  // The segments each row may cross (rows the segment's y range covers, one more each side for
  // round-off; the crossing itself is decided exactly below), in compressed rows.
  std::vector<long long> start(static_cast<std::size_t>(row_count) + 1, 0);
  std::vector<std::array<long long, 2>> span(m);
  for (std::size_t k = 0; k < m; ++k) {
    const double y0 = std::min(loop[k].y(), loop[(k + 1) % m].y()), y1 = std::max(loop[k].y(), loop[(k + 1) % m].y());
    const long long r0 = std::max(first_row, static_cast<long long>(std::floor((y0 - centre.y()) / row_height)) - 1),
                    r1 = std::min(last_row, static_cast<long long>(std::ceil((y1 - centre.y()) / row_height)) + 1);
    span[k] = {r0, r1};
    for (long long r = r0; r <= r1; ++r) ++start[static_cast<std::size_t>(r - first_row) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> crossing_segments(static_cast<std::size_t>(start.back()));
  {
    std::vector<long long> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < m; ++k)
      for (long long r = span[k][0]; r <= span[k][1]; ++r)
        crossing_segments[static_cast<std::size_t>(fill[static_cast<std::size_t>(r - first_row)]++)] = int(k);
  }
  std::vector<Point2> lattice;
  std::vector<double> crossings;
  for (long long r = first_row; r <= last_row; ++r) {
    const double y = centre.y() + static_cast<double>(r) * row_height;
    const double stagger = (r % 2 == 0) ? 0.0 : 0.5 * h;
    // Where the row crosses the outline (a segment from below y to at or above it, or back): the
    // row is inside between the first and second crossing, the third and fourth, ...
    crossings.clear();
    for (long long s = start[static_cast<std::size_t>(r - first_row)]; s < start[static_cast<std::size_t>(r - first_row) + 1];
         ++s) {
      const std::size_t k = static_cast<std::size_t>(crossing_segments[static_cast<std::size_t>(s)]);
      const Point2 &p = loop[k], &q = loop[(k + 1) % m];
      if ((p.y() <= y) == (q.y() <= y)) continue;
      crossings.push_back(p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y()));
    }
    std::sort(crossings.begin(), crossings.end());
    for (std::size_t c = 0; c + 1 < crossings.size(); c += 2) {
      const long long i0 = static_cast<long long>(std::ceil((crossings[c] + clearance - centre.x() - stagger) / h)),
                      i1 = static_cast<long long>(std::floor((crossings[c + 1] - clearance - centre.x() - stagger) / h));
      for (long long i = i0; i <= i1; ++i) {
        const Point2 p(centre.x() + stagger + static_cast<double>(i) * h, y);
        if (near.clear(p)) lattice.push_back(p);
      }
    }
  }
  return lattice;
}

}  // namespace detail

inline PanelMesh mesh_panel(const Eigen::Matrix2Xd& outline, double edge_length) {
  using detail::Point2;
  detail::require_panel_outline(outline, edge_length);
  const double h = edge_length;
  const std::size_t m = static_cast<std::size_t>(outline.cols());
  std::vector<Point2> loop(m);
  for (std::size_t k = 0; k < m; ++k) loop[k] = outline.col(static_cast<Index>(k));
  const double clearance = detail::panel_clearance * h;
  std::vector<double> segment_clearance(m);
  for (std::size_t k = 0; k < m; ++k)
    segment_clearance[k] = std::max(clearance, detail::panel_long_segment_clearance * (loop[(k + 1) % m] - loop[k]).norm());
  const detail::SegmentGrid near(loop, std::move(segment_clearance), h);
  detail::require_simple_outline(loop, near);

  // The points: the outline, the lattice along a Hilbert curve, then a box around them all. Of
  // the lattice's placements 0, 1/4, 1/2 and 3/4 of a row height up, the one that keeps the most
  // vertices (two rows across a narrow strip rather than one).
  std::vector<Point2> lattice;
  for (int quarter = 0; quarter < detail::panel_lattice_placements; ++quarter) {
    std::vector<Point2> placed =
        detail::panel_lattice(loop, h, double(quarter) / detail::panel_lattice_placements, near);
    if (placed.size() > lattice.size()) lattice = std::move(placed);
  }
  Point2 lo = loop[0], hi = loop[0];
  for (const Point2& p : loop) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), h);
  const std::uint32_t side = 1u << 16;
  const auto key = [&](const Point2& p) {
    const auto cell = [&](double v) {
      return static_cast<std::uint32_t>(std::min(double(side - 1), std::max(0.0, v / extent * (side - 1))));
    };
    return detail::hilbert_index(side, cell(p.x() - lo.x()), cell(p.y() - lo.y()));
  };
  {
    std::vector<std::pair<std::uint64_t, std::size_t>> keyed(lattice.size());
    for (std::size_t v = 0; v < lattice.size(); ++v) keyed[v] = {key(lattice[v]), v};
    std::sort(keyed.begin(), keyed.end());
    std::vector<Point2> sorted(lattice.size());
    for (std::size_t v = 0; v < lattice.size(); ++v) sorted[v] = lattice[keyed[v].second];
    lattice = std::move(sorted);
  }
  std::size_t n = m + lattice.size();
  std::vector<Point2> points = loop;
  points.insert(points.end(), lattice.begin(), lattice.end());
  const double margin = extent + h;
  points.emplace_back(lo.x() - margin, lo.y() - margin);
  points.emplace_back(hi.x() + margin, lo.y() - margin);
  points.emplace_back(hi.x() + margin, hi.y() + margin);
  points.emplace_back(lo.x() - margin, hi.y() + margin);

  // Delaunay in the box, in Hilbert order (short walks to each point).
  detail::PlanarTriangulation triangulation(std::move(points));
  const int box = static_cast<int>(n);
  triangulation.start_with_quad(box, box + 1, box + 2, box + 3);
  std::vector<std::pair<std::uint64_t, int>> order(n);
  for (std::size_t v = 0; v < n; ++v) order[v] = {key(triangulation.points[v]), static_cast<int>(v)};
  std::sort(order.begin(), order.end());
  for (const auto& entry : order) triangulation.insert(entry.second);

  // The outline's segments as constrained edges, constrained Delaunay, the inside kept.
  std::vector<std::array<int, 2>> segments(m);
  for (std::size_t k = 0; k < m; ++k) segments[k] = {static_cast<int>(k), static_cast<int>((k + 1) % m)};
  triangulation.constrain(segments);
  triangulation.flip_to_delaunay();
  triangulation.keep_triangles(triangulation.enclosed_by_constraints());
  std::vector<char> used(n, 0);
  for (const std::array<int, 3>& f : triangulation.triangles)
    for (int v : f) {
      if (v >= box) throw std::logic_error("drape: mesh_panel: a triangle outside the outline was kept");
      used[static_cast<std::size_t>(v)] = 1;
    }
  if (std::find(used.begin(), used.end(), 0) != used.end())
    throw std::logic_error("drape: mesh_panel: a vertex is in no triangle inside the outline");
  triangulation.points.resize(n);

  // Refinement where a triangle is thin (at outline corners between segments of unequal length,
  // at short segments, across narrow parts), no new vertex near the outline: a corner's own angle
  // stays (the centre of a thin triangle at a sharp corner lies near its sides).
  const auto accept = [&](int t, const Point2& centre) {
    const Point2& corner = triangulation.points[static_cast<std::size_t>(triangulation.triangles[static_cast<std::size_t>(t)][0])];
    const double needed = std::min(detail::panel_refinement_clearance * (centre - corner).norm(), clearance);
    return near.distance_within(centre, needed) >= needed;
  };
  triangulation.refine(detail::panel_refinement_angle, static_cast<int>(n), accept);
  n = triangulation.points.size();

  // Interior vertices smoothed; the outline stays.
  std::vector<detail::VertexFreedom> freedom(n, detail::VertexFreedom::Free);
  std::fill(freedom.begin(), freedom.begin() + static_cast<std::ptrdiff_t>(m), detail::VertexFreedom::Fixed);
  triangulation.smooth(freedom, detail::generator_smoothing_passes);
  triangulation.refine(detail::panel_refinement_angle, static_cast<int>(n), accept);
  n = triangulation.points.size();

  PanelMesh panel;
  panel.outline_count = static_cast<int>(m);
  panel.rest.resize(2, static_cast<Index>(n));
  for (std::size_t v = 0; v < n; ++v) panel.rest.col(static_cast<Index>(v)) = triangulation.points[v];
  std::vector<std::array<int, 3>>& faces = triangulation.triangles;
  for (std::array<int, 3>& f : faces) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  std::sort(faces.begin(), faces.end());
  panel.triangles.resize(3, static_cast<Index>(faces.size()));
  for (std::size_t t = 0; t < faces.size(); ++t)
    panel.triangles.col(static_cast<Index>(t)) = Eigen::Vector3i(faces[t][0], faces[t][1], faces[t][2]);
  return panel;
}

template <class Scalar>
ClothMesh<Scalar> panel_cloth_mesh(const PanelMesh& panel) {
  ClothMesh<Scalar> mesh;
  const Index n = panel.rest.cols();
  mesh.rest_uv = panel.rest.template cast<Scalar>();
  mesh.positions = Matrix3X<Scalar>::Zero(3, n);
  mesh.positions.topRows(2) = mesh.rest_uv;
  mesh.triangles.resize(static_cast<std::size_t>(panel.triangles.cols()));
  for (Index t = 0; t < panel.triangles.cols(); ++t)
    mesh.triangles[static_cast<std::size_t>(t)] = {panel.triangles(0, t), panel.triangles(1, t), panel.triangles(2, t)};
  std::vector<int>& outline = mesh.groups["outline"];
  outline.resize(static_cast<std::size_t>(panel.outline_count));
  std::iota(outline.begin(), outline.end(), 0);
  return mesh;
}

}  // namespace drape
