// Closest points of cloth self-collision (collision/primitive_distance.hpp) against dense sampling
// of the primitives, with a local optimality check (no nearby point of the primitive is closer),
// known answers and degenerate input; and the test-side mesh checks (tests/collision/mesh_checks.hpp):
// triangle-triangle intersection on known, constructed and exactly touching pairs, and the mesh-wide
// checks on a grid folded over itself.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Geometry>

#include "collision/mesh_checks.hpp"
#include "drape/collision/primitive_distance.hpp"
#include "drape/core/grid.hpp"

using namespace drape;

namespace {

using V3 = Vec3<double>;

template <class S>
Vec3<S> random_point(std::mt19937& rng, double half_width) {
  std::uniform_real_distribution<double> u(-half_width, half_width);
  return V3(u(rng), u(rng), u(rng)).template cast<S>();
}

V3 wide(const Vec3<float>& x) { return x.cast<double>(); }
V3 wide(const Vec3<double>& x) { return x; }

/// Smallest distance from p to the triangle over a barycentric lattice of spacing 1/n, and the
/// most the true distance can undercut it (a lattice cell's diameter).
struct Sampled {
  double distance;
  double resolution;
};

Sampled sampled_triangle_distance(const V3& p, const V3& a, const V3& b, const V3& c, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double wb = double(i) / n, wc = double(j) / n;
      best = std::min(best, ((1 - wb - wc) * a + wb * b + wc * c - p).norm());
    }
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  return {best, longest / n};
}

Sampled sampled_segment_distance(const V3& p0, const V3& p1, const V3& q0, const V3& q1, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double s = double(i) / n, t = double(j) / n;
      best = std::min(best, (p0 + s * (p1 - p0) - q0 - t * (q1 - q0)).norm());
    }
  return {best, ((p1 - p0).norm() + (q1 - q0).norm()) / n};
}

/// Tolerances for comparing with values computed in double from the Scalar input.
template <class S>
double accuracy() {
  return std::is_same_v<S, float> ? 2e-6 : 1e-12;
}

/// Checks a closest point on a triangle: valid weights, the distance of the point they give, no
/// farther than the sampled minimum, no nearer than the sampling allows, and no nearby point of the
/// triangle (a step of 1e-3 along every feasible direction of the weights) closer.
template <class S>
std::string check_triangle_closest(const Vec3<S>& p, const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& c) {
  const PointTriangleClosest<S> r = closest_point_on_triangle(p, a, b, c);
  const V3 x = wide(p), pa = wide(a), pb = wide(b), pc = wide(c);
  const V3 w = r.weights.template cast<double>();
  const double scale = 1 + x.norm() + pa.norm() + pb.norm() + pc.norm();
  const double eps = accuracy<S>() * scale;
  if (!(w.minCoeff() >= 0) || std::abs(w.sum() - 1) > accuracy<S>()) return "weights not barycentric";
  const auto distance_at = [&](const V3& weights) {
    return (weights[0] * pa + weights[1] * pb + weights[2] * pc - x).norm();
  };
  const double d = std::sqrt(double(r.distance_squared));
  if (std::abs(d - distance_at(w)) > eps) return "distance is not that of the weights' point";
  const Sampled sampled = sampled_triangle_distance(x, pa, pb, pc, 100);
  if (d > sampled.distance + eps) return "farther than a sampled point";
  if (d < sampled.distance - sampled.resolution - eps) return "nearer than the triangle allows";
  const double step = 1e-3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j || w[j] < step) continue;
      V3 moved = w;
      moved[i] += step;
      moved[j] -= step;
      // Squared distances: a first-order decrease at the kernel's point would show as ~1e-3 here.
      if (distance_at(moved) * distance_at(moved) < d * d - eps) return "a nearby point of the triangle is closer";
    }
  return "";
}

template <class S>
std::string check_segment_closest(const Vec3<S>& p0, const Vec3<S>& p1, const Vec3<S>& q0, const Vec3<S>& q1) {
  const SegmentClosest<S> r = closest_points_on_segments(p0, p1, q0, q1);
  const V3 a0 = wide(p0), a1 = wide(p1), b0 = wide(q0), b1 = wide(q1);
  const double scale = 1 + a0.norm() + a1.norm() + b0.norm() + b1.norm();
  const double eps = accuracy<S>() * scale;
  if (!(r.s >= 0 && r.s <= 1 && r.t >= 0 && r.t <= 1)) return "parameters outside [0, 1]";
  const auto distance_at = [&](double s, double t) { return (a0 + s * (a1 - a0) - b0 - t * (b1 - b0)).norm(); };
  const double d = std::sqrt(double(r.distance_squared));
  if (std::abs(d - distance_at(double(r.s), double(r.t))) > eps) return "distance is not that of the points";
  const Sampled sampled = sampled_segment_distance(a0, a1, b0, b1, 120);
  if (d > sampled.distance + eps) return "farther than a sampled pair";
  if (d < sampled.distance - sampled.resolution - eps) return "nearer than the segments allow";
  const double step = 1e-3;
  for (double ds : {-step, 0.0, step})
    for (double dt : {-step, 0.0, step}) {
      const double s = double(r.s) + ds, t = double(r.t) + dt;
      if (s < 0 || s > 1 || t < 0 || t > 1) continue;
      if (distance_at(s, t) * distance_at(s, t) < d * d - eps) return "a nearby pair of points is closer";
    }
  return "";
}

}  // namespace

TEMPLATE_TEST_CASE("closest point on a triangle: sampled minimum, local optimality, random cases",
                   "[collision][geometry]", float, double) {
  using S = TestType;
  std::mt19937 rng(2002);
  std::uniform_real_distribution<double> unit(0, 1);
  int inside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3<S> a = random_point<S>(rng, 1), b = random_point<S>(rng, 1), c = random_point<S>(rng, 1);
    Vec3<S> p = random_point<S>(rng, 2);
    if (trial % 3 == 0) {  // over the face, close to it: the projection case
      const double wb = unit(rng) * 0.9, wc = unit(rng) * (0.9 - wb);
      const V3 normal = (wide(b) - wide(a)).cross(wide(c) - wide(a)).normalized();
      p = ((1 - wb - wc) * wide(a) + wb * wide(b) + wc * wide(c) + 0.05 * (unit(rng) - 0.5) * normal)
              .template cast<S>();
    }
    const std::string problem = check_triangle_closest(p, a, b, c);
    INFO("trial " << trial << ": " << problem);
    REQUIRE(problem.empty());
    inside += closest_point_on_triangle(p, a, b, c).weights.minCoeff() > 0;
  }
  CHECK(inside > 60);  // the face case was exercised, not only edges and corners
}

TEMPLATE_TEST_CASE("closest point on a triangle: known answers in every region", "[collision][geometry]", float,
                   double) {
  using S = TestType;
  const Vec3<S> a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case {
    Vec3<S> p;
    double distance_squared;
    V3 weights;
  };
  const std::vector<Case> cases = {
      {Vec3<S>(S(0.25), S(0.25), 2), 4, V3(0.5, 0.25, 0.25)},  // face
      {Vec3<S>(S(0.25), S(0.25), -2), 4, V3(0.5, 0.25, 0.25)},
      {Vec3<S>(2, -1, 0), 2, V3(0, 1, 0)},               // corner b
      {Vec3<S>(-1, -1, 1), 3, V3(1, 0, 0)},              // corner a
      {Vec3<S>(-1, 3, 0), 5, V3(0, 0, 1)},               // corner c
      {Vec3<S>(S(0.5), -1, 1), 2, V3(0.5, 0.5, 0)},      // edge ab
      {Vec3<S>(1, 1, 0), 0.5, V3(0, 0.5, 0.5)},          // edge bc
      {Vec3<S>(-2, S(0.25), 0), 4, V3(0.75, 0, 0.25)},   // edge ca
      {Vec3<S>(S(0.5), S(0.5), 0), 0, V3(0, 0.5, 0.5)},  // on the edge
      {Vec3<S>(0, 0, 0), 0, V3(1, 0, 0)},                // on the corner
  };
  for (const Case& k : cases) {
    const PointTriangleClosest<S> r = closest_point_on_triangle(k.p, a, b, c);
    INFO("p = " << k.p.transpose() << ": distance^2 " << r.distance_squared << ", weights " << r.weights.transpose());
    CHECK(std::abs(double(r.distance_squared) - k.distance_squared) < 1e-6);
    CHECK((r.weights.template cast<double>() - k.weights).cwiseAbs().maxCoeff() < 1e-6);
  }
}

TEMPLATE_TEST_CASE("closest point on a degenerate triangle: collinear, coincident corners, a sliver",
                   "[collision][geometry]", float, double) {
  using S = TestType;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3<S> a = random_point<S>(rng, 1), b = random_point<S>(rng, 1);
    Vec3<S> p = random_point<S>(rng, 1.5);
    std::array<Vec3<S>, 3> corners;
    switch (trial % 7) {
      case 0:
        corners = {a, b, Vec3<S>((wide(a) + unit(rng) * (wide(b) - wide(a))).template cast<S>())};
        break;  // c between
      case 1:
        corners = {a, b, Vec3<S>((wide(a) + (1 + unit(rng)) * (wide(b) - wide(a))).template cast<S>())};
        break;  // beyond
      case 2: corners = {a, a, b}; break;
      case 3: corners = {a, a, a}; break;
      default: {  // a sliver: c a hair (1e-7, 1e-11, 1e-14) off the line ab, p over its inside
        const V3 off = (wide(b) - wide(a)).cross(V3(0.3, -0.7, 0.2)).normalized();
        const V3 normal = (wide(b) - wide(a)).cross(off).normalized();
        const double hair = trial % 7 == 4 ? 1e-7 : trial % 7 == 5 ? 1e-11 : 1e-14;
        corners = {a, b, Vec3<S>((wide(a) + 0.6 * (wide(b) - wide(a)) + hair * off).template cast<S>())};
        p = (wide(a) + 0.55 * (wide(b) - wide(a)) + 0.4 * hair * off + 0.1 * unit(rng) * normal).template cast<S>();
      }
    }
    for (int rotation = 0; rotation < 3; ++rotation) {  // the degenerate corner in every place
      const Vec3<S>&ca = corners[std::size_t(rotation)], &cb = corners[std::size_t((rotation + 1) % 3)],
            &cc = corners[std::size_t((rotation + 2) % 3)];
      const std::string problem = check_triangle_closest(p, ca, cb, cc);
      INFO("trial " << trial << " rotation " << rotation << ": " << problem);
      REQUIRE(problem.empty());
    }
  }
  // A sliver 9e-12 thick (found by a randomized search) over which the face's weights, computed
  // through its near-zero normal, pass as inside yet are 8e-8 off: the edges give the distance.
  if constexpr (std::is_same_v<S, double>) {
    const V3 a(-0.69679231022957466, -0.75189731197742393, 0.97536100918080271);
    const V3 b(-0.83156214845524601, 0.094713587156381784, 0.29565338436949751);
    const V3 c(-0.76288854821337637, -0.33668723083938512, 0.64200662131628872);
    const V3 p(-0.77716048591952658, -0.24725176990835065, 0.57017068124735037);
    const auto to_edge = [&](const V3& from, const V3& to) {
      const double s = std::clamp((p - from).dot(to - from) / (to - from).squaredNorm(), 0.0, 1.0);
      return (from + s * (to - from) - p).norm();
    };
    const double edges = std::min({to_edge(a, b), to_edge(b, c), to_edge(c, a)});
    CHECK(std::abs(std::sqrt(closest_point_on_triangle(p, a, b, c).distance_squared) - edges) < 1e-10);
  }
  // A point on the line of a collinear triangle, beyond its end: the far corner is the answer.
  const PointTriangleClosest<S> r =
      closest_point_on_triangle(Vec3<S>(5, 0, 0), Vec3<S>(0, 0, 0), Vec3<S>(2, 0, 0), Vec3<S>(1, 0, 0));
  CHECK(std::abs(double(r.distance_squared) - 9) < 1e-6);
  CHECK(std::abs(double(r.weights[1]) - 1) < 1e-6);
}

TEMPLATE_TEST_CASE("closest points of two segments: sampled minimum, local optimality, random cases",
                   "[collision][geometry]", float, double) {
  using S = TestType;
  std::mt19937 rng(2021);
  int interior = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3<S> p0 = random_point<S>(rng, 1), p1 = random_point<S>(rng, 1);
    Vec3<S> q0 = random_point<S>(rng, 1), q1 = random_point<S>(rng, 1);
    if (trial % 4 == 0) {  // nearly touching in the middle: the interior case
      const V3 mid = 0.5 * (wide(p0) + wide(p1)) + 0.02 * random_point<double>(rng, 1);
      const V3 dir = random_point<double>(rng, 1);
      q0 = (mid - 0.5 * dir).template cast<S>();
      q1 = (mid + 0.5 * dir).template cast<S>();
    }
    const std::string problem = check_segment_closest(p0, p1, q0, q1);
    INFO("trial " << trial << ": " << problem);
    REQUIRE(problem.empty());
    const SegmentClosest<S> r = closest_points_on_segments(p0, p1, q0, q1);
    interior += r.s > 0 && r.s < 1 && r.t > 0 && r.t < 1;
  }
  CHECK(interior > 50);
}

TEMPLATE_TEST_CASE("closest points of two segments: parallel, collinear, zero length, small angles",
                   "[collision][geometry]", float, double) {
  using S = TestType;
  const auto segments = [](double d, const V3& p0, const V3& p1, const V3& q0, const V3& q1) {
    const SegmentClosest<S> r = closest_points_on_segments<S>(p0.cast<S>(), p1.cast<S>(), q0.cast<S>(), q1.cast<S>());
    INFO("expected " << d << ", got " << std::sqrt(double(r.distance_squared)) << " at s " << r.s << ", t " << r.t);
    CHECK(std::abs(std::sqrt(double(r.distance_squared)) - d) < 1e-6);
    CHECK(check_segment_closest<S>(p0.cast<S>(), p1.cast<S>(), q0.cast<S>(), q1.cast<S>()) == "");
  };
  segments(0.5, V3(0, 0, 0), V3(1, 0, 0), V3(0.2, 0.5, 0), V3(3, 0.5, 0));                 // parallel, overlapping
  segments(0.5, V3(0, 0, 0), V3(1, 0, 0), V3(3, 0.5, 0), V3(0.2, 0.5, 0));                 // antiparallel
  segments(std::hypot(1.0, 0.5), V3(0, 0, 0), V3(1, 0, 0), V3(2, 0.5, 0), V3(3, 0.5, 0));  // parallel, apart
  segments(0, V3(0, 0, 0), V3(1, 0, 0), V3(0.5, 0, 0), V3(2, 0, 0));                       // collinear, overlapping
  segments(1, V3(0, 0, 0), V3(1, 0, 0), V3(2, 0, 0), V3(3, 0, 0));                         // collinear, apart
  segments(0, V3(0, 0, 0), V3(1, 0, 0), V3(1, 0, 0), V3(1, 1, 1));                         // sharing an end
  segments(1, V3(0, 0, 0), V3(0, 0, 0), V3(-1, 1, 0), V3(1, 1, 0));                        // p is a point
  segments(std::sqrt(2.0), V3(0, 0, 0), V3(1, 0, 0), V3(2, 1, 0), V3(2, 1, 0));            // q is a point
  segments(std::sqrt(3.0), V3(0, 0, 0), V3(0, 0, 0), V3(1, 1, 1), V3(1, 1, 1));            // two points
  segments(1, V3(-1, 0, 0), V3(1, 0, 0), V3(0, -1, 1), V3(0, 1, 1));                       // skew, perpendicular
  for (double angle : {1e-2, 1e-4, 1e-6}) {  // crossing at a small angle, in the plane and 0.01 above it
    segments(0, V3(-1, 0, 0), V3(1, 0, 0), V3(-1, -angle, 0), V3(1, angle, 0));
    segments(0.01, V3(-1, 0, 0), V3(1, 0, 0), V3(-1, -angle, 0.01), V3(1, angle, 0.01));
  }
}

// ---------------------------------------------------------------------------------------------
// Mesh checks

namespace {

template <class S>
bool intersect(const std::array<V3, 3>& a, const std::array<V3, 3>& b) {
  return test::triangles_intersect<S>(a[0].cast<S>(), a[1].cast<S>(), a[2].cast<S>(), b[0].cast<S>(), b[1].cast<S>(),
                                      b[2].cast<S>());
}

/// Both orders of the pair and every rotation of the corners give the same answer.
template <class S>
bool intersect_every_way(const std::array<V3, 3>& a, const std::array<V3, 3>& b) {
  const bool first = intersect<S>(a, b);
  for (int r = 0; r < 3; ++r) {
    const std::array<V3, 3> ra = {a[std::size_t(r)], a[std::size_t((r + 1) % 3)], a[std::size_t((r + 2) % 3)]};
    const std::array<V3, 3> rb = {b[std::size_t((r + 2) % 3)], b[std::size_t(r)], b[std::size_t((r + 1) % 3)]};
    if (intersect<S>(ra, rb) != first || intersect<S>(rb, ra) != first) throw std::runtime_error("order dependent");
  }
  return first;
}

/// A grid of n x n nodes, spacing h, folded about the column m = (n - 1) / 2: columns 0..m lie at
/// y = 0, columns m+1..n-1 come back over them at y = gap, column m+1 straight above column m.
template <class S>
Matrix3X<S> folded_grid(int n, double h, double gap) {
  Matrix3X<S> x(3, n * n);
  const int m = (n - 1) / 2;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool top = i > m;
      x.col(j * n + i) = V3((top ? 2 * m + 1 - i : i) * h, top ? gap : 0.0, j * h).template cast<S>();
    }
  return x;
}

}  // namespace

TEMPLATE_TEST_CASE("triangles_intersect: known pairs, touching counts", "[collision][mesh_checks]", float, double) {
  using S = TestType;
  const std::array<V3, 3> base = {V3(0, 0, 0), V3(4, 0, 0), V3(0, 4, 0)};
  // Piercing: b's edge goes through a's interior.
  CHECK(intersect_every_way<S>(base, {V3(1, 1, -1), V3(1, 1, 1), V3(3, 3, 1)}));
  // Linked like two rings: each pierces the other's interior once.
  CHECK(intersect_every_way<S>(base, {V3(1, 1, -1), V3(1, 1, 2), V3(-3, 1, 0.5)}));
  // Parallel planes, overlapping in projection.
  CHECK_FALSE(intersect_every_way<S>(base, {V3(1, 1, 0.25), V3(3, 0.5, 0.25), V3(0.5, 3, 0.25)}));
  // A vertex exactly on a's face, the rest above: touching.
  CHECK(intersect_every_way<S>(base, {V3(1, 1, 0), V3(2, 1, 1), V3(1, 2, 1)}));
  // A vertex exactly on a's edge, and on a's corner.
  CHECK(intersect_every_way<S>(base, {V3(2, 0, 0), V3(2, -1, 1), V3(3, -1, 1)}));
  CHECK(intersect_every_way<S>(base, {V3(4, 0, 0), V3(5, 1, 1), V3(5, -1, 1)}));
  // A vertex in a's plane but outside a, the rest above: apart.
  CHECK_FALSE(intersect_every_way<S>(base, {V3(3, 3, 0), V3(4, 4, 1), V3(3, 4, 1)}));
  // A vertex a hair above a's face: apart (the hair is far above the rounding bound).
  CHECK_FALSE(intersect_every_way<S>(base, {V3(1, 1, 1.0 / 1024), V3(2, 1, 1), V3(1, 2, 1)}));
  // Edges crossing (b's edge runs across a's edge, touching it), the rest apart.
  CHECK(intersect_every_way<S>(base, {V3(2, -1, 0), V3(2, 1, 0), V3(2, 0, 3)}));
  CHECK(intersect_every_way<S>(base, {V3(2, -1, 1), V3(2, 1, -1), V3(2, -2, 3)}));
  // Coplanar: overlapping, containing, touching at a corner, along an edge, apart.
  CHECK(intersect_every_way<S>(base, {V3(1, 1, 0), V3(5, 1, 0), V3(1, 5, 0)}));
  CHECK(intersect_every_way<S>(base, {V3(0.5, 0.5, 0), V3(1, 0.5, 0), V3(0.5, 1, 0)}));
  CHECK(intersect_every_way<S>(base, {V3(4, 0, 0), V3(5, 0, 0), V3(5, 1, 0)}));
  CHECK(intersect_every_way<S>(base, {V3(1, 0, 0), V3(3, 0, 0), V3(2, -1, 0)}));
  CHECK_FALSE(intersect_every_way<S>(base, {V3(3, 3, 0), V3(5, 3, 0), V3(3, 5, 0)}));
  CHECK_FALSE(intersect_every_way<S>(base, {V3(0, -1, 0), V3(4, -1, 0), V3(2, -3, 0)}));
  CHECK_FALSE(intersect_every_way<S>(base, {V3(5, 0, 0), V3(6, 0, 0), V3(5.5, -1, 0)}));  // edges on one line
  // Coplanar in a tilted plane whose coordinates are not exact: still no false intersection far apart.
  const Mat3<double> tilt = Eigen::AngleAxis<double>(0.7, V3(1, 2, 3).normalized()).toRotationMatrix();
  const std::array<V3, 3> tilted_a = {tilt * base[0], tilt * base[1], tilt * base[2]};
  CHECK_FALSE(intersect_every_way<S>(tilted_a, {tilt * V3(3, 3, 0), tilt * V3(5, 3, 0), tilt * V3(3, 5, 0)}));
  CHECK(intersect_every_way<S>(tilted_a, {tilt * V3(1, 1, 0), tilt * V3(5, 1, 0), tilt * V3(1, 5, 0)}));
  // Degenerate: a zero-area triangle (a segment) through a's interior, and beside it.
  CHECK(intersect_every_way<S>(base, {V3(1, 1, -1), V3(1, 1, 1), V3(1, 1, 0.5)}));
  CHECK_FALSE(intersect_every_way<S>(base, {V3(5, 5, -1), V3(5, 5, 1), V3(5, 5, 0.5)}));
}

TEMPLATE_TEST_CASE("triangles_intersect: constructed piercing and separated pairs", "[collision][mesh_checks]", float,
                   double) {
  using S = TestType;
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> unit(0, 1);
  int wrong = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::array<V3, 3> a = {random_point<double>(rng, 1), random_point<double>(rng, 1),
                                 random_point<double>(rng, 1)};
    if ((a[1] - a[0]).cross(a[2] - a[0]).norm() < 0.1) continue;
    // Piercing: an edge of b through a point of a's interior (a margin from a's edges and plane
    // that float rounding cannot undo).
    const double wb = 0.05 + 0.85 * unit(rng), wc = 0.05 + (0.9 - wb) * unit(rng);
    const V3 x = (1 - wb - wc) * a[0] + wb * a[1] + wc * a[2];
    const V3 dir = random_point<double>(rng, 1).normalized();
    const double before = 0.05 + unit(rng), after = 0.05 + unit(rng);
    std::array<V3, 3> b = {x - before * dir, x + after * dir, random_point<double>(rng, 1)};
    if (std::abs(dir.dot((a[1] - a[0]).cross(a[2] - a[0]).normalized())) > 0.05) wrong += !intersect<S>(a, b);
    // Touching exactly: b has a corner at a's corner.
    wrong += !intersect<S>(a, {a[1], random_point<double>(rng, 1), random_point<double>(rng, 1)});
    // Separated: b moved along a plane's normal to its far side, with a margin.
    const V3 normal = random_point<double>(rng, 1).normalized();
    const double top = std::max({normal.dot(a[0]), normal.dot(a[1]), normal.dot(a[2])});
    const double shift = top + 0.01 + unit(rng) - std::min({normal.dot(b[0]), normal.dot(b[1]), normal.dot(b[2])});
    for (V3& v : b) v += shift * normal;
    wrong += intersect<S>(a, b);
  }
  CHECK(wrong == 0);
}

TEMPLATE_TEST_CASE("mesh checks on a grid folded over itself: no intersection, the gap; pushed through: found",
                   "[collision][mesh_checks]", float, double) {
  using S = TestType;
  const int n = 33;  // 2048 triangles
  const double h = 0.1, gap = 0.025;
  const Grid<S> grid(n, n, S(h), S(1));
  const std::vector<std::array<int, 3>> triangles = grid.triangles();
  REQUIRE(triangles.size() == 2048);
  Matrix3X<S> x = folded_grid<S>(n, h, gap);
  CHECK_FALSE(test::first_intersection(x, triangles).found);
  // The closest pairs: a layer over the other at the gap, and inside the fold's vertical strip (gap
  // by h cells) a corner against the opposite cell diagonal, at gap h / sqrt(gap^2 + h^2).
  const double expected = gap * h / std::hypot(gap, h);
  CHECK(std::abs(double(test::min_nonadjacent_distance(x, triangles)) - expected) < 1e-6);

  // One node of the upper layer pushed through the lower one.
  const int m = (n - 1) / 2, pushed = 16 * n + (m + 5);
  x(1, pushed) = S(-gap);
  const test::MeshIntersection hit = test::first_intersection(x, triangles);
  REQUIRE(hit.found);
  REQUIRE(hit.tri_a < hit.tri_b);
  const auto has_pushed = [&](int t) {
    const auto& tri = triangles[std::size_t(t)];
    return tri[0] == pushed || tri[1] == pushed || tri[2] == pushed;
  };
  CHECK((has_pushed(hit.tri_a) || has_pushed(hit.tri_b)));
  // The reported pair does intersect, and an earlier pair does not (first in list order).
  const auto& ta = triangles[std::size_t(hit.tri_a)];
  const auto& tb = triangles[std::size_t(hit.tri_b)];
  CHECK(
      test::triangles_intersect<S>(x.col(ta[0]), x.col(ta[1]), x.col(ta[2]), x.col(tb[0]), x.col(tb[1]), x.col(tb[2])));
  CHECK(test::min_nonadjacent_distance(x, triangles) < S(1e-6));
}

TEMPLATE_TEST_CASE("min_nonadjacent_distance: adjacency is skipped; vertex-face and edge-edge pairs count",
                   "[collision][mesh_checks]", float, double) {
  using S = TestType;
  // A bowtie: two coplanar triangles sharing node 0. Pairs through node 0 (distance 0) are skipped;
  // the nearest others are an outer edge and an edge of the other triangle at node 0, sqrt(1/2).
  Matrix3X<S> bowtie(3, 5);
  bowtie << 0, 1, 0, -1, 0,  //
      0, 0, 1, 0, -1,        //
      0, 0, 0, 0, 0;
  CHECK(std::abs(double(test::min_nonadjacent_distance<S>(bowtie, {{0, 1, 2}, {0, 3, 4}})) - std::sqrt(0.5)) < 1e-6);
  // Without the outer edges' neighbours (a single triangle each, no node shared) the corners are 1 apart.
  Matrix3X<S> apart(3, 6);
  apart << S(0.5), 1, S(0.5), S(-0.5), -1, S(-0.5),  //
      0, 0, 1, 0, 0, -1,                             //
      0, 0, 0, 0, 0, 0;
  CHECK(std::abs(double(test::min_nonadjacent_distance<S>(apart, {{0, 1, 2}, {3, 4, 5}})) - 1) < 1e-6);
  CHECK_FALSE(test::first_intersection<S>(bowtie, {{0, 1, 2}, {0, 3, 4}}).found);  // they share a node
  // Crossed edges: two triangles in perpendicular planes whose edges pass 0.3 apart; every vertex is
  // farther from the other triangle.
  Matrix3X<S> crossed(3, 6);
  crossed << -1, 1, 0, 0, 0, 0,  //
      0, 0, 0, -1, 1, 0,         //
      0, 0, -2, S(0.3), S(0.3), 2;
  CHECK(std::abs(double(test::min_nonadjacent_distance<S>(crossed, {{0, 1, 2}, {3, 4, 5}})) - 0.3) < 1e-6);
  // A vertex 0.2 over a face, everything else farther.
  Matrix3X<S> over(3, 6);
  over << 0, 4, 0, 1, 3, 1,  //
      0, 0, 4, 1, 1, 3,      //
      0, 0, 0, S(0.2), 3, 3;
  CHECK(std::abs(double(test::min_nonadjacent_distance<S>(over, {{0, 1, 2}, {3, 4, 5}})) - 0.2) < 1e-6);
}

TEMPLATE_TEST_CASE("mesh checks: the sweeps along x find what testing all pairs one by one finds",
                   "[collision][mesh_checks]", float, double) {
  using S = TestType;
  // A folded grid whose nodes are moved at random: by a little (no intersection, the layers 0 to
  // 2 gaps apart) and by more than the gap (layers through each other), for several seeds.
  const int n = 17;
  const double h = 0.1, gap = 0.025;
  const std::vector<std::array<int, 3>> triangles = Grid<S>(n, n, S(h), S(1)).triangles();
  int intersecting = 0;
  for (const double amplitude : {0.4 * gap, 3.0 * gap})
    for (unsigned seed = 1; seed <= 4; ++seed) {
      INFO("amplitude " << amplitude << ", seed " << seed);
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(-amplitude, amplitude);
      Matrix3X<S> x = folded_grid<S>(n, h, gap);
      for (Index i = 0; i < x.size(); ++i) x.data()[i] += S(u(rng));
      const test::MeshIntersection swept = test::first_intersection(x, triangles);
      const test::MeshIntersection all = test::first_intersection_all_pairs(x, triangles);
      CHECK(swept.found == all.found);
      CHECK(swept.tri_a == all.tri_a);
      CHECK(swept.tri_b == all.tri_b);
      intersecting += all.found;
      CHECK(test::min_nonadjacent_distance(x, triangles) == test::min_nonadjacent_distance_all_pairs(x, triangles));
    }
  CHECK(intersecting >= 3);  // both answers occur
  CHECK(intersecting <= 5);
}
