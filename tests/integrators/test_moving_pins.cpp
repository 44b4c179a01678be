// Moving pins (core/pin_path.hpp, core/pin_set.hpp) in both integrators: pins on key-frame and
// callback paths end every step exactly on their path; pins added and released during a run; a
// released cloth falls freely; the force of pins lifting a cloth at constant speed equals its
// weight; eliminated and filtered pins, direct and iterative solvers agree.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/physics/air_drag.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/solvers/enable_ldlt.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

ClothSpecd hanging_cloth(int n = 9) {
  ClothSpecd spec = test::small_spec<double>(n, 10.0);
  spec.springs = {{2000.0, 2.0}, {1000.0, 1.0}, {100.0, 0.2}};
  return spec;  // two corners pinned
}

std::unique_ptr<Integrator<double>> make(const Clothd& cloth, IntegratorKind kind, ImplicitOptions options = {}) {
  options.dt = kind == IntegratorKind::Implicit ? 0.01 : 5e-4;
  options.threads = 1;
  options.tolerance = 1e-9;
  return make_integrator(cloth, kind, options);
}

}  // namespace

TEST_CASE("pin paths: key frames (linear, smooth) and their checks", "[pins][path]") {
  const std::vector<double> times{0.0, 1.0, 3.0};
  const std::vector<Vec3<double>> keys{{0, 0, 0}, {1, 2, 0}, {1, 0, 4}};
  const auto linear = PinPath<double>::keyframes(times, keys, Interpolation::Linear);
  const auto smooth = PinPath<double>::keyframes(times, keys, Interpolation::Smooth);
  const Vec3<double> here(9, 9, 9);
  for (std::size_t k = 0; k < times.size(); ++k) {
    CHECK(linear.position(times[k], here) == keys[k]);
    CHECK((smooth.position(times[k], here) - keys[k]).norm() <= 1e-15);
  }
  CHECK((linear.position(0.5, here) - Vec3<double>(0.5, 1, 0)).norm() <= 1e-15);
  CHECK((linear.position(2.0, here) - Vec3<double>(1, 1, 2)).norm() <= 1e-15);
  CHECK(linear.position(-1.0, here) == keys.front());
  CHECK(linear.position(7.0, here) == keys.back());
  // Smooth: at rest at the ends, the velocity continuous through the interior key (Catmull-Rom).
  const auto velocity = [&](double t) {
    const double e = 1e-8;
    return Vec3<double>((smooth.position(t + e, here) - smooth.position(t - e, here)) / (2 * e));
  };
  CHECK(velocity(1e-6).norm() <= 1e-4);
  CHECK(velocity(3.0 - 1e-6).norm() <= 1e-4);
  const Vec3<double> tangent = (keys[2] - keys[0]) / 3.0;
  CHECK((velocity(1.0 - 1e-6) - tangent).norm() <= 1e-4);
  CHECK((velocity(1.0 + 1e-6) - tangent).norm() <= 1e-4);
  CHECK(PinPath<double>().holds());
  CHECK(PinPath<double>().position(1.0, here) == here);
  CHECK_THROWS_WITH(PinPath<double>::keyframes({0.0, 0.0}, {keys[0], keys[1]}), Catch::Contains("pin path times"));
  CHECK_THROWS_WITH(PinPath<double>::keyframes({0.0, 1.0}, {keys[0]}), Catch::Contains("pin path positions"));
  CHECK_THROWS_WITH(PinPath<double>::keyframes({}, {}), Catch::Contains("pin path times"));
  CHECK_THROWS_WITH(PinPath<double>::callback({}), Catch::Contains("pin path"));
  PinSet<double> set(Pins({0, 3}, 5));
  CHECK_THROWS_WITH(set.pin(5), Catch::Contains("pinned node"));
  CHECK_FALSE(set.release(2));
}

TEST_CASE("moving pins end every step exactly on their paths, in both integrators", "[pins][moving]") {
  const Clothd cloth(hanging_cloth());
  const int a = 0, b = cloth.grid().node(8, 0);
  const Vec3<double> xa = cloth.grid().rest_positions().col(a), xb = cloth.grid().rest_positions().col(b);
  // A curtain drawn: corner b slides toward corner a (smooth key frames); corner a is lifted and
  // waved by a callback.
  const auto drawn = PinPath<double>::keyframes({0.0, 0.5, 1.0}, {xb, 0.5 * (xa + xb), xa + Vec3<double>(0.2, 0, 0)});
  const auto waved = PinPath<double>::callback(
      [xa](double t) { return Vec3<double>(xa + Vec3<double>(0.1 * std::sin(6 * t), 0.3 * t, 0)); });
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    auto stepper = make(cloth, kind);
    stepper->pins().pin(b, drawn);
    stepper->pins().pin(a, waved);
    Stated state = cloth.initial_state();
    const int steps = int(std::lround(1.2 / stepper->dt()));
    for (int k = 0; k < steps; ++k) {
      REQUIRE(stepper->step(state).ok());
      REQUIRE(state.positions.col(b) == drawn.position(state.time, Vec3<double>::Zero()));
      REQUIRE(state.positions.col(a) == waved.position(state.time, Vec3<double>::Zero()));
    }
    // The cloth came along: its centre moved toward the drawn corner's end.
    CHECK(state.positions.row(0).mean() < 0.5 * (xa.x() + xb.x()));
  }
}

TEST_CASE("pins released during a run: the cloth falls freely; pins added hold", "[pins][release]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    const Clothd cloth(hanging_cloth());
    auto stepper = make(cloth, kind);
    Stated state = cloth.initial_state();
    for (int k = 0; k < int(std::lround(0.3 / stepper->dt())); ++k) REQUIRE(stepper->step(state).ok());
    // Let go of both corners: with only internal forces besides gravity the centre of mass
    // falls at exactly g.
    for (int p : cloth.pins().nodes()) REQUIRE(stepper->pins().release(p));
    const VectorX<double>& m = cloth.grid().masses();
    const Vec3<double> momentum = state.velocities * m;
    const double t0 = state.time;
    for (int k = 0; k < int(std::lround(0.2 / stepper->dt())); ++k) REQUIRE(stepper->step(state).ok());
    const Vec3<double> gained = state.velocities * m - momentum;
    const double expected = -10.0 * m.sum() * (state.time - t0);
    CHECK(std::abs(gained.y() - expected) <= 1e-6 * std::abs(expected));
    CHECK(std::abs(gained.x()) + std::abs(gained.z()) <= 1e-6 * std::abs(expected));
    // Pin the middle node where it is now: it stays there.
    const int middle = cloth.grid().node(4, 4);
    stepper->pins().pin(middle);
    const Vec3<double> held = state.positions.col(middle);
    for (int k = 0; k < 20; ++k) {
      REQUIRE(stepper->step(state).ok());
      REQUIRE(state.positions.col(middle) == held);
    }
  }
}

TEST_CASE("pins lifting a cloth at constant speed carry its weight", "[pins][reaction]") {
  // The air rises with the pins: its drag damps the swinging but pulls nothing once the cloth
  // moves with them, so the pins alone carry the weight.
  const double speed = 0.2;  // m/s, upward
  ClothSpecd spec = hanging_cloth();
  spec.force_terms.push_back(std::make_shared<AirDrag<double>>(0.05, WindField<double>(Vec3<double>(0, speed, 0))));
  const Clothd cloth(spec);
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    auto stepper = make(cloth, kind);
    Stated state = cloth.initial_state();
    for (int p : cloth.pins().nodes()) {
      const Vec3<double> x = cloth.grid().rest_positions().col(p);
      stepper->pins().pin(
          p, PinPath<double>::keyframes({0.0, 10.0}, {x, x + Vec3<double>(0, 10 * speed, 0)}, Interpolation::Linear));
    }
    for (int k = 0; k < int(std::lround(5.0 / stepper->dt())); ++k) REQUIRE(stepper->step(state).ok());
    const std::vector<int>& pinned = stepper->pins().nodes();
    const Matrix3X<double> forces =
        pin_forces<double>(cloth, state, pinned, Matrix3X<double>::Zero(3, Index(pinned.size())));
    const double weight = 10.0 * cloth.grid().masses().sum();
    CHECK(std::abs(forces.rowwise().sum().y() - weight) <= 0.01 * weight);
    CHECK(std::abs(state.velocities.row(1).mean() - speed) <= 0.01 * speed);
  }
}

TEST_CASE("moving pins: eliminated or filtered, direct or iterative, the same steps", "[pins][solvers]") {
  const Clothd cloth(hanging_cloth(7));
  const int corner = cloth.grid().node(6, 0);
  const Vec3<double> x = cloth.grid().rest_positions().col(corner);
  const auto path = PinPath<double>::keyframes({0.0, 0.5}, {x, x + Vec3<double>(-0.3, 0.2, 0.1)});
  Stated reference;
  for (const auto& [treatment, solver] :
       {std::pair{PinTreatment::Eliminate, LinearSolverKind::Cg}, std::pair{PinTreatment::Filter, LinearSolverKind::Cg},
        std::pair{PinTreatment::Eliminate, LinearSolverKind::Ldlt},
        std::pair{PinTreatment::Filter, LinearSolverKind::Ldlt}}) {
    INFO(to_string(treatment) << ", " << to_string(solver));
    ImplicitOptions options;
    options.pin_treatment = treatment;
    options.solver = solver;
    auto stepper = make(cloth, IntegratorKind::Implicit, options);
    stepper->pins().pin(corner, path);
    Stated state = cloth.initial_state();
    for (int k = 0; k < 60; ++k) REQUIRE(stepper->step(state).ok());
    if (reference.positions.size() == 0) reference = state;
    CHECK((state.positions - reference.positions).cwiseAbs().maxCoeff() <= 1e-7);
  }
}
