// The multigrid preconditioner (multigrid.hpp): its hierarchy, the Galerkin operators, the symmetry
// and definiteness CG relies on, and the iteration counts that are its reason to exist.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/core/instruction_set_choice.hpp"
#include "drape/fwd.hpp"
#include "drape/physics/air.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/multigrid.hpp"
#include "drape/solvers/pcg.hpp"
#include "drape/solvers/single_precision_multigrid.hpp"
#include "support/dense.hpp"
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

/// A with every coupling of rows two apart along a lattice line, whose row between them is in the
/// system, replaced by two couplings of twice the block through that row (dense, pair by pair: the
/// operator the hierarchy's level 1 is summed from).
Eigen::MatrixXd routed_dense(const Eigen::MatrixXd& a, const GridLayout& layout) {
  Eigen::MatrixXd routed = a;
  const auto row = [&](int i, int j) {
    return i < 0 || j < 0 || i >= layout.nx || j >= layout.ny
               ? -1
               : layout.row_of_node[static_cast<std::size_t>(j * layout.nx + i)];
  };
  for (int j = 0; j < layout.ny; ++j)
    for (int i = 0; i < layout.nx; ++i)
      for (const auto& [di, dj] : {std::pair{2, 0}, std::pair{-2, 0}, std::pair{0, 2}, std::pair{0, -2}}) {
        const int r = row(i, j), c = row(i + di, j + dj), m = row(i + di / 2, j + dj / 2);
        if (r < 0 || c < 0 || m < 0) continue;
        const Eigen::Matrix3d b = a.block<3, 3>(3 * r, 3 * c);
        routed.block<3, 3>(3 * r, 3 * c) -= b;
        routed.block<3, 3>(3 * r, 3 * m) += 2 * b;
        routed.block<3, 3>(3 * m, 3 * c) += 2 * b;
        routed.block<3, 3>(3 * r, 3 * r) -= 0.5 * (b + b.transpose());
        routed.block<3, 3>(3 * m, 3 * m) -= b + b.transpose();
      }
  return routed;
}

/// S a S + I - S for p's constraints (dense).
Eigen::MatrixXd filtered_dense(const Eigen::MatrixXd& a, const LinearSystem<double>& system) {
  const int rows = system.block_rows();
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(3 * rows, 3 * rows);
  for (int r = 0; r < rows; ++r) s.block<3, 3>(3 * r, 3 * r) = system.constraints.filter(r);
  return s * a * s + Eigen::MatrixXd::Identity(3 * rows, 3 * rows) - s;
}

/// Checks that every level l >= 1 of `mg` is P^T A_{l-1} P, starting from `fine` for level 0 (dense
/// products); returns the most blocks in a row of each level >= 1.
std::vector<int> check_galerkin_levels(const MultigridPreconditioner<double>& mg, Eigen::MatrixXd fine) {
  std::vector<int> widest;
  for (int l = 1; l < mg.level_count(); ++l) {
    const Eigen::MatrixXd prolong = Eigen::MatrixXd(mg.prolongation(l));
    const Eigen::MatrixXd expected = prolong.transpose() * fine * prolong;
    const Eigen::MatrixXd coarse = mg.level_matrix(l).to_dense();
    INFO("level " << l);
    CHECK((coarse - expected).norm() <= 1e-12 * expected.norm());
    const std::vector<int>& rb = mg.level_matrix(l).row_begin();
    int most = 0;
    for (std::size_t r = 0; r + 1 < rb.size(); ++r) most = std::max(most, rb[r + 1] - rb[r]);
    widest.push_back(most);
    fine = coarse;
  }
  return widest;
}

TEST_CASE("multigrid: coarse operators are the Galerkin products P^T A P", "[multigrid]") {
  const auto p = make_problem<double>(17);
  MultigridSettings settings;
  settings.route_through_midpoints = false;
  MultigridPreconditioner<double> mg(settings);
  mg.analyze(p->system);
  REQUIRE(mg.update_in_team(p->system));
  REQUIRE(mg.level_count() >= 3);
  const std::vector<int> widest = check_galerkin_levels(mg, p->a.to_dense());
  CHECK(widest[0] > 9);  // unrouted, level 1 couples nodes two coarse lines apart
}

TEST_CASE("multigrid: the routed operator keeps A's energy for linear motion and reaches one node", "[multigrid]") {
  for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    const auto p = make_problem<double>(17, pins);
    MultigridHierarchy<double> hierarchy;
    hierarchy.analyze(p->layout, p->a, 16, true);
    REQUIRE(hierarchy.routed());
    hierarchy.route(p->a, false);
    const Eigen::MatrixXd a = p->a.to_dense(), routed = hierarchy.routed_matrix().to_dense();
    INFO((pins == PinTreatment::Filter ? "filtered" : "eliminated") << " pins");
    CHECK((routed - routed_dense(a, p->layout)).norm() <= 1e-13 * a.norm());
    CHECK((routed - routed.transpose()).norm() <= 1e-14 * a.norm());
    CHECK(test::cholesky_succeeds(routed));
    // Motion linear in the lattice coordinates (each component its own gradient): the same energy
    // and the same forces on interior rows; a random motion has a different energy.
    VectorX<double> linear(a.rows());
    for (int j = 0; j < 17; ++j)
      for (int i = 0; i < 17; ++i) {
        const int r = p->layout.row_of_node[static_cast<std::size_t>(j * 17 + i)];
        if (r >= 0) linear.segment<3>(3 * r) << 0.3 * i - 0.1 * j + 1.0, 0.2 * j, -0.05 * i + 0.7;
      }
    const double energy = linear.dot(a * linear);
    CHECK(std::abs(linear.dot(routed * linear) - energy) <= 1e-12 * std::abs(energy));
    VectorX<double> constant = VectorX<double>::Zero(a.rows());
    for (int r = 0; r < p->a.block_rows(); ++r) constant.segment<3>(3 * r) << 1.0, -2.0, 0.5;
    CHECK((routed * constant - a * constant).norm() <= 1e-12 * (a * constant).norm());  // row sums
    const VectorX<double> random = test::random_velocities<double>(p->a.block_rows(), 1.0, 3u).reshaped();
    CHECK(std::abs(random.dot(routed * random) - random.dot(a * random)) > 1e-6 * random.dot(a * random));
    // Couplings to the 8 neighbours only: at most 9 blocks per row, against 13 in A.
    int widest = 0, widest_a = 0;
    for (int r = 0; r < p->a.block_rows(); ++r) {
      widest = std::max(widest, hierarchy.routed_matrix().row_begin()[static_cast<std::size_t>(r) + 1] -
                                    hierarchy.routed_matrix().row_begin()[static_cast<std::size_t>(r)]);
      widest_a = std::max(
          widest_a, p->a.row_begin()[static_cast<std::size_t>(r) + 1] - p->a.row_begin()[static_cast<std::size_t>(r)]);
    }
    CHECK(widest == 9);
    CHECK(widest_a == 13);
  }
}

TEST_CASE("multigrid: routed, the levels are P^T A' P (S A' S + I - S under a filter), 9 blocks per row",
          "[multigrid]") {
  for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    const auto p = make_problem<double>(17, pins);
    INFO((pins == PinTreatment::Filter ? "filtered" : "eliminated") << " pins");
    REQUIRE(p->system.constraints.empty() == (pins == PinTreatment::Eliminate));
    MultigridPreconditioner<double> mg;  // routes by default
    mg.analyze(p->system);
    REQUIRE(mg.hierarchy().routed());
    REQUIRE(mg.update_in_team(p->system));
    Eigen::MatrixXd fine = routed_dense(p->a.to_dense(), p->layout);
    if (pins == PinTreatment::Filter) fine = filtered_dense(fine, p->system);
    REQUIRE(mg.level_count() >= 3);
    const std::vector<int> widest = check_galerkin_levels(mg, fine);
    CHECK(widest[0] == 9);
    CHECK(*std::max_element(widest.begin(), widest.end()) == 9);
  }
}

TEST_CASE("multigrid CG: routing keeps the iterations", "[multigrid]") {
  for (int n : {33, 65}) {
    const auto p = make_problem<double>(n);
    IterativeSettings settings;
    settings.tolerance = 1e-6;
    settings.threads = 1;
    settings.preconditioner = PreconditionerKind::Multigrid;
    int iterations[2] = {0, 0};
    for (bool route : {false, true}) {
      MultigridSettings mg;
      mg.route_through_midpoints = route;
      PcgSolver<double> solver(settings, mg);
      solver.analyze(p->system);
      VectorX<double> x = VectorX<double>::Zero(p->b.size());
      const SolveStatus status = solver.solve(p->system, x);
      REQUIRE(status.ok());
      iterations[route ? 1 : 0] = status.iterations;
    }
    INFO(n << " x " << n << ": " << iterations[0] << " iterations unrouted, " << iterations[1] << " routed");
    CHECK(iterations[1] <= iterations[0] + 1);
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

TEST_CASE("multigrid-float: a float V-cycle in the double solve keeps its accuracy and its iterations",
          "[multigrid][mixed]") {
  for (const PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter})
    for (int n : {17, 33, 65}) {
      const auto p = make_problem<double>(n, pins);
      const Solve mixed = pcg(*p, PreconditionerKind::MultigridFloat, 1e-9);
      const Solve full = pcg(*p, PreconditionerKind::Multigrid, 1e-9);
      EigenLdltSolver<double> direct;
      direct.analyze(p->system);
      VectorX<double> exact = VectorX<double>::Zero(p->b.size());
      REQUIRE(direct.solve(p->system, exact).ok());
      INFO(n << " x " << n << (pins == PinTreatment::Filter ? ", filtered pins" : "") << ": float cycle "
             << mixed.status.iterations << " iterations, double cycle " << full.status.iterations);
      REQUIRE(mixed.status.ok());
      CHECK(mixed.status.residual <= 1e-9);  // CG's residual, in double
      CHECK((mixed.x - exact).norm() <= 1e-7 * exact.norm());
      CHECK(mixed.status.iterations <= full.status.iterations + 1);
      if (pins == PinTreatment::Filter)
        for (int node : p->cloth.pins().nodes())
          CHECK(mixed.x.segment<3>(3 * p->assembler.row_of_node()[static_cast<std::size_t>(node)]).norm() == 0.0);
    }
}

TEST_CASE("multigrid-float: the float cycle is the double cycle to float accuracy, and symmetric",
          "[multigrid][mixed]") {
  for (const PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    const auto p = make_problem<double>(33, pins);
    MultigridPreconditioner<double> full;
    SinglePrecisionMultigrid<double> mixed;
    full.analyze(p->system);
    mixed.analyze(p->system);
    REQUIRE(full.update_in_team(p->system));
    REQUIRE(mixed.update_in_team(p->system));
    REQUIRE(mixed.cycle().level_rows() == full.level_rows());
    REQUIRE(mixed.single_system().edges.valid());  // the float fine level uses the edge form too
    const auto mixed_apply = [&](const VectorX<double>& r) {
      VectorX<double> z(r.size());
      mixed.apply_in_team(r.data(), z.data());
      return z;
    };
    for (unsigned seed = 1; seed <= 3; ++seed) {
      INFO((pins == PinTreatment::Filter ? "filtered pins, " : "") << "seed " << seed);
      const VectorX<double> u = test::random_velocities<double>(p->a.block_rows(), 1.0, seed).reshaped();
      const VectorX<double> v = test::random_velocities<double>(p->a.block_rows(), 1.0, seed + 100).reshaped();
      const VectorX<double> bu = mixed_apply(u), bv = mixed_apply(v);
      const VectorX<double> exact = apply(full, u);
      CHECK((bu - exact).norm() <= 1e-5 * exact.norm());
      CHECK((bu - exact).norm() > 0);  // it did run in float
      CHECK(std::abs(u.dot(bv) - v.dot(bu)) <= 1e-5 * std::abs(u.dot(bv)));
      CHECK(u.dot(bu) > 0);
    }
  }
}

TEST_CASE("multigrid-float: level 1 is the double level 1 rounded once, the fine smoother the rounded diagonal",
          "[multigrid][mixed]") {
  // Without constraints the float cycle reads the fine block rows only on the diagonal (the
  // smoother), and sums level 1 in double from the double matrix: each of its values is the double
  // cycle's, rounded (the Galerkin weights are dyadic: exact in float). With filtered pins the
  // whole matrix is rounded and level 1 summed from it in float: close, not equal.
  struct Restore {
    InstructionSet saved = instruction_set();
    ~Restore() { use_instruction_set(saved); }
  } restore;
  for (const InstructionSet set : {InstructionSet::Baseline, detected_instruction_set()})
    for (const bool route : {true, false})
      for (const PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
        INFO((set == InstructionSet::Avx2 ? "AVX2" : "baseline") << (route ? ", routed" : ", not routed")
                                                                   << (pins == PinTreatment::Filter ? ", filtered pins" : ""));
        use_instruction_set(set);
        const auto p = make_problem<double>(33, pins);
        MultigridSettings settings;
        settings.route_through_midpoints = route;
        MultigridPreconditioner<double> full(settings);
        SinglePrecisionMultigrid<double> mixed(settings);
        full.analyze(p->system);
        mixed.analyze(p->system);
        REQUIRE(full.update_in_team(p->system));
        REQUIRE(mixed.update_in_team(p->system));
        REQUIRE(mixed.cycle().level_count() > 2);
        const BlockSparseMatrix<double>& a1 = full.level_matrix(1);
        const BlockSparseMatrix<float>& s1 = mixed.cycle().level_matrix(1);
        REQUIRE(s1.block_count() == a1.block_count());
        int rounded_once = 0;
        double worst = 0, largest = 0;
        for (int q = 0; q < 9 * a1.block_count(); ++q) {
          rounded_once += s1.values()[q] == static_cast<float>(a1.values()[q]);
          worst = std::max(worst, std::abs(double(s1.values()[q]) - a1.values()[q]));
          largest = std::max(largest, std::abs(a1.values()[q]));
        }
        if (pins == PinTreatment::Eliminate)
          CHECK(rounded_once == 9 * a1.block_count());
        else
          CHECK(rounded_once < 9 * a1.block_count());
        CHECK(worst <= 1e-6 * largest);
        const BlockSparseMatrix<float>& fine = mixed.single_system().matrix;
        for (int r = 0; r < p->a.block_rows(); ++r) {
          const int k = p->a.diagonal()[static_cast<std::size_t>(r)];
          for (int q = 0; q < 9; ++q) REQUIRE(fine.values()[9 * k + q] == static_cast<float>(p->a.values()[9 * k + q]));
        }
      }
}

TEST_CASE("multigrid-float: the float copy keeps the air's blocks on the diagonal", "[multigrid][mixed][air]") {
  // Linear drag and aerodynamic forces put a 3x3 block on every row of the edge form (about a
  // quarter of the mass here): a float copy without them would precondition another matrix.
  ClothSpec<double> spec;
  spec.nx = spec.ny = 17;
  AirSettings air;
  air.wind = {5, 0, 2};
  air.drag = 0.5;
  air.aerodynamics.drag_coefficient = 1.2;
  air.aerodynamics.lift_coefficient = 0.5;
  spec.force_terms = air_force_terms<double>(air, Gridd(spec.nx, spec.ny, spec.spacing, spec.node_mass).triangles());
  const Cloth<double> cloth(spec);
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<double> system = assembler.make_system();
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 9u);
  assembler.assemble_system(test::jiggled_positions(cloth, 0.05, 10u), v, 0, 1.0 / 60, JacobianVariant::Spd, system);
  REQUIRE(system.edges.valid());
  REQUIRE(system.edges.uses_row_blocks());
  MultigridPreconditioner<double> full;
  SinglePrecisionMultigrid<double> mixed;
  full.analyze(system);
  mixed.analyze(system);
  REQUIRE(full.update_in_team(system));
  REQUIRE(mixed.update_in_team(system));
  REQUIRE(mixed.single_system().edges.uses_row_blocks());
  const VectorX<double> r = test::random_velocities<double>(system.block_rows(), 1.0, 11u).reshaped();
  VectorX<double> z(r.size());
  mixed.apply_in_team(r.data(), z.data());
  const VectorX<double> exact = apply(full, r);
  CHECK((z - exact).norm() <= 1e-5 * exact.norm());
}

TEST_CASE("multigrid-float: two threads agree with one, and repeat bitwise", "[multigrid][mixed][threads]") {
  const auto p = make_problem<double>(129);
  const Solve one = pcg(*p, PreconditionerKind::MultigridFloat, 1e-8, 1);
  const Solve two = pcg(*p, PreconditionerKind::MultigridFloat, 1e-8, 2);
  const Solve again = pcg(*p, PreconditionerKind::MultigridFloat, 1e-8, 2);
  REQUIRE(one.status.ok());
  REQUIRE(two.status.ok());
  CHECK((two.x - one.x).norm() <= 1e-6 * one.x.norm());
  CHECK(two.x == again.x);
  CHECK(two.status.iterations == again.status.iterations);
}

TEST_CASE("multigrid: bad set-up is rejected with the parameter's name", "[multigrid][validation]") {
  const auto p = make_problem<double>(9);
  IterativeSettings settings;
  settings.preconditioner = PreconditionerKind::Multigrid;
  LinearSystem<double> without_layout = p->system;
  without_layout.layout = GridLayout{};
  MultigridPreconditioner<double> alone;
  CHECK_THROWS_WITH(alone.analyze(without_layout), Catch::Contains("preconditioner"));
  // PCG takes the algebraic multigrid instead (a cloth that is not a grid).
  PcgSolver<double> no_layout(settings);
  no_layout.analyze(without_layout);
  CHECK(dynamic_cast<const AlgebraicMultigrid<double>*>(&no_layout.preconditioner()) != nullptr);
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
