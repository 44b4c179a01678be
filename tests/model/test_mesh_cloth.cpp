// Cloths made of any triangle mesh: the mesh's checks, its springs, masses and pins, the general
// force pass, the grid through the mesh path, and mesh cloths in every integrator with colliders.

#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <vector>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/mesh_generators.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/force_assembler.hpp"
#include "model/mesh_helpers.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// Two triangles sharing edge (1, 2): a unit square in the x-z plane.
ClothMesh<double> two_triangles() {
  ClothMesh<double> m;
  m.positions.resize(3, 4);
  m.positions << 0, 1, 0, 1, 0, 0, 0, 0, 0, 0, 1, 1;
  m.triangles = {{0, 2, 1}, {1, 2, 3}};
  return m;
}

std::string error_of(const ClothMesh<double>& m) {
  try {
    m.validate("mesh");
  } catch (const InvalidParameter& e) {
    return e.what();
  }
  return "no error";
}

template <class S>
ClothSpec<S> mesh_spec(ClothMesh<S> mesh, S gravity) {
  ClothSpec<S> spec;
  spec.mesh = std::move(mesh);
  spec.gravity = gravity;
  spec.springs = {{S(300), S(2)}, {S(200), S(1)}, {S(50), S(0.5)}};
  return spec;
}

/// The springs' forces summed spring by spring (spring_force), plus gravity.
template <class S>
Matrix3X<S> reference_forces(const Cloth<S>& cloth, const Matrix3X<S>& x, const Matrix3X<S>& v) {
  Matrix3X<S> f = cloth.gravity() * cloth.masses().transpose();
  const SpringSet<S>& sp = cloth.springs();
  for (int s = 0; s < sp.size(); ++s) {
    const int a = sp.a()[std::size_t(s)], b = sp.b()[std::size_t(s)];
    const Vec3<S> fa = spring_force<S>(x.col(a), x.col(b), v.col(a), v.col(b), sp.rest_length()[std::size_t(s)],
                                       sp.stiffness()[std::size_t(s)], sp.damping()[std::size_t(s)]);
    f.col(a) += fa;
    f.col(b) -= fa;
  }
  return f;
}

}  // namespace

TEST_CASE("a mesh no cloth can be made of is rejected, naming the element", "[mesh]") {
  CHECK(error_of(two_triangles()) == "no error");
  ClothMesh<double> m = two_triangles();
  m.triangles.clear();
  CHECK_THAT(error_of(m), Catch::Contains("'mesh'") && Catch::Contains("at least one face"));
  m = two_triangles();
  m.triangles[1][2] = 4;
  CHECK_THAT(error_of(m), Catch::Contains("'mesh.triangles[1]' = vertex id 4") && Catch::Contains("[0, 3]"));
  m = two_triangles();
  m.positions(1, 2) = std::nan("");
  CHECK_THAT(error_of(m), Catch::Contains("'mesh.positions[2]'"));
  m = two_triangles();
  m.positions.col(3) = m.positions.col(1) * 2 - m.positions.col(2);  // on the line through 1 and 2
  CHECK_THAT(error_of(m), Catch::Contains("'mesh.triangles[1]'") && Catch::Contains("degenerate"));
  m = two_triangles();
  m.triangles[1] = {2, 1, 3};  // runs edge 2 -> 1 as triangle 0 runs 2 -> 1
  CHECK_THAT(error_of(m), Catch::Contains("'mesh.triangles[1]'") && Catch::Contains("inconsistent orientation"));
  m = two_triangles();
  m.positions.conservativeResize(3, 6);
  m.positions.col(4) = Vec3<double>(2, 0, 0);
  m.positions.col(5) = Vec3<double>(3, 0, 0);
  m.triangles.push_back({1, 2, 4});  // a third face on edge (1, 2)
  CHECK_THAT(error_of(m), Catch::Contains("non-manifold"));
  m = two_triangles();
  m.rest_uv.resize(2, 3);
  m.rest_uv.setZero();
  CHECK_THAT(error_of(m), Catch::Contains("'mesh.rest_uv'") && Catch::Contains("one per vertex (4)"));
  m = two_triangles();
  m.positions.conservativeResize(3, 5);
  m.positions.col(4) = Vec3<double>(5, 0, 5);
  const std::vector<std::string> warnings = m.validate();
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("1 vertices belong to no face") && Catch::Contains("vertex 4"));
}

TEST_CASE("mesh springs: faces' edges, quad diagonals and hinges, each pair once, colours without shared nodes",
          "[mesh]") {
  ClothSpec<double> spec = mesh_spec(two_triangles(), 0.0);
  spec.pinned_nodes = std::vector<int>{};
  const Cloth<double> two(spec);
  CHECK(two.springs().count(SpringCategory::Structural) == 5);
  CHECK(two.springs().count(SpringCategory::Shear) == 0);
  CHECK(two.springs().count(SpringCategory::Bend) == 1);  // across edge (1, 2): nodes 0 and 3
  const auto& sp = two.springs();
  for (int s = 0; s < sp.size(); ++s)
    if (sp.category()[std::size_t(s)] == SpringCategory::Bend) {
      CHECK(sp.a()[std::size_t(s)] == 0);
      CHECK(sp.b()[std::size_t(s)] == 3);
      CHECK(sp.rest_length()[std::size_t(s)] == Approx(std::sqrt(2.0)));
    }

  ClothMesh<double> quad = two_triangles();
  quad.triangles.clear();
  quad.quads = {{0, 2, 3, 1}};
  const Cloth<double> one_quad(mesh_spec(quad, 0.0));
  CHECK(one_quad.springs().count(SpringCategory::Structural) == 4);
  CHECK(one_quad.springs().count(SpringCategory::Shear) == 2);
  CHECK(one_quad.springs().count(SpringCategory::Bend) == 0);  // its hinge joins a diagonal's nodes
  CHECK(one_quad.triangles().size() == 2);

  const Cloth<double> patch(mesh_spec(test::irregular_patch<double>(9, 0.1, 5), 0.0));
  const SpringSet<double>& ps = patch.springs();
  std::set<std::pair<int, int>> pairs;
  for (int s = 0; s < ps.size(); ++s) pairs.insert({ps.a()[std::size_t(s)], ps.b()[std::size_t(s)]});
  CHECK(pairs.size() == std::size_t(ps.size()));
  // Euler: a disk-like patch of V vertices and F triangles has V + F - 1 edges and F... interior edges.
  const int v = 81, f = 128, edges = v + f - 1;
  CHECK(ps.count(SpringCategory::Structural) == edges);
  std::set<std::pair<int, int>> bend_pairs;  // one bend spring per pair of opposite vertices not yet joined
  const ClothMesh<double>& mesh = patch.mesh();
  for (const Hinge& h : mesh.hinges()) bend_pairs.insert({std::min(h.c, h.d), std::max(h.c, h.d)});
  CHECK(mesh.hinges().size() == std::size_t(edges - 4 * 8));  // interior edges
  CHECK(ps.count(SpringCategory::Bend) == int(bend_pairs.size()));
  CHECK(ps.count(SpringCategory::Bend) > 150);
  for (int c = 0; c < ps.colour_count(); ++c) {
    std::set<int> nodes;
    for (int s = ps.colour_begin()[std::size_t(c)]; s < ps.colour_begin()[std::size_t(c) + 1]; ++s) {
      REQUIRE(nodes.insert(ps.a()[std::size_t(s)]).second);
      REQUIRE(nodes.insert(ps.b()[std::size_t(s)]).second);
    }
  }
  CHECK(ps.colour_begin().back() == ps.size());
}

TEST_CASE("a 2D pattern sets the rest lengths; an areal density sets the masses", "[mesh]") {
  ClothMesh<double> m = two_triangles();
  m.positions *= 3.0;  // laid out three times larger than its pattern
  m.rest_uv.resize(2, 4);
  m.rest_uv << 0, 1, 0, 1, 0, 0, 1, 1;
  ClothSpec<double> spec = mesh_spec(m, 10.0);
  spec.areal_density = 0.2;
  const Cloth<double> cloth(spec);
  const auto& sp = cloth.springs();
  for (int s = 0; s < sp.size(); ++s) {
    const double expected = sp.category()[std::size_t(s)] == SpringCategory::Bend ||
                                    (sp.a()[std::size_t(s)] == 1 && sp.b()[std::size_t(s)] == 2)
                                ? std::sqrt(2.0)
                                : 1.0;
    CHECK(sp.rest_length()[std::size_t(s)] == Approx(expected));
  }
  CHECK(cloth.masses().sum() == Approx(0.2));  // 1 m^2 of pattern
  CHECK(cloth.masses()[1] == Approx(0.2 / 3));  // in both triangles: a third of each
  CHECK(cloth.masses()[0] == Approx(0.2 / 6));
  CHECK(cloth.start_positions() == m.positions);
  CHECK(cloth.pins().count() == 0);
  CHECK(!cloth.is_grid());
  CHECK_THROWS_AS(cloth.grid(), std::logic_error);
}

TEST_CASE("nodes in no face are held; pins by id", "[mesh]") {
  ClothMesh<double> m = two_triangles();
  m.positions.conservativeResize(3, 5);
  m.positions.col(4) = Vec3<double>(5, 0, 5);
  ClothSpec<double> spec = mesh_spec(m, 10.0);
  spec.pinned_nodes = std::vector<int>{0};
  const Cloth<double> cloth(spec);
  CHECK(cloth.pins().nodes() == std::vector<int>{0, 4});
  CHECK(cloth.warnings().size() == 1);
  spec.pinned_nodes = std::vector<int>{5};
  CHECK_THROWS_WITH(Cloth<double>(spec), Catch::Contains("'pinned node' = 5") && Catch::Contains("[0, 4]"));
}

TEMPLATE_TEST_CASE("on an irregular mesh the force pass equals the per-spring sum, the same bits on 1 and 2 threads",
                   "[mesh]", float, double) {
  using S = TestType;
  // Large enough that two threads each take a share of the springs and the node blocks.
  const Cloth<S> cloth(mesh_spec(test::irregular_patch<S>(40, S(0.05), 3), S(10)));
  REQUIRE(!cloth.is_grid());
  Matrix3X<S> x = cloth.start_positions();
  const Matrix3X<S> jiggle = test::random_velocities<S>(cloth.node_count(), S(0.01), 8);
  x += jiggle;
  const Matrix3X<S> v = test::random_velocities<S>(cloth.node_count(), S(2), 9);
  const Matrix3X<S> expected = reference_forces(cloth, x, v);
  Matrix3X<S> f1(3, cloth.node_count()), f2(3, cloth.node_count());
  ForceAssembler<S>(cloth, 1).force(x, v, 0, f1);
  ForceAssembler<S>(cloth, 2).force(x, v, 0, f2);
  const S tol = std::is_same<S, float>::value ? S(1e-5) : S(1e-13);
  REQUIRE((f1 - expected).cwiseAbs().maxCoeff() <= tol * expected.cwiseAbs().maxCoeff());
  REQUIRE((f1.array() == f2.array()).all());
  // Internal forces only: total momentum kept (they sum to zero).
  const Matrix3X<S> internal = f1 - cloth.gravity() * cloth.masses().transpose();
  REQUIRE(internal.rowwise().sum().norm() <= S(100) * tol * internal.norm());
}

TEST_CASE("a grid through the mesh path steps bit for bit as the grid", "[mesh]") {
  ClothSpec<double> grid_spec;
  grid_spec.nx = 9;
  grid_spec.ny = 7;
  grid_spec.spacing = 0.1;
  ClothSpec<double> via_mesh = grid_spec;
  via_mesh.mesh = grid_mesh<double>(9, 7, 0.1);
  const Cloth<double> grid(grid_spec), meshed(via_mesh);
  REQUIRE(meshed.is_grid());
  REQUIRE(meshed.pins().nodes() == grid.pins().nodes());
  for (IntegratorKind kind : {IntegratorKind::Rk2, IntegratorKind::Symplectic, IntegratorKind::Implicit}) {
    ImplicitOptions options;
    options.dt = kind == IntegratorKind::Implicit ? 1.0 / 60 : 5e-4;
    auto a = make_integrator(grid, kind, options);
    auto b = make_integrator(meshed, kind, options);
    State<double> sa = grid.initial_state(), sb = meshed.initial_state();
    for (int step = 0; step < 40; ++step) {
      REQUIRE(a->step(sa).ok());
      REQUIRE(b->step(sb).ok());
    }
    INFO(int(kind));
    REQUIRE((sa.positions.array() == sb.positions.array()).all());
    REQUIRE((sa.velocities.array() == sb.velocities.array()).all());
  }
}

TEMPLATE_TEST_CASE("an irregular cloth dropped on a sphere stays outside it in every integrator", "[mesh]", float,
                   double) {
  using S = TestType;
  ClothMesh<S> patch = test::irregular_patch<S>(12, S(0.05), 11);
  ClothSpec<S> spec = mesh_spec(patch, S(10));
  spec.springs = {{S(200), S(0.2)}, {S(50), S(0.1)}, {S(10), S(0.02)}};
  spec.areal_density = S(0.2);
  spec.placement.position = Vec3<S>(S(-0.275), S(0.05), S(-0.275));  // centred over the sphere
  const Collider<S> sphere = Collider<S>::sphere(Vec3<S>(0, S(-0.2), 0), S(0.2));
  spec.colliders = {sphere};
  const Cloth<S> cloth(spec);
  for (IntegratorKind kind : {IntegratorKind::Rk2, IntegratorKind::Symplectic, IntegratorKind::Implicit}) {
    ImplicitOptions options;
    options.dt = kind == IntegratorKind::Implicit ? 1.0 / 200 : 2e-4;
    if (std::is_same<S, float>::value) options.tolerance = 1e-5;  // what float CG reaches
    const int steps = int(0.4 / options.dt);
    auto integrator = make_integrator(cloth, kind, options);
    State<S> s = cloth.initial_state();
    S deepest = S(1);
    for (int step = 0; step < steps; ++step) {
      const StepStatus status = integrator->step(s);
      INFO("integrator " << int(kind) << " step " << step << ": " << to_string(status.error) << ", residual " << status.residual << " after " << status.iterations);
      REQUIRE(status.ok());
      for (int i = 0; i < cloth.node_count(); ++i)
        deepest = std::min(deepest, sphere.query(s.positions.col(i), s.time).distance);
    }
    INFO(int(kind));
    // Resting on the sphere (the middle is in contact), never deeper than the tolerance.
    CHECK(deepest >= cloth.contact_thickness() - cloth.contact_tolerance() - S(1e-5));
    CHECK(deepest <= cloth.contact_thickness() + S(0.01));
  }
}
