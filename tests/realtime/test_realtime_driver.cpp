#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include "drape/fwd.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/realtime/realtime_driver.hpp"
#include "test_common.hpp"

namespace {

/// A steady clock whose time only moves when a test says so.
struct FakeClock {
  using rep = std::int64_t;
  using period = std::nano;
  using duration = std::chrono::nanoseconds;
  using time_point = std::chrono::time_point<FakeClock>;
  static constexpr bool is_steady = true;
  static inline time_point current{};
  static time_point now() { return current; }
  static void advance(duration d) { current += d; }
};

using Driver = drape::RealtimeDriver<FakeClock>;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

/// Random frame intervals between 0.1 ms and 60 ms, at nanosecond resolution.
std::vector<nanoseconds> irregular_intervals(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::int64_t> ns(100'000, 60'000'000);
  std::vector<nanoseconds> out;
  for (int k = 0; k < count; ++k) out.emplace_back(ns(rng));
  return out;
}

}  // namespace

TEST_CASE("irregular frame intervals: simulated time = factor x wall time within one dt", "[realtime]") {
  const double dt = 0.001;
  for (const double factor : {1.0, 0.5, 2.0}) {
    CAPTURE(factor);
    Driver driver(dt, {factor, 1'000'000});
    driver.start();
    double simulated = 0, wall = 0;
    int frames_with_steps = 0;
    for (const nanoseconds d : irregular_intervals(500, 7)) {
      FakeClock::advance(d);
      const drape::RealtimeFrame f = driver.next_frame();
      simulated += f.steps * dt;
      wall += std::chrono::duration<double>(d).count();
      frames_with_steps += f.steps > 0;
      REQUIRE(f.dropped == 0.0);
      REQUIRE(f.wall_elapsed == Approx(std::chrono::duration<double>(d).count()));
      // Never ahead of the wall clock, never more than one step behind it.
      REQUIRE(simulated <= factor * wall + 1e-9);
      REQUIRE(factor * wall - simulated < dt + 1e-9);
      REQUIRE(f.total_simulated == Approx(simulated));
      REQUIRE(f.interpolation >= 0.0);
      REQUIRE(f.interpolation < 1.0);
      REQUIRE(f.interpolation * dt == Approx(factor * wall - simulated).margin(1e-9));
    }
    REQUIRE(frames_with_steps > 400);
    REQUIRE(driver.next_frame().overall_factor() == Approx(factor).epsilon(1e-3));
  }
}

TEST_CASE("factor 0.5 runs at half speed and 2 at double speed", "[realtime]") {
  const double dt = 0.0005;
  for (const double factor : {0.5, 2.0}) {
    CAPTURE(factor);
    Driver driver(dt, {factor, 1'000'000});
    driver.start();
    drape::RealtimeFrame f;
    for (int k = 0; k < 300; ++k) {  // 300 frames of 1/60 s = 5 s of wall time
      FakeClock::advance(nanoseconds(16'666'667));
      f = driver.next_frame();
      // Steady frames: each frame's achieved factor is the requested one to within one step.
      REQUIRE(std::abs(f.achieved_factor - factor) <= dt / f.wall_elapsed + 1e-12);
    }
    REQUIRE(f.total_wall == Approx(5.0).epsilon(1e-6));
    REQUIRE(std::abs(f.total_simulated - factor * 5.0) < dt);
  }
}

TEST_CASE("the cap bounds the steps per frame and the dropped time is reported", "[realtime]") {
  const double dt = 0.001;
  const int cap = 10;
  Driver driver(dt, {1.0, cap});
  driver.start();
  double dropped = 0;
  for (int k = 0; k < 20; ++k) {
    FakeClock::advance(milliseconds(100));  // 100 steps owed per frame, 10 allowed
    const drape::RealtimeFrame f = driver.next_frame();
    REQUIRE(f.steps == cap);
    REQUIRE(f.dropped == Approx(0.090).margin(1e-12));
    dropped += f.dropped;
    REQUIRE(f.total_dropped == Approx(dropped));
    // Everything owed is accounted for: granted + dropped + carried remainder.
    REQUIRE(f.total_simulated + f.total_dropped + f.interpolation * dt == Approx(f.total_wall));
    REQUIRE(f.achieved_factor == Approx(0.1));
  }
  // Dropped time is never made up later: once frames are fast again, the driver keeps pace
  // without a burst of catch-up steps.
  FakeClock::advance(milliseconds(5));
  const drape::RealtimeFrame f = driver.next_frame();
  REQUIRE(f.steps <= 6);
  REQUIRE(f.dropped == 0.0);
}

TEST_CASE("whole steps only: the remainder carries to the next frame", "[realtime]") {
  Driver driver(0.010, {1.0, 100});
  driver.start();
  FakeClock::advance(milliseconds(25));
  drape::RealtimeFrame f = driver.next_frame();
  REQUIRE(f.steps == 2);
  REQUIRE(f.interpolation == Approx(0.5));
  FakeClock::advance(milliseconds(7));  // 5 ms carried + 7 ms = 12 ms -> 1 step, 2 ms left
  f = driver.next_frame();
  REQUIRE(f.steps == 1);
  REQUIRE(f.interpolation == Approx(0.2));
  FakeClock::advance(milliseconds(0));  // a zero-length frame is legal and grants nothing
  f = driver.next_frame();
  REQUIRE(f.steps == 0);
  REQUIRE(f.achieved_factor == 0.0);
}

TEST_CASE("the same states result whatever the frame pacing", "[realtime]") {
  const drape::Clothd cloth(drape::test::small_spec<double>(6, 10.0));
  const double dt = 0.001;

  // Runs the cloth under `intervals`; returns the state after every whole 0.1 s of wall time.
  const auto run = [&](const std::vector<nanoseconds>& intervals) {
    drape::Rk2d rk2(cloth, {dt, 1});
    Driver driver(rk2.dt(), {1.0, 1'000'000});
    driver.start();
    drape::Stated state = cloth.initial_state();
    std::vector<std::pair<std::int64_t, drape::Stated>> checkpoints;
    nanoseconds wall{0};
    for (const nanoseconds d : intervals) {
      FakeClock::advance(d);
      wall += d;
      const drape::RealtimeFrame f = driver.next_frame();
      for (int k = 0; k < f.steps; ++k) REQUIRE(rk2.step(state).ok());
      if (wall.count() % 100'000'000 == 0) checkpoints.emplace_back(driver.steps_granted(), state);
    }
    return checkpoints;
  };

  // Pacing A: steady 20 ms frames. Pacing B: random frames, each 0.1 s split at random points.
  std::vector<nanoseconds> steady(50, milliseconds(20));
  std::vector<nanoseconds> irregular;
  std::mt19937 rng(3);
  for (int block = 0; block < 10; ++block) {
    std::int64_t left = 100'000'000;
    while (left > 0) {
      const std::int64_t d = std::min<std::int64_t>(left, std::uniform_int_distribution<std::int64_t>(1, 30'000'000)(rng));
      irregular.emplace_back(d);
      left -= d;
    }
  }
  const auto a = run(steady);
  const auto b = run(irregular);
  REQUIRE(a.size() == 10);
  REQUIRE(b.size() == 10);
  REQUIRE(irregular.size() > 50);
  for (std::size_t c = 0; c < a.size(); ++c) {
    CAPTURE(c);
    REQUIRE(a[c].first == b[c].first);
    REQUIRE(a[c].first == std::int64_t(100) * std::int64_t(c + 1));
    REQUIRE((a[c].second.positions.array() == b[c].second.positions.array()).all());
    REQUIRE((a[c].second.velocities.array() == b[c].second.velocities.array()).all());
  }
}

TEST_CASE("zero, negative and non-finite driver inputs are rejected", "[realtime]") {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {0.0, -0.001, inf, nan}) {
    REQUIRE_THROWS_WITH(Driver(bad, {1.0, 10}), Catch::Contains("'dt'") && Catch::Contains("> 0"));
    REQUIRE_THROWS_WITH(Driver(0.001, {bad, 10}), Catch::Contains("'realtime_factor'") && Catch::Contains("> 0"));
  }
  for (const int bad : {0, -1}) REQUIRE_THROWS_WITH(Driver(0.001, {1.0, bad}), Catch::Contains("'max_steps_per_frame'"));
  REQUIRE_NOTHROW(Driver(0.001, {1.0, 1}));
}

TEST_CASE("the default clock is std::chrono::steady_clock", "[realtime]") {
  STATIC_REQUIRE(std::is_same_v<drape::RealtimeDriver<>::clock, std::chrono::steady_clock>);
  drape::RealtimeDriver<> driver(0.001);
  driver.start();
  const drape::RealtimeFrame f = driver.next_frame();
  REQUIRE(f.steps >= 0);
  REQUIRE(f.wall_elapsed >= 0.0);
}
