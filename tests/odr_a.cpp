#include <catch2/catch.hpp>

#include "drape/drape.hpp"

int odr_b_node_count();

TEST_CASE("every public header links from two translation units", "[odr]") {
  drape::Clothd cloth{drape::ClothSpecd{}};
  REQUIRE(cloth.node_count() == odr_b_node_count());
}
