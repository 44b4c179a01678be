// Seam springs (physics/seam_springs.hpp): the force law and its exact derivatives (finite
// differences, while closing and closed), momentum and angular momentum kept, the rest length's
// ramp, pull-only while closing, two separate sheets sewn edge to edge by the implicit step within
// the closing time (float and double), and bad arguments named.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "drape/core/mesh_generators.hpp"
#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/physics/seam_springs.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// Two 5 x 5 sheets, 0.1 m apart in x, side by side in the x-z plane, each a grid mesh; the first's
/// right edge (x = 0.4) is sewn to the second's left edge (x = 0.5), node for node.
template <class S>
struct TwoSheets {
  ClothMesh<S> mesh;
  std::vector<std::array<int, 2>> pairs;
};

template <class S>
TwoSheets<S> two_sheets(S gap) {
  const ClothMesh<S> one = grid_mesh<S>(5, 5, S(0.1));
  TwoSheets<S> out;
  const Index n = one.positions.cols();
  out.mesh.positions.resize(3, 2 * n);
  out.mesh.positions.leftCols(n) = one.positions;
  out.mesh.positions.rightCols(n) = one.positions;
  out.mesh.positions.rightCols(n).row(0).array() += S(0.4) + gap;
  for (const auto& t : one.triangles) out.mesh.triangles.push_back(t);
  for (const auto& t : one.triangles)
    out.mesh.triangles.push_back({t[0] + int(n), t[1] + int(n), t[2] + int(n)});
  // grid_mesh: node (i, j) is j * 5 + i, i along x.
  for (int j = 0; j < 5; ++j) out.pairs.push_back({j * 5 + 4, int(n) + j * 5});
  return out;
}

}  // namespace

TEST_CASE("seam springs: exact derivatives while closing, at the ramp's end and closed (finite differences)",
          "[seams][jacobian]") {
  const TwoSheets<double> sheets = two_sheets(0.1);
  for (const double t : {0.3, 0.999, 1.5}) {
    INFO("t = " << t);
    auto seams = std::make_shared<SeamSprings<double>>(sheets.pairs, sheets.mesh.positions, 80.0, 0.7, 1.0);
    ClothSpecd spec;
    spec.mesh = sheets.mesh;
    spec.pinned_nodes = std::vector<int>{};
    spec.gravity = 0;
    spec.force_terms = {seams};
    const Clothd cloth(spec);
    // Every node moved by up to 1 cm: the pairs stay wider than L(t), so every one pulls while closing.
    std::srand(7);
    const Matrix3X<double> x = sheets.mesh.positions + 0.01 * Matrix3X<double>::Random(3, cloth.node_count());
    const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 8u);
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
    assembler.assemble_jacobians(x, v, t, JacobianVariant::Exact, kx, kv);
    CHECK(test::max_relative_error(kx.to_dense(), test::fd_jacobian(cloth, x, v, true, t)) < 1e-6);
    CHECK(test::max_relative_error(kv.to_dense(), test::fd_jacobian(cloth, x, v, false, t)) < 1e-6);
  }
}

TEST_CASE("seam springs keep momentum and angular momentum; the rest length ramps to zero; they only pull",
          "[seams][momentum]") {
  const TwoSheets<double> sheets = two_sheets(0.1);
  const SeamSprings<double> seams(sheets.pairs, sheets.mesh.positions, 50.0, 0.3, 2.0, 1.0);
  const Index n = sheets.mesh.positions.cols();
  Matrix3X<double> x = sheets.mesh.positions + 0.05 * Matrix3X<double>::Random(3, n);
  const Matrix3X<double> v = Matrix3X<double>::Random(3, n);
  Matrix3X<double> f = Matrix3X<double>::Zero(3, n);
  seams.add_force(x, v, 2.0, f);
  CHECK(f.rowwise().sum().norm() < 1e-12);
  Vec3<double> torque = Vec3<double>::Zero();
  for (Index i = 0; i < n; ++i) torque += x.col(i).cross(f.col(i));
  // Damping on relative velocities has a torque of its own; the springs alone have none.
  Matrix3X<double> fs = Matrix3X<double>::Zero(3, n);
  SeamSprings<double>(sheets.pairs, sheets.mesh.positions, 50.0, 0.0, 2.0, 1.0).add_force(x, v, 2.0, fs);
  Vec3<double> spring_torque = Vec3<double>::Zero();
  for (Index i = 0; i < n; ++i) spring_torque += x.col(i).cross(fs.col(i));
  CHECK(spring_torque.norm() < 1e-12);
  CHECK(fs.norm() > 0.1);
  // Rest length: L0 until the start time, half at mid-ramp, zero at and after its end.
  CHECK(seams.rest_length(0, 0.5) == Approx(0.1));
  CHECK(seams.rest_length(0, 2.0) == Approx(0.05));
  CHECK(seams.rest_length(0, 3.0) == 0);
  CHECK(seams.rest_length(0, 9.0) == 0);
  // Pull-only while closing: at t = 2 (L = 5 cm) a pair 4 cm apart feels only its damping.
  Matrix3X<double> close = sheets.mesh.positions;
  for (const auto& [a, b] : sheets.pairs) close.col(b) = close.col(a) + Vec3<double>(0.04, 0, 0);
  Matrix3X<double> f_close = Matrix3X<double>::Zero(3, n);
  seams.add_force(close, Matrix3X<double>::Zero(3, n), 2.0, f_close);
  CHECK(f_close.norm() == 0);
  // After the ramp a zero-length spring: f_a = -k (x_a - x_b).
  Matrix3X<double> f_end = Matrix3X<double>::Zero(3, n);
  seams.add_force(close, Matrix3X<double>::Zero(3, n), 3.5, f_end);
  const auto [a, b] = sheets.pairs[0];
  CHECK((f_end.col(a) - 50.0 * Vec3<double>(0.04, 0, 0)).norm() < 1e-12);
}

TEMPLATE_TEST_CASE("two sheets sewn edge to edge close within the closing time and stay one flat sheet",
                   "[seams][implicit]", float, double) {
  using S = TestType;
  const TwoSheets<S> sheets = two_sheets(S(0.1));
  ClothSpec<S> spec;
  spec.mesh = sheets.mesh;
  spec.pinned_nodes = std::vector<int>{};
  spec.gravity = 0;
  spec.node_mass = S(0.01);
  spec.springs = {{S(300), S(0.5)}, {S(0), S(0)}, {S(20), S(0.05)}};
  const S closing = S(0.5);
  auto seams = std::make_shared<SeamSprings<S>>(sheets.pairs, sheets.mesh.positions, S(400), S(0.5), closing);
  spec.force_terms = {seams};
  const Cloth<S> cloth(spec);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  ImplicitEuler<S> integrator(cloth, options);
  State<S> s = cloth.initial_state();
  S widest_at_half = 0;
  while (s.time < S(1.5)) {
    REQUIRE(integrator.step(s).ok());
    if (std::abs(double(s.time) - 0.25) < 0.5 / 60) widest_at_half = seams->widest_gap(s.positions);
  }
  // Half way through the ramp the gaps are near half their start (they follow L(t)).
  CHECK(widest_at_half > S(0.03));
  CHECK(widest_at_half < S(0.07));
  // Closed: the pairs within a millimetre, the sheet one piece 0.8 m + the closed gap wide.
  CHECK(seams->widest_gap(s.positions) < S(1e-3));
  const S width = s.positions.row(0).maxCoeff() - s.positions.row(0).minCoeff();
  CHECK(width == Approx(0.8).margin(0.01));
  // Flat: nothing pushed any node out of the plane, and no momentum was made.
  CHECK(s.positions.row(1).cwiseAbs().maxCoeff() < S(1e-6));
  CHECK(s.velocities.rowwise().sum().norm() < S(1e-4));
}

TEST_CASE("seam springs name their bad arguments", "[seams][errors]") {
  const TwoSheets<double> sheets = two_sheets(0.1);
  const Matrix3X<double>& x = sheets.mesh.positions;
  auto message = [&](std::vector<std::array<int, 2>> pairs, double k, double c, double closing) -> std::string {
    try {
      SeamSprings<double>(std::move(pairs), x, k, c, closing);
    } catch (const InvalidParameter& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(message({{0, 99}}, 1, 0, 1), Catch::Contains("seam pairs[0]") && Catch::Contains("[0, 50)"));
  CHECK_THAT(message({{0, 1}, {3, 3}}, 1, 0, 1), Catch::Contains("seam pairs[1]"));
  CHECK_THAT(message(sheets.pairs, 0, 0, 1), Catch::Contains("seam stiffness"));
  CHECK_THAT(message(sheets.pairs, 1, -1, 1), Catch::Contains("seam damping"));
  CHECK_THAT(message(sheets.pairs, 1, 0, std::nan("")), Catch::Contains("seam closing time"));
  CHECK(message(sheets.pairs, 1, 0, 0).empty());
}
