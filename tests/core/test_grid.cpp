#include <catch2/catch.hpp>

#include <limits>
#include <set>

#include <Eigen/Geometry>

#include "drape/core/grid.hpp"

using drape::Grid;

TEMPLATE_TEST_CASE("grid numbers nodes row by row and lays them flat and horizontal", "[grid]", float, double) {
  const Grid<TestType> grid(4, 3, TestType(0.5), TestType(0.25));
  REQUIRE(grid.node_count() == 12);
  REQUIRE(grid.node(0, 0) == 0);
  REQUIRE(grid.node(3, 0) == 3);
  REQUIRE(grid.node(0, 1) == 4);
  REQUIRE(grid.node(3, 2) == 11);
  for (int id = 0; id < grid.node_count(); ++id) REQUIRE(grid.node(grid.coord(id).i, grid.coord(id).j) == id);

  const auto x = grid.rest_positions();
  REQUIRE(x.cols() == 12);
  REQUIRE(x.row(1).isZero());  // horizontal: y = 0 everywhere
  REQUIRE(x(0, grid.node(3, 2)) == TestType(1.5));
  REQUIRE(x(2, grid.node(3, 2)) == TestType(1.0));
  REQUIRE(grid.total_mass() == Approx(3.0));
}

TEST_CASE("the default grid is 3.2 m wide", "[grid]") {
  const Grid<double> grid(33, 33, 0.1, 0.03);
  const auto x = grid.rest_positions();
  REQUIRE((x.col(grid.node(32, 0)) - x.col(grid.node(0, 0))).norm() == Approx(3.2));
  REQUIRE(grid.total_mass() == Approx(32.67));
}

TEST_CASE("triangles cover every cell twice, face +y and use every node", "[grid]") {
  const Grid<double> grid(5, 4, 0.1, 0.03);
  const auto tris = grid.triangles();
  REQUIRE(tris.size() == 2u * 4u * 3u);
  const auto x = grid.rest_positions();
  std::set<int> used;
  double area = 0;
  for (const auto& t : tris) {
    const Eigen::Vector3d n = (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0]));
    REQUIRE(n.y() > 0);  // counter-clockwise seen from above
    area += 0.5 * n.norm();
    used.insert(t.begin(), t.end());
  }
  REQUIRE(area == Approx(0.4 * 0.3));
  REQUIRE(used.size() == 20u);
}

TEMPLATE_TEST_CASE("a grid rejects bad sizes, spacing and mass by name", "[grid][validation]", float, double) {
  using S = TestType;
  using Catch::Matchers::Contains;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  REQUIRE_THROWS_WITH(Grid<S>(1, 4, S(0.1), S(0.03)), Contains("'nx'") && Contains(">= 2"));
  REQUIRE_THROWS_WITH(Grid<S>(4, 1, S(0.1), S(0.03)), Contains("'ny'"));
  REQUIRE_THROWS_WITH(Grid<S>(4, 4, S(0), S(0.03)), Contains("'spacing'") && Contains("> 0"));
  REQUIRE_THROWS_WITH(Grid<S>(4, 4, nan, S(0.03)), Contains("'spacing'"));
  REQUIRE_THROWS_WITH(Grid<S>(4, 4, S(0.1), nan), Contains("'node_mass'") && Contains("finite"));
  REQUIRE_THROWS_WITH(Grid<S>(4, 4, S(0.1), S(-1)), Contains("'node_mass'"));
  REQUIRE_THROWS_WITH(Grid<S>(20000, 20000, S(0.1), S(0.03)), Contains("'nx * ny'"));
}
