// The mesh generators: the grid as a mesh, the disk and the rectangle with a hole. Valid meshes that
// face +y, areas against the polygons they must cover and the shapes they approximate (second order
// in the edge length), angles and edge lengths, exact boundaries, groups, vertex order, and bad
// arguments named.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "drape/core/grid.hpp"
#include "drape/core/mesh_generators.hpp"

namespace {

const double pi = 3.14159265358979323846;

template <class S>
struct MeshFacts {
  double area = 0;
  double min_angle_degrees = 180;
  double mean_edge = 0;
  bool faces_up = true;
  std::map<std::pair<int, int>, int> edge_uses;  // undirected edge -> faces
};

template <class S>
MeshFacts<S> facts(const drape::ClothMesh<S>& mesh) {
  MeshFacts<S> out;
  for (const auto& t : mesh.triangles) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.positions.col(t[static_cast<std::size_t>(k)]).template cast<double>();
    const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]);
    out.faces_up = out.faces_up && normal.y() > 0;
    out.area += 0.5 * normal.norm();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
      out.min_angle_degrees = std::min(out.min_angle_degrees, std::atan2(u.cross(w).norm(), u.dot(w)) * 180 / pi);
      const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++out.edge_uses[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& e : out.edge_uses)
    out.mean_edge +=
        (mesh.positions.col(e.first.first) - mesh.positions.col(e.first.second)).template cast<double>().norm();
  out.mean_edge /= static_cast<double>(out.edge_uses.size());
  return out;
}

/// The undirected edges that only one face uses.
template <class S>
std::set<std::pair<int, int>> boundary_edges(const MeshFacts<S>& f) {
  std::set<std::pair<int, int>> out;
  for (const auto& e : f.edge_uses)
    if (e.second == 1) out.insert(e.first);
  return out;
}

/// The edges of a closed loop of vertices.
std::set<std::pair<int, int>> loop_edges(const std::vector<int>& loop) {
  std::set<std::pair<int, int>> out;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int a = loop[k], b = loop[(k + 1) % loop.size()];
    out.insert({std::min(a, b), std::max(a, b)});
  }
  return out;
}

int disk_rings(double radius, double edge_length) {
  return std::max(1, static_cast<int>(std::lround(1.12 * radius / edge_length)));
}

/// The area of the regular n-gon inscribed in a circle of radius r.
double inscribed_polygon_area(int n, double r) { return 0.5 * n * r * r * std::sin(2 * pi / n); }

}  // namespace

TEMPLATE_TEST_CASE("grid_mesh has the grid's positions and triangles exactly, marked as a lattice", "[mesh]", float,
                   double) {
  using S = TestType;
  const drape::Grid<S> grid(7, 5, S(0.1), S(1));
  const drape::ClothMesh<S> mesh = drape::grid_mesh(7, 5, S(0.1));
  REQUIRE(mesh.positions.cols() == grid.node_count());
  REQUIRE((mesh.positions.array() == grid.rest_positions().array()).all());
  REQUIRE(mesh.triangles == grid.triangles());
  REQUIRE(mesh.quads.empty());
  REQUIRE(mesh.lattice.has_value());
  REQUIRE(mesh.lattice->nx == 7);
  REQUIRE(mesh.lattice->ny == 5);
  REQUIRE(mesh.lattice->spacing == S(0.1));
  REQUIRE(mesh.validate().empty());
  REQUIRE_THROWS_AS(drape::grid_mesh(1, 5, S(0.1)), drape::InvalidParameter);
}

TEMPLATE_TEST_CASE("disk_mesh: a valid flat mesh facing +y, the boundary on the circle, vertices ring by ring",
                   "[mesh][disk]", float, double) {
  using S = TestType;
  const double radius = 0.5, h = 0.05;
  const int rings = disk_rings(radius, h);  // 11
  const drape::ClothMesh<S> mesh = drape::disk_mesh(S(radius), S(h));
  REQUIRE(mesh.validate().empty());
  REQUIRE(mesh.vertex_count() == 3 * rings * (rings + 1) + 1);
  REQUIRE(mesh.triangles.size() == static_cast<std::size_t>(6 * rings * rings));
  REQUIRE(mesh.positions.row(1).isZero());  // flat at height 0
  const MeshFacts<S> f = facts(mesh);
  REQUIRE(f.faces_up);

  // The boundary: ring K, exactly the mesh's boundary edges, on the circle to round-off, in order of angle.
  REQUIRE(mesh.groups.size() == 1);
  const std::vector<int>& boundary = mesh.groups.at("boundary");
  REQUIRE(boundary.size() == static_cast<std::size_t>(6 * rings));
  REQUIRE(boundary_edges(f) == loop_edges(boundary));
  const double eps = std::numeric_limits<S>::epsilon();
  for (std::size_t j = 0; j < boundary.size(); ++j) {
    const Eigen::Vector3d p = mesh.positions.col(boundary[j]).template cast<double>();
    REQUIRE(std::abs(p.norm() - radius) <= 4 * eps * radius);
    const double angle = 2 * pi * static_cast<double>(j) / static_cast<double>(boundary.size());
    REQUIRE(std::abs(p.x() - radius * std::cos(angle)) <= 4 * eps * radius);
    REQUIRE(std::abs(p.z() - radius * std::sin(angle)) <= 4 * eps * radius);
  }
  // The centre first, then ring by ring: vertex ids 1 + 3k(k-1) ... 3k(k+1) stay near ring k's
  // radius after smoothing, so an edge joins vertices at most two rings' lengths apart.
  REQUIRE(mesh.positions.col(0).norm() == S(0));
  for (int k = 1; k < rings; ++k)
    for (int v = 1 + 3 * k * (k - 1); v <= 3 * k * (k + 1); ++v)
      REQUIRE(std::abs(double(mesh.positions.col(v).norm()) - radius * k / rings) < 0.25 * radius / rings);
  for (const auto& e : f.edge_uses) REQUIRE(e.first.second - e.first.first <= 12 * rings);
}

TEMPLATE_TEST_CASE("disk_mesh covers the inscribed 6K-gon; its area converges to pi r^2 at second order",
                   "[mesh][disk]", float, double) {
  using S = TestType;
  const double radius = 1.0;
  const double tolerance = std::is_same<S, float>::value ? 2e-6 : 1e-12;
  double previous_error = 0;
  int previous_vertices = 0;
  for (double h : {0.1, 0.05, 0.025}) {
    const int rings = disk_rings(radius, h);
    const drape::ClothMesh<S> mesh = drape::disk_mesh(S(radius), S(h));
    const double area = facts(mesh).area, polygon = inscribed_polygon_area(6 * rings, radius);
    REQUIRE(std::abs(area - polygon) <= tolerance * polygon);
    // The polygonal error: pi r^2 - A = pi r^2 (pi^2 / (54 K^2)) (1 + O(K^-2)).
    const double error = pi * radius * radius - area;
    const double predicted = pi * radius * radius * pi * pi / (54.0 * rings * rings);
    REQUIRE(error > 0);
    REQUIRE(std::abs(error / predicted - 1) < 0.01);
    if (previous_error > 0) {
      INFO("h = " << h << ": error ratio " << previous_error / error);
      REQUIRE(previous_error / error > 3.5);  // K doubles (11, 22, 45): the error falls by 4 (4.18)
      REQUIRE(previous_error / error < 4.5);
      const double growth = double(mesh.vertex_count()) / previous_vertices;  // vertices grow as 1 / h^2
      REQUIRE(growth > 3.5);
      REQUIRE(growth < 4.5);
    }
    previous_error = error;
    previous_vertices = mesh.vertex_count();
  }
}

TEST_CASE("disk_mesh: every angle above 43 degrees, edges within 5% of the target on average", "[mesh][disk]") {
  for (double h : {1.0, 0.5, 0.25, 0.12, 0.05, 0.02}) {
    const drape::ClothMesh<double> mesh = drape::disk_mesh(1.0, h);
    const MeshFacts<double> f = facts(mesh);
    INFO("edge_length " << h << ", " << disk_rings(1.0, h) << " rings: smallest angle " << f.min_angle_degrees
                        << ", mean edge " << f.mean_edge);
    REQUIRE(f.min_angle_degrees > 43.0);
    REQUIRE(std::abs(f.mean_edge / h - 1) < (h <= 0.12 ? 0.05 : 0.15));  // K rounded matters when small
  }
}

TEMPLATE_TEST_CASE("disk_mesh with a ring: its vertices on their circle, its sides edges, each zone's rings evenly spaced",
                   "[mesh][disk]", float, double) {
  using S = TestType;
  const double radius = 0.15, h = 0.01, ring_radius = 0.09;
  const int inner = disk_rings(ring_radius, h), rings = inner + disk_rings(radius - ring_radius, h);  // 10 + 7
  const drape::ClothMesh<S> mesh = drape::disk_mesh(S(radius), S(h), S(ring_radius));
  REQUIRE(mesh.validate().empty());
  REQUIRE(mesh.vertex_count() == 3 * rings * (rings + 1) + 1);
  const MeshFacts<S> f = facts(mesh);
  REQUIRE(f.faces_up);
  REQUIRE(boundary_edges(f) == loop_edges(mesh.groups.at("boundary")));
  REQUIRE(std::abs(f.area - inscribed_polygon_area(6 * rings, radius)) <= 2e-6 * f.area);

  // Group "ring": ring `inner`, exactly on its circle in order of angle, and each side an edge.
  REQUIRE(mesh.groups.size() == 2);
  const std::vector<int>& ring = mesh.groups.at("ring");
  REQUIRE(ring.size() == static_cast<std::size_t>(6 * inner));
  const double eps = std::numeric_limits<S>::epsilon();
  for (std::size_t j = 0; j < ring.size(); ++j) {
    REQUIRE(ring[j] == 1 + 3 * inner * (inner - 1) + static_cast<int>(j));
    const Eigen::Vector3d p = mesh.positions.col(ring[j]).template cast<double>();
    const double angle = 2 * pi * static_cast<double>(j) / static_cast<double>(ring.size());
    REQUIRE(std::abs(p.x() - ring_radius * std::cos(angle)) <= 4 * eps * ring_radius);
    REQUIRE(std::abs(p.z() - ring_radius * std::sin(angle)) <= 4 * eps * ring_radius);
  }
  for (const auto& side : loop_edges(ring)) REQUIRE(f.edge_uses.count(side) == 1);

  // The other rings stay near their zone's even spacing after smoothing.
  for (int k = 1; k < rings; ++k) {
    const double spacing = k <= inner ? ring_radius / inner : (radius - ring_radius) / (rings - inner);
    const double at = k <= inner ? ring_radius * k / inner : ring_radius + spacing * (k - inner);
    for (int v = 1 + 3 * k * (k - 1); v <= 3 * k * (k + 1); ++v)
      REQUIRE(std::abs(double(mesh.positions.col(v).norm()) - at) < 0.25 * spacing);
  }

  // Without the ring, no ring of this edge length lies on the circle: the nearest is 2 mm off.
  const drape::ClothMesh<S> plain = drape::disk_mesh(S(radius), S(h));
  double nearest = 1;
  for (drape::Index v = 0; v < plain.positions.cols(); ++v)
    nearest = std::min(nearest, std::abs(double(plain.positions.col(v).norm()) - ring_radius));
  REQUIRE(nearest > 1e-3);
}

TEST_CASE("disk_mesh with a ring: every angle above 40 degrees, edges within 7% of the target on average",
          "[mesh][disk]") {
  for (double h : {0.1, 0.05, 0.02, 0.01})
    for (double fraction : {0.05, 0.3, 0.5, 0.6, 0.77, 0.95}) {
      const double ring_radius = std::clamp(fraction, h, 1 - h);
      const drape::ClothMesh<double> mesh = drape::disk_mesh(1.0, h, ring_radius);
      const MeshFacts<double> f = facts(mesh);
      INFO("edge_length " << h << ", ring at " << ring_radius << ": smallest angle " << f.min_angle_degrees
                          << ", mean edge " << f.mean_edge);
      REQUIRE(mesh.validate().empty());
      REQUIRE(f.min_angle_degrees > 40.0);
      REQUIRE(std::abs(f.mean_edge / h - 1) < 0.07);
    }
}

TEMPLATE_TEST_CASE("rectangle_with_hole_mesh: straight sides, kept corners, the hole on its circle, groups",
                   "[mesh][rectangle]", float, double) {
  using S = TestType;
  const double width = 2.0, height = 1.0, cx = 0.7, cz = 0.45, r = 0.25, h = 0.05;
  const drape::ClothMesh<S> mesh = drape::rectangle_with_hole_mesh(S(width), S(height), {S(cx), S(cz)}, S(r), S(h));
  REQUIRE(mesh.validate().empty());
  REQUIRE(mesh.positions.row(1).isZero());
  const MeshFacts<S> f = facts(mesh);
  REQUIRE(f.faces_up);

  const std::vector<int>&left = mesh.groups.at("left"), &right = mesh.groups.at("right"),
        &bottom = mesh.groups.at("bottom"), &top = mesh.groups.at("top"), &corners = mesh.groups.at("corners"),
        &boundary = mesh.groups.at("boundary"), &hole = mesh.groups.at("hole");
  REQUIRE(mesh.groups.size() == 7);
  // Corners kept, in order.
  const S corner_x[] = {S(0), S(width), S(width), S(0)}, corner_z[] = {S(0), S(0), S(height), S(height)};
  REQUIRE(corners.size() == 4);
  for (int c = 0; c < 4; ++c) {
    REQUIRE(mesh.positions(0, corners[static_cast<std::size_t>(c)]) == corner_x[c]);
    REQUIRE(mesh.positions(2, corners[static_cast<std::size_t>(c)]) == corner_z[c]);
  }
  // Each side holds exactly the vertices on its line, in order, from corner to corner; its
  // coordinate across is exact (the side is straight).
  const auto check_side = [&](const std::vector<int>& side, int across, S value, int along) {
    int on_line = 0;
    for (int v = 0; v < mesh.vertex_count(); ++v) on_line += mesh.positions(across, v) == value;
    REQUIRE(static_cast<int>(side.size()) == on_line);
    REQUIRE(side.size() >= 5);
    for (std::size_t k = 1; k < side.size(); ++k)
      REQUIRE(mesh.positions(along, side[k]) > mesh.positions(along, side[k - 1]));
  };
  check_side(left, 0, S(0), 2);
  check_side(right, 0, S(width), 2);
  check_side(bottom, 2, S(0), 0);
  check_side(top, 2, S(height), 0);
  REQUIRE(left.front() == corners[0]);
  REQUIRE(left.back() == corners[3]);
  REQUIRE(bottom.back() == corners[1]);
  REQUIRE(top.back() == corners[2]);
  REQUIRE(boundary.size() == left.size() + right.size() + bottom.size() + top.size() - 4);
  REQUIRE(boundary.front() == corners[0]);

  // The hole: a regular N-gon on its circle, in order of angle.
  const int n = std::max(6, static_cast<int>(std::lround(2 * pi * r / h)));
  REQUIRE(hole.size() == static_cast<std::size_t>(n));
  const double eps = std::numeric_limits<S>::epsilon();
  for (std::size_t j = 0; j < hole.size(); ++j) {
    const double angle = 2 * pi * static_cast<double>(j) / n;
    const Eigen::Vector2d p(double(mesh.positions(0, hole[j])), double(mesh.positions(2, hole[j])));
    REQUIRE(std::abs((p - Eigen::Vector2d(cx, cz)).norm() - r) <= 8 * eps);
    REQUIRE(std::abs(p.x() - (cx + r * std::cos(angle))) <= 8 * eps);
    REQUIRE(std::abs(p.y() - (cz + r * std::sin(angle))) <= 8 * eps);
  }
  // The mesh's boundary is the rectangle's loop and the hole's loop, nothing else.
  std::set<std::pair<int, int>> expected = loop_edges(boundary);
  const std::set<std::pair<int, int>> around_hole = loop_edges(hole);
  expected.insert(around_hole.begin(), around_hole.end());
  REQUIRE(boundary_edges(f) == expected);
}

TEMPLATE_TEST_CASE("rectangle_with_hole_mesh: area w h minus the inscribed N-gon, converging at second order",
                   "[mesh][rectangle]", float, double) {
  using S = TestType;
  const double width = 1.6, height = 1.2, r = 0.3;
  const double tolerance = std::is_same<S, float>::value ? 2e-6 : 1e-12;
  double previous_error = 0;
  int previous_vertices = 0;
  for (double h : {0.08, 0.04, 0.02}) {
    const drape::ClothMesh<S> mesh = drape::rectangle_with_hole_mesh(S(width), S(height), {S(0.8), S(0.6)}, S(r), S(h));
    const int n = static_cast<int>(mesh.groups.at("hole").size());
    REQUIRE(n == std::lround(2 * pi * r / h));
    const double area = facts(mesh).area, exact_polygon = width * height - inscribed_polygon_area(n, r);
    REQUIRE(std::abs(area - exact_polygon) <= tolerance * width * height);
    // The hole's polygonal error: A - (w h - pi r^2) = pi r^2 (2 pi / N)^2 / 6 (1 + O(N^-2)).
    const double error = area - (width * height - pi * r * r);
    const double predicted = pi * r * r * std::pow(2 * pi / n, 2) / 6;
    REQUIRE(std::abs(error / predicted - 1) < 0.02);
    if (previous_error > 0) {
      INFO("h = " << h << ": error ratio " << previous_error / error);
      REQUIRE(previous_error / error > 3.5);  // N = 24, 47, 94: the error falls by about 4
      REQUIRE(previous_error / error < 4.5);
      const double growth = double(mesh.vertex_count()) / previous_vertices;
      REQUIRE(growth > 3.5);
      REQUIRE(growth < 4.5);
    }
    previous_error = error;
    previous_vertices = mesh.vertex_count();
  }
}

TEST_CASE("rectangle_with_hole_mesh: every angle above 30 degrees, edges within 15% of the target on average",
          "[mesh][rectangle]") {
  struct Case {
    double width, height, cx, cz, r, h;
  };
  // Holes in the middle and one or two edges from a side, large and smallest (six edges), coarse and fine.
  const Case cases[] = {{2.0, 1.0, 0.7, 0.45, 0.25, 0.05}, {1.0, 1.0, 0.5, 0.5, 0.1, 0.1},
                        {1.0, 0.7, 0.35, 0.31, 0.2, 0.1},  {3.0, 2.0, 0.61, 1.0, 0.5, 0.1},
                        {1.3, 1.1, 0.979, 0.6, 0.3, 0.02}, {0.9, 2.2, 0.45, 1.9, 0.2, 0.03},
                        {1.2, 0.8, 0.5, 0.4, 0.25, 0.0377}};
  for (const Case& c : cases) {
    const drape::ClothMesh<double> mesh = drape::rectangle_with_hole_mesh(c.width, c.height, {c.cx, c.cz}, c.r, c.h);
    const MeshFacts<double> f = facts(mesh);
    INFO(c.width << " x " << c.height << ", hole " << c.r << " at (" << c.cx << ", " << c.cz << "), edge " << c.h
                 << ": smallest angle " << f.min_angle_degrees << ", mean edge " << f.mean_edge);
    REQUIRE(mesh.validate().empty());
    REQUIRE(f.min_angle_degrees > 35.0);  // 35.8 to 38.4 here; 32 at worst over 1500 random rectangles
    REQUIRE(std::abs(f.mean_edge / c.h - 1) < 0.15);
  }
}

TEST_CASE("rectangle_with_hole_mesh numbers its vertices along a space-filling curve", "[mesh][rectangle]") {
  // Sizes that float holds exactly, so both meshes start from the same numbers.
  const drape::ClothMesh<double> mesh = drape::rectangle_with_hole_mesh(2.0, 1.0, {0.75, 0.5}, 0.25, 0.03125);
  std::vector<int> gaps;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      gaps.push_back(std::abs(t[static_cast<std::size_t>(k)] - t[static_cast<std::size_t>((k + 1) % 3)]));
  std::sort(gaps.begin(), gaps.end());
  // Half the edges join vertices at most 8 ids apart (in rows, an edge would span about a row: 64).
  REQUIRE(gaps[gaps.size() / 2] <= 8);
  REQUIRE(gaps[gaps.size() * 3 / 4] <= 40);
  // The same mesh in float and double: connectivity and groups are made in double.
  const drape::ClothMesh<float> single = drape::rectangle_with_hole_mesh(2.0f, 1.0f, {0.75f, 0.5f}, 0.25f, 0.03125f);
  REQUIRE(single.triangles == mesh.triangles);
  REQUIRE(single.groups == mesh.groups);
}

TEMPLATE_TEST_CASE("the generators reject bad arguments by name", "[mesh][validation]", float, double) {
  using S = TestType;
  using Catch::Matchers::Contains;
  const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(0), S(0.1)), Contains("'radius'") && Contains("> 0"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(nan, S(0.1)), Contains("'radius'"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), -S(0.1)), Contains("'edge_length'") && Contains("> 0"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), inf), Contains("'edge_length'"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(1.5)), Contains("'edge_length'") && Contains("<= radius"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(1e-4)), Contains("'radius / edge_length'"));
  REQUIRE_NOTHROW(drape::disk_mesh(S(1), S(1)));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(0.1), -S(0.5)), Contains("'ring_radius'") && Contains("0 (no ring)"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(0.1), nan), Contains("'ring_radius'"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(0.1), S(0.09)),
                      Contains("'ring_radius'") && Contains("radius - edge_length"));
  REQUIRE_THROWS_WITH(drape::disk_mesh(S(1), S(0.1), S(0.91)), Contains("'ring_radius'"));
  REQUIRE_NOTHROW(drape::disk_mesh(S(1), S(0.1), S(0.1)));
  REQUIRE_NOTHROW(drape::disk_mesh(S(1), S(0.1), S(0.9)));

  using V2 = Eigen::Matrix<S, 2, 1>;
  const V2 centre(S(1), S(0.5));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(0), S(1), centre, S(0.2), S(0.05)), Contains("'width'"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), nan, centre, S(0.2), S(0.05)), Contains("'height'"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), S(1), centre, -S(0.2), S(0.05)), Contains("'hole_radius'"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), S(1), centre, S(0.2), S(0)), Contains("'edge_length'"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), S(1), V2(nan, S(0.5)), S(0.2), S(0.05)),
                      Contains("'hole_centre'") && Contains("finite"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), S(1), centre, S(0.2), S(0.25)),
                      Contains("'edge_length'") && Contains("<= hole_radius"));
  // The hole must stay an edge length from every side: just inside that and just outside, per side.
  const S r = S(0.2), h = S(0.05), near = S(0.26);
  for (const V2& inside : {V2(near, S(0.5)), V2(S(2) - near, S(0.5)), V2(S(1), near), V2(S(1), S(1) - near)})
    REQUIRE(drape::rectangle_with_hole_mesh(S(2), S(1), inside, r, h).validate().empty());
  const S too_near = S(0.24);
  for (const V2& outside :
       {V2(too_near, S(0.5)), V2(S(2) - too_near, S(0.5)), V2(S(1), too_near), V2(S(1), S(1) - too_near)})
    REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(2), S(1), outside, r, h),
                        Contains("'hole_centre'") && Contains("from every side"));
  REQUIRE_THROWS_WITH(drape::rectangle_with_hole_mesh(S(100), S(100), V2(S(50), S(50)), S(1), S(0.01)),
                      Contains("vertices"));
}
