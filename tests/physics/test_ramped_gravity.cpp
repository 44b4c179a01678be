// Ramped gravity (physics/ramped_gravity.hpp): no force before the start, the weight after the ramp,
// linear in between; a falling cloth's momentum grows by the ramped impulse; bad arguments named.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/ramped_gravity.hpp"

using namespace drape;

TEST_CASE("ramped gravity: nothing before the start, linear over the ramp, the full weight after", "[ramped_gravity]") {
  VectorX<double> m(3);
  m << 0.1, 0.2, 0.3;
  const RampedGravity<double> gravity(m, 10.0, 1.0, 0.5);
  const Matrix3X<double> x = Matrix3X<double>::Random(3, 3), v = Matrix3X<double>::Zero(3, 3);
  auto force_at = [&](double t) {
    Matrix3X<double> f = Matrix3X<double>::Zero(3, 3);
    gravity.add_force(x, v, t, f);
    return f;
  };
  CHECK(force_at(0.99).norm() == 0);
  const Matrix3X<double> half = force_at(1.25), full = force_at(1.5), later = force_at(7.0);
  for (int i = 0; i < 3; ++i) {
    CHECK(half(1, i) == Approx(-0.5 * 10 * m[i]).epsilon(1e-14));
    CHECK(full(1, i) == Approx(-10 * m[i]).epsilon(1e-14));
    CHECK(later(1, i) == full(1, i));
    CHECK(full(0, i) == 0);
    CHECK(full(2, i) == 0);
  }
  CHECK_FALSE(gravity.has_derivatives());
  // No ramp: on at the start.
  const RampedGravity<double> step(m, 10.0, 1.0, 0.0);
  CHECK(step.share(0.999) == 0);
  CHECK(step.share(1.0) == 1);
}

TEMPLATE_TEST_CASE("a free cloth under ramped gravity gains the ramped impulse as momentum", "[ramped_gravity][implicit]",
                   float, double) {
  using S = TestType;
  ClothSpec<S> spec;
  spec.mesh = disk_mesh<S>(S(0.3), S(0.05));
  spec.pinned_nodes = std::vector<int>{};
  spec.areal_density = S(0.2);
  spec.gravity = 0;
  const Cloth<S> probe(spec);
  const VectorX<S> masses = probe.masses();
  spec.force_terms = {std::make_shared<RampedGravity<S>>(masses, S(10), S(0.2), S(0.3))};
  const Cloth<S> cloth(spec);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  ImplicitEuler<S> integrator(cloth, options);
  State<S> s = cloth.initial_state();
  for (int k = 0; k < 60; ++k) REQUIRE(integrator.step(s).ok());
  // Impulse per kg: 0 until 0.2 s, 10 * 0.3 / 2 over the ramp, 10 * 0.5 after: 6.5 m/s at t = 1 s;
  // a step samples the force at one end of the step, at most one step's worth (1/6 m/s) off.
  const S total = masses.sum();
  const S vy = (s.velocities.row(1) * masses).sum() / total;
  CHECK(std::abs(double(vy) + 6.5) < 10.0 / 60 + 1e-3);
  // Every node falls alike (no force but gravity acts on the unstrained disk).
  CHECK((s.velocities.row(1).array() - vy).abs().maxCoeff() < S(1e-3));
  CHECK(s.velocities.row(0).cwiseAbs().maxCoeff() < S(1e-4));
}

TEST_CASE("ramped gravity names its bad arguments", "[ramped_gravity][errors]") {
  VectorX<double> m = VectorX<double>::Ones(2);
  auto message = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const InvalidParameter& e) {
      return e.what();
    }
    return "";
  };
  CHECK_THAT(message([&] { RampedGravity<double>(m, -1.0, 0.0, 0.0); }), Catch::Contains("ramped gravity g"));
  CHECK_THAT(message([&] { RampedGravity<double>(m, 10.0, 0.0, -1.0); }), Catch::Contains("ramped gravity ramp"));
  m[1] = -1;
  CHECK_THAT(message([&] { RampedGravity<double>(m, 10.0, 0.0, 0.0); }), Catch::Contains("ramped gravity masses[1]"));
}
