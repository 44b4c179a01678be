// One parse and one to_string for every option enum (core/enum_names.hpp): names round-trip, and a
// bad name is rejected naming the option and listing every name.
#include <catch2/catch.hpp>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/integrator.hpp"

using namespace drape;
using Catch::Matchers::Contains;

namespace {
template <class Enum>
void require_round_trip(const std::vector<std::string>& expected_names) {
  REQUIRE(names<Enum>() == expected_names);
  for (const EnumName<Enum>& e : EnumNames<Enum>::values) {
    REQUIRE(std::string(to_string(e.value)) == e.name);
    REQUIRE(parse<Enum>(e.name) == e.value);
  }
  Enum untouched = EnumNames<Enum>::values[0].value;
  REQUIRE_FALSE(try_parse<Enum>("no such name", untouched));
  REQUIRE(untouched == EnumNames<Enum>::values[0].value);
  REQUIRE_THROWS_AS(parse<Enum>("no such name"), InvalidParameter);
  REQUIRE_THROWS_WITH(parse<Enum>("no such name"),
                      Contains(std::string("'") + EnumNames<Enum>::parameter + "' = 'no such name'") &&
                          Contains(joined_names<Enum>()));
}
}  // namespace

TEST_CASE("every option enum parses and prints its names", "[enum_names]") {
  require_round_trip<JacobianVariant>({"exact", "symmetric", "spd"});
  require_round_trip<PinTreatment>({"eliminate", "filter"});
  require_round_trip<PreconditionerKind>({"multigrid", "multigrid-float", "block-jacobi", "amg", "amg-float"});
  require_round_trip<LinearSolverKind>({"cg", "bicgstab", "ldlt", "lu", "cholmod", "umfpack"});
  require_round_trip<IntegratorKind>({"rk2", "implicit", "symplectic"});
  require_round_trip<BoundaryCondition>({"one-corner", "two-corners"});
  require_round_trip<SpringCategory>({"structural", "shear", "bend"});
  CHECK(joined_names<PinTreatment>(" | ") == "eliminate | filter");
  CHECK(std::string(to_string(static_cast<JacobianVariant>(7))) == "unknown");
}

TEST_CASE("InvalidParameter carries the parameter, value and allowed range separately", "[enum_names][validation]") {
  try {
    parse<JacobianVariant>("full");
    FAIL("no exception");
  } catch (const InvalidParameter& e) {
    CHECK(e.parameter() == "jacobian");
    CHECK(e.value() == "'full'");
    CHECK(e.allowed() == "exact, symmetric, spd");
    CHECK(std::string(e.what()) == "drape: parameter 'jacobian' = 'full' is invalid; allowed: exact, symmetric, spd");
  }
}
