#pragma once
/// \file outline_sampling.hpp
/// Each panel's outline as one closed polygon at a target edge length, the polygon a panel mesher
/// fills, and the one-to-one pairing of the points of stitched edges that a seam joins (drape's
/// garments.md, "Sewing patterns").
///
/// - Every edge is split into n = max(1, round(length / h)) segments of equal arc length; the two
///   edges of a stitch both take the larger of their two n, so their points pair one to one.
/// - The panel's vertices are points of the polygon exactly (the edges' ends), each once.
/// - The polygon runs counter-clockwise in the panel plane. A panel whose edge loop runs clockwise
///   is reversed (PanelOutline::reversed); the side of the panel that faces away from the body
///   after placement (GarmentCode's right side of the fabric, the edge loop's right-hand normal) is
///   then local -z, else local +z: outward_normal().

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drape/core/validation.hpp"
#include "drape/garment/sewing_pattern.hpp"

namespace drape {

struct PanelOutline {
  /// The polygon, counter-clockwise in the panel plane (m); the last point joins the first.
  std::vector<Eigen::Vector2d> points;
  /// Per edge of the panel: the polygon indices of its points from its start vertex (u = 0) to its
  /// end vertex (u = 1), segments + 1 of them. They run up the polygon (wrapping past the end)
  /// unless the outline is reversed, then down.
  std::vector<std::vector<int>> edge_points;
  /// Per edge: the number of segments it is split into.
  std::vector<int> segments;
  /// Per vertex of the panel: its polygon index, -1 for a vertex that no edge uses.
  std::vector<int> vertex_points;
  /// The panel's edge loop runs clockwise; the polygon runs it backwards.
  bool reversed = false;
};

struct PatternOutlines {
  double edge_length = 0;  ///< the target h, m
  std::vector<PanelOutline> panels;  ///< one per panel of the pattern, same order
};

/// The largest polygon sample_outlines() makes, in points over all panels.
constexpr long long max_outline_points = 10'000'000;

/// Every panel's outline at target edge length `edge_length` (m). The pattern should have passed
/// validate().
/// \throws InvalidParameter (`edge_length`) unless it is finite and > 0 and the outlines have at
///   most max_outline_points points; PatternError (path `pattern.panels.NAME`) when a panel's
///   polygon at this edge length crosses itself or encloses no area (a curve drawn as too few
///   chords): a shorter edge length helps.
inline PatternOutlines sample_outlines(const SewingPattern& pattern, double edge_length);

/// The pairs (point of sides[0]'s panel polygon, point of sides[1]'s panel polygon) of stitch
/// `stitch`, one per point of its edges, in order along sides[1]'s edge from its start. The rule is
/// GarmentCode's (pygarment/meshgen/boxmeshgen.py, read_stitches() and _swap_stitch_ranges()): by
/// default the first edge's points run reversed, so its end meets the second's start; in a
/// right_wrong stitch both run forwards (start meets start).
inline std::vector<std::pair<int, int>> stitch_point_pairs(const SewingPattern& pattern,
                                                           const PatternOutlines& outlines, int stitch);

/// The unit normal, in the body's frame, of the side of panel `panel` that faces away from the body
/// (the loop's right-hand normal): rotation * (0, 0, +1) for a counter-clockwise loop, rotation *
/// (0, 0, -1) for a clockwise (reversed) one. A mesh of the counter-clockwise polygon whose
/// triangles run counter-clockwise in the panel plane faces this way when the outline is not reversed.
inline Eigen::Vector3d outward_normal(const SewingPattern& pattern, const PatternOutlines& outlines, int panel);

// ---------------------------------------------------------------------------------------------------

inline PatternOutlines sample_outlines(const SewingPattern& pattern, double edge_length) {
  detail::require_positive_finite("edge_length", edge_length);
  PatternOutlines out;
  out.edge_length = edge_length;
  out.panels.resize(pattern.panels.size());

  // Segments per edge, then equalised across each stitch.
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    const PatternPanel& panel = pattern.panels[p];
    PanelOutline& outline = out.panels[p];
    outline.segments.resize(panel.edges.size());
    for (std::size_t e = 0; e < panel.edges.size(); ++e) {
      const double length = ::drape::edge_length(panel, static_cast<int>(e));
      const double n = std::round(length / edge_length);
      if (!(n <= double(max_outline_points)))
        detail::fail_argument("edge_length", detail::to_text(edge_length),
                              "finite, > 0 and long enough for at most " + detail::to_text(max_outline_points) +
                                  " outline points (panel " + panel.name + " edge " + detail::to_text(e) + " is " +
                                  detail::to_text(length) + " m long)");
      outline.segments[e] = std::max(1, static_cast<int>(n));
    }
  }
  for (const Stitch& stitch : pattern.stitches) {
    int& a = out.panels[std::size_t(stitch.sides[0].panel)].segments[std::size_t(stitch.sides[0].edge)];
    int& b = out.panels[std::size_t(stitch.sides[1].panel)].segments[std::size_t(stitch.sides[1].edge)];
    a = b = std::max(a, b);
  }
  long long total = 0;
  for (const PanelOutline& outline : out.panels)
    for (int n : outline.segments) total += n;
  if (total > max_outline_points)
    detail::fail_argument("edge_length", detail::to_text(edge_length),
                          "long enough for at most " + detail::to_text(max_outline_points) + " outline points (this gives " +
                              detail::to_text(total) + ")");

  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    const PatternPanel& panel = pattern.panels[p];
    PanelOutline& outline = out.panels[p];
    const int edges = static_cast<int>(panel.edges.size());
    std::vector<int> point_edge;
    outline.vertex_points.assign(panel.vertices.size(), -1);
    outline.edge_points.resize(panel.edges.size());
    for (int e = 0; e < edges; ++e) {
      const int n = outline.segments[std::size_t(e)];
      const std::vector<double> u = edge_parameters(panel, e, n);
      const int first = static_cast<int>(outline.points.size());
      outline.vertex_points[std::size_t(panel.edges[std::size_t(e)].start)] = first;
      for (int k = 0; k < n; ++k) {
        // The start exactly (u = 0 gives the vertex), the inner points on the curve.
        outline.points.push_back(edge_point(panel, e, u[std::size_t(k)]));
        point_edge.push_back(e);
      }
      std::vector<int>& indices = outline.edge_points[std::size_t(e)];
      indices.resize(std::size_t(n) + 1);
      for (int k = 0; k <= n; ++k) indices[std::size_t(k)] = first + k;
    }
    const int count = static_cast<int>(outline.points.size());
    if (edges > 0) outline.edge_points.back().back() = 0;  // the last edge ends at the first point

    const std::string path = panel_path(panel.name);
    const OutlineCrossing crossing = find_outline_crossing(outline.points, point_edge);
    const std::string advice = " at edge length " + detail::short_number(edge_length) + " m; a shorter edge length draws its curves closer";
    if (crossing.found)
      detail::pattern_fail("", path,
                           "the sampled outline crosses itself (edge " + detail::to_text(crossing.edge_a) + " meets edge " +
                               detail::to_text(crossing.edge_b) + ")" + advice);
    const double area = twice_signed_area(outline.points);
    if (!(area != 0) || count < 3) detail::pattern_fail("", path, "the sampled outline encloses no area" + advice);
    if (area < 0) {
      // Reversed with point 0 kept: old index i becomes (count - i) % count.
      outline.reversed = true;
      std::vector<Eigen::Vector2d> reversed(outline.points.size());
      for (int i = 0; i < count; ++i) reversed[std::size_t((count - i) % count)] = outline.points[std::size_t(i)];
      outline.points = std::move(reversed);
      for (std::vector<int>& indices : outline.edge_points)
        for (int& i : indices) i = (count - i) % count;
      for (int& i : outline.vertex_points)
        if (i >= 0) i = (count - i) % count;
    }
  }
  return out;
}

inline std::vector<std::pair<int, int>> stitch_point_pairs(const SewingPattern& pattern,
                                                           const PatternOutlines& outlines, int stitch) {
  const Stitch& s = pattern.stitches[std::size_t(stitch)];
  const std::vector<int>& a = outlines.panels[std::size_t(s.sides[0].panel)].edge_points[std::size_t(s.sides[0].edge)];
  const std::vector<int>& b = outlines.panels[std::size_t(s.sides[1].panel)].edge_points[std::size_t(s.sides[1].edge)];
  const std::size_t n = std::min(a.size(), b.size());
  const bool reversed = stitch_meets_reversed(s);
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(n);
  for (std::size_t k = 0; k < n; ++k) pairs.emplace_back(reversed ? a[a.size() - 1 - k] : a[k], b[k]);
  return pairs;
}

inline Eigen::Vector3d outward_normal(const SewingPattern& pattern, const PatternOutlines& outlines, int panel) {
  const double side = outlines.panels[std::size_t(panel)].reversed ? -1 : 1;
  return pattern.panels[std::size_t(panel)].rotation * Eigen::Vector3d(0, 0, side);
}

}  // namespace drape
