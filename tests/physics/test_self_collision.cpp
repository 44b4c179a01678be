// Self-collision (contact/self_collision.hpp) in scenes where the cloth folds onto itself, for
// every integrator: an exact triangle-triangle test over all triangle pairs that share no node
// (brute force, tests/collision/mesh_checks.hpp) finds no intersection at any step, and pairs of
// primitives that share no node keep a stated fraction of the layer distance; the same scenes
// without self-collision do pass through themselves (so the checks can fail); the fail-safe alone
// keeps the cloth apart; friction between layers; determinism; bad input. Joined nodes (the sides
// of a seam): a closed seam stays closed where it is pushed apart without them, a panel dropped
// onto the seam is still held off, pairs that share a node join all theirs, bad ids named.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "collision/cloth_shapes.hpp"
#include "collision/mesh_checks.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/contact/contact_handler.hpp"
#include "drape/core/mesh_generators.hpp"
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

TEMPLATE_TEST_CASE("self-collision: two layers pressed together by colliders end the fail-safe with no crossing left",
                   "[self-collision][failsafe]", float, double) {
  using T = TestType;
  // A vertex 0.5 um above a triangle (within the continuous test's touching tolerance), the
  // triangle held by a collider below and the vertex's triangle by one above (a fold squeezed
  // between arm and torso): proximity cannot part them, so the fail-safe takes the pair. Once its
  // zone has moved rigidly the pair keeps its start shape and cannot cross: the fail-safe ends
  // with nothing unresolved and leaves the resting layers where they are.
  SelfCollisionSettings<T> settings;
  settings.enabled = true;
  settings.impulse_rounds = 0;
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  Matrix3X<double> start(3, 6);
  start << 0, 1, 0, 0.2, 1.2, 0.2,  //
      0, 0, 0, 5e-7, 5e-3, 5e-3,    //
      0, 0, 1, 0.2, 0.2, 1.2;
  const Matrix3X<T> x = start.cast<T>();
  const VectorX<T> masses = VectorX<T>::Constant(6, T(0.01));
  SelfCollisionHandler<T> handler(settings, T(0.005), triangles, masses, x);
  const T dt = T(0.01);
  Matrix3X<T> v = Matrix3X<T>::Zero(3, 6);
  Matrix3X<T> x_new = x;
  const ColliderHold<T> below{Vec3<T>(0, 1, 0), T(0.5)}, above{Vec3<T>(0, -1, 0), T(0.5)};
  handler.respond(x, dt, x_new, v, std::vector<std::uint8_t>(6, 0),
                  [&](int i) { return i < 3 ? below : above; });
  CHECK(handler.report().zones == 1);
  CHECK(handler.report().unresolved == 0);
  CHECK((x_new - x).norm() < 1e-6 * x.norm());
  CHECK(v.norm() < T(1e-4));
  CHECK_FALSE(test::first_intersection(x_new, triangles).found);
}

TEMPLATE_TEST_CASE("self-collision: a node the end-of-step check pushes out of a collider does not pass through the layer above",
                   "[self-collision][keep-clear]", float, double) {
  // A heavy triangle B falls onto the tip p of a light triangle A, which sits 1 mm above the contact
  // layer of a small sphere (h = 5 mm): the impulse drives p 2 mm into the layer. The colliders'
  // check then pushes p out along the sphere's normal, up by 2 mm, past B, which stopped 1 mm above
  // it: one pass of self-collision and then the check leaves A through B. Alternating them, p is
  // held by the sphere in the second pass, so B gives way instead.
  using T = TestType;
  const T h = T(0.005);
  const std::vector<Collider<T>> colliders = {Collider<T>::sphere(Vec3<T>(0, T(-0.05), 0), T(0.05))};
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  Matrix3X<double> start(3, 6), end(3, 6);
  start << 0, 0.25, -0.25, -0.3, 0.3, 0,  //
      0.006, -0.05, -0.05, 0.02, 0.02, 0.02,  //
      0, 0.05, 0.05, -0.3, -0.3, 0.4;
  end = start;
  end.rightCols(3).row(1).setConstant(0.004);  // B falls 16 mm in the step, through p
  VectorX<T> masses(6);
  masses << T(0.001), T(0.001), T(0.001), T(0.1), T(0.1), T(0.1);
  const Matrix3X<T> x = start.cast<T>();
  const T dt = T(0.01);
  const std::vector<std::uint8_t> pinned(6, 0);
  SelfCollisionSettings<T> settings;
  settings.enabled = true;
  auto run = [&](bool alternate) {
    ContactHandler<T> contacts(colliders, h, masses);
    SelfCollisionHandler<T> self(settings, h, triangles, masses, x);
    Matrix3X<T> x_new = end.cast<T>(), v = (x_new - x) / dt;
    contacts.respond(x, (x_new - x) / dt, 0, dt, x_new, v, pinned);
    REQUIRE(contacts.report().contacts == 0);  // nothing touches the sphere before the layers meet
    auto held = [&](int i) { return contacts.hold(i); };
    if (alternate) {
      self.respond_and_keep_clear(x, dt, x_new, v, pinned, held,
                                  [&](Ref3X<T> x1, Ref3X<T> v1) { return contacts.keep_clear(x1, v1, pinned); });
      CHECK(self.report().clear_passes == 1);
    } else {
      self.respond(x, dt, x_new, v, pinned, held);
      CHECK(contacts.keep_clear(x_new, v, pinned) == 1);  // p alone
    }
    CHECK(self.report().unresolved == 0);
    const T depth = h - (x_new.col(0) - Vec3<T>(0, T(-0.05), 0)).norm() + T(0.05);
    CHECK(depth <= T(0.01) * h + T(1e-6));  // p ends outside the sphere's layer either way
    return x_new;
  };
  const Matrix3X<T> once = run(false);
  CHECK(test::first_intersection(once, triangles).found);  // the check passed p through B
  const Matrix3X<T> alternating = run(true);
  CHECK_FALSE(test::first_intersection(alternating, triangles).found);
  CHECK(alternating(1, 0) < alternating(1, 3));  // p below B, as it started
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

namespace {

/// Appends an nx x nz panel of 0.1 m grid cells to `mesh`, in the x-z plane from `origin` (node
/// (i, j) at origin + (0.1 i, 0, 0.1 j), counter-clockwise seen from +y); its nodes follow the
/// mesh's. Returns its node (i, j) as an id of the mesh.
std::function<int(int, int)> add_panel(ClothMesh<double>& mesh, int nx, int nz, const Vec3<double>& origin) {
  const ClothMesh<double> panel = grid_mesh<double>(nx, nz, 0.1);
  const int first = mesh.vertex_count();
  Matrix3X<double> positions(3, first + panel.vertex_count());
  positions.leftCols(first) = mesh.positions;
  positions.rightCols(panel.vertex_count()) = panel.positions.colwise() + origin;
  mesh.positions = positions;
  for (const std::array<int, 3>& t : panel.triangles)
    mesh.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
  return [first, nx](int i, int j) { return first + j * nx + i; };  // grid_mesh: node (i, j) is j nx + i
}

/// Two 5 x 5-node panels side by side in the x-z plane with a closed seam: the first's right
/// edge (x = 0.4) and the second's left edge (x = 0.4 + gap) are separate nodes, sewn pairwise.
struct SewnPanels {
  ClothMesh<double> mesh;
  std::vector<std::array<int, 2>> seam;
};
SewnPanels closed_seam(double gap = 0) {
  SewnPanels out;
  const auto left = add_panel(out.mesh, 5, 5, Vec3<double>::Zero());
  const auto right = add_panel(out.mesh, 5, 5, Vec3<double>(0.4 + gap, 0, 0));
  for (int j = 0; j < 5; ++j) out.seam.push_back({left(4, j), right(0, j)});
  return out;
}

/// A free cloth of `mesh` as folding_cloth() (h = 1 cm, self-collision on), gravity off.
ClothSpec<double> panel_cloth(const ClothMesh<double>& mesh, const std::vector<std::array<int, 2>>& joined) {
  ClothSpec<double> spec = folding_cloth<double>(3, 3);
  spec.mesh = mesh;
  spec.gravity = 0;
  spec.self_collision.joined_nodes = joined;
  return spec;
}

/// The widest distance between the nodes of a pair.
double widest_gap(const Matrix3X<double>& x, const std::vector<std::array<int, 2>>& pairs) {
  double widest = 0;
  for (const auto& [a, b] : pairs) widest = std::max(widest, (x.col(a) - x.col(b)).norm());
  return widest;
}

/// Takes 10 steps of a cloth at rest; returns how far any node moved and the widest gap of `pairs`
/// at the end, and sums what self-collision did over the steps into `seen`.
std::pair<double, double> rest_run(const Clothd& cloth, IntegratorKind kind,
                                   const std::vector<std::array<int, 2>>& pairs, SelfCollisionReport& seen) {
  auto stepper = integrator(cloth, kind);
  State<double> state = cloth.initial_state();
  seen = {};
  for (int k = 0; k < 10; ++k) {
    REQUIRE(stepper->step(state).ok());
    const SelfCollisionReport& r = stepper->self_collision_report();
    seen.proximity_pairs += r.proximity_pairs;
    seen.repulsions += r.repulsions;
    seen.impacts += r.impacts;
    seen.zones += r.zones;
  }
  const double moved = (state.positions - cloth.start_positions()).colwise().norm().maxCoeff();
  return {moved, widest_gap(state.positions, pairs)};
}

/// The triangles of `triangles` whose corners all pass `keep`, with their nodes renumbered in the
/// order they first appear, and those nodes' columns of x: a mesh of its own for the checks of
/// mesh_checks.hpp, which count every column of x.
std::pair<Matrix3X<double>, std::vector<std::array<int, 3>>> part_of(const Matrix3X<double>& x,
                                                                    const std::vector<std::array<int, 3>>& triangles,
                                                                    const std::function<bool(int)>& keep) {
  std::vector<int> index(std::size_t(x.cols()), -1);
  std::vector<int> used;
  std::vector<std::array<int, 3>> part;
  for (const std::array<int, 3>& t : triangles) {
    if (!keep(t[0]) || !keep(t[1]) || !keep(t[2])) continue;
    std::array<int, 3> renumbered{};
    for (std::size_t k = 0; k < 3; ++k) {
      int& id = index[std::size_t(t[k])];
      if (id < 0) {
        id = int(used.size());
        used.push_back(t[k]);
      }
      renumbered[k] = id;
    }
    part.push_back(renumbered);
  }
  Matrix3X<double> xs(3, Index(used.size()));
  for (std::size_t k = 0; k < used.size(); ++k) xs.col(Index(k)) = x.col(used[k]);
  return {xs, part};
}

}  // namespace

TEST_CASE("self-collision with joined nodes: the two sides of a closed seam do not push each other apart",
          "[self-collision][joined]") {
  for (const double gap : {0.0, 0.001}) {
    const SewnPanels panels = closed_seam(gap);
    for (IntegratorKind kind : {IntegratorKind::Rk2, IntegratorKind::Implicit}) {
      INFO(to_string(kind) << ", seam closed to " << gap << " m");
      SelfCollisionReport seen;
      // Joined: no pair across the seam is tested, so nothing moves.
      const Clothd joined(panel_cloth(panels.mesh, panels.seam));
      const auto [moved, widest] = rest_run(joined, kind, panels.seam, seen);
      CHECK(moved < 1e-12);
      CHECK(std::abs(widest - gap) < 1e-12);
      CHECK(seen.proximity_pairs == 0);
      CHECK(seen.repulsions == 0);
      CHECK(seen.impacts == 0);
      CHECK(seen.zones == 0);
      // Not joined (the check can fail): a seam node and the other panel's triangles and edges at
      // its partner are closer than 2h. Coincident, they touch: every step crosses and needs the
      // fail-safe, which moves the seam's region; 1 mm apart, they are pushed towards 2h apart.
      const Clothd apart(panel_cloth(panels.mesh, {}));
      const auto [moved_apart, widest_apart] = rest_run(apart, kind, panels.seam, seen);
      if (gap == 0) {
        CHECK(seen.impacts > 0);
        CHECK(seen.zones > 0);
        CHECK(moved_apart > 1e-4);
      } else {
        CHECK(seen.repulsions > 0);
        CHECK(widest_apart > 0.5 * 2 * apart.contact_thickness());
      }
    }
  }
}

TEST_CASE("self-collision with joined nodes: a panel dropped onto a closed seam is still held off by it",
          "[self-collision][joined]") {
  // The sewn panels lie on a floor; a third 0.4 m square panel falls onto them across the seam.
  // Its nodes are joined to none: every pair between it and the seam's panels is still tested.
  for (const bool enabled : {true, false}) {
    for (IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2}) {
      if (!enabled && kind != IntegratorKind::Implicit) continue;
      INFO(to_string(kind) << (enabled ? "" : ", self-collision off"));
      SewnPanels panels = closed_seam();
      const double h = 0.01;
      panels.mesh.positions.row(1).setConstant(h);  // resting on the floor
      const int sewn = panels.mesh.vertex_count();
      add_panel(panels.mesh, 5, 5, Vec3<double>(0.2, h + 0.06, 0.05));
      ClothSpec<double> spec = panel_cloth(panels.mesh, panels.seam);
      spec.gravity = 10;
      spec.self_collision.enabled = enabled;
      spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)).set_friction(0.3, 0.3));
      const Clothd cloth(spec);
      auto stepper = integrator(cloth, kind);
      State<double> state = cloth.initial_state();
      state.velocities.rightCols(cloth.node_count() - sewn).row(1).setConstant(-3.0);
      const auto left = [&](int v) { return v < 25 || v >= sewn; };
      const auto right = [&](int v) { return v >= 25; };
      int first_crossing = -1;
      double closest = 1e30;
      const int steps = int(std::lround(0.5 / stepper->dt()));
      for (int k = 0; k < steps; ++k) {
        REQUIRE(stepper->step(state).ok());
        CHECK(stepper->self_collision_report().unresolved == 0);
        // The dropped panel with each sewn panel, each a mesh of its own (brute force).
        for (const auto& keep : {std::function<bool(int)>(left), std::function<bool(int)>(right)}) {
          const auto [x, triangles] = part_of(state.positions, cloth.triangles(), keep);
          if (first_crossing < 0 && test::first_intersection(x, triangles).found) first_crossing = k;
          closest = std::min(closest, test::min_nonadjacent_distance(x, triangles));
        }
      }
      const double dropped_height = state.positions.rightCols(cloth.node_count() - sewn).row(1).mean();
      if (!enabled) {
        CHECK(first_crossing >= 0);  // the check can fail
        continue;
      }
      CHECK(first_crossing == -1);
      CHECK(closest >= 0.01 * 2 * h);
      CHECK(dropped_height == Approx(3 * h).margin(0.5 * h));  // on the sewn panels, a layer above them
      CHECK(widest_gap(state.positions, panels.seam) < 0.1 * h);
    }
  }
}

TEST_CASE("self-collision with joined nodes: pairs that share a node join all three (a corner where seams meet)",
          "[self-collision][joined]") {
  // Three panels round a corner at the origin: a (x < 0, z > 0) and b (x > 0, z < 0) each sewn to
  // c (x > 0, z > 0) along an edge. a's and b's corners at the origin are sewn to c's only, yet
  // the three are one: a's corner touches b's triangles there, and must not push them.
  ClothMesh<double> mesh;
  const auto a = add_panel(mesh, 5, 5, Vec3<double>(-0.4, 0, 0));
  const auto b = add_panel(mesh, 5, 5, Vec3<double>(0, 0, -0.4));
  const auto c = add_panel(mesh, 5, 5, Vec3<double>(0, 0, 0));
  std::vector<std::array<int, 2>> seams;
  for (int j = 0; j < 5; ++j) seams.push_back({a(4, j), c(0, j)});
  for (int i = 0; i < 5; ++i) seams.push_back({b(i, 4), c(i, 0)});
  const std::vector<std::array<int, 2>> reversed(seams.rbegin(), seams.rend());
  const std::vector<std::array<int, 2>> corners = {{a(4, 0), b(0, 4)}};
  for (const bool in_order : {true, false}) {
    INFO((in_order ? "in order" : "reversed"));
    const std::vector<std::array<int, 2>>& pairs = in_order ? seams : reversed;
    const MeshTopology topology(mesh.vertex_count(), mesh.all_triangles(), pairs);
    CHECK(topology.representative(b(0, 4)) == a(4, 0));  // the lowest of the three
    CHECK(topology.representative(c(0, 0)) == a(4, 0));
    CHECK(topology.representative(c(1, 0)) == b(1, 4));
    CHECK(topology.representative(a(1, 1)) == a(1, 1));
    for (int t = 0; t < topology.triangle_count(); ++t)  // a's corner belongs to b's triangles at b's corner
      CHECK(topology.triangle_has_node(t, a(4, 0)) ==
            (topology.triangle_has_node(t, b(0, 4)) || topology.triangle_has_node(t, c(0, 0))));
    for (IntegratorKind kind : {IntegratorKind::Rk2, IntegratorKind::Implicit}) {
      INFO(to_string(kind));
      const Clothd cloth(panel_cloth(mesh, pairs));
      SelfCollisionReport seen;
      const auto [moved, gap] = rest_run(cloth, kind, corners, seen);
      CHECK(moved < 1e-12);
      CHECK(seen.proximity_pairs + seen.repulsions + seen.impacts + seen.zones == 0);
    }
  }
  // The seams without the corner's pairs (the check can fail): the three corners touch there and
  // cross every step.
  std::vector<std::array<int, 2>> without_corner;
  for (const std::array<int, 2>& p : seams)
    if (p[1] != c(0, 0)) without_corner.push_back(p);
  REQUIRE(without_corner.size() == seams.size() - 2);
  const Clothd unjoined(panel_cloth(mesh, without_corner));
  SelfCollisionReport seen;
  const double moved = rest_run(unjoined, IntegratorKind::Implicit, corners, seen).first;
  CHECK(seen.impacts > 0);
  CHECK(moved > 1e-4);
}

TEST_CASE("self-collision: bad joined nodes are named", "[self-collision][joined][validation]") {
  const SewnPanels panels = closed_seam();  // 50 nodes
  auto message = [&](const std::vector<std::array<int, 2>>& joined, bool enabled) {
    ClothSpec<double> spec = panel_cloth(panels.mesh, joined);
    spec.self_collision.enabled = enabled;
    try {
      Clothd cloth(spec);
    } catch (const InvalidParameter& e) { return std::string(e.what()); }
    return std::string();
  };
  CHECK_THAT(message({{0, 1}, {4, 50}}, true), Catch::Contains("'self joined nodes[1]'") && Catch::Contains("[0, 50)"));
  CHECK_THAT(message({{-1, 3}}, true), Catch::Contains("'self joined nodes[0]'"));
  CHECK_THAT(message({{0, 1}, {2, 3}, {7, 7}}, true), Catch::Contains("'self joined nodes[2]'"));
  CHECK_THAT(message({{4, 50}}, false), Catch::Contains("'self joined nodes[0]'"));  // checked with it off too
  CHECK(message(panels.seam, true).empty());
  // A grid cloth's nodes.
  ClothSpec<double> grid;
  grid.self_collision.joined_nodes = {{0, 1089}};
  CHECK_THROWS_WITH(Clothd{grid}, Catch::Contains("'self joined nodes[0]'") && Catch::Contains("[0, 1089)"));
  // The handler alone, and the topology.
  const std::vector<std::array<int, 3>> triangles = {{0, 1, 2}, {3, 4, 5}};
  const Matrix3X<double> x = Matrix3X<double>::Random(3, 6);
  SelfCollisionSettings<double> settings;
  settings.enabled = true;
  settings.joined_nodes = {{2, 6}};
  CHECK_THROWS_WITH(SelfCollisionHandler<double>(settings, 0.005, triangles, VectorX<double>::Ones(6), x),
                    Catch::Contains("'self joined nodes[0]'") && Catch::Contains("[0, 6)"));
  CHECK_THROWS_WITH(MeshTopology(6, triangles, {{0, 3}, {5, 5}}), Catch::Contains("'joined'") &&
                                                                       Catch::Contains("pair 1"));
}
