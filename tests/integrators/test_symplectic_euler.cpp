#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstring>

#include "drape/integrators/make_integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/platform/team.hpp"
#include "integrators/explicit_test_helpers.hpp"
#include "test_common.hpp"

using namespace drape;

using test::run;
using test::swing_spec;

TEMPLATE_TEST_CASE("one symplectic Euler step: v += dt f(x, v) / m, then x += dt v with the new v",
                   "[symplectic][stages]", float, double) {
  using S = TestType;
  for (int threads : {1, 2}) {
    const Cloth<S> cloth(test::stage_spec<S>());
    State<S> s = test::stage_start(cloth);
    const S dt = S(IntegratorOptions{}.dt);
    const ForceAssembler<S> forces(cloth, 1);
    Matrix3X<S> f(3, cloth.node_count());
    forces.force(s.positions, s.velocities, S(0), f);
    Matrix3X<S> v_new =
        s.velocities + dt * Matrix3X<S>(f.array().rowwise() / cloth.grid().masses().transpose().array());
    Matrix3X<S> x_new = s.positions + dt * v_new;
    for (int p : cloth.pins().nodes()) {
      x_new.col(p) = s.positions.col(p);
      v_new.col(p).setZero();
    }
    SymplecticEuler<S> stepper(cloth, {double(dt), threads});
    REQUIRE(stepper.forces().threads() == std::min(threads, max_threads()));
    const S t0 = s.time;
    REQUIRE(stepper.step(s).ok());
    INFO(threads << " thread(s)");
    test::require_step_result(s, x_new, v_new, t0, dt);
  }
}

TEST_CASE("symplectic Euler is first order: global error halves when dt halves", "[symplectic][convergence]") {
  const Cloth<double> cloth(swing_spec(0.05));
  const double T = 0.25;
  const State<double> reference = run<Rk2<double>>(cloth, 1e-3 / 64, T);  // second order: converged
  double previous = 0;
  for (double dt : {1e-3, 5e-4, 2.5e-4}) {
    const double error =
        (run<SymplecticEuler<double>>(cloth, dt, T).positions - reference.positions).cwiseAbs().maxCoeff();
    if (previous > 0) {
      INFO("dt " << dt << " error " << error << " ratio " << previous / error);
      REQUIRE(previous / error == Approx(2.0).epsilon(0.15));
    }
    previous = error;
  }
}

// Symplectic Euler conserves a modified energy within O(dt) of the true one for all time: the
// energy error of an undamped cloth oscillates with an amplitude proportional to dt and, once the
// swing has spread its energy over the modes (the first seconds), stops growing. RK2 at the same dt
// drifts (its error grows with the length of the run).
TEST_CASE("symplectic Euler without damping: energy error O(dt) and bounded over a long run, RK2's drifts",
          "[symplectic][energy]") {
  const Cloth<double> cloth(swing_spec(0));
  const double E0 = total_energy(cloth, cloth.initial_state());
  // The largest |E - E0| in each of four equal stretches of a 16 s run.
  const auto errors = [&](IntegratorKind kind, double dt) {
    ImplicitOptions options;
    options.dt = dt;
    options.threads = 1;
    auto stepper = make_integrator(cloth, kind, options);
    State<double> s = cloth.initial_state();
    std::array<double, 4> worst{};
    const long steps = std::lround(16.0 / dt);
    for (long k = 0; k < steps; ++k) {
      REQUIRE(stepper->step(s).ok());
      double& w = worst[static_cast<std::size_t>(4 * k / steps)];
      w = std::max(w, std::abs(total_energy(cloth, s) - E0));
    }
    return worst;
  };
  const std::array<double, 4> coarse = errors(IntegratorKind::Symplectic, 1e-3);
  const std::array<double, 4> fine = errors(IntegratorKind::Symplectic, 5e-4);
  const std::array<double, 4> rk2 = errors(IntegratorKind::Rk2, 1e-3);
  const auto largest = [](const std::array<double, 4>& w) { return *std::max_element(w.begin(), w.end()); };
  INFO("symplectic dt 1 ms " << coarse[1] << " -> " << coarse[3] << ", 0.5 ms " << fine[1] << " -> " << fine[3]
                             << "; RK2 1 ms " << rk2[1] << " -> " << rk2[3]);
  // First order in dt.
  CHECK(largest(coarse) / largest(fine) == Approx(2.0).epsilon(0.3));
  // Bounded: the last 4 s are no worse than the second 4 s (up to the swing's own variation).
  CHECK(coarse[3] <= 1.5 * coarse[1]);
  CHECK(fine[3] <= 1.5 * fine[1]);
  // RK2 drifts at the same dt, far past the symplectic error.
  CHECK(rk2[3] > 3 * rk2[1]);
  CHECK(rk2[3] > 10 * coarse[3]);
  // Small against the energy exchanged (the cloth falls ~0.4 m).
  CHECK(largest(fine) < 2e-2 * cloth.grid().total_mass() * 10.0);
}

TEMPLATE_TEST_CASE("symplectic Euler free fall: x_n = -g t^2 / 2 - g t dt / 2 exactly, springs at rest",
                   "[symplectic][free-fall]", float, double) {
  using S = TestType;
  // v_n = -g n dt, x_n = -g dt^2 n (n + 1) / 2: first order, half a step ahead of the parabola.
  test::require_free_fall<SymplecticEuler, S>([](S t, S dt) { return -S(10) * t * t / 2 - S(10) * t * dt / 2; });
}

TEMPLATE_TEST_CASE("symplectic Euler: pinned nodes stay bit-identical and at rest", "[symplectic][pins]", float,
                   double) {
  test::require_pins_stay_put<SymplecticEuler, TestType>(ClothSpec<TestType>{}.boundary);
}

TEST_CASE("symplectic Euler: 1 and 2 threads agree bit for bit; a diverging step is reported",
          "[symplectic][threads][failure]") {
  ClothSpec<double> spec;
  const Cloth<double> cloth(spec);
  State<double> one = cloth.initial_state(), two = one;
  SymplecticEuler<double> a(cloth, {IntegratorOptions{}.dt, 1}), b(cloth, {IntegratorOptions{}.dt, 2});
  for (int k = 0; k < 200; ++k) {
    REQUIRE(a.step(one).ok());
    REQUIRE(b.step(two).ok());
  }
  CHECK(std::memcmp(one.positions.data(), two.positions.data(), sizeof(double) * std::size_t(one.positions.size())) ==
        0);
  CHECK(std::memcmp(one.velocities.data(), two.velocities.data(),
                    sizeof(double) * std::size_t(one.velocities.size())) == 0);

  auto stiff = test::small_spec<double>(5, 10.0);
  stiff.springs = {{1e7, 0}, {1e7, 0}, {1e7, 0}};
  const Cloth<double> exploding(stiff);
  auto stepper = make_integrator(exploding, IntegratorKind::Symplectic, [] {
    ImplicitOptions o;
    o.dt = 0.01;
    o.threads = 1;
    return o;
  }());
  State<double> s = exploding.initial_state();
  s.positions = test::jiggled_positions(exploding, 0.2, 1);
  StepStatus status;
  State<double> before;
  for (int k = 0; k < 10000 && status.ok(); ++k) {
    before = s;
    status = stepper->step(s);
  }
  REQUIRE(status.error == StepError::NonFiniteState);
  REQUIRE(std::memcmp(s.positions.data(), before.positions.data(), sizeof(double) * std::size_t(s.positions.size())) ==
          0);
  REQUIRE(s.time == before.time);
}

TEST_CASE("the default scene is stable with symplectic Euler at the default dt for both boundary conditions",
          "[symplectic][defaults]") {
  // Largest stable dt of the default scene over 5 s: 0.71 ms (docs/parameters.md); the default 0.5 ms.
  test::require_default_scene_stable<SymplecticEuler<double>>();
}
