#pragma once
// What the tests of the explicit integrators (test_rk2.cpp, test_symplectic_euler.cpp) share: the
// swinging cloth, a run of one integrator, the start and the check of a single step against the
// scheme written out, and the checks every explicit integrator passes (free fall, pins, the default
// scene at the default dt).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <type_traits>

#include "drape/integrators/explicit_integrator.hpp"
#include "drape/physics/diagnostics.hpp"
#include "test_common.hpp"

namespace drape::test {

// A small swinging cloth: one corner pinned, gravity on, kd = 0 unless asked for.
inline ClothSpec<double> swing_spec(double kd = 0) {
  auto spec = small_spec<double>(5, 10.0);
  spec.boundary = BoundaryCondition::OneCorner;
  spec.springs = {{300, kd}, {200, kd}, {50, kd}};
  return spec;
}

// `duration` seconds of `cloth` with `Stepper` at `dt` on one thread.
template <class Stepper>
State<double> run(const Cloth<double>& cloth, double dt, double duration) {
  Stepper stepper(cloth, {dt, 1});
  State<double> s = cloth.initial_state();
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < steps; ++k) REQUIRE(stepper.step(s).ok());
  return s;
}

// The default cloth (6.2k springs, two threads are used), two corners pinned.
template <class S>
ClothSpec<S> stage_spec() {
  ClothSpec<S> spec;
  spec.boundary = BoundaryCondition::TwoCorners;
  return spec;
}

// A start far from rest for one step: jiggled positions, random velocities, and a velocity on a
// pinned node that the step must ignore.
template <class S>
State<S> stage_start(const Cloth<S>& cloth) {
  State<S> s = cloth.initial_state();
  s.positions = jiggled_positions(cloth, S(0.2), 31);
  s.velocities = random_velocities<S>(cloth.node_count(), S(1), 32);
  s.velocities.col(cloth.pins().nodes().back()) = Vec3<S>(1, -2, 3);  // ignored: pinned
  return s;
}

// The state after one step from t0 by dt equals (x_new, v_new) to rounding.
template <class S>
void require_step_result(const State<S>& s, const Matrix3X<S>& x_new, const Matrix3X<S>& v_new, S t0, S dt) {
  const S eps = std::is_same<S, float>::value ? S(1e-6) : S(1e-14);
  REQUIRE((s.positions - x_new).cwiseAbs().maxCoeff() <= eps * x_new.cwiseAbs().maxCoeff());
  REQUIRE((s.velocities - v_new).cwiseAbs().maxCoeff() <= eps * v_new.cwiseAbs().maxCoeff());
  REQUIRE(s.time == t0 + dt);
}

// An unpinned cloth falls 500 steps of 1 ms with `Stepper`: every node at height expected(t, dt)
// with velocity -g t, the springs at rest.
template <template <class> class Stepper, class S, class Expected>
void require_free_fall(const Expected& expected) {
  auto spec = small_spec<S>(4, S(10));
  spec.pinned_nodes = std::vector<int>{};
  spec.springs = {{S(300), S(1)}, {S(200), S(1)}, {S(50), S(1)}};
  const Cloth<S> cloth(spec);
  const S dt = S(1e-3);
  Stepper<S> stepper(cloth, {double(dt), 1});
  State<S> s = cloth.initial_state();
  for (int k = 0; k < 500; ++k) REQUIRE(stepper.step(s).ok());
  const S t = S(500) * dt;
  const S height = expected(t, dt);
  const S tol = std::is_same<S, float>::value ? S(1e-4) : S(1e-12);
  REQUIRE(s.time == Approx(t));
  for (int i = 0; i < cloth.node_count(); ++i) {
    REQUIRE(close<S>(s.positions(1, i), height, tol));
    REQUIRE(close<S>(s.velocities(1, i), -S(10) * t, tol));
  }
  REQUIRE(std::abs(max_strain(cloth, s.positions)) < tol);
}

// A 9 x 9 cloth held by `boundary` runs 300 steps with `Stepper` from a start with a velocity on a
// pinned node: its pinned nodes keep their bits and stay at rest while the rest falls.
template <template <class> class Stepper, class S>
void require_pins_stay_put(BoundaryCondition boundary) {
  ClothSpec<S> spec;
  spec.nx = spec.ny = 9;
  spec.boundary = boundary;
  const Cloth<S> cloth(spec);
  Stepper<S> stepper(cloth);
  State<S> s = cloth.initial_state();
  const Matrix3X<S> start = s.positions;
  s.velocities.col(cloth.pins().nodes().front()) = Vec3<S>(1, 2, 3);  // a careless caller
  for (int k = 0; k < 300; ++k) REQUIRE(stepper.step(s).ok());
  for (int p : cloth.pins().nodes()) {
    REQUIRE(std::memcmp(s.positions.col(p).data(), start.col(p).data(), 3 * sizeof(S)) == 0);
    REQUIRE(s.velocities.col(p).isZero(0));
  }
  REQUIRE(s.positions.row(1).minCoeff() < S(-0.1));  // the rest of the cloth did fall
}

// The default scene runs 3 s with `Stepper` at the default dt for both boundary conditions:
// bounded (nothing flew off) and the springs not absurdly stretched.
template <class Stepper>
void require_default_scene_stable() {
  for (auto bc : {BoundaryCondition::OneCorner, BoundaryCondition::TwoCorners}) {
    ClothSpec<double> spec;
    spec.boundary = bc;
    const Cloth<double> cloth(spec);
    Stepper stepper(cloth);
    State<double> s = cloth.initial_state();
    const int steps = static_cast<int>(std::lround(3.0 / stepper.dt()));
    for (int k = 0; k < steps; ++k) REQUIRE(stepper.step(s).ok());
    REQUIRE(s.positions.cwiseAbs().maxCoeff() < 10.0);
    REQUIRE(max_strain(cloth, s.positions) < 0.5);
  }
}

}  // namespace drape::test
