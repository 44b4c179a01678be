// Air: the wind field, linear drag and per-triangle aerodynamic drag and lift (physics/air.hpp).
// Derivatives against central finite differences, analytic plate forces, the terminal velocity
// of a falling cloth in a side wind in both integrators, a flag in gusty wind at dt = 1/60, and
// determinism.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/physics/air.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/platform/team.hpp"
#include "support/dense.hpp"
#include "test_common.hpp"

using namespace drape;
using Dense = Eigen::MatrixXd;

namespace {

GustSettings strong_gusts(std::uint64_t seed = 7) {
  GustSettings g;
  g.amplitude = 3.0;
  g.period = 1.5;
  g.wavelength = 2.0;
  g.seed = seed;
  return g;
}

/// A damped 5x5 cloth (all nodes free unless pinned below) with `terms`.
Clothd cloth_with(std::vector<std::shared_ptr<const ForceTerm<double>>> terms, bool pinned = false) {
  ClothSpecd spec = test::small_spec<double>(5, 10.0);
  spec.springs = {{300.0, 2.0}, {200.0, 1.5}, {50.0, 0.5}};
  if (!pinned) spec.pinned_nodes = std::vector<int>{};
  spec.force_terms = std::move(terms);
  return Clothd(spec);
}

void jacobians(const Clothd& cloth, const Matrix3X<double>& x, const Matrix3X<double>& v, JacobianVariant variant,
               Dense& dfdx, Dense& dfdv) {
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
  assembler.assemble_jacobians(x, v, 0.3, variant, kx, kv);
  dfdx = kx.to_dense();
  dfdv = kv.to_dense();
}

}  // namespace

TEST_CASE("wind field: deterministic per seed, bounded gusts, exact gradient", "[air][wind]") {
  const Vec3<double> mean(4, 0, 1);
  const WindField<double> a(mean, strong_gusts(7)), b(mean, strong_gusts(7)), c(mean, strong_gusts(8));
  const WindField<double> steady(mean);
  CHECK(steady.uniform());
  CHECK_FALSE(a.uniform());
  double max_gust = 0, max_difference = 0;
  for (int k = 0; k < 200; ++k) {
    const Vec3<double> x(0.1 * k, std::sin(0.3 * k), -0.05 * k);
    const double t = 0.013 * k;
    CHECK(a.velocity(x, t) == b.velocity(x, t));
    max_difference = std::max(max_difference, (a.velocity(x, t) - c.velocity(x, t)).norm());
    max_gust = std::max(max_gust, (a.velocity(x, t) - mean).norm());
    CHECK(steady.velocity(x, t) == mean);
    Mat3<double> fd;
    const double h = 1e-6;
    for (int d = 0; d < 3; ++d) {
      Vec3<double> xp = x, xm = x;
      xp[d] += h;
      xm[d] -= h;
      fd.col(d) = (a.velocity(xp, t) - a.velocity(xm, t)) / (2 * h);
    }
    REQUIRE((a.gradient(x, t) - fd).cwiseAbs().maxCoeff() < 1e-7);
  }
  CHECK(max_gust <= 3.0 + 1e-12);
  CHECK(max_gust > 1.0);        // the gusts are there
  CHECK(max_difference > 0.5);  // another seed, other gusts
  GustSettings bad;
  bad.amplitude = -1;
  CHECK_THROWS_WITH(WindField<double>(mean, bad), Catch::Contains("'gust amplitude'"));
  CHECK_THROWS_WITH(AirDrag<double>(-0.1), Catch::Contains("'air drag'"));
  AerodynamicSettings aero;
  aero.lift_coefficient = std::nan("");
  CHECK_THROWS_WITH(AerodynamicForce<double>({}, {}, aero), Catch::Contains("'lift coefficient'"));
}

TEST_CASE("linear drag and aerodynamic force: Jacobians against finite differences", "[air][jacobian]") {
  const WindField<double> wind(Vec3<double>(3, -1, 2), strong_gusts());
  AerodynamicSettings aero;
  aero.drag_coefficient = 1.2;
  aero.lift_coefficient = 0.8;
  const Clothd probe = cloth_with({});
  const std::shared_ptr<const ForceTerm<double>> drag = std::make_shared<AirDrag<double>>(0.4, wind);
  const std::shared_ptr<const ForceTerm<double>> aerodynamic =
      std::make_shared<AerodynamicForce<double>>(probe.grid().triangles(), wind, aero);
  for (const auto& term : {drag, aerodynamic}) {
    const Clothd cloth = cloth_with({term});
    for (unsigned seed : {1u, 2u}) {
      // Tilted, stretched and compressed triangles, moving through the gusts.
      const Matrix3X<double> x = test::jiggled_positions(cloth, 0.35, seed);
      const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 4.0, seed + 10);
      Dense dfdx, dfdv;
      jacobians(cloth, x, v, JacobianVariant::Exact, dfdx, dfdv);
      INFO(term->name() << ", seed " << seed);
      CHECK(test::max_relative_error(dfdx, test::fd_jacobian(cloth, x, v, true, 0.3)) < 1e-6);
      CHECK(test::max_relative_error(dfdv, test::fd_jacobian(cloth, x, v, false, 0.3)) < 1e-6);
      // A symmetric system gets only the symmetric, damping part of the velocity derivative.
      const Clothd springs_only = cloth_with({});
      Dense sx, sv, px, pv;
      jacobians(cloth, x, v, JacobianVariant::Spd, sx, sv);
      jacobians(springs_only, x, v, JacobianVariant::Spd, px, pv);
      CHECK(sx == px);
      const Dense air_v = sv - pv;
      CHECK((air_v - air_v.transpose()).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, air_v.cwiseAbs().maxCoeff()));
      CHECK(test::symmetric_eigenvalues(air_v).maxCoeff() <= 1e-12);
      CHECK(air_v.cwiseAbs().maxCoeff() > 1e-6);
    }
  }
}

TEST_CASE("aerodynamic force on a plate: drag 1/2 rho C_d A u^2 along the normal, lift at 45 degrees",
          "[air][aerodynamics]") {
  AerodynamicSettings aero;
  aero.density = 1.2;
  aero.drag_coefficient = 1.1;
  aero.lift_coefficient = 0.7;
  // One right triangle in the x-z plane, area 0.5, normal along y.
  const AerodynamicForce<double> force({{0, 1, 2}}, {}, aero);
  const Vec3<double> a(0, 0, 0), b(1, 0, 0), c(0, 0, 1);
  const double area = 0.5, u = 3.0;
  // Moving along its normal: pure drag, opposing the motion; the corner order does not matter.
  const Vec3<double> up(0, u, 0);
  const Vec3<double> f = force.triangle_force(a, b, c, up);
  CHECK(f.isApprox(Vec3<double>(0, -0.5 * 1.2 * 1.1 * area * u * u, 0), 1e-14));
  CHECK(force.triangle_force(a, c, b, up).isApprox(f, 1e-14));
  // Moving along the plate: no force. At 45 degrees: drag 1/2 rho C_d A q^2 / 2 along the normal,
  // lift 1/2 rho C_l A q^2 / 2 perpendicular to the flow.
  CHECK(force.triangle_force(a, b, c, Vec3<double>(u, 0, 0)).norm() < 1e-14);
  const Vec3<double> v45 = Vec3<double>(1, 1, 0).normalized() * u;
  const Vec3<double> f45 = force.triangle_force(a, b, c, v45);
  const Vec3<double> lift = f45 - f45.dot(Vec3<double>::UnitY()) * Vec3<double>::UnitY();
  const double drag_normal = 0.5 * 1.2 * 1.1 * area * u * u * 0.5;  // (v.n)^2 = u^2 / 2
  const Vec3<double> drag_part(0, -drag_normal, 0);
  const Vec3<double> lift_part = f45 - drag_part;
  CHECK(std::abs(lift_part.dot(v45)) < 1e-12);                                             // perpendicular to the flow
  CHECK(lift_part.norm() == Approx(0.5 * 1.2 * 0.7 * area * u * u * 0.5).epsilon(1e-12));  // sin 45 cos 45 = 1/2
  CHECK(lift.norm() > 0);
  // Head-on: lift vanishes (only drag).
  CHECK((force.triangle_force(a, b, c, up) - Vec3<double>(0, -0.5 * 1.2 * 1.1 * area * u * u, 0)).norm() < 1e-12);
}

TEMPLATE_TEST_CASE("linear drag in a side wind: terminal velocity (w_x, -m g / c, w_z) in every integrator",
                   "[air][drag]", float, double) {
  using S = TestType;
  AirSettings air;
  air.drag = 0.06;  // N s/m per node: terminal fall speed 0.03 * 10 / 0.06 = 5 m/s
  air.wind = {2.0, 0.0, -1.0};
  ClothSpec<S> spec = test::small_spec<S>(6, S(10));
  spec.springs = {{S(300), S(1)}, {S(200), S(1)}, {S(50), S(0.5)}};
  spec.pinned_nodes = std::vector<int>{};
  spec.force_terms = air_force_terms<S>(air, Grid<S>(6, 6, S(0.1), S(0.03)).triangles());
  REQUIRE(spec.force_terms.size() == 1);
  const Cloth<S> cloth(spec);
  const Vec3<S> terminal(S(2), -S(0.03 * 10 / 0.06), S(-1));
  ImplicitOptions implicit;
  implicit.dt = 1.0 / 60;
  implicit.tolerance = 1e-7;
  std::vector<std::unique_ptr<Integrator<S>>> integrators;
  integrators.push_back(std::make_unique<Rk2<S>>(cloth, IntegratorOptions{1e-3, 1}));
  integrators.push_back(std::make_unique<SymplecticEuler<S>>(cloth, IntegratorOptions{1e-3, 1}));
  integrators.push_back(std::make_unique<ImplicitEuler<S>>(cloth, implicit));
  for (auto& integrator : integrators) {
    State<S> s = cloth.initial_state();
    while (s.time < S(8)) REQUIRE(integrator->step(s).ok());  // 16 time constants m / c
    INFO("dt " << integrator->dt());
    for (int i = 0; i < cloth.node_count(); ++i)
      REQUIRE((s.velocities.col(i) - terminal).norm() < S(0.01) * terminal.norm());  // within 1%
  }
}

TEST_CASE("a flag in gusty wind stays stable with the implicit step at dt = 1/60", "[air][stability][long]") {
  // The default cloth pinned along one edge (i = 0), wind along +x with gusts, aerodynamic drag and
  // lift: it must fly, not blow up, with the default (symmetric, SPD) system and with the Exact one.
  ClothSpecd spec;
  std::vector<int> edge;
  for (int j = 0; j < spec.ny; ++j) edge.push_back(j * spec.nx);
  spec.pinned_nodes = edge;
  AirSettings air;
  air.wind = {10, 0, 0};
  air.gusts.amplitude = 4;
  air.aerodynamics.drag_coefficient = 1.2;
  air.aerodynamics.lift_coefficient = 0.5;
  spec.force_terms = air_force_terms<double>(air, Gridd(spec.nx, spec.ny, spec.spacing, spec.node_mass).triangles());
  const Clothd cloth(spec);
  for (JacobianVariant variant : {JacobianVariant::Spd, JacobianVariant::Exact}) {
    ImplicitOptions o;
    o.dt = 1.0 / 60;
    o.jacobian = variant;
    o.solver = variant == JacobianVariant::Exact ? LinearSolverKind::Bicgstab : LinearSolverKind::Cg;
    ImplicitEuler<double> ie(cloth, o);
    State<double> s = cloth.initial_state();
    double farthest_free_x = 0;
    for (int k = 0; k < 300; ++k) {  // 5 s
      const StepStatus status = ie.step(s);
      INFO(to_string(variant) << ", step " << k << ": " << to_string(status.error));
      REQUIRE(status.ok());
    }
    for (int j = 0; j < spec.ny; ++j)
      farthest_free_x = std::max(farthest_free_x, s.positions(0, j * spec.nx + spec.nx - 1));
    INFO(to_string(variant));
    CHECK(max_strain(cloth, s.positions) < 0.3);
    CHECK(s.velocities.cwiseAbs().maxCoeff() < 30);  // bounded, no blow-up
    // It flies: the free edge is blown downwind of the pinned edge, not hanging at x = 0 below it.
    CHECK(farthest_free_x > 1.5);
  }
}

TEST_CASE("aerodynamic force shares work: colours without a shared node, one pass as two", "[air][threads]") {
  const Gridd grid(9, 7, 0.1, 0.03);
  const WindField<double> wind(Vec3<double>(3, -1, 2), strong_gusts());
  AerodynamicSettings aero;
  aero.drag_coefficient = 1.2;
  aero.lift_coefficient = 0.8;
  const AerodynamicForce<double> force(grid.triangles(), wind, aero);
  // Every triangle once; within a colour no node twice (threads write a colour's nodes at once).
  std::vector<std::array<int, 3>> given = grid.triangles(), sorted = force.triangles();
  std::sort(given.begin(), given.end());
  std::sort(sorted.begin(), sorted.end());
  CHECK(given == sorted);
  const std::vector<int>& begin = force.colour_begin();
  REQUIRE(begin.size() >= 2);
  CHECK(begin.size() <= 14);  // greedy on a grid (6 triangles per node): 13 colours at most
  for (std::size_t c = 0; c + 1 < begin.size(); ++c) {
    std::vector<int> nodes;
    for (int k = begin[c]; k < begin[c + 1]; ++k)
      for (int node : force.triangles()[static_cast<std::size_t>(k)]) nodes.push_back(node);
    std::sort(nodes.begin(), nodes.end());
    INFO("colour " << c);
    CHECK(std::adjacent_find(nodes.begin(), nodes.end()) == nodes.end());
  }
  // The fused pass of the implicit assembly gives add_force() and add_derivatives() bit for bit,
  // on one thread and on a team.
  ClothSpecd spec;
  spec.nx = 9;
  spec.ny = 7;
  const Matrix3X<double> x = test::jiggled_positions(Clothd(spec), 0.35, 3);
  const Matrix3X<double> v = test::random_velocities<double>(grid.node_count(), 4.0, 4);
  struct Recorder final : ForceDerivatives<double> {
    explicit Recorder(int n) : dfdv(3 * n, 3 * n), dfdx(3 * n, 3 * n) {
      dfdv.setZero();
      dfdx.setZero();
    }
    bool symmetric() const override { return false; }
    void add(int a, int b, const Mat3<double>& x_block, const Mat3<double>& v_block) override {
      dfdx.block<3, 3>(3 * a, 3 * b) += x_block;
      dfdv.block<3, 3>(3 * a, 3 * b) += v_block;
    }
    Dense dfdv, dfdx;
  };
  const int n = grid.node_count();
  Matrix3X<double> f_apart = Matrix3X<double>::Zero(3, n);
  Recorder apart(n);
  force.add_force(x, v, 0.4, f_apart);
  force.add_derivatives(x, v, 0.4, apart);
  for (int threads : {1, 2}) {
    INFO(threads << " threads");
    Matrix3X<double> f_fused = Matrix3X<double>::Zero(3, n);
    Recorder fused(n);
    run_in_team(threads, [&] { force.add_force_and_derivatives(x, v, 0.4, f_fused, fused); });
    CHECK(f_fused == f_apart);
    CHECK(fused.dfdx == apart.dfdx);
    CHECK(fused.dfdv == apart.dfdv);
  }
  CHECK(f_apart.cwiseAbs().maxCoeff() > 1e-3);
}

TEST_CASE("air in a symmetric system keeps the solvers' edge form: its product is A's", "[air][edges]") {
  AirSettings air;
  air.wind = {3, -1, 2};
  air.gusts = strong_gusts();
  air.drag = 0.2;
  air.aerodynamics.drag_coefficient = 1.2;
  air.aerodynamics.lift_coefficient = 0.8;
  const Clothd cloth = cloth_with(air_force_terms<double>(air, Gridd(5, 5, 0.1, 0.03).triangles()), true);
  // Flat, every triangle's lumped block N N^T is diagonal but not a multiple of I.
  const bool flat = GENERATE(false, true);
  const Matrix3X<double> x = flat ? cloth.initial_state().positions : test::jiggled_positions(cloth, 0.35, 8);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 4.0, 9);
  for (JacobianVariant variant : {JacobianVariant::Spd, JacobianVariant::Symmetric, JacobianVariant::Exact}) {
    INFO(to_string(variant) << (flat ? ", flat" : ", jiggled"));
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    LinearSystem<double> system = assembler.make_system();
    assembler.assemble_system(x, v, 0.3, 1.0 / 60, variant, system);
    if (variant == JacobianVariant::Exact) {  // the aerodynamic position blocks couple corners
      CHECK_FALSE(system.edges.valid());
      continue;
    }
    REQUIRE(system.edges.valid());
    CHECK(system.edges.uses_row_blocks());
    const VectorX<double> p = test::random_velocities<double>(system.block_rows(), 1.0, 10).reshaped();
    VectorX<double> by_edges(p.size()), by_blocks(p.size());
    system.edges.multiply(p.data(), by_edges.data());
    system.matrix.multiply(p.data(), by_blocks.data());
    CHECK((by_edges - by_blocks).cwiseAbs().maxCoeff() <= 1e-13 * by_blocks.cwiseAbs().maxCoeff());
    // The air's blocks are in it: without them the product differs.
    const Clothd still = cloth_with({}, true);
    JacobianAssembler<double> plain(still, PinTreatment::Eliminate, 1);
    LinearSystem<double> no_air = plain.make_system();
    plain.assemble_system(x, v, 0.3, 1.0 / 60, variant, no_air);
    VectorX<double> without(p.size());
    no_air.edges.multiply(p.data(), without.data());
    CHECK((by_edges - without).cwiseAbs().maxCoeff() > 1e-6 * by_blocks.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("linear drag folds into the edge form's diagonal: its product is still A's", "[air][edges]") {
  AirSettings air;
  air.wind = {3, -1, 2};
  air.drag = 0.2;
  const Clothd cloth = cloth_with(air_force_terms<double>(air, Gridd(5, 5, 0.1, 0.03).triangles()), true);
  const Clothd still = cloth_with({}, true);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.35, 8);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 4.0, 9);
  // Exact too: a uniform wind has no position derivative, so drag's blocks are -c I on the diagonal.
  for (JacobianVariant variant : {JacobianVariant::Spd, JacobianVariant::Symmetric, JacobianVariant::Exact}) {
    INFO(to_string(variant));
    JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
    LinearSystem<double> system = assembler.make_system();
    assembler.assemble_system(x, v, 0.3, 1.0 / 60, variant, system);
    REQUIRE(system.edges.valid());
    CHECK(system.edges.uses_row_diagonal());
    CHECK_FALSE(system.edges.uses_row_blocks());
    const VectorX<double> p = test::random_velocities<double>(system.block_rows(), 1.0, 10).reshaped();
    VectorX<double> by_edges(p.size()), by_blocks(p.size()), without(p.size());
    system.edges.multiply(p.data(), by_edges.data());
    system.matrix.multiply(p.data(), by_blocks.data());
    CHECK((by_edges - by_blocks).cwiseAbs().maxCoeff() <= 1e-13 * by_blocks.cwiseAbs().maxCoeff());
    JacobianAssembler<double> plain(still, PinTreatment::Eliminate, 1);
    LinearSystem<double> no_air = plain.make_system();
    plain.assemble_system(x, v, 0.3, 1.0 / 60, variant, no_air);
    no_air.edges.multiply(p.data(), without.data());
    // The difference is exactly the drag's dt c p.
    CHECK((by_edges - without - (1.0 / 60) * 0.2 * p).cwiseAbs().maxCoeff() <= 1e-13 * by_blocks.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("air terms keep runs reproducible: 1 and 2 threads agree bit for bit", "[air][threads]") {
  if (max_threads() < 2) return;
  ClothSpecd spec;
  spec.nx = spec.ny = 48;
  AirSettings air;
  air.wind = {3, 0, 1};
  air.gusts.amplitude = 2;
  air.drag = 0.01;
  air.aerodynamics.drag_coefficient = 1.0;
  air.aerodynamics.lift_coefficient = 0.3;
  spec.force_terms = air_force_terms<double>(air, Gridd(48, 48, 0.1, 0.03).triangles());
  const Clothd cloth(spec);
  const auto rk2 = [&](int threads) {
    Rk2<double> integrator(cloth, {5e-4, threads});
    State<double> s = cloth.initial_state();
    for (int k = 0; k < 100; ++k) REQUIRE(integrator.step(s).ok());
    return s;
  };
  const auto implicit = [&](int threads) {
    ImplicitOptions o;
    o.dt = 1.0 / 60;
    o.threads = threads;
    ImplicitEuler<double> integrator(cloth, o);
    State<double> s = cloth.initial_state();
    for (int k = 0; k < 10; ++k) REQUIRE(integrator.step(s).ok());
    return s;
  };
  const State<double> r1 = rk2(1), r2 = rk2(2), i1 = implicit(1), i2 = implicit(2);
  CHECK(r1.positions == r2.positions);
  CHECK(r1.velocities == r2.velocities);
  CHECK(i1.positions == i2.positions);  // 48 x 48: PCG stays on one thread, the assembly uses two
}
