// Dihedral-angle bending (physics/dihedral_bending.hpp) on irregular meshes: the angle of a known
// fold, the force as -dE/dx and both Jacobians against central finite differences (double and
// float), the symmetric variant's -k g g^T, equilibrium in a curved rest shape, momentum and
// torque, energy kept by a small explicit step and lost to damping, the same bits on 1 and 2
// threads, and a grid cloth bent through the implicit and symplectic integrators.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "drape/core/mesh_generators.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/physics/air_drag.hpp"
#include "drape/physics/dihedral_bending.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/platform/team.hpp"
#include "model/mesh_helpers.hpp"
#include "physics/dihedral_checks.hpp"
#include "support/dense.hpp"
#include "test_common.hpp"

using namespace drape;
using namespace drape::test::dihedral;

namespace {

/// An nx x ny patch of cells `spacing` apart in the x-y plane, every vertex jittered by up to a
/// quarter of the spacing, each cell split along a random diagonal, counter-clockwise seen from
/// +z. The part beyond x = fold_at is turned by `fold` (rad) about the line x = fold_at, z = 0, and
/// every vertex rises by `bulge` y^2 (a curved sheet). `pattern`: the rest shape is the flat jittered
/// patch (rest_uv), the positions the folded one; otherwise the folded shape is the rest shape.
template <class S>
ClothMesh<S> folded_patch(unsigned seed, double fold, double bulge = 0, bool pattern = false, int nx = 6, int ny = 5) {
  const double spacing = 0.1, fold_at = 0.5 * (nx - 1) * spacing;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25 * spacing, 0.25 * spacing);
  std::bernoulli_distribution flip(0.5);
  ClothMesh<S> mesh;
  mesh.positions.resize(3, nx * ny);
  Matrix2X<S> flat(2, nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = i * spacing + jitter(rng), y = j * spacing + jitter(rng);
      const double beyond = std::max(0.0, x - fold_at);
      flat.col(j * nx + i) << S(x), S(y);
      mesh.positions.col(j * nx + i) << S(std::min(x, fold_at) + beyond * std::cos(fold)), S(y),
          S(beyond * std::sin(fold) + bulge * y * y);
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
      if (flip(rng)) {
        mesh.triangles.push_back({v00, v10, v11});
        mesh.triangles.push_back({v00, v11, v01});
      } else {
        mesh.triangles.push_back({v00, v10, v01});
        mesh.triangles.push_back({v10, v11, v01});
      }
    }
  if (pattern) mesh.rest_uv = flat;
  return mesh;
}

/// -sum_e k_e g g^T: the symmetric variant's position blocks, from the term's own angle gradient.
template <class S>
Dense gauss_newton(const DihedralBending<S>& term, const Matrix3X<S>& x) {
  Dense out = Dense::Zero(x.size(), x.size());
  for (std::size_t k = 0; k < term.hinges().size(); ++k) {
    const Hinge& h = term.hinges()[k];
    const std::array<int, 4> node{h.a, h.b, h.c, h.d};
    S theta;
    std::array<Vec3<S>, 4> g;
    REQUIRE(DihedralBending<S>::angle_derivatives(x.col(h.a), x.col(h.b), x.col(h.c), x.col(h.d), theta, g));
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        out.block<3, 3>(3 * node[i], 3 * node[j]) -=
            double(term.hinge_stiffness(int(k))) * (g[i] * g[j].transpose()).template cast<double>();
  }
  return out;
}

/// (a, b, c, d) of a hinge with edge a = 0 -> b = (1, 0, 0) along x, c in the x-y plane on +y and
/// d turned by `fold` out of it about the edge, toward +z (the front of triangle (a, b, c)) for
/// fold > 0; then all four rotated and moved as one rigid body.
template <class S>
std::array<Vec3<S>, 4> folded_hinge(double fold, const Eigen::AngleAxis<double>& turn, const Eigen::Vector3d& shift) {
  const std::array<Eigen::Vector3d, 4> p{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                         Eigen::Vector3d(0.3, 0.8, 0),
                                         Eigen::Vector3d(0.6, -0.5 * std::cos(fold), 0.5 * std::sin(fold))};
  std::array<Vec3<S>, 4> out;
  for (std::size_t k = 0; k < 4; ++k) out[k] = (turn * p[k] + shift).template cast<S>();
  return out;
}

}  // namespace

TEST_CASE("dihedral bending: parameters and mesh are checked", "[bending]") {
  const ClothMesh<double> mesh = folded_patch<double>(1, 0.5);
  CHECK_THROWS_AS(DihedralBending<double>(mesh, -1.0, 0.0), InvalidParameter);
  CHECK_THROWS_WITH(DihedralBending<double>(mesh, -1.0, 0.0), Catch::Contains("'bending stiffness'"));
  CHECK_THROWS_WITH(DihedralBending<double>(mesh, std::nan(""), 0.0), Catch::Contains("'bending stiffness'"));
  CHECK_THROWS_WITH(DihedralBending<double>(mesh, 1.0, -0.5), Catch::Contains("'bending damping'"));
  CHECK_THROWS_WITH(DihedralBending<double>(mesh, 1.0, HUGE_VAL), Catch::Contains("'bending damping'"));
  ClothMesh<double> broken = mesh;
  broken.triangles[3][1] = 1000;
  CHECK_THROWS_WITH(DihedralBending<double>(broken, 1.0, 0.0), Catch::Contains("'mesh.triangles[3]'"));
  const DihedralBending<double> zero(mesh, 0.0, 0.0);
  CHECK_FALSE(zero.has_derivatives());
  const Matrix3X<double> x = jittered(mesh.positions, 0.03, 2);
  CHECK(force_of(zero, x, x).cwiseAbs().maxCoeff() == 0);
}

TEST_CASE("dihedral bending from explicit hinges: sizes, ids and constants are checked", "[bending][explicit]") {
  using Constants = DihedralBending<double>::HingeConstants;
  const std::vector<Hinge> hinges{{0, 1, 2, 3}, {1, 2, 0, 4}};
  const std::vector<Constants> constants{{0.1, 0.01, 0.0}, {0.2, 0.0, -0.5}};
  const DihedralBending<double> term(5, hinges, constants);
  CHECK(term.hinges().size() == 2);
  CHECK(term.has_derivatives());
  CHECK_FALSE(DihedralBending<double>(5, hinges, {{0, 0, 0}, {0, 0, 0}}).has_derivatives());
  CHECK(DihedralBending<double>(5, {}, {}).hinges().empty());
  CHECK(DihedralBending<double>(5, {}, {}).name() == "dihedral bending");
  CHECK(DihedralBending<double>(5, {}, {}, "seam hinges").name() == "seam hinges");
  CHECK_THROWS_WITH(DihedralBending<double>(0, {}, {}), Catch::Contains("'node count'"));
  CHECK_THROWS_WITH(DihedralBending<double>(5, hinges, {constants[0]}), Catch::Contains("'hinge constants'"));
  CHECK_THROWS_WITH(DihedralBending<double>(4, hinges, constants),
                    Catch::Contains("'hinges[1]'") && Catch::Contains("vertex id 4"));
  CHECK_THROWS_WITH(DihedralBending<double>(5, {{0, 1, 2, 3}, {1, 2, 1, 4}}, constants),
                    Catch::Contains("'hinges[1]'") && Catch::Contains("twice"));
  const auto with = [&](std::size_t k, Constants c) {
    std::vector<Constants> changed = constants;
    changed[k] = c;
    return changed;
  };
  CHECK_THROWS_WITH(DihedralBending<double>(5, hinges, with(1, {-0.1, 0, 0})),
                    Catch::Contains("'hinge constants[1].stiffness'"));
  CHECK_THROWS_WITH(DihedralBending<double>(5, hinges, with(0, {0.1, std::nan(""), 0})),
                    Catch::Contains("'hinge constants[0].damping'"));
  CHECK_THROWS_WITH(DihedralBending<double>(5, hinges, with(0, {0.1, 0, 3.5})),
                    Catch::Contains("'hinge constants[0].rest_angle'"));
  CHECK_THROWS_WITH(DihedralBending<double>(5, hinges, with(0, {0.1, 0, HUGE_VAL})),
                    Catch::Contains("'hinge constants[0].rest_angle'"));
  // A rest shape without a triangle has no constants.
  const Vec3<double> o(0, 0, 0), x(1, 0, 0), y(0, 1, 0);
  CHECK_THROWS_WITH(DihedralBending<double>::rest_constants(o, x, Vec3<double>(2, 0, 0), -y, 1.0, 0.0),
                    Catch::Contains("'hinge rest shape'"));
  CHECK_THROWS_WITH(DihedralBending<double>::rest_constants(o, o, y, -y, 1.0, 0.0),
                    Catch::Contains("'hinge rest shape'"));
  // A unit square split along its diagonal: k 3 |e|^2 / (A1 + A2) = 3 * 2 / 1, flat.
  const DihedralBending<double>::HingeConstants square =
      DihedralBending<double>::rest_constants(o, Vec3<double>(1, 1, 0), y, x, 0.5, 0.25);
  CHECK(square.stiffness == Approx(3.0).epsilon(1e-15));
  CHECK(square.damping == Approx(1.5).epsilon(1e-15));
  CHECK(square.rest_angle == 0);
}

TEMPLATE_TEST_CASE("dihedral bending from explicit hinges: the mesh's hinges and rest constants give its bits",
                   "[bending][explicit]", float, double) {
  using S = TestType;
  using Constants = typename DihedralBending<S>::HingeConstants;
  for (const bool pattern : {false, true}) {
    INFO((pattern ? "flat pattern" : "curved rest shape"));
    const ClothMesh<S> mesh = folded_patch<S>(11, 0.9, 1.2, pattern, 14, 12);  // several chunks and colours
    const DihedralBending<S> from_mesh(mesh, S(0.02), S(0.003));
    const Matrix3X<S> rest = mesh.rest_shape();
    std::vector<Hinge> hinges = mesh.hinges();
    std::vector<Constants> constants;
    for (const Hinge& h : hinges)
      constants.push_back(DihedralBending<S>::rest_constants(rest.col(h.a), rest.col(h.b), rest.col(h.c), rest.col(h.d),
                                                             S(0.02), S(0.003)));
    const DihedralBending<S> explicit_term(mesh.vertex_count(), hinges, constants);
    REQUIRE(from_mesh.hinges().size() > 2 * DihedralBending<S>::hinges_per_chunk);
    REQUIRE(from_mesh.colour_begin().size() > 2);
    // The same order, chunks and colours, and the same constants per hinge.
    REQUIRE(explicit_term.hinges().size() == from_mesh.hinges().size());
    for (std::size_t k = 0; k < hinges.size(); ++k) {
      const Hinge &p = explicit_term.hinges()[k], &q = from_mesh.hinges()[k];
      REQUIRE(std::array<int, 4>{p.a, p.b, p.c, p.d} == std::array<int, 4>{q.a, q.b, q.c, q.d});
      CHECK(explicit_term.hinge_stiffness(int(k)) == from_mesh.hinge_stiffness(int(k)));
      CHECK(explicit_term.hinge_damping(int(k)) == from_mesh.hinge_damping(int(k)));
      CHECK(explicit_term.rest_angle(int(k)) == from_mesh.rest_angle(int(k)));
    }
    CHECK(explicit_term.chunk_begin() == from_mesh.chunk_begin());
    CHECK(explicit_term.colour_begin() == from_mesh.colour_begin());
    const Matrix3X<S> x = jittered(mesh.positions, 0.02, 3);
    const Matrix3X<S> v = jittered<S>(Matrix3X<S>::Zero(3, x.cols()), 1.0, 4);
    CHECK(force_of(explicit_term, x, v) == force_of(from_mesh, x, v));
    Recorder<S> a(from_mesh, mesh.vertex_count(), false), b(explicit_term, mesh.vertex_count(), false);
    from_mesh.add_derivatives(x, v, S(0), a);
    explicit_term.add_derivatives(x, v, S(0), b);
    CHECK(a.dfdx == b.dfdx);
    CHECK(a.dfdv == b.dfdv);
    // Hinges given in another order: their constants follow them.
    std::vector<std::size_t> order(hinges.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), std::mt19937(5));
    std::vector<Hinge> shuffled_hinges;
    std::vector<Constants> shuffled_constants;
    for (std::size_t k : order) {
      shuffled_hinges.push_back(hinges[k]);
      shuffled_constants.push_back(constants[k]);
    }
    const DihedralBending<S> shuffled(mesh.vertex_count(), shuffled_hinges, shuffled_constants);
    const auto key = [](const Hinge& h) { return std::array<int, 4>{h.a, h.b, h.c, h.d}; };
    std::map<std::array<int, 4>, std::array<S, 3>> expected;
    for (std::size_t k = 0; k < hinges.size(); ++k)
      expected[key(hinges[k])] = {constants[k].stiffness, constants[k].damping, constants[k].rest_angle};
    int mismatched = 0;
    for (std::size_t k = 0; k < shuffled.hinges().size(); ++k) {
      const int q = int(k);
      const std::array<S, 3> got{shuffled.hinge_stiffness(q), shuffled.hinge_damping(q), shuffled.rest_angle(q)};
      mismatched += expected.at(key(shuffled.hinges()[k])) != got;
    }
    CHECK(mismatched == 0);
    const Dense f = dense(force_of(from_mesh, x, v));
    const double round_off = std::is_same<S, float>::value ? 1e-5 : 1e-13;
    CHECK((dense(force_of(shuffled, x, v)) - f).cwiseAbs().maxCoeff() <= round_off * f.cwiseAbs().maxCoeff());
  }
}

TEMPLATE_TEST_CASE("dihedral angle of a hinge folded by a known angle, both signs", "[bending][angle]", float, double) {
  using S = TestType;
  const double tolerance = std::is_same<S, float>::value ? 2e-6 : 1e-14;
  const Eigen::AngleAxis<double> turn(0.7, Eigen::Vector3d(1, -2, 0.5).normalized());
  const Eigen::Vector3d shift(0.3, -1.2, 2.0);
  for (const double fold : {0.0, 0.25, 1.0, 2.0, 3.1}) {
    for (const double sign : {1.0, -1.0}) {
      INFO("fold " << sign * fold);
      // d toward the front of triangle (a, b, c): the hinge closes on the front, theta < 0.
      for (const auto& placement :
           {std::make_pair(Eigen::AngleAxis<double>(0, Eigen::Vector3d::UnitX()), Eigen::Vector3d(0, 0, 0)),
            std::make_pair(turn, shift)}) {
        const std::array<Vec3<S>, 4> p = folded_hinge<S>(sign * fold, placement.first, placement.second);
        CHECK(double(DihedralBending<S>::angle(p[0], p[1], p[2], p[3])) == Approx(-sign * fold).margin(tolerance));
        // Seen from the other triangle (the edge run the other way): the same angle.
        CHECK(double(DihedralBending<S>::angle(p[1], p[0], p[3], p[2])) == Approx(-sign * fold).margin(tolerance));
      }
    }
  }
  // A mesh of the two triangles: E = k_e (theta - theta0)^2 / 2 with k_e = k 3 |e|^2 / (A1 + A2).
  const double areas = 0.5 * 0.8 + 0.5 * 0.5, stiffness = 0.2;
  const double k_e = stiffness * 3 / areas, pi = std::acos(-1.0);
  for (const double rest_fold : {0.0, 0.6, 2.5}) {
    ClothMesh<S> mesh;
    mesh.positions.resize(3, 4);
    const std::array<Vec3<S>, 4> rest =
        folded_hinge<S>(rest_fold, Eigen::AngleAxis<double>(0, Eigen::Vector3d::UnitX()), Eigen::Vector3d::Zero());
    for (int k = 0; k < 4; ++k) mesh.positions.col(k) = rest[std::size_t(k)];
    mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
    const DihedralBending<S> term(mesh, S(stiffness), S(0));
    REQUIRE(term.hinges().size() == 1);
    CHECK(double(term.hinge_stiffness(0)) == Approx(k_e).epsilon(1e-6));
    CHECK(double(term.rest_angle(0)) == Approx(-rest_fold).margin(1e-6));
    for (const double fold : {0.3, -0.3, -0.6, -2.5}) {
      INFO("rest fold " << rest_fold << ", fold " << fold);
      Matrix3X<S> x(3, 4);
      const std::array<Vec3<S>, 4> p = folded_hinge<S>(fold, turn, shift);
      for (int k = 0; k < 4; ++k) x.col(k) = p[std::size_t(k)];
      // theta - theta0 in (-pi, pi]: from -2.5 rad to 2.5 rad is 2 pi - 5 the short way round.
      double strain = -fold + rest_fold;
      if (strain > pi) strain -= 2 * pi;
      CHECK(double(term.energy(x)) == Approx(0.5 * k_e * strain * strain).epsilon(1e-5).margin(1e-12));
    }
  }
}

TEMPLATE_TEST_CASE("dihedral bending: force is -dE/dx, exact Jacobians match finite differences", "[bending][jacobian]",
                   float, double) {
  using S = TestType;
  const bool is_float = std::is_same<S, float>::value;
  const S h = is_float ? S(3e-4) : S(1e-6);
  const double tolerance = is_float ? 2e-3 : 1e-7;
  for (const bool pattern : {false, true}) {
    const ClothMesh<S> mesh = folded_patch<S>(3, 1.0, 1.5, pattern);
    const DihedralBending<S> term(mesh, S(0.02), S(0.003));
    for (unsigned seed : {1u, 2u}) {
      INFO((pattern ? "flat pattern" : "curved rest shape") << ", seed " << seed);
      const Matrix3X<S> x = jittered(mesh.positions, 0.015, seed);
      const Matrix3X<S> v = jittered<S>(Matrix3X<S>::Zero(3, x.cols()), 2.0, seed + 10);
      const Matrix3X<S> still = Matrix3X<S>::Zero(3, x.cols());
      // Force against -dE/dx (at rest: no damping force).
      Matrix3X<S> grad(3, x.cols());
      for (Index k = 0; k < x.size(); ++k) {
        Matrix3X<S> xp = x, xm = x;
        xp.data()[k] += h;
        xm.data()[k] -= h;
        grad.data()[k] = S((double(term.energy(xp)) - double(term.energy(xm))) / (2 * double(h)));
      }
      const Dense f = dense(force_of(term, x, still));
      CHECK(relative_error(f, -dense(grad)) < tolerance);
      CHECK(f.cwiseAbs().maxCoeff() > 1e-3);
      // Exact variant: dF/dx (elastic and damping) and dF/dv.
      Recorder<S> exact(term, mesh.vertex_count(), false);
      term.add_derivatives(x, v, S(0), exact);
      CHECK(exact.undeclared == 0);
      const Dense fd_x = fd_jacobian(term, x, v, true, h), fd_v = fd_jacobian(term, x, v, false, h);
      CHECK(relative_error(dense_matrix(exact.dfdx), fd_x) < tolerance);
      CHECK(relative_error(dense_matrix(exact.dfdv), fd_v) < tolerance);
      // Without damping the exact dF/dx is minus the Hessian of E: symmetric.
      const DihedralBending<S> elastic(mesh, S(0.02), S(0));
      Recorder<S> hessian(elastic, mesh.vertex_count(), false);
      elastic.add_derivatives(x, v, S(0), hessian);
      const Dense k = dense_matrix(hessian.dfdx);
      CHECK((k - k.transpose()).cwiseAbs().maxCoeff() <= (is_float ? 1e-5 : 1e-13) * k.cwiseAbs().maxCoeff());
      CHECK(relative_error(k, fd_jacobian(elastic, x, v, true, h)) < tolerance);
    }
  }
}

TEMPLATE_TEST_CASE("dihedral bending: the symmetric variant adds -k g g^T and the damping's dF/dv",
                   "[bending][jacobian]", float, double) {
  using S = TestType;
  const double tolerance = std::is_same<S, float>::value ? 1e-5 : 1e-13;
  const ClothMesh<S> mesh = folded_patch<S>(4, 0.8, 1.0);
  const DihedralBending<S> term(mesh, S(0.02), S(0.003));
  const Matrix3X<S> x = jittered(mesh.positions, 0.015, 5);
  const Matrix3X<S> v = jittered<S>(Matrix3X<S>::Zero(3, x.cols()), 2.0, 6);
  Recorder<S> symmetric(term, mesh.vertex_count(), true), exact(term, mesh.vertex_count(), false);
  term.add_derivatives(x, v, S(0), symmetric);
  term.add_derivatives(x, v, S(0), exact);
  CHECK(symmetric.undeclared == 0);
  const Dense kx = dense_matrix(symmetric.dfdx), kv = dense_matrix(symmetric.dfdv);
  const Dense expected = gauss_newton(term, x);
  CHECK(relative_error(kx, expected) < tolerance);
  // The same velocity blocks as the exact variant; -c_e g g^T is -k_e g g^T scaled by c / k.
  CHECK(relative_error(kv, dense_matrix(exact.dfdv)) < tolerance);
  CHECK(relative_error(kv, expected * (0.003 / 0.02)) < 10 * tolerance);
  // Negative semi-definite: the implicit step's SPD matrix stays SPD.
  const double scale = kx.cwiseAbs().maxCoeff();
  CHECK(test::symmetric_eigenvalues(kx).maxCoeff() <= 10 * tolerance * scale);
  CHECK(test::symmetric_eigenvalues(kv).maxCoeff() <= 10 * tolerance * kv.cwiseAbs().maxCoeff());
  // The exact variant differs by the (theta - theta0) Hessian(theta) term.
  CHECK((dense_matrix(exact.dfdx) - kx).cwiseAbs().maxCoeff() > 0.1 * scale);
}

TEMPLATE_TEST_CASE("dihedral bending: a mesh is in equilibrium in its curved rest shape", "[bending][rest]", float,
                   double) {
  using S = TestType;
  const double tolerance = std::is_same<S, float>::value ? 1e-5 : 1e-13;
  const ClothMesh<S> curved = folded_patch<S>(7, 1.2, 2.0);
  const DihedralBending<S> term(curved, S(0.05), S(0.01));
  const Matrix3X<S> still = Matrix3X<S>::Zero(3, curved.vertex_count());
  // The same shape with a flat pattern as its rest shape: pushed back toward flat.
  ClothMesh<S> pattern = curved;
  pattern.rest_uv = folded_patch<S>(7, 1.2, 2.0, true).rest_uv;
  const DihedralBending<S> flattening(pattern, S(0.05), S(0.01));
  const Dense pushed = dense(force_of(flattening, curved.positions, still));
  REQUIRE(pushed.cwiseAbs().maxCoeff() > 1e-2);
  CHECK(dense(force_of(term, curved.positions, still)).cwiseAbs().maxCoeff() <=
        tolerance * pushed.cwiseAbs().maxCoeff());
  CHECK(term.energy(curved.positions) == 0);
  CHECK(flattening.energy(curved.positions) > 0);
  // The rest angles are the folded ones: some near the fold's 1.2 rad.
  double largest = 0;
  for (std::size_t k = 0; k < term.hinges().size(); ++k)
    largest = std::max(largest, std::abs(double(term.rest_angle(int(k)))));
  CHECK(largest > 0.5);
}

TEST_CASE("dihedral bending: internal forces carry no net force and no torque", "[bending][momentum]") {
  const ClothMesh<double> mesh = folded_patch<double>(8, 1.0, 1.0, true);
  const DihedralBending<double> term(mesh, 0.03, 0.004);
  for (unsigned seed : {1u, 2u, 3u}) {
    const Matrix3X<double> x =
        jittered(mesh.positions, 0.015, seed) + Matrix3X<double>::Constant(3, mesh.vertex_count(), 2.5);
    const Matrix3X<double> v = jittered<double>(Matrix3X<double>::Zero(3, x.cols()), 2.0, seed + 20);
    const Matrix3X<double> f = force_of(term, x, v);
    Vec3<double> net = Vec3<double>::Zero(), torque = Vec3<double>::Zero();
    double scale = 0;
    for (int i = 0; i < mesh.vertex_count(); ++i) {
      net += f.col(i);
      torque += x.col(i).cross(Vec3<double>(f.col(i)));
      scale = std::max(scale, f.col(i).norm() * std::max(1.0, x.col(i).norm()));
    }
    INFO("seed " << seed);
    REQUIRE(scale > 1e-3);
    CHECK(net.norm() < 1e-13 * scale);
    CHECK(torque.norm() < 1e-13 * scale);
  }
}

TEST_CASE("dihedral bending: a small explicit step keeps the energy, damping dissipates it", "[bending][energy]") {
  // Vertex masses of 1 g, a 57-degree fold released from rest: velocity Verlet at 0.1 ms for 0.6 s.
  const ClothMesh<double> mesh = folded_patch<double>(9, 1.0, 0.0, true);
  const double mass = 1e-3, dt = 1e-4;
  const int steps = 6000;
  for (const double damping : {0.0, 1e-5}) {
    const DihedralBending<double> term(mesh, 1e-4, damping);
    Matrix3X<double> x = mesh.positions, v = Matrix3X<double>::Zero(3, mesh.vertex_count());
    const auto total = [&] { return term.energy(x) + 0.5 * mass * v.squaredNorm(); };
    const double start = total();
    double largest_kinetic = 0, largest_change = 0, previous = start, largest_rise = 0;
    Matrix3X<double> f = force_of(term, x, v);
    for (int s = 0; s < steps; ++s) {
      v += (0.5 * dt / mass) * f;
      x += dt * v;
      f = force_of(term, x, v);
      v += (0.5 * dt / mass) * f;
      const double now = total();
      largest_kinetic = std::max(largest_kinetic, 0.5 * mass * v.squaredNorm());
      largest_change = std::max(largest_change, std::abs(now - start));
      largest_rise = std::max(largest_rise, now - previous);
      previous = now;
    }
    INFO("damping " << damping << ": energy " << start << " -> " << total());
    if (damping == 0) {
      CHECK(largest_kinetic > 0.2 * start);  // the fold opens: energy moves between the two forms
      CHECK(largest_change < 1e-5 * start);
    } else {
      CHECK(total() < 0.6 * start);
      CHECK(largest_rise < 1e-6 * start);  // never gains energy
    }
  }
}

TEST_CASE("dihedral bending: colours share no vertex; the same bits on 1 and 2 threads", "[bending][threads]") {
  const ClothMesh<double> mesh = folded_patch<double>(11, 1.0, 1.0, false, 14, 12);
  const DihedralBending<double> term(mesh, 0.02, 0.003);
  // Every hinge once; no vertex twice within a colour.
  const auto key = [](const Hinge& h) { return std::array<int, 4>{h.a, h.b, h.c, h.d}; };
  std::vector<std::array<int, 4>> given, sorted;
  for (const Hinge& h : mesh.hinges()) given.push_back(key(h));
  for (const Hinge& h : term.hinges()) sorted.push_back(key(h));
  std::sort(given.begin(), given.end());
  std::sort(sorted.begin(), sorted.end());
  CHECK(given == sorted);
  // Chunks of consecutive hinges; the chunks of a colour share no vertex.
  const std::vector<int>& chunk = term.chunk_begin();
  const std::vector<int>& colour = term.colour_begin();
  REQUIRE(colour.size() >= 2);
  REQUIRE(colour.back() + 1 == static_cast<int>(chunk.size()));
  CHECK(chunk.back() == static_cast<int>(given.size()));
  CHECK(chunk.size() > 4);  // several chunks, so two threads share a colour
  for (std::size_t c = 0; c + 1 < colour.size(); ++c) {
    std::vector<int> nodes;
    for (int q = colour[c]; q < colour[c + 1]; ++q) {
      std::set<int> in_chunk;
      for (int k = chunk[std::size_t(q)]; k < chunk[std::size_t(q) + 1]; ++k)
        for (int node : key(term.hinges()[std::size_t(k)])) in_chunk.insert(node);
      nodes.insert(nodes.end(), in_chunk.begin(), in_chunk.end());
    }
    std::sort(nodes.begin(), nodes.end());
    INFO("colour " << c);
    CHECK(std::adjacent_find(nodes.begin(), nodes.end()) == nodes.end());
  }
  // coupled_nodes(): every pair of a hinge's vertices, once.
  std::set<std::array<int, 2>> pairs;
  for (const Hinge& h : mesh.hinges()) {
    const std::array<int, 4> v = key(h);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) pairs.insert({std::min(v[i], v[j]), std::max(v[i], v[j])});
  }
  const std::vector<std::array<int, 2>> coupled = term.coupled_nodes();
  CHECK(coupled == std::vector<std::array<int, 2>>(pairs.begin(), pairs.end()));

  const int n = mesh.vertex_count();
  const Matrix3X<double> x = jittered(mesh.positions, 0.015, 12);
  const Matrix3X<double> v = jittered<double>(Matrix3X<double>::Zero(3, n), 2.0, 13);
  for (const bool symmetric : {false, true}) {
    INFO((symmetric ? "symmetric" : "exact"));
    Matrix3X<double> f_apart = Matrix3X<double>::Zero(3, n);
    Recorder<double> apart(term, n, symmetric);
    term.add_force(x, v, 0.0, f_apart);
    term.add_derivatives(x, v, 0.0, apart);
    for (int threads : {1, 2}) {
      INFO(threads << " threads");
      Matrix3X<double> f = Matrix3X<double>::Zero(3, n), f_fused = Matrix3X<double>::Zero(3, n);
      Recorder<double> blocks(term, n, symmetric), fused(term, n, symmetric);
      run_in_team(threads, [&] {
        term.add_force(x, v, 0.0, f);
        term.add_derivatives(x, v, 0.0, blocks);
        term.add_force_and_derivatives(x, v, 0.0, f_fused, fused);
      });
      CHECK(f == f_apart);
      CHECK(f_fused == f_apart);
      CHECK(blocks.dfdx == apart.dfdx);
      CHECK(blocks.dfdv == apart.dfdv);
      CHECK(fused.dfdx == apart.dfdx);
      CHECK(fused.dfdv == apart.dfdv);
      CHECK(blocks.overlapping == 0);
      CHECK(fused.overlapping == 0);
      CHECK(fused.undeclared == 0);
    }
  }
}

TEST_CASE("dihedral bending on a grid cloth: the assembled Jacobians, and a cantilever that holds up",
          "[bending][cloth]") {
  const int n = 7;
  const double spacing = 0.1;
  const ClothMesh<double> mesh = grid_mesh<double>(n, n, spacing);
  ClothSpecd spec = test::small_spec<double>(n, 10.0);
  spec.springs = {{300.0, 2.0}, {200.0, 1.5}, {0.0, 0.0}};  // no bend springs: bending is the term's
  SECTION("the system's blocks against finite differences of the cloth's force") {
    spec.gravity = 0;
    spec.pinned_nodes = std::vector<int>{};
    spec.force_terms = {std::make_shared<DihedralBending<double>>(mesh, 0.5, 0.05)};
    const Clothd cloth(spec);
    const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 4);
    const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 2.0, 5);
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
    assembler.assemble_jacobians(x, v, 0.0, JacobianVariant::Exact, kx, kv);
    CHECK(test::max_relative_error(kx.to_dense(), test::fd_jacobian(cloth, x, v, true)) < 1e-6);
    CHECK(test::max_relative_error(kv.to_dense(), test::fd_jacobian(cloth, x, v, false)) < 1e-6);
  }
  SECTION("pinned along two rows, the free edge droops far less with bending, in every integrator") {
    std::vector<int> clamped;
    for (int i = 0; i < 2 * n; ++i) clamped.push_back(i);  // rows j = 0 and 1
    spec.pinned_nodes = clamped;
    const auto free_edge_height = [&](const Clothd& cloth, Integrator<double>& integrator) {
      State<double> s = cloth.initial_state();
      while (s.time < 3.0) REQUIRE(integrator.step(s).ok());
      REQUIRE(s.positions.allFinite());
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += s.positions(1, (n - 1) * n + i);
      return sum / n;
    };
    std::vector<double> heights;
    for (const double stiffness : {0.0, 2.0}) {
      // Air drag (m / c = 0.6 s) brings the swinging to rest within the 3 s.
      spec.force_terms = {std::make_shared<DihedralBending<double>>(mesh, stiffness, 0.002),
                          std::make_shared<AirDrag<double>>(0.05)};
      const Clothd cloth(spec);
      ImplicitOptions spd;
      spd.dt = 0.01;
      spd.threads = 1;
      ImplicitOptions exact = spd;
      exact.jacobian = JacobianVariant::Exact;
      exact.solver = LinearSolverKind::Bicgstab;
      ImplicitEuler<double> implicit_spd(cloth, spd), implicit_exact(cloth, exact);
      SymplecticEuler<double> symplectic(cloth, IntegratorOptions{2e-4, 1});
      for (Integrator<double>* integrator :
           std::initializer_list<Integrator<double>*>{&implicit_spd, &implicit_exact, &symplectic}) {
        heights.push_back(free_edge_height(cloth, *integrator));
        INFO("stiffness " << stiffness << ", integrator " << heights.size() << ": free edge at y = " << heights.back());
      }
    }
    // The cloth is 0.6 m long: without bending it hangs, with it it holds its free edge up.
    for (int k = 0; k < 3; ++k) {
      INFO("integrator " << k << ": " << heights[std::size_t(k)] << " without, " << heights[std::size_t(3 + k)]
                         << " with");
      CHECK(heights[std::size_t(k)] < -0.35);
      CHECK(heights[std::size_t(3 + k)] > heights[std::size_t(k)] + 0.15);
      // At rest, the integrators agree on where.
      CHECK(std::abs(heights[std::size_t(3 + k)] - heights[3]) < 0.02);
    }
  }
}

namespace {

/// The mean height of the free edge (the last row, z = 0.6) of a 0.6 m square patch n x n clamped
/// along z <= 0.1 m, loaded by gravity and settled by implicit steps: a cantilever plate 0.5 m long
/// whose stiffness is the dihedral term's alone (no bend or shear springs; stiff structural springs
/// keep its length).
double settled_free_edge(ClothMesh<double> mesh, int n, double bending) {
  const double h = 0.6 / (n - 1);
  ClothSpecd spec;
  std::vector<int> clamped;
  for (int k = 0; k < n * n; ++k)
    if (k / n * h < 0.1 + 1e-9) {
      mesh.positions.col(k) = Vec3<double>((k % n) * h, 0, (k / n) * h);  // a straight clamped edge
      clamped.push_back(k);
    }
  spec.mesh = mesh;
  spec.areal_density = 0.2;  // kg/m^2: the same weight whatever the triangles
  spec.gravity = 9.81;
  spec.springs = {{2000.0, 0.5}, {0.0, 0.0}, {0.0, 0.0}};
  spec.pinned_nodes = clamped;
  spec.force_terms = {std::make_shared<DihedralBending<double>>(mesh, bending, 0.1 * bending),
                      std::make_shared<AirDrag<double>>(2e-3)};
  const Clothd cloth(spec);
  ImplicitOptions options;
  options.dt = 0.02;
  options.threads = 1;
  ImplicitEuler<double> implicit(cloth, options);
  State<double> s = cloth.initial_state();
  while (s.time < 6.0) REQUIRE(implicit.step(s).ok());
  REQUIRE(s.positions.allFinite());
  REQUIRE(s.velocities.cwiseAbs().maxCoeff() < 1e-4);  // at rest
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += s.positions(1, (n - 1) * n + i);
  return sum / n;
}

}  // namespace

TEST_CASE("dihedral bending: a square cloth sags the same meshed regularly or irregularly", "[bending][sag][long]") {
  // Measured (13 x 13 and the three seeds): random diagonals change the sag by at most 2%, vertices
  // jittered by up to a quarter of the spacing stiffen the plate by 6-14% (5% at 7 x 7, 11-12% at
  // 25 x 25: docs/bending.md, "Irregular meshes").
  const int n = 13;
  const double h = 0.6 / (n - 1), bending = 0.2;
  const double regular = settled_free_edge(test::regular_patch(n, h), n, bending);
  INFO("regular mesh: free edge at y = " << regular);
  CHECK(regular < -0.02);  // it sags (a beam of rigidity 3 k: 0.026 m) ...
  CHECK(regular > -0.05);  // ... and bending carries the load
  double jittered_sum = 0;
  for (const unsigned seed : {1u, 2u, 3u}) {
    ClothMesh<double> mesh = test::irregular_patch(n, h, seed);
    const double jittered = settled_free_edge(mesh, n, bending);
    mesh.positions = test::regular_patch(n, h).positions;
    const double diagonals = settled_free_edge(mesh, n, bending);
    INFO("seed " << seed << ": free edge at y = " << diagonals << " with random diagonals, " << jittered
                 << " jittered");
    CHECK(std::abs(diagonals - regular) < 0.03 * std::abs(regular));
    CHECK(std::abs(jittered - regular) < 0.16 * std::abs(regular));
    jittered_sum += jittered;
  }
  CHECK(std::abs(jittered_sum / 3 - regular) < 0.12 * std::abs(regular));
}
