// Sewing patterns without a file (drape/garment/): every curve type against points and lengths
// worked out by hand, GarmentCode's conventions (the side of a relative control point, the circle
// arc flags, the Euler angles), validate()'s refusals with their paths, and the outlines sampled
// for a mesher: vertices kept, counter-clockwise, equal arc length, stitched edges of equal counts
// and their points paired the way GarmentCode's box mesh pairs them.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "drape/garment/outline_sampling.hpp"
#include "drape/garment/pattern_curves.hpp"
#include "drape/garment/sewing_pattern.hpp"

using namespace drape;
using Catch::Matchers::Contains;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

const double pi = 3.14159265358979323846;

bool near(const Vector2d& a, const Vector2d& b, double eps = 1e-12) { return (a - b).norm() <= eps; }
bool near(const Vector3d& a, const Vector3d& b, double eps = 1e-12) { return (a - b).norm() <= eps; }

CurveShape quadratic(const Vector2d& c) {
  CurveShape s;
  s.type = CurveType::Quadratic;
  s.control[0] = c;
  return s;
}

CurveShape cubic(const Vector2d& c0, const Vector2d& c1) {
  CurveShape s;
  s.type = CurveType::Cubic;
  s.control = {c0, c1};
  return s;
}

CurveShape circle(double radius, bool large_arc, bool right) {
  CurveShape s;
  s.type = CurveType::Circle;
  s.radius = radius;
  s.large_arc = large_arc;
  s.right = right;
  return s;
}

/// The length of a polyline of `n` equal parameter steps along the curve.
double polyline_length(const Vector2d& a, const Vector2d& b, const CurveShape& shape, int n) {
  double sum = 0;
  Vector2d previous = a;
  for (int k = 1; k <= n; ++k) {
    const Vector2d p = curve_point(a, b, shape, double(k) / n);
    sum += (p - previous).norm();
    previous = p;
  }
  return sum;
}

/// The closed-form length of the quadratic Bezier curve p0, c, p1: the integral of
/// sqrt(A u^2 + B u + C) over [0, 1].
double quadratic_length(const Vector2d& p0, const Vector2d& c, const Vector2d& p1) {
  const Vector2d a = p0 - 2 * c + p1, b = 2 * (c - p0);
  const double A = 4 * a.squaredNorm(), B = 4 * a.dot(b), C = b.squaredNorm();
  const auto antiderivative = [&](double u) {
    const double q = std::sqrt(A * u * u + B * u + C);
    return (2 * A * u + B) * q / (4 * A) +
           (4 * A * C - B * B) / (8 * A * std::sqrt(A)) * std::log(2 * std::sqrt(A) * q + 2 * A * u + B);
  };
  return antiderivative(1) - antiderivative(0);
}

/// A panel of the given corners (cm-sized, in metres), straight edges in the given order.
PatternPanel polygon_panel(const std::string& name, const std::vector<Vector2d>& corners) {
  PatternPanel panel;
  panel.name = name;
  panel.vertices = corners;
  for (int i = 0; i < int(corners.size()); ++i) panel.edges.push_back({i, (i + 1) % int(corners.size()), {}});
  return panel;
}

/// Two panels like a shirt's front and back: a square at z = +0.1 whose loop runs counter-clockwise
/// (seen from +z: its outward normal +z) and a mirrored square at z = -0.1 whose loop runs
/// clockwise (outward -z), sewn along both sides. The front's right side (edge 1, x = 0.4, going
/// up) meets the back's edge 3 (x = 0.4, going down); the left sides likewise.
SewingPattern front_and_back() {
  SewingPattern pattern;
  PatternPanel front = polygon_panel("front", {{0, 0}, {0.4, 0}, {0.4, 0.5}, {0, 0.5}});
  front.translation = Vector3d(-0.2, 1.0, 0.1);
  PatternPanel back = polygon_panel("back", {{0, 0}, {0, 0.5}, {0.4, 0.5}, {0.4, 0}});  // clockwise
  back.translation = Vector3d(-0.2, 1.0, -0.1);
  // A curved neckline on the front, bulging down into the panel: to the left of its direction -x.
  front.edges[2].curve = quadratic(relative_to_absolute(front.vertices[2], front.vertices[3], 0.5, 0.2));
  pattern.panels = {front, back};
  pattern.stitches.push_back({{StitchSide{0, 1}, StitchSide{1, 2}}, false});  // front right, back right
  pattern.stitches.push_back({{StitchSide{0, 3}, StitchSide{1, 0}}, false});  // front left, back left
  return pattern;
}

std::string validation_error(const SewingPattern& pattern, const PatternCheckOptions& options = {}) {
  try {
    validate(pattern, "test", options);
  } catch (const PatternError& e) { return e.what(); }
  return "";
}

}  // namespace

TEST_CASE("a relative control point lies t along the edge and s to its left, in edge lengths", "[garment]") {
  // GarmentCode's rel_to_abs_2d: start + t (end - start) + s (-(end - start).y, (end - start).x).
  const Vector2d start(1, 1), end(3, 1);  // along +x: its left is +y
  CHECK(near(relative_to_absolute(start, end, 0.25, 0.5), Vector2d(1.5, 2)));
  CHECK(near(relative_to_absolute(start, end, 0.5, -0.25), Vector2d(2, 0.5)));
  // Along +y the left is -x.
  CHECK(near(relative_to_absolute(Vector2d(0, 0), Vector2d(0, 2), 0.5, 0.5), Vector2d(-1, 1)));
}

TEST_CASE("quadratic and cubic Bezier edges: points by hand, lengths against closed forms", "[garment]") {
  const Vector2d p0(0, 0), p1(4, 0), c(1, 3);
  const CurveShape q = quadratic(c);
  CHECK(near(curve_point(p0, p1, q, 0.5), (p0 + 2 * c + p1) / 4));
  CHECK(near(curve_point(p0, p1, q, 0.25), 0.5625 * p0 + 0.375 * c + 0.0625 * p1));
  CHECK(curve_point(p0, p1, q, 0) == p0);
  CHECK(curve_point(p0, p1, q, 1) == p1);
  CHECK(curve_length(p0, p1, q) == Approx(quadratic_length(p0, c, p1)).epsilon(1e-12));
  CHECK(curve_length(p0, p1, q, 0, 0.3) + curve_length(p0, p1, q, 0.3, 1) == Approx(curve_length(p0, p1, q)).epsilon(1e-12));

  const Vector2d c0(0, 2), c1(5, -1);
  const CurveShape k = cubic(c0, c1);
  CHECK(near(curve_point(p0, p1, k, 0.5), (p0 + 3 * c0 + 3 * c1 + p1) / 8));
  CHECK(near(curve_point(p0, p1, k, 0.25), (27 * p0 + 27 * c0 + 9 * c1 + p1) / 64));
  CHECK(curve_length(p0, p1, k) == Approx(polyline_length(p0, p1, k, 200000)).epsilon(1e-9));
  // Control points on the chord at a third and two thirds: the straight segment, at constant speed.
  const CurveShape straight_cubic = cubic(Vector2d(4.0 / 3, 0), Vector2d(8.0 / 3, 0));
  CHECK(curve_length(p0, p1, straight_cubic) == Approx(4).epsilon(1e-13));
  // A cusp (the speed vanishes at u = 1/2): a curve that runs out and back along a line.
  const CurveShape cusp = cubic(Vector2d(0, 3), Vector2d(4, 3));
  CHECK(curve_length(p0, p1, cusp) == Approx(polyline_length(p0, p1, cusp, 200000)).epsilon(1e-9));

  CurveShape line;
  CHECK(curve_length(Vector2d(1, 2), Vector2d(4, 6), line) == Approx(5).epsilon(1e-15));
  CHECK(near(curve_point(Vector2d(1, 2), Vector2d(4, 6), line, 0.5), Vector2d(2.5, 4)));
}

TEST_CASE("circle arcs: [radius, large_arc, right] as GarmentCode and SVG read them", "[garment]") {
  // Chord from (0, 0) to (2, 0), radius 2: the centres are (1, +-sqrt 3); the small arc sweeps
  // pi / 3, the large one 5 pi / 3. A small arc with `right` bulges to the right of +x (down), its
  // centre above; GarmentCode's CircleEdge: right = control_y < 0, the arc's middle at relative
  // [0.5, control_y].
  const Vector2d a(0, 0), b(2, 0);
  const double r = 2, d = std::sqrt(3.0);
  struct Case {
    bool large_arc, right;
    Vector2d middle;
    double angle;
  };
  const Case cases[] = {{false, true, {1, -(r - d)}, pi / 3},
                        {false, false, {1, r - d}, pi / 3},
                        {true, true, {1, -(r + d)}, 5 * pi / 3},
                        {true, false, {1, r + d}, 5 * pi / 3}};
  for (const Case& c : cases) {
    INFO("large_arc " << c.large_arc << ", right " << c.right);
    const CurveShape arc = circle(r, c.large_arc, c.right);
    CHECK(near(curve_point(a, b, arc, 0.5), c.middle, 1e-12));
    CHECK(curve_length(a, b, arc) == Approx(r * c.angle).epsilon(1e-14));
    // A quarter of the way along lies a quarter of the angle round from the start, on the circle.
    const CircleArc centre_form = circle_arc(a, b, r, c.large_arc, c.right);
    CHECK(std::abs(centre_form.sweep) == Approx(c.angle));
    CHECK((curve_point(a, b, arc, 0.25) - centre_form.centre).norm() == Approx(r));
    CHECK((curve_point(a, b, arc, 0.25) - a).norm() == Approx(2 * r * std::sin(c.angle / 8)));
    // `right`: counter-clockwise round the centre.
    CHECK((centre_form.sweep > 0) == c.right);
    CHECK(near(curve_point(a, b, arc, 1), b));
  }
  // Radius at half the chord: the half circle, bulging right with `right`.
  CHECK(near(curve_point(a, b, circle(1, false, true), 0.5), Vector2d(1, -1), 1e-12));
  CHECK(curve_length(a, b, circle(1, false, false)) == Approx(pi));
  // Below half the chord: taken as the half circle, as SVG does.
  CHECK(near(curve_point(a, b, circle(0.5, false, false), 0.5), Vector2d(1, 1), 1e-12));
}

TEST_CASE("GarmentCode's own circle arcs: the hoody's necklines are centred on the body's centre line", "[garment]") {
  // The neckline edges of GarmentCode's hoody (assets/Patterns/hoody_mean_specification.json, cm):
  // the left front's from the neck point down to the centre front (x = 0), [radius, 0, 0], and the
  // left back's from the centre back up to the neck point, [radius, 0, 1]. Read as drape reads them,
  // both circles are centred on x = 0, so the left and right halves make one smooth neckline; with
  // either flag misread the centres land near x = 10.8, the neck point's x.
  const CircleArc front = circle_arc(Vector2d(10.818799999999998, 49.963062523006585), Vector2d(0.0, 34.31450269441045),
                                     11.564126734773824, false, false);
  CHECK(std::abs(front.centre.x()) < 0.01);
  CHECK(front.centre.y() == Approx(34.31450269441045 + 11.564126734773824));  // straight above the centre front
  const CircleArc back = circle_arc(Vector2d(0.0, 44.26956007084882), Vector2d(10.8188, 49.91845847814037),
                                    13.184560591816423, false, true);
  CHECK(std::abs(back.centre.x()) < 0.01);
  CHECK(back.centre.y() == Approx(44.26956007084882 + 13.184560591816423));
  // The front neckline dips into the panel: its middle lies to +x of its chord's middle.
  CHECK(curve_point(Vector2d(10.818799999999998, 49.963062523006585), Vector2d(0.0, 34.31450269441045),
                    circle(11.564126734773824, false, false), 0.5)
            .x() > 5.41);
}

TEST_CASE("points at equal arc length along a curve", "[garment]") {
  const Vector2d a(0, 0), b(1, 0);
  for (const CurveShape& shape : {quadratic(Vector2d(0.05, 0.8)), cubic(Vector2d(0, 0.5), Vector2d(0.9, -0.3)),
                                  circle(0.7, true, false), CurveShape{}}) {
    const int n = 13;
    const std::vector<double> u = equal_length_parameters(a, b, shape, n);
    REQUIRE(u.size() == std::size_t(n) + 1);
    CHECK(u.front() == 0);
    CHECK(u.back() == 1);
    const double total = curve_length(a, b, shape);
    for (int k = 0; k < n; ++k) CHECK(curve_length(a, b, shape, u[std::size_t(k)], u[std::size_t(k) + 1]) == Approx(total / n).epsilon(1e-9));
  }
}

TEST_CASE("Euler angles in degrees: about x, then y, then z (R = Rz Ry Rx)", "[garment]") {
  // GarmentCode's rotation.py: _Rz(z) * _Ry(y) * _Rx(x).
  const Eigen::Matrix3d rx = rotation_from_euler_degrees(Vector3d(90, 0, 0));
  CHECK(near(rx * Vector3d(0, 1, 0), Vector3d(0, 0, 1)));
  const Eigen::Matrix3d rz = rotation_from_euler_degrees(Vector3d(0, 0, 90));
  CHECK(near(rz * Vector3d(1, 0, 0), Vector3d(0, 1, 0)));
  // x first: y -> z (about x), then z -> x (about y). In the other order y would stay y, then go to z.
  const Eigen::Matrix3d rxy = rotation_from_euler_degrees(Vector3d(90, 90, 0));
  CHECK(near(rxy * Vector3d(0, 1, 0), Vector3d(1, 0, 0)));
  // A general one against the three matrices of rotation.py written out.
  const double x = 0.3, y = -1.1, z = 2.0;
  Eigen::Matrix3d mx, my, mz;
  mx << 1, 0, 0, 0, std::cos(x), -std::sin(x), 0, std::sin(x), std::cos(x);
  my << std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y);
  mz << std::cos(z), -std::sin(z), 0, std::sin(z), std::cos(z), 0, 0, 0, 1;
  const Eigen::Matrix3d r = rotation_from_euler_degrees(Vector3d(x, y, z) * 180 / pi);
  CHECK((r - mz * my * mx).cwiseAbs().maxCoeff() < 1e-14);

  PatternPanel panel;
  panel.rotation = rz;
  panel.translation = Vector3d(1, 2, 3);
  CHECK(near(panel_to_world(panel, Vector2d(1, 0)), Vector3d(1, 3, 3)));
}

TEST_CASE("validate() accepts a sound pattern and names each defect's place", "[garment]") {
  const SewingPattern good = front_and_back();
  CHECK(validation_error(good) == "");

  SewingPattern p;
  CHECK_THAT(validation_error(p), Contains("test: pattern.panels: the pattern has no panels"));

  p = good;
  p.panels[0].edges[2].end = 0;  // edge 2 ends at vertex 0, edge 3 starts at vertex 3
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front.edges[2].endpoints: the edge loop does not close: "
                                           "edge 2 ends at vertex 0 but edge 3 starts at vertex 3"));
  p = good;
  p.panels[1].edges[1].end = 7;
  CHECK_THAT(validation_error(p),
             Contains("pattern.panels.back.edges[1].endpoints[1]: vertex 7 out of range (panel back has 4 vertices)"));
  p = good;
  std::swap(p.panels[0].vertices[2], p.panels[0].vertices[3]);  // a bow tie: edges 1 and 3 cross
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front: the outline crosses itself: edge 1 meets edge 3"));
  p = good;
  p.panels[0].edges[0].curve = quadratic(Vector2d(0.2, 2.0));  // the hem bulges up through the neckline
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front: the outline crosses itself: edge 0 meets edge 2"));
  p = good;
  p.panels[0].edges[0].curve = cubic(Vector2d(0.6, -0.3), Vector2d(-0.2, -0.3));  // a loop in the hem
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front.edges[0]: the outline crosses itself: edge 0 meets itself"));
  p = good;
  p.panels[0].edges[1].curve = circle(0.1, false, true);  // chord 0.5
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front.edges[1].curvature.params[0]: radius 0.1 m is less "
                                           "than half the chord (0.25 m)"));
  p = good;
  p.panels[1].rotation(0, 0) = 2;
  CHECK_THAT(validation_error(p), Contains("pattern.panels.back.rotation: not a rotation"));
  p = good;
  p.panels[1].vertices[2].x() = std::nan("");
  CHECK_THAT(validation_error(p), Contains("pattern.panels.back.vertices[2]: the vertex is not finite"));
  p = good;
  p.panels[1].name = "front";
  CHECK_THAT(validation_error(p), Contains("pattern.panels.front: two panels are named front"));

  p = good;
  p.stitches[1].sides[1].edge = 9;
  CHECK_THAT(validation_error(p),
             Contains("pattern.stitches[1][1].edge: edge 9 out of range (panel back has 4 edges)"));
  p = good;
  p.stitches[0].sides[0].panel = 2;
  CHECK_THAT(validation_error(p), Contains("pattern.stitches[0][0].panel: panel 2 out of range (the pattern has 2 panels)"));
  p = good;
  p.stitches[1].sides[1] = {0, 1};  // already in stitch 0
  CHECK_THAT(validation_error(p), Contains("pattern.stitches[1][1]: edge 1 of panel front is also in stitch 0"));

  // Stitched edges 0.5 m against 0.75 m (ratio 1.5) are refused, against 0.65 m (1.3, like
  // GarmentCode's gathered pencil-dress waist) accepted.
  p = good;
  p.panels[1].vertices[1].y() = p.panels[1].vertices[2].y() = 0.75;
  CHECK_THAT(validation_error(p), Contains("pattern.stitches[0]: stitch 0 sews edges of very different lengths: 0.5 m "
                                           "(panel front edge 1) and 0.75 m (panel back edge 2), ratio 1.5 (allowed: "
                                           "at most 1.4)"));
  p.panels[1].vertices[1].y() = p.panels[1].vertices[2].y() = 0.65;
  CHECK(validation_error(p) == "");
  PatternCheckOptions strict;
  strict.max_stitch_length_ratio = 1.05;
  CHECK_THAT(validation_error(p, strict), Contains("ratio 1.3 (allowed: at most 1.05)"));
}

TEST_CASE("outlines: vertices kept, counter-clockwise, equal arc length, stitched counts equal", "[garment]") {
  SewingPattern pattern = front_and_back();
  // The back's sides shorter than the front's (0.48 m against 0.5 m); sewn together, both take the
  // larger count.
  pattern.panels[1].vertices[2].y() = 0.48;
  pattern.panels[1].vertices[1].y() = 0.48;
  REQUIRE(validation_error(pattern) == "");
  const double h = 0.045;
  const PatternOutlines outlines = sample_outlines(pattern, h);
  REQUIRE(outlines.panels.size() == 2);
  CHECK(outlines.panels[0].reversed == false);
  CHECK(outlines.panels[1].reversed == true);
  for (std::size_t p = 0; p < 2; ++p) {
    const PatternPanel& panel = pattern.panels[p];
    const PanelOutline& outline = outlines.panels[p];
    INFO(panel.name);
    CHECK(twice_signed_area(outline.points) > 0);
    int total = 0;
    for (std::size_t e = 0; e < panel.edges.size(); ++e) {
      const std::vector<int>& indices = outline.edge_points[e];
      const int n = outline.segments[e];
      total += n;
      REQUIRE(indices.size() == std::size_t(n) + 1);
      // Ends exactly at the edge's vertices; inner points at equal arc length.
      CHECK(outline.points[std::size_t(indices.front())] == panel.vertices[std::size_t(panel.edges[e].start)]);
      CHECK(outline.points[std::size_t(indices.back())] == panel.vertices[std::size_t(panel.edges[e].end)]);
      CHECK(outline.vertex_points[std::size_t(panel.edges[e].start)] == indices.front());
      const double length = edge_length(panel, int(e));
      const std::vector<double> u = edge_parameters(panel, int(e), n);
      for (int k = 0; k <= n; ++k)
        CHECK(near(outline.points[std::size_t(indices[std::size_t(k)])], edge_point(panel, int(e), u[std::size_t(k)])));
      // Chords of a curve at equal arc length are nearly equal; of a straight edge exactly length / n.
      if (panel.edges[e].curve.type == CurveType::Straight)
        CHECK((outline.points[std::size_t(indices[1])] - outline.points[std::size_t(indices[0])]).norm() ==
              Approx(length / n));
    }
    CHECK(int(outline.points.size()) == total);
  }
  // Unstitched edges: n = round(length / h); the front's bottom 0.4 m gives 9.
  CHECK(outlines.panels[0].segments[0] == 9);
  CHECK(outlines.panels[1].segments[1] == 9);
  // Stitch 0: front edge 1 (0.5 m: 11) with back edge 2 (0.48 m: 11); stitch 1: front edge 3
  // (0.5 m: 11) with back edge 0 (0.48 m: 11). Shorter h separates them: at 0.0195, 26 and 25 -> 26.
  const PatternOutlines fine = sample_outlines(pattern, 0.0195);
  CHECK(std::lround(0.48 / 0.0195) == 25);
  CHECK(fine.panels[0].segments[1] == 26);
  CHECK(fine.panels[1].segments[2] == 26);
  CHECK(fine.panels[1].segments[0] == 26);
  // The front's neckline is the quadratic curve, its points equally spaced along it.
  const std::vector<int>& neck = fine.panels[0].edge_points[2];
  const double neck_length = edge_length(pattern.panels[0], 2);
  for (std::size_t k = 0; k + 1 < neck.size(); ++k) {
    const Vector2d chord = fine.panels[0].points[std::size_t(neck[k + 1])] - fine.panels[0].points[std::size_t(neck[k])];
    CHECK(chord.norm() == Approx(neck_length / double(neck.size() - 1)).epsilon(1e-3));
  }
  CHECK_THROWS_AS(sample_outlines(pattern, 0.0), InvalidParameter);
  CHECK_THROWS_AS(sample_outlines(pattern, 1e-9), InvalidParameter);
}

TEST_CASE("stitch pairs: the first edge's end meets the second's start; right_wrong pairs starts", "[garment]") {
  SewingPattern pattern = front_and_back();
  const PatternOutlines outlines = sample_outlines(pattern, 0.05);
  for (int s = 0; s < 2; ++s) {
    INFO("stitch " << s);
    const Stitch& stitch = pattern.stitches[std::size_t(s)];
    const PatternPanel& a = pattern.panels[std::size_t(stitch.sides[0].panel)];
    const PatternPanel& b = pattern.panels[std::size_t(stitch.sides[1].panel)];
    const std::vector<std::pair<int, int>> pairs = stitch_point_pairs(pattern, outlines, s);
    REQUIRE(pairs.size() == 11);
    const PatternEdge& ea = a.edges[std::size_t(stitch.sides[0].edge)];
    const PatternEdge& eb = b.edges[std::size_t(stitch.sides[1].edge)];
    const PanelOutline& oa = outlines.panels[std::size_t(stitch.sides[0].panel)];
    const PanelOutline& ob = outlines.panels[std::size_t(stitch.sides[1].panel)];
    // First pair: a's end vertex with b's start vertex; last: a's start with b's end.
    CHECK(oa.points[std::size_t(pairs.front().first)] == a.vertices[std::size_t(ea.end)]);
    CHECK(ob.points[std::size_t(pairs.front().second)] == b.vertices[std::size_t(eb.start)]);
    CHECK(oa.points[std::size_t(pairs.back().first)] == a.vertices[std::size_t(ea.start)]);
    CHECK(ob.points[std::size_t(pairs.back().second)] == b.vertices[std::size_t(eb.end)]);
    // Placed, the paired points lie straight across the gap between front and back (0.2 m).
    for (const auto& [i, j] : pairs) {
      const Vector3d pa = panel_to_world(a, oa.points[std::size_t(i)]), pb = panel_to_world(b, ob.points[std::size_t(j)]);
      CHECK((pa - pb).norm() == Approx(0.2).epsilon(1e-12));
    }
  }
  // Outward normals: the front's loop runs counter-clockwise (+z), the back's clockwise (-z).
  CHECK(near(outward_normal(pattern, outlines, 0), Vector3d(0, 0, 1)));
  CHECK(near(outward_normal(pattern, outlines, 1), Vector3d(0, 0, -1)));

  pattern.stitches[0].right_wrong = true;
  const std::vector<std::pair<int, int>> pairs = stitch_point_pairs(pattern, outlines, 0);
  const PatternEdge& ea = pattern.panels[0].edges[1];
  CHECK(outlines.panels[0].points[std::size_t(pairs.front().first)] == pattern.panels[0].vertices[std::size_t(ea.start)]);
  CHECK(outlines.panels[0].points[std::size_t(pairs.back().first)] == pattern.panels[0].vertices[std::size_t(ea.end)]);
}
