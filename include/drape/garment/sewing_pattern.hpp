#pragma once
/// \file sewing_pattern.hpp
/// A sewing pattern (drape's garments.md, "Sewing patterns"): flat panels, each a closed loop of
/// edges in its own plane and a rigid placement of that plane around the body, and the stitches
/// that sew pairs of edges together. It holds what GarmentCode's pattern "specification" JSON holds
/// (the optional drape::pattern_io reads one) in metres, with the curves' control points absolute.
///
/// - A panel's edges form one loop in order: edge i ends at the vertex where edge i + 1 starts, the
///   last ends where the first starts. The loop may run either way round; GarmentCode turns each
///   panel's loop so that its right-hand normal, rotation * (0, 0, +1) for a counter-clockwise
///   loop and rotation * (0, 0, -1) for a clockwise one, points away from the body (the fabric's
///   right side, pygarment/garmentcode/panel.py, autonorm()).
/// - A point p of the panel plane is at rotation * (p.x, p.y, 0) + translation in the body's frame
///   (panel_to_world()).
/// - A stitch sews edge `sides[0]` to edge `sides[1]`. By default (GarmentCode's "right side to
///   right side") the end of the first edge meets the start of the second and the start of the
///   first the end of the second; with `right_wrong` the starts meet and the ends meet
///   (stitch_meets_reversed()).
///
/// validate() checks what the model alone can check and throws a PatternError whose path is the
/// place in GarmentCode's JSON layout (`pattern.panels.NAME.edges[3]`, `pattern.stitches[7][1]`).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drape/core/detail/planar_triangulation.hpp"
#include "drape/core/placement.hpp"
#include "drape/core/validation.hpp"
#include "drape/garment/pattern_curves.hpp"

namespace drape {

/// A defect of a sewing pattern. what() is `SOURCE: PATH: MESSAGE` (`SOURCE: ` left out when there
/// is no source), e.g. `shirt.json: pattern.stitches[7][1].edge: edge 12 out of range (panel
/// right_btorso has 6 edges)`.
class PatternError : public std::runtime_error {
 public:
  PatternError(std::string source, std::string path, std::string message)
      : std::runtime_error(compose(source, path, message)),
        m_source(std::move(source)),
        m_path(std::move(path)),
        m_message(std::move(message)) {}

  /// The file (or the name given for text in memory); may be empty.
  const std::string& source() const { return m_source; }
  /// Where in the pattern, in GarmentCode's JSON layout (`pattern.panels.left_ftorso.edges[3]`).
  const std::string& path() const { return m_path; }
  /// What is wrong.
  const std::string& message() const { return m_message; }

 private:
  static std::string compose(const std::string& source, const std::string& path, const std::string& message) {
    std::string out;
    if (!source.empty()) out += source + ": ";
    if (!path.empty()) out += path + ": ";
    return out + message;
  }
  std::string m_source, m_path, m_message;
};

struct PatternEdge {
  int start = 0;  ///< vertex index of the panel
  int end = 0;    ///< vertex index of the panel
  CurveShape curve;
};

struct PatternPanel {
  std::string name;
  std::vector<Eigen::Vector2d> vertices;  ///< m, in the panel plane
  std::vector<PatternEdge> edges;         ///< one closed loop, in loop order
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();  ///< m
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< a rotation matrix (orthonormal, det +1)
};

struct StitchSide {
  int panel = 0;  ///< index into SewingPattern::panels
  int edge = 0;   ///< index into that panel's edges
};

struct Stitch {
  std::array<StitchSide, 2> sides;
  /// GarmentCode's "right_wrong" stitch: the right side of one panel's fabric to the wrong side of
  /// the other's; the two edges then meet start to start. Default: start to end.
  bool right_wrong = false;
};

struct SewingPattern {
  std::vector<PatternPanel> panels;
  std::vector<Stitch> stitches;

  /// The index of the panel named `name`, -1 if none is.
  int find_panel(const std::string& name) const {
    for (std::size_t p = 0; p < panels.size(); ++p)
      if (panels[p].name == name) return static_cast<int>(p);
    return -1;
  }
};

/// What validate() accepts.
struct PatternCheckOptions {
  /// Largest ratio of the longer to the shorter edge of a stitch. GarmentCode's example patterns
  /// have at most 1.0034 (the shirt), 1.0015 (the hoody), 1.102 (the jumpsuit) and 1.302 (the
  /// pencil dress, whose waist seam gathers the bodice by design); 1.4 accepts them and refuses a
  /// stitch of clearly mismatched edges (1.5 and more). Strongly ruffled seams need it raised.
  double max_stitch_length_ratio = 1.4;
  /// Largest |coordinate| of a vertex, control point or translation, and largest radius, in metres.
  double max_coordinate = 1000;
};

/// The rotation of GarmentCode's Euler angles in degrees `[x, y, z]`: about x first, then y, then z,
/// fixed axes, R = Rz Ry Rx (pygarment/pattern/rotation.py, euler_xyz_to_R, which places the
/// panels in pygarment/meshgen/boxmeshgen.py; drape's Placement::rotation() is the same).
inline Eigen::Matrix3d rotation_from_euler_degrees(const Eigen::Vector3d& degrees) {
  Placement<double> placement;
  placement.rotation_degrees = degrees;
  return placement.rotation();
}

/// Moves panel `name` by `offset` (m, added to its translation): a placement other than the
/// pattern's, e.g. a sleeve started outside the torso's panels (docs/garments.md).
/// \throws InvalidParameter (`panel offsets`) naming the panel and the pattern's panels if it has
///   none of that name, or the offset if it is not finite.
inline void move_panel(SewingPattern& pattern, const std::string& name, const Eigen::Vector3d& offset) {
  const auto panel = std::find_if(pattern.panels.begin(), pattern.panels.end(),
                                  [&name](const PatternPanel& p) { return p.name == name; });
  if (panel == pattern.panels.end()) {
    std::string names;
    for (const PatternPanel& p : pattern.panels) names += (names.empty() ? "" : ", ") + p.name;
    throw InvalidParameter("panel offsets", "'" + name + "'", "a panel of the pattern: " + names);
  }
  if (!offset.allFinite())
    throw InvalidParameter("panel offsets", "a non-finite offset of '" + name + "'", "finite offsets (m)");
  panel->translation += offset;
}

/// A point of the panel plane in the body's frame: rotation * (x, y, 0) + translation.
inline Eigen::Vector3d panel_to_world(const PatternPanel& panel, const Eigen::Vector2d& point) {
  return panel.rotation * Eigen::Vector3d(point.x(), point.y(), 0) + panel.translation;
}

/// The point of edge `edge` at parameter u in [0, 1] (its start vertex at 0, its end vertex at 1).
inline Eigen::Vector2d edge_point(const PatternPanel& panel, int edge, double u) {
  const PatternEdge& e = panel.edges[std::size_t(edge)];
  return curve_point(panel.vertices[std::size_t(e.start)], panel.vertices[std::size_t(e.end)], e.curve, u);
}

/// The arc length of edge `edge` (m; relative accuracy 1e-12, pattern_curves.hpp).
inline double edge_length(const PatternPanel& panel, int edge) {
  const PatternEdge& e = panel.edges[std::size_t(edge)];
  return curve_length(panel.vertices[std::size_t(e.start)], panel.vertices[std::size_t(e.end)], e.curve);
}

/// The parameters of `segments` + 1 points at equal arc length along edge `edge`, from 0 to 1.
inline std::vector<double> edge_parameters(const PatternPanel& panel, int edge, int segments) {
  const PatternEdge& e = panel.edges[std::size_t(edge)];
  return equal_length_parameters(panel.vertices[std::size_t(e.start)], panel.vertices[std::size_t(e.end)], e.curve,
                                 segments);
}

/// Whether the stitch pairs the first edge's points in reverse: true (GarmentCode's default) when
/// the end of sides[0] meets the start of sides[1]; false for a right_wrong stitch, whose starts meet.
/// The rule is boxmeshgen.py's (pygarment/meshgen): `swap = not (len(stitch) == 3 and stitch[-1] ==
/// 'right_wrong')`, and a swapped stitch zips the first edge's vertices reversed with the second's.
inline bool stitch_meets_reversed(const Stitch& stitch) { return !stitch.right_wrong; }

/// The JSON path of a panel: `pattern.panels.NAME`, or `pattern.panels["NA.ME"]` for a name that
/// holds '.', '[', ']' or '"' (or is empty).
inline std::string panel_path(const std::string& name) {
  if (!name.empty() && name.find_first_of(".[]\"") == std::string::npos) return "pattern.panels." + name;
  std::string quoted = "\"";
  for (char c : name) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return "pattern.panels[" + quoted + "\"]";
}

/// `pattern.stitches[K]`.
inline std::string stitch_path(int stitch) { return "pattern.stitches[" + detail::to_text(stitch) + "]"; }

/// The first two edges of a closed polyline that cross or touch where they should not, found on
/// its segments pairwise; `point_edge[k]` is the edge that segment k (points k to k + 1, the last
/// to the first) belongs to. Segments next to each other may share their common point but not
/// fold back over each other.
struct OutlineCrossing {
  bool found = false;
  int edge_a = -1, edge_b = -1;
  Eigen::Vector2d where = Eigen::Vector2d::Zero();
};
inline OutlineCrossing find_outline_crossing(const std::vector<Eigen::Vector2d>& points,
                                             const std::vector<int>& point_edge);

/// The twice signed area of a closed polygon (> 0 counter-clockwise).
inline double twice_signed_area(const std::vector<Eigen::Vector2d>& points) {
  double sum = 0;
  for (std::size_t i = 0, n = points.size(); i < n; ++i) {
    const Eigen::Vector2d& a = points[i];
    const Eigen::Vector2d& b = points[(i + 1) % n];
    sum += a.x() * b.y() - a.y() * b.x();
  }
  return sum;
}

/// The checks validate() makes on each panel's outline use each curved edge as this many chords
/// between equal steps of its parameter (a straight edge as one).
constexpr int validation_chords_per_curve = 16;

/// Checks the pattern: at least one panel; unique, non-empty panel names; per panel at least two
/// edges forming one closed loop of vertex indices in range, no edge from a vertex to itself or of
/// zero chord, finite coordinates within options.max_coordinate, circle radii > 0 and at least half
/// the chord (to 1e-3), a rotation matrix (orthonormal to 1e-6, det +1), an outline that neither
/// crosses nor touches itself and encloses an area; per stitch panels and edges in range, two
/// different edges, no edge in two stitches, edge lengths within options.max_stitch_length_ratio.
/// \throws PatternError for the first defect, its path in GarmentCode's JSON layout and `source`
///   (a file name, may be empty) in front.
inline void validate(const SewingPattern& pattern, const std::string& source = "",
                     const PatternCheckOptions& options = {});

/// The first half of validate(): the panels (a reader checks them before it reads the stitches).
inline void validate_panels(const SewingPattern& pattern, const std::string& source = "",
                            const PatternCheckOptions& options = {});

/// The second half of validate(): the stitches, on panels that passed validate_panels().
inline void validate_stitches(const SewingPattern& pattern, const std::string& source = "",
                              const PatternCheckOptions& options = {});

// ---------------------------------------------------------------------------------------------------

namespace detail {

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// A number for a message, to `digits` significant digits.
inline std::string short_number(double x, int digits = 6) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, x == 0 ? 0.0 : x);
  return text;
}

inline std::string metres(double x) { return short_number(x); }

inline std::string point_text(const Eigen::Vector2d& p) { return "(" + metres(p.x()) + ", " + metres(p.y()) + ") m"; }

}  // namespace detail

inline OutlineCrossing find_outline_crossing(const std::vector<Eigen::Vector2d>& points,
                                             const std::vector<int>& point_edge) {
  OutlineCrossing out;
  const std::size_t n = points.size();
  if (n < 3) return out;
  const auto next = [n](std::size_t k) { return (k + 1) % n; };
  // Neighbours: share a point; they must not fold back onto each other (collinear, opposite).
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector2d a = points[next(k)] - points[k], b = points[next(next(k))] - points[next(k)];
    const double scale = a.norm() * b.norm();
    if (std::abs(detail::cross2(a, b)) <= 1e-12 * scale && a.dot(b) < 0) {
      out = {true, point_edge[k], point_edge[next(k)], points[next(k)]};
      return out;
    }
  }
  // The others, swept along x: segments sorted by their smallest x, each tested against the ones
  // after it that start before it ends.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::vector<double> lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) {
    lo[k] = std::min(points[k].x(), points[next(k)].x());
    hi[k] = std::max(points[k].x(), points[next(k)].x());
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return lo[a] < lo[b]; });
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = order[i];
    const double a_ylo = std::min(points[a].y(), points[next(a)].y());
    const double a_yhi = std::max(points[a].y(), points[next(a)].y());
    for (std::size_t j = i + 1; j < n && lo[order[j]] <= hi[a]; ++j) {
      const std::size_t b = order[j];
      if (b == next(a) || a == next(b)) continue;  // neighbours, checked above
      if (std::max(points[b].y(), points[next(b)].y()) < a_ylo || std::min(points[b].y(), points[next(b)].y()) > a_yhi)
        continue;
      if (detail::segments_meet(points[a], points[next(a)], points[b], points[next(b)])) {
        const std::size_t first = std::min(a, b), second = std::max(a, b);
        out = {true, point_edge[first], point_edge[second], points[first]};
        // The crossing point, for the message: where the first meets the second's line.
        const Eigen::Vector2d d = points[next(first)] - points[first], e = points[next(second)] - points[second];
        const double denominator = detail::cross2(d, e);
        if (denominator != 0) {
          const double t = std::clamp(detail::cross2(points[second] - points[first], e) / denominator, 0.0, 1.0);
          out.where = points[first] + t * d;
        }
        return out;
      }
    }
  }
  return out;
}

namespace detail {

[[noreturn]] inline void pattern_fail(const std::string& source, const std::string& path, const std::string& message) {
  throw PatternError(source, path, message);
}

inline std::string edge_path(const PatternPanel& panel, int e) {
  return panel_path(panel.name) + ".edges[" + to_text(e) + "]";
}

inline void check_point(const std::string& source, const std::string& path, const char* what,
                        const Eigen::Vector2d& p, double limit) {
  if (!p.allFinite()) pattern_fail(source, path, std::string(what) + " is not finite");
  if (std::abs(p.x()) > limit || std::abs(p.y()) > limit)
    pattern_fail(source, path,
                 std::string(what) + " " + point_text(p) + " is farther than " + metres(limit) + " m from the origin");
}

inline void validate_panel(const PatternPanel& panel, const std::string& source, const PatternCheckOptions& options) {
  const std::string path = panel_path(panel.name);
  const int vertex_count = static_cast<int>(panel.vertices.size());
  const int edge_count = static_cast<int>(panel.edges.size());
  for (int v = 0; v < vertex_count; ++v)
    check_point(source, path + ".vertices[" + to_text(v) + "]", "the vertex", panel.vertices[std::size_t(v)],
                options.max_coordinate);
  if (edge_count < 2)
    pattern_fail(source, path + ".edges",
                 to_text(edge_count) + (edge_count == 1 ? " edge" : " edges") +
                     ": a panel's outline is a closed loop of at least 2 edges");
  for (int e = 0; e < edge_count; ++e) {
    const PatternEdge& edge = panel.edges[std::size_t(e)];
    const std::string at = edge_path(panel, e);
    const int ends[2] = {edge.start, edge.end};
    for (int k = 0; k < 2; ++k)
      if (ends[k] < 0 || ends[k] >= vertex_count)
        pattern_fail(source, at + ".endpoints[" + to_text(k) + "]",
                     "vertex " + to_text(ends[k]) + " out of range (panel " + panel.name + " has " +
                         to_text(vertex_count) + (vertex_count == 1 ? " vertex)" : " vertices)"));
    if (edge.start == edge.end)
      pattern_fail(source, at + ".endpoints", "the edge starts and ends at vertex " + to_text(edge.start));
  }
  // The loop: edge e ends where edge e + 1 starts, the last where the first starts.
  for (int e = 0; e < edge_count; ++e) {
    const PatternEdge& edge = panel.edges[std::size_t(e)];
    const int f = (e + 1) % edge_count;
    const PatternEdge& following = panel.edges[std::size_t(f)];
    if (edge.end != following.start)
      pattern_fail(source, edge_path(panel, e) + ".endpoints",
                   "the edge loop does not close: edge " + to_text(e) + " ends at vertex " + to_text(edge.end) +
                       " but edge " + to_text(f) + " starts at vertex " + to_text(following.start) +
                       " (each edge starts where the one before it ends, the first where the last ends)");
  }
  for (int e = 0; e < edge_count; ++e) {
    const PatternEdge& edge = panel.edges[std::size_t(e)];
    const std::string at = edge_path(panel, e);
    const Eigen::Vector2d& a = panel.vertices[std::size_t(edge.start)];
    const Eigen::Vector2d& b = panel.vertices[std::size_t(edge.end)];
    const double chord = (b - a).norm();
    if (!(chord > 0))
      pattern_fail(source, at + ".endpoints",
                   "vertices " + to_text(edge.start) + " and " + to_text(edge.end) + " are at the same point " +
                       point_text(a));
    const CurveShape& c = edge.curve;
    if (c.type == CurveType::Quadratic || c.type == CurveType::Cubic) {
      const int controls = c.type == CurveType::Quadratic ? 1 : 2;
      for (int k = 0; k < controls; ++k)
        check_point(source, at + ".curvature.params[" + to_text(k) + "]", "the control point",
                    c.control[std::size_t(k)], options.max_coordinate);
    } else if (c.type == CurveType::Circle) {
      const std::string radius_path = at + ".curvature.params[0]";
      if (!std::isfinite(c.radius) || !(c.radius > 0) || c.radius > options.max_coordinate)
        pattern_fail(source, radius_path,
                     "radius " + short_number(c.radius) + " m (allowed: finite, > 0 and at most " +
                         metres(options.max_coordinate) + " m)");
      if (c.radius < 0.5 * chord * (1 - 1e-3))
        pattern_fail(source, radius_path,
                     "radius " + metres(c.radius) + " m is less than half the chord (" + metres(0.5 * chord) +
                         " m): no circle of that radius joins vertices " + to_text(edge.start) + " and " +
                         to_text(edge.end));
    }
  }
  if (!panel.translation.allFinite() || panel.translation.cwiseAbs().maxCoeff() > options.max_coordinate)
    pattern_fail(source, path + ".translation",
                 "the translation is not finite or farther than " + metres(options.max_coordinate) + " m");
  const Eigen::Matrix3d& r = panel.rotation;
  if (!r.allFinite() || !(((r.transpose() * r) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-6) ||
      !(std::abs(r.determinant() - 1) <= 1e-6))
    pattern_fail(source, path + ".rotation", "not a rotation (orthonormal with determinant +1)");

  // The outline: each curve as chords; it must enclose an area and not cross itself.
  std::vector<Eigen::Vector2d> points;
  std::vector<int> point_edge;
  for (int e = 0; e < edge_count; ++e) {
    const int chords = panel.edges[std::size_t(e)].curve.type == CurveType::Straight ? 1 : validation_chords_per_curve;
    for (int k = 0; k < chords; ++k) {
      points.push_back(edge_point(panel, e, double(k) / chords));
      point_edge.push_back(e);
    }
  }
  const OutlineCrossing crossing = find_outline_crossing(points, point_edge);
  if (crossing.found) {
    const std::string where = " near " + point_text(crossing.where);
    if (crossing.edge_a == crossing.edge_b)
      pattern_fail(source, edge_path(panel, crossing.edge_a),
                   "the outline crosses itself: edge " + to_text(crossing.edge_a) + " meets itself" + where);
    pattern_fail(source, path,
                 "the outline crosses itself: edge " + to_text(crossing.edge_a) + " meets edge " +
                     to_text(crossing.edge_b) + where);
  }
  const double area = 0.5 * std::abs(twice_signed_area(points));
  double perimeter = 0;
  for (std::size_t k = 0; k < points.size(); ++k) perimeter += (points[(k + 1) % points.size()] - points[k]).norm();
  if (!(area > 1e-9 * perimeter * perimeter))
    pattern_fail(source, path, "the outline encloses no area");
}

}  // namespace detail

inline void validate(const SewingPattern& pattern, const std::string& source, const PatternCheckOptions& options) {
  validate_panels(pattern, source, options);
  validate_stitches(pattern, source, options);
}

inline void validate_panels(const SewingPattern& pattern, const std::string& source,
                            const PatternCheckOptions& options) {
  if (pattern.panels.empty()) detail::pattern_fail(source, "pattern.panels", "the pattern has no panels");
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
    const std::string& name = pattern.panels[p].name;
    if (name.empty()) detail::pattern_fail(source, "pattern.panels", "panel " + detail::to_text(p) + " has no name");
    for (std::size_t q = 0; q < p; ++q)
      if (pattern.panels[q].name == name)
        detail::pattern_fail(source, panel_path(name), "two panels are named " + name);
  }
  for (const PatternPanel& panel : pattern.panels) detail::validate_panel(panel, source, options);
}

inline void validate_stitches(const SewingPattern& pattern, const std::string& source,
                              const PatternCheckOptions& options) {
  const int panel_count = static_cast<int>(pattern.panels.size());
  std::vector<std::vector<int>> stitch_of(pattern.panels.size());  // per panel and edge: the stitch, or -1
  for (std::size_t p = 0; p < pattern.panels.size(); ++p) stitch_of[p].assign(pattern.panels[p].edges.size(), -1);
  for (int s = 0; s < static_cast<int>(pattern.stitches.size()); ++s) {
    const Stitch& stitch = pattern.stitches[std::size_t(s)];
    std::array<double, 2> length{};
    for (int k = 0; k < 2; ++k) {
      const StitchSide& side = stitch.sides[std::size_t(k)];
      const std::string at = stitch_path(s) + "[" + detail::to_text(k) + "]";
      if (side.panel < 0 || side.panel >= panel_count)
        detail::pattern_fail(source, at + ".panel",
                             "panel " + detail::to_text(side.panel) + " out of range (the pattern has " +
                                 detail::to_text(panel_count) + " panels)");
      const PatternPanel& panel = pattern.panels[std::size_t(side.panel)];
      const int edges = static_cast<int>(panel.edges.size());
      if (side.edge < 0 || side.edge >= edges)
        detail::pattern_fail(source, at + ".edge",
                             "edge " + detail::to_text(side.edge) + " out of range (panel " + panel.name + " has " +
                                 detail::to_text(edges) + " edges)");
      int& owner = stitch_of[std::size_t(side.panel)][std::size_t(side.edge)];
      if (owner >= 0)
        detail::pattern_fail(source, at,
                             "edge " + detail::to_text(side.edge) + " of panel " + panel.name + " is also in " +
                                 (owner == s ? std::string("the other side of this stitch")
                                             : "stitch " + detail::to_text(owner)) +
                                 ": an edge is sewn once");
      owner = s;
      length[std::size_t(k)] = edge_length(panel, side.edge);
    }
    const double longer = std::max(length[0], length[1]), shorter = std::min(length[0], length[1]);
    if (!(longer <= options.max_stitch_length_ratio * shorter)) {
      const auto side_text = [&](int k) {
        const StitchSide& side = stitch.sides[std::size_t(k)];
        return detail::metres(length[std::size_t(k)]) + " m (panel " + pattern.panels[std::size_t(side.panel)].name +
               " edge " + detail::to_text(side.edge) + ")";
      };
      detail::pattern_fail(source, stitch_path(s),
                           "stitch " + detail::to_text(s) + " sews edges of very different lengths: " + side_text(0) +
                               " and " + side_text(1) + ", ratio " + detail::short_number(longer / shorter, 4) +
                               " (allowed: at most " + detail::short_number(options.max_stitch_length_ratio) + ")");
    }
  }
}

}  // namespace drape
