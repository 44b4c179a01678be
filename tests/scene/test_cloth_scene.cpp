// Several cloths in one scene (scene/cloth_scene.hpp) and where each starts (core/placement.hpp):
// a scene of one cloth is that cloth stepped alone, bit for bit; two cloths stacked on a floor
// rest with the upper one pushing on the lower with its weight; two cloths dropped onto each
// other over a box never intersect (exact triangle-triangle test over the union of both meshes,
// brute force) in either integrator, and do without the scene's collisions; determinism; bad input;
// a closed seam stays closed with a cloth's or the scene's joined nodes and is pushed open without.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "collision/cloth_shapes.hpp"
#include "collision/mesh_checks.hpp"
#include "drape/core/mesh_generators.hpp"
#include "drape/core/placement.hpp"
#include "drape/fwd.hpp"
#include "drape/scene/cloth_scene.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// A free nx x nx cloth 0.1 m apart, 0.01 kg per node, light damped springs, gravity 10.
template <class S>
ClothSpec<S> light_cloth(int n, S thickness = S(0.01)) {
  ClothSpec<S> spec = test::small_spec<S>(n, S(10));
  spec.node_mass = S(0.01);
  spec.springs = {{S(1000), S(1)}, {S(500), S(0.5)}, {S(20), S(0.05)}};
  spec.pinned_nodes = std::vector<int>{};
  spec.contact_thickness = thickness;
  return spec;
}

template <class S>
ImplicitOptions options_for(IntegratorKind kind) {
  ImplicitOptions options;
  options.dt = kind == IntegratorKind::Implicit ? 1.0 / 60 : 1e-3;
  options.threads = 1;
  options.tolerance = std::is_same_v<S, float> ? 1e-5 : 1e-8;
  return options;
}

template <class S>
SelfCollisionSettings<S> collisions_on() {
  SelfCollisionSettings<S> settings;
  settings.enabled = true;
  return settings;
}

/// Every cloth's triangles and positions as one mesh, in the scene's node numbering.
template <class S>
struct UnionMesh {
  std::vector<std::array<int, 3>> triangles;
  Matrix3X<S> positions;
};

template <class S>
UnionMesh<S> union_mesh(const ClothScene<S>& scene) {
  UnionMesh<S> mesh;
  mesh.positions.resize(3, scene.node_count());
  for (int k = 0; k < scene.cloth_count(); ++k) {
    const int offset = scene.node_offset(k);
    for (std::array<int, 3> t : scene.cloth(k).grid().triangles())
      mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    mesh.positions.middleCols(offset, scene.cloth(k).node_count()) = scene.state(k).positions;
  }
  return mesh;
}

const IntegratorKind both_integrators[] = {IntegratorKind::Implicit, IntegratorKind::Symplectic};

}  // namespace

TEST_CASE("placement: the flat grid turned about x, then y, then z, and moved", "[scene][placement]") {
  ClothSpec<double> spec = light_cloth<double>(5);
  const Clothd unplaced(spec);
  CHECK(unplaced.initial_state().positions == unplaced.grid().rest_positions());  // identity: the same bits
  spec.placement.position = Vec3<double>(1, 2, 3);
  spec.placement.rotation_degrees = Vec3<double>(90, 0, 0);  // the +z rows go to -y: the cloth hangs
  const Clothd placed(spec);
  const Matrix3X<double> x = placed.initial_state().positions;
  const Grid<double>& grid = placed.grid();
  CHECK((x.col(grid.node(0, 0)) - Vec3<double>(1, 2, 3)).norm() < 1e-12);
  CHECK((x.col(grid.node(4, 0)) - Vec3<double>(1.4, 2, 3)).norm() < 1e-12);
  CHECK((x.col(grid.node(0, 4)) - Vec3<double>(1, 1.6, 3)).norm() < 1e-12);
  spec.placement.rotation_degrees = Vec3<double>(0, 90, 0);  // about y: +x goes to -z
  CHECK((Clothd(spec).initial_state().positions.col(grid.node(4, 0)) - Vec3<double>(1, 2, 2.6)).norm() < 1e-12);
  spec.placement.rotation_degrees = Vec3<double>(0, 0, 90);  // about z: +x goes to +y
  CHECK((Clothd(spec).initial_state().positions.col(grid.node(4, 0)) - Vec3<double>(1, 2.4, 3)).norm() < 1e-12);

  spec.placement.position.x() = std::nan("");
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("'placement.position'"));
  spec.placement.position.x() = 0;
  spec.placement.rotation_degrees.y() = INFINITY;
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("'placement.rotation'"));
}

TEMPLATE_TEST_CASE(
    "cloth scene: one cloth with the scene's collisions is that cloth alone with self-collision, bit "
    "for bit",
    "[scene]", float, double) {
  using S = TestType;
  for (IntegratorKind kind : both_integrators) {
    INFO(to_string(kind));
    ClothSpec<S> spec = light_cloth<S>(9);
    spec.ny = 17;
    spec.colliders.push_back(Collider<S>::plane(Vec3<S>::Zero(), Vec3<S>(0, 1, 0)).set_friction(S(0.3), S(0.3)));
    const ImplicitOptions options = options_for<S>(kind);

    ClothSpec<S> alone_spec = spec;
    alone_spec.self_collision = collisions_on<S>();
    const Cloth<S> alone(alone_spec);
    auto stepper = make_integrator(alone, kind, options);
    State<S> state = alone.initial_state();
    state.positions = test::laid_along(alone, test::folded_path(double(spec.contact_thickness), 0.9, 0.15));

    ClothScene<S> scene({spec}, kind, options, collisions_on<S>());
    scene.state(0).positions = state.positions;
    int contacts = 0;
    const int steps = kind == IntegratorKind::Implicit ? 60 : 600;
    for (int k = 0; k < steps; ++k) {
      REQUIRE(stepper->step(state).ok());
      REQUIRE(scene.step().ok());
      contacts += scene.collision_report().proximity_pairs;
    }
    CHECK(contacts > 0);  // the fold lies on itself: the handler did work
    CHECK(scene.state(0).positions == state.positions);
    CHECK(scene.state(0).velocities == state.velocities);
    CHECK(scene.state(0).time == state.time);
  }
}

TEMPLATE_TEST_CASE("cloth scene: two cloths stacked on a floor; the upper pushes on the lower with its weight",
                   "[scene][long]", float, double) {
  using S = TestType;
  for (IntegratorKind kind : both_integrators) {
    INFO(to_string(kind));
    const S h = S(0.01);
    ClothSpec<S> lower = light_cloth<S>(17, h);  // 1.6 m square, resting on the floor
    lower.colliders.push_back(Collider<S>::plane(Vec3<S>::Zero(), Vec3<S>(0, 1, 0)).set_friction(S(0.5), S(0.5)));
    lower.placement.position = Vec3<S>(0, h, 0);
    ClothSpec<S> upper = light_cloth<S>(9, h);  // 0.8 m square, turned 30 degrees, over the middle
    upper.colliders = lower.colliders;
    upper.placement.rotation_degrees = Vec3<S>(0, 30, 0);
    upper.placement.position = Vec3<S>(S(0.45), 3 * h, S(0.95));
    ClothScene<S> scene({lower, upper}, kind, options_for<S>(kind), collisions_on<S>());
    const S dt = scene.integrator(0).dt();
    const int settle = int(std::lround(0.5 / double(dt))), measure = int(std::lround(1.0 / double(dt)));
    double on_lower = 0, on_upper = 0, floor_on_upper = 0, lowest = 1e30;
    for (int k = 0; k < settle + measure; ++k) {
      REQUIRE(scene.step().ok());
      lowest = std::min(lowest, double(scene.state(0).positions.row(1).minCoeff()));
      if (k < settle) continue;
      on_lower += double(scene.contact_force_on(0).y()) / measure;
      on_upper += double(scene.contact_force_on(1).y()) / measure;
      floor_on_upper += double(scene.integrator(1).contact_report().normal_force.y()) / measure;
    }
    const double weight_upper = 81 * 0.01 * 10;
    INFO("upper on lower " << -on_lower << " N, lower on upper " << on_upper << " N, weight " << weight_upper);
    CHECK(-on_lower == Approx(weight_upper).epsilon(0.01));
    CHECK(on_upper == Approx(weight_upper).epsilon(0.01));
    CHECK(floor_on_upper == 0);  // the upper one never reaches the floor
    // The upper one's push never drives the lower one into the floor (the floor carries it).
    CHECK(lowest >= 0.9 * double(h));
    // It rests a layer distance (2h) above the lower one.
    const double top = double(scene.state(1).positions.row(1).mean());
    CHECK(top == Approx(3 * double(h)).margin(0.1 * double(h)));
  }
}

TEST_CASE("cloth scene: two cloths dropped onto each other over a box never intersect", "[scene][long]") {
  for (IntegratorKind kind : both_integrators) {
    for (bool collide : {true, false}) {
      INFO(to_string(kind) << (collide ? " with" : " without") << " the scene's collisions");
      const double h = 0.01;
      ClothSpec<double> lower = light_cloth<double>(13, h);
      lower.colliders.push_back(
          Colliderd::box(Vec3<double>(0.6, -0.25, 0.6), Vec3<double>(0.25, 0.25, 0.25)).set_friction(0.5, 0.5));
      lower.colliders.push_back(Colliderd::plane(Vec3<double>(0, -0.5, 0), Vec3<double>(0, 1, 0)).set_friction(1, 1));
      lower.placement.position = Vec3<double>(0, 0.05, 0);
      ClothSpec<double> upper = light_cloth<double>(11, h);
      upper.colliders = lower.colliders;
      upper.placement.rotation_degrees = Vec3<double>(0, 45, 0);
      upper.placement.position = Vec3<double>(0.6 - 0.5 * std::sqrt(2.0), 0.2, 0.6);  // centred over the box
      SelfCollisionSettings<double> collisions;
      collisions.enabled = collide;
      ClothScene<double> scene({lower, upper}, kind, options_for<double>(kind), collisions);
      const double dt = scene.integrator(0).dt();
      const int steps = int(std::lround(1.5 / dt)), check_every = std::max(1, int(std::lround(1.0 / 60 / dt)));
      int first_intersection = -1, contacts = 0, unresolved = 0;
      double closest = 1e30;
      for (int k = 0; k < steps; ++k) {
        REQUIRE(scene.step().ok());
        contacts += scene.collision_report().proximity_pairs;
        unresolved += scene.collision_report().unresolved;
        if ((k + 1) % check_every != 0) continue;
        const UnionMesh<double> mesh = union_mesh(scene);
        if (first_intersection < 0 && test::first_intersection(mesh.positions, mesh.triangles).found)
          first_intersection = k;
        closest = std::min(closest, test::min_nonadjacent_distance(mesh.positions, mesh.triangles));
      }
      if (collide) {
        CHECK(first_intersection == -1);
        CHECK(unresolved == 0);
        CHECK(contacts > 0);
        CHECK(closest >= 0.001 * 2 * h);
      } else {
        CHECK(first_intersection >= 0);  // the check can fail: without collisions they pass through
      }
    }
  }
}

TEST_CASE("cloth scene: the same inputs give the same bits", "[scene]") {
  auto run = [] {
    ClothSpec<double> a = light_cloth<double>(9), b = light_cloth<double>(7);
    a.colliders.push_back(Colliderd::sphere(Vec3<double>(0.4, -0.4, 0.4), 0.3));
    b.colliders = a.colliders;
    b.placement.position = Vec3<double>(0.1, 0.15, 0.1);
    ImplicitOptions options = options_for<double>(IntegratorKind::Implicit);
    options.threads = 2;
    ClothScene<double> scene({a, b}, IntegratorKind::Implicit, options, collisions_on<double>());
    for (int k = 0; k < 60; ++k) REQUIRE(scene.step().ok());
    return std::array<Matrix3X<double>, 2>{scene.state(0).positions, scene.state(1).positions};
  };
  const auto first = run(), second = run();
  CHECK(first[0] == second[0]);
  CHECK(first[1] == second[1]);
}

TEST_CASE("cloth scene: bad input names the cloth and the parameter", "[scene]") {
  const ImplicitOptions options = options_for<double>(IntegratorKind::Implicit);
  CHECK_THROWS_WITH(ClothScene<double>({}, IntegratorKind::Implicit, options, {}), Catch::Contains("'cloths'"));
  ClothSpec<double> bad = light_cloth<double>(5);
  bad.spacing = -1;
  CHECK_THROWS_WITH(ClothScene<double>({light_cloth<double>(5), bad}, IntegratorKind::Implicit, options, {}),
                    Catch::Contains("'cloths[1].spacing'"));
  SelfCollisionSettings<double> collisions = collisions_on<double>();
  collisions.friction = -1;
  CHECK_THROWS_WITH(ClothScene<double>({light_cloth<double>(5)}, IntegratorKind::Implicit, options, collisions),
                    Catch::Contains("'self friction'"));
  ClothSpec<double> thin = light_cloth<double>(5, 0.0);
  CHECK_THROWS_WITH(ClothScene<double>({thin}, IntegratorKind::Implicit, options, collisions_on<double>()),
                    Catch::Contains("'contact thickness'"));
}

TEST_CASE("cloth scene: joined nodes, a cloth's own or the scene's, keep a closed seam closed", "[scene][joined]") {
  // Two 5 x 5 panels side by side with a seam closed to 1 mm (the first's nodes at x = 0.4, the
  // second's at x = 0.401), gravity off: nothing moves unless the scene's collisions push across
  // the seam, towards 2h = 2 cm apart.
  ClothSpec<double> left = light_cloth<double>(5), right = left;
  left.gravity = right.gravity = 0;
  right.placement.position = Vec3<double>(0.401, 0, 0);
  ClothMesh<double> panels;  // both in one cloth
  const ClothMesh<double> panel = grid_mesh<double>(5, 5, 0.1);
  panels.positions.resize(3, 50);
  panels.positions << panel.positions, panel.positions.colwise() + Vec3<double>(0.401, 0, 0);
  panels.triangles = panel.triangles;
  for (std::array<int, 3> t : panel.triangles) panels.triangles.push_back({t[0] + 25, t[1] + 25, t[2] + 25});
  std::vector<std::array<int, 2>> seam;  // the same ids in the one cloth and in the scene of two
  for (int j = 0; j < 5; ++j) seam.push_back({j * 5 + 4, 25 + j * 5});
  ClothSpec<double> sewn = left;
  sewn.mesh = panels;

  const ImplicitOptions options = options_for<double>(IntegratorKind::Implicit);
  // The seam's widest gap after 0.1 s and the pairs the scene's collisions acted on.
  auto run = [&](const std::vector<ClothSpec<double>>& cloths, const SelfCollisionSettings<double>& collisions) {
    ClothScene<double> scene(cloths, IntegratorKind::Implicit, options, collisions);
    int acted = 0;
    for (int k = 0; k < 6; ++k) {
      REQUIRE(scene.step().ok());
      const SelfCollisionReport& r = scene.collision_report();
      acted += r.proximity_pairs + r.repulsions + r.impacts + r.zones;
    }
    Matrix3X<double> x(3, scene.node_count());
    for (int k = 0; k < scene.cloth_count(); ++k)
      x.middleCols(scene.node_offset(k), scene.cloth(k).node_count()) = scene.state(k).positions;
    double widest = 0;
    for (const auto& [a, b] : seam) widest = std::max(widest, (x.col(a) - x.col(b)).norm());
    return std::make_pair(widest, acted);
  };
  const double layer = 2 * left.contact_thickness;
  {
    INFO("one cloth, its own joined nodes");
    sewn.self_collision.joined_nodes = seam;
    const auto [gap, acted] = run({sewn}, collisions_on<double>());
    CHECK(std::abs(gap - 0.001) < 1e-12);
    CHECK(acted == 0);
  }
  {
    INFO("one cloth, not joined (the check can fail)");
    sewn.self_collision.joined_nodes.clear();
    const auto [gap, acted] = run({sewn}, collisions_on<double>());
    CHECK(gap > 0.5 * layer);
    CHECK(acted > 0);
  }
  {
    INFO("two cloths, the scene's joined nodes");
    SelfCollisionSettings<double> collisions = collisions_on<double>();
    collisions.joined_nodes = seam;
    const auto [gap, acted] = run({left, right}, collisions);
    CHECK(std::abs(gap - 0.001) < 1e-12);
    CHECK(acted == 0);
    collisions.joined_nodes = {{0, 1}, {3, 50}};
    CHECK_THROWS_WITH(ClothScene<double>({left, right}, IntegratorKind::Implicit, options, collisions),
                      Catch::Contains("'self joined nodes[1]'") && Catch::Contains("[0, 50)"));
  }
}
