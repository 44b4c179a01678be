// Contact with colliders in both integrators (contact/contact_handler.hpp): resting contact with
// the reaction equal to the weight (on a floor, on a box mesh's top and on a round table), a cloth
// draped over a table's rounded rim, Coulomb friction on a slope (analytic and meshed) against
// g (sin a - mu cos a), no tunnelling through a thin box, a thin mesh plate or a disk or past a fast
// collider or a fast mesh plate (checked by brute force on every node's path), direct and iterative
// solvers agreeing, momentum, determinism (on a mesh too) and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <memory>

#include "drape/core/solid_generators.hpp"
#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/physics/air.hpp"
#include "drape/solvers/enable_ldlt.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

constexpr double pi = 3.14159265358979323846;

/// A free, damped n x n cloth 0.1 m apart (1 m across at n = 11), gravity 10.
template <class S>
ClothSpec<S> free_cloth(int n = 11) {
  ClothSpec<S> spec = test::small_spec<S>(n, S(10));
  spec.springs = {{S(2000), S(2)}, {S(1000), S(1)}, {S(100), S(0.2)}};
  spec.pinned_nodes = std::vector<int>{};
  return spec;
}

template <class S>
std::unique_ptr<Integrator<S>> integrator(const Cloth<S>& cloth, IntegratorKind kind,
                                          LinearSolverKind solver = LinearSolverKind::Cg, int contact_rounds = 1) {
  ImplicitOptions options;
  options.contact_rounds = contact_rounds;
  options.dt = kind == IntegratorKind::Implicit ? 0.01 : 5e-4;
  options.threads = 1;
  options.solver = solver;
  options.tolerance = std::is_same_v<S, float> ? 1e-5 : 1e-8;
  return make_integrator(cloth, kind, options);
}

/// Runs `seconds`, calling `check(state_before, state_after)` after every step.
template <class S>
void run(Integrator<S>& integrator, State<S>& state, double seconds,
         const std::function<void(const State<S>&, const State<S>&)>& check = {}) {
  const int steps = int(std::lround(seconds / double(integrator.dt())));
  State<S> before;
  for (int k = 0; k < steps; ++k) {
    if (check) before = state;
    const StepStatus status = integrator.step(state);
    INFO("step " << k << ": " << to_string(status.error));
    REQUIRE(status.ok());
    if (check) check(before, state);
  }
}

/// The cloth's mass-weighted mean velocity.
template <class S>
Vec3<double> mean_velocity(const State<S>& state) {
  return state.velocities.template cast<double>().rowwise().mean();
}

/// Smallest distance from point c to the segment p0 -> p1.
double segment_distance(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& c) {
  const Vec3<double> d = p1 - p0;
  const double s = d.squaredNorm() > 0 ? std::clamp((c - p0).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p0 + s * d - c).norm();
}

/// Each node's straight path from `before` to `after` in `judge`'s moving frame, sampled `spacing`
/// apart or closer, stays outside `judge` inflated by the cloth's contact thickness.
void require_paths_outside(const Colliderd& judge, const Clothd& cloth, const Stated& before, const Stated& after,
                           double spacing) {
  const double floor = cloth.contact_thickness() - cloth.contact_tolerance();
  const RigidPose<double> pose0 = judge.motion().pose(before.time), pose1 = judge.motion().pose(after.time);
  for (Index i = 0; i < after.positions.cols(); ++i) {
    const Vec3<double> p0 = pose0.to_local(before.positions.col(i)), p1 = pose1.to_local(after.positions.col(i));
    const int samples = 1 + int((p1 - p0).norm() / spacing);
    for (int j = 0; j <= samples; ++j) {
      const Vec3<double> world = pose0.to_world(p0 + (p1 - p0) * (double(j) / samples));
      REQUIRE(judge.query(world, before.time).distance >= floor);
    }
  }
}

}  // namespace

TEMPLATE_TEST_CASE("contact: a cloth dropped on a plane or a box mesh rests on it and the floor carries its weight",
                   "[contact][mesh_collider][long]", float, double) {
  using S = TestType;
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic})
    for (const bool meshed : {false, true}) {
    INFO(to_string(kind) << (meshed ? ", box mesh" : ", plane"));
    ClothSpec<S> spec = free_cloth<S>();
    // The floor at y = -0.3: a plane, or the top of a 4 m wide box meshed with 2 x 2 squares a face.
    spec.colliders.push_back(meshed ? Collider<S>::mesh(box_mesh<S>(Vec3<S>(2, S(0.5), 2), 2),
                                                        Vec3<S>(S(0.5), S(-0.8), S(0.5)))
                                    : Collider<S>::plane(Vec3<S>(0, S(-0.3), 0), Vec3<S>(0, 1, 0)));
    const Cloth<S> cloth(spec);
    auto stepper = integrator(cloth, kind);
    State<S> state = cloth.initial_state();
    const S h = cloth.contact_thickness();
    const S floor = S(-0.3) + h;
    run<S>(*stepper, state, 1.5, [&](const State<S>&, const State<S>& after) {
      // Brute force: no node below the floor by more than the stated tolerance, and the
      // end-of-step check never had to push one out.
      REQUIRE(after.positions.row(1).minCoeff() >= floor - cloth.contact_tolerance());
      REQUIRE(stepper->contact_report().corrected == 0);
    });
    const ContactReport<S>& report = stepper->contact_report();
    if (kind == IntegratorKind::Implicit) {
      // At rest every contact is a constraint of the one solve of the step.
      CHECK(report.rounds == 1);
      CHECK(report.after_solve == 0);
    }
    const double weight = double(cloth.grid().masses().sum()) * 10.0;
    CHECK(report.contacts == cloth.node_count());
    CHECK(std::abs(double(report.normal_force.y()) - weight) <= 0.005 * weight);
    CHECK(std::abs(double(report.normal_force.x())) + std::abs(double(report.normal_force.z())) <= 1e-6 * weight);
    CHECK(mean_velocity(state).norm() <= 1e-3);
    CHECK(std::abs(double(state.positions.row(1).mean()) - double(floor)) <= 1e-4);
    }
}

TEMPLATE_TEST_CASE("contact: a cloth dropped on a round table rests on its top; over a smaller one it drapes",
                   "[contact][cylinder]", float, double) {
  using S = TestType;
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    // Radius 0.8, top at y = -0.3: the whole cloth (corners 0.71 from its middle) lands on the top.
    ClothSpec<S> spec = free_cloth<S>();
    spec.colliders.push_back(
        Collider<S>::cylinder(Vec3<S>(S(0.5), S(-0.4), S(0.5)), S(0.8), S(0.1), Mat3<S>::Identity(), S(0.02)));
    const Cloth<S> cloth(spec);
    auto stepper = integrator(cloth, kind);
    State<S> state = cloth.initial_state();
    const S top = S(-0.3) + cloth.contact_thickness();
    run<S>(*stepper, state, 1.5, [&](const State<S>&, const State<S>& after) {
      REQUIRE(after.positions.row(1).minCoeff() >= top - cloth.contact_tolerance());
      REQUIRE(stepper->contact_report().corrected == 0);
    });
    const ContactReport<S>& report = stepper->contact_report();
    const double weight = double(cloth.grid().masses().sum()) * 10.0;
    CHECK(report.contacts == cloth.node_count());
    CHECK(std::abs(double(report.normal_force.y()) - weight) <= 0.005 * weight);
    CHECK(mean_velocity(state).norm() <= 1e-3);
    CHECK(std::abs(double(state.positions.row(1).mean()) - double(top)) <= 1e-4);

    // The drape tester: radius 0.3, rims rounded by 0.05, a rough top. The middle rests on the top
    // and the rest hangs over the rim; no node is ever deeper in the table than the tolerance.
    ClothSpec<S> drape_spec = free_cloth<S>();
    const Collider<S> table =
        Collider<S>::cylinder(Vec3<S>(S(0.5), S(-0.4), S(0.5)), S(0.3), S(0.1), Mat3<S>::Identity(), S(0.05))
            .set_friction(S(0.3), S(0.3));
    drape_spec.colliders.push_back(table);
    const Cloth<S> draped(drape_spec);
    auto drape_stepper = integrator(draped, kind);
    State<S> drape_state = draped.initial_state();
    S closest = S(1);
    run<S>(*drape_stepper, drape_state, 1.5, [&](const State<S>&, const State<S>& after) {
      for (Index i = 0; i < after.positions.cols(); ++i)
        closest = std::min(closest, table.query(after.positions.col(i), after.time).distance);
      REQUIRE(closest >= draped.contact_thickness() - draped.contact_tolerance());
      REQUIRE(drape_stepper->contact_report().corrected == 0);
    });
    CHECK(closest <= draped.contact_thickness() + draped.contact_tolerance());  // it did touch
    const int middle = draped.grid().node(5, 5);
    CHECK(std::abs(double(drape_state.positions(1, middle) - top)) <= 1e-3);
    for (const int corner : {draped.grid().node(0, 0), draped.grid().node(10, 0), draped.grid().node(0, 10),
                             draped.grid().node(10, 10)})
      CHECK(drape_state.positions(1, corner) < S(-0.5));
    CHECK(drape_stepper->contact_report().contacts > 0);
  }
}

TEMPLATE_TEST_CASE("contact: friction on a slope, analytic or meshed, sliding at g (sin a - mu cos a) or sticking",
                   "[contact][friction][mesh_collider][long]", float, double) {
  using S = TestType;
  const double angle = 20 * pi / 180;  // tan a = 0.364
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic})
    for (const double mu : {0.0, 0.2, 0.5})
      for (const bool meshed : {false, true}) {
      INFO(to_string(kind) << ", mu = " << mu << (meshed ? ", box mesh" : ", plane"));
      ClothSpec<S> spec = free_cloth<S>();
      const Mat3<S> tilt = Eigen::AngleAxis<S>(S(angle), Vec3<S>::UnitZ()).toRotationMatrix();
      const Vec3<S> normal = tilt * Vec3<S>::UnitY();
      // The slope through the origin: a plane, or the top face of an 8 m tilted box mesh.
      spec.colliders.push_back(
          (meshed ? Collider<S>::mesh(box_mesh<S>(Vec3<S>(4, S(0.5), 4), 4), Vec3<S>(-S(0.5) * normal), tilt)
                  : Collider<S>::plane(Vec3<S>::Zero(), normal))
              .set_friction(S(mu), S(mu)));
      const Cloth<S> cloth(spec);
      auto stepper = integrator(cloth, kind);
      State<S> state = cloth.initial_state();
      // Laid flat on the slope, resting on it at the contact thickness.
      state.positions = ((tilt * state.positions).colwise() + cloth.contact_thickness() * normal).eval();
      const Vec3<double> start = state.positions.template cast<double>().rowwise().mean();
      const Vec3<double> downhill = -(tilt * Vec3<S>::UnitX()).template cast<double>();
      const double time = 1.0;
      run<S>(*stepper, state, time);
      const double travelled = (state.positions.template cast<double>().rowwise().mean() - start).dot(downhill);
      if (mu < std::tan(angle)) {
        // From rest at constant acceleration: s = a t^2 / 2, v = a t.
        const double expected = 10.0 * (std::sin(angle) - mu * std::cos(angle));
        CHECK(std::abs(mean_velocity(state).dot(downhill) / time - expected) <= 0.05 * expected);
        CHECK(std::abs(2 * travelled / (time * time) - expected) <= 0.05 * expected);
        CHECK(stepper->contact_report().sliding == cloth.node_count());
      } else {
        CHECK(std::abs(travelled) < 1e-3);
        CHECK((state.positions.template cast<double>().rowwise().mean() - start).norm() < 1e-3);
        CHECK(stepper->contact_report().sticking == cloth.node_count());
      }
    }
}

TEST_CASE("contact: a cloth on the floor thrown upward leaves it (contacts never pull)", "[contact]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    ClothSpecd spec = free_cloth<double>();
    spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)));
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    state.positions.row(1).setConstant(cloth.contact_thickness());
    state.velocities.row(1).setConstant(2.0);
    run<double>(*stepper, state, 0.1);
    // Free flight: y = h + 2 t - 5 t^2.
    CHECK(std::abs(state.positions.row(1).mean() - (cloth.contact_thickness() + 0.2 - 0.05)) <= 0.01);
    CHECK(stepper->contact_report().contacts == 0);
    // Resting on the floor, lifted by its middle: the contacts around it let go and follow.
    Stated rest = cloth.initial_state();
    rest.positions.row(1).setConstant(cloth.contact_thickness());
    run<double>(*stepper, rest, 0.05);
    REQUIRE(stepper->contact_report().contacts == cloth.node_count());
    const int middle = cloth.grid().node(5, 5), beside = cloth.grid().node(6, 5);
    const Vec3<double> start = rest.positions.col(middle);
    stepper->pins().pin(middle,
                        PinPath<double>::keyframes({rest.time, rest.time + 1.0}, {start, start + Vec3<double>(0, 1, 0)},
                                                   Interpolation::Linear));
    run<double>(*stepper, rest, 0.3);
    CHECK(rest.positions(1, beside) > 0.15);
    CHECK(stepper->contact_report().contacts < cloth.node_count() - 8);
  }
}

TEST_CASE("contact: nodes the solve sends into a collider get an impulse, or with rounds are solved again",
          "[contact][rounds]") {
  // At rest 1 cm above the floor: the velocity at the start predicts no contact, but one step of
  // 0.1 s falls 0.1 m, so the first solve reaches the floor. With one round (the default) those
  // nodes get an impulse after the solve; with two the step is solved again with them as
  // constraints. Either way they end on the floor, and they are constraints of the next step.
  ClothSpecd spec = free_cloth<double>(7);
  spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)));
  const Clothd cloth(spec);
  for (const int rounds : {1, 2}) {
    INFO(rounds << " round(s)");
    ImplicitOptions options;
    options.dt = 0.1;
    options.threads = 1;
    options.contact_rounds = rounds;
    ImplicitEulerd implicit(cloth, options);
    Stated state = cloth.initial_state();
    state.positions.row(1).setConstant(cloth.contact_thickness() + 0.01);
    REQUIRE(implicit.step(state).ok());
    const ContactReport<double>& report = implicit.contact_report();
    CHECK(report.rounds == rounds);
    CHECK(report.contacts == cloth.node_count());
    CHECK(report.after_solve == (rounds == 1 ? cloth.node_count() : 0));
    CHECK(report.corrected == 0);
    CHECK((state.positions.row(1).array() - cloth.contact_thickness()).abs().maxCoeff() <= 1e-9);
    REQUIRE(implicit.step(state).ok());  // resting now: constraints from the start, one solve
    CHECK(implicit.contact_report().rounds == 1);
    CHECK(implicit.contact_report().after_solve == 0);
  }
}

TEST_CASE("contact: a surface that had to pull lets go for good: a cloth blown off a floor leaves it",
          "[contact][rounds]") {
  // Resting on the floor in an updraft that lifts it (drag 0.05 N s/m per node in 20 m/s upward:
  // 1 N against a weight of 0.3 N). The first step finds the contacts pulling and lets them go;
  // from the next step they stay free (not constrained again at rest on the surface), so the
  // cloth rises. Were they constrained again each step, one round would hold it down for ever.
  ClothSpecd spec = free_cloth<double>(7);
  spec.colliders.push_back(Colliderd::plane(Vec3<double>::Zero(), Vec3<double>(0, 1, 0)));
  AirSettings air;
  air.drag = 0.05;
  air.wind = {0, 20, 0};
  spec.force_terms = air_force_terms<double>(air, Gridd(7, 7, 0.1, 0.03).triangles());
  const Clothd cloth(spec);
  for (const int rounds : {1, 3}) {
    INFO(rounds << " round(s)");
    ImplicitOptions options;
    options.dt = 0.01;
    options.threads = 1;
    options.contact_rounds = rounds;
    ImplicitEulerd implicit(cloth, options);
    Stated state = cloth.initial_state();
    state.positions.row(1).setConstant(cloth.contact_thickness());
    for (int k = 0; k < 5; ++k) REQUIRE(implicit.step(state).ok());
    CHECK(implicit.contact_report().contacts == 0);
    CHECK(state.positions.row(1).minCoeff() > cloth.contact_thickness() + 0.001);
    CHECK(state.velocities.row(1).minCoeff() > 0.05);
  }
}

TEST_CASE("contact: a cloth thrown at a thin box or a thin mesh plate never passes through it",
          "[contact][tunnelling][mesh_collider][long]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic})
    for (const bool meshed : {false, true}) {
    INFO(to_string(kind) << (meshed ? ", mesh plate" : ", box"));
    ClothSpecd spec = free_cloth<double>();
    spec.gravity = 0;
    // 1 cm thick, 3 m wide, top face at y = 0; the cloth moves 0.3 m (implicit) or 15 mm (RK2)
    // per step toward it, more than the box is thick.
    const double half = 0.005;
    const Vec3<double> centre(0.5, -half, 0.5), extents(1.5, half, 1.5);
    spec.colliders.push_back(meshed ? Colliderd::mesh(box_mesh<double>(extents, 3), centre)
                                    : Colliderd::box(centre, extents));
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    state.positions.row(1).array() += 1.0;
    state.velocities.row(1).setConstant(-30.0);
    const double top = cloth.contact_thickness();
    run<double>(*stepper, state, 0.3, [&](const Stated& before, const Stated& after) {
      for (Index i = 0; i < after.positions.cols(); ++i) {
        // Every node's straight path stays above the box's top face (all nodes are over the box).
        REQUIRE(std::min(before.positions(1, i), after.positions(1, i)) >= top - cloth.contact_tolerance());
      }
    });
    CHECK(state.velocities.row(1).maxCoeff() <= 1e-6);  // stopped on it, not bounced through
    }
}

TEST_CASE("contact: a cloth thrown at a thin disk never passes through it", "[contact][tunnelling][cylinder]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    ClothSpecd spec = free_cloth<double>();
    spec.gravity = 0;
    // 1 cm thick, radius 1.5, top at y = 0, under the whole cloth; the cloth moves 0.3 m (implicit)
    // or 15 mm (symplectic) per step toward it, more than the disk is thick.
    const double half = 0.005;
    spec.colliders.push_back(Colliderd::cylinder(Vec3<double>(0.5, -half, 0.5), 1.5, half));
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    state.positions.row(1).array() += 1.0;
    state.velocities.row(1).setConstant(-30.0);
    const double top = cloth.contact_thickness();
    run<double>(*stepper, state, 0.3, [&](const Stated& before, const Stated& after) {
      for (Index i = 0; i < after.positions.cols(); ++i)
        REQUIRE(std::min(before.positions(1, i), after.positions(1, i)) >= top - cloth.contact_tolerance());
    });
    CHECK(state.velocities.row(1).maxCoeff() <= 1e-6);
  }
}

TEST_CASE("contact: a fast tilted rod swept through a hanging cloth never passes a node",
          "[contact][tunnelling][cylinder]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    ClothSpecd spec = free_cloth<double>(11);
    spec.pinned_nodes = std::vector<int>{0, 10};  // two corners
    // A cylinder of radius 0.08 lying along z (a quarter turn about x), 1.6 m long, under the
    // cloth's middle and moving up at 20 m/s: 0.2 m per implicit step, more than its diameter.
    const double radius = 0.08, speed = 20.0;
    const Mat3<double> lying = Eigen::AngleAxisd(pi / 2, Vec3<double>::UnitX()).toRotationMatrix();
    const Colliderd rod =
        Colliderd::cylinder(Vec3<double>(0.5, -1.0, 0.5), radius, 0.8, lying, 0.02).moving(Vec3<double>(0, speed, 0));
    spec.colliders.push_back(rod);
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    run<double>(*stepper, state, 0.1, [&](const Stated& before, const Stated& after) {
      require_paths_outside(rod, cloth, before, after, 1e-3);
    });
    CHECK(state.positions.row(1).maxCoeff() > 0.3);  // thrown up by the rod
  }
}

TEST_CASE("contact: a thin mesh plate swept fast through a hanging cloth never passes a node, moved or key-framed",
          "[contact][tunnelling][mesh_collider]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic})
    for (const bool key_framed : {false, true}) {
    INFO(to_string(kind) << (key_framed ? ", key-framed vertices" : ", rigid motion"));
    ClothSpecd spec = free_cloth<double>(11);
    spec.pinned_nodes = std::vector<int>{0, 10};  // two corners
    // A plate 4 mm thick and 0.6 m wide, tilted, under the cloth's middle and moving up at 20 m/s:
    // 0.2 m per implicit step, fifty times its thickness. The same plate as an analytic box judges.
    const double speed = 20.0;
    const Vec3<double> extents(0.3, 0.002, 0.3), centre(0.5, -1.0, 0.5);
    const Mat3<double> turn = Eigen::AngleAxisd(0.3, Vec3<double>(1, 0, 1).normalized()).toRotationMatrix();
    // Key-framed: the vertices themselves at 0 and 0.1 s (the mesh deforms, as a body's would).
    const ClothMesh<double> mesh = box_mesh<double>(extents, 2);
    Matrix3X<double> at_start = (turn * mesh.positions).colwise() + centre;
    Matrix3X<double> at_end = at_start.colwise() + Vec3<double>(0, 0.1 * speed, 0);
    const Colliderd plate = key_framed ? Colliderd::animated_mesh(mesh, {at_start, at_end}, {0.0, 0.1})
                                       : Colliderd::mesh(mesh, centre, turn).moving(Vec3<double>(0, speed, 0));
    const Colliderd judge = Colliderd::box(centre, extents, turn).moving(Vec3<double>(0, speed, 0));
    spec.colliders.push_back(plate);
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    run<double>(*stepper, state, 0.1, [&](const Stated& before, const Stated& after) {
      require_paths_outside(judge, cloth, before, after, 5e-4);  // the plate is 4 mm thick
    });
    CHECK(state.positions.row(1).maxCoeff() > 0.3);  // thrown up by the plate
    }
}

TEST_CASE("contact: a fast sphere hitting a hanging cloth never passes a node", "[contact][tunnelling]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    ClothSpecd spec = free_cloth<double>(11);
    spec.pinned_nodes = std::vector<int>{0, 10};  // two corners
    const double radius = 0.15, speed = 20.0;
    const Vec3<double> start(0.5, -1.0, 0.5);  // under the cloth's middle, moving up at 20 m/s
    spec.colliders.push_back(Colliderd::sphere(start, radius).moving(Vec3<double>(0, speed, 0)));
    const Clothd cloth(spec);
    auto stepper = integrator(cloth, kind);
    Stated state = cloth.initial_state();
    const double h = cloth.contact_thickness();
    run<double>(*stepper, state, 0.1, [&](const Stated& before, const Stated& after) {
      // In the sphere's frame each node moves on a straight line from where it was to where it
      // is: that path must stay outside the sphere inflated by h (the sphere moves 0.33 m per
      // implicit step, more than its diameter).
      const double t0 = before.time, t1 = after.time;
      const Vec3<double> c0 = start + Vec3<double>(0, speed * t0, 0), c1 = start + Vec3<double>(0, speed * t1, 0);
      for (Index i = 0; i < after.positions.cols(); ++i) {
        const Vec3<double> p0 = before.positions.col(i) - c0, p1 = after.positions.col(i) - c1;
        REQUIRE(segment_distance(p0, p1, Vec3<double>::Zero()) >= radius + h - cloth.contact_tolerance());
      }
    });
    // The sphere hit the cloth and threw it up (only nodes collide: the cloth can also slip off
    // between them, see drape's contact.md).
    CHECK(state.positions.row(1).maxCoeff() > 0.3);
  }
}

TEST_CASE("contact: direct and iterative solvers give the same contact step", "[contact][solvers]") {
  ClothSpecd spec = free_cloth<double>(7);
  spec.colliders.push_back(Colliderd::sphere(Vec3<double>(0.3, -0.5, 0.3), 0.45));
  spec.colliders.push_back(Colliderd::plane(Vec3<double>(0, -0.7, 0), Vec3<double>(0, 1, 0)));
  const Clothd cloth(spec);
  auto cg = integrator(cloth, IntegratorKind::Implicit, LinearSolverKind::Cg);
  auto ldlt = integrator(cloth, IntegratorKind::Implicit, LinearSolverKind::Ldlt);
  // Draped over the sphere first, then one step from the same state with each solver (whole
  // trajectories part ways: a contact on the edge of letting go can decide either way).
  Stated state = cloth.initial_state();
  for (int k = 0; k < 40; ++k) REQUIRE(cg->step(state).ok());
  Stated a = state, b = state;
  REQUIRE(cg->step(a).ok());
  REQUIRE(ldlt->step(b).ok());
  CHECK(cg->contact_report().contacts > 10);
  CHECK(cg->contact_report().contacts == ldlt->contact_report().contacts);
  CHECK((a.positions - b.positions).cwiseAbs().maxCoeff() <= 1e-8);
  CHECK((a.velocities - b.velocities).cwiseAbs().maxCoeff() <= 1e-6);
}

TEST_CASE("contact: colliders out of reach change nothing; momentum kept without external forces",
          "[contact][momentum]") {
  for (const IntegratorKind kind : {IntegratorKind::Implicit, IntegratorKind::Rk2, IntegratorKind::Symplectic}) {
    INFO(to_string(kind));
    ClothSpecd spec = free_cloth<double>(7);
    spec.gravity = 0;
    const Clothd bare(spec);
    spec.colliders.push_back(Colliderd::sphere(Vec3<double>(0, 50, 0), 1.0));
    spec.colliders.push_back(Colliderd::plane(Vec3<double>(0, -50, 0), Vec3<double>(0, 1, 0)));
    const Clothd with_colliders(spec);
    auto a = integrator(bare, kind);
    auto b = integrator(with_colliders, kind);
    Stated sa = bare.initial_state();
    sa.positions = test::jiggled_positions(bare, 0.2, 3u);
    sa.velocities = test::random_velocities<double>(bare.node_count(), 0.5, 4u);
    Stated sb = sa;
    const Vec3<double> momentum = sa.velocities * bare.grid().masses();
    for (int k = 0; k < 100; ++k) {
      REQUIRE(a->step(sa).ok());
      REQUIRE(b->step(sb).ok());
    }
    CHECK(sa.positions == sb.positions);
    CHECK(b->contact_report().contacts == 0);
    CHECK((sb.velocities * bare.grid().masses() - momentum).norm() <= 1e-7 * momentum.norm());
  }
}

TEST_CASE("contact: same inputs and threads give bit-identical states", "[contact][determinism][mesh_collider]") {
  ClothSpecd spec = free_cloth<double>(17);
  spec.colliders.push_back(Colliderd::sphere(Vec3<double>(0.8, -0.5, 0.8), 0.45).set_friction(0.4, 0.3));
  spec.colliders.push_back(
      Colliderd::mesh(torus_mesh<double>(0.4, 0.1, 48, 16), Vec3<double>(0.8, -0.6, 0.8)).set_friction(0.3, 0.3));
  spec.colliders.push_back(Colliderd::plane(Vec3<double>(0, -0.9, 0), Vec3<double>(0, 1, 0)).set_friction(0.5, 0.5));
  const Clothd cloth(spec);
  for (const int threads : {1, 2}) {
    ImplicitOptions options;
    options.dt = 0.01;
    options.threads = threads;
    Stated s1 = cloth.initial_state(), s2 = s1;
    auto a = make_integrator(cloth, IntegratorKind::Implicit, options);
    auto b = make_integrator(cloth, IntegratorKind::Implicit, options);
    for (int k = 0; k < 80; ++k) {
      REQUIRE(a->step(s1).ok());
      REQUIRE(b->step(s2).ok());
    }
    CHECK(a->contact_report().contacts > 0);
    CHECK(s1.positions == s2.positions);
    CHECK(s1.velocities == s2.velocities);
  }
}

TEST_CASE("contact: bad input names the parameter", "[contact][validation]") {
  ClothSpecd spec = test::small_spec<double>(5, 10.0);  // two corners pinned, at y = 0
  spec.colliders.push_back(Colliderd::sphere(Vec3<double>(0, 0, 0), 0.1));
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("colliders[0]") && Catch::Contains("pinned node 0"));
  // A mesh collider, still or key-framed, over a pinned node at the start.
  spec.colliders = {Colliderd::mesh(box_mesh<double>(Vec3<double>(0.1, 0.1, 0.1)))};
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("colliders[0]") && Catch::Contains("pinned node 0"));
  const ClothMesh<double> box = box_mesh<double>(Vec3<double>(0.1, 0.1, 0.1));
  spec.colliders = {Colliderd::animated_mesh(box, {box.positions, Matrix3X<double>(box.positions.array() + 1.0)}, {0.0, 1.0})};
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("colliders[0]") && Catch::Contains("pinned node 0"));
  spec.colliders.clear();
  spec.contact_thickness = -0.001;
  CHECK_THROWS_WITH(Clothd(spec), Catch::Contains("contact thickness"));
  spec.contact_thickness = 0.005;
  const Clothd cloth(spec);
  ImplicitOptions options;
  options.contact_rounds = 0;
  CHECK_THROWS_WITH(ImplicitEulerd(cloth, options), Catch::Contains("contact_rounds"));
}
