// The signed distance of a triangle mesh (collision/mesh_distance.hpp) and the mesh collider built
// on it (contact/collider.hpp): a box mesh against the analytic box to rounding, a sphere mesh
// between its inscribed and circumscribed balls, the tree's closest point against every triangle,
// the sign at the edges and corners of a non-convex mesh and across the hole of an open one
// against a brute-force winding number, the swept test against the analytic box's on a thin plate,
// moved vertices against a mesh built on them, and bad meshes named.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "drape/collision/mesh_distance.hpp"
#include "drape/contact/collider.hpp"
#include "drape/core/solid_generators.hpp"

using namespace drape;

namespace {

constexpr double pi = 3.14159265358979323846;

template <class S>
Mat3<S> tilt() {
  return Eigen::AngleAxis<S>(S(0.7), Vec3<S>(1, 2, 3).normalized()).toRotationMatrix();
}

/// The winding number of a closed or open mesh about p, summed in long double (the reference).
template <class S>
long double reference_winding(const ClothMesh<S>& mesh, const Vec3<S>& p) {
  using W = long double;
  using V = Eigen::Matrix<W, 3, 1>;
  W sum = 0;
  for (const auto& t : mesh.all_triangles()) {
    const V a = (mesh.positions.col(t[0]) - p).template cast<W>(), b = (mesh.positions.col(t[1]) - p).template cast<W>(),
            c = (mesh.positions.col(t[2]) - p).template cast<W>();
    const W la = a.norm(), lb = b.norm(), lc = c.norm();
    sum += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return sum / (4 * W(pi));
}

/// The icosphere with its vertices pushed in or out at random: star-shaped, with sharp convex and
/// concave edges and corners, and fans of very different angles about a vertex.
ClothMesh<double> spiky_ball(unsigned seed) {
  ClothMesh<double> mesh = icosphere_mesh<double>(1.0, 2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> radius(0.2, 1.8);
  for (Index i = 0; i < mesh.positions.cols(); ++i) mesh.positions.col(i) *= radius(rng);
  return mesh;
}

}  // namespace

TEMPLATE_TEST_CASE("mesh distance: a box meshed by its faces has the analytic box's distance and normal",
                   "[mesh_collider]", float, double) {
  using S = TestType;
  const Vec3<S> half(S(0.6), S(0.4), S(0.8));
  const Vec3<S> centre(S(0.1), S(0.2), S(-0.1));
  const Collider<S> box = Collider<S>::box(centre, half, tilt<S>());
  const S eps = std::is_same_v<S, float> ? S(2e-6) : S(1e-13);
  for (const int divisions : {1, 3}) {
    INFO("divisions " << divisions);
    const Collider<S> mesh = Collider<S>::mesh(box_mesh<S>(half, divisions), centre, tilt<S>());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.6, 1.6);
    for (int k = 0; k < 3000; ++k) {
      const Vec3<S> p = centre + tilt<S>() * Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
      const ColliderContact<S> a = box.query(p, S(0)), b = mesh.query(p, S(0));
      INFO("p " << p.transpose());
      REQUIRE(std::abs(a.distance - b.distance) <= eps * 4);
      // Inside, two faces at nearly the same distance make the normal ambiguous: skip those.
      const Vec3<S> local = (tilt<S>().transpose() * (p - centre)).cwiseAbs();
      Vec3<S> gaps = (half - local).cwiseAbs();
      std::sort(gaps.data(), gaps.data() + 3);
      if (a.distance < 0 && gaps[1] - gaps[0] < S(1e-3)) continue;
      REQUIRE(a.normal.dot(b.normal) >= 1 - 100 * eps);
    }
  }
}

TEMPLATE_TEST_CASE("mesh distance: a sphere mesh lies between its inscribed and circumscribed balls",
                   "[mesh_collider]", float, double) {
  using S = TestType;
  const S radius = S(0.5);
  const ClothMesh<S> sphere = icosphere_mesh<S>(radius, 3);
  const MeshDistance<S> distance(sphere.triangles, sphere.positions);
  // The inscribed radius: the nearest face plane to the centre.
  S inner = radius;
  for (const auto& t : sphere.triangles) {
    const Vec3<S> a = sphere.positions.col(t[0]), b = sphere.positions.col(t[1]), c = sphere.positions.col(t[2]);
    inner = std::min(inner, S(std::abs((b - a).cross(c - a).normalized().dot(a))));
  }
  REQUIRE(inner > S(0.99) * radius);  // level 3: within 1% of the sphere
  const S eps = std::is_same_v<S, float> ? S(1e-6) : S(1e-14);
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> r(0.0, 2.0);
  for (int k = 0; k < 3000; ++k) {
    const Vec3<S> direction = Vec3<double>(g(rng), g(rng), g(rng)).normalized().template cast<S>();
    const S length = S(r(rng)) * radius;
    const typename MeshDistance<S>::Closest c = distance.closest(Vec3<S>(length * direction));
    // Ball(inner) inside the mesh's solid inside Ball(radius): the signed distances are ordered.
    REQUIRE(c.distance >= length - radius - eps);
    REQUIRE(c.distance <= length - inner + eps);
    // Away from the surface (and from the centre, where no direction is radial) the normal is
    // nearly radial.
    if (length > S(1.2) * radius || (length < S(0.8) * radius && length > S(0.5) * radius))
      REQUIRE(c.normal.dot(direction) >= S(0.99));
  }
}

TEST_CASE("mesh distance: the tree's closest point is the nearest of all triangles", "[mesh_collider]") {
  const ClothMesh<double> mesh = torus_mesh<double>(0.6, 0.2, 40, 16);
  const MeshDistance<double> distance(mesh.triangles, mesh.positions);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const Vec3<double> p(u(rng), 0.4 * u(rng), u(rng));
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh.triangles)
      nearest = std::min(nearest, closest_point_on_triangle<double>(p, mesh.positions.col(t[0]),
                                                                     mesh.positions.col(t[1]), mesh.positions.col(t[2]))
                                      .distance_squared);
    REQUIRE(std::abs(distance.closest(p).distance) == Approx(std::sqrt(nearest)).epsilon(1e-14).margin(1e-15));
  }
}

TEST_CASE("mesh distance: inside and outside are right at the edges and corners of a non-convex mesh",
          "[mesh_collider][long]") {
  for (const unsigned seed : {1u, 2u, 3u}) {
    const ClothMesh<double> mesh = spiky_ball(seed);
    const MeshDistance<double> distance(mesh.triangles, mesh.positions);
    REQUIRE(distance.closed());
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    const auto check = [&](const Vec3<double>& p) {
      INFO("seed " << seed << ", p " << p.transpose());
      REQUIRE((distance.closest(p).distance < 0) == (reference_winding(mesh, p) > 0.5L));
    };
    // Points near every corner (closest to it, or to an edge or face about it) and every edge.
    // Pseudo-normals without the angle weights get a few of the corners wrong.
    for (Index v = 0; v < mesh.positions.cols(); ++v)
      for (int j = 0; j < 20; ++j) check(mesh.positions.col(v) + 0.01 * Vec3<double>(g(rng), g(rng), g(rng)));
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        const Vec3<double> middle = 0.5 * (mesh.positions.col(t[std::size_t(k)]) + mesh.positions.col(t[std::size_t((k + 1) % 3)]));
        check(middle + 0.05 * Vec3<double>(g(rng), g(rng), g(rng)));
      }
  }
}

TEST_CASE("mesh distance: across the hole of an open mesh inside and outside are right", "[mesh_collider]") {
  // A sphere with its top cap (y > 0.8 r) cut away: the hole's rim is the border.
  ClothMesh<double> sphere = icosphere_mesh<double>(1.0, 3);
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : sphere.triangles)
    if (std::max({sphere.positions(1, t[0]), sphere.positions(1, t[1]), sphere.positions(1, t[2])}) <= 0.8)
      kept.push_back(t);
  sphere.triangles = kept;
  const MeshDistance<double> distance(sphere.triangles, sphere.positions);
  REQUIRE_FALSE(distance.closed());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> height(0.55, 1.0), turn(0, 2 * pi), out(1.05, 1.3), in(0.7, 0.95);
  int near_rim = 0;
  for (int k = 0; k < 2000; ++k) {
    // Directions in the cone over the hole and its rim, points well inside or outside the sphere;
    // inside only below the rim's plane (above it, in the missing cap, nothing encloses them).
    const double y = height(rng), s = std::sqrt(1 - y * y), phi = turn(rng);
    const Vec3<double> direction(s * std::cos(phi), y, s * std::sin(phi));
    const bool inside = k % 2 == 0;
    const Vec3<double> p = (inside ? in(rng) : out(rng)) * direction;
    if (inside && p.y() > 0.75) continue;
    const typename MeshDistance<double>::Closest c = distance.closest(p);
    near_rim += c.weights.minCoeff() == 0 ? 1 : 0;
    INFO("p " << p.transpose() << ", winding " << double(reference_winding(sphere, p)));
    REQUIRE((c.distance < 0) == inside);
    REQUIRE(std::abs(c.distance) > 0);
  }
  CHECK(near_rim > 300);  // the border decided many of them
}

TEST_CASE("mesh distance: moved vertices answer as a mesh built on them", "[mesh_collider]") {
  const ClothMesh<double> ball = icosphere_mesh<double>(0.5, 2);
  ClothMesh<double> moved = ball;
  for (Index i = 0; i < moved.positions.cols(); ++i)
    moved.positions.col(i) += Vec3<double>(0.3 * std::sin(3.0 * double(i)), 0.2, 0.1 * std::cos(double(i)));
  MeshDistance<double> refitted(ball.triangles, ball.positions);
  refitted.set_positions(moved.positions);
  const MeshDistance<double> rebuilt(moved.triangles, moved.positions);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 1000; ++k) {
    const Vec3<double> p(u(rng), u(rng), u(rng));
    const auto a = refitted.closest(p), b = rebuilt.closest(p);
    // The same point; on a shared edge or corner perhaps from another triangle (last bits).
    REQUIRE(a.distance == Approx(b.distance).margin(1e-15));
    REQUIRE((a.normal - b.normal).norm() <= 1e-12);
  }
  REQUIRE_THROWS_WITH(refitted.set_positions(Matrix3X<double>::Zero(3, 5)), Catch::Contains("positions"));
}

TEMPLATE_TEST_CASE("mesh collider: the swept test finds a thin plate where the analytic box does",
                   "[mesh_collider][tunnelling]", float, double) {
  using S = TestType;
  // 2 mm thick, 1 m wide; paths up to 1 m long cross it from every side.
  const Vec3<S> half(S(0.5), S(0.001), S(0.5));
  const Collider<S> box = Collider<S>::box(Vec3<S>::Zero(), half, tilt<S>());
  const Collider<S> mesh = Collider<S>::mesh(box_mesh<S>(half, 2), Vec3<S>::Zero(), tilt<S>());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  const S offset = S(0.004);
  const S tolerance = std::is_same_v<S, float> ? S(2e-5) : S(1e-6);
  int hits = 0;
  for (int k = 0; k < 3000; ++k) {
    const Vec3<S> x0 = tilt<S>() * Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    const Vec3<S> x1 = tilt<S>() * Vec3<S>(S(u(rng)), S(u(rng)), S(u(rng)));
    const S a = box.first_contact(x0, S(0), x1, S(1), offset), b = mesh.first_contact(x0, S(0), x1, S(1), offset);
    INFO("x0 " << x0.transpose() << ", x1 " << x1.transpose() << ", s " << a << " " << b);
    REQUIRE((a < 0) == (b < 0));
    if (a < 0) continue;
    ++hits;
    // The mesh's first contact is on the analytic box's offset surface, and the path before it
    // stays outside (sampled 1 mm apart).
    const auto distance = [&](S s) { return box.query(Vec3<S>(x0 + s * (x1 - x0)), S(0)).distance; };
    if (a == 0) {  // starts within the offset
      REQUIRE(b == 0);
      continue;
    }
    REQUIRE(distance(b) >= offset - tolerance);
    REQUIRE(distance(b) <= offset + tolerance);
    const int samples = 1 + int((x1 - x0).norm() / S(1e-3));
    for (int j = 0; j < samples && S(j) / S(samples) < b; ++j) REQUIRE(distance(S(j) / S(samples)) >= offset - tolerance);
  }
  CHECK(hits > 1000);
}

TEMPLATE_TEST_CASE("mesh collider: spinning and moving as the analytic shapes do", "[mesh_collider]", float, double) {
  using S = TestType;
  const Vec3<S> half(S(0.3), S(0.2), S(0.4));
  const Collider<S> box = Collider<S>::box(Vec3<S>(S(0.1), 0, 0), half).moving(Vec3<S>(0, 1, 0), Vec3<S>(2, 0, 1));
  const Collider<S> mesh =
      Collider<S>::mesh(box_mesh<S>(half), Vec3<S>(S(0.1), 0, 0)).moving(Vec3<S>(0, 1, 0), Vec3<S>(2, 0, 1));
  CHECK(mesh.kind() == ShapeKind::Mesh);
  CHECK(mesh.bounding_radius() == Approx(double(half.norm())).epsilon(1e-6));
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 500; ++k) {
    const Vec3<S> p(S(u(rng)), S(u(rng)), S(u(rng)));
    const S t = S(0.3);
    const ColliderContact<S> a = box.query(p, t), b = mesh.query(p, t);
    REQUIRE(std::abs(a.distance - b.distance) <= (std::is_same_v<S, float> ? S(1e-5) : S(1e-12)));
    REQUIRE((a.velocity - b.velocity).norm() <= (std::is_same_v<S, float> ? S(1e-5) : S(1e-12)));
  }
}

TEST_CASE("mesh collider: bad meshes name the collider mesh and the element", "[mesh_collider][validation]") {
  ClothMesh<double> box = box_mesh<double>(Vec3<double>(0.5, 0.5, 0.5));
  ClothMesh<double> inward = box;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  REQUIRE_THROWS_WITH(Colliderd::mesh(inward), Catch::Contains("collider mesh") && Catch::Contains("inward"));
  ClothMesh<double> out_of_range = box;
  out_of_range.triangles[3][1] = 99;
  REQUIRE_THROWS_WITH(Colliderd::mesh(out_of_range), Catch::Contains("collider mesh.triangles[3]"));
  ClothMesh<double> not_finite = box;
  not_finite.positions(0, 2) = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(Colliderd::mesh(not_finite), Catch::Contains("collider mesh"));
  REQUIRE_THROWS_WITH(Colliderd::mesh(ClothMesh<double>{}), Catch::Contains("collider mesh"));
  REQUIRE_THROWS_WITH(Colliderd::mesh(box, Vec3<double>(0, std::nan(""), 0)), Catch::Contains("collider position"));
  // An open sheet is allowed, either way up.
  ClothMesh<double> sheet = box;
  sheet.triangles.resize(2);
  REQUIRE_NOTHROW(Colliderd::mesh(sheet));
  REQUIRE_THROWS_WITH(icosphere_mesh<double>(1.0, 9), Catch::Contains("levels"));
  REQUIRE_THROWS_WITH(torus_mesh<double>(0.5, 0.6, 10, 10), Catch::Contains("minor"));
}

TEST_CASE("solid generators: closed, outward and of the right volume", "[mesh_collider]") {
  const auto volume = [](const ClothMesh<double>& m) { return MeshDistance<double>(m.triangles, m.positions).signed_volume(); };
  const auto closed = [](const ClothMesh<double>& m) { return MeshDistance<double>(m.triangles, m.positions).closed(); };
  const ClothMesh<double> sphere = icosphere_mesh<double>(1.0, 4), box = box_mesh<double>(Vec3<double>(1, 2, 3), 4),
                          torus = torus_mesh<double>(1.0, 0.25, 64, 32);
  for (const auto* m : {&sphere, &box, &torus}) {
    REQUIRE(m->validate().empty());
    REQUIRE(closed(*m));
  }
  CHECK(sphere.triangles.size() == 20 * 256);
  CHECK(volume(sphere) == Approx(4.0 / 3.0 * pi).epsilon(0.005));
  CHECK(volume(box) == Approx(48.0).epsilon(1e-12));
  CHECK(volume(torus) == Approx(2 * pi * pi * 1.0 * 0.25 * 0.25).epsilon(0.01));
}

TEMPLATE_TEST_CASE("mesh collider: key frames of a box moving and turning answer as the analytic box moving so",
                   "[mesh_collider][animated]", float, double) {
  using S = TestType;
  // Key frames of the box's vertices every 0.1 s along the analytic box's motion (velocity and
  // spin about its centre): linear in between, so the surfaces differ by the chord of the turn.
  const Vec3<S> half(S(0.3), S(0.2), S(0.4)), velocity(S(0.5), S(1), 0), spin(0, S(0.2), 0);
  const Collider<S> box = Collider<S>::box(Vec3<S>::Zero(), half).moving(velocity, spin);
  const ClothMesh<S> mesh = box_mesh<S>(half, 2);
  std::vector<Matrix3X<S>> frames;
  std::vector<S> times;
  for (int k = 0; k <= 10; ++k) {
    const S t = S(0.1) * S(k);
    const RigidPose<S> pose = box.motion().pose(t);
    frames.push_back((pose.rotation * mesh.positions).colwise() + pose.translation);
    times.push_back(t);
  }
  const Collider<S> animated = Collider<S>::animated_mesh(mesh, frames, times);
  CHECK(animated.deforms());
  CHECK(animated.bounding_radius() >= half.norm());
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1), when(0, 1);
  // The turn between frames is 0.02 rad: the chord is within 0.5 mm of the arc at this size.
  const S close = S(5e-4);
  int near = 0;
  for (int k = 0; k < 3000; ++k) {
    const S t = S(when(rng));
    const S dx = S(u(rng)), dy = S(u(rng)), dz = S(u(rng));  // in this order on every compiler
    const Vec3<S> p = box.motion().pose(t).translation + Vec3<S>(dx, dy, dz);
    near += std::abs(box.query(p, t).distance) < S(0.02) ? 1 : 0;
    const ColliderContact<S> a = box.query(p, t), b = animated.query(p, t);
    INFO("t " << t << ", p " << p.transpose());
    REQUIRE(std::abs(a.distance - b.distance) <= close);
    // Near the surface the velocity is the frames' slope at the closest point; the box's is that
    // of its material point at p: they differ by w x (p - c), and by the turn over one frame interval.
    if (std::abs(a.distance) < S(0.02)) REQUIRE((a.velocity - b.velocity).norm() <= S(0.01));
  }
  CHECK(near > 15);  // the band within 2 cm of the surface holds about 1% of the points
  // Before the first and after the last frame the mesh holds still.
  Matrix3X<S> x;
  animated.mesh_positions(S(-1), x);
  CHECK(x == frames.front());
  animated.mesh_positions(S(5), x);
  CHECK(x == frames.back());
  CHECK(animated.query(Vec3<S>(0, 5, 0), S(3)).velocity.norm() == 0);
}

TEST_CASE("mesh collider: the swept test of a deforming mesh finds every crossing of a moving plate",
          "[mesh_collider][animated][tunnelling]") {
  // A 2 mm plate whose vertices move 0.5 m up in one step (key frames), points still or moving:
  // the first contact is where the analytic box moving the same way first comes within the offset.
  const Vec3<double> half(0.5, 0.001, 0.5);
  const ClothMesh<double> plate = box_mesh<double>(half, 2);
  Matrix3X<double> up = plate.positions;
  up.row(1).array() += 0.5;
  const Colliderd animated = Colliderd::animated_mesh(plate, {plate.positions, up}, {0.0, 1.0});
  const Colliderd box = Colliderd::box(Vec3<double>::Zero(), half).moving(Vec3<double>(0, 0.5, 0));
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-0.6, 0.6), y(-0.2, 0.8);
  const double offset = 0.004;
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3<double> x0(u(rng), y(rng), u(rng)), x1 = x0 + Vec3<double>(0.1 * u(rng), 0.3 * u(rng), 0.1 * u(rng));
    const double a = box.first_contact(x0, 0.0, x1, 1.0, offset), b = animated.first_contact(x0, 0.0, x1, 1.0, offset);
    INFO("x0 " << x0.transpose() << ", x1 " << x1.transpose() << ", s " << a << " " << b);
    REQUIRE((a < 0) == (b < 0));
    if (a < 0) continue;
    ++hits;
    // Never late, never far: at most the offset's tolerance from the analytic box's contact.
    const auto gap = [&](double s) { return box.query(Vec3<double>(x0 + s * (x1 - x0)), s).distance - offset; };
    REQUIRE(b <= a + 1e-9);
    REQUIRE(gap(b) <= offset + 1e-6);
  }
  CHECK(hits > 500);
}

TEST_CASE("mesh collider: bad key frames name the frame and the element", "[mesh_collider][animated][validation]") {
  const ClothMesh<double> box = box_mesh<double>(Vec3<double>(0.5, 0.5, 0.5));
  const Matrix3X<double> x = box.positions;
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {}, {}), Catch::Contains("collider frames"));
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {x, x}, {0.0}), Catch::Contains("collider frame times"));
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {x, x}, {1.0, 1.0}),
                      Catch::Contains("collider frame times") && Catch::Contains("increasing"));
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {x, Matrix3X<double>(x.leftCols(5))}, {0.0, 1.0}),
                      Catch::Contains("collider frames[1]") && Catch::Contains("vertices"));
  Matrix3X<double> flat = x;
  flat.row(1).setZero();
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {x, x, flat}, {0.0, 1.0, 2.0}),
                      Catch::Contains("collider frames[2].triangles"));
  Matrix3X<double> nan = x;
  nan(2, 3) = std::numeric_limits<double>::quiet_NaN();
  REQUIRE_THROWS_WITH(Colliderd::animated_mesh(box, {nan}, {0.0}), Catch::Contains("collider frames[0]"));
}
