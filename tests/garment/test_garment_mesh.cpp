// A garment's cloth mesh from its pattern (garment/garment_mesh.hpp): GarmentCode's T-shirt meshed
// whole (a valid mesh, panels rigidly placed, outward faces, every seam pair on two panels' outlines
// at the stitch's ends), and two flat panels sewn edge to edge by seam springs in the implicit step
// closing into one flat sheet, float and double.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <set>
#include <string>

#include "drape/garment/garment_mesh.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"
#include "drape/physics/seam_springs.hpp"
#include "garment/mesh_in_scalar.hpp"

using namespace drape;

namespace {

const std::string shirt_path = std::string(DRAPE_SOURCE_DIR) + "/scenes/garments/shirt_mean.json";

double triangle_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Two 40 x 30 cm rectangles in the plane z = 0, 6 cm apart along x, their facing edges stitched
/// (the first's right edge, bottom to top, meets the second's left edge, top to bottom: GarmentCode's
/// default, the end of one at the start of the other).
SewingPattern two_rectangles() {
  SewingPattern p;
  for (int k = 0; k < 2; ++k) {
    PatternPanel panel;
    panel.name = k == 0 ? "left" : "right";
    panel.vertices = {{0, 0}, {0.4, 0}, {0.4, 0.3}, {0, 0.3}};
    for (int e = 0; e < 4; ++e) panel.edges.push_back(PatternEdge{e, (e + 1) % 4, {}});
    panel.translation = Eigen::Vector3d(k == 0 ? 0.0 : 0.46, 0, 0);
    panel.rotation = Eigen::Matrix3d::Identity();
    p.panels.push_back(panel);
  }
  // Edge 1 of the left runs (0.4, 0) -> (0.4, 0.3); edge 3 of the right runs (0, 0.3) -> (0, 0).
  Stitch s;
  s.sides[0] = StitchSide{0, 1};
  s.sides[1] = StitchSide{1, 3};
  p.stitches.push_back(s);
  validate(p);
  return p;
}

}  // namespace

TEST_CASE("the T-shirt meshed whole: one valid mesh, panels placed rigidly, faces outward, seams on outlines",
          "[garment][mesh]") {
  const SewingPattern shirt = pattern_io::read_sewing_pattern(shirt_path);
  for (const double h : {0.01, 0.015, 0.02}) {
    INFO("edge length " << h);
    const GarmentMesh g = garment_mesh(shirt, h);
    const ClothMesh<double>& m = g.mesh;
    REQUIRE_NOTHROW(m.validate("garment"));
    REQUIRE(g.panel_begin.size() == shirt.panels.size() + 1);
    REQUIRE(g.panel_begin.back() == m.positions.cols());
    const PatternOutlines outlines = sample_outlines(shirt, h);
    // Rigid placement: every triangle's area in 3D is its area in the pattern.
    double worst = 0;
    for (const auto& t : m.triangles) {
      const auto lift = [&](int i) { return Eigen::Vector3d(m.rest_uv(0, i), m.rest_uv(1, i), 0); };
      const double rest = triangle_area(lift(t[0]), lift(t[1]), lift(t[2]));
      const double placed = triangle_area(m.positions.col(t[0]), m.positions.col(t[1]), m.positions.col(t[2]));
      worst = std::max(worst, std::abs(placed - rest) / rest);
    }
    CHECK(worst < 1e-9);
    for (std::size_t k = 0; k < shirt.panels.size(); ++k) {
      INFO("panel " << shirt.panels[k].name);
      // Faces outward: the area-weighted normal of the panel's triangles along outward_normal().
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      for (const auto& t : m.triangles)
        if (t[0] >= g.panel_begin[k] && t[0] < g.panel_begin[k + 1])
          normal += (m.positions.col(t[1]) - m.positions.col(t[0])).cross(m.positions.col(t[2]) - m.positions.col(t[0]));
      CHECK(normal.normalized().dot(outward_normal(shirt, outlines, int(k))) > 0.999);
      CHECK(m.groups.at("panel " + shirt.panels[k].name).size() == std::size_t(g.panel_begin[k + 1] - g.panel_begin[k]));
    }
    // Seams: each pair joins outline points of the stitch's two panels, the stitch's ends to its ends.
    std::size_t expected = 0;
    for (std::size_t s = 0; s < shirt.stitches.size(); ++s)
      expected += outlines.panels[std::size_t(shirt.stitches[s].sides[0].panel)]
                      .edge_points[std::size_t(shirt.stitches[s].sides[0].edge)]
                      .size();
    REQUIRE(g.seam_pairs.size() == expected);
    for (std::size_t p = 0; p < g.seam_pairs.size(); ++p) {
      const Stitch& s = shirt.stitches[std::size_t(g.seam_stitch[p])];
      for (int side = 0; side < 2; ++side) {
        const int panel = s.sides[std::size_t(side)].panel, v = g.seam_pairs[p][std::size_t(side)];
        REQUIRE(v >= g.panel_begin[std::size_t(panel)]);
        REQUIRE(v < g.panel_begin[std::size_t(panel)] + int(outlines.panels[std::size_t(panel)].points.size()));
      }
    }
  }
}

TEMPLATE_TEST_CASE("two flat panels sewn edge to edge become one flat sheet", "[garment][seams]", float, double) {
  using S = TestType;
  const SewingPattern pattern = two_rectangles();
  const GarmentMesh g = garment_mesh(pattern, 0.03);
  ClothSpec<S> spec;
  spec.mesh = drape::test::in_scalar<S>(g.mesh);
  spec.pinned_nodes = std::vector<int>{};
  spec.gravity = 0;
  spec.areal_density = S(0.2);
  spec.springs = {{S(300), S(0.3)}, {S(0), S(0)}, {S(5), S(0.01)}};
  const Matrix3X<S> start = spec.mesh->positions;
  auto seams = std::make_shared<SeamSprings<S>>(g.seam_pairs, start, S(200), S(0.2), S(0.5));
  spec.force_terms = {seams};
  const Cloth<S> cloth(spec);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  ImplicitEuler<S> integrator(cloth, options);
  State<S> s = cloth.initial_state();
  while (s.time < S(2)) REQUIRE(integrator.step(s).ok());
  // Closed: every pair within half a millimetre; one sheet 80 cm wide, still in its plane.
  CHECK(seams->widest_gap(s.positions) < S(5e-4));
  const S width = s.positions.row(0).maxCoeff() - s.positions.row(0).minCoeff();
  CHECK(width == Approx(0.8).margin(0.005));
  CHECK(s.positions.row(2).cwiseAbs().maxCoeff() < S(1e-5));
  // Every seam point where the pattern puts it, 0.4 m from the left edge, up the seam's line.
  for (const auto& [a, b] : g.seam_pairs) {
    CHECK(std::abs(double(s.positions(1, a) - s.positions(1, b))) < 5e-4);
    CHECK(std::abs(double(s.positions(0, a) - s.positions.row(0).minCoeff()) - 0.4) < 0.005);
  }
}
