// Every linear solver gives the same dv on the same system; filtered and eliminated pins agree;
// failures are reported, not hidden; opt-in solvers are registered by their headers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "drape/fwd.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/solvers/enable_ldlt.hpp"
#include "drape/solvers/enable_lu.hpp"
#include "drape/solvers/solver_registry.hpp"
#include "support/dense.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// A linear system with its matrix and right-hand side under their short names.
struct System : LinearSystem<double> {
  explicit System(LinearSystem<double> s) : LinearSystem<double>(std::move(s)) {}
  const BlockSparseMatrix<double>& a = matrix;
  const VectorX<double>& b = rhs;
  System(const System& other) : LinearSystem<double>(other) {}
};

/// The implicit system of a deformed, moving 6x6 cloth with two pinned corners (with
/// PinTreatment::Filter, the pinned rows are fixed constraints of the system).
System make_system(JacobianVariant variant, PinTreatment pins = PinTreatment::Eliminate, double dt = 0.01) {
  static const Clothd cloth = [] {
    ClothSpecd spec = test::small_spec<double>(6, 10.0);
    spec.springs = {{2000.0, 2.0}, {800.0, 1.0}, {100.0, 0.5}};
    return Clothd(spec);
  }();
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.2, 3u);
  Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 4u);
  for (int p : cloth.pins().nodes()) v.col(p).setZero();
  JacobianAssembler<double> assembler(cloth, pins, 1);
  LinearSystem<double> s = assembler.make_system();
  assembler.assemble_system(x, v, 0, dt, variant, s);
  return System(std::move(s));
}

VectorX<double> solve_with(LinearSolverKind name, const LinearSystem<double>& s, double tolerance = 1e-10) {
  IterativeSettings settings;
  settings.tolerance = tolerance;
  settings.threads = 1;
  auto solver = make_linear_solver<double>(name, settings);
  solver->analyze(s);
  VectorX<double> x = VectorX<double>::Zero(s.rhs.size());
  const SolveStatus status = solver->solve(s, x);
  INFO(to_string(name) << ": " << to_string(status.error));
  REQUIRE(status.ok());
  CHECK(status.residual <= 1e-9);
  return x;
}

double relative_difference(const VectorX<double>& a, const VectorX<double>& b) { return (a - b).norm() / b.norm(); }

}  // namespace

TEST_CASE("every solver gives the dense solution of the symmetric (SPD) system", "[solvers]") {
  const System s = make_system(JacobianVariant::Spd);
  const VectorX<double> reference = test::solve_general(s.a.to_dense(), s.b);
  for (const LinearSolverKind name : available_solvers()) {
    INFO(to_string(name));
    CHECK(relative_difference(solve_with(name, s), reference) < 1e-8);
  }
}

TEST_CASE("the non-symmetric solvers solve the Exact system", "[solvers]") {
  const System s = make_system(JacobianVariant::Exact);
  const Eigen::MatrixXd dense = s.a.to_dense();
  REQUIRE((dense - dense.transpose()).cwiseAbs().maxCoeff() > 1e-6);
  const VectorX<double> reference = test::solve_general(dense, s.b);
  for (const LinearSolverKind name : available_solvers()) {
    if (solver_info(name).capabilities.symmetric_only) continue;
    INFO(to_string(name));
    CHECK(relative_difference(solve_with(name, s), reference) < 1e-8);
  }
}

TEST_CASE("filtered pins (PCG over all nodes) and eliminated pins give the same dv", "[solvers][pins]") {
  const System eliminated = make_system(JacobianVariant::Spd, PinTreatment::Eliminate);
  const System filtered = make_system(JacobianVariant::Spd, PinTreatment::Filter);
  const Clothd cloth = [] {
    ClothSpecd spec = test::small_spec<double>(6, 10.0);
    return Clothd(spec);
  }();
  REQUIRE(filtered.b.size() == eliminated.b.size() + 3 * cloth.pins().count());
  REQUIRE(filtered.constraints.constrained_rows() == cloth.pins().count());
  const VectorX<double> direct = solve_with(LinearSolverKind::Ldlt, eliminated);
  // PCG multiplies by the edge form on one thread and by block rows otherwise (a team, or a matrix
  // without an edge form): both must apply the filter.
  System blocks_only = filtered;
  blocks_only.edges = EdgeOperator<double>();
  REQUIRE(filtered.edges.valid());
  REQUIRE_FALSE(blocks_only.edges.valid());
  const LinearSystem<double>* const forms[] = {&filtered, &blocks_only};
  for (const std::string name : {"cg", "bicgstab"})
    for (const LinearSystem<double>* a : forms) {
      INFO(name << (a == &blocks_only ? ", block rows" : ", edge form"));
      IterativeSettings settings;
      settings.tolerance = 1e-10;
      auto solver = make_linear_solver<double>(name, settings);
      REQUIRE(solver->capabilities().supports_constraints);
      solver->analyze(*a);
      VectorX<double> x = VectorX<double>::Ones(filtered.b.size());  // a warm start that violates the pins
      const SolveStatus status = solver->solve(*a, x);
      REQUIRE(status.ok());
      // Free rows agree with the eliminated solve, pinned rows are exactly zero.
      VectorX<double> free(direct.size());
      for (int node = 0, r = 0; node < cloth.node_count(); ++node) {
        if (cloth.pins().is_pinned(node)) {
          CHECK(x.segment<3>(3 * node).isZero(0.0));
          continue;
        }
        free.segment<3>(3 * r++) = x.segment<3>(3 * node);
      }
      CHECK(relative_difference(free, direct) < 1e-8);
    }
}

TEST_CASE("CG and LDLT report an indefinite system instead of returning garbage", "[solvers]") {
  // Heavily compressed cloth, Symmetric Jacobian, large dt: indefinite system matrix.
  ClothSpecd spec = test::small_spec<double>(5, 0.0);
  spec.springs = ClothSpecd::default_springs();
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.05, 5u) * 0.4;
  const Matrix3X<double> v = Matrix3X<double>::Zero(3, cloth.node_count());
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<double> system = assembler.make_system();
  const BlockSparseMatrix<double>& a = system.matrix;
  assembler.assemble_system(x, v, 0, 0.05, JacobianVariant::Symmetric, system);
  system.rhs.setOnes();
  for (const std::string name : {"cg", "ldlt"}) {
    auto solver = make_linear_solver<double>(name);
    solver->analyze(system);
    VectorX<double> dv = VectorX<double>::Zero(a.size());
    INFO(name);
    CHECK(solver->solve(system, dv).error == SolveError::NotPositiveDefinite);
  }
}

TEST_CASE("an iterative solver that hits its cap says so", "[solvers]") {
  const System s = make_system(JacobianVariant::Spd, PinTreatment::Eliminate, 0.1);
  for (const std::string name : {"cg", "bicgstab"}) {
    IterativeSettings settings;
    settings.max_iterations = 2;
    auto solver = make_linear_solver<double>(name, settings);
    solver->analyze(s);
    VectorX<double> x = VectorX<double>::Zero(s.b.size());
    const SolveStatus status = solver->solve(s, x);
    INFO(name);
    CHECK(status.error == SolveError::NoConvergence);
    CHECK(status.iterations == 2);
    CHECK(status.residual > 1e-6);
  }
}

TEST_CASE("PCG with two threads agrees with one thread and is reproducible", "[solvers][threads]") {
  // 80 x 80 nodes so that the solver really uses two threads (PcgSolver::min_rows_per_thread).
  ClothSpecd spec = test::small_spec<double>(80, 10.0);
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.1, 3u);
  const Matrix3X<double> v = Matrix3X<double>::Zero(3, cloth.node_count());
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<double> system = assembler.make_system();
  assembler.assemble_system(x, v, 0, 0.01, JacobianVariant::Spd, system);
  const auto run = [&](int threads) {
    IterativeSettings settings;
    settings.threads = threads;
    settings.tolerance = 1e-8;
    PcgSolver<double> cg(settings);
    cg.analyze(system);
    VectorX<double> dv = VectorX<double>::Zero(system.size());
    REQUIRE(cg.solve(system, dv).ok());
    return dv;
  };
  const VectorX<double> one = run(1), two = run(2), two_again = run(2);
  CHECK(relative_difference(two, one) < 1e-7);
  CHECK(two == two_again);
}

TEST_CASE("float PCG agrees with double", "[solvers][float]") {
  const System s = make_system(JacobianVariant::Spd);
  const VectorX<double> reference = solve_with(LinearSolverKind::Ldlt, s);
  // Same system in float.
  ClothSpecf spec = test::small_spec<float>(6, 10.0f);
  spec.springs = {{2000.0f, 2.0f}, {800.0f, 1.0f}, {100.0f, 0.5f}};
  const Clothf cloth(spec);
  const Clothd cloth_d = [] {
    ClothSpecd sd = test::small_spec<double>(6, 10.0);
    return Clothd(sd);
  }();
  const Matrix3X<float> x = test::jiggled_positions(cloth_d, 0.2, 3u).cast<float>();
  Matrix3X<float> v = test::random_velocities<double>(cloth.node_count(), 1.0, 4u).cast<float>();
  for (int p : cloth.pins().nodes()) v.col(p).setZero();
  JacobianAssembler<float> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<float> system = assembler.make_system();
  assembler.assemble_system(x, v, 0, 0.01f, JacobianVariant::Spd, system);
  IterativeSettings settings;
  settings.tolerance = 1e-5;
  for (const std::string name : {"cg", "ldlt"}) {
    auto solver = make_linear_solver<float>(name, settings);
    solver->analyze(system);
    VectorX<float> dv = VectorX<float>::Zero(system.size());
    REQUIRE(solver->solve(system, dv).ok());
    INFO(name);
    CHECK(relative_difference(dv.cast<double>(), reference) < 1e-4);
  }
}

TEST_CASE("the per-spring (edge) mat-vec equals the block-CSR mat-vec", "[solvers][edges]") {
  for (JacobianVariant variant : {JacobianVariant::Spd, JacobianVariant::Exact}) {
    for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
      const System s = make_system(variant, pins);
      REQUIRE(s.edges.valid());
      const VectorX<double> x = VectorX<double>::Random(s.b.size());
      VectorX<double> by_edges(x.size()), by_blocks(x.size());
      s.edges.multiply(x.data(), by_edges.data(), 1);
      VectorX<double> two_threads(x.size());
      s.multiply(x.data(), two_threads.data(), 2);  // the system's product: the edge form, on two threads
      const VectorX<double> dense = s.a.to_dense() * x;
      System blocks_only = s;
      blocks_only.edges.invalidate();
      REQUIRE_FALSE(blocks_only.edges.valid());
      blocks_only.multiply(x.data(), by_blocks.data(), 1);
      INFO(to_string(variant) << ", pins " << int(pins));
      CHECK((by_blocks - dense).cwiseAbs().maxCoeff() < 1e-12 * dense.cwiseAbs().maxCoeff());
      CHECK((by_edges - dense).cwiseAbs().maxCoeff() < 1e-12 * dense.cwiseAbs().maxCoeff());
      CHECK(two_threads == by_edges);
    }
  }
}

TEST_CASE("opt-in solvers: registered by their header, otherwise rejected naming it", "[solvers][registry]") {
  // This program includes enable_ldlt.hpp and enable_lu.hpp: both are registered, for both scalars.
  const std::vector<LinearSolverKind> available = available_solvers();
  for (const std::string name : {"ldlt", "lu"}) {
    INFO(name);
    const LinearSolverKind kind = parse<LinearSolverKind>(name);
    CHECK(std::find(available.begin(), available.end(), kind) != available.end());
    CHECK(std::string(make_linear_solver<double>(name)->name()) == name);
    CHECK(std::string(make_linear_solver<float>(name)->name()) == name);
  }
  // A program that includes neither header: simulated by emptying the registry for a moment.
  auto& registered = detail::registered_opt_ins();
  const auto saved = registered;
  registered[static_cast<std::size_t>(LinearSolverKind::Ldlt)] = false;
  registered[static_cast<std::size_t>(LinearSolverKind::Lu)] = false;
  for (const std::string name : {"ldlt", "lu"}) {
    INFO(name);
    const LinearSolverKind kind = parse<LinearSolverKind>(name);
    bool thrown = false;
    try {
      require_solver_available(kind);
    } catch (const std::invalid_argument& e) {
      thrown = true;
      CHECK_THAT(e.what(), Catch::Contains("solver") && Catch::Contains("drape/solvers/enable_" + name + ".hpp"));
    }
    CHECK(thrown);
    const std::vector<LinearSolverKind> without = available_solvers();
    CHECK(std::find(without.begin(), without.end(), kind) == without.end());
  }
  registered = saved;
  CHECK_THROWS_AS(make_linear_solver<double>("magic"), std::invalid_argument);
}
