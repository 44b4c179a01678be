#include <catch2/catch.hpp>

#include <cstring>

#include "drape/integrators/rk2.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/platform/team.hpp"
#include "integrators/explicit_test_helpers.hpp"
#include "test_common.hpp"

using namespace drape;

using test::run;
using test::swing_spec;

TEMPLATE_TEST_CASE("one fused RK2 step equals the midpoint rule written out with the force pass", "[rk2][stages]",
                   float, double) {
  using S = TestType;
  for (int threads : {1, 2}) {
    const Cloth<S> cloth(test::stage_spec<S>());
    State<S> s = test::stage_start(cloth);
    const S dt = S(IntegratorOptions{}.dt), half = dt / 2;
    // The midpoint rule, one Eigen expression per line.
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
    test::require_step_result(s, x_new, v_new, t0, dt);
  }
}

TEST_CASE("RK2 is second order: global error shrinks ~4x when dt halves", "[rk2][convergence]") {
  const Cloth<double> cloth(swing_spec(0.05));
  const double T = 0.25;
  const State<double> reference = run<Rk2<double>>(cloth, 1e-3 / 64, T);
  double previous = 0;
  for (double dt : {2e-3, 1e-3, 5e-4}) {
    const double error = (run<Rk2<double>>(cloth, dt, T).positions - reference.positions).cwiseAbs().maxCoeff();
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
  test::require_free_fall<Rk2, S>([](S t, S) { return -S(10) * t * t / 2; });
}

TEMPLATE_TEST_CASE("pinned nodes stay bit-identical and at rest", "[rk2][pins]", float, double) {
  for (auto bc : {BoundaryCondition::OneCorner, BoundaryCondition::TwoCorners})
    test::require_pins_stay_put<Rk2, TestType>(bc);
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
  test::require_default_scene_stable<Rk2<double>>();
}
