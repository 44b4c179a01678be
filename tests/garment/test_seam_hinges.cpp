// Hinges across a garment's seams (garment/seam_hinges.hpp): on GarmentCode's T-shirt every segment
// of a stitch is a boundary edge on both sides and gets its two hinges, wired and weighted as the
// convention asks; the term of a sewn pair of panels against finite differences; and a strip of two
// panels sewn end to end, clamped as a cantilever, sags like the strip cut in one piece, while
// without the seam hinges it folds at the seam (float and double).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include "drape/garment/garment.hpp"
#include "drape/garment/seam_hinges.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"
#include "physics/dihedral_checks.hpp"
#include "garment/mesh_in_scalar.hpp"

using namespace drape;
using namespace drape::test::dihedral;

namespace {

const std::string shirt_path = std::string(DRAPE_SOURCE_DIR) + "/scenes/garments/shirt_mean.json";

double area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d e = b - a, f = c - a;
  return 0.5 * std::abs(e.x() * f.y() - e.y() * f.x());
}

/// A strip `length` x `width` cut into `pieces` equal rectangles sewn end to end, lying flat in the
/// x-z plane from x = 0 (the pattern turned 90 degrees about x), each seam already closed. Stitch k
/// sews the right edge of piece k (bottom to top) to the left edge of piece k + 1 (top to bottom).
SewingPattern sewn_strip(int pieces, double length, double width) {
  SewingPattern p;
  const double piece = length / pieces;
  for (int k = 0; k < pieces; ++k) {
    PatternPanel panel;
    panel.name = "piece " + std::to_string(k);
    panel.vertices = {{0, 0}, {piece, 0}, {piece, width}, {0, width}};
    for (int e = 0; e < 4; ++e) panel.edges.push_back(PatternEdge{e, (e + 1) % 4, {}});
    panel.translation = Eigen::Vector3d(k * piece, 0, 0);
    panel.rotation = rotation_from_euler_degrees(Eigen::Vector3d(90, 0, 0));
    p.panels.push_back(panel);
  }
  for (int k = 0; k + 1 < pieces; ++k) {
    Stitch s;
    s.sides[0] = StitchSide{k, 1};
    s.sides[1] = StitchSide{k + 1, 3};
    p.stitches.push_back(s);
  }
  validate(p);
  return p;
}

/// The term in Scalar, hinge for hinge.
template <class S>
std::shared_ptr<DihedralBending<S>> in_scalar(const DihedralBending<double>& term) {
  std::vector<typename DihedralBending<S>::HingeConstants> constants;
  for (std::size_t k = 0; k < term.hinges().size(); ++k)
    constants.push_back({S(term.hinge_stiffness(int(k))), S(term.hinge_damping(int(k))), S(term.rest_angle(int(k)))});
  return std::make_shared<DihedralBending<S>>(term.node_count(), term.hinges(), constants);
}

}  // namespace

TEST_CASE("seam hinges of the T-shirt: two per segment of every stitch, on each side's edge, flat at rest",
          "[garment][seam hinges]") {
  const SewingPattern shirt = pattern_io::read_sewing_pattern(shirt_path);
  const double k = 2e-5, c = 3e-7;
  for (const double h : {0.01, 0.015, 0.02}) {
    INFO("edge length " << h);
    const GarmentMesh g = garment_mesh(shirt, h);
    const ClothMesh<double>& m = g.mesh;
    const SeamHinges seam = seam_hinges(g, k, c);
    // Every pair of consecutive points of one stitch is a boundary edge on both sides: nothing skipped.
    int segments = 0;
    for (std::size_t i = 0; i + 1 < g.seam_pairs.size(); ++i) segments += g.seam_stitch[i] == g.seam_stitch[i + 1];
    CHECK(seam.skipped_segments == 0);
    REQUIRE(seam.hinges.size() == 2 * std::size_t(segments));
    REQUIRE(seam.constants.size() == seam.hinges.size());
    const auto panel_of = [&](int v) {
      return int(std::upper_bound(g.panel_begin.begin(), g.panel_begin.end(), v) - g.panel_begin.begin()) - 1;
    };
    std::map<int, std::set<int>> partners;
    for (const auto& [p, q] : g.seam_pairs) {
      partners[p].insert(q);
      partners[q].insert(p);
    }
    // Each triangle by its corners in order, and the triangles of every vertex.
    std::set<std::array<int, 3>> runs;
    std::map<int, std::vector<std::array<int, 3>>> around;
    for (const auto& t : m.triangles) {
      for (std::size_t r = 0; r < 3; ++r) runs.insert({t[r], t[(r + 1) % 3], t[(r + 2) % 3]});
      for (int v : t) around[v].push_back(t);
    }
    const auto uv = [&](int v) { return Eigen::Vector2d(m.rest_uv.col(v)); };
    int wrong_wiring = 0, wrong_constants = 0;
    for (std::size_t n = 0; n < seam.hinges.size(); ++n) {
      const Hinge& e = seam.hinges[n];
      // Edge and c on one panel, as triangle (a, b, c) runs them; d on the other panel, in a triangle
      // with the partners of a and b.
      const int pa = panel_of(e.a);
      bool ok = panel_of(e.b) == pa && panel_of(e.c) == pa && panel_of(e.d) != pa && runs.count({e.a, e.b, e.c}) == 1;
      std::array<int, 3> other{-1, -1, -1};
      for (const auto& t : around[e.d]) {
        int hits = 0;
        for (int v : t) hits += int(partners[e.a].count(v) + partners[e.b].count(v));
        if (hits == 2) other = t;
      }
      ok = ok && other[0] >= 0;
      wrong_wiring += !ok;
      if (!ok) continue;
      // k_e = (k / 2) 3 |e|^2 / (A1 + A2) from the rest triangles on both sides, the rest angle 0.
      const double a1 = area(uv(e.a), uv(e.b), uv(e.c)), a2 = area(uv(other[0]), uv(other[1]), uv(other[2]));
      const double expected = 0.5 * k * 3 * (uv(e.b) - uv(e.a)).squaredNorm() / (a1 + a2);
      const DihedralBending<double>::HingeConstants& got = seam.constants[n];
      wrong_constants += std::abs(got.stiffness - expected) > 1e-12 * expected ||
                         std::abs(got.damping - expected * c / k) > 1e-12 * expected * c / k || got.rest_angle != 0;
    }
    CHECK(wrong_wiring == 0);
    CHECK(wrong_constants == 0);
    // The two hinges of a segment sit on different panels' edges, each the other's wing tip.
    for (std::size_t n = 0; n < seam.hinges.size(); n += 2) {
      const Hinge &p = seam.hinges[n], &q = seam.hinges[n + 1];
      CHECK((p.c == q.d && p.d == q.c));
    }
  }
}

TEMPLATE_TEST_CASE("seam hinges of a sewn pair of panels: force and Jacobians against finite differences",
                   "[garment][seam hinges][jacobian]", float, double) {
  using S = TestType;
  const bool is_float = std::is_same<S, float>::value;
  const S step = is_float ? S(3e-4) : S(1e-6);
  const double tolerance = is_float ? 2e-3 : 1e-7;
  const GarmentMesh g = garment_mesh(sewn_strip(2, 0.12, 0.06), 0.03);
  const SeamHinges seam = seam_hinges(g, 0.02, 0.003);
  REQUIRE(seam.hinges.size() == 4);  // two segments of the one seam
  const std::shared_ptr<DihedralBending<S>> term =
      in_scalar<S>(DihedralBending<double>(int(g.mesh.positions.cols()), seam.hinges, seam.constants));
  const int n = term->node_count();
  const Matrix3X<S> flat = g.mesh.positions.cast<S>();
  const Matrix3X<S> still = Matrix3X<S>::Zero(3, n);
  // The second piece folded down by 0.6 rad about the seam (x = 0.06), everything jittered by 3 mm
  // (the seam a little open).
  Matrix3X<S> x = flat;
  for (Index v = 0; v < n; ++v)
    if (v >= g.panel_begin[1]) {
      const double r = double(flat(0, v)) - 0.06;
      x(0, v) = S(0.06 + r * std::cos(0.6));
      x(1, v) = S(-r * std::sin(0.6));
    }
  x = jittered(x, 0.003, 1);
  const Matrix3X<S> v = jittered<S>(still, 2.0, 2);
  Matrix3X<S> grad(3, n);
  for (Index k = 0; k < x.size(); ++k) {
    Matrix3X<S> xp = x, xm = x;
    xp.data()[k] += step;
    xm.data()[k] -= step;
    grad.data()[k] = S((double(term->energy(xp)) - double(term->energy(xm))) / (2 * double(step)));
  }
  const Dense f = dense(force_of(*term, x, still));
  CHECK(f.cwiseAbs().maxCoeff() > 1e-2);
  // Flat with the seam closed, the seam's rest shape: no force (to the round-off of the placement's
  // 90 degree turn).
  CHECK(dense(force_of(*term, flat, still)).cwiseAbs().maxCoeff() <
        (is_float ? 1e-5 : 1e-12) * f.cwiseAbs().maxCoeff());
  CHECK(double(term->energy(flat)) < 1e-12 * double(term->energy(x)));
  CHECK(relative_error(f, -dense(grad)) < tolerance);
  Recorder<S> exact(*term, n, false);
  term->add_derivatives(x, v, S(0), exact);
  CHECK(exact.undeclared == 0);
  CHECK(relative_error(dense_matrix(exact.dfdx), fd_jacobian(*term, x, v, true, step)) < tolerance);
  CHECK(relative_error(dense_matrix(exact.dfdv), fd_jacobian(*term, x, v, false, step)) < tolerance);
}

namespace {

/// A fabric stiff enough to hold a 20 cm cantilever up: cotton's weight (0.22 kg/m^2) with the
/// bending rigidity 0.01 N m (an Euler-Bernoulli beam of it sinks 43 mm at 20 cm).
Fabric stiff_fabric() {
  Fabric f = fabric_preset("cotton");
  f.bending_rigidity = 0.01;
  f.bending_damping = fabric_bending_damping_time * hinge_stiffness(f);
  return f;
}

/// The mean height of the free end (x = 0.24 m) of a 0.24 x 0.06 m strip of `pieces` panels sewn
/// end to end (dress_garment(), the seams closed from the start), clamped along x <= 0.04 m and
/// settled under gravity for 3 s by implicit steps; without `seam_bending` the garment's seam
/// hinges are left out. In float the garment's terms are rebuilt in float.
template <class S>
double settled_tip(int pieces, bool seam_bending) {
  const double length = 0.24, clamp = 0.04;
  SewingSettings sewing;
  sewing.edge_length = 0.015;
  sewing.seam_closing_time = 0;
  const Garment g = dress_garment(sewn_strip(pieces, length, 0.06), stiff_fabric(), sewing);
  std::vector<std::shared_ptr<const ForceTerm<double>>> terms = g.spec.force_terms;
  if (!seam_bending) terms.erase(std::remove(terms.begin(), terms.end(), g.seam_bending), terms.end());
  ClothSpec<S> spec;
  if constexpr (std::is_same<S, double>::value) {
    spec = g.spec;
    spec.force_terms = terms;
  } else {
    spec.mesh = drape::test::in_scalar<S>(g.pieces.mesh);
    spec.areal_density = S(*g.spec.areal_density);
    spec.gravity = 0;
    const auto& sp = g.spec.springs;
    spec.springs = {{S(sp.structural.stiffness), S(sp.structural.damping)}, {0, 0}, {0, 0}};
    for (const auto& term : terms) {
      if (const auto* bending = dynamic_cast<const DihedralBending<double>*>(term.get()))
        spec.force_terms.push_back(in_scalar<S>(*bending));
      else if (dynamic_cast<const SeamSprings<double>*>(term.get()))
        spec.force_terms.push_back(std::make_shared<SeamSprings<S>>(g.pieces.seam_pairs, spec.mesh->positions,
                                                                    S(sewing.seam_stiffness), S(sewing.seam_damping),
                                                                    S(sewing.seam_closing_time)));
      else
        spec.force_terms.push_back(std::make_shared<RampedGravity<S>>(
            (spec.mesh->vertex_areas() * *spec.areal_density).eval(), S(sewing.gravity), S(sewing.seam_closing_time),
            S(sewing.gravity_ramp)));
    }
    REQUIRE(spec.force_terms.size() == terms.size());
  }
  // One layer that never meets itself: self-collision off keeps the test short.
  spec.self_collision.enabled = false;
  const Matrix3X<double>& start = g.pieces.mesh.positions;
  std::vector<int> clamped;
  for (Index v = 0; v < start.cols(); ++v)
    if (start(0, v) <= clamp + 1e-9) clamped.push_back(int(v));
  spec.pinned_nodes = clamped;
  const Cloth<S> cloth(spec);
  ImplicitOptions options;
  options.dt = 0.01;
  options.threads = 1;
  ImplicitEuler<S> implicit(cloth, options);
  State<S> s = cloth.initial_state();
  while (s.time < S(3)) REQUIRE(implicit.step(s).ok());
  REQUIRE(s.positions.allFinite());
  // The seams stay closed: the hinges bend the strip, not a gap.
  CHECK(g.seams->widest_gap(s.positions.template cast<double>().eval()) < 1e-3);
  double sum = 0;
  int count = 0;
  for (Index v = 0; v < start.cols(); ++v)
    if (start(0, v) >= length - 1e-9) {
      sum += double(s.positions(1, v));
      ++count;
    }
  REQUIRE(count >= 4);
  return sum / count;
}

}  // namespace

TEMPLATE_TEST_CASE("a strip sewn from two panels sags like the strip in one piece; without seam hinges it folds",
                   "[garment][seam hinges][sag][long]", float, double) {
  using S = TestType;
  const double one_piece = settled_tip<S>(1, true), sewn = settled_tip<S>(2, true),
               without = settled_tip<S>(2, false);
  INFO("free end at y = " << one_piece << " (one piece), " << sewn << " (sewn), " << without
                          << " (sewn, no seam hinges)");
  CHECK(one_piece < -0.02);  // it sags ...
  CHECK(one_piece > -0.09);  // ... and bending carries the load
  CHECK(std::abs(sewn - one_piece) < 0.1 * std::abs(one_piece));
  // Without the hinges the outer panel hangs from the seam: the tip falls about its 12 cm further.
  CHECK(without < one_piece - 0.05);
}
