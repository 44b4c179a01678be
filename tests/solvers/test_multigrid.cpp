// The multigrid preconditioner (multigrid.hpp): its hierarchy, the Galerkin operators, the symmetry
// and definiteness CG relies on, and the iteration counts that are its reason to exist.
#include <catch2/catch.hpp>

#include <memory>
#include <stdexcept>
#include <string>

#include <Eigen/SparseCore>

#include "drape/fwd.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/multigrid.hpp"
#include "drape/solvers/pcg.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// The implicit system of a deformed, moving n x n cloth with the default (stiff, cloth-like)
/// springs, both top corners pinned, at dt = 1/60.
template <class S = double>
struct Problem {
  Cloth<S> cloth;
  JacobianAssembler<S> assembler;
  LinearSystem<S> system;
  const BlockSparseMatrix<S>& a = system.matrix;
  const VectorX<S>& b = system.rhs;
  const GridLayout& layout = system.layout;

  Problem(int n, PinTreatment pins, S dt = S(1) / S(60))
      : cloth([n] {
          ClothSpec<S> spec;
          spec.nx = spec.ny = n;
          return spec;
        }()),
        assembler(cloth, pins, 1) {
    const Matrix3X<S> x = test::jiggled_positions(cloth, S(0.05), 7u);
    Matrix3X<S> v = test::random_velocities<S>(cloth.node_count(), S(1), 8u);
    for (int p : cloth.pins().nodes()) v.col(p).setZero();
    system = assembler.make_system();
    assembler.assemble_system(x, v, 0, dt, JacobianVariant::Spd, system);
  }
};

template <class S>
std::unique_ptr<Problem<S>> make_problem(int n, PinTreatment pins = PinTreatment::Eliminate) {
  return std::make_unique<Problem<S>>(n, pins);
}

struct Solve {
  VectorX<double> x;
  SolveStatus status;
};

/// CG on p's system (its constraints: the pinned rows under PinTreatment::Filter).
Solve pcg(const Problem<double>& p, PreconditionerKind preconditioner, double tolerance, int threads = 1) {
  IterativeSettings settings;
  settings.tolerance = tolerance;
  settings.threads = threads;
  settings.max_iterations = 5000;
  settings.preconditioner = preconditioner;
  PcgSolver<double> solver(settings);
  solver.analyze(p.system);
  Solve s{VectorX<double>::Zero(p.b.size()), {}};
  s.status = solver.solve(p.system, s.x);
  return s;
}

/// z = B r with a fresh hierarchy for p's matrix.
VectorX<double> apply(MultigridPreconditioner<double>& mg, const VectorX<double>& r) {
  VectorX<double> z(r.size());
  mg.apply_in_team(r.data(), z.data());
  return z;
}

}  // namespace

TEST_CASE("multigrid: each coarser lattice keeps every other line and the last one", "[multigrid]") {
  const detail::CoarseAxis five = detail::coarsen_axis(5);
  CHECK(five.position == std::vector<int>{0, 2, 4});
  CHECK(five.parent[1] == std::array<int, 2>{0, 1});
  CHECK(five.parent[3] == std::array<int, 2>{1, 2});
  CHECK(five.parent[4] == std::array<int, 2>{2, -1});
  const detail::CoarseAxis six = detail::coarsen_axis(6);
  CHECK(six.position == std::vector<int>{0, 2, 4, 5});
  CHECK(six.parent[3] == std::array<int, 2>{1, 2});
  CHECK(six.parent[5] == std::array<int, 2>{3, -1});
  CHECK_FALSE(detail::coarsen_axis(2).halves());

  const auto p = make_problem<double>(33);
  MultigridPreconditioner<double> mg;
  mg.analyze(p->system);
  // 33 -> 17 -> 9 -> 5 -> 3 nodes per side, minus the two pinned corners on every level.
  CHECK(mg.level_rows() == std::vector<int>{33 * 33 - 2, 17 * 17 - 2, 9 * 9 - 2, 5 * 5 - 2, 3 * 3 - 2});
}

TEST_CASE("multigrid: prolongation is bilinear interpolation, without the eliminated pins", "[multigrid]") {
  for (PinTreatment pins : {PinTreatment::Filter, PinTreatment::Eliminate}) {
    const auto p = make_problem<double>(17, pins);
    MultigridPreconditioner<double> mg;
    mg.analyze(p->system);
    const Eigen::SparseMatrix<double> prolong = mg.prolongation(1);
    // Coarse values of a linear function of the lattice coordinates (i, j) are interpolated exactly.
    const int nc = 9;
    VectorX<double> coarse(prolong.cols());
    for (int J = 0; J < nc; ++J)
      for (int I = 0; I < nc; ++I) {
        int row = 0;  // coarse rows are numbered like the lattice, skipping eliminated nodes
        for (int k = 0; k < J * nc + I; ++k)
          if (pins == PinTreatment::Filter || !(k == 0 || k == nc - 1)) ++row;
        if (pins == PinTreatment::Eliminate && (J * nc + I == 0 || J * nc + I == nc - 1)) continue;
        coarse.segment<3>(3 * row) << 2.0 * I + 3.0 * J + 1.0, 0.5 * I, -1.0 * J;
      }
    const VectorX<double> fine = prolong * coarse;
    int exact = 0, checked = 0;
    for (int j = 0; j < 17; ++j)
      for (int i = 0; i < 17; ++i) {
        const int row = p->layout.row_of_node[static_cast<std::size_t>(j * 17 + i)];
        if (row < 0) continue;
        // Next to an eliminated pin the interpolation misses that parent (zero correction there).
        const bool near_pin = pins == PinTreatment::Eliminate && j <= 1 && (i <= 1 || i >= 15);
        if (near_pin) continue;
        ++checked;
        const Eigen::Vector3d expected(2.0 * (i / 2.0) + 3.0 * (j / 2.0) + 1.0, 0.5 * (i / 2.0), -1.0 * (j / 2.0));
        if ((fine.segment<3>(3 * row) - expected).norm() < 1e-12) ++exact;
      }
    CHECK(checked > 250);
    CHECK(exact == checked);
  }
}

TEST_CASE("multigrid: coarse operators are the Galerkin products P^T A P", "[multigrid]") {
  const auto p = make_problem<double>(17);
  MultigridPreconditioner<double> mg;
  mg.analyze(p->system);
  REQUIRE(mg.update_in_team(p->system));
  Eigen::MatrixXd fine = p->a.to_dense();
  REQUIRE(mg.level_count() >= 3);
  for (int l = 1; l < mg.level_count(); ++l) {
    const Eigen::MatrixXd prolong = Eigen::MatrixXd(mg.prolongation(l));
    const Eigen::MatrixXd expected = prolong.transpose() * fine * prolong;
    const Eigen::MatrixXd coarse = mg.level_matrix(l).to_dense();
    INFO("level " << l);
    CHECK((coarse - expected).norm() <= 1e-12 * expected.norm());
    fine = coarse;
  }
}

TEST_CASE("multigrid: the V-cycle is a symmetric positive definite operator", "[multigrid]") {
  const auto p = make_problem<double>(33);
  MultigridPreconditioner<double> mg;
  mg.analyze(p->system);
  REQUIRE(mg.update_in_team(p->system));
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const VectorX<double> u = test::random_velocities<double>(p->a.block_rows(), 1.0, seed).reshaped();
    const VectorX<double> v = test::random_velocities<double>(p->a.block_rows(), 1.0, seed + 100).reshaped();
    const VectorX<double> bu = apply(mg, u), bv = apply(mg, v);
    INFO("seed " << seed);
    CHECK(std::abs(u.dot(bv) - v.dot(bu)) <= 1e-12 * std::abs(u.dot(bv)) + 1e-14 * u.norm() * bv.norm());
    CHECK(u.dot(bu) > 0);
  }
}

TEST_CASE("multigrid CG: a handful of iterations at every size, and the direct solve's answer", "[multigrid]") {
  for (int n : {9, 17, 33, 65}) {
    const auto p = make_problem<double>(n);
    const Solve mg = pcg(*p, PreconditionerKind::Multigrid, 1e-8);
    const Solve jacobi = pcg(*p, PreconditionerKind::BlockJacobi, 1e-8);
    EigenLdltSolver<double> direct;
    direct.analyze(p->system);
    VectorX<double> exact = VectorX<double>::Zero(p->b.size());
    REQUIRE(direct.solve(p->system, exact).ok());
    INFO(n << " x " << n << ": multigrid " << mg.status.iterations << " iterations, block Jacobi "
           << jacobi.status.iterations);
    REQUIRE(mg.status.ok());
    CHECK(mg.status.residual <= 1e-8);
    CHECK((mg.x - exact).norm() <= 1e-6 * exact.norm());
    CHECK(mg.status.iterations <= 20);
    CHECK(jacobi.status.iterations >= 3 * mg.status.iterations);
  }
}

TEST_CASE("multigrid CG: filtered pins give the eliminated pins' answer", "[multigrid]") {
  const auto eliminated = make_problem<double>(17, PinTreatment::Eliminate);
  const auto filtered = make_problem<double>(17, PinTreatment::Filter);
  const Solve e = pcg(*eliminated, PreconditionerKind::Multigrid, 1e-10);
  const Solve f = pcg(*filtered, PreconditionerKind::Multigrid, 1e-10, 1);
  REQUIRE(e.status.ok());
  REQUIRE(f.status.ok());
  CHECK(f.status.iterations <= 40);  // weaker coarse correction next to pins kept in the system
  double worst = 0;
  for (int node = 0; node < 17 * 17; ++node) {
    const int re = eliminated->assembler.row_of_node()[static_cast<std::size_t>(node)];
    const int rf = filtered->assembler.row_of_node()[static_cast<std::size_t>(node)];
    if (re < 0) {
      CHECK(f.x.segment<3>(3 * rf).norm() == 0.0);  // pinned: dv held at zero
      continue;
    }
    worst = std::max(worst, (f.x.segment<3>(3 * rf) - e.x.segment<3>(3 * re)).norm());
  }
  CHECK(worst <= 1e-7 * e.x.norm());
}

TEST_CASE("multigrid CG: two threads agree with one, and repeat bitwise", "[multigrid][threads]") {
  const auto p = make_problem<double>(129);  // above the team thresholds: both threads work
  const Solve one = pcg(*p, PreconditionerKind::Multigrid, 1e-8, 1);
  const Solve two = pcg(*p, PreconditionerKind::Multigrid, 1e-8, 2);
  const Solve again = pcg(*p, PreconditionerKind::Multigrid, 1e-8, 2);
  REQUIRE(one.status.ok());
  REQUIRE(two.status.ok());
  CHECK((two.x - one.x).norm() <= 1e-6 * one.x.norm());
  CHECK(two.x == again.x);
  CHECK(two.status.iterations == again.status.iterations);
}

TEST_CASE("multigrid: a grid small enough for one level is solved exactly", "[multigrid]") {
  const auto p = make_problem<double>(3);  // 7 free nodes <= max_direct_rows
  const Solve s = pcg(*p, PreconditionerKind::Multigrid, 1e-10);
  REQUIRE(s.status.ok());
  CHECK(s.status.iterations <= 1);
}

TEST_CASE("multigrid: float", "[multigrid][float]") {
  const auto p = make_problem<float>(17);
  IterativeSettings settings;
  settings.tolerance = 1e-4;
  settings.threads = 1;
  settings.preconditioner = PreconditionerKind::Multigrid;
  PcgSolver<float> solver(settings);
  solver.analyze(p->system);
  VectorX<float> x = VectorX<float>::Zero(p->b.size());
  const SolveStatus status = solver.solve(p->system, x);
  REQUIRE(status.ok());
  CHECK(status.iterations <= 15);
  CHECK((p->b - p->a.to_dense() * x).norm() <= 2e-4f * p->b.norm());
}

TEST_CASE("multigrid: bad set-up is rejected with the parameter's name", "[multigrid][validation]") {
  const auto p = make_problem<double>(9);
  IterativeSettings settings;
  settings.preconditioner = PreconditionerKind::Multigrid;
  PcgSolver<double> no_layout(settings);
  LinearSystem<double> without_layout = p->system;
  without_layout.layout = GridLayout{};
  CHECK_THROWS_WITH(no_layout.analyze(without_layout), Catch::Contains("preconditioner"));
  MultigridPreconditioner<double> mg;
  LinearSystem<double> wrong = p->system;
  wrong.layout.nx = 8;
  CHECK_THROWS_AS(mg.analyze(wrong), std::invalid_argument);
  CHECK_THROWS_WITH(mg.analyze(wrong), Catch::Contains("grid layout"));
  MultigridSettings bad;
  bad.omega = 1.5;
  MultigridPreconditioner<double> bad_omega(bad);
  CHECK_THROWS_WITH(bad_omega.analyze(p->system), Catch::Contains("omega"));
}
