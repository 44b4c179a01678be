// Self-collision (contact/self_collision.hpp) in scenes where the cloth folds onto itself, for
// every integrator: an exact triangle-triangle test over all triangle pairs that share no node
// (brute force, tests/collision/mesh_checks.hpp) finds no intersection at any step, and pairs of
// primitives that share no node keep a stated fraction of the layer distance; the same scenes
// without self-collision do pass through themselves (so the checks can fail); the fail-safe alone
// keeps the cloth apart; friction between layers; determinism; bad input.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>

#include "collision/cloth_shapes.hpp"
#include "collision/mesh_checks.hpp"
#include "drape/fwd.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "model/mesh_helpers.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// A free nx x ny cloth 0.1 m apart with light, damped springs, gravity 10, self-collision on.
template <class S>
ClothSpec<S> folding_cloth(int nx, int ny) {
  ClothSpec<S> spec = test::small_spec<S>(nx, S(10));
  spec.ny = ny;
  spec.node_mass = S(0.01);
  spec.springs = {{S(1000), S(1)}, {S(500), S(0.5)}, {S(20), S(0.05)}};
  spec.pinned_nodes = std::vector<int>{};
  spec.contact_thickness = S(0.01);
  spec.self_collision.enabled = true;
  return spec;
}

template <class S>
std::unique_ptr<Integrator<S>> integrator(const Cloth<S>& cloth, IntegratorKind kind) {
  ImplicitOptions options;
  options.dt = kind == IntegratorKind::Implicit ? 1.0 / 60 : 1e-3;
  options.threads = 1;
  options.tolerance = std::is_same_v<S, float> ? 1e-5 : 1e-8;
  return make_integrator(cloth, kind, options);
}

/// What a run saw: the first step with an intersection (-1: none), the smallest distance between
/// primitives that share no node over all steps, steps that needed the fail-safe.
struct RunCheck {
  int first_intersecting_step = -1;
  double closest = 1e30;
  int failsafe_steps = 0;
  int unresolved = 0;
};

template <class S>
RunCheck run_checked(Integrator<S>& integrator, State<S>& state, double seconds) {
  const std::vector<std::array<int, 3>>& triangles = integrator.cloth().triangles();
  RunCheck out;
  const int steps = int(std::lround(seconds / double(integrator.dt())));
  for (int k = 0; k < steps; ++k) {
    const StepStatus status = integrator.step(state);
    INFO("step " << k << ": " << to_string(status.error));
    REQUIRE(status.ok());
    const SelfCollisionReport& report = integrator.self_collision_report();
    out.failsafe_steps += report.failsafe() ? 1 : 0;
    out.unresolved += report.unresolved;
    if (out.first_intersecting_step < 0 && test::first_intersection(state.positions, triangles).found)
      out.first_intersecting_step = k;
    out.closest = std::min(out.closest, double(test::min_nonadjacent_distance(state.positions, triangles)));
  }
  return out;
}

const IntegratorKind all_integrators[] = {IntegratorKind::Implicit, IntegratorKind::Symplectic, IntegratorKind::Rk2};

/// A flat triangle (nodes 0-2) in the x-z plane and a node (3) of a far triangle 8 mm above it
/// (layer distance 10 mm), moving down 6 mm and along x by `slide` over one step of 0.01 s. The
/// handler's step with `hold(i)` as the colliders' hold; returns the end positions and velocities.
std::pair<Matrix3X<double>, Matrix3X<double>> layer_on_held_triangle(
    const SelfCollisionSettings<double>& settings, double slide, const std::function<ColliderHold<double>(int)>& hold,
    SelfCollisionReport* report = nullptr) {
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  Matrix3X<double> x(3, 6);
  x << 0, 0.1, 0, 0.02, 0.5, 0.5,  //
      0, 0, 0, 0.008, 0.5, 0.6,    //
      0, 0, 0.1, 0.02, 0.5, 0.6;
  const VectorX<double> masses = VectorX<double>::Constant(6, 0.01);
  SelfCollisionHandler<double> handler(settings, 0.005, triangles, masses, x);
  const double dt = 0.01;
  Matrix3X<double> v = Matrix3X<double>::Zero(3, 6);
  v(1, 3) = -0.6;  // 6 mm down over the step: ends 2 mm above the triangle
  v(0, 3) = slide;
  Matrix3X<double> x_new = x + dt * v;
  handler.respond(x, dt, x_new, v, std::vector<std::uint8_t>(6, 0), hold);
  if (report != nullptr) *report = handler.report();
  return {x_new, v};
}

}  // namespace

TEMPLATE_TEST_CASE("self-collision: a cloth folded over itself falls onto its lower half and rests there",
                   "[self-collision][long]", float, double) {
  using S = TestType;
  for (IntegratorKind kind : all_integrators) {
    INFO(to_string(kind));
    ClothSpec<S> spec = folding_cloth<S>(9, 17);
    spec.colliders.push_back(Collider<S>::plane(Vec3<S>::Zero(), Vec3<S>(0, 1, 0)).set_friction(S(0.3), S(0.3)));
    const Cloth<S> cloth(spec);
    auto stepper = integrator(cloth, kind);
    State<S> state = cloth.initial_state();
    const double h = double(spec.contact_thickness);
    state.positions = test::laid_along(cloth, test::folded_path(h, 0.9, 0.15));
    const RunCheck check = run_checked(*stepper, state, 1.5);
    CHECK(check.first_intersecting_step == -1);
    CHECK(check.unresolved == 0);
    CHECK(check.closest >= 0.01 * 2 * h);
    // The upper layer (the last rows) lies on the lower one, a layer distance above it.
    const Grid<S>& grid = cloth.grid();
    double top = 0;
    for (int i = 0; i < grid.nx(); ++i) top += double(state.positions(1, grid.node(i, grid.ny() - 1)));
    top /= grid.nx();
    CHECK(top == Approx(3 * h).margin(0.5 * h));
  }
}

TEST_CASE("self-collision: without it the same fold passes through itself (the check can fail)", "[self-collision]") {
  ClothSpec<double> spec = folding_cloth<double>(9, 17);
  spec.self_collision.enabled = false;
  spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)));
  const Clothd cloth(spec);
  auto stepper = integrator(cloth, IntegratorKind::Implicit);
  State<double> state = cloth.initial_state();
  state.positions = test::laid_along(cloth, test::folded_path(spec.contact_thickness, 0.9, 0.15));
  const RunCheck check = run_checked(*stepper, state, 1.5);
  CHECK(check.first_intersecting_step >= 0);
}

TEST_CASE("self-collision: a hanging cloth let fall onto a floor piles up in folds without passing through itself",
          "[self-collision][long]") {
  for (IntegratorKind kind : all_integrators) {
    INFO(to_string(kind));
    ClothSpec<double> spec = folding_cloth<double>(11, 21);
    spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)).set_friction(0.5, 0.5));
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    State<double> state = cloth.initial_state();
    // Upright, its lower edge 5 cm above the floor, waved a little so that it buckles into folds.
    state.positions = test::laid_along(cloth, [](double s) -> Eigen::Vector2d {
      return {0.03 * std::sin(7.0 * s), 0.05 + s};
    });
    const RunCheck check = run_checked(*stepper, state, 2.0);
    CHECK(check.first_intersecting_step == -1);
    CHECK(check.unresolved == 0);
    CHECK(check.closest >= 0.01 * 2 * spec.contact_thickness);
    // It piled up: everything lies within a few layers of the floor.
    CHECK(state.positions.row(1).maxCoeff() < 0.5);
  }
}

TEST_CASE("self-collision: impact zones alone keep a triangle from passing through another, momentum kept",
          "[self-collision][failsafe]") {
  // Two triangles 0.1 m apart; in one step the upper one would pass 0.2 m through the lower one.
  // With no impulse rounds only the fail-safe acts: one zone moving rigidly, with the pair's
  // momentum (equal masses: both move by the mean displacement).
  SelfCollisionSettings<double> settings;
  settings.enabled = true;
  settings.impulse_rounds = 0;
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  Matrix3X<double> x(3, 6);
  x << 0, 1, 0, 0.2, 1.2, 0.2,  //
      0, 0, 0, 0.1, 0.1, 0.1,   //
      0, 0, 1, 0.2, 0.2, 1.2;
  const VectorX<double> masses = VectorX<double>::Constant(6, 0.01);
  SelfCollisionHandler<double> handler(settings, 0.005, triangles, masses, x);
  const double dt = 0.01;
  Matrix3X<double> v = Matrix3X<double>::Zero(3, 6);
  v.rightCols(3).row(1).setConstant(-30.0);  // 0.3 m down over the step
  Matrix3X<double> x_new = x + dt * v;
  REQUIRE(x_new.rightCols(3).row(1).maxCoeff() < 0);  // without a response it ends below: passed through
  const Vec3<double> momentum = v * masses;
  handler.respond(x, dt, x_new, v, std::vector<std::uint8_t>(6, 0), [](int) { return ColliderHold<double>{}; });
  CHECK(handler.report().zones == 1);
  CHECK(handler.report().zone_nodes == 6);
  CHECK(handler.report().unresolved == 0);
  CHECK_FALSE(test::first_intersection(x_new, triangles).found);
  // Still on its side of the lower triangle's plane (the zone turned: its pair's angular momentum).
  const Vec3<double> a = x_new.col(0), normal = (x_new.col(1) - a).cross(x_new.col(2) - a);
  for (int i = 3; i < 6; ++i) CHECK(normal.dot(x_new.col(i) - a) * normal.y() > 0);
  CHECK((v * masses - momentum).norm() < 1e-12);
  CHECK((x_new * masses - x * masses).y() / masses.sum() == Approx(-0.15));  // the centre of mass moved as before
}

TEST_CASE("self-collision: a layer pressing a collider-held node into its collider does not slide it",
          "[self-collision][held]") {
  // A flat triangle held by a collider whose normal leans 30 degrees from the triangle's (a
  // cloth on a rounded edge); a node 8 mm above it (layer distance 10 mm) moving down. The collider
  // carries the push: the held nodes stay where the step put them (a push slid along the
  // collider's surface crept the lower of two stacked cloths off the box in the implicit step),
  // and the upper node alone stops.
  SelfCollisionSettings<double> settings;
  settings.enabled = true;
  const ColliderHold<double> leaning{Vec3<double>(0.5, std::sqrt(0.75), 0.0), 0.5};  // rougher than the layers
  SelfCollisionReport report;
  const auto [x_new, v] = layer_on_held_triangle(
      settings, 0.0, [&](int i) { return i < 3 ? leaning : ColliderHold<double>{}; }, &report);
  CHECK(report.repulsions > 0);
  const Vec3<double> corner[3] = {{0, 0, 0}, {0.1, 0, 0}, {0, 0, 0.1}};  // where the triangle starts
  for (int i = 0; i < 3; ++i) {
    CHECK((x_new.col(i) - corner[i]).norm() < 1e-15);  // a slide would be millimetres
    CHECK(v.col(i).norm() < 1e-13);
  }
  CHECK(x_new(1, 3) >= 0.008 - 1e-12);  // stopped at its start distance at least
  CHECK(std::abs(x_new(0, 3) - 0.02) < 1e-15);
}

TEST_CASE(
    "self-collision: a layer's friction drags a collider-held node only along a collider smoother than the layers",
    "[self-collision][held]") {
  // A flat triangle lying on a floor (held, normal +y); a node 8 mm above it (layer distance
  // 10 mm) moving down and along +x. Friction between the layers (0.4) acts on the pair. On a
  // floor rougher than that (0.5) the floor's friction carries the drag: the held triangle stays
  // and the upper node alone slows. On a floor smoother than that (0.1) the drag slides the
  // triangle along the floor, never into it; the pair's momentum along x is kept.
  SelfCollisionSettings<double> settings;
  settings.enabled = true;
  settings.friction = 0.4;
  auto drag = [&](double floor_friction) {
    const ColliderHold<double> floor{Vec3<double>(0, 1, 0), floor_friction};
    SelfCollisionReport report;
    const auto result = layer_on_held_triangle(
        settings, 0.5, [&](int i) { return i < 3 ? floor : ColliderHold<double>{}; }, &report);
    CHECK(report.repulsions > 0);
    return result;
  };
  const Vec3<double> corner[3] = {{0, 0, 0}, {0.1, 0, 0}, {0, 0, 0.1}};  // where the triangle starts
  const VectorX<double> masses = VectorX<double>::Constant(6, 0.01);
  const auto [x_rough, v_rough] = drag(0.5);
  for (int i = 0; i < 3; ++i) {
    CHECK((x_rough.col(i) - corner[i]).norm() < 1e-15);  // a drag would be millimetres
    CHECK(v_rough.col(i).norm() < 1e-13);
  }
  CHECK(v_rough(0, 3) < 0.5 - 1e-3);  // the upper node slowed: the floor held its layer still
  const auto [x_smooth, v_smooth] = drag(0.1);
  for (int i = 0; i < 3; ++i) {
    CHECK(v_smooth(0, i) > 1e-3);                        // dragged along +x
    CHECK(x_smooth(1, i) == Approx(0.0).margin(1e-15));  // not into the floor, not off it
  }
  CHECK(v_smooth(0, 3) < 0.5 - 1e-3);
  CHECK((v_smooth.row(0) * masses).value() == Approx(0.5 * 0.01).epsilon(1e-12));
}

TEST_CASE("self-collision: friction between layers slows an upper layer sliding over the lower", "[self-collision]") {
  // The fold's upper layer rests on the lower one (pinned) and is thrown along the fold line (+x);
  // the fold's springs pull it back either way, friction between the layers slows it further.
  auto travel = [](double mu) {
    ClothSpec<double> spec = folding_cloth<double>(9, 17);
    spec.self_collision.friction = mu;
    spec.pinned_nodes = std::vector<int>{};
    for (int node = 0; node < 9 * 9; ++node) spec.pinned_nodes->push_back(node);  // rows j <= 8
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, IntegratorKind::Implicit);
    State<double> state = cloth.initial_state();
    state.positions = test::laid_along(cloth, test::folded_path(spec.contact_thickness, 0.9, 0.01));
    const Grid<double>& grid = cloth.grid();
    for (int node = 0; node < grid.node_count(); ++node)
      if (state.positions(1, node) > 0.015) state.velocities(0, node) = 1.0;
    const int far = grid.node(4, grid.ny() - 1);
    const double start = state.positions(0, far);
    const RunCheck check = run_checked(*stepper, state, 0.25);
    CHECK(check.first_intersecting_step == -1);
    return state.positions(0, far) - start;
  };
  const double free = travel(0.0), rough = travel(0.8);
  CHECK(free > 0.05);
  CHECK(rough < 0.8 * free);
}

TEST_CASE("self-collision: same inputs give bit-identical states", "[self-collision][determinism]") {
  ClothSpec<double> spec = folding_cloth<double>(9, 17);
  spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)));
  const Clothd cloth(spec);
  auto a = integrator(cloth, IntegratorKind::Implicit);
  auto b = integrator(cloth, IntegratorKind::Implicit);
  State<double> sa = cloth.initial_state();
  sa.positions = test::laid_along(cloth, test::folded_path(spec.contact_thickness, 0.9, 0.15));
  State<double> sb = sa;
  for (int k = 0; k < 60; ++k) {
    REQUIRE(a->step(sa).ok());
    REQUIRE(b->step(sb).ok());
  }
  CHECK(a->self_collision_report().proximity_pairs > 0);
  CHECK((sa.positions.array() == sb.positions.array()).all());
  CHECK((sa.velocities.array() == sb.velocities.array()).all());
}

TEST_CASE("self-collision: bad settings name the parameter", "[self-collision][validation]") {
  auto message = [](const std::function<void(ClothSpec<double>&)>& change) {
    ClothSpec<double> spec;
    spec.self_collision.enabled = true;
    change(spec);
    try {
      Clothd cloth(spec);
    } catch (const InvalidParameter& e) { return std::string(e.what()); }
    return std::string();
  };
  CHECK_THAT(message([](auto& s) { s.self_collision.friction = -0.1; }), Catch::Contains("self friction"));
  CHECK_THAT(message([](auto& s) { s.self_collision.impulse_rounds = 65; }), Catch::Contains("self impulse rounds"));
  CHECK_THAT(message([](auto& s) { s.self_collision.separation_rate = 0; }), Catch::Contains("self separation rate"));
  CHECK_THAT(message([](auto& s) { s.contact_thickness = 0; }), Catch::Contains("contact thickness"));
  CHECK(message([](auto&) {}).empty());
}

namespace {

/// An irregular 9 x 17-node cloth (a jittered lattice 0.1 m apart cut by random diagonals), free,
/// self-collision on, laid along `path` as folding_cloth() is by laid_along().
ClothSpec<double> folding_mesh_cloth(State<double>& start, const std::function<Eigen::Vector2d(double)>& path) {
  const ClothMesh<double> square = test::irregular_patch(17, 0.1, 4);
  ClothMesh<double> mesh;  // its first 9 columns
  std::vector<int> index(std::size_t(17 * 17), -1);
  mesh.positions.resize(3, 9 * 17);
  for (int k = 0, n = 0; k < 17 * 17; ++k)
    if (k % 17 < 9) {
      index[std::size_t(k)] = n;
      mesh.positions.col(n++) = square.positions.col(k);
    }
  for (const std::array<int, 3>& t : square.triangles)
    if (index[std::size_t(t[0])] >= 0 && index[std::size_t(t[1])] >= 0 && index[std::size_t(t[2])] >= 0)
      mesh.triangles.push_back({index[std::size_t(t[0])], index[std::size_t(t[1])], index[std::size_t(t[2])]});
  ClothSpec<double> spec = folding_cloth<double>(9, 17);
  spec.mesh = mesh;
  spec.areal_density = 1.0;  // 0.01 kg per 0.1 m x 0.1 m cell, as folding_cloth()
  const Clothd cloth(spec);
  start = cloth.initial_state();
  for (int k = 0; k < cloth.node_count(); ++k) {
    const Eigen::Vector2d zy = path(mesh.positions(2, k));
    start.positions.col(k) = Vec3<double>(mesh.positions(0, k), zy.y(), zy.x());
  }
  return spec;
}

}  // namespace

TEST_CASE("self-collision on an irregular mesh cloth: folded over itself, it rests on its lower half",
          "[self-collision][mesh][long]") {
  for (const bool enabled : {true, false}) {
    for (IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Symplectic}) {
      if (!enabled && kind != IntegratorKind::Implicit) continue;
      INFO(to_string(kind) << (enabled ? "" : ", self-collision off"));
      State<double> state;
      ClothSpec<double> spec = folding_mesh_cloth(state, test::folded_path(0.01, 0.9, 0.15));
      spec.self_collision.enabled = enabled;
      spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)).set_friction(0.3, 0.3));
      const Clothd cloth(spec);
      REQUIRE(!cloth.is_grid());
      REQUIRE(!test::first_intersection(state.positions, cloth.triangles()).found);
      auto stepper = integrator(cloth, kind);
      const RunCheck check = run_checked(*stepper, state, 1.5);
      if (!enabled) {
        CHECK(check.first_intersecting_step >= 0);  // the check can fail
        continue;
      }
      CHECK(check.first_intersecting_step == -1);
      CHECK(check.unresolved == 0);
      CHECK(check.closest >= 0.01 * 2 * 0.01);
      // The upper layer's end (the last row) lies on the lower one, a layer distance above it.
      double top = 0;
      int count = 0;
      for (int k = 0; k < cloth.node_count(); ++k)
        if (spec.mesh->positions(2, k) > 1.55) {
          top += state.positions(1, k);
          ++count;
        }
      CHECK(top / count == Approx(3 * 0.01).margin(0.005));
    }
  }
}
