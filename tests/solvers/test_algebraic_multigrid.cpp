// The algebraic multigrid preconditioner (algebraic_multigrid.hpp, aggregation_hierarchy.hpp): its
// Galerkin levels and filtered coarse spaces, the symmetric positive definite V-cycle, CG to the
// direct solution with and without constraints, iterations that stay nearly flat as an irregular
// mesh is refined, units that do not matter, and the same bits for any team size. Systems come from
// a lattice cloth (JacobianAssembler) and from a spring cloth on an irregular triangulation. The
// same V-cycle in float inside the double CG (single_precision_algebraic_multigrid.hpp, amg-float).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/core/mesh_generators.hpp"
#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/solvers/algebraic_multigrid.hpp"
#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/pcg.hpp"
#include "drape/solvers/single_precision_algebraic_multigrid.hpp"
#include "drape/solvers/solver_registry.hpp"
#include "support/dense.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// The implicit system of a deformed, moving n x n lattice cloth with the default springs, both
/// top corners pinned, at dt = 1/60 (as in test_multigrid.cpp).
template <class S = double>
struct GridProblem {
  Cloth<S> cloth;
  JacobianAssembler<S> assembler;
  LinearSystem<S> system;

  GridProblem(int n, PinTreatment pins)
      : cloth([n] {
          ClothSpec<S> spec;
          spec.nx = spec.ny = n;
          return spec;
        }()),
        assembler(cloth, pins, 1) {
    system = assembler.make_system();
    assemble();
  }
  void assemble() {
    const Matrix3X<S> x = test::jiggled_positions(cloth, S(0.05), 7u);
    Matrix3X<S> v = test::random_velocities<S>(cloth.node_count(), S(1), 8u);
    for (int p : cloth.pins().nodes()) v.col(p).setZero();
    assembler.assemble_system(x, v, 0, S(1) / S(60), JacobianVariant::Spd, system);
  }
};

/// A spring cloth with no lattice: m x m points over a 3.2 m square, jittered by up to 0.3 of their
/// spacing, each cell cut by a random diagonal, the nodes numbered at random; stretch springs
/// (20000 N/m, 10 N s/m) on the triangles' edges, bending springs (500 N/m, 1 N s/m) across the
/// interior edges, 3 kg/m^2. The implicit matrix M + dt D + dt^2 K (spd variant) at dt = 1/60 of the
/// cloth stretched by 2% and wrinkled, times `scale` (other units); a random right-hand side.
template <class S = double>
struct IrregularProblem {
  LinearSystem<S> system;
  Matrix3X<double> rest;
  int nodes = 0;

  IrregularProblem(int m, unsigned seed, double scale = 1.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const double side = 3.2, h = side / (m - 1), dt = 1.0 / 60;
    nodes = m * m;
    std::vector<int> number(static_cast<std::size_t>(nodes));
    std::iota(number.begin(), number.end(), 0);
    std::shuffle(number.begin(), number.end(), rng);
    const auto node = [&](int i, int j) { return number[static_cast<std::size_t>(j * m + i)]; };
    rest.resize(3, nodes);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const double di = i > 0 && i < m - 1 ? 0.3 * h * u(rng) : 0.0;
        const double dj = j > 0 && j < m - 1 ? 0.3 * h * u(rng) : 0.0;
        rest.col(node(i, j)) << i * h + di, j * h + dj, 0.0;
      }
    std::vector<std::array<int, 3>> triangles;
    for (int j = 0; j + 1 < m; ++j)
      for (int i = 0; i + 1 < m; ++i) {
        const int a = node(i, j), b = node(i + 1, j), c = node(i, j + 1), d = node(i + 1, j + 1);
        if (rng() & 1u) {
          triangles.push_back({a, b, d});
          triangles.push_back({a, d, c});
        } else {
          triangles.push_back({a, b, c});
          triangles.push_back({b, d, c});
        }
      }
    // Each edge once (a stretch spring); an edge of two triangles also joins their opposite corners.
    std::vector<std::array<int, 3>> edges;  // (low, high, opposite corner)
    for (const auto& t : triangles)
      for (int e = 0; e < 3; ++e) {
        const int a = t[static_cast<std::size_t>(e)], b = t[static_cast<std::size_t>((e + 1) % 3)];
        edges.push_back({std::min(a, b), std::max(a, b), t[static_cast<std::size_t>((e + 2) % 3)]});
      }
    std::sort(edges.begin(), edges.end());
    std::vector<std::array<int, 2>> stretch, bend;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      if (k > 0 && edges[k][0] == edges[k - 1][0] && edges[k][1] == edges[k - 1][1])
        bend.push_back({edges[k - 1][2], edges[k][2]});
      else
        stretch.push_back({edges[k][0], edges[k][1]});
    }
    std::vector<double> mass(static_cast<std::size_t>(nodes), 0.0);
    for (const auto& t : triangles) {
      const double area = 0.5 * (rest.col(t[1]) - rest.col(t[0])).cross(rest.col(t[2]) - rest.col(t[0])).norm();
      for (int v : t) mass[static_cast<std::size_t>(v)] += 3.0 * area / 3.0;
    }
    Matrix3X<double> x = rest;
    for (int n = 0; n < nodes; ++n) {
      x(0, n) = 1.02 * x(0, n) + 0.05 * h * u(rng);
      x(1, n) += 0.05 * h * u(rng);
      x(2, n) = 0.05 * std::sin(3 * rest(0, n)) * std::cos(2 * rest(1, n)) + 0.1 * h * u(rng);
    }
    std::vector<std::vector<int>> columns(static_cast<std::size_t>(nodes));
    for (const auto* list : {&stretch, &bend})
      for (const auto& s : *list) {
        columns[static_cast<std::size_t>(s[0])].push_back(s[1]);
        columns[static_cast<std::size_t>(s[1])].push_back(s[0]);
      }
    BlockSparseMatrix<double> a(std::move(columns));
    for (int n = 0; n < nodes; ++n)
      a.block(a.diagonal()[static_cast<std::size_t>(n)]) = mass[static_cast<std::size_t>(n)] * Mat3<double>::Identity();
    for (const auto* list : {&stretch, &bend}) {
      const bool bending = list == &bend;
      const double ks = bending ? 500 : 20000, kd = bending ? 1 : 10;
      for (const auto& s : *list) {
        const int p = s[0], q = s[1];
        const SpringLinearisation<double> l = linearise_spring<double>(
            x.col(p), x.col(q), Vec3<double>::Zero(), Vec3<double>::Zero(), (rest.col(q) - rest.col(p)).norm(), ks, kd,
            JacobianVariant::Spd);
        const Mat3<double> uu = l.u * l.u.transpose();
        const Mat3<double> c = dt * kd * uu + dt * dt * (l.k_uu * uu + l.k_i * Mat3<double>::Identity());
        a.block(a.diagonal()[static_cast<std::size_t>(p)]) += c;
        a.block(a.diagonal()[static_cast<std::size_t>(q)]) += c;
        a.block(a.find(p, q)) -= c;
        a.block(a.find(q, p)) -= c;
      }
    }
    std::vector<std::vector<int>> pattern(static_cast<std::size_t>(nodes));
    for (int r = 0; r < nodes; ++r)
      for (int k = a.row_begin()[static_cast<std::size_t>(r)]; k < a.row_begin()[static_cast<std::size_t>(r) + 1]; ++k)
        pattern[static_cast<std::size_t>(r)].push_back(a.column()[static_cast<std::size_t>(k)]);
    system.matrix = BlockSparseMatrix<S>(std::move(pattern));
    for (int q = 0; q < 9 * a.block_count(); ++q) system.matrix.values()[q] = S(scale * a.values()[q]);
    system.constraints = ConstraintFilter<S>(nodes);
    system.rhs.resize(3 * nodes);
    for (int i = 0; i < 3 * nodes; ++i) system.rhs[i] = S(scale * u(rng));
  }

  /// Pins and contacts: the two corners at x = 0 fixed, every node beyond x = 2 m held on a plane
  /// with normal (0.3, 0, 1) (a floor the cloth lies on), prescribed value 0. `curved`: on a sphere
  /// of radius 20 m instead, so the normals of neighbouring nodes differ by about 0.01 rad.
  void constrain(bool curved = false) {
    const Vec3<double> plane = Vec3<double>(0.3, 0, 1).normalized();
    for (int n = 0; n < nodes; ++n) {
      const Vec3<S> normal =
          (curved ? Vec3<double>(rest.col(n) - Vec3<double>(1.6, 1.6, -20)).normalized() : plane).template cast<S>();
      if (rest(0, n) < 1e-9 && (rest(1, n) < 1e-9 || rest(1, n) > 3.2 - 1e-9))
        system.constraints.fix(n);
      else if (rest(0, n) > 2.0)
        system.constraints.constrain(n, Mat3<S>::Identity() - normal * normal.transpose(), Vec3<S>::Zero());
    }
  }
};

template <class S>
struct Solve {
  VectorX<S> x;
  SolveStatus status;
};

/// CG on `system` with `kind`, from zero.
template <class S>
Solve<S> pcg(const LinearSystem<S>& system, PreconditionerKind kind, double tolerance, int threads = 1,
             const AlgebraicMultigridSettings& amg = {}) {
  IterativeSettings settings;
  settings.tolerance = tolerance;
  settings.threads = threads;
  settings.max_iterations = 20000;
  settings.preconditioner = kind;
  PcgSolver<S> solver(settings, {}, amg);
  solver.analyze(system);
  Solve<S> s{VectorX<S>::Zero(system.size()), {}};
  s.status = solver.solve(system, s.x);
  return s;
}

/// The direct solution (the constraints through the modified system).
VectorX<double> direct(const LinearSystem<double>& system) {
  EigenLdltSolver<double> solver;
  solver.analyze(system);
  VectorX<double> x = VectorX<double>::Zero(system.size());
  REQUIRE(solver.solve(system, x).ok());
  return x;
}

template <class S>
bool update(Preconditioner<S>& amg, const LinearSystem<S>& system, int threads = 1) {
  bool ok = false;
  run_in_team(threads, [&] {
    const bool mine = amg.update_in_team(system);
    if (team_rank() == 0) ok = mine;
  });
  return ok;
}

template <class S>
VectorX<S> apply(Preconditioner<S>& amg, const VectorX<S>& r, int threads = 1) {
  VectorX<S> z(r.size());
  run_in_team(threads, [&] { amg.apply_in_team(r.data(), z.data()); });
  return z;
}

VectorX<double> random_vector(int rows, unsigned seed) {
  return test::random_velocities<double>(rows, 1.0, seed).reshaped();
}

/// The block-diagonal matrix of a level's row filters (projections).
Eigen::MatrixXd filters(const AggregationHierarchy<double>& h, int l) {
  const int rows = h.rows(l);
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(3 * rows, 3 * rows);
  for (int r = 0; r < rows; ++r) s.block<3, 3>(3 * r, 3 * r) = h.filter(l, r);
  return s;
}

}  // namespace

TEST_CASE("amg: aggregates of the lattice cloth are patches of its stretch springs; levels shrink to the direct size",
          "[amg]") {
  GridProblem<double> p(33, PinTreatment::Eliminate);
  AlgebraicMultigrid<double> amg;
  amg.analyze(p.system);
  REQUIRE(amg.built());
  const std::vector<int> rows = amg.level_rows();
  INFO("levels " << ::Catch::Detail::stringify(rows));
  REQUIRE(rows.size() >= 3);
  for (std::size_t l = 1; l < rows.size(); ++l) CHECK(rows[l] * 3 < rows[l - 1]);
  CHECK(rows.back() <= amg.settings().max_direct_rows);
  // Every row is in an aggregate (each has a strong stretch spring); an aggregate's members are
  // joined by structural or shear springs, never only by bending ones two nodes apart.
  const std::vector<int>& of = amg.hierarchy().aggregates(0);
  const std::vector<int>& node_of_row = p.assembler.node_of_row();
  std::vector<std::vector<int>> members(static_cast<std::size_t>(rows[1]));
  for (int r = 0; r < rows[0]; ++r) {
    REQUIRE(of[static_cast<std::size_t>(r)] >= 0);
    const std::size_t aggregate = static_cast<std::size_t>(of[static_cast<std::size_t>(r)]);
    members[aggregate].push_back(node_of_row[static_cast<std::size_t>(r)]);
  }
  for (const std::vector<int>& m : members) {
    REQUIRE(!m.empty());
    CHECK(m.size() <= 13);
    int i0 = 33, i1 = -1, j0 = 33, j1 = -1;
    for (int node : m) {
      i0 = std::min(i0, node % 33);
      i1 = std::max(i1, node % 33);
      j0 = std::min(j0, node / 33);
      j1 = std::max(j1, node / 33);
    }
    CHECK(i1 - i0 <= 4);
    CHECK(j1 - j0 <= 4);
  }
  CHECK(amg.operator_complexity() < 1.5);
}

TEST_CASE("amg: coarse operators are P^T A P filtered, and P moves no constrained direction", "[amg]") {
  // Dense checks on small systems: a lattice cloth with filtered pins, an irregular one with pins
  // and contacts on a plane, and one with contacts on a sphere, whose aggregates have nearly
  // parallel normals: directions all but removed, which the coarse filters remove.
  GridProblem<double> grid(17, PinTreatment::Filter);
  IrregularProblem<double> irregular(16, 5u), curved(16, 5u);
  irregular.constrain();
  curved.constrain(true);
  for (const LinearSystem<double>* system : {&grid.system, &irregular.system, &curved.system}) {
    INFO((system == &grid.system ? "lattice" : system == &irregular.system ? "irregular" : "curved contacts"));
    AlgebraicMultigridSettings settings;
    settings.max_direct_rows = 8;  // three levels or more
    AlgebraicMultigrid<double> amg(settings);
    amg.analyze(*system);
    REQUIRE(update(amg, *system));
    const AggregationHierarchy<double>& h = amg.hierarchy();
    REQUIRE(amg.level_count() >= 3);
    // Level 0 is S A S + I - S.
    const Eigen::MatrixXd s0 = filters(h, 0);
    const Eigen::MatrixXd identity0 = Eigen::MatrixXd::Identity(s0.rows(), s0.cols());
    const Eigen::MatrixXd filtered = s0 * system->matrix.to_dense() * s0 + identity0 - s0;
    CHECK((amg.level_matrix(0).to_dense() - filtered).norm() <= 1e-14 * filtered.norm());
    int constrained_coarse = 0;
    for (int l = 1; l < amg.level_count(); ++l) {
      INFO("level " << l);
      const Eigen::MatrixXd prolong = Eigen::MatrixXd(h.prolongation(l));
      const Eigen::MatrixXd fine_filter = filters(h, l - 1), coarse_filter = filters(h, l);
      const Eigen::MatrixXd coarse_identity = Eigen::MatrixXd::Identity(coarse_filter.rows(), coarse_filter.cols());
      const Eigen::MatrixXd expected =
          prolong.transpose() * amg.level_matrix(l - 1).to_dense() * prolong + coarse_identity - coarse_filter;
      const Eigen::MatrixXd coarse = amg.level_matrix(l).to_dense();
      CHECK((coarse - expected).norm() <= 1e-12 * expected.norm());
      CHECK((coarse - coarse.transpose()).norm() <= 1e-13 * coarse.norm());
      CHECK(test::cholesky_succeeds(coarse));
      // P = S P Pi: nothing into a constrained fine direction, nothing from a removed coarse one.
      CHECK((prolong - fine_filter * prolong).norm() <= 1e-13 * prolong.norm());
      CHECK((prolong - prolong * coarse_filter).norm() <= 1e-13 * prolong.norm());
      for (int r = 0; r < h.rows(l); ++r) constrained_coarse += h.kind(l, r) != ConstraintKind::Free;
    }
    // The contacts reach the coarse levels (the lattice's two pins share aggregates with free nodes).
    if (system != &grid.system) CHECK(constrained_coarse > 0);
  }
}

TEST_CASE("amg: the V-cycle is a symmetric positive definite operator", "[amg]") {
  GridProblem<double> grid(33, PinTreatment::Eliminate);
  IrregularProblem<double> irregular(32, 3u);
  irregular.constrain();
  for (const LinearSystem<double>* system : {&grid.system, &irregular.system}) {
    INFO((system == &grid.system ? "lattice" : "irregular, constrained"));
    AlgebraicMultigrid<double> amg;
    amg.analyze(*system);
    REQUIRE(update(amg, *system));
    for (unsigned seed = 1; seed <= 4; ++seed) {
      INFO("seed " << seed);
      const VectorX<double> u = random_vector(system->block_rows(), seed);
      const VectorX<double> v = random_vector(system->block_rows(), seed + 100);
      const VectorX<double> bu = apply(amg, u), bv = apply(amg, v);
      CHECK(std::abs(u.dot(bv) - v.dot(bu)) <= 1e-12 * (std::abs(u.dot(bv)) + 1e-3 * u.norm() * bv.norm()));
      CHECK(u.dot(bu) > 0);
    }
  }
  // The whole operator, on the directions CG lets through: S B S + I - S is positive definite.
  IrregularProblem<double> small(12, 9u);
  small.constrain();
  AlgebraicMultigridSettings settings;
  settings.max_direct_rows = 4;
  AlgebraicMultigrid<double> amg(settings);
  amg.analyze(small.system);
  REQUIRE(update(amg, small.system));
  REQUIRE(amg.level_count() >= 3);
  const int n = small.system.size();
  Eigen::MatrixXd b(n, n);
  for (int k = 0; k < n; ++k) b.col(k) = apply(amg, VectorX<double>(VectorX<double>::Unit(n, k)));
  CHECK((b - b.transpose()).norm() <= 1e-12 * b.norm());
  const Eigen::MatrixXd s = filters(amg.hierarchy(), 0);
  const Eigen::MatrixXd filtered = s * b * s + Eigen::MatrixXd::Identity(n, n) - s;
  CHECK(test::cholesky_succeeds(0.5 * (filtered + filtered.transpose())));
}

TEST_CASE("amg CG: the direct solution, in a few iterations", "[amg]") {
  for (int n : {9, 17, 33, 65}) {
    for (const PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
      GridProblem<double> p(n, pins);
      const Solve<double> amg = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
      const Solve<double> jacobi = pcg(p.system, PreconditionerKind::BlockJacobi, 1e-10);
      const VectorX<double> exact = direct(p.system);
      INFO(n << " x " << n << (pins == PinTreatment::Filter ? ", filtered pins" : "") << ": amg "
             << amg.status.iterations << " iterations, block Jacobi " << jacobi.status.iterations);
      REQUIRE(amg.status.ok());
      CHECK(amg.status.residual <= 1e-10);
      CHECK((amg.x - exact).norm() <= 1e-8 * exact.norm());
      CHECK(amg.status.iterations <= 40);  // measured 26-28 at every size
      if (n >= 33) CHECK(jacobi.status.iterations >= 5 * amg.status.iterations);
    }
  }
  IrregularProblem<double> irregular(32, 4u);
  const Solve<double> amg = pcg(irregular.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  const VectorX<double> exact = direct(irregular.system);
  REQUIRE(amg.status.ok());
  CHECK((amg.x - exact).norm() <= 1e-8 * exact.norm());
}

TEST_CASE("amg CG: constrained directions keep their values; block-Jacobi CG's and the direct answer", "[amg]") {
  IrregularProblem<double> p(32, 6u);
  p.constrain();
  const ConstraintFilter<double>& c = p.system.constraints;
  REQUIRE(c.constrained_rows() > 200);
  const Solve<double> amg = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  const Solve<double> jacobi = pcg(p.system, PreconditionerKind::BlockJacobi, 1e-10);
  REQUIRE(amg.status.ok());
  REQUIRE(jacobi.status.ok());
  INFO("amg " << amg.status.iterations << " iterations, block Jacobi " << jacobi.status.iterations);
  CHECK(amg.status.iterations * 5 < jacobi.status.iterations);
  int fixed = 0, held = 0;
  for (int r = 0; r < p.nodes; ++r) {
    const Vec3<double> xr = amg.x.segment<3>(3 * r);
    if (c.kind(r) == ConstraintKind::Fixed) {
      CHECK(xr.norm() == 0.0);
      ++fixed;
    } else if (c.kind(r) == ConstraintKind::Projected) {
      CHECK(((Mat3<double>::Identity() - c.filter(r)) * xr).norm() <= 1e-12 * (1 + xr.norm()));
      ++held;
    }
  }
  CHECK(fixed == 2);
  CHECK(held > 200);
  CHECK((amg.x - jacobi.x).norm() <= 1e-7 * jacobi.x.norm());
  CHECK((amg.x - direct(p.system)).norm() <= 1e-7 * jacobi.x.norm());

  // Pins kept in the system under the filter: the eliminated pins' answer.
  GridProblem<double> eliminated(17, PinTreatment::Eliminate), filtered(17, PinTreatment::Filter);
  const Solve<double> e = pcg(eliminated.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  const Solve<double> f = pcg(filtered.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  REQUIRE(e.status.ok());
  REQUIRE(f.status.ok());
  double worst = 0;
  for (int node = 0; node < 17 * 17; ++node) {
    const int re = eliminated.assembler.row_of_node()[static_cast<std::size_t>(node)];
    const int rf = filtered.assembler.row_of_node()[static_cast<std::size_t>(node)];
    if (re < 0) {
      CHECK(f.x.segment<3>(3 * rf).norm() == 0.0);
      continue;
    }
    worst = std::max(worst, (f.x.segment<3>(3 * rf) - e.x.segment<3>(3 * re)).norm());
  }
  CHECK(worst <= 1e-7 * e.x.norm());
}

TEST_CASE("amg CG: iterations stay nearly flat as an irregular mesh is refined from 1k to 16k nodes", "[amg][slow]") {
  // Block Jacobi's count doubles with each refinement (the condition number grows with the node
  // count at a fixed dt); a working V-cycle's grows by a few. Measured (tolerance 1e-8): 32, 38, 47
  // with smoothed aggregation; 92 with plain aggregation at 16k nodes; block Jacobi 247, 500.
  std::vector<int> amg_iterations;
  for (int m : {32, 64, 128}) {
    IrregularProblem<double> p(m, 3u);
    const Solve<double> amg = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8);
    INFO(m * m << " nodes: amg " << amg.status.iterations << " iterations");
    REQUIRE(amg.status.ok());
    CHECK(amg.status.iterations <= 60);
    amg_iterations.push_back(amg.status.iterations);
    if (m <= 64) {
      const Solve<double> jacobi = pcg(p.system, PreconditionerKind::BlockJacobi, 1e-8);
      INFO("block Jacobi " << jacobi.status.iterations << " iterations");
      CHECK(jacobi.status.iterations >= 5 * amg.status.iterations);
    }
    if (m == 128) {
      AlgebraicMultigridSettings plain;
      plain.prolongator_weight = 0;
      const Solve<double> unsmoothed = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8, 1, plain);
      INFO("plain aggregation " << unsmoothed.status.iterations << " iterations");
      CHECK(unsmoothed.status.iterations > 75);
    }
  }
  CHECK(amg_iterations[2] <= amg_iterations[0] + 20);
}

TEST_CASE("amg CG: the units of a constrained system do not change the iterations", "[amg]") {
  // The filtered operator S A S + I - S puts a unit identity on the constrained directions whatever
  // A's scale: the coarse spaces must not see it (filtered prolongator, strength without I - Pi).
  int iterations[2] = {0, 0};
  for (const double scale : {1.0, 1e-4}) {
    IrregularProblem<double> p(32, 3u, scale);
    p.constrain();
    const Solve<double> amg = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8);
    REQUIRE(amg.status.ok());
    iterations[scale == 1.0 ? 0 : 1] = amg.status.iterations;
  }
  INFO("iterations at scale 1: " << iterations[0] << ", at scale 1e-4: " << iterations[1]);
  CHECK(std::abs(iterations[0] - iterations[1]) <= 2);
}

TEST_CASE("amg: one and two threads give the same bits", "[amg][threads]") {
  GridProblem<double> p(129, PinTreatment::Filter);  // levels 0 and 1 above min_team_rows: shared
  // Contacts on a third of the cloth as well.
  const Mat3<double> plane = Mat3<double>::Identity() - Vec3<double>(0, 1, 0) * Vec3<double>(0, 1, 0).transpose();
  for (int r = 0; r < p.system.block_rows() / 3; ++r)
    if (p.system.constraints.kind(r) == ConstraintKind::Free)
      p.system.constraints.constrain(r, plane, Vec3<double>::Zero());
  AlgebraicMultigrid<double> one, two;
  one.analyze(p.system);
  two.analyze(p.system);
  REQUIRE(update(one, p.system, 1));
  REQUIRE(update(two, p.system, 2));
  REQUIRE(one.level_rows() == two.level_rows());
  REQUIRE(two.level_rows()[1] >= two.settings().min_team_rows);
  for (int l = 0; l < one.level_count(); ++l) {
    INFO("level " << l);
    const BlockSparseMatrix<double>& a = one.level_matrix(l);
    const BlockSparseMatrix<double>& b = two.level_matrix(l);
    CHECK(std::equal(a.values(), a.values() + 9 * a.block_count(), b.values()));
    CHECK(one.smoother_omega(l) == two.smoother_omega(l));
  }
  const VectorX<double> r = random_vector(p.system.block_rows(), 21u);
  const VectorX<double> z1 = apply(one, r, 1), z2 = apply(two, r, 2);
  CHECK(z1 == z2);
  CHECK(apply(one, r, 2) == z1);  // and a hierarchy updated by one thread, applied by two
  // CG itself sums its dot products per thread: close, and repeatable for a thread count.
  const Solve<double> s1 = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8, 1);
  const Solve<double> s2 = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8, 2);
  const Solve<double> again = pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8, 2);
  REQUIRE(s1.status.ok());
  REQUIRE(s2.status.ok());
  CHECK((s2.x - s1.x).norm() <= 1e-6 * s1.x.norm());
  CHECK(s2.x == again.x);
}

TEST_CASE("amg: float", "[amg][float]") {
  GridProblem<float> grid(17, PinTreatment::Filter);
  const Solve<float> s = pcg(grid.system, PreconditionerKind::AlgebraicMultigrid, 1e-4);
  REQUIRE(s.status.ok());
  CHECK(s.status.iterations <= 20);
  IrregularProblem<float> single(24, 8u);
  IrregularProblem<double> full(24, 8u);
  single.constrain();
  full.constrain();
  const Solve<float> f = pcg(single.system, PreconditionerKind::AlgebraicMultigrid, 1e-5);
  const Solve<double> d = pcg(full.system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  REQUIRE(f.status.ok());
  REQUIRE(d.status.ok());
  CHECK((f.x.cast<double>() - d.x).norm() <= 1e-3 * d.x.norm());
  AlgebraicMultigrid<float> amg;
  amg.analyze(single.system);
  REQUIRE(update(amg, single.system));
  const VectorX<float> u = random_vector(single.nodes, 1u).cast<float>();
  const VectorX<float> v = random_vector(single.nodes, 2u).cast<float>();
  const VectorX<float> bu = apply(amg, u), bv = apply(amg, v);
  CHECK(std::abs(u.dot(bv) - v.dot(bu)) <= 1e-5f * std::abs(u.dot(bv)));
  CHECK(u.dot(bu) > 0);
}

/// ImplicitEuler analyzes the system of JacobianAssembler::make_system(), all zeros: `late` analyzed
/// so builds its hierarchy at its first update, and must then equal `early`, analyzed assembled.
/// `cycle(p)`: p's AlgebraicMultigrid (double, or the float one inside).
template <class Preconditioner, class Cycle>
void check_analysis_before_values(Cycle&& cycle) {
  GridProblem<double> assembled(33, PinTreatment::Filter);
  Cloth<double> cloth([] {
    ClothSpec<double> spec;
    spec.nx = spec.ny = 33;
    return spec;
  }());
  JacobianAssembler<double> assembler(cloth, PinTreatment::Filter, 1);
  LinearSystem<double> system = assembler.make_system();
  Preconditioner late, early;
  late.analyze(system);
  CHECK_FALSE(cycle(late).built());
  early.analyze(assembled.system);
  CHECK(cycle(early).built());
  Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 8u);
  for (int p : cloth.pins().nodes()) v.col(p).setZero();
  assembler.assemble_system(test::jiggled_positions(cloth, 0.05, 7u), v, 0, 1.0 / 60, JacobianVariant::Spd, system);
  REQUIRE(update(late, system, 2));
  REQUIRE(cycle(late).built());
  REQUIRE(update(early, assembled.system));
  REQUIRE(cycle(late).level_rows() == cycle(early).level_rows());
  const VectorX<double> r = random_vector(system.block_rows(), 5u);
  CHECK(apply(late, r) == apply(early, r));
}

TEST_CASE("amg: a system analyzed before its values gets its hierarchy at the first update", "[amg]") {
  check_analysis_before_values<AlgebraicMultigrid<double>>(
      [](const AlgebraicMultigrid<double>& p) -> const AlgebraicMultigrid<double>& { return p; });
}

TEST_CASE("amg: no strong coupling, or a system small enough for one level", "[amg]") {
  // Block-diagonal: nothing to aggregate; the one level is solved by block Jacobi, exactly here.
  std::vector<std::vector<int>> columns(200);
  LinearSystem<double> diagonal;
  diagonal.matrix = BlockSparseMatrix<double>(columns);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int r = 0; r < 200; ++r) {
    Mat3<double> m;
    for (int q = 0; q < 9; ++q) m.data()[q] = u(rng);
    diagonal.matrix.block(diagonal.matrix.diagonal()[static_cast<std::size_t>(r)]) =
        m * m.transpose() + Mat3<double>::Identity();
  }
  diagonal.rhs = random_vector(200, 4u);
  const Solve<double> d = pcg(diagonal, PreconditionerKind::AlgebraicMultigrid, 1e-12);
  REQUIRE(d.status.ok());
  CHECK(d.status.iterations <= 1);
  GridProblem<double> tiny(3, PinTreatment::Eliminate);  // 7 rows: the coarsest level at once
  const Solve<double> t = pcg(tiny.system, PreconditionerKind::AlgebraicMultigrid, 1e-12);
  REQUIRE(t.status.ok());
  CHECK(t.status.iterations <= 1);
}

TEST_CASE("amg: settings out of range are rejected with their names", "[amg][validation]") {
  GridProblem<double> p(9, PinTreatment::Eliminate);
  const auto rejects = [&](AlgebraicMultigridSettings s, const char* name) {
    AlgebraicMultigrid<double> amg(s);
    CHECK_THROWS_AS(amg.analyze(p.system), InvalidParameter);
    CHECK_THROWS_WITH(amg.analyze(p.system), Catch::Contains(name));
  };
  AlgebraicMultigridSettings s;
  s.strength = 1.5;
  rejects(s, "amg strength");
  s = {};
  s.prolongator_weight = -1;
  rejects(s, "amg prolongator_weight");
  s = {};
  s.sweeps = 0;
  rejects(s, "amg sweeps");
  s = {};
  s.omega = 0;
  rejects(s, "amg omega");
  s = {};
  s.max_direct_rows = 0;
  rejects(s, "amg max_direct_rows");
  s = {};
  s.max_levels = 0;
  rejects(s, "amg max_levels");
  s = {};
  s.spectral_steps = 1;
  rejects(s, "amg spectral_steps");
}

TEST_CASE("amg: chosen by name, needs no lattice, and steps an implicit cloth with contacts", "[amg][integration]") {
  CHECK(parse<PreconditionerKind>("amg") == PreconditionerKind::AlgebraicMultigrid);
  CHECK_FALSE(needs_grid_layout(PreconditionerKind::AlgebraicMultigrid));
  CHECK(needs_grid_layout(PreconditionerKind::MultigridFloat));
  IterativeSettings settings;
  settings.preconditioner = PreconditionerKind::AlgebraicMultigrid;
  const std::unique_ptr<LinearSolver<double>> solver = make_linear_solver<double>("cg", settings);
  const auto* cg = dynamic_cast<const PcgSolver<double>*>(solver.get());
  REQUIRE(cg);
  CHECK(dynamic_cast<const AlgebraicMultigrid<double>*>(&cg->preconditioner()));
  // Without a lattice layout: the geometric multigrid refuses the system, and PCG where it was
  // chosen takes amg, which solves it.
  GridProblem<double> p(17, PinTreatment::Eliminate);
  p.system.layout = GridLayout{};
  MultigridPreconditioner<double> geometric;
  CHECK_THROWS_AS(geometric.analyze(p.system), InvalidParameter);
  settings.preconditioner = PreconditionerKind::Multigrid;
  PcgSolver<double> chosen(settings);
  chosen.analyze(p.system);
  CHECK(dynamic_cast<const AlgebraicMultigrid<double>*>(&chosen.preconditioner()) != nullptr);
  CHECK(pcg(p.system, PreconditionerKind::AlgebraicMultigrid, 1e-8).status.ok());

  // A cloth dropped on a sphere: contacts are projected rows that come and go every step.
  ClothSpec<double> spec;
  spec.nx = spec.ny = 17;
  spec.pinned_nodes = std::vector<int>{};
  spec.colliders.push_back(Collider<double>::sphere(Vec3<double>(0.8, -0.6, 0.8), 0.5));
  const Cloth<double> cloth(spec);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  options.threads = 1;
  options.preconditioner = PreconditionerKind::AlgebraicMultigrid;
  ImplicitEuler<double> integrator(cloth, options);
  State<double> state = cloth.initial_state();
  int most_contacts = 0;
  for (int k = 0; k < 40; ++k) {
    REQUIRE(integrator.step(state).ok());
    most_contacts = std::max(most_contacts, integrator.contact_report().contacts);
  }
  CHECK(most_contacts > 20);
  for (int node = 0; node < cloth.node_count(); ++node)
    CHECK((state.positions.col(node) - Vec3<double>(0.8, -0.6, 0.8)).norm() >= 0.5);
  // The last step's system, with its contacts: block-Jacobi CG's answer.
  const LinearSystem<double>& system = integrator.system();
  int held = 0;
  for (int r = 0; r < system.block_rows(); ++r) held += system.constraints.kind(r) == ConstraintKind::Projected;
  CHECK(held > 20);
  const Solve<double> amg = pcg(system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
  const Solve<double> jacobi = pcg(system, PreconditionerKind::BlockJacobi, 1e-10);
  REQUIRE(amg.status.ok());
  REQUIRE(jacobi.status.ok());
  CHECK((amg.x - jacobi.x).norm() <= 1e-7 * jacobi.x.norm());
}

TEST_CASE("amg-float: CG reaches the double tolerance and the direct answer in amg's iterations", "[amg][mixed]") {
  // The float V-cycle inside the double CG: CG's residual, iterate and product with A stay double,
  // so it stops at the same tolerance; the cycle's rounding may cost an iteration or two.
  IrregularProblem<double> irregular(32, 6u);
  irregular.constrain();
  GridProblem<double> grid(33, PinTreatment::Filter);
  for (const LinearSystem<double>* system : {&irregular.system, &grid.system}) {
    const Solve<double> mixed = pcg(*system, PreconditionerKind::AlgebraicMultigridFloat, 1e-10);
    const Solve<double> full = pcg(*system, PreconditionerKind::AlgebraicMultigrid, 1e-10);
    INFO((system == &grid.system ? "lattice, filtered pins" : "irregular, pins and contacts")
         << ": amg-float " << mixed.status.iterations << " iterations, amg " << full.status.iterations);
    REQUIRE(mixed.status.ok());
    REQUIRE(full.status.ok());
    CHECK(mixed.status.residual <= 1e-10);  // CG's residual, in double
    CHECK(mixed.status.iterations <= full.status.iterations + 2);
    const VectorX<double> exact = direct(*system);
    CHECK((mixed.x - exact).norm() <= 1e-7 * exact.norm());
    const ConstraintFilter<double>& c = system->constraints;
    int constrained = 0;
    for (int r = 0; r < system->block_rows(); ++r) {
      const Vec3<double> xr = mixed.x.segment<3>(3 * r);
      if (c.kind(r) == ConstraintKind::Fixed) CHECK(xr.norm() == 0.0);
      if (c.kind(r) == ConstraintKind::Projected)
        CHECK(((Mat3<double>::Identity() - c.filter(r)) * xr).norm() <= 1e-12 * (1 + xr.norm()));
      constrained += c.kind(r) != ConstraintKind::Free;
    }
    CHECK(constrained >= 2);
  }
}

TEST_CASE("amg-float: the float cycle is amg's to float accuracy, symmetric and positive definite",
          "[amg][mixed]") {
  IrregularProblem<double> p(32, 3u);
  p.constrain();
  AlgebraicMultigrid<double> full;
  SinglePrecisionAlgebraicMultigrid<double> mixed;
  full.analyze(p.system);
  mixed.analyze(p.system);
  REQUIRE(mixed.cycle().built());  // aggregated from the rounded values at analyze()
  REQUIRE(update(full, p.system));
  REQUIRE(update(mixed, p.system));
  REQUIRE(mixed.cycle().level_rows() == full.level_rows());
  REQUIRE(mixed.single_system().constraints.constrained_rows() == p.system.constraints.constrained_rows());
  for (unsigned seed = 1; seed <= 3; ++seed) {
    INFO("seed " << seed);
    const VectorX<double> u = random_vector(p.nodes, seed), v = random_vector(p.nodes, seed + 100);
    const VectorX<double> bu = apply(mixed, u), bv = apply(mixed, v);
    const VectorX<double> exact = apply(full, u);
    CHECK((bu - exact).norm() <= 1e-4 * exact.norm());
    CHECK((bu - exact).norm() > 0);  // it did run in float
    CHECK(std::abs(u.dot(bv) - v.dot(bu)) <= 1e-5 * std::abs(u.dot(bv)));
    CHECK(u.dot(bu) > 0);
  }
}

TEST_CASE("amg-float: one and two threads give the same bits", "[amg][mixed][threads]") {
  // Eliminated pins: the fine level reads the float edge form; filtered pins and contacts on a
  // third of the cloth: the filtered block rows. Levels 0 and 1 are shared by the team.
  for (const PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    GridProblem<double> p(129, pins);
    if (pins == PinTreatment::Filter) {
      const Mat3<double> plane = Mat3<double>::Identity() - Vec3<double>(0, 1, 0) * Vec3<double>(0, 1, 0).transpose();
      for (int r = 0; r < p.system.block_rows() / 3; ++r)
        if (p.system.constraints.kind(r) == ConstraintKind::Free)
          p.system.constraints.constrain(r, plane, Vec3<double>::Zero());
    }
    INFO((pins == PinTreatment::Filter ? "filtered pins and contacts" : "eliminated pins"));
    SinglePrecisionAlgebraicMultigrid<double> one, two;
    one.analyze(p.system);
    two.analyze(p.system);
    REQUIRE(update(one, p.system, 1));
    REQUIRE(update(two, p.system, 2));
    CHECK(two.single_system().edges.valid() == (pins == PinTreatment::Eliminate));
    REQUIRE(one.cycle().level_rows() == two.cycle().level_rows());
    REQUIRE(two.cycle().level_rows()[1] >= two.cycle().settings().min_team_rows);
    for (int l = 0; l < one.cycle().level_count(); ++l) {
      INFO("level " << l);
      const BlockSparseMatrix<float>& a = one.cycle().level_matrix(l);
      const BlockSparseMatrix<float>& b = two.cycle().level_matrix(l);
      CHECK(std::equal(a.values(), a.values() + 9 * a.block_count(), b.values()));
      CHECK(one.cycle().smoother_omega(l) == two.cycle().smoother_omega(l));
    }
    const VectorX<double> r = random_vector(p.system.block_rows(), 21u);
    const VectorX<double> z1 = apply(one, r, 1);
    CHECK(apply(two, r, 2) == z1);
    CHECK(apply(one, r, 2) == z1);
    const Solve<double> s2 = pcg(p.system, PreconditionerKind::AlgebraicMultigridFloat, 1e-8, 2);
    const Solve<double> again = pcg(p.system, PreconditionerKind::AlgebraicMultigridFloat, 1e-8, 2);
    REQUIRE(s2.status.ok());
    CHECK(s2.x == again.x);
  }
}

TEST_CASE("amg-float: a system analyzed before its values gets the hierarchy of one analyzed after", "[amg][mixed]") {
  check_analysis_before_values<SinglePrecisionAlgebraicMultigrid<double>>(
      [](const SinglePrecisionAlgebraicMultigrid<double>& p) -> const AlgebraicMultigrid<float>& { return p.cycle(); });
}

TEST_CASE("amg-float: chosen by name, and what a mesh cloth gets for the float geometric multigrid",
          "[amg][mixed][integration]") {
  CHECK(parse<PreconditionerKind>("amg-float") == PreconditionerKind::AlgebraicMultigridFloat);
  CHECK_FALSE(needs_grid_layout(PreconditionerKind::AlgebraicMultigridFloat));
  IterativeSettings settings;
  settings.preconditioner = PreconditionerKind::AlgebraicMultigridFloat;
  const std::unique_ptr<LinearSolver<double>> solver = make_linear_solver<double>("cg", settings);
  const auto* cg = dynamic_cast<const PcgSolver<double>*>(solver.get());
  REQUIRE(cg);
  CHECK(dynamic_cast<const SinglePrecisionAlgebraicMultigrid<double>*>(&cg->preconditioner()));
  PcgSolver<float> single(settings);  // already in float: the plain cycle
  CHECK(dynamic_cast<const AlgebraicMultigrid<float>*>(&single.preconditioner()));
  // Without a lattice layout the geometric kinds give way: multigrid to amg, multigrid-float to
  // amg-float.
  GridProblem<double> p(17, PinTreatment::Eliminate);
  p.system.layout = GridLayout{};
  for (const PreconditionerKind geometric : {PreconditionerKind::Multigrid, PreconditionerKind::MultigridFloat}) {
    settings.preconditioner = geometric;
    PcgSolver<double> chosen(settings);
    chosen.analyze(p.system);
    const bool float_cycle = dynamic_cast<const SinglePrecisionAlgebraicMultigrid<double>*>(&chosen.preconditioner());
    const bool double_cycle = dynamic_cast<const AlgebraicMultigrid<double>*>(&chosen.preconditioner());
    CHECK(float_cycle == (geometric == PreconditionerKind::MultigridFloat));
    CHECK(double_cycle == (geometric == PreconditionerKind::Multigrid));
  }

  // A disk mesh of about 2300 vertices hanging from two pins, its default solver against amg: the
  // fine level is shared by the team and reads the float edge form.
  ClothSpec<double> spec;
  spec.mesh = disk_mesh(1.0, 0.04);
  spec.areal_density = 3.0;
  spec.springs.shear = {0, 0};
  spec.pinned_nodes = std::vector<int>{0, 1};
  const Cloth<double> cloth(spec);
  REQUIRE(cloth.node_count() >= AlgebraicMultigridSettings{}.min_team_rows);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  options.threads = 1;
  ImplicitEuler<double> mixed(cloth, options);
  options.preconditioner = PreconditionerKind::AlgebraicMultigrid;
  ImplicitEuler<double> full(cloth, options);
  State<double> a = cloth.initial_state(), b = cloth.initial_state();
  int mixed_iterations = 0, full_iterations = 0;
  for (int k = 0; k < 6; ++k) {
    const StepStatus sa = mixed.step(a), sb = full.step(b);
    REQUIRE(sa.ok());
    REQUIRE(sb.ok());
    mixed_iterations += sa.iterations;
    full_iterations += sb.iterations;
  }
  const auto* mesh_cg = dynamic_cast<const PcgSolver<double>*>(&mixed.solver());
  REQUIRE(mesh_cg);
  const auto* chosen = dynamic_cast<const SinglePrecisionAlgebraicMultigrid<double>*>(&mesh_cg->preconditioner());
  REQUIRE(chosen);
  CHECK(chosen->single_system().edges.valid());
  const double apart = (a.positions - b.positions).norm();
  const double moved = (b.positions - cloth.initial_state().positions).norm();
  INFO("amg-float " << mixed_iterations << " iterations in 6 steps, amg " << full_iterations
                    << "; positions apart " << apart << " m, moved " << moved << " m");
  CHECK(mixed_iterations <= full_iterations + 6);
  CHECK(apart <= 1e-5 * moved);  // measured 2.7e-7: CG stops at 1e-6 of the residual
  CHECK(apart > 0);  // the float cycle did run
}
