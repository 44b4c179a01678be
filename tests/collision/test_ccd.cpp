// Continuous collision tests of cloth self-collision (collision/continuous_collision.hpp). Every
// answer is held to the header's two promises: never late (no later than a time at which the pair
// is known to be within the tolerance, and never nullopt then) and never far (the pair is within
// 2 tolerance + 3 r at the answer). Inputs: vertices through triangles and edges through
// edges at known times (interior, grazing an edge or a corner, at t = 0 and t = 1, coplanar motion,
// near-parallel and parallel edges, tiny and large motion), random motion against a sampled
// distance, near misses that must give nullopt (parallel layers, coplanar pass-bys, co-moving
// pairs), zero tolerance, and the search's work bounds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include <Eigen/Geometry>

#include "drape/collision/continuous_collision.hpp"
#include "drape/collision/primitive_distance.hpp"

using namespace drape;

namespace {

using V3 = Vec3<double>;
using Pair = drape::detail::ImpactPair;
template <class S>
using Points = std::array<Vec3<S>, 4>;

const char* name(Pair pair) { return pair == Pair::VertexTriangle ? "vertex-triangle" : "edge-edge"; }

template <class S>
std::optional<S> impact(Pair pair, const Points<S>& start, const Points<S>& end, S tolerance) {
  return pair == Pair::VertexTriangle ? vertex_triangle_impact(start, end, tolerance)
                                      : edge_edge_impact(start, end, tolerance);
}

/// The pair's distance at time t, in double from the given input.
template <class S>
double distance_at(Pair pair, const Points<S>& start, const Points<S>& end, double t) {
  std::array<V3, 4> x;
  for (std::size_t i = 0; i < 4; ++i) {
    const V3 from = start[i].template cast<double>(), to = end[i].template cast<double>();
    x[i] = from + t * (to - from);
  }
  if (pair == Pair::VertexTriangle)
    return std::sqrt(closest_point_on_triangle(x[0], x[1], x[2], x[3]).distance_squared);
  return std::sqrt(closest_points_on_segments(x[0], x[1], x[2], x[3]).distance_squared);
}

/// The most the distance at an answer may be: 2 tolerance + 3 r, r = 64 eps (largest coordinate),
/// plus this check's own rounding.
template <class S>
double far_bound(const Points<S>& start, const Points<S>& end, double tolerance) {
  double largest = 0;
  for (std::size_t i = 0; i < 4; ++i)
    largest = std::max({largest, double(start[i].cwiseAbs().maxCoeff()), double(end[i].cwiseAbs().maxCoeff())});
  const double r = 64 * std::numeric_limits<double>::epsilon() * largest;
  return 2 * tolerance + 4 * r;
}

std::string describe(double value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

/// "" if `answer` keeps both promises; `contact` is a time at which the pair is within the
/// tolerance (checked here), if one is known. A search that ran out of intervals promises only the
/// first.
template <class S>
std::string check_answer(Pair pair, const Points<S>& start, const Points<S>& end, S tolerance, std::optional<S> answer,
                         std::optional<double> contact) {
  if (contact) {
    const double d = distance_at(pair, start, end, *contact);
    if (d > double(tolerance))
      return "test error: no contact at t = " + describe(*contact) + ", distance " + describe(d);
    if (!answer) return "missed the contact at t = " + describe(*contact);
    if (double(*answer) > *contact)
      return "late: " + describe(double(*answer)) + " after contact at " + describe(*contact);
  }
  if (answer) {
    if (!(*answer >= 0 && *answer <= 1)) return "answer outside [0, 1]: " + describe(double(*answer));
    const double d = distance_at(pair, start, end, double(*answer)), bound = far_bound(start, end, double(tolerance));
    if (d > bound && !drape::detail::impact_search(pair, start, end, tolerance).exhausted)
      return "far: distance " + describe(d) + " > " + describe(bound) + " at t = " + describe(double(*answer));
  }
  return "";
}

template <class S>
std::string describe(const Points<S>& start, const Points<S>& end, S tolerance) {
  std::ostringstream s;
  s.precision(17);
  s << "tolerance " << tolerance << "\n";
  for (std::size_t i = 0; i < 4; ++i) s << "  " << start[i].transpose() << "  ->  " << end[i].transpose() << "\n";
  return s.str();
}

/// Counts failures of many trials and keeps the first one's story.
struct Tally {
  int trials = 0, failures = 0;
  std::string first;
  template <class S>
  void add(const std::string& problem, Pair pair, const Points<S>& start, const Points<S>& end, S tolerance) {
    ++trials;
    if (problem.empty()) return;
    if (failures++ == 0) first = std::string(name(pair)) + ": " + problem + "\n" + describe(start, end, tolerance);
  }
};

V3 random_vector(std::mt19937& rng, double half_width) {
  std::uniform_real_distribution<double> u(-half_width, half_width);
  return {u(rng), u(rng), u(rng)};
}

Mat3<double> random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> angle(0, 6.283185307179586);
  return Eigen::AngleAxis<double>(angle(rng), random_vector(rng, 1).normalized()).toRotationMatrix();
}

/// Points at a known time `at` moving with `velocity`: their start and end in Scalar, the start
/// exact at t = 0 and the end exact at t = 1.
template <class S>
void place(const std::array<V3, 4>& at, const std::array<V3, 4>& velocity, double time, Points<S>& start,
           Points<S>& end) {
  for (std::size_t i = 0; i < 4; ++i) {
    start[i] = (at[i] - time * velocity[i]).template cast<S>();
    end[i] = (at[i] + (1 - time) * velocity[i]).template cast<S>();
  }
}

/// One of n cases, drawn independently for every choice a trial makes.
int choose(std::mt19937& rng, int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); }

/// A tolerance for a trial: small (1e-8 in double, 1e-5 in float, above its rounding), 1e-3, 0.02.
template <class S>
S trial_tolerance(std::mt19937& rng) {
  const std::array<S, 3> tolerances = {std::is_same_v<S, float> ? S(1e-5) : S(1e-8), S(1e-3), S(0.02)};
  return tolerances[std::size_t(choose(rng, 3))];
}

/// The time of contact of a trial: random, or exactly 0 or 1.
double trial_time(std::mt19937& rng) {
  const int kind = choose(rng, 10);
  if (kind == 0) return 0;
  if (kind == 1) return 1;
  return std::uniform_real_distribution<double>(0, 1)(rng);
}

/// Velocities of a trial: from very slow to ten times the size of the pair.
std::array<V3, 4> trial_velocities(std::mt19937& rng) {
  const std::array<double, 4> speeds = {1e-6, 0.3, 2, 10};
  const double speed = speeds[std::size_t(choose(rng, 4))];
  std::array<V3, 4> v;
  for (V3& x : v) x = random_vector(rng, speed);
  return v;
}

/// One trial in three moves in one plane throughout (z = 0, then rotated and shifted as a whole):
/// the coplanarity cubic vanishes identically.
void maybe_coplanar(std::mt19937& rng, std::array<V3, 4>& at, std::array<V3, 4>& velocity) {
  if (choose(rng, 3) != 0) return;
  const Mat3<double> rotation = random_rotation(rng);
  const V3 shift = random_vector(rng, 1);
  for (std::size_t i = 0; i < 4; ++i) {
    at[i].z() = 0;
    velocity[i].z() = 0;
    at[i] = rotation * at[i] + shift;
    velocity[i] = rotation * velocity[i];
  }
}

}  // namespace

TEMPLATE_TEST_CASE("a vertex passing through a triangle at a known time is found, no later", "[collision][ccd]", float,
                   double) {
  using S = TestType;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  Tally tally;
  for (int trial = 0; trial < 10000; ++trial) {
    std::array<V3, 4> at;
    do {
      for (std::size_t i = 1; i < 4; ++i) at[i] = random_vector(rng, 1);
    } while ((at[2] - at[1]).cross(at[3] - at[1]).norm() < 0.2);
    // Where p meets the triangle: inside, on an edge (grazing it), or at a corner.
    V3 w;
    const int where = choose(rng, 7);
    if (where < 5) {
      w = V3(0.02 + unit(rng), 0.02 + unit(rng), 0.02 + unit(rng));
    } else if (where == 5) {
      w = V3(0, unit(rng), unit(rng));
    } else {
      w = V3(0, 0, 1);
    }
    w /= w.sum();
    at[0] = w[0] * at[1] + w[1] * at[2] + w[2] * at[3];
    std::array<V3, 4> velocity = trial_velocities(rng);
    maybe_coplanar(rng, at, velocity);
    const double time = trial_time(rng);
    Points<S> start, end;
    place(at, velocity, time, start, end);
    const S tolerance = trial_tolerance<S>(rng);
    const std::optional<S> answer = vertex_triangle_impact(start, end, tolerance);
    tally.add(check_answer(Pair::VertexTriangle, start, end, tolerance, answer, time), Pair::VertexTriangle, start, end,
              tolerance);
  }
  INFO(tally.first);
  CHECK(tally.failures == 0);
}

TEMPLATE_TEST_CASE("edges passing through each other at a known time are found, no later", "[collision][ccd]", float,
                   double) {
  using S = TestType;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0, 1);
  Tally tally;
  for (int trial = 0; trial < 10000; ++trial) {
    std::array<V3, 4> at;
    do {
      at[0] = random_vector(rng, 1);
      at[1] = random_vector(rng, 1);
    } while ((at[1] - at[0]).norm() < 0.2);
    // Where they meet on p: inside or at an end; q's direction: any, near-parallel, parallel.
    const int end_of_p = choose(rng, 5);
    const double s = end_of_p == 0 ? 0.0 : end_of_p == 1 ? 1.0 : unit(rng);
    const V3 meet = at[0] + s * (at[1] - at[0]);
    const V3 along = (at[1] - at[0]).normalized();
    const V3 across = along.cross(random_vector(rng, 1)).normalized();
    const int kind = choose(rng, 4);
    const double angle = kind == 1 ? 1e-3 : kind == 2 ? 1e-6 : 0.0;
    const V3 direction = kind == 0 ? random_vector(rng, 1).normalized() : V3((along + angle * across).normalized());
    const double length = 0.2 + 2 * unit(rng), t_on_q = choose(rng, 7) == 0 ? 1.0 : unit(rng);
    at[2] = meet - t_on_q * length * direction;
    at[3] = meet + (1 - t_on_q) * length * direction;
    std::array<V3, 4> velocity = trial_velocities(rng);
    maybe_coplanar(rng, at, velocity);
    const double time = trial_time(rng);
    Points<S> start, end;
    place(at, velocity, time, start, end);
    const S tolerance = trial_tolerance<S>(rng);
    tally.add(check_answer(Pair::EdgeEdge, start, end, tolerance, edge_edge_impact(start, end, tolerance), time),
              Pair::EdgeEdge, start, end, tolerance);
  }
  INFO(tally.first);
  CHECK(tally.failures == 0);
}

TEMPLATE_TEST_CASE("random motion: no sampled contact is missed or answered late, and no answer is far",
                   "[collision][ccd]", float, double) {
  using S = TestType;
  std::mt19937 rng(3);
  for (Pair pair : {Pair::VertexTriangle, Pair::EdgeEdge}) {
    Tally tally;
    int contacts = 0, answers = 0;
    for (int trial = 0; trial < 4000; ++trial) {
      // Every fourth pair 1000 away from the origin, where float input has ~1e-4 steps.
      const V3 offset = trial % 4 == 3 ? V3(1000, -700, 300) : V3::Zero();
      Points<S> start, end;
      for (std::size_t i = 0; i < 4; ++i) {
        start[i] = (offset + random_vector(rng, 1)).template cast<S>();
        end[i] = (offset + random_vector(rng, 1)).template cast<S>();
      }
      const S tolerance = trial % 3 == 0 ? S(1e-3) : trial % 3 == 1 ? S(0.05) : S(0.2);
      std::optional<double> contact;
      const int samples = 200;
      for (int k = 0; k <= samples && !contact; ++k) {
        const double t = double(k) / samples;
        if (distance_at(pair, start, end, t) <= double(tolerance)) contact = t;
      }
      const std::optional<S> answer = impact(pair, start, end, tolerance);
      contacts += contact.has_value();
      answers += answer.has_value();
      tally.add(check_answer(pair, start, end, tolerance, answer, contact), pair, start, end, tolerance);
    }
    INFO(name(pair) << ": " << tally.first);
    CHECK(tally.failures == 0);
    CHECK(contacts > 600);          // the trials do meet
    CHECK(answers < tally.trials);  // and do miss
  }
}

TEMPLATE_TEST_CASE("near misses give nullopt: parallel layers, coplanar pass-bys, co-moving pairs", "[collision][ccd]",
                   float, double) {
  using S = TestType;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> unit(0, 1);
  Tally tally;
  for (int trial = 0; trial < 10000; ++trial) {
    const Pair pair = trial % 2 == 0 ? Pair::VertexTriangle : Pair::EdgeEdge;
    const S tolerance = std::is_same_v<S, float> ? S(trial % 4 < 2 ? 1e-4 : 1e-2) : S(trial % 4 < 2 ? 1e-7 : 1e-2);
    const double gap = double(tolerance) * (2.05 + 100 * unit(rng) * unit(rng));  // the bound is 2 tolerance
    std::array<V3, 4> from, to;
    switch (trial / 2 % 3) {
      case 0: {  // two parallel planes at the gap, every point moving (and deforming) in its own
        const int upper = pair == Pair::VertexTriangle ? 1 : 2;  // p alone, or q0 q1
        for (std::size_t i = 0; i < 4; ++i) {
          const double z = int(i) < upper ? gap : 0.0;
          from[i] = V3(2 * unit(rng) - 1, 2 * unit(rng) - 1, z);
          to[i] = V3(2 * unit(rng) - 1, 2 * unit(rng) - 1, z);
        }
        break;
      }
      case 1: {  // one plane throughout: passing beside the triangle's edge bc, or beside a parallel edge
        const V3 a(-1, -0.5, 0), b(0.5, -0.8, 0), c(0.6, 0.9, 0);
        const V3 along = (c - b).normalized(), out = V3(along.y(), -along.x(), 0);  // away from a
        const double s0 = 4 * unit(rng) - 2, s1 = 4 * unit(rng) - 2;
        if (pair == Pair::VertexTriangle) {
          from = {b + s0 * along + gap * out, a, b, c};
          to = {b + s1 * along + gap * out, a, b, c};
        } else {
          const double length = 0.2 + unit(rng);
          from = {b, c, b + s0 * along + gap * out, b + (s0 + length) * along + gap * out};
          to = {b, c, b + s1 * along + gap * out, b + (s1 + length) * along + gap * out};
        }
        const V3 common = random_vector(rng, 2);  // the plane itself moves
        for (V3& x : to) x += common;
        break;
      }
      default: {  // apart, and moving together
        do {
          for (V3& x : from) x = random_vector(rng, 1);
        } while (distance_at<double>(pair, from, from, 0) < gap);
        const V3 common = random_vector(rng, 3);
        for (std::size_t i = 0; i < 4; ++i) to[i] = from[i] + common;
        break;
      }
    }
    const Mat3<double> rotation = random_rotation(rng);
    const V3 shift = random_vector(rng, 1);
    Points<S> start, end;
    for (std::size_t i = 0; i < 4; ++i) {
      start[i] = (rotation * from[i] + shift).template cast<S>();
      end[i] = (rotation * to[i] + shift).template cast<S>();
    }
    const std::optional<S> answer = impact(pair, start, end, tolerance);
    tally.add(answer ? "a contact at t = " + describe(double(*answer)) + ", gap " + describe(gap) : "", pair, start,
              end, tolerance);
  }
  INFO(tally.first);
  CHECK(tally.failures == 0);
}

TEMPLATE_TEST_CASE("special cases: touching throughout, zero tolerance, contact at t = 0 and t = 1, scale",
                   "[collision][ccd]", float, double) {
  using S = TestType;
  const Vec3<S> a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const auto vt = [&](const Vec3<S>& p0, const Vec3<S>& p1, S tolerance) {
    return vertex_triangle_impact<S>({p0, a, b, c}, {p1, a, b, c}, tolerance);
  };
  SECTION("a vertex resting on the triangle, or on its corner, the whole step: contact at 0") {
    CHECK(vt(Vec3<S>(S(0.25), S(0.25), 0), Vec3<S>(S(0.25), S(0.25), 0), S(0)) == S(0));
    CHECK(vt(a, a, S(0)) == S(0));
    CHECK(edge_edge_impact<S>({a, b, b, c}, {a, b, b, c}, S(0)) == S(0));  // sharing an end
  }
  SECTION("zero tolerance, exactly representable crossings") {
    // The answer is the crossing itself, or a few rounding bounds (1e-14) before it.
    const auto near = [](std::optional<S> answer, double time) {
      return answer && double(*answer) <= time && double(*answer) > time - 1e-7;
    };
    CHECK(near(vt(Vec3<S>(S(0.25), S(0.25), -1), Vec3<S>(S(0.25), S(0.25), 1), S(0)), 0.5));
    CHECK(near(vt(Vec3<S>(S(0.5), S(0.5), -1), Vec3<S>(S(0.5), S(0.5), 1), S(0)), 0.5));  // through edge bc
    CHECK(near(vt(Vec3<S>(0, 0, -1), Vec3<S>(0, 0, 1), S(0)), 0.5));                      // through corner a
    CHECK_FALSE(vt(Vec3<S>(S(0.75), S(0.75), -1), Vec3<S>(S(0.75), S(0.75), 1), S(0)));   // past the edge
    // q sweeps down through p's segment, crossing at t = 0.25.
    const Vec3<S> q0(S(0.5), -1, 1), q1(S(0.5), 1, 1), drop(0, 0, -4);
    CHECK(near(edge_edge_impact<S>({a, b, q0, q1}, {a, b, q0 + drop, q1 + drop}, S(0)), 0.25));
  }
  SECTION("zero tolerance, touching exactly at t = 1 or t = 0 with coordinates that do not add exactly") {
    std::mt19937 rng(5);
    int missed = 0;
    for (int trial = 0; trial < 500; ++trial) {
      Points<S> start, end;
      for (std::size_t i = 0; i < 4; ++i) {
        start[i] = (V3(1000, -300, 70) + random_vector(rng, 1)).template cast<S>();
        end[i] = (V3(-20, 500, 3) + random_vector(rng, 1)).template cast<S>();
      }
      // p lands on corner a; p1 lands on q0 (vertices meet), at the end or at the start.
      Points<S> vt_start = start, vt_end = end, ee_start = start, ee_end = end;
      if (trial % 2 == 0) {
        vt_end[0] = vt_end[1];
        ee_end[1] = ee_end[2];
      } else {
        vt_start[0] = vt_start[1];
        ee_start[1] = ee_start[2];
      }
      const double time = trial % 2 == 0 ? 1.0 : 0.0;
      const auto hit = vertex_triangle_impact(vt_start, vt_end, S(0));
      missed += !hit || double(*hit) > time;
      const auto crossing = edge_edge_impact(ee_start, ee_end, S(0));
      missed += !crossing || double(*crossing) > time;
    }
    CHECK(missed == 0);
  }
  SECTION("non-finite input is a contact at the start") {
    const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
    CHECK(vt(Vec3<S>(nan, 0, 0), Vec3<S>(0, 0, 1), S(0)) == S(0));
    CHECK(vt(Vec3<S>(0, 0, 1), Vec3<S>(inf, 0, 1), S(0)) == S(0));
    CHECK(edge_edge_impact<S>({a, b, c, Vec3<S>(0, nan, 0)}, {a, b, c, c}, S(0)) == S(0));
  }
  SECTION("large motion: across the triangle from 1000 away and back out, tolerance 1e-6 of the size") {
    const auto hit = vt(Vec3<S>(S(0.2), S(0.3), -1000), Vec3<S>(S(0.2), S(0.3), 1000), S(1e-6));
    REQUIRE(hit);
    CHECK(double(*hit) <= 0.5);
    CHECK(double(*hit) > 0.5 - 1e-6);
    const Vec3<S> q0(S(0.5), -1, 1000), q1(S(0.5), 1, 1000), drop(0, 0, -2000);
    const auto crossing = edge_edge_impact<S>({a, b, q0, q1}, {a, b, q0 + drop, q1 + drop}, S(1e-6));
    REQUIRE(crossing);
    CHECK(double(*crossing) <= 0.5);
    CHECK(double(*crossing) > 0.5 - 1e-6);
  }
  SECTION("tiny scale: a 1e-5 triangle, a crossing at t = 0.3 and a miss by 10 tolerances") {
    const S size = S(1e-5), tolerance = S(1e-9);
    const Vec3<S> ta = a * size, tb = b * size, tc = c * size;
    const Vec3<S> p0 = Vec3<S>(S(0.2), S(0.2), S(-0.3)) * size, p1 = Vec3<S>(S(0.2), S(0.2), S(0.7)) * size;
    const auto hit = vertex_triangle_impact<S>({p0, ta, tb, tc}, {p1, ta, tb, tc}, tolerance);
    REQUIRE(hit);
    CHECK(double(*hit) <= 0.3 + 1e-6);
    CHECK(double(*hit) > 0.3 - 1e-3);
    const Vec3<S> beside(0, 0, 10 * tolerance);
    CHECK_FALSE(
        vertex_triangle_impact<S>({Vec3<S>(tb + beside), ta, tb, tc}, {Vec3<S>(tc + beside), ta, tb, tc}, tolerance));
  }
  SECTION("a tolerance near the rounding of the closest points' direction: still within 2 tolerance") {
    // Edges meeting end to side, found by a randomized search: with a tolerance of 1e-8 the
    // direction between closest points 1e-8 apart is uncertain to ~1e-8, and a search that took
    // the first short interval it could not exclude answered 2.09e-8 away.
    const Points<double> start = {V3(-1.0987535677371278, 0.89454981716579318, -0.013890185839247809),
                                  V3(0.75093683298535252, 0.037919529949642219, 0.42005915176385472),
                                  V3(-2.079916364014962, 1.3876329068212689, -0.053485622441152417),
                                  V3(-1.1028538486006167, 0.53909064716167521, 0.3456478304184607)};
    const Points<double> end = {V3(-0.87579346652226808, 0.65659302570430012, 0.15684849334651549),
                                V3(0.57844452925419731, 0.095329437146061693, 0.3960025110412515),
                                V3(-2.3188436881305363, 1.2136019966859886, -0.081051674139561727),
                                V3(-0.87578386849490431, 0.65742509232461144, 0.1560068788734453)};
    const auto hit = edge_edge_impact(start, end, 1e-8);
    REQUIRE(hit);
    CHECK(distance_at(Pair::EdgeEdge, start, end, *hit) <= far_bound(start, end, 1e-8));
  }
  SECTION("coplanar: a vertex sliding in the triangle's plane enters across edge bc at t = 0.6") {
    // p moves along the line x = y toward the corner a, crossing bc (x + y = 1) at x = y = 0.5.
    const Vec3<S> p0(S(1.1), S(1.1), 0), p1(S(0.1), S(0.1), 0);
    const auto hit = vt(p0, p1, S(1e-6));
    REQUIRE(hit);
    CHECK(double(*hit) <= 0.6 + 1e-6);
    CHECK(double(*hit) > 0.6 - 1e-3);
    // Sliding past the corner b, 0.01 outside it, never enters.
    CHECK_FALSE(vt(Vec3<S>(S(1.01), -1, 0), Vec3<S>(S(1.01), 1, 0), S(1e-4)));
  }
}

TEMPLATE_TEST_CASE(
    "search work: layers apart take one interval, crossings a few dozen, a cut-short search is never late",
    "[collision][ccd]", float, double) {
  using S = TestType;
  // A vertex 0.01 over a tilted triangle, both drifting: the closest points' direction excludes at once.
  const Mat3<double> tilt = Eigen::AngleAxis<double>(0.9, V3(1, 2, 3).normalized()).toRotationMatrix();
  const auto tilted = [&](double x, double y, double z) -> Vec3<S> { return (tilt * V3(x, y, z)).template cast<S>(); };
  const auto layered = drape::detail::impact_search<S>(
      Pair::VertexTriangle, {tilted(0.3, 0.3, 0.01), tilted(0, 0, 0), tilted(1, 0, 0), tilted(0, 1, 0)},
      {tilted(0.35, 0.3, 0.01), tilted(0.01, 0, 0), tilted(1.01, 0, 0), tilted(0.01, 1, 0)}, S(1e-4));
  CHECK_FALSE(layered.time);
  CHECK(layered.intervals == 1);
  // Two parallel edges of the two layers.
  const auto parallel = drape::detail::impact_search<S>(
      Pair::EdgeEdge, {tilted(0, 0, 0), tilted(1, 0, 0), tilted(0.2, 0.05, 0.01), tilted(1.2, 0.05, 0.01)},
      {tilted(0, 0.01, 0), tilted(1, 0.01, 0), tilted(0.25, 0.05, 0.01), tilted(1.25, 0.05, 0.01)}, S(1e-4));
  CHECK_FALSE(parallel.time);
  CHECK(parallel.intervals == 1);
  // Touching at the start: the first interval answers.
  const auto touching = drape::detail::impact_search<S>(
      Pair::VertexTriangle, {tilted(0.3, 0.3, 0), tilted(0, 0, 0), tilted(1, 0, 0), tilted(0, 1, 0)},
      {tilted(0.3, 0.3, -1), tilted(0, 0, 1), tilted(1, 0, 1), tilted(0, 1, 1)}, S(1e-4));
  CHECK(touching.time == 0.0);
  CHECK(touching.intervals == 1);

  // Random crossings: the work they take, and the same searches cut short.
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> unit(0, 1);
  int most = 0, exhausted = 0, late = 0, lost = 0;
  long total = 0;
  const int trials = 2000;
  for (int trial = 0; trial < trials; ++trial) {
    const Pair pair = trial % 2 == 0 ? Pair::VertexTriangle : Pair::EdgeEdge;
    std::array<V3, 4> at;
    for (V3& x : at) x = random_vector(rng, 1);
    if (pair == Pair::VertexTriangle) {
      const V3 w = V3(unit(rng), unit(rng), unit(rng)) / 3;
      at[0] = (1 - w[1] - w[2]) * at[1] + w[1] * at[2] + w[2] * at[3];
    } else {
      const V3 meet = at[0] + unit(rng) * (at[1] - at[0]), direction = at[3] - at[2];
      const double t_on_q = unit(rng);
      at[2] = meet - t_on_q * direction;
      at[3] = meet + (1 - t_on_q) * direction;
    }
    const std::array<V3, 4> velocity = {random_vector(rng, 2), random_vector(rng, 2), random_vector(rng, 2),
                                        random_vector(rng, 2)};
    const double time = unit(rng);
    Points<S> start, end;
    place(at, velocity, time, start, end);
    const S tolerance = std::is_same_v<S, float> ? S(1e-5) : S(1e-6);
    if (distance_at(pair, start, end, time) > double(tolerance)) continue;  // the construction lost to rounding
    const auto search = drape::detail::impact_search(pair, start, end, tolerance);
    most = std::max(most, search.intervals);
    total += search.intervals;
    exhausted += search.exhausted;
    for (int limit : {1, 3, 10, 30, 100}) {
      const auto cut = drape::detail::impact_search(pair, start, end, tolerance, limit);
      lost += !cut.time;
      late += cut.time && *cut.time > time;
    }
  }
  INFO("intervals: at most " << most << ", on average " << double(total) / trials);
  CHECK(exhausted == 0);
  CHECK(most < 200);
  CHECK(double(total) / trials < 60);
  CHECK(lost == 0);
  CHECK(late == 0);
}
