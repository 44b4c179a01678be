#include <catch2/catch.hpp>

#include <limits>

#include "drape/integrators/rk2.hpp"
#include "drape/model/cloth.hpp"

using namespace drape;
using Catch::Matchers::Contains;

namespace {
template <class F>
void require_rejects(F&& build, const std::string& parameter, const std::string& allowed) {
  REQUIRE_THROWS_AS(build(), std::invalid_argument);
  REQUIRE_THROWS_WITH(build(), Contains("'" + parameter + "'") && Contains(allowed));
}
}  // namespace

TEMPLATE_TEST_CASE("bad scene parameters are rejected with the parameter's name and range", "[validation]", float,
                   double) {
  using S = TestType;
  const S nan = std::numeric_limits<S>::quiet_NaN();
  const S inf = std::numeric_limits<S>::infinity();
  const auto with = [](auto change) {
    return [change] {
      ClothSpec<S> spec;
      change(spec);
      return Cloth<S>(spec);
    };
  };
  require_rejects(with([](auto& s) { s.nx = 1; }), "nx", ">= 2");
  require_rejects(with([](auto& s) { s.ny = 0; }), "ny", ">= 2");
  require_rejects(with([](auto& s) { s.spacing = 0; }), "spacing", "> 0");
  require_rejects(with([&](auto& s) { s.spacing = nan; }), "spacing", "finite");
  require_rejects(with([](auto& s) { s.node_mass = -1; }), "node_mass", "> 0");
  require_rejects(with([&](auto& s) { s.node_mass = inf; }), "node_mass", "finite");
  // The time step belongs to the integrator (integrators/integrator.hpp).
  const Cloth<S> cloth{ClothSpec<S>{}};
  require_rejects([&] { return Rk2<S>(cloth, {0.0}); }, "dt", "> 0");
  require_rejects([&] { return Rk2<S>(cloth, {double(nan)}); }, "dt", "finite");
  require_rejects(with([](auto& s) { s.gravity = -10; }), "gravity", ">= 0");
  require_rejects(with([](auto& s) { s.springs.structural.stiffness = -1; }), "structural.stiffness", ">= 0");
  require_rejects(with([&](auto& s) { s.springs.shear.damping = nan; }), "shear.damping", "finite");
  require_rejects(with([&](auto& s) { s.springs.bend.stiffness = inf; }), "bend.stiffness", "finite");
  require_rejects(with([](auto& s) { s.springs.bend.damping = -0.5; }), "bend.damping", ">= 0");
  require_rejects(with([](auto& s) { s.pinned_nodes = std::vector<int>{0, 33 * 33}; }), "pinned node", "[0, 1088]");
  require_rejects(with([](auto& s) { s.pinned_nodes = std::vector<int>{-1}; }), "pinned node", "[0, 1088]");
  require_rejects(with([](auto& s) { s.boundary = static_cast<BoundaryCondition>(3); }), "boundary_condition",
                  "1 (one corner) or 2 (two corners)");
  REQUIRE_NOTHROW(Cloth<S>(ClothSpec<S>{}));
}

TEST_CASE("a step with a bad dt or a state of the wrong size is rejected", "[validation]") {
  const Cloth<double> cloth{ClothSpec<double>{}};
  Rk2<double> rk2(cloth);
  State<double> state = cloth.initial_state();
  REQUIRE_THROWS_WITH(rk2.set_dt(0.0), Contains("'dt'"));
  REQUIRE_THROWS_WITH(rk2.set_dt(-1e-3), Contains("'dt'"));
  REQUIRE_THROWS_WITH(rk2.set_dt(std::numeric_limits<double>::infinity()), Contains("'dt'"));
  ClothSpec<double> small;
  small.nx = small.ny = 5;
  State<double> wrong = Cloth<double>(small).initial_state();
  REQUIRE_THROWS_WITH(rk2.step(wrong), Contains("'state'"));
}

TEST_CASE("boundary presets pin corner (0,0), or (0,0) and (nx-1,0)", "[validation]") {
  ClothSpec<double> spec;
  spec.boundary = BoundaryCondition::OneCorner;
  REQUIRE(Cloth<double>(spec).pins().nodes() == std::vector<int>{0});
  spec.boundary = BoundaryCondition::TwoCorners;
  REQUIRE(Cloth<double>(spec).pins().nodes() == std::vector<int>{0, 32});
  spec.pinned_nodes = std::vector<int>{5, 3, 5};
  REQUIRE(Cloth<double>(spec).pins().nodes() == std::vector<int>{3, 5});
}
