#include <catch2/catch.hpp>

#include <cstring>

#include "drape/integrators/rk2.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/platform/team.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

// A small swinging cloth: one corner pinned, gravity on, kd = 0 unless asked for.
ClothSpec<double> swing_spec(double kd = 0) {
  auto spec = test::small_spec<double>(5, 10.0);
  spec.boundary = BoundaryCondition::OneCorner;
  spec.springs = {{300, kd}, {200, kd}, {50, kd}};
  return spec;
}

State<double> run(const Cloth<double>& cloth, double dt, double duration) {
  Rk2<double> rk2(cloth, {dt, 1});
  State<double> s = cloth.initial_state();
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < steps; ++k) REQUIRE(rk2.step(s).ok());
  return s;
}

}  // namespace

TEMPLATE_TEST_CASE("one fused RK2 step equals the midpoint rule written out with the force pass", "[rk2][stages]",
                   float, double) {
  using S = TestType;
  for (int threads : {1, 2}) {
    ClothSpec<S> spec;  // the brief's cloth: 6.2k springs, two threads are used
    spec.boundary = BoundaryCondition::TwoCorners;
    const Cloth<S> cloth(spec);
    State<S> s = cloth.initial_state();
    s.positions = test::jiggled_positions(cloth, S(0.2), 31);
    s.velocities = test::random_velocities<S>(cloth.node_count(), S(1), 32);
    s.velocities.col(cloth.pins().nodes().back()) = Vec3<S>(1, -2, 3);  // ignored: pinned
    const S dt = S(IntegratorOptions{}.dt), half = dt / 2;
    // The midpoint rule of the brief, one Eigen expression per line.
    const ForceAssembler<S> forces(cloth, 1);
    const auto acceleration = [&](const Matrix3X<S>& x, const Matrix3X<S>& v) {
      Matrix3X<S> f(3, cloth.node_count());
      forces.force(x, v, S(0), f);
      return Matrix3X<S>(f.array().rowwise() / cloth.grid().masses().transpose().array());
    };
    Matrix3X<S> x_mid = s.positions + half * s.velocities;
    Matrix3X<S> v_mid = s.velocities + half * acceleration(s.positions, s.velocities);
    for (int p : cloth.pins().nodes()) {
      x_mid.col(p) = s.positions.col(p);
      v_mid.col(p).setZero();
    }
    Matrix3X<S> x_new = s.positions + dt * v_mid;
    Matrix3X<S> v_new = s.velocities + dt * acceleration(x_mid, v_mid);
    for (int p : cloth.pins().nodes()) {
      x_new.col(p) = s.positions.col(p);
      v_new.col(p).setZero();
    }
    Rk2<S> rk2(cloth, {double(dt), threads});
    REQUIRE(rk2.forces().threads() == std::min(threads, max_threads()));
    const S t0 = s.time;
    REQUIRE(rk2.step(s).ok());
    INFO(threads << " thread(s)");
    const S eps = std::is_same<S, float>::value ? S(1e-6) : S(1e-14);
    REQUIRE((s.positions - x_new).cwiseAbs().maxCoeff() <= eps * x_new.cwiseAbs().maxCoeff());
    REQUIRE((s.velocities - v_new).cwiseAbs().maxCoeff() <= eps * v_new.cwiseAbs().maxCoeff());
    REQUIRE(s.time == t0 + dt);
  }
}

TEST_CASE("RK2 is second order: global error shrinks ~4x when dt halves", "[rk2][convergence]") {
  const Cloth<double> cloth(swing_spec(0.05));
  const double T = 0.25;
  const State<double> reference = run(cloth, 1e-3 / 64, T);
  double previous = 0;
  for (double dt : {2e-3, 1e-3, 5e-4}) {
    const double error = (run(cloth, dt, T).positions - reference.positions).cwiseAbs().maxCoeff();
    if (previous > 0) {
      INFO("dt " << dt << " error " << error << " ratio " << previous / error);
      REQUIRE(previous / error == Approx(4.0).epsilon(0.15));
    }
    previous = error;
  }
}

// The bound asked for is O(dt^2); the midpoint rule's amplitude error on oscillations is in fact
// O(dt^3) (|R(i w dt)|^2 = 1 + (w dt)^4 / 4 per step), so the measured ratio lies between 4 and 8.
TEST_CASE("RK2 energy drift without damping is O(dt^2) or better", "[rk2][energy]") {
  const Cloth<double> cloth(swing_spec(0));
  const double E0 = total_energy(cloth, cloth.initial_state());
  const auto drift = [&](double dt) {
    Rk2<double> rk2(cloth, {dt, 1});
    State<double> s = cloth.initial_state();
    double worst = 0;
    for (int k = 0; k < std::lround(0.5 / dt); ++k) {
      REQUIRE(rk2.step(s).ok());
      worst = std::max(worst, std::abs(total_energy(cloth, s) - E0));
    }
    return worst;
  };
  const double d1 = drift(1e-3), d2 = drift(5e-4);
  INFO("drift " << d1 << " -> " << d2);
  REQUIRE(d1 / d2 > 3.5);
  REQUIRE(d1 / d2 < 9.0);
  // And it is small against the energy exchanged (the cloth falls ~1 m).
  REQUIRE(d2 < 1e-3 * cloth.grid().total_mass() * 10.0);
}

TEMPLATE_TEST_CASE("unpinned cloth falls freely: y = -g t^2 / 2, springs stay at rest", "[rk2][free-fall]", float,
                   double) {
  using S = TestType;
  auto spec = test::small_spec<S>(4, S(10));
  spec.pinned_nodes = std::vector<int>{};
  spec.springs = {{S(300), S(1)}, {S(200), S(1)}, {S(50), S(1)}};
  const Cloth<S> cloth(spec);
  const S dt = S(1e-3);
  Rk2<S> rk2(cloth, {double(dt), 1});
  State<S> s = cloth.initial_state();
  for (int k = 0; k < 500; ++k) REQUIRE(rk2.step(s).ok());
  const S t = S(500) * dt;
  const S expected = -S(10) * t * t / 2;
  const S tol = std::is_same<S, float>::value ? S(1e-4) : S(1e-12);
  REQUIRE(s.time == Approx(t));
  for (int i = 0; i < cloth.node_count(); ++i) {
    REQUIRE(test::close<S>(s.positions(1, i), expected, tol));
    REQUIRE(test::close<S>(s.velocities(1, i), -S(10) * t, tol));
  }
  REQUIRE(std::abs(max_strain(cloth, s.positions)) < tol);
}

TEMPLATE_TEST_CASE("pinned nodes stay bit-identical and at rest", "[rk2][pins]", float, double) {
  using S = TestType;
  for (auto bc : {BoundaryCondition::OneCorner, BoundaryCondition::TwoCorners}) {
    ClothSpec<S> spec;
    spec.nx = spec.ny = 9;
    spec.boundary = bc;
    const Cloth<S> cloth(spec);
    Rk2<S> rk2(cloth);
    State<S> s = cloth.initial_state();
    const Matrix3X<S> start = s.positions;
    s.velocities.col(cloth.pins().nodes().front()) = Vec3<S>(1, 2, 3);  // a careless caller
    for (int k = 0; k < 300; ++k) REQUIRE(rk2.step(s).ok());
    for (int p : cloth.pins().nodes()) {
      REQUIRE(std::memcmp(s.positions.col(p).data(), start.col(p).data(), 3 * sizeof(S)) == 0);
      REQUIRE(s.velocities.col(p).isZero(0));
    }
    REQUIRE(s.positions.row(1).minCoeff() < S(-0.1));  // the rest of the cloth did fall
  }
}

TEST_CASE("a diverging RK2 step is reported and leaves the state unchanged", "[rk2][failure]") {
  auto spec = test::small_spec<double>(5, 10.0);
  spec.springs = {{1e7, 0}, {1e7, 0}, {1e7, 0}};
  spec.boundary = BoundaryCondition::OneCorner;
  const Cloth<double> cloth(spec);
  Rk2<double> rk2(cloth, {0.01, 1});
  State<double> s = cloth.initial_state();
  s.positions = test::jiggled_positions(cloth, 0.2, 1);
  StepStatus status;
  int k = 0;
  State<double> before;
  for (; k < 10000; ++k) {
    before = s;
    status = rk2.step(s);
    if (!status.ok()) break;
  }
  REQUIRE(status.error == StepError::NonFiniteState);
  REQUIRE(s.all_finite());
  REQUIRE(std::memcmp(s.positions.data(), before.positions.data(), sizeof(double) * std::size_t(s.positions.size())) == 0);
  REQUIRE(s.time == before.time);
}

TEST_CASE("the default scene is stable with RK2 at the default dt for both boundary conditions", "[rk2][defaults]") {
  for (auto bc : {BoundaryCondition::OneCorner, BoundaryCondition::TwoCorners}) {
    ClothSpec<double> spec;
    spec.boundary = bc;
    const Cloth<double> cloth(spec);
    Rk2<double> rk2(cloth);
    State<double> s = cloth.initial_state();
    const int steps = static_cast<int>(std::lround(3.0 / rk2.dt()));
    for (int k = 0; k < steps; ++k) REQUIRE(rk2.step(s).ok());
    // Bounded: nothing flew off, and the springs are not absurdly stretched.
    REQUIRE(s.positions.cwiseAbs().maxCoeff() < 10.0);
    REQUIRE(max_strain(cloth, s.positions) < 0.5);
  }
}
