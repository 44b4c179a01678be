#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstring>

#include "drape/integrators/make_integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"
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

template <class Stepper>
State<double> run(const Cloth<double>& cloth, double dt, double duration) {
  Stepper stepper(cloth, {dt, 1});
  State<double> s = cloth.initial_state();
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < steps; ++k) REQUIRE(stepper.step(s).ok());
  return s;
}

}  // namespace

TEMPLATE_TEST_CASE("one symplectic Euler step: v += dt f(x, v) / m, then x += dt v with the new v",
                   "[symplectic][stages]", float, double) {
  using S = TestType;
  for (int threads : {1, 2}) {
    ClothSpec<S> spec;  // the brief's cloth: 6.2k springs, two threads are used
    spec.boundary = BoundaryCondition::TwoCorners;
    const Cloth<S> cloth(spec);
    State<S> s = cloth.initial_state();
    s.positions = test::jiggled_positions(cloth, S(0.2), 31);
    s.velocities = test::random_velocities<S>(cloth.node_count(), S(1), 32);
    s.velocities.col(cloth.pins().nodes().back()) = Vec3<S>(1, -2, 3);  // ignored: pinned
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
    const S eps = std::is_same<S, float>::value ? S(1e-6) : S(1e-14);
    REQUIRE((s.positions - x_new).cwiseAbs().maxCoeff() <= eps * x_new.cwiseAbs().maxCoeff());
    REQUIRE((s.velocities - v_new).cwiseAbs().maxCoeff() <= eps * v_new.cwiseAbs().maxCoeff());
    REQUIRE(s.time == t0 + dt);
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
  auto spec = test::small_spec<S>(4, S(10));
  spec.pinned_nodes = std::vector<int>{};
  spec.springs = {{S(300), S(1)}, {S(200), S(1)}, {S(50), S(1)}};
  const Cloth<S> cloth(spec);
  const S dt = S(1e-3);
  SymplecticEuler<S> stepper(cloth, {double(dt), 1});
  State<S> s = cloth.initial_state();
  for (int k = 0; k < 500; ++k) REQUIRE(stepper.step(s).ok());
  const S t = S(500) * dt;
  // v_n = -g n dt, x_n = -g dt^2 n (n + 1) / 2: first order, half a step ahead of the parabola.
  const S expected = -S(10) * t * t / 2 - S(10) * t * dt / 2;
  const S tol = std::is_same<S, float>::value ? S(1e-4) : S(1e-12);
  REQUIRE(s.time == Approx(t));
  for (int i = 0; i < cloth.node_count(); ++i) {
    REQUIRE(test::close<S>(s.positions(1, i), expected, tol));
    REQUIRE(test::close<S>(s.velocities(1, i), -S(10) * t, tol));
  }
  REQUIRE(std::abs(max_strain(cloth, s.positions)) < tol);
}

TEMPLATE_TEST_CASE("symplectic Euler: pinned nodes stay bit-identical and at rest", "[symplectic][pins]", float,
                   double) {
  using S = TestType;
  ClothSpec<S> spec;
  spec.nx = spec.ny = 9;
  const Cloth<S> cloth(spec);
  SymplecticEuler<S> stepper(cloth);
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
  for (auto bc : {BoundaryCondition::OneCorner, BoundaryCondition::TwoCorners}) {
    ClothSpec<double> spec;
    spec.boundary = bc;
    const Cloth<double> cloth(spec);
    SymplecticEuler<double> stepper(cloth);
    State<double> s = cloth.initial_state();
    const int steps = static_cast<int>(std::lround(3.0 / stepper.dt()));
    for (int k = 0; k < steps; ++k) REQUIRE(stepper.step(s).ok());
    REQUIRE(s.positions.cwiseAbs().maxCoeff() < 10.0);
    REQUIRE(max_strain(cloth, s.positions) < 0.5);
  }
}
