#include <catch2/catch.hpp>

#include <set>
#include <utility>

#include "drape/core/spring_set.hpp"

using namespace drape;

TEMPLATE_TEST_CASE("the default 33 x 33 cloth has 2112 structural, 2048 shear, 2046 bend springs", "[springs]", float,
                   double) {
  const Grid<TestType> grid(33, 33, TestType(0.1), TestType(0.03));
  const SpringSet<TestType> springs(grid, {{1, 2}, {3, 4}, {5, 6}});
  REQUIRE(springs.count(SpringCategory::Structural) == 2112);
  REQUIRE(springs.count(SpringCategory::Shear) == 2048);
  REQUIRE(springs.count(SpringCategory::Bend) == 2046);
  REQUIRE(springs.size() == 2112 + 2048 + 2046);
}

TEST_CASE("springs join the right neighbours with their own constants and rest lengths", "[springs]") {
  const Grid<double> grid(6, 5, 0.1, 0.03);
  const SpringSet<double> springs(grid, {{10, 1}, {20, 2}, {30, 3}});
  const auto x = grid.rest_positions();
  std::set<std::pair<int, int>> seen;
  for (int s = 0; s < springs.size(); ++s) {
    const int a = springs.a()[s], b = springs.b()[s];
    const auto ca = grid.coord(a), cb = grid.coord(b);
    const int di = std::abs(ca.i - cb.i), dj = std::abs(ca.j - cb.j);
    const double length = (x.col(b) - x.col(a)).norm();
    REQUIRE(springs.rest_length()[s] == Approx(length));
    switch (springs.category()[s]) {
      case SpringCategory::Structural:
        REQUIRE(di + dj == 1);
        REQUIRE(springs.stiffness()[s] == 10);
        REQUIRE(springs.damping()[s] == 1);
        break;
      case SpringCategory::Shear:
        REQUIRE((di == 1 && dj == 1));
        REQUIRE(springs.stiffness()[s] == 20);
        REQUIRE(springs.damping()[s] == 2);
        break;
      case SpringCategory::Bend:
        REQUIRE(((di == 2 && dj == 0) || (di == 0 && dj == 2)));
        REQUIRE(springs.stiffness()[s] == 30);
        REQUIRE(springs.damping()[s] == 3);
        break;
    }
    REQUIRE(seen.insert({std::min(a, b), std::max(a, b)}).second);  // no duplicates
  }
}

TEST_CASE("no two springs of one colour share a node", "[springs]") {
  for (int n : {2, 3, 4, 7, 33}) {
    const Grid<double> grid(n, n + 1, 0.1, 0.03);
    const SpringSet<double> springs(grid, {{1, 0}, {1, 0}, {1, 0}});
    REQUIRE(springs.colour_begin().back() == springs.size());
    for (int c = 0; c < springs.colour_count(); ++c) {
      std::set<int> nodes;
      for (int s = springs.colour_begin()[c]; s < springs.colour_begin()[c + 1]; ++s) {
        REQUIRE(nodes.insert(springs.a()[s]).second);
        REQUIRE(nodes.insert(springs.b()[s]).second);
      }
    }
  }
}
