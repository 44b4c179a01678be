// Rigid colliders (contact/collider.hpp): the analytic gradient of every shape against central
// differences inside and outside, known distances, the cylinder's distance and normal against the
// nearest of densely sampled surface points, moving and spinning colliders, the constant motion's
// pose, the swept test (thin boxes and disks, misses, starts inside, relative motion, and a sampled
// check that it never passes a contact), and parameter checks.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "drape/contact/collider.hpp"

using namespace drape;

namespace {

template <class S>
Mat3<S> tilt() {
  return Eigen::AngleAxis<S>(S(0.7), Vec3<S>(1, 2, 3).normalized()).toRotationMatrix();
}

/// One collider of every kind (two boxes and two cylinders: sharp and rounded), placed off the
/// origin and tilted, some of them moving and spinning.
template <class S>
std::vector<Collider<S>> shapes() {
  return {Collider<S>::plane(Vec3<S>(S(0.1), S(-0.2), S(0.3)), Vec3<S>(S(0.3), 1, S(-0.2))),
          Collider<S>::sphere(Vec3<S>(S(0.2), S(0.1), S(-0.3)), S(0.7)),
          Collider<S>::capsule(Vec3<S>(S(-0.5), S(0.2), S(0.1)), Vec3<S>(S(0.6), S(-0.3), S(0.4)), S(0.3))
              .moving(Vec3<S>(S(0.2), 0, S(-0.1)), Vec3<S>(S(0.5), S(-1), S(0.3))),
          Collider<S>::box(Vec3<S>(S(0.1), S(0.2), S(-0.1)), Vec3<S>(S(0.6), S(0.4), S(0.8)), tilt<S>()),
          Collider<S>::box(Vec3<S>(S(0.1), S(0.2), S(-0.1)), Vec3<S>(S(0.6), S(0.4), S(0.8)), tilt<S>(), S(0.25))
              .moving(Vec3<S>(0, S(-0.3), S(0.2)), Vec3<S>(1, S(0.2), S(-0.4))),
          Collider<S>::cylinder(Vec3<S>(S(-0.1), S(0.1), S(0.2)), S(0.7), S(0.4), tilt<S>()),
          Collider<S>::cylinder(Vec3<S>(S(0.1), S(-0.1), 0), S(0.6), S(0.5), tilt<S>(), S(0.2))
              .moving(Vec3<S>(S(0.1), S(0.2), 0), Vec3<S>(S(-0.3), S(0.8), S(0.5)))};
}

template <class S>
Vec3<S> random_point(std::mt19937& rng, double half_width) {
  std::uniform_real_distribution<double> u(-half_width, half_width);
  return Vec3<double>(u(rng), u(rng), u(rng)).cast<S>();
}

template <class S>
bool close3(const Vec3<S>& a, const Vec3<S>& b, S eps) {
  return (a - b).cwiseAbs().maxCoeff() <= eps;
}

constexpr double pi = 3.14159265358979323846;

/// Points of a cylinder's surface at most `spacing` apart along and around it, in its local frame
/// (radius r about y, half height h, rims rounded by `rounding`): a profile in (distance from the
/// axis, y) from the top cap's centre over the rims to the bottom cap's centre, turned about y.
std::vector<Vec3<double>> cylinder_surface(double r, double h, double rounding, double spacing) {
  std::vector<Eigen::Vector2d> profile;
  const auto line = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const int n = std::max(1, int(std::ceil((b - a).norm() / spacing)));
    for (int j = 0; j < n; ++j) profile.push_back(a + (b - a) * (double(j) / n));
  };
  const auto arc = [&](const Eigen::Vector2d& centre, double from, double to) {
    const int n = std::max(1, int(std::ceil(rounding * std::abs(to - from) / spacing)));
    for (int j = 0; j < n; ++j) {
      const double a = from + (to - from) * j / n;
      profile.push_back(centre + rounding * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  };
  const double inner_r = r - rounding, inner_h = h - rounding;
  line({0, h}, {inner_r, h});
  if (rounding > 0) arc({inner_r, inner_h}, pi / 2, 0);
  line({r, inner_h}, {r, -inner_h});
  if (rounding > 0) arc({inner_r, -inner_h}, 0, -pi / 2);
  line({inner_r, -h}, {0, -h});
  profile.emplace_back(0, -h);
  std::vector<Vec3<double>> points;
  for (const Eigen::Vector2d& q : profile) {
    const int around = std::max(1, int(std::ceil(2 * pi * q.x() / spacing)));
    for (int k = 0; k < around; ++k) {
      const double a = 2 * pi * k / around;
      points.emplace_back(q.x() * std::cos(a), q.y(), q.x() * std::sin(a));
    }
  }
  return points;
}

/// Whether local point p lies in the cylinder (the surface counts as inside), from its definition:
/// within the sharp cylinder and not in a rim's corner outside the rounding's circle.
bool inside_cylinder(const Vec3<double>& p, double r, double h, double rounding) {
  const double a = std::sqrt(p.x() * p.x() + p.z() * p.z()), y = std::abs(p.y());
  if (a > r || y > h) return false;
  const double u = a - (r - rounding), v = y - (h - rounding);
  return u <= 0 || v <= 0 || u * u + v * v <= rounding * rounding;
}

}  // namespace

TEST_CASE("collider normals are the central-difference gradient of the distance, inside and outside; float agrees",
          "[collider]") {
  const double h = 1e-6, t = 0.3;
  const std::vector<Collider<double>> colliders = shapes<double>();
  const std::vector<Collider<float>> single = shapes<float>();
  std::mt19937 rng(11);
  for (std::size_t i = 0; i < colliders.size(); ++i) {
    const Collider<double>& collider = colliders[i];
    INFO(to_string(collider.kind()) << ", rounding " << collider.rounding());
    int inside = 0, outside = 0, skipped = 0;
    const int points = 2000;
    for (int k = 0; k < points; ++k) {
      const Vec3<double> x = random_point<double>(rng, 1.3);
      const ColliderContact<double> c = collider.query(x, t);
      INFO("x = " << x.transpose() << ", distance " << c.distance);
      REQUIRE(std::abs(c.normal.norm() - 1) < 1e-14);
      Vec3<double> fd;
      bool across_medial_axis = false;
      for (int d = 0; d < 3; ++d) {
        Vec3<double> xp = x, xm = x;
        xp[d] += h;
        xm[d] -= h;
        const ColliderContact<double> cp = collider.query(xp, t), cm = collider.query(xm, t);
        // The interior's medial axis, where the nearest surface point jumps, is no place for differences.
        across_medial_axis |= (cp.normal - c.normal).norm() > 0.1 || (cm.normal - c.normal).norm() > 0.1;
        fd[d] = (cp.distance - cm.distance) / (2 * h);
      }
      if (across_medial_axis) {
        ++skipped;
        continue;
      }
      (c.distance < 0 ? inside : outside)++;
      REQUIRE(close3<double>(c.normal, fd, 1e-7));
      // The same collider in float: the same distance and normal to float precision.
      const ColliderContact<float> f = single[i].query(x.cast<float>(), float(t));
      CHECK(std::abs(double(f.distance) - c.distance) < 2e-6);
      CHECK(std::abs(double(f.normal.norm()) - 1) < 1e-6);
      CHECK(close3<double>(f.normal.cast<double>(), c.normal, 1e-3));
    }
    CHECK(inside >= 20);
    CHECK(outside >= 20);
    CHECK(skipped <= points / 100);
  }
}

TEMPLATE_TEST_CASE("collider distances and normals at known points", "[collider]", float, double) {
  using S = TestType;
  const S eps = 20 * std::numeric_limits<S>::epsilon();
  const auto check = [eps](const Collider<S>& collider, const Vec3<S>& x, double distance, const Vec3<S>& normal) {
    const ColliderContact<S> c = collider.query(x, 0);
    INFO(to_string(collider.kind()) << " at " << x.transpose() << ": " << c.distance << ", " << c.normal.transpose());
    CHECK(std::abs(c.distance - S(distance)) <= eps);
    CHECK(close3<S>(c.normal, normal.normalized(), eps));
  };
  const Vec3<S> c(1, 2, 3);
  const Collider<S> sphere = Collider<S>::sphere(c, S(0.5));
  check(sphere, c + Vec3<S>(0, 0, 2), 1.5, Vec3<S>(0, 0, 1));
  check(sphere, c + Vec3<S>(S(0.3), S(-0.4), 0), -0.0, Vec3<S>(S(0.3), S(-0.4), 0));
  check(sphere, c + Vec3<S>(S(-0.1), 0, 0), -0.4, Vec3<S>(-1, 0, 0));

  // The segment (1,2,3)-(1,4,3): caps beyond the ends, the side along the axis.
  const Collider<S> capsule = Collider<S>::capsule(c, c + Vec3<S>(0, 2, 0), S(0.5));
  CHECK(capsule.half_length() == S(1));
  check(capsule, c + Vec3<S>(0, 3, 0), 0.5, Vec3<S>(0, 1, 0));
  check(capsule, c + Vec3<S>(0, -1, 0), 0.5, Vec3<S>(0, -1, 0));
  check(capsule, c + Vec3<S>(0, S(-0.5), S(0.5)), std::sqrt(0.5) - 0.5, Vec3<S>(0, -1, 1));
  check(capsule, c + Vec3<S>(0, S(1.5), S(-1)), 0.5, Vec3<S>(0, 0, -1));
  check(capsule, c + Vec3<S>(S(0.2), S(0.7), 0), -0.3, Vec3<S>(1, 0, 0));

  // Box 2 x 4 x 6 at c: faces, edges and corners, then the same outer size with rounded edges.
  const Vec3<S> half(1, 2, 3);
  const Collider<S> sharp = Collider<S>::box(c, half);
  check(sharp, c + Vec3<S>(2, 0, 0), 1, Vec3<S>(1, 0, 0));
  check(sharp, c + Vec3<S>(2, -3, 0), std::sqrt(2.0), Vec3<S>(1, -1, 0));
  check(sharp, c + Vec3<S>(2, 3, -4), std::sqrt(3.0), Vec3<S>(1, 1, -1));
  check(sharp, c + Vec3<S>(S(0.9), 0, 0), -0.1, Vec3<S>(1, 0, 0));
  check(sharp, c + Vec3<S>(0, S(-1.5), 0), -0.5, Vec3<S>(0, -1, 0));
  check(sharp, c + Vec3<S>(S(0.5), S(1.2), S(2.9)), -0.1, Vec3<S>(0, 0, 1));
  const Collider<S> round = Collider<S>::box(c, half, Mat3<S>::Identity(), S(0.5));
  CHECK(round.rounding() == S(0.5));
  check(round, c + Vec3<S>(2, 0, 0), 1, Vec3<S>(1, 0, 0));
  check(round, c + Vec3<S>(2, -3, 0), 1.5 * std::sqrt(2.0) - 0.5, Vec3<S>(1, -1, 0));
  check(round, c + Vec3<S>(2, 3, -4), 1.5 * std::sqrt(3.0) - 0.5, Vec3<S>(1, 1, -1));
  check(round, c + Vec3<S>(S(0.9), 0, 0), -0.1, Vec3<S>(1, 0, 0));
  // The outer corner of the sharp box lies outside the rounded one: (sqrt 3 - 1) r.
  check(round, c + half, (std::sqrt(3.0) - 1) * 0.5, Vec3<S>(1, 1, 1));
  // A rotated box: the face normal turns with it.
  const Mat3<S> r = tilt<S>();
  const Collider<S> turned = Collider<S>::box(c, half, r, S(0.5));
  check(turned, c + r * Vec3<S>(0, 0, 4), 1, r.col(2));
  check(turned, c + r * Vec3<S>(2, -3, 0), 1.5 * std::sqrt(2.0) - 0.5, r * Vec3<S>(1, -1, 0));

  // A cylinder of radius 0.5 from y = 1 to 3 about c: caps, side, the sharp rim, inside.
  const Collider<S> can = Collider<S>::cylinder(c, S(0.5), 1);
  CHECK(can.half_height() == S(1));
  CHECK(can.radius() == S(0.5));
  check(can, c + Vec3<S>(0, 3, 0), 2, Vec3<S>(0, 1, 0));
  check(can, c + Vec3<S>(S(0.3), S(-1.5), S(-0.2)), 0.5, Vec3<S>(0, -1, 0));
  check(can, c + Vec3<S>(0, S(0.3), 2), 1.5, Vec3<S>(0, 0, 1));
  check(can, c + Vec3<S>(S(-1.5), 2, 0), std::sqrt(2.0), Vec3<S>(-1, 1, 0));
  check(can, c + Vec3<S>(S(0.4), 0, 0), -0.1, Vec3<S>(1, 0, 0));
  check(can, c + Vec3<S>(S(0.1), S(0.9), S(-0.1)), -0.1, Vec3<S>(0, 1, 0));
  check(can, c + Vec3<S>(S(0.24), S(-0.3), S(0.32)), -0.1, Vec3<S>(S(0.24), 0, S(0.32)));
  // On the axis the side is nearest in every horizontal direction: any of them is a subgradient.
  const ColliderContact<S> axis = can.query(c + Vec3<S>(0, S(0.2), 0), 0);
  CHECK(std::abs(axis.distance + S(0.5)) <= eps);
  CHECK(std::abs(axis.normal.norm() - 1) <= eps);
  CHECK(axis.normal.y() == 0);
  // Rims rounded by 0.2: the inner cylinder (0.3, 0.8) inflated by 0.2.
  const Collider<S> rounded = Collider<S>::cylinder(c, S(0.5), 1, Mat3<S>::Identity(), S(0.2));
  check(rounded, c + Vec3<S>(S(1.5), 2, 0), 1.2 * std::sqrt(2.0) - 0.2, Vec3<S>(1, 1, 0));
  check(rounded, c + Vec3<S>(0, -2, S(-1.5)), 1.2 * std::sqrt(2.0) - 0.2, Vec3<S>(0, -1, -1));
  check(rounded, c + Vec3<S>(S(0.5), 1, 0), (std::sqrt(2.0) - 1) * 0.2, Vec3<S>(1, 1, 0));  // the sharp corner
  check(rounded, c + Vec3<S>(S(0.1), S(1.5), S(0.1)), 0.5, Vec3<S>(0, 1, 0));
  check(rounded, c + Vec3<S>(0, 0, S(-0.9)), 0.4, Vec3<S>(0, 0, -1));
  // Turned: the axis and the side's normals turn with it.
  const Mat3<S> turn = tilt<S>();
  const Collider<S> tilted = Collider<S>::cylinder(c, S(0.5), 1, turn, S(0.2));
  check(tilted, c + turn * Vec3<S>(0, 0, 2), 1.5, turn.col(2));
  check(tilted, c + turn * Vec3<S>(0, -3, 0), 2, -turn.col(1));
  check(tilted, c + turn * Vec3<S>(S(1.5), 2, 0), 1.2 * std::sqrt(2.0) - 0.2, turn * Vec3<S>(1, 1, 0));
  // Rounded by its radius it is a capsule along y; by its radius and half height, a sphere.
  const Collider<S> pill = Collider<S>::cylinder(c, S(0.5), 1, Mat3<S>::Identity(), S(0.5));
  const Collider<S> capsule_y = Collider<S>::capsule(c - Vec3<S>(0, S(0.5), 0), c + Vec3<S>(0, S(0.5), 0), S(0.5));
  const Collider<S> ball = Collider<S>::cylinder(c, S(0.5), S(0.5), Mat3<S>::Identity(), S(0.5));
  std::mt19937 rng(23);
  for (int k = 0; k < 200; ++k) {
    const Vec3<S> x = c + random_point<S>(rng, 1.5);
    check(pill, x, double(capsule_y.query(x, 0).distance), capsule_y.query(x, 0).normal);
    check(ball, x, double(sphere.query(x, 0).distance), sphere.query(x, 0).normal);
  }

  // A plane through c tilted by its normal (not unit on input).
  const Vec3<S> n(1, 1, 0);
  const Collider<S> plane = Collider<S>::plane(c, n);
  check(plane, c + Vec3<S>(1, 0, 5), std::sqrt(0.5), n);
  check(plane, c + Vec3<S>(-2, 0, -1), -std::sqrt(2.0), n);
  check(plane, c + Vec3<S>(1, -1, 7), 0, n);
  // An upside-down plane (normal -y, the rotation from +y is a half turn).
  check(Collider<S>::plane(c, Vec3<S>(0, -3, 0)), c + Vec3<S>(4, -1, 2), 1, Vec3<S>(0, -1, 0));
}

TEST_CASE("cylinder distance and normal: the nearest of densely sampled surface points, near rims and caps too",
          "[collider][cylinder]") {
  // The distance is never more than the distance to any surface point and at most the samples'
  // spacing less than the nearest sample's; its sign is the inside test's; the surface point it
  // names (x - d n) is on the sampled surface; the bounding radius holds every sample.
  struct Case {
    const char* name;
    double radius, half_height, rounding;
    Mat3<double> rotation;
  };
  const Case cases[] = {{"sharp", 0.6, 0.4, 0, Mat3<double>::Identity()},
                        {"rounded, tilted", 0.6, 0.4, 0.15, tilt<double>()},
                        {"rims a half torus", 0.6, 0.25, 0.25, tilt<double>()},
                        {"a capsule", 0.3, 0.6, 0.3, Mat3<double>::Identity()}};
  const double spacing = 0.005;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  for (const Case& c : cases) {
    INFO(c.name);
    const double r = c.radius, h = c.half_height, rho = c.rounding;
    const Collider<double> cylinder = Collider<double>::cylinder(Vec3<double>(0.3, -0.2, 0.1), r, h, c.rotation, rho);
    CHECK(cylinder.kind() == ShapeKind::Cylinder);
    CHECK(cylinder.radius() == r);
    CHECK(cylinder.half_height() == h);
    CHECK(cylinder.rounding() == rho);
    const RigidPose<double> pose = cylinder.motion().pose(0);
    const std::vector<Vec3<double>> surface = cylinder_surface(r, h, rho, spacing);
    double farthest = 0;
    for (const Vec3<double>& q : surface) farthest = std::max(farthest, q.norm());
    CHECK(farthest <= cylinder.bounding_radius() + 1e-12);
    CHECK(farthest >= cylinder.bounding_radius() - spacing);
    const auto nearest = [&](const Vec3<double>& p) {
      double best = INFINITY;
      for (const Vec3<double>& q : surface) best = std::min(best, (p - q).squaredNorm());
      return std::sqrt(best);
    };
    // Local query points: anywhere around the shape, then near a rim, on the caps and on the side.
    std::vector<Vec3<double>> points;
    for (int k = 0; k < 100; ++k)
      points.emplace_back((2 * u(rng) - 1) * 1.4 * r, (2 * u(rng) - 1) * (1.4 * h + 0.1), (2 * u(rng) - 1) * 1.4 * r);
    const auto around = [&](double axial, double y) {
      const double a = 2 * pi * u(rng);
      return Vec3<double>(axial * std::cos(a), y, axial * std::sin(a));
    };
    const double side = u(rng) < 0.5 ? -1 : 1;
    for (int k = 0; k < 60; ++k) {
      // A point of a rim's arc, moved along its normal from 0.6 rho inside to 0.1 outside, or,
      // for a sharp rim, anywhere within 0.05 of the edge.
      const double a = 0.5 * pi * u(rng), offset = -0.6 * rho + (0.6 * rho + 0.1) * u(rng);
      const double reach = rho + offset;
      Vec3<double> p = around(r - rho + reach * std::cos(a), side * (h - rho + reach * std::sin(a)));
      if (rho == 0) p = around(r + 0.05 * (2 * u(rng) - 1), side * (h + 0.05 * (2 * u(rng) - 1)));
      points.push_back(p);
    }
    for (int k = 0; k < 60; ++k)
      points.push_back(around((r - rho) * u(rng), (k % 2 ? 1 : -1) * (h + 0.1 * u(rng) - 0.05)));
    for (int k = 0; k < 30; ++k) points.push_back(around(r + 0.1 * u(rng) - 0.05, (h - rho) * (2 * u(rng) - 1)));
    int inside = 0;
    for (const Vec3<double>& p : points) {
      const ColliderContact<double> q = cylinder.query(pose.to_world(p), 0);
      const double brute = nearest(p);
      INFO("local p = " << p.transpose() << ", distance " << q.distance << ", nearest sample " << brute);
      REQUIRE(std::abs(q.normal.norm() - 1) < 1e-14);
      REQUIRE(std::abs(q.distance) <= brute + 1e-12);
      REQUIRE(brute <= std::abs(q.distance) + spacing);
      if (std::abs(q.distance) > 1e-9) REQUIRE((q.distance < 0) == inside_cylinder(p, r, h, rho));
      inside += q.distance < 0;
      const Vec3<double> foot = p - q.distance * (pose.rotation.transpose() * q.normal);
      REQUIRE(nearest(foot) <= spacing);
    }
    CHECK(inside >= 40);
    CHECK(inside <= int(points.size()) - 40);
  }
}

TEST_CASE("rigid motion: constant pose against a hand-computed rotation, frame maps and point velocity",
          "[collider][motion]") {
  // R0: a quarter turn about x; w: 2 rad/s about z, so at t = 0.25 a further 0.5 rad about z.
  Mat3<double> r0;
  r0 << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Vec3<double> p0(1, 2, 3), v(0.4, -0.2, 1), w(0, 0, 2);
  const RigidMotion<double> motion = RigidMotion<double>::constant(p0, r0, v, w);
  const double t = 0.25, c = std::cos(0.5), s = std::sin(0.5);
  Mat3<double> rz;
  rz << c, -s, 0, s, c, 0, 0, 0, 1;
  Mat3<double> expected;  // rz * r0, multiplied out by hand
  expected << c, 0, s, s, 0, -c, 0, 1, 0;
  CHECK((rz * r0 - expected).cwiseAbs().maxCoeff() < 1e-15);
  const RigidPose<double> pose = motion.pose(t);
  CHECK((pose.rotation - expected).cwiseAbs().maxCoeff() < 1e-14);
  CHECK((pose.translation - Vec3<double>(1.1, 1.95, 3.25)).cwiseAbs().maxCoeff() < 1e-14);
  CHECK(pose.velocity == v);
  CHECK(pose.angular_velocity == w);
  const Vec3<double> local(0.3, -0.7, 1.1);
  const Vec3<double> x = pose.to_world(local);
  CHECK((x - (expected * local + pose.translation)).norm() < 1e-14);
  CHECK((pose.to_local(x) - local).norm() < 1e-14);
  CHECK((pose.point_velocity(x) - (v + w.cross(x - pose.translation))).norm() < 1e-14);
  // The velocity is the time derivative of the material point's path.
  const double dt = 1e-6;
  const Vec3<double> path_rate = (motion.pose(t + dt).to_world(local) - motion.pose(t - dt).to_world(local)) / (2 * dt);
  CHECK((pose.point_velocity(x) - path_rate).norm() < 1e-8);
  CHECK(motion.pose(0).rotation == r0);
  CHECK_FALSE(motion.is_static());
  CHECK(RigidMotion<double>().is_static());
  CHECK(RigidMotion<double>::fixed(p0, r0).is_static());
  CHECK(RigidMotion<double>::fixed(p0, r0).pose(7).translation == p0);
  CHECK_FALSE(RigidMotion<double>::callback([](double) { return RigidPose<double>{}; }).is_static());
}

TEMPLATE_TEST_CASE("moving and spinning colliders: distance from the moved shape, surface velocity",
                   "[collider][motion]", float, double) {
  using S = TestType;
  const S eps = 50 * std::numeric_limits<S>::epsilon();
  const Vec3<S> c(1, 2, 3), v(S(0.5), -1, S(2)), w(S(0.3), S(-2), S(1.5)), x(S(1.7), S(1.1), S(4.2));
  const S t = S(0.4);
  // A sliding sphere: the distance at t is the static distance from the shifted centre.
  const Collider<S> sliding = Collider<S>::sphere(c, S(0.5)).moving(v);
  const ColliderContact<S> at_t = sliding.query(x, t), shifted = Collider<S>::sphere(c + t * v, S(0.5)).query(x, 0);
  CHECK(std::abs(at_t.distance - shifted.distance) <= eps);
  CHECK(close3<S>(at_t.normal, shifted.normal, eps));
  CHECK(close3<S>(at_t.velocity, v, eps));
  // A spinning sphere stays put; its surface moves at w x (x - c).
  const Collider<S> spinning = Collider<S>::sphere(c, S(0.5)).moving(Vec3<S>::Zero(), w);
  const ColliderContact<S> spun = spinning.query(x, t);
  CHECK(std::abs(spun.distance - Collider<S>::sphere(c, S(0.5)).query(x, 0).distance) <= eps);
  CHECK(close3<S>(spun.velocity, w.cross(x - c), eps));
  // A box sliding and spinning about its own centre equals the static box at the pose of time t.
  const Mat3<S> r0 = tilt<S>();
  const Vec3<S> half(S(0.6), S(0.4), S(0.8));
  const Collider<S> tumbling = Collider<S>::box(c, half, r0, S(0.1)).moving(v, w);
  const Mat3<S> rt = Eigen::AngleAxis<S>(t * w.norm(), w.normalized()).toRotationMatrix() * r0;
  const Collider<S> frozen = Collider<S>::box(c + t * v, half, rt, S(0.1));
  std::mt19937 rng(3);
  for (int k = 0; k < 50; ++k) {
    const Vec3<S> y = c + random_point<S>(rng, 1.5);
    const ColliderContact<S> a = tumbling.query(y, t), b = frozen.query(y, 0);
    CHECK(std::abs(a.distance - b.distance) <= eps);
    CHECK(close3<S>(a.normal, b.normal, 10 * eps));
    CHECK(close3<S>(a.velocity, v + w.cross(y - (c + t * v)), eps));
  }
  // So does a tilted cylinder with rounded rims.
  const Collider<S> rolling = Collider<S>::cylinder(c, S(0.5), S(0.3), r0, S(0.1)).moving(v, w);
  const Collider<S> still = Collider<S>::cylinder(c + t * v, S(0.5), S(0.3), rt, S(0.1));
  for (int k = 0; k < 50; ++k) {
    const Vec3<S> y = c + random_point<S>(rng, 1.5);
    const ColliderContact<S> a = rolling.query(y, t), b = still.query(y, 0);
    CHECK(std::abs(a.distance - b.distance) <= eps);
    CHECK(close3<S>(a.normal, b.normal, 10 * eps));
    CHECK(close3<S>(a.velocity, v + w.cross(y - (c + t * v)), eps));
  }
  // A callback motion is used as given (here: the same sliding sphere).
  Collider<S> driven = Collider<S>::sphere(Vec3<S>::Zero(), S(0.5));
  driven.set_motion(RigidMotion<S>::callback([&](S time) {
    RigidPose<S> p;
    p.translation = c + time * v;
    p.velocity = v;
    return p;
  }));
  CHECK_FALSE(driven.motion().is_static());
  CHECK(std::abs(driven.query(x, t).distance - at_t.distance) <= eps);
  CHECK(close3<S>(driven.query(x, t).velocity, v, eps));
}

TEMPLATE_TEST_CASE("swept test: thin boxes, misses, starts inside, moving spheres, planes", "[collider][swept]", float,
                   double) {
  using S = TestType;
  const S accuracy = S(1e-6);
  // A 1 mm thick wall at x = 0.5 and a 1 m path straight through it, in one step.
  const Collider<S> wall = Collider<S>::box(Vec3<S>(S(0.5), 0, 0), Vec3<S>(S(0.0005), S(0.2), S(0.2)));
  const Vec3<S> from(0, S(0.05), S(0.03)), to(1, S(0.05), S(0.03));
  CHECK(std::abs(wall.first_contact(from, 0, to, 1, 0) - S(0.4995)) <= accuracy);
  CHECK(std::abs(wall.first_contact(from, 0, to, 1, S(0.002)) - S(0.4975)) <= accuracy);
  CHECK(std::abs(wall.first_contact(to, 0, from, 1, 0) - S(0.4995)) <= accuracy);
  // Obliquely: from (0, 0, 0) to (1, 0.3, -0.1) the wall's face x = 0.4995 is reached at s = 0.4995.
  CHECK(std::abs(wall.first_contact(Vec3<S>::Zero(), 0, Vec3<S>(1, S(0.3), S(-0.1)), 1, 0) - S(0.4995)) <= accuracy);
  // Through a rounded, tilted thin plate: the crossing is found (s strictly inside the path).
  const Collider<S> plate =
      Collider<S>::box(Vec3<S>(S(0.5), 0, 0), Vec3<S>(S(0.0005), S(0.2), S(0.2)), tilt<S>(), S(0.0004));
  const S s_plate = plate.first_contact(from, 0, to, 1, 0);
  CHECK(s_plate > S(0.4));
  CHECK(s_plate < S(0.6));
  CHECK(plate.query(from + s_plate * (to - from), 0).distance <= S(2e-6));
  // A 1 mm thick disk of radius 0.2 at x = 0.5, its axis along x, crossed on the same path; a path
  // 0.25 from its axis passes by, and one at 0.1999 grazes its rim.
  const Mat3<S> axis_x = Eigen::AngleAxis<S>(S(-pi / 2), Vec3<S>::UnitZ()).toRotationMatrix();
  const Collider<S> coin = Collider<S>::cylinder(Vec3<S>(S(0.5), 0, 0), S(0.2), S(0.0005), axis_x);
  CHECK(std::abs(coin.first_contact(from, 0, to, 1, 0) - S(0.4995)) <= accuracy);
  CHECK(std::abs(coin.first_contact(to, 0, from, 1, S(0.002)) - S(0.4975)) <= accuracy);
  CHECK(coin.first_contact(Vec3<S>(0, S(0.25), 0), 0, Vec3<S>(1, S(0.25), 0), 1, 0) < 0);
  CHECK(coin.first_contact(Vec3<S>(0, 0, S(0.1999)), 0, Vec3<S>(1, 0, S(0.1999)), 1, 0) >= 0);
  CHECK(coin.first_contact(Vec3<S>(0, 0, S(0.2001)), 0, Vec3<S>(1, 0, S(0.2001)), 1, 0) < 0);
  // Onto a round table's top (radius 0.5, top at y = 0) from above, and along its axis from below.
  const Collider<S> table = Collider<S>::cylinder(Vec3<S>(0, S(-0.1), 0), S(0.5), S(0.1), Mat3<S>::Identity(), S(0.05));
  CHECK(std::abs(table.first_contact(Vec3<S>(S(0.2), 1, 0), 0, Vec3<S>(S(0.2), -1, 0), 1, S(0.01)) - S(0.495)) <=
        accuracy);
  CHECK(std::abs(table.first_contact(Vec3<S>(0, -1, 0), 0, Vec3<S>(0, 1, 0), 1, 0) - S(0.4)) <= accuracy);
  // Passing above the wall, or stopping short of it: negative.
  CHECK(wall.first_contact(Vec3<S>(0, S(0.3), 0), 0, Vec3<S>(1, S(0.3), 0), 1, 0) < 0);
  CHECK(wall.first_contact(Vec3<S>(0, S(0.3), 0), 0, Vec3<S>(1, S(0.3), 0), 1, S(0.099)) < 0);
  CHECK(wall.first_contact(Vec3<S>(0, S(0.3), 0), 0, Vec3<S>(1, S(0.3), 0), 1, S(0.101)) >= 0);
  CHECK(wall.first_contact(from, 0, Vec3<S>(S(0.49), S(0.05), S(0.03)), 1, 0) < 0);
  CHECK(wall.first_contact(from, 0, from, 1, 0) < 0);
  // Starting inside, or within the offset: 0.
  CHECK(wall.first_contact(Vec3<S>(S(0.5), 0, 0), 0, to, 1, 0) == 0);
  CHECK(wall.first_contact(Vec3<S>(S(0.498), 0, 0), 0, from, 1, S(0.002)) == 0);
  // A small sphere sweeping across a point that does not move: relative motion finds it.
  const Collider<S> ball = Collider<S>::sphere(Vec3<S>(S(-0.5), 0, 0), S(0.01)).moving(Vec3<S>(1, 0, 0));
  const Vec3<S> still(0, S(0.003), 0);
  const S expected_s = S(0.5) - std::sqrt(S(0.01) * S(0.01) - S(0.003) * S(0.003));
  CHECK(std::abs(ball.first_contact(still, 0, still, 1, 0) - expected_s) <= accuracy);
  CHECK(ball.first_contact(Vec3<S>(0, S(0.02), 0), 0, Vec3<S>(0, S(0.02), 0), 1, 0) < 0);
  CHECK(ball.first_contact(still, 0, still, S(0.4), 0) < 0);  // the ball has not arrived yet at t = 0.4
  // A capsule end cap and a tilted plane (solved exactly).
  const Collider<S> capsule = Collider<S>::capsule(Vec3<S>(0, 0, 0), Vec3<S>(0, 1, 0), S(0.1));
  CHECK(std::abs(capsule.first_contact(Vec3<S>(0, 2, 0), 0, Vec3<S>(0, 0, 0), 1, 0) - S(0.45)) <= accuracy);
  const Collider<S> plane = Collider<S>::plane(Vec3<S>(0, 1, 0), Vec3<S>(0, 1, 1));
  // d(s) = (y + z - 1) / sqrt 2 along (0, 3, 0) -> (0, -1, 0): y(s) = 3 - 4 s, contact at offset 0.1
  // when 2 - 4 s = 0.1 sqrt 2.
  const S plane_s = (2 - S(0.1) * std::sqrt(S(2))) / 4;
  CHECK(std::abs(plane.first_contact(Vec3<S>(0, 3, 0), 0, Vec3<S>(0, -1, 0), 1, S(0.1)) - plane_s) <= accuracy);
  CHECK(plane.first_contact(Vec3<S>(0, 3, 0), 0, Vec3<S>(0, 2, 0), 1, S(0.1)) < 0);
  CHECK(plane.first_contact(Vec3<S>(0, 1, 0), 0, Vec3<S>(0, 3, 0), 1, S(0.1)) == 0);
}

TEST_CASE("swept test on random paths: never past the first contact, never a missed one", "[collider][swept]") {
  // Dense sampling of each path is the reference: every sample before the returned s is farther than
  // the offset, the point at s is at the offset, and a path reported as a miss has no close sample.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Collider<double>> colliders = shapes<double>();
  colliders.push_back(Collider<double>::box(Vec3<double>(0, 0, 0), Vec3<double>(0.0005, 0.6, 0.6), tilt<double>()));
  colliders.push_back(Collider<double>::sphere(Vec3<double>(0.1, 0, 0), 0.02).moving(Vec3<double>(-0.3, 0.2, 0)));
  const int samples = 5000;
  for (const Collider<double>& collider : colliders) {
    int hits = 0, misses = 0;
    for (int k = 0; k < 300; ++k) {
      const double t0 = u(rng), t1 = t0 + u(rng), offset = 0.05 * u(rng);
      const RigidPose<double> frame = collider.motion().pose(t0), end = collider.motion().pose(t1);
      // Every other path is aimed at the shape's centre (mid-way between its poses at t0 and t1).
      const Vec3<double> x0 = random_point<double>(rng, 1.6);
      const Vec3<double> x1 =
          k % 2 ? random_point<double>(rng, 1.6)
                : Vec3<double>(frame.translation + end.translation - x0 + 2 * random_point<double>(rng, 0.06));
      const double s = collider.first_contact(x0, t0, x1, t1, offset);
      // The local path, placed back in the world at t0 to read the distance.
      const Vec3<double> p0 = frame.to_local(x0), p1 = end.to_local(x1);
      const auto gap = [&](double r) {
        return collider.query(frame.to_world(p0 + r * (p1 - p0)), t0).distance - offset;
      };
      INFO(to_string(collider.kind()) << " path " << k << ", s = " << s);
      double first_close = -1;
      for (int j = 0; j <= samples && first_close < 0; ++j)
        if (gap(double(j) / samples) <= 0) first_close = double(j) / samples;
      if (s < 0) {
        ++misses;
        CHECK(first_close < 0);
        continue;
      }
      ++hits;
      CHECK(s <= 1);
      CHECK(gap(s) <= 2e-6 * (1 + offset));
      if (first_close >= 0) CHECK(s <= first_close);
      // Finer than the samples: nothing before s comes within the offset.
      bool clear_before = true;
      for (int j = 0; j < 1000 && s > 0; ++j) clear_before &= gap(s * j / 1000) > 0;
      CHECK(clear_before);
    }
    INFO(to_string(collider.kind()));
    CHECK(hits >= 10);
    CHECK(misses >= 10);
  }
}

TEST_CASE("collider parameters are checked, each error names its parameter", "[collider][validation]") {
  const Vec3<double> o(0, 0, 0), nan_point(0, std::nan(""), 0), inf = Vec3<double>::Constant(INFINITY);
  CHECK_THROWS_AS(Collider<double>::sphere(o, 0), InvalidParameter);
  CHECK_THROWS_WITH(Collider<double>::sphere(o, 0), Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::sphere(o, -1), Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::sphere(o, INFINITY), Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::capsule(o, Vec3<double>(1, 0, 0), std::nan("")),
                    Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::sphere(nan_point, 1), Catch::Contains("'collider position'"));
  CHECK_THROWS_WITH(Collider<double>::plane(inf, Vec3<double>(0, 1, 0)), Catch::Contains("'collider position'"));
  CHECK_THROWS_WITH(Collider<double>::capsule(o, nan_point, 1), Catch::Contains("'collider position'"));
  CHECK_THROWS_WITH(Collider<double>::box(inf, Vec3<double>(1, 1, 1)), Catch::Contains("'collider position'"));
  CHECK_THROWS_WITH(Collider<double>::plane(o, o), Catch::Contains("'collider normal'"));
  CHECK_THROWS_WITH(Collider<double>::plane(o, nan_point), Catch::Contains("'collider normal'"));
  CHECK_THROWS_WITH(Collider<double>::capsule(Vec3<double>(1, 2, 3), Vec3<double>(1, 2, 3), 1),
                    Catch::Contains("'capsule axis'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 0, 1)), Catch::Contains("'collider half extents'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 1, -2)), Catch::Contains("'collider half extents'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, nan_point), Catch::Contains("'collider half extents'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 0.5, 2), Mat3<double>::Identity(), 0.6),
                    Catch::Contains("'collider rounding'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 0.5, 2), Mat3<double>::Identity(), -0.1),
                    Catch::Contains("'collider rounding'"));
  CHECK_NOTHROW(Collider<double>::box(o, Vec3<double>(1, 0.5, 2), Mat3<double>::Identity(), 0.5));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 0, 1), Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, std::nan(""), 1), Catch::Contains("'collider radius'"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 1, -1), Catch::Contains("'collider half height'"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 1, INFINITY), Catch::Contains("'collider half height'"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(nan_point, 1, 1), Catch::Contains("'collider position'"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 1, 0.5, Mat3<double>::Identity(), 0.6),
                    Catch::Contains("'collider rounding'") && Catch::Contains("[0, 0.5]"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 0.4, 0.5, Mat3<double>::Identity(), 0.41),
                    Catch::Contains("'collider rounding'") && Catch::Contains("[0, 0.4"));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 1, 0.5, Mat3<double>::Identity(), -0.1),
                    Catch::Contains("'collider rounding'"));
  CHECK_NOTHROW(Collider<double>::cylinder(o, 0.4, 0.5, Mat3<double>::Identity(), 0.4));
  CHECK_THROWS_WITH(Collider<double>::cylinder(o, 1, 1, 2 * Mat3<double>::Identity()),
                    Catch::Contains("'collider rotation'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 1, 1), 2 * Mat3<double>::Identity()),
                    Catch::Contains("'collider rotation'"));
  CHECK_THROWS_WITH(Collider<double>::box(o, Vec3<double>(1, 1, 1), -Mat3<double>::Identity()),
                    Catch::Contains("'collider rotation'"));
  Collider<double> ball = Collider<double>::sphere(o, 1);
  CHECK_THROWS_WITH(ball.set_friction(-0.1, 0.2), Catch::Contains("'static friction'"));
  CHECK_THROWS_WITH(ball.set_friction(0.3, std::nan("")), Catch::Contains("'kinetic friction'"));
  CHECK_THROWS_WITH(ball.moving(nan_point), Catch::Contains("'collider velocity'"));
  CHECK_THROWS_WITH(ball.moving(o, inf), Catch::Contains("'collider angular velocity'"));
  CHECK_THROWS_WITH(ball.set_motion(RigidMotion<double>::callback(nullptr)), Catch::Contains("'collider motion'"));
  // Kinetic friction above static is allowed; defaults are frictionless.
  CHECK(ball.static_friction() == 0);
  CHECK(ball.kinetic_friction() == 0);
  ball.set_friction(0.2, 0.5);
  CHECK(ball.static_friction() == 0.2);
  CHECK(ball.kinetic_friction() == 0.5);
  CHECK(ball.kind() == ShapeKind::Sphere);
  CHECK(ball.radius() == 1);
  CHECK(to_string(ShapeKind::Capsule) == std::string("capsule"));
  CHECK(parse<ShapeKind>("box") == ShapeKind::Box);
  CHECK(joined_names<ShapeKind>() == "plane, sphere, capsule, box, cylinder, mesh");
  CHECK(parse<ShapeKind>("cylinder") == ShapeKind::Cylinder);
  CHECK_THROWS_WITH(parse<ShapeKind>("cone"), Catch::Contains("'collider shape'"));
}
