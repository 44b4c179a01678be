// Force terms (core/force_term.hpp): the one place a new force plugs in. Two terms written here,
// as a user would, prove that both integrators, the implicit system, the Newton iteration and the
// diagnostics take them in without any change: linear air drag (per node, velocity derivative on
// the diagonal) and tethers (zero-length springs between far nodes, blocks off the spring pattern).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/enable_ldlt.hpp"
#include "drape/solvers/enable_lu.hpp"
#include "test_common.hpp"

using namespace drape;
using Dense = Eigen::MatrixXd;

namespace {

/// f_i = -c (v_i - v_air): df/dv = -c I, no position derivative.
template <class S>
class LinearDrag final : public ForceTerm<S> {
 public:
  LinearDrag(S c, Vec3<S> air = Vec3<S>::Zero()) : m_c(c), m_air(air) {}
  std::string name() const override { return "linear drag"; }
  void add_force(const ConstRef3X<S>&, const ConstRef3X<S>& v, S, Ref3X<S> f) const override {
    f -= m_c * (v.colwise() - m_air);
  }
  bool has_derivatives() const override { return true; }
  void add_derivatives(const ConstRef3X<S>& x, const ConstRef3X<S>&, S, ForceDerivatives<S>& out) const override {
    for (Index i = 0; i < x.cols(); ++i)
      out.add(int(i), int(i), Mat3<S>::Zero(), -m_c * Mat3<S>::Identity());
  }

 private:
  S m_c;
  Vec3<S> m_air;
};

/// Zero-length springs of stiffness k between node pairs: f_a = k (x_b - x_a), f_b = -f_a.
template <class S>
class Tethers final : public ForceTerm<S> {
 public:
  Tethers(S k, std::vector<std::array<int, 2>> pairs, bool declare = true)
      : m_k(k), m_pairs(std::move(pairs)), m_declare(declare) {}
  std::string name() const override { return "tethers"; }
  void add_force(const ConstRef3X<S>& x, const ConstRef3X<S>&, S, Ref3X<S> f) const override {
    for (const auto& [a, b] : m_pairs) {
      const Vec3<S> pull = m_k * (x.col(b) - x.col(a));
      f.col(a) += pull;
      f.col(b) -= pull;
    }
  }
  std::vector<std::array<int, 2>> coupled_nodes() const override {
    return m_declare ? m_pairs : std::vector<std::array<int, 2>>{};
  }
  bool has_derivatives() const override { return true; }
  void add_derivatives(const ConstRef3X<S>&, const ConstRef3X<S>&, S, ForceDerivatives<S>& out) const override {
    const Mat3<S> k = m_k * Mat3<S>::Identity(), zero = Mat3<S>::Zero();
    for (const auto& [a, b] : m_pairs) {
      out.add(a, a, -k, zero);
      out.add(b, b, -k, zero);
      out.add(a, b, k, zero);
      out.add(b, a, k, zero);
    }
  }

 private:
  S m_k;
  std::vector<std::array<int, 2>> m_pairs;
  bool m_declare;
};

/// A uniform field that oscillates in time: f_i = m_i a sin(w t) e_x (no derivatives: the implicit
/// step treats it explicitly).
template <class S>
class OscillatingField final : public ForceTerm<S> {
 public:
  OscillatingField(const Cloth<S>& cloth, S amplitude, S omega) : m_mass(cloth.grid().masses()), m_a(amplitude), m_w(omega) {}
  std::string name() const override { return "oscillating field"; }
  void add_force(const ConstRef3X<S>&, const ConstRef3X<S>&, S t, Ref3X<S> f) const override {
    f.row(0) += (m_a * std::sin(m_w * t)) * m_mass.transpose();
  }

 private:
  VectorX<S> m_mass;
  S m_a, m_w;
};

ClothSpecd spec_with(std::vector<std::shared_ptr<const ForceTerm<double>>> terms, int n = 5) {
  ClothSpecd spec = test::small_spec<double>(n, 10.0);
  spec.springs = {{300.0, 2.0}, {200.0, 1.5}, {50.0, 0.5}};
  spec.force_terms = std::move(terms);
  return spec;
}

}  // namespace

TEST_CASE("force terms add their force to the force pass, for any thread count", "[terms]") {
  const auto drag = std::make_shared<LinearDrag<double>>(0.7, Vec3<double>(1, 0, -2));
  const auto tethers = std::make_shared<Tethers<double>>(40.0, std::vector<std::array<int, 2>>{{0, 24}, {4, 20}});
  const Clothd plain(spec_with({}, 48)), with_terms(spec_with({drag, tethers}, 48));
  const Matrix3X<double> x = test::jiggled_positions(plain, 0.2, 1u);
  const Matrix3X<double> v = test::random_velocities<double>(plain.node_count(), 1.0, 2u);
  Matrix3X<double> expected(3, plain.node_count()), terms = Matrix3X<double>::Zero(3, plain.node_count());
  ForceAssembler<double>(plain, 1).force(x, v, 0, expected);
  drag->add_force(x, v, 0, terms);
  tethers->add_force(x, v, 0, terms);
  expected += terms;
  for (int threads : {1, 2}) {
    Matrix3X<double> f(3, plain.node_count());
    ForceAssembler<double>(with_terms, threads).force(x, v, 0, f);
    INFO(threads << " thread(s)");
    CHECK((f - expected).cwiseAbs().maxCoeff() <= 1e-12 * expected.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("the assembled Jacobians include the terms' blocks (finite differences)", "[terms][jacobian]") {
  const auto drag = std::make_shared<LinearDrag<double>>(0.7);
  // Tethers across the cloth: blocks no spring has.
  const auto tethers = std::make_shared<Tethers<double>>(40.0, std::vector<std::array<int, 2>>{{0, 24}, {4, 20}, {7, 17}});
  ClothSpecd spec = spec_with({drag, tethers});
  spec.pinned_nodes = std::vector<int>{};  // every node in the system
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 3u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 4u);
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
  assembler.assemble_jacobians(x, v, 0, JacobianVariant::Exact, kx, kv);
  CHECK(test::max_relative_error(kx.to_dense(), test::fd_jacobian(cloth, x, v, true)) < 1e-6);
  CHECK(test::max_relative_error(kv.to_dense(), test::fd_jacobian(cloth, x, v, false)) < 1e-6);
}

TEST_CASE("the implicit system takes the terms: A = M - dt df/dv - dt^2 df/dx, b = dt (f + dt df/dx v)",
          "[terms][system]") {
  const auto drag = std::make_shared<LinearDrag<double>>(0.7);
  const auto tethers = std::make_shared<Tethers<double>>(40.0, std::vector<std::array<int, 2>>{{0, 24}, {4, 20}, {7, 17}});
  ClothSpecd spec = spec_with({drag, tethers});
  spec.pinned_nodes = std::vector<int>{0, 4};
  const Clothd cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 5u);
  Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 6u);
  for (int p : cloth.pins().nodes()) v.col(p).setZero();
  const double dt = 0.02;
  for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    JacobianAssembler<double> assembler(cloth, pins, 1);
    LinearSystem<double> system = assembler.make_system();
    BlockSparseMatrix<double> kx = assembler.make_matrix(), kv = assembler.make_matrix();
    assembler.assemble_jacobians(x, v, 0, JacobianVariant::Spd, kx, kv);
    // Twice: a term-only block must be rewritten, not added to.
    assembler.assemble_system(x, v, 0, dt, JacobianVariant::Spd, system);
    assembler.assemble_system(x, v, 0, dt, JacobianVariant::Spd, system);
    CHECK_FALSE(system.edges.valid());  // the edge operator has no room for the terms' blocks
    Matrix3X<double> f(3, cloth.node_count());
    ForceAssembler<double>(cloth, 1).force(x, v, 0, f);
    const int rows = assembler.system_nodes();
    VectorX<double> m(3 * rows), vf(3 * rows), ff(3 * rows), vall = VectorX<double>::Zero(3 * cloth.node_count());
    for (int r = 0; r < rows; ++r) {
      const int node = assembler.node_of_row()[std::size_t(r)];
      m.segment<3>(3 * r).setConstant(cloth.grid().masses()[node]);
      vf.segment<3>(3 * r) = v.col(node);
      ff.segment<3>(3 * r) = f.col(node);
    }
    const Dense expected_a = Dense(m.asDiagonal()) - dt * kv.to_dense() - dt * dt * kx.to_dense();
    INFO("pins " << to_string(pins));
    CHECK(test::max_relative_error(system.matrix.to_dense(), expected_a) < 1e-12);
    // The pinned nodes' velocities are zero here, so the eliminated columns add nothing to b.
    const VectorX<double> expected_b = dt * (ff + dt * (kx.to_dense() * vf));
    CHECK((system.rhs - expected_b).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, expected_b.cwiseAbs().maxCoeff()));
  }
}

TEST_CASE("a term that writes a block it did not declare is an error, not a silent drop", "[terms][system]") {
  const auto undeclared = std::make_shared<Tethers<double>>(40.0, std::vector<std::array<int, 2>>{{6, 18}}, false);
  const Clothd cloth(spec_with({undeclared}));
  ImplicitOptions o;
  o.dt = 0.01;
  ImplicitEuler<double> ie(cloth, o);
  State<double> s = cloth.initial_state();
  CHECK_THROWS_AS(ie.step(s), std::logic_error);
}

TEMPLATE_TEST_CASE("linear drag: a falling cloth reaches the terminal velocity m g / c in both integrators",
                   "[terms][drag]", float, double) {
  using S = TestType;
  const S c = S(0.06);  // per node, N s/m: terminal speed 0.03 * 10 / 0.06 = 5 m/s, time constant 0.5 s
  ClothSpec<S> spec = test::small_spec<S>(6, S(10));
  spec.springs = {{S(300), S(1)}, {S(200), S(1)}, {S(50), S(0.5)}};
  spec.pinned_nodes = std::vector<int>{};
  spec.force_terms = {std::make_shared<LinearDrag<S>>(c)};
  const Cloth<S> cloth(spec);
  const S terminal = cloth.grid().masses()[0] * S(10) / c;
  const S tol = std::is_same<S, float>::value ? S(2e-3) : S(1e-3);
  ImplicitOptions implicit;
  implicit.dt = 1.0 / 60;
  implicit.tolerance = 1e-7;
  std::vector<std::unique_ptr<Integrator<S>>> integrators;
  integrators.push_back(std::make_unique<Rk2<S>>(cloth, IntegratorOptions{1e-3, 1}));
  integrators.push_back(std::make_unique<ImplicitEuler<S>>(cloth, implicit));
  for (auto& integrator : integrators) {
    State<S> s = cloth.initial_state();
    while (s.time < S(8)) REQUIRE(integrator->step(s).ok());  // 16 time constants
    INFO("dt " << integrator->dt());
    for (int i = 0; i < cloth.node_count(); ++i) REQUIRE(std::abs(s.velocities(1, i) / -terminal - 1) < tol);
    REQUIRE(s.velocities.row(0).cwiseAbs().maxCoeff() < tol * terminal);
  }
}

TEST_CASE("a force term changes the pin reaction: at rest the pins carry weight and field", "[terms][equilibrium]") {
  // A uniform drag in a steady wind across the pin line acts like a constant force c v_air per
  // node once the cloth is at rest.
  const Vec3<double> air(0, 0, 0.5);
  const double c = 0.2;
  ClothSpecd spec;  // 33 x 33, two corners
  spec.force_terms = {std::make_shared<LinearDrag<double>>(c, air)};
  const Clothd cloth(spec);
  ImplicitOptions o;
  o.dt = 0.3;
  o.solver = LinearSolverKind::Ldlt;
  ImplicitEuler<double> ie(cloth, o);
  State<double> s = cloth.initial_state();
  for (int k = 0; k < 120; ++k) REQUIRE(ie.step(s).ok());
  const double n = cloth.node_count();
  const Vec3<double> expected(0, cloth.grid().total_mass() * 10.0, -n * c * air.z());
  const Vec3<double> reaction = pin_reaction(cloth, s);
  INFO("reaction " << reaction.transpose() << ", expected " << expected.transpose());
  CHECK((reaction - expected).norm() < 1e-3 * expected.norm());
  CHECK(max_free_force(cloth, s) < 1e-3);
}

TEST_CASE("a time-dependent term is evaluated at RK2's stage times: second order stays", "[terms][rk2][order]") {
  // Unpinned cloth without gravity under f = m a sin(w t) e_x: every node moves with
  // x(t) = x0 + a/w t - a/w^2 sin(w t), exactly, and the springs stay at rest.
  ClothSpecd spec = test::small_spec<double>(4, 0.0);
  spec.pinned_nodes = std::vector<int>{};
  const double a = 3.0, w = 10.0, t_end = 1.0;
  const Clothd probe(spec);
  spec.force_terms = {std::make_shared<OscillatingField<double>>(probe, a, w)};
  const Clothd cloth(spec);
  const auto error = [&](double dt) {
    Rk2<double> rk2(cloth, {dt, 1});
    State<double> s = cloth.initial_state();
    const int steps = int(std::lround(t_end / dt));
    for (int k = 0; k < steps; ++k) REQUIRE(rk2.step(s).ok());
    const double exact = a / w * s.time - a / (w * w) * std::sin(w * s.time);
    return std::abs(s.positions(0, 0) - exact);
  };
  const double e1 = error(0.002), e2 = error(0.001);
  INFO("errors " << e1 << " -> " << e2);
  CHECK(e1 / e2 > 3.5);
  CHECK(e1 / e2 < 4.5);
}

TEST_CASE("RK2 with force terms: 1 and 2 threads agree bit for bit", "[terms][threads]") {
  if (max_threads() < 2) return;
  const auto drag = std::make_shared<LinearDrag<double>>(0.05, Vec3<double>(1, 0, 0));
  ClothSpecd spec;
  spec.nx = spec.ny = 48;
  spec.force_terms = {drag};
  const Clothd cloth(spec);
  const auto run = [&](int threads) {
    Rk2<double> rk2(cloth, {5e-4, threads});
    State<double> s = cloth.initial_state();
    for (int k = 0; k < 200; ++k) REQUIRE(rk2.step(s).ok());
    return s;
  };
  const State<double> one = run(1), two = run(2);
  CHECK(one.positions == two.positions);
  CHECK(one.velocities == two.velocities);
}

TEST_CASE("Newton iterations converge with a term's derivatives in the system", "[terms][newton]") {
  const auto tethers = std::make_shared<Tethers<double>>(20.0, std::vector<std::array<int, 2>>{{6, 30}, {11, 29}});
  ClothSpecd spec = spec_with({tethers, std::make_shared<LinearDrag<double>>(0.3)}, 6);
  const Clothd cloth(spec);
  ImplicitOptions o;
  o.dt = 0.05;
  o.jacobian = JacobianVariant::Exact;
  o.solver = LinearSolverKind::Lu;
  o.newton_iterations = 30;
  o.newton_tolerance = 1e-9;
  ImplicitEuler<double> ie(cloth, o);
  State<double> start = cloth.initial_state();
  start.positions = test::jiggled_positions(cloth, 0.1, 9u);
  for (int p : cloth.pins().nodes()) start.positions.col(p) = cloth.grid().rest_positions().col(p);
  State<double> s = start;
  const StepStatus status = ie.step(s);
  INFO(to_string(status.error) << ", " << ie.newton_iterations_done() << " Newton iterations, residual "
                               << ie.newton_residual());
  REQUIRE(status.ok());
  CHECK(ie.newton_residual() <= 1e-9);
  // The backward Euler equations hold with the terms' forces at the end of the step.
  CHECK(test::backward_euler_residual(cloth, start, s, o.dt) < 1e-7);
}
