// Jacobians of the damped spring force against central finite differences of the assembled global
// force, symmetry, and positive definiteness of the SPD variant; the assembled system, its edge
// form and its independence of the thread count.
#include <catch2/catch.hpp>

#include <algorithm>

#include "drape/fwd.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "support/dense.hpp"
#include "test_common.hpp"

using namespace drape;
using Dense = Eigen::MatrixXd;

namespace {

ClothSpecd damped_spec(int n) {
  ClothSpecd spec = test::small_spec<double>(n, 10.0);
  spec.springs = {{300.0, 2.0}, {200.0, 1.5}, {50.0, 0.5}};
  spec.pinned_nodes = std::vector<int>{};  // every node in the system
  return spec;
}

void assembled(const Clothd& cloth, const Matrix3X<double>& x, const Matrix3X<double>& v, JacobianVariant variant,
               Dense& dfdx, Dense& dfdv) {
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
  assembler.assemble_jacobians(x, v, 0, variant, kx, kv);
  dfdx = kx.to_dense();
  dfdv = kv.to_dense();
}

using test::fd_jacobian;
using test::max_relative_error;

}  // namespace

TEST_CASE("Exact df/dx and df/dv match finite differences of the damped force", "[jacobian]") {
  const Clothd cloth(damped_spec(4));
  for (unsigned seed : {1u, 2u, 3u}) {
    // +-35% of the spacing: a mix of stretched and compressed springs, random velocities.
    const Matrix3X<double> x = test::jiggled_positions(cloth, 0.35, seed);
    const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 2.0, seed + 10);
    Dense dfdx, dfdv;
    assembled(cloth, x, v, JacobianVariant::Exact, dfdx, dfdv);
    CHECK(max_relative_error(dfdx, fd_jacobian(cloth, x, v, true)) < 1e-6);
    CHECK(max_relative_error(dfdv, fd_jacobian(cloth, x, v, false)) < 1e-6);
  }
}

TEST_CASE("Symmetric df/dx is the exact Jacobian of the undamped force and drops the damping term", "[jacobian]") {
  const Clothd cloth(damped_spec(4));
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.35, 7u);
  const Matrix3X<double> v0 = Matrix3X<double>::Zero(3, cloth.node_count());
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 2.0, 8u);
  Dense sym, dfdv, sym_v, exact_v;
  assembled(cloth, x, v0, JacobianVariant::Symmetric, sym, dfdv);
  CHECK(max_relative_error(sym, fd_jacobian(cloth, x, v0, true)) < 1e-6);
  // With velocities the damping term's x-derivative is what separates Exact from Symmetric.
  assembled(cloth, x, v, JacobianVariant::Symmetric, sym_v, dfdv);
  assembled(cloth, x, v, JacobianVariant::Exact, exact_v, dfdv);
  CHECK(max_relative_error(sym_v, sym) < 1e-12);  // Symmetric ignores v
  CHECK(max_relative_error(exact_v, sym) > 1e-3);
}

TEST_CASE("Spd df/dx equals the exact elastic Jacobian when every spring is stretched", "[jacobian]") {
  const Clothd cloth(damped_spec(4));
  // Scaled by 1.2 plus a small jiggle: every spring longer than its rest length.
  Matrix3X<double> x = test::jiggled_positions(cloth, 0.03, 3u) * 1.2;
  const Matrix3X<double> v0 = Matrix3X<double>::Zero(3, cloth.node_count());
  Dense spd, dfdv;
  assembled(cloth, x, v0, JacobianVariant::Spd, spd, dfdv);
  CHECK(max_relative_error(spd, fd_jacobian(cloth, x, v0, true)) < 1e-6);
}

TEST_CASE("Symmetric and Spd Jacobians are symmetric, Exact is not; Spd is negative semi-definite", "[jacobian]") {
  const Clothd cloth(damped_spec(4));
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.35, 11u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 2.0, 12u);
  Dense exact, sym, spd, dfdv;
  assembled(cloth, x, v, JacobianVariant::Exact, exact, dfdv);
  assembled(cloth, x, v, JacobianVariant::Symmetric, sym, dfdv);
  assembled(cloth, x, v, JacobianVariant::Spd, spd, dfdv);
  CHECK((sym - sym.transpose()).cwiseAbs().maxCoeff() < 1e-12 * sym.cwiseAbs().maxCoeff());
  CHECK((spd - spd.transpose()).cwiseAbs().maxCoeff() < 1e-12 * spd.cwiseAbs().maxCoeff());
  CHECK((dfdv - dfdv.transpose()).cwiseAbs().maxCoeff() < 1e-12 * dfdv.cwiseAbs().maxCoeff());
  CHECK((exact - exact.transpose()).cwiseAbs().maxCoeff() > 1e-3 * exact.cwiseAbs().maxCoeff());
  CHECK(test::symmetric_eigenvalues(spd).maxCoeff() <= 1e-9 * spd.cwiseAbs().maxCoeff());
  CHECK(test::symmetric_eigenvalues(dfdv).maxCoeff() <= 1e-9 * dfdv.cwiseAbs().maxCoeff());
}

TEST_CASE("the Spd system matrix factorises where the Symmetric one does not (heavy compression)", "[jacobian]") {
  ClothSpecd spec = damped_spec(5);
  spec.springs = ClothSpecd::default_springs();
  const Clothd cloth(spec);
  // Squashed to 40% of its size with a small out-of-plane jiggle: every spring heavily compressed.
  Matrix3X<double> x = test::jiggled_positions(cloth, 0.05, 5u) * 0.4;
  const Matrix3X<double> v = Matrix3X<double>::Zero(3, cloth.node_count());
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<double> system = assembler.make_system();
  const BlockSparseMatrix<double>& a = system.matrix;
  const double dt = 1.0 / 60;
  assembler.assemble_system(x, v, 0, dt, JacobianVariant::Symmetric, system);
  CHECK_FALSE(test::cholesky_succeeds(a.to_dense()));
  assembler.assemble_system(x, v, 0, dt, JacobianVariant::Spd, system);
  CHECK(test::cholesky_succeeds(a.to_dense()));
}

TEST_CASE("system matrix and right-hand side follow the linearised implicit Euler formula", "[jacobian]") {
  // A = M - dt df/dv - dt^2 df/dx, b = dt (f + dt df/dx v), checked against the separately
  // assembled Jacobians and the force assembler, with two pinned nodes eliminated.
  ClothSpecd spec = damped_spec(4);
  spec.pinned_nodes = std::vector<int>{0, 3};
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 21u);
  Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 22u);
  v.col(0).setZero();
  v.col(3).setZero();
  const double dt = 0.02;
  for (JacobianVariant variant : {JacobianVariant::Exact, JacobianVariant::Symmetric, JacobianVariant::Spd}) {
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    REQUIRE(assembler.system_nodes() == cloth.node_count() - 2);
    LinearSystem<double> system = assembler.make_system();
    const BlockSparseMatrix<double>& a = system.matrix;
    const VectorX<double>& rhs = system.rhs;
    BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
    assembler.assemble_system(x, v, 0, dt, variant, system);
    assembler.assemble_jacobians(x, v, 0, variant, kx, kv);
    VectorX<double> m(a.size());
    VectorX<double> vf(a.size());
    Matrix3X<double> f(3, cloth.node_count());
    ForceAssembler<double>(cloth, 1).force(x, v, 0, f);
    VectorX<double> ff(a.size());
    for (int r = 0; r < assembler.system_nodes(); ++r) {
      const int node = assembler.node_of_row()[static_cast<std::size_t>(r)];
      m.segment<3>(3 * r).setConstant(cloth.grid().masses()[node]);
      vf.segment<3>(3 * r) = v.col(node);
      ff.segment<3>(3 * r) = f.col(node);
    }
    const Dense expected_a = Dense(m.asDiagonal()) - dt * kv.to_dense() - dt * dt * kx.to_dense();
    CHECK(max_relative_error(a.to_dense(), expected_a) < 1e-12);
    const VectorX<double> expected_b = dt * (ff + dt * (kx.to_dense() * vf));
    CHECK((rhs - expected_b).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, expected_b.cwiseAbs().maxCoeff()));
  }
}

TEST_CASE("float assembly agrees with double", "[jacobian][float]") {
  const Clothd cloth_d(damped_spec(4));
  ClothSpecf spec_f = test::small_spec<float>(4, 10.0f);
  spec_f.springs = {{300.0f, 2.0f}, {200.0f, 1.5f}, {50.0f, 0.5f}};
  spec_f.pinned_nodes = std::vector<int>{};
  const Clothf cloth_f(spec_f);
  const Matrix3X<double> x = test::jiggled_positions(cloth_d, 0.3, 31u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth_d.node_count(), 1.0, 32u);
  JacobianAssembler<double> ad(cloth_d, PinTreatment::Eliminate, 1);
  JacobianAssembler<float> af(cloth_f, PinTreatment::Eliminate, 1);
  LinearSystem<double> sd = ad.make_system();
  LinearSystem<float> sf = af.make_system();
  const BlockSparseMatrix<double>& md = sd.matrix;
  const BlockSparseMatrix<float>& mf = sf.matrix;
  const VectorX<double>& bd = sd.rhs;
  const VectorX<float>& bf = sf.rhs;
  ad.assemble_system(x, v, 0, 0.01, JacobianVariant::Exact, sd);
  af.assemble_system(x.cast<float>(), v.cast<float>(), 0, 0.01f, JacobianVariant::Exact, sf);
  CHECK(max_relative_error(mf.to_dense().cast<double>(), md.to_dense()) < 1e-5);
  CHECK((bf.cast<double>() - bd).cwiseAbs().maxCoeff() < 1e-5 * std::max(1.0, bd.cwiseAbs().maxCoeff()));
}

TEST_CASE("reassembly overwrites every value of the system (no stale blocks)", "[jacobian]") {
  // The assembler writes each block once per step instead of zeroing and adding: a matrix full of
  // garbage from an earlier use must come out equal to a fresh one.
  ClothSpecd spec = damped_spec(5);
  spec.pinned_nodes = std::vector<int>{0, 4};
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 41u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 42u);
  for (JacobianVariant variant : {JacobianVariant::Exact, JacobianVariant::Spd}) {
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    LinearSystem<double> fresh_system = assembler.make_system(), reused_system = assembler.make_system();
    const BlockSparseMatrix<double>& fresh = fresh_system.matrix;
    BlockSparseMatrix<double>& reused = reused_system.matrix;
    const VectorX<double>& b_fresh = fresh_system.rhs;
    VectorX<double>& b_reused = reused_system.rhs;
    b_reused.setConstant(1e30);
    std::fill(reused.values(), reused.values() + 9 * reused.block_count(), 1e30);
    assembler.assemble_system(x, v, 0, 0.02, variant, fresh_system);
    assembler.assemble_system(x, v, 0, 0.02, variant, reused_system);
    INFO(to_string(variant));
    CHECK(reused.to_dense() == fresh.to_dense());
    CHECK(b_reused == b_fresh);
  }
}

TEST_CASE("the edge form holds each spring's C: symmetric (6 values) unless Exact", "[jacobian][edges]") {
  // A = M + sum_e [C -C; -C C]: rebuilt densely from the edge values it must equal the blocks.
  ClothSpecd spec = damped_spec(4);
  spec.pinned_nodes = std::vector<int>{0, 3};
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 51u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 52u);
  for (JacobianVariant variant : {JacobianVariant::Exact, JacobianVariant::Symmetric, JacobianVariant::Spd}) {
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    LinearSystem<double> system = assembler.make_system();
    const BlockSparseMatrix<double>& a = system.matrix;
    const EdgeOperator<double>& edges = system.edges;
    assembler.assemble_system(x, v, 0, 0.02, variant, system);
    REQUIRE(edges.valid());
    CHECK(edges.symmetric() == (variant != JacobianVariant::Exact));
    Dense rebuilt = Dense::Zero(a.size(), a.size());
    for (int r = 0; r < a.block_rows(); ++r)
      rebuilt.block<3, 3>(3 * r, 3 * r).diagonal().setConstant(edges.row_mass()[r]);
    for (int e = 0; e < edges.edge_count(); ++e) {
      double c[9];
      for (int k = 0; k < edges.stride(); ++k)
        c[k] = edges.values()[EdgeOperator<double>::value_index(e, k, edges.stride())];
      Mat3<double> block;
      if (edges.symmetric())
        block << c[0], c[1], c[3], c[1], c[2], c[4], c[3], c[4], c[5];  // stored row by row
      else
        block = Eigen::Map<const Mat3<double>>(c);
      const int ra = edges.edge_rows()[2 * e], rb = edges.edge_rows()[2 * e + 1];
      if (ra >= 0) rebuilt.block<3, 3>(3 * ra, 3 * ra) += block;
      if (rb >= 0) rebuilt.block<3, 3>(3 * rb, 3 * rb) += block;
      if (ra >= 0 && rb >= 0) {
        rebuilt.block<3, 3>(3 * ra, 3 * rb) -= block;
        rebuilt.block<3, 3>(3 * rb, 3 * ra) -= block;
      }
    }
    INFO(to_string(variant));
    CHECK(max_relative_error(rebuilt, a.to_dense()) < 1e-14);
  }
}

TEST_CASE("system assembly on two threads equals one thread bit for bit", "[jacobian][threads]") {
  if (max_threads() < 2) {
    WARN("only one thread available: nothing to compare");
    return;
  }
  // 48 x 48: enough springs for the assembler to wake a second thread.
  ClothSpecd spec = damped_spec(48);
  spec.pinned_nodes = std::vector<int>{0, 47};
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 61u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 62u);
  for (JacobianVariant variant : {JacobianVariant::Exact, JacobianVariant::Spd}) {
    JacobianAssembler<double> one(cloth, PinTreatment::Eliminate, 1), two(cloth, PinTreatment::Eliminate, 2);
    REQUIRE(two.threads() == 2);
    LinearSystem<double> s1 = one.make_system(), s2 = two.make_system();
    const BlockSparseMatrix<double>& a1 = s1.matrix;
    const BlockSparseMatrix<double>& a2 = s2.matrix;
    const VectorX<double>& b1 = s1.rhs;
    const VectorX<double>& b2 = s2.rhs;
    one.assemble_system(x, v, 0, 0.02, variant, s1);
    two.assemble_system(x, v, 0, 0.02, variant, s2);
    INFO(to_string(variant));
    CHECK(std::equal(a1.values(), a1.values() + 9 * a1.block_count(), a2.values()));
    CHECK(std::equal(s1.edges.values(), s1.edges.values() + s1.edges.value_count(), s2.edges.values()));
    CHECK(b1 == b2);
  }
}
