#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "drape/fwd.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/io/state_io.hpp"
#include "test_common.hpp"

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("drape_test_state_" + name)).string();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

template <class S>
bool bit_identical(const drape::State<S>& a, const drape::State<S>& b) {
  return a.time == b.time && a.positions.cols() == b.positions.cols() &&
         (a.positions.array() == b.positions.array()).all() && (a.velocities.array() == b.velocities.array()).all();
}

}  // namespace

TEMPLATE_TEST_CASE("a saved and loaded state resumes bit-identically", "[state_io]", float, double) {
  using S = TestType;
  const drape::Cloth<S> cloth(drape::test::small_spec<S>(6, S(10)));
  const S dt = S(0.001);
  drape::Rk2<S> continuous(cloth, {double(dt), 1});
  drape::State<S> reference = cloth.initial_state();
  for (int k = 0; k < 40; ++k) REQUIRE(continuous.step(reference).ok());

  // The same 40 steps, saved after 17 and resumed from the file.
  drape::Rk2<S> first(cloth, {double(dt), 1});
  drape::State<S> s = cloth.initial_state();
  for (int k = 0; k < 17; ++k) REQUIRE(first.step(s).ok());
  const std::string path = temp_path(std::string("resume_") + drape::detail::scalar_name<S>());
  drape::save_state(path, s);
  drape::State<S> loaded = drape::load_state<S>(path, cloth.node_count());
  REQUIRE(bit_identical(loaded, s));
  drape::Rk2<S> second(cloth, {double(dt), 1});
  for (int k = 17; k < 40; ++k) REQUIRE(second.step(loaded).ok());
  REQUIRE(bit_identical(loaded, reference));
  std::remove(path.c_str());
}

TEST_CASE("awkward values survive the round trip exactly", "[state_io]") {
  drape::Stated s;
  s.positions.resize(3, 2);
  s.velocities.resize(3, 2);
  s.positions << 0.1, 1.0 / 3.0, -0.0, 1e-310, 5e-324, -1.7976931348623157e308;
  s.velocities << 2.0 / 3.0, 123456789.123456789, -1e-17, 0.30000000000000004, 1.0, -2.5;
  s.time = 0.1 + 0.2;
  const std::string path = temp_path("awkward");
  drape::save_state(path, s);
  const drape::Stated loaded = drape::load_state<double>(path);
  REQUIRE(bit_identical(loaded, s));
  REQUIRE(std::signbit(loaded.positions(1, 0)));  // -0.0 (comma init is row-major)
  REQUIRE(read_text(path).rfind("drape-state 1\nscalar double\nnodes 2\n", 0) == 0);
  std::remove(path.c_str());
}

TEST_CASE("state files with problems give errors that name the file", "[state_io]") {
  drape::Stated s;
  s.positions = drape::Matrix3X<double>::Random(3, 4);
  s.velocities = drape::Matrix3X<double>::Random(3, 4);
  const std::string good = temp_path("good");
  drape::save_state(good, s);
  const std::string text = read_text(good);
  const std::string bad = temp_path("bad");

  SECTION("missing file") {
    REQUIRE_THROWS_WITH(drape::load_state<double>(temp_path("does_not_exist")),
                        Catch::Contains("does_not_exist") && Catch::Contains("cannot open"));
  }
  SECTION("truncated in the middle of the nodes") {
    write_text(bad, text.substr(0, text.size() / 2));
    REQUIRE_THROWS_AS(drape::load_state<double>(bad), drape::StateFormatError);
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains(bad) && Catch::Contains("truncated"));
  }
  SECTION("truncated just before the end marker") {
    write_text(bad, text.substr(0, text.size() - 4));
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains(bad) && Catch::Contains("'end'"));
  }
  SECTION("a corrupt number") {
    std::string t = text;
    t.replace(t.find("\n", t.find("time")) + 1, 3, "0.x");
    write_text(bad, t);
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains(bad) && Catch::Contains("is not a number"));
  }
  SECTION("the wrong number of nodes for the cloth") {
    REQUIRE_THROWS_WITH(drape::load_state<double>(good, 1089),
                        Catch::Contains(good) && Catch::Contains("has 4 nodes but the cloth has 1089"));
  }
  SECTION("not a state file / another version") {
    write_text(bad, "v 1 2 3\n");
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains(bad) && Catch::Contains("drape-state"));
    write_text(bad, "drape-state 7\n" + text.substr(text.find('\n') + 1));
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains("unsupported format version 7"));
  }
  SECTION("more nodes than declared") {
    std::string t = text;
    t.insert(t.rfind("end"), "1 2 3 4 5 6\n");
    write_text(bad, t);
    REQUIRE_THROWS_WITH(drape::load_state<double>(bad), Catch::Contains("more nodes than declared"));
  }
  SECTION("a float file loads into a double state exactly") {
    drape::Statef f;
    f.positions = drape::Matrix3X<float>::Random(3, 3);
    f.velocities = drape::Matrix3X<float>::Random(3, 3);
    drape::save_state(bad, f);
    const drape::Stated d = drape::load_state<double>(bad);
    REQUIRE((d.positions.cast<float>().array() == f.positions.array()).all());
    REQUIRE((d.positions.array() == f.positions.cast<double>().array()).all());
  }
  std::remove(good.c_str());
  std::remove(bad.c_str());
}
