// The sewing-pattern reader (drape::pattern_io, docs/garments.md): GarmentCode's T-shirt read whole
// (panels, stitches, sizes, its panels placed around the body, its stitches pairing points that
// meet), the units and the older forms of the format, and every defect of a file refused with the
// file, the JSON path and what is wrong.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "drape/garment/outline_sampling.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"

namespace fs = std::filesystem;
using namespace drape;
using namespace drape::pattern_io;
using Catch::Matchers::Contains;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

const std::string shirt_path = std::string(DRAPE_SOURCE_DIR) + "/scenes/garments/shirt_mean.json";
const std::string body_path = std::string(DRAPE_SOURCE_DIR) + "/scenes/bodies/f_smpl_average_A40.obj";

// Two panels like a shirt's front and back (cm): the front's loop counter-clockwise, the back's
// clockwise; a quadratic neckline in front, a circle neckline and a cubic hem at the back; both
// sides sewn.
const std::string two_panels = R"({
  "pattern": {
    "panels": {
      "front": {
        "translation": [-20, 100, 10],
        "rotation": [0, 0, 0],
        "vertices": [[0, 0], [40, 0], [40, 50], [0, 50]],
        "edges": [
          {"endpoints": [0, 1]},
          {"endpoints": [1, 2]},
          {"endpoints": [2, 3], "curvature": {"type": "quadratic", "params": [[0.5, 0.2]]}},
          {"endpoints": [3, 0]}
        ]
      },
      "back": {
        "translation": [-20, 100, -10],
        "rotation": [0, 0, 0],
        "vertices": [[0, 0], [0, 50], [40, 50], [40, 0]],
        "edges": [
          {"endpoints": [0, 1]},
          {"endpoints": [1, 2], "curvature": {"type": "circle", "params": [30, 0, 1]}},
          {"endpoints": [2, 3]},
          {"endpoints": [3, 0], "curvature": {"type": "cubic", "params": [[0.3, 0.1], [0.7, 0.1]]}}
        ]
      }
    },
    "stitches": [
      [{"panel": "front", "edge": 1}, {"panel": "back", "edge": 2}],
      [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 0}]
    ]
  },
  "parameters": {},
  "properties": {"curvature_coords": "relative", "normalize_panel_translation": false,
                 "normalized_edge_loops": true, "units_in_meter": 100}
})";

/// `text` with the first `from` replaced by `to` (which must be there).
std::string with(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

/// The message parse_sewing_pattern() throws for `text`, empty if it reads it.
std::string error_of(const std::string& text, const PatternCheckOptions& options = {}) {
  try {
    (void)parse_sewing_pattern(text, "t.json", options);
  } catch (const PatternError& e) { return e.what(); }
  return "";
}

bool near(const Vector2d& a, const Vector2d& b, double eps = 1e-12) { return (a - b).norm() <= eps; }

double perimeter(const PatternPanel& panel) {
  double sum = 0;
  for (int e = 0; e < int(panel.edges.size()); ++e) sum += edge_length(panel, e);
  return sum;
}

}  // namespace

TEST_CASE("GarmentCode's T-shirt: 8 panels, 18 stitches, in metres", "[pattern_io]") {
  const SewingPattern shirt = read_sewing_pattern(shirt_path);
  REQUIRE(shirt.panels.size() == 8);
  REQUIRE(shirt.stitches.size() == 18);
  const std::vector<std::string> names = {"left_btorso", "left_ftorso",    "left_sleeve_f",  "left_sleeve_b",
                                          "right_ftorso", "right_sleeve_b", "right_sleeve_f", "right_btorso"};
  for (std::size_t p = 0; p < names.size(); ++p) CHECK(shirt.panels[p].name == names[p]);  // the file's order
  const PatternPanel& front = shirt.panels[1];
  REQUIRE(front.vertices.size() == 7);
  REQUIRE(front.edges.size() == 7);
  CHECK(near(front.vertices[1], Vector2d(0.28690530000000003, 0), 1e-15));  // [28.690530000000003, 0] cm
  CHECK((front.translation - Vector3d(0, 0.9457103829637592, 0.25)).norm() < 1e-12);
  CHECK(front.edges[3].curve.type == CurveType::Cubic);
  CHECK(front.edges[5].curve.type == CurveType::Quadratic);
  // The quadratic neckline [0.5, 0.3]: half-way along the chord, 0.3 chord lengths to its left.
  const Vector2d a = front.vertices[5], b = front.vertices[6], chord = b - a;
  CHECK(near(front.edges[5].curve.control[0], a + 0.5 * chord + 0.3 * Vector2d(-chord.y(), chord.x())));
  // Sleeves turned by -50.483 degrees about z (the left) and +50.483 (the right).
  const Eigen::Matrix3d turn = rotation_from_euler_degrees(Vector3d(0, 0, -50.48299999999997));
  CHECK((shirt.panels[2].rotation - turn).cwiseAbs().maxCoeff() < 1e-15);
  CHECK(shirt.panels[2].rotation(1, 0) < 0);
  // Outline lengths: a torso half 1.34-1.36 m round, a sleeve half 0.98 m.
  CHECK(perimeter(shirt.panels[0]) == Approx(1.342).margin(0.005));
  CHECK(perimeter(shirt.panels[1]) == Approx(1.356).margin(0.005));
  CHECK(perimeter(shirt.panels[2]) == Approx(0.984).margin(0.005));
  // Mirror images: left and right halves of the same length.
  CHECK(perimeter(shirt.panels[1]) == Approx(perimeter(shirt.panels[4])).epsilon(1e-12));
  CHECK(perimeter(shirt.panels[0]) == Approx(perimeter(shirt.panels[7])).epsilon(1e-12));
  // The front's centre seam with the other front: 0.3176 m both.
  CHECK(edge_length(shirt.panels[4], 0) == Approx(0.31758).margin(1e-5));
  CHECK(edge_length(shirt.panels[1], 6) == Approx(edge_length(shirt.panels[4], 0)).epsilon(1e-12));
}

TEST_CASE("the T-shirt's panels surround the body, their outward normals away from it", "[pattern_io]") {
  // The body (scenes/bodies): y up, feet at y = 0, 1.658 m tall, facing +z. Its chest and waist
  // (1.0 to 1.35 m up, within 0.2 m of the centre line) span z from -0.116 to 0.159 m.
  std::ifstream obj(body_path);
  REQUIRE(obj);
  double z_min = 1e9, z_max = -1e9;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream in(line.substr(2));
    double x = 0, y = 0, z = 0;
    in >> x >> y >> z;
    if (y > 1.0 && y < 1.35 && std::abs(x) < 0.2) {
      z_min = std::min(z_min, z);
      z_max = std::max(z_max, z);
    }
  }
  REQUIRE(z_max > z_min);

  const SewingPattern shirt = read_sewing_pattern(shirt_path);
  const PatternOutlines outlines = sample_outlines(shirt, 0.01);
  for (int p = 0; p < int(shirt.panels.size()); ++p) {
    const PatternPanel& panel = shirt.panels[std::size_t(p)];
    INFO(panel.name);
    Vector3d centre = Vector3d::Zero();
    for (const Vector2d& q : outlines.panels[std::size_t(p)].points) centre += panel_to_world(panel, q);
    centre /= double(outlines.panels[std::size_t(p)].points.size());
    const bool front = panel.name.find("ftorso") != std::string::npos || panel.name.find("sleeve_f") != std::string::npos;
    const bool left = panel.name.rfind("left", 0) == 0;
    // Fronts before the body, backs behind it, left halves on the body's left (+x), at chest height.
    if (front)
      CHECK(centre.z() > z_max);
    else
      CHECK(centre.z() < z_min);
    CHECK((centre.x() > 0) == left);
    CHECK(centre.y() > 1.0);
    CHECK(centre.y() < 1.35);
    // The loops of the back panels run clockwise in the file (GarmentCode orients every loop so
    // that its right-hand normal looks away from the body): the polygon is reversed for them.
    CHECK(outlines.panels[std::size_t(p)].reversed == !front);
    // Fronts face +z, backs -z, all away from the body's centre line.
    const Vector3d normal = outward_normal(shirt, outlines, p);
    CHECK(normal.z() * (front ? 1 : -1) > 0.99);
    const Vector3d away = centre - Vector3d(0, centre.y(), 0.5 * (z_min + z_max));
    CHECK(normal.dot(away.normalized()) > 0.3);
  }
}

TEST_CASE("the T-shirt sampled: vertices kept, stitched edges of equal counts, paired points that meet", "[pattern_io]") {
  const SewingPattern shirt = read_sewing_pattern(shirt_path);
  const double h = 0.01;
  const PatternOutlines outlines = sample_outlines(shirt, h);
  for (std::size_t p = 0; p < shirt.panels.size(); ++p) {
    const PatternPanel& panel = shirt.panels[p];
    const PanelOutline& outline = outlines.panels[p];
    INFO(panel.name);
    CHECK(twice_signed_area(outline.points) > 0);
    for (std::size_t v = 0; v < panel.vertices.size(); ++v)
      CHECK(outline.points[std::size_t(outline.vertex_points[v])] == panel.vertices[v]);
    for (std::size_t e = 0; e < panel.edges.size(); ++e) {
      const int n = outline.segments[e];
      const double length = edge_length(panel, int(e));
      CHECK(n >= std::max(1L, std::lround(length / h)));
      // Segments of equal arc length.
      const std::vector<int>& points = outline.edge_points[e];
      for (std::size_t k = 0; k + 1 < points.size(); ++k) {
        const double chord = (outline.points[std::size_t(points[k + 1])] - outline.points[std::size_t(points[k])]).norm();
        CHECK(chord <= length / n * (1 + 1e-9));
        CHECK(chord >= 0.98 * length / n);
      }
    }
  }
  // At h = 9.88 mm the side seam's edges (0.26229 and 0.26140 m) round to 27 and 26 segments; sewn
  // together, both take 27, and so for every stitch.
  const double odd_h = 0.00988;
  CHECK(std::lround(edge_length(shirt.panels[1], 1) / odd_h) == 27);
  CHECK(std::lround(edge_length(shirt.panels[0], 5) / odd_h) == 26);
  const PatternOutlines odd = sample_outlines(shirt, odd_h);
  CHECK(odd.panels[1].segments[1] == 27);
  CHECK(odd.panels[0].segments[5] == 27);
  for (const Stitch& stitch : shirt.stitches)
    CHECK(odd.panels[std::size_t(stitch.sides[0].panel)].segments[std::size_t(stitch.sides[0].edge)] ==
          odd.panels[std::size_t(stitch.sides[1].panel)].segments[std::size_t(stitch.sides[1].edge)]);

  int distinct = 0;
  for (int s = 0; s < int(shirt.stitches.size()); ++s) {
    INFO("stitch " << s);
    const Stitch& stitch = shirt.stitches[std::size_t(s)];
    const PatternPanel& a = shirt.panels[std::size_t(stitch.sides[0].panel)];
    const PatternPanel& b = shirt.panels[std::size_t(stitch.sides[1].panel)];
    const PanelOutline& oa = outlines.panels[std::size_t(stitch.sides[0].panel)];
    const PanelOutline& ob = outlines.panels[std::size_t(stitch.sides[1].panel)];
    CHECK(oa.segments[std::size_t(stitch.sides[0].edge)] == ob.segments[std::size_t(stitch.sides[1].edge)]);
    CHECK_FALSE(stitch.right_wrong);
    const std::vector<std::pair<int, int>> pairs = stitch_point_pairs(shirt, outlines, s);
    REQUIRE(pairs.size() == std::size_t(ob.segments[std::size_t(stitch.sides[1].edge)]) + 1);
    // Placed in 3D, the two edges run opposite ways (each panel's loop turns the same way seen from
    // outside, so a seam is walked once each way), and paired points are closer than under the
    // reversed pairing. Edges under a centimetre (the armhole corners) cannot tell the pairings
    // apart by distance across the gap of 0.2-0.45 m between the placed panels: their direction can.
    const auto world_a = [&](int i) { return panel_to_world(a, oa.points[std::size_t(i)]); };
    const auto world_b = [&](int i) { return panel_to_world(b, ob.points[std::size_t(i)]); };
    const Vector3d direction_a = world_a(pairs.front().first) - world_a(pairs.back().first);
    const Vector3d direction_b = world_b(pairs.back().second) - world_b(pairs.front().second);
    CHECK(direction_a.normalized().dot(direction_b.normalized()) < 0);  // a runs back along b
    double paired = 0, reversed = 0;
    const std::size_t n = pairs.size();
    for (std::size_t k = 0; k < n; ++k) {
      paired += (world_a(pairs[k].first) - world_b(pairs[k].second)).norm();
      reversed += (world_a(pairs[k].first) - world_b(pairs[n - 1 - k].second)).norm();
    }
    if (edge_length(b, stitch.sides[1].edge) > 0.02) {
      CHECK(paired < reversed);
      ++distinct;
    }
    // The centre seams join panels placed side by side: their paired points coincide.
    if (s >= 16) CHECK(paired / double(n) < 1e-12);
  }
  CHECK(distinct == 14);
}

TEST_CASE("units: properties.units_in_meter, 100 when absent", "[pattern_io]") {
  const SewingPattern cm = parse_sewing_pattern(two_panels, "t.json");
  CHECK(near(cm.panels[0].vertices[2], Vector2d(0.4, 0.5)));
  CHECK((cm.panels[0].translation - Vector3d(-0.2, 1.0, 0.1)).norm() < 1e-15);
  CHECK(cm.panels[1].edges[1].curve.radius == Approx(0.3));
  const SewingPattern mm = parse_sewing_pattern(with(two_panels, "\"units_in_meter\": 100", "\"units_in_meter\": 1000"), "t.json");
  CHECK(near(mm.panels[0].vertices[2], Vector2d(0.04, 0.05)));
  CHECK((mm.panels[0].translation - Vector3d(-0.02, 0.1, 0.01)).norm() < 1e-15);
  CHECK(mm.panels[1].edges[1].curve.radius == Approx(0.03));
  const std::string no_properties =
      with(two_panels, R"(  "properties": {"curvature_coords": "relative", "normalize_panel_translation": false,
                 "normalized_edge_loops": true, "units_in_meter": 100})",
           R"(  "comment": "no properties")");
  CHECK(near(parse_sewing_pattern(no_properties, "t.json").panels[0].vertices[2], Vector2d(0.4, 0.5)));
}

TEST_CASE("curvature in GarmentCode's older bare [t, s] form, right_wrong stitches, centred panels", "[pattern_io]") {
  const SewingPattern dict = parse_sewing_pattern(two_panels, "t.json");
  const SewingPattern bare = parse_sewing_pattern(
      with(two_panels, R"("curvature": {"type": "quadratic", "params": [[0.5, 0.2]]})", R"("curvature": [0.5, 0.2])"),
      "t.json");
  CHECK(bare.panels[0].edges[2].curve.type == CurveType::Quadratic);
  CHECK(near(bare.panels[0].edges[2].curve.control[0], dict.panels[0].edges[2].curve.control[0]));
  CHECK(near(dict.panels[0].edges[2].curve.control[0], Vector2d(0.2, 0.42)));  // 0.2 of 0.4 m to the left of -x: down

  const SewingPattern rw = parse_sewing_pattern(
      with(two_panels, R"({"panel": "back", "edge": 2}])", R"({"panel": "back", "edge": 2}, "right_wrong"])"), "t.json");
  CHECK(rw.stitches[0].right_wrong);
  CHECK_FALSE(rw.stitches[1].right_wrong);
  CHECK_FALSE(stitch_meets_reversed(rw.stitches[0]));

  // normalize_panel_translation: vertices about their mean, the mean (0.2, 0.25) added to x and y.
  const SewingPattern centred = parse_sewing_pattern(
      with(two_panels, "\"normalize_panel_translation\": false", "\"normalize_panel_translation\": true"), "t.json");
  CHECK(near(centred.panels[0].vertices[0], Vector2d(-0.2, -0.25)));
  CHECK((centred.panels[0].translation - Vector3d(0, 1.25, 0.1)).norm() < 1e-15);
  CHECK(near(centred.panels[0].edges[2].curve.control[0], Vector2d(0, 0.17)));
}

TEST_CASE("every defect of a pattern file is named by the file, the JSON path and what is wrong", "[pattern_io]") {
  REQUIRE(error_of(two_panels) == "");
  struct Bad {
    std::string from, to, message;
  };
  const std::vector<Bad> cases = {
      {R"("type": "quadratic")", R"("type": "spline")",
       R"(t.json: pattern.panels.front.edges[2].curvature.type: unknown curve type "spline" (allowed: quadratic, cubic, circle))"},
      {R"({"panel": "back", "edge": 2})", R"({"panel": "back", "edge": 12})",
       "t.json: pattern.stitches[0][1].edge: edge 12 out of range (panel back has 4 edges)"},
      {R"({"panel": "back", "edge": 0})", R"({"panel": "bakc", "edge": 0})",
       R"(t.json: pattern.stitches[1][1].panel: unknown panel "bakc" (the pattern's panels: front, back))"},
      {R"({"panel": "front", "edge": 3})", R"({"panel": "front", "edge": 1})",
       "t.json: pattern.stitches[1][0]: edge 1 of panel front is also in stitch 0: an edge is sewn once"},
      {R"({"endpoints": [3, 0]})", R"({"endpoints": [3, 1]})",
       "t.json: pattern.panels.front.edges[3].endpoints: the edge loop does not close: edge 3 ends at vertex 1 but edge 0 "
       "starts at vertex 0"},
      {R"({"endpoints": [1, 2]})", R"({"endpoints": [1, 9]})",
       "t.json: pattern.panels.front.edges[1].endpoints[1]: vertex 9 out of range (panel front has 4 vertices)"},
      {R"({"endpoints": [1, 2]})", R"({"endpoints": [1, -1]})",
       "t.json: pattern.panels.front.edges[1].endpoints[1]: vertex -1 out of range (panel front has 4 vertices)"},
      {R"({"endpoints": [1, 2]})", R"({"endpoints": [1, 2.5]})",
       "t.json: pattern.panels.front.edges[1].endpoints[1]: expected a vertex index (an integer), found a number 2.5"},
      {R"({"endpoints": [1, 2]})", R"({"endpoints": [1]})",
       "t.json: pattern.panels.front.edges[1].endpoints: expected two vertex indices [i, j], found an array of 1 element"},
      {"[[0, 0], [40, 0], [40, 50], [0, 50]]", "[[0, 0], [40, 0], [0, 50], [40, 50]]",
       "t.json: pattern.panels.front: the outline crosses itself: edge 1 meets edge 3 near (0.2, 0.25) m"},
      {"[[0.5, 0.2]]", "[[0.5, 3.0]]", "t.json: pattern.panels.front: the outline crosses itself: edge 0 meets edge 2"},
      {"[[0.5, 0.2]]", "[[0.5, 0.2], [0.6, 0.1]]",
       "t.json: pattern.panels.front.edges[2].curvature.params: 2 control points for a quadratic curve (allowed: 1, as "
       "[[t, s]])"},
      {"[[0.3, 0.1], [0.7, 0.1]]", "[[0.3, 0.1]]",
       "t.json: pattern.panels.back.edges[3].curvature.params: 1 control point for a cubic curve (allowed: 2"},
      {"[[0.3, 0.1], [0.7, 0.1]]", "[[0.3, 0.1], [0.7]]",
       "t.json: pattern.panels.back.edges[3].curvature.params[1]: expected a control point [t, s] (an array of 2 "
       "numbers), found an array of 1 element"},
      {"[30, 0, 1]", "[30, 0]",
       "t.json: pattern.panels.back.edges[1].curvature.params: 2 parameters for a circle arc (allowed: 3, as [radius, "
       "large_arc, right])"},
      {"[30, 0, 1]", "[30, 2, 1]",
       "t.json: pattern.panels.back.edges[1].curvature.params[1]: large_arc 2 (allowed: 0, 1, false or true)"},
      {"[30, 0, 1]", "[10, 0, 1]",
       "t.json: pattern.panels.back.edges[1].curvature.params[0]: radius 0.1 m is less than half the chord (0.2 m)"},
      {"[30, 0, 1]", "[-30, 0, 1]", "t.json: pattern.panels.back.edges[1].curvature.params[0]: radius -0.3 m (allowed:"},
      {R"("curvature": {"type": "circle", "params")", R"("curvature": {"kind": "circle", "params")",
       "t.json: pattern.panels.back.edges[1].curvature.type: missing (quadratic, cubic or circle)"},
      {"[[0, 0], [0, 50], [40, 50], [40, 0]]", "[[0, 0], [0, 75], [40, 75], [40, 0]]",
       "t.json: pattern.stitches[0]: stitch 0 sews edges of very different lengths: 0.5 m (panel front edge 1) and "
       "0.75 m (panel back edge 2), ratio 1.5 (allowed: at most 1.4)"},
      {R"("rotation": [0, 0, 0],)", "",
       "t.json: pattern.panels.front.rotation: missing (a panel has vertices, edges, translation and rotation)"},
      {R"("translation": [-20, 100, 10])", R"("translation": "up")",
       R"(t.json: pattern.panels.front.translation: expected the translation [x, y, z] (an array of 3 numbers), found a string "up")"},
      {R"("translation": [-20, 100, 10])", R"("translation": [-20, 100])",
       "t.json: pattern.panels.front.translation: expected the translation [x, y, z] (an array of 3 numbers), found an "
       "array of 2 elements"},
      {"[[0, 0], [40, 0], [40, 50], [0, 50]]", "[[0, 0], [40, null], [40, 50], [0, 50]]",
       "t.json: pattern.panels.front.vertices[1][1]: expected a vertex [x, y] (a number), found null"},
      {"[[0, 0], [40, 0], [40, 50], [0, 50]]", "[[0, 0], [4e7, 0], [40, 50], [0, 50]]",
       "t.json: pattern.panels.front.vertices[1]: the vertex (400000, 0) m is farther than 1000 m from the origin"},
      {"[[0, 0], [40, 0], [40, 50], [0, 50]]", "[[0, 0], [1e999, 0], [40, 50], [0, 50]]",
       "t.json: invalid JSON at line 7, column 31: number overflow parsing '1e999'"},
      {"[[0, 0], [40, 0], [40, 50], [0, 50]]", "[[0, 0], [NaN, 0], [40, 50], [0, 50]]",
       "t.json: invalid JSON at line 7, column 31: syntax error while parsing value - invalid literal"},
      {R"({"endpoints": [3, 0]}
        ])",
       R"({"endpoints": [3, 0]},
        ])",
       "t.json: invalid JSON at line 13, column 9: syntax error while parsing value"},
      {R"("stitches": [)", R"("stitches": [[{"panel": "front", "edge": 0}],)",
       "t.json: pattern.stitches[0]: expected a stitch"},
      {R"({"panel": "back", "edge": 2}])", R"({"panel": "back", "edge": 2}, "wrong_right"])",
       R"(t.json: pattern.stitches[0][2]: "wrong_right" (allowed: "right_wrong", or no third element))"},
      {R"({"panel": "front", "edge": 1})", R"({"panel": "front", "edge": "1"})",
       R"(t.json: pattern.stitches[0][0].edge: expected an edge index (an integer), found a string "1")"},
      {R"("stitches": [)", R"("stitches": {"a": 1}, "old": [)",
       "t.json: pattern.stitches: expected the stitches (a JSON array), found an object"},
      {"\"units_in_meter\": 100", "\"units_in_meter\": 0",
       "t.json: properties.units_in_meter: 0 units in a metre (allowed: > 0, e.g. 100 for centimetres)"},
      {R"("curvature_coords": "relative")", R"("curvature_coords": "absolute")",
       R"(t.json: properties.curvature_coords: "absolute" (allowed: "relative")"},
      {R"("normalized_edge_loops": true)", R"("normalized_edge_loops": false)",
       "t.json: properties.normalized_edge_loops: false (allowed: true;"},
      {R"("pattern": {)", R"("patterns": {)", "t.json: pattern: missing (the panels and stitches)"},
  };
  for (const Bad& bad : cases) {
    INFO(bad.from << " -> " << bad.to);
    CHECK_THAT(error_of(with(two_panels, bad.from, bad.to)), Contains(bad.message));
  }
  // An empty pattern, one panel of one edge, the top level not an object, nothing at all.
  const std::size_t panels_at = two_panels.find("\"panels\": {") + 11, stitches_at = two_panels.find("\"stitches\"");
  const std::string empty = two_panels.substr(0, panels_at) + "},\n    " + two_panels.substr(stitches_at);
  CHECK_THAT(error_of(empty), Contains("t.json: pattern.panels: the pattern has no panels"));
  CHECK_THAT(error_of("[1, 2]"), Contains("t.json: expected a sewing pattern (a JSON object at the top), found an array"));
  CHECK_THAT(error_of(""), Contains("t.json: invalid JSON at line 1, column 1"));
  CHECK_THAT(error_of(with(with(two_panels, R"(          {"endpoints": [1, 2]},
          {"endpoints": [2, 3], "curvature": {"type": "quadratic", "params": [[0.5, 0.2]]}},
          {"endpoints": [3, 0]})", ""), R"({"endpoints": [0, 1]},)", R"({"endpoints": [0, 1]})")),
             Contains("t.json: pattern.panels.front.edges: 1 edge: a panel's outline is a closed loop of at least 2 edges"));
}

TEST_CASE("files: a missing one, the shirt from disk, bounds on what a file may hold", "[pattern_io]") {
  const fs::path dir = fs::temp_directory_path() / "drape_test_pattern_io";
  fs::create_directories(dir);
  const std::string missing = (dir / "none.json").string();
  fs::remove(missing);
  try {
    (void)read_sewing_pattern(missing);
    FAIL("read a missing file");
  } catch (const PatternError& e) {
    CHECK(std::string(e.what()) == missing + ": cannot open the file (No such file or directory)");
    CHECK(e.source() == missing);
    CHECK(e.path().empty());
  }
  const std::string bad = (dir / "bad.json").string();
  std::ofstream(bad) << with(two_panels, R"("type": "quadratic")", R"("type": "spline")");
  try {
    (void)read_sewing_pattern(bad);
    FAIL("read a bad file");
  } catch (const PatternError& e) {
    CHECK(e.source() == bad);
    CHECK(e.path() == "pattern.panels.front.edges[2].curvature.type");
    CHECK(e.message() == R"(unknown curve type "spline" (allowed: quadratic, cubic, circle))");
  }
  fs::remove_all(dir);

  // More edges than a panel may have.
  std::string edges;
  for (int e = 0; e <= max_panel_edges; ++e) edges += std::string(e ? ", " : "") + R"({"endpoints": [0, 1]})";
  CHECK_THAT(error_of(with(two_panels, R"({"endpoints": [0, 1]},)", edges + ",")),
             Contains("t.json: pattern.panels.front.edges: 1004 edges (allowed: at most 1000 per panel"));
}
