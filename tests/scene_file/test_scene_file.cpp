// The scene-file library (drape::scene_file) on its own, without a renderer: settings read from a
// scene file and flags, the one reader of the [[colliders]], [[moving-pins]] and [[cloths]] tables,
// the scene built from the settings (every cloth, the start state, the floor) and the moving pins
// applied over time. drape-render's own use of it is tested by tests/viewer/test_cli.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "drape/core/mesh_generators.hpp"
#include "drape/core/pin_set.hpp"
#include "drape/scene_file/build_scene.hpp"
#if DRAPE_TEST_HAS_PATTERN_IO
#include "drape/garment/fabric.hpp"
#include "drape/physics/seam_springs.hpp"
#endif
#include "drape/scene_file/command_line.hpp"
#include "drape/scene_file/pin_schedule.hpp"

namespace fs = std::filesystem;
using namespace drape::scene_file;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("drape_test_scene_file_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// read_settings() of a scene file with the text `toml` (and `flags`).
Settings read_text(const fs::path& dir, const std::string& toml, const std::vector<std::string>& flags = {}) {
  std::ofstream(dir / "scene.toml") << toml;
  return read_settings((dir / "scene.toml").string(), flags);
}

/// The message of read_settings()'s SettingsError for a scene file with `toml`; "" if it accepts it.
std::string error_of(const fs::path& dir, const std::string& toml, const std::vector<std::string>& flags = {}) {
  try {
    (void)read_text(dir, toml, flags);
  } catch (const SettingsError& e) { return e.what(); }
  return "";
}

double distance(const drape::Colliderd& c, double x, double y, double z, double t = 0) {
  return c.query(drape::Vec3<double>(x, y, z), t).distance;
}

}  // namespace

TEST_CASE("colliders: [[colliders]] tables build the library's colliders where the file puts them",
          "[scene_file][colliders]") {
  const fs::path dir = fresh_dir("colliders");
  std::ofstream(dir / "scene.toml") << R"(
contact-thickness = 0.01
contact-rounds = 7
integrator = "implicit"
floor-collider = true
floor-friction = 0.2
floor-height = -2.0

[[colliders]]
shape = "plane"
point = [0.0, -1.0, 0.0]
normal = [0.0, 2.0, 0.0]

[[colliders]]
shape = "sphere"
center = [1.0, 2.0, 3.0]
radius = 0.5
static_friction = 0.4
velocity = [1.0, 0.0, 0.0]

[[colliders]]
shape = "capsule"
a = [0.0, -3.0, 0.0]
b = [2.0, -3.0, 0.0]
radius = 0.25
kinetic_friction = 0.3

[[colliders]]
shape = "box"
center = [0.0, -3.0, 0.0]
half_extents = [1.0, 0.5, 2.0]
rotation_axis = [0.0, 3.0, 0.0]
rotation_angle = 90.0
rounding = 0.1
static_friction = 0.5
kinetic_friction = 0.2
angular_velocity = [0.0, 1.0, 0.0]
)";
  const Settings s = read_settings((dir / "scene.toml").string());
  const std::vector<drape::Colliderd>& c = s.cloth.colliders;
  REQUIRE(c.size() == 4);
  REQUIRE(s.collider_keys == std::vector<std::string>{"colliders[0]", "colliders[1]", "colliders[2]", "colliders[3]"});
  REQUIRE(s.cloth.contact_thickness == 0.01);
  REQUIRE(s.stepping.contact_rounds == 7);

  // The plane y = -1, normal +y (the normal's length does not matter).
  REQUIRE(c[0].kind() == drape::ShapeKind::Plane);
  REQUIRE(distance(c[0], 3, 0.5, 7) == Approx(1.5));
  REQUIRE(c[0].query(drape::Vec3<double>(3, 0.5, 7), 0).normal.isApprox(drape::Vec3<double>::UnitY()));
  REQUIRE(c[0].motion().is_static());
  REQUIRE(c[0].static_friction() == 0);
  REQUIRE(c[0].kinetic_friction() == 0);
  // The sphere, moving at 1 m/s along x; kinetic friction defaults to the static one.
  REQUIRE(c[1].kind() == drape::ShapeKind::Sphere);
  REQUIRE(distance(c[1], 1, 4, 3) == Approx(1.5));
  REQUIRE(distance(c[1], 3, 4, 3, 2.0) == Approx(1.5));  // moved by 2 m at t = 2 s
  REQUIRE(!c[1].motion().is_static());
  REQUIRE(c[1].static_friction() == 0.4);
  REQUIRE(c[1].kinetic_friction() == 0.4);
  // The capsule from a to b; static friction defaults to the kinetic one.
  REQUIRE(c[2].kind() == drape::ShapeKind::Capsule);
  REQUIRE(distance(c[2], 1, -2, 0) == Approx(0.75));
  REQUIRE(distance(c[2], 3, -3, 0) == Approx(0.75));
  REQUIRE(distance(c[2], -1, -3, 0) == Approx(0.75));
  REQUIRE(c[2].static_friction() == 0.3);
  REQUIRE(c[2].kinetic_friction() == 0.3);
  // The box turned 90 degrees about +y: its x half extent (1) lies along z, its z (2) along x.
  REQUIRE(c[3].kind() == drape::ShapeKind::Box);
  REQUIRE(distance(c[3], 0, -3, 3) == Approx(2.0));
  REQUIRE(distance(c[3], 3, -3, 0) == Approx(1.0));
  // Its edges rounded with radius 0.1: 0.1 m out from both faces at an edge is
  // sqrt(2) * 0.2 - 0.1 from the rounded edge (local (1.1, 0.6, 0) is world (0, -2.4, -1.1)).
  REQUIRE(distance(c[3], 0, -2.4, -1.1) == Approx(std::sqrt(2.0) * 0.2 - 0.1));
  REQUIRE(c[3].rounding() == 0.1);
  // Spinning at 1 rad/s about +y: after pi/2 s it has turned 180 degrees in all.
  REQUIRE(distance(c[3], 0, -3, 3, std::acos(-1.0) / 2) == Approx(1.0));
  REQUIRE(c[3].static_friction() == 0.5);
  REQUIRE(c[3].kinetic_friction() == 0.2);

  // The floor: --floor-height wins over the plane facing +y, which would set it otherwise.
  REQUIRE(s.floor.collider);
  REQUIRE(s.floor.friction == 0.2);
  REQUIRE(fixed_floor_height(s) == -2.0);
  const drape::Colliderd floor = floor_collider(s, -2.0);
  REQUIRE(distance(floor, 5, -1, 5) == Approx(1.0));
  REQUIRE(floor.static_friction() == 0.2);
  REQUIRE(floor.kinetic_friction() == 0.2);
  REQUIRE(is_floor(floor, -2.0));
  REQUIRE(is_floor(c[0], -1.0));
  REQUIRE(!is_floor(c[0], -2.0));
  REQUIRE(!is_floor(c[1], 2.0));

  // Flags override the file's keys; --sphere comes after the file's colliders.
  const Settings f =
      read_settings((dir / "scene.toml").string(), {"--contact-thickness", "0.02", "--contact-rounds", "3",
                                                    "--floor-friction", "0.6", "--floor-height", "-1.5", "--sphere",
                                                    "5", "6", "7", "0.5"});
  REQUIRE(f.cloth.contact_thickness == 0.02);
  REQUIRE(f.stepping.contact_rounds == 3);
  REQUIRE(f.floor.friction == 0.6);
  REQUIRE(fixed_floor_height(f) == -1.5);
  REQUIRE(f.cloth.colliders.size() == 5);
  REQUIRE(f.collider_keys.back() == "--sphere");
  REQUIRE(distance(f.cloth.colliders.back(), 5, 8, 7) == Approx(1.5));
  REQUIRE(f.cloth.colliders.back().kind() == drape::ShapeKind::Sphere);

  // Without --floor-height the floor goes to the highest static plane facing +y; without any, the
  // camera chooses it at run time.
  std::ofstream(dir / "planes.toml") << "[[colliders]]\nshape = \"plane\"\npoint = [0, -0.7, 0]\nnormal = [0, 1, 0]\n"
                                        "[[colliders]]\nshape = \"plane\"\npoint = [0, -0.4, 0]\nnormal = [0, 1, 0]\n"
                                        "[[colliders]]\nshape = \"plane\"\npoint = [0, -0.1, 0]\nnormal = [1, 1, 0]\n"
                                        "[[colliders]]\nshape = \"plane\"\npoint = [0, -0.2, 0]\nnormal = [0, 1, 0]\n"
                                        "velocity = [0, -1, 0]\n";
  REQUIRE(fixed_floor_height(read_settings((dir / "planes.toml").string())) == -0.4);
  REQUIRE(!fixed_floor_height(read_settings("", {"--sphere", "5", "6", "7", "0.5"})));
  REQUIRE(read_settings("").cloth.colliders.empty());  // none by default
  fs::remove_all(dir);
}

TEST_CASE("colliders: a [[colliders]] cylinder is a round table, turned, rounded and moved as the file says",
          "[scene_file][colliders][cylinder]") {
  const fs::path dir = fresh_dir("cylinder");
  const Settings s = read_text(dir, R"(
[[colliders]]
shape = "cylinder"
center = [0.5, -0.4, 0.5]
radius = 0.3
half_height = 0.1

[[colliders]]
shape = "cylinder"
center = [0.0, -3.0, 0.0]
radius = 0.5
half_height = 1.0
rotation_axis = [0.0, 0.0, 2.0]
rotation_angle = 90.0
rounding = 0.2
static_friction = 0.4
velocity = [1.0, 0.0, 0.0]
)");
  const std::vector<drape::Colliderd>& c = s.cloth.colliders;
  REQUIRE(c.size() == 2);
  // A round table of radius 0.3, its top at y = -0.3.
  REQUIRE(c[0].kind() == drape::ShapeKind::Cylinder);
  REQUIRE(c[0].radius() == 0.3);
  REQUIRE(c[0].half_height() == 0.1);
  REQUIRE(c[0].rounding() == 0);
  REQUIRE(c[0].motion().is_static());
  REQUIRE(distance(c[0], 0.5, 0.0, 0.5) == Approx(0.3));
  REQUIRE(distance(c[0], 1.3, -0.4, 0.5) == Approx(0.5));
  REQUIRE(distance(c[0], 0.5, -1.0, 0.7) == Approx(0.5));
  // Turned a quarter turn about +z: its axis lies along x, caps at x = -1 and 1, rims rounded by 0.2.
  REQUIRE(c[1].rounding() == 0.2);
  REQUIRE(distance(c[1], 3, -3, 0) == Approx(2.0));
  REQUIRE(distance(c[1], 0, -1, 0) == Approx(1.5));
  REQUIRE(distance(c[1], 0.5, -3, -1) == Approx(0.5));
  REQUIRE(distance(c[1], -2, -1.5, 0) == Approx(1.2 * std::sqrt(2.0) - 0.2));
  // Moving at 1 m/s along x; kinetic friction defaults to the static one.
  REQUIRE(distance(c[1], 4, -3, 0, 1.0) == Approx(2.0));
  REQUIRE(c[1].static_friction() == 0.4);
  REQUIRE(c[1].kinetic_friction() == 0.4);

  // Its errors name the key typed.
  using Catch::Contains;
  const std::string can = "[[colliders]]\nshape = \"cylinder\"\ncenter = [0, -1, 0]\nradius = 1.0\n";
  REQUIRE_THAT(error_of(dir, can),
               Contains("key 'colliders[0].half_height' is missing; a cylinder needs center, radius, half_height"));
  REQUIRE_THAT(error_of(dir, can + "half_height = 0.0\n"), Contains("colliders[0].half_height = 0") &&
                                                               Contains("is invalid") && Contains("> 0"));
  REQUIRE_THAT(error_of(dir, can + "half_height = 0.5\nrounding = 0.6\n"),
               Contains("colliders[0].rounding = 0.6") && Contains("[0, 0.5]"));
  REQUIRE_THAT(error_of(dir, "[[colliders]]\nshape = \"cylinder\"\ncenter = [0, -1, 0]\nradius = -0.5\n"
                             "half_height = 1.0\n"),
               Contains("colliders[0].radius = -0.5"));
  REQUIRE_THAT(error_of(dir, can + "half_height = 0.5\nrotation_axis = [0, 0, 0]\n"),
               Contains("colliders[0].rotation_axis"));
  REQUIRE_THAT(error_of(dir, can + "half_height = 0.5\nhalf_extents = [1, 1, 1]\n"),
               Contains("key 'colliders[0].half_extents' does not belong to a cylinder (it is a box's); a cylinder "
                        "has the keys shape, velocity, angular_velocity, static_friction, kinetic_friction, center, "
                        "radius, half_height, rotation_axis, rotation_angle, rounding"));
  REQUIRE_THAT(error_of(dir, "[[colliders]]\nshape = \"box\"\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\n"
                             "half_height = 1.0\n"),
               Contains("key 'colliders[0].half_height' does not belong to a box (it is a cylinder's)"));
  REQUIRE_THAT(error_of(dir, "[[colliders]]\nshape = \"cone\"\n"),
               Contains("plane | sphere | capsule | box | cylinder"));
  fs::remove_all(dir);
}

TEST_CASE("colliders: a [[colliders]] mesh reads its OBJ file, scaled, placed and turned as the file says",
          "[scene_file][colliders][mesh_collider]") {
  using Catch::Contains;
  const fs::path dir = fresh_dir("mesh_collider");
  // A cube 20 cm across in centimetres, its faces counter-clockwise seen from outside.
  const std::string cube = "v -10 -10 -10\nv 10 -10 -10\nv 10 10 -10\nv -10 10 -10\n"
                           "v -10 -10 10\nv 10 -10 10\nv 10 10 10\nv -10 10 10\n"
                           "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";
  std::ofstream(dir / "cube.obj") << cube;
  const Settings s = read_text(dir, R"(
[[colliders]]
shape = "mesh"
file = "cube.obj"
scale = 0.01
center = [1.0, 2.0, 3.0]
rotation_axis = [0.0, 1.0, 0.0]
rotation_angle = 45.0
static_friction = 0.3
)");
  const std::vector<drape::Colliderd>& c = s.cloth.colliders;
  REQUIRE(c.size() == 1);
  REQUIRE(c[0].kind() == drape::ShapeKind::Mesh);
  CHECK(c[0].static_friction() == 0.3);
  // 10 cm half extents about (1, 2, 3), turned 45 degrees about y: a corner direction is along x.
  CHECK(distance(c[0], 1.0, 2.5, 3.0) == Approx(0.4));
  CHECK(distance(c[0], 1.5, 2.0, 3.0) == Approx(0.5 - 0.1 * std::sqrt(2.0)).epsilon(1e-9));
  CHECK(distance(c[0], 1.0, 2.0, 3.0) == Approx(-0.1));

  // Errors name the table's key and the file.
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\n"), Contains("colliders[0].file") && Contains("missing"));
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\nfile = \"none.obj\"\n"),
             Contains("colliders[0].file") && Contains("none.obj"));
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\nfile = \"cube.obj\"\nscale = -1.0\n"),
             Contains("colliders[0].scale") && Contains("> 0"));
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\nfile = \"cube.obj\"\nradius = 1.0\n"),
             Contains("colliders[0].radius") && Contains("does not belong"));
  std::string inward = cube;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"f 1 4 3 2", "f 2 3 4 1"}, {"f 5 6 7 8", "f 8 7 6 5"}, {"f 1 2 6 5", "f 5 6 2 1"},
           {"f 3 4 8 7", "f 7 8 4 3"}, {"f 2 3 7 6", "f 6 7 3 2"}, {"f 1 5 8 4", "f 4 8 5 1"}})
    inward.replace(inward.find(from), from.size(), to);
  std::ofstream(dir / "inward.obj") << inward;
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\nfile = \"inward.obj\"\n"),
             Contains("colliders[0].file") && Contains("inward.obj") && Contains("inward"));
  std::ofstream(dir / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n";
  CHECK_THAT(error_of(dir, "[[colliders]]\nshape = \"mesh\"\nfile = \"flat.obj\"\n"),
             Contains("colliders[0].file") && Contains("flat.obj"));

  // Key frames: the cube 1 m higher after 2 s, linear in between.
  std::string raised;
  std::istringstream lines(cube);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("v ", 0) == 0) {
      double x = 0, y = 0, z = 0;
      std::istringstream(line.substr(2)) >> x >> y >> z;
      line = "v " + std::to_string(x) + " " + std::to_string(y + 100) + " " + std::to_string(z);
    }
    raised += line + "\n";
  }
  std::ofstream(dir / "raised.obj") << raised;
  const std::string animated = "[[colliders]]\nshape = \"mesh\"\nfile = \"cube.obj\"\nscale = 0.01\n";
  const Settings a = read_text(dir, animated + "frames = [{time = 0.0, file = \"cube.obj\"}, {time = 2.0, file = \"raised.obj\"}]\n");
  REQUIRE(a.cloth.colliders.size() == 1);
  CHECK(a.cloth.colliders[0].deforms());
  CHECK(distance(a.cloth.colliders[0], 0, 2.0, 0, 0.0) == Approx(1.9));
  CHECK(distance(a.cloth.colliders[0], 0, 2.0, 0, 1.0) == Approx(1.4));
  CHECK(distance(a.cloth.colliders[0], 0, 2.0, 0, 3.0) == Approx(0.9));
  CHECK(a.cloth.colliders[0].query(drape::Vec3<double>(0, 2, 0), 1.0).velocity.y() == Approx(0.5));
  CHECK_THAT(error_of(dir, animated + "frames = [{time = 1.0, file = \"cube.obj\"}, {time = 1.0, file = \"raised.obj\"}]\n"),
             Contains("colliders[0].frames[1].time") && Contains("increasing"));
  CHECK_THAT(error_of(dir, animated + "frames = [{time = 0.0, file = \"cube.obj\"}, {time = 1.0, file = \"flat.obj\"}]\n"),
             Contains("colliders[0].frames[1].file") && Contains("flat.obj"));
  CHECK_THAT(error_of(dir, animated + "frames = [{time = 0.0}]\n"), Contains("colliders[0].frames[0].file") && Contains("missing"));
  CHECK_THAT(error_of(dir, animated + "frames = [{time = 0.0, file = \"cube.obj\", speed = 1.0}]\n"),
             Contains("colliders[0].frames[0].speed"));
  CHECK_THAT(error_of(dir, animated + "frames = []\n"), Contains("colliders[0].frames") && Contains("at least one"));
}

TEST_CASE("[[colliders]], [[moving-pins]], [[cloths]]: one reader names unknown and misspelt keys, bad entries",
          "[scene_file][tables]") {
  const fs::path dir = fresh_dir("tables");
  using Catch::Contains;
  // An unknown key, with the key it misspells ('-' for '_' or back) and the keys the table has.
  const std::string sphere = "[[colliders]]\nshape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
  REQUIRE_THAT(error_of(dir, sphere + "static-friction = 0.1\n"),
               Contains("unknown key 'colliders[0].static-friction' (did you mean 'static_friction'?); a sphere "
                        "has the keys shape, velocity, angular_velocity, static_friction, kinetic_friction, center, "
                        "radius"));
  REQUIRE_THAT(error_of(dir, sphere + "half_extents = [1, 1, 1]\n"),
               Contains("key 'colliders[0].half_extents' does not belong to a sphere (it is a box's)"));
  REQUIRE_THAT(error_of(dir, "[[moving-pins]]\nnode = [0, 0]\nrelase = 1.0\n"),
               Contains("unknown key 'moving-pins[0].relase'; a pin has the keys node, id, times, positions, "
                        "interpolation, start, release"));
  REQUIRE_THAT(error_of(dir, "[[cloths]]\nstructural_ks = 100.0\n"),
               Contains("unknown key 'cloths[0].structural_ks' (did you mean 'structural-ks'?); a cloth has the "
                        "keys nx"));
  REQUIRE_THAT(error_of(dir, "[[cloths]]\nnx = 4\n[[cloths]]\nny = 4\ncolor = 1\n"),
               Contains("unknown key 'cloths[1].color'; a cloth has the keys"));
  // Entries that are not tables, and keys that are not arrays of tables.
  REQUIRE_THAT(error_of(dir, "colliders = 3\n"),
               Contains("key 'colliders' must be an array of tables ([[colliders]] with a shape each)"));
  REQUIRE_THAT(error_of(dir, "moving-pins = [1]\n"),
               Contains("key 'moving-pins[0]' must be a table ([[moving-pins]] with node = [i, j] or id = k)"));
  REQUIRE_THAT(error_of(dir, "cloths = \"two\"\n"),
               Contains("key 'cloths' must be an array of tables ([[cloths]], one per cloth after the first)"));
  // The tables in order, each under its own key.
  const Settings s = read_text(dir, sphere + sphere + "[[cloths]]\nnx = 4\n[[cloths]]\nny = 5\n"
                                     "[[moving-pins]]\nnode = [1, 0]\n[[moving-pins]]\nid = 3\n");
  REQUIRE(s.collider_keys == std::vector<std::string>{"colliders[0]", "colliders[1]"});
  REQUIRE(s.extra_cloths.size() == 2);
  REQUIRE(s.extra_cloths[0].key == "cloths[0]");
  REQUIRE(s.extra_cloths[0].nx == 4);
  REQUIRE(s.extra_cloths[1].ny == 5);
  REQUIRE(s.moving_pins.size() == 2);
  REQUIRE(s.moving_pins[1].key == "moving-pins[1]");
  REQUIRE(pin_node(s, s.moving_pins[0]) == 1);
  REQUIRE(pin_node(s, s.moving_pins[1]) == 3);
  fs::remove_all(dir);
}

TEST_CASE("read_settings: flags over the scene file; a bad flag is an error naming it", "[scene_file]") {
  const fs::path dir = fresh_dir("flags");
  const std::string scene = "nx = 12\nny = 7\nintegrator = \"implicit\"\ndt = 0.005\n";
  const Settings file = read_text(dir, scene);
  REQUIRE(file.cloth.nx == 12);
  REQUIRE(file.cloth.ny == 7);
  REQUIRE(file.integrator == drape::IntegratorKind::Implicit);
  REQUIRE(file.stepping.dt == 0.005);
  const Settings flags = read_text(dir, scene, {"--nx", "9", "--integrator", "symplectic"});
  REQUIRE(flags.cloth.nx == 9);
  REQUIRE(flags.cloth.ny == 7);
  REQUIRE(flags.integrator == drape::IntegratorKind::Symplectic);
  REQUIRE_THAT(error_of(dir, scene, {"--bogus", "1"}), Catch::Contains("--bogus"));
  REQUIRE_THAT(error_of(dir, scene, {"--help"}), Catch::Contains("--help"));
  REQUIRE_THAT(error_of(dir, scene, {"--nx", "1"}), Catch::Contains("--nx = 1 is invalid; allowed: [2, 10000]"));
  REQUIRE_THAT(error_of(dir, "nx = 1\n"), Catch::Contains("--nx = 1 is invalid"));
  REQUIRE_THAT(error_of(dir, "nx = 1.5\n"), Catch::Contains("key 'nx' must be an integer"));
  fs::remove_all(dir);
}

TEST_CASE("usd: a .usda file in an existing folder or in --out; errors name the flag or the key", "[scene_file]") {
  const fs::path dir = fresh_dir("usd");
  using Catch::Contains;
  const std::string in_dir = (dir / "scene.usda").string();
  CHECK(read_text(dir, "usd = \"" + in_dir + "\"\n").output.usd == in_dir);
  CHECK(read_text(dir, "", {"--usd", in_dir}).output.usd == in_dir);
  // In the --out folder, which drape-render creates.
  const std::string out = (dir / "frames").string();
  CHECK(error_of(dir, "", {"--out", out + "/", "--usd", out + "/scene.usda"}).empty());
  CHECK_THAT(error_of(dir, "", {"--usd", (dir / "scene.usd").string()}),
             Contains("--usd (extension) = '.usd' is invalid; allowed: .usda"));
  CHECK_THAT(error_of(dir, "usd = \"" + (dir / "scene.obj").string() + "\"\n"),
             Contains("scene.toml': usd (extension) = '.obj'") && Contains(".usda"));
  CHECK_THAT(error_of(dir, "", {"--usd", (dir / "missing" / "scene.usda").string()}),
             Contains("--usd = '") && Contains("missing") && Contains("existing folder"));
  CHECK_THAT(error_of(dir, "usd = \"" + (dir / "missing" / "scene.usda").string() + "\"\n"),
             Contains("scene.toml': usd = '") && Contains("existing folder"));
  fs::remove_all(dir);
}

TEST_CASE("prepare_scene: every cloth, the start state, the air's force and the floor, without a renderer",
          "[scene_file]") {
  const fs::path dir = fresh_dir("prepare");
  // The floor collider at a height the settings fix.
  const PreparedScene fixed =
      prepare_scene(read_text(dir, "nx = 6\nny = 6\nfloor-collider = true\nfloor-height = -1.25\n"));
  REQUIRE(fixed.floor_y == -1.25);
  REQUIRE(fixed.first.colliders.size() == 1);
  REQUIRE(distance(fixed.first.colliders.back(), 0, 0, 0) == Approx(1.25));
  REQUIRE(fixed.specs.size() == 1);
  REQUIRE(fixed.first.force_terms.empty());  // still air: no force term
  REQUIRE(fixed.start.positions.cols() == 36);

  // Unfixed, the floor goes below the box the fixed camera frames: below where the cloth can hang.
  const PreparedScene framed =
      prepare_scene(read_text(dir, "nx = 6\nny = 6\nfloor-collider = true\n[air]\ndrag = 0.1\n"
                                   "[[cloths]]\nnx = 3\nny = 3\nposition = [0.0, 1.0, 0.0]\n"));
  REQUIRE(framed.floor_y <= framed.framed.min.y());
  REQUIRE(framed.floor_y < framed.start.positions.row(1).minCoeff());
  REQUIRE(framed.first.colliders.size() == 1);
  REQUIRE(distance(framed.first.colliders.back(), 0, 0, 0) == Approx(-framed.floor_y));
  REQUIRE(framed.first.force_terms.size() == 1);  // the air's drag
  REQUIRE(framed.specs.size() == 2);
  REQUIRE(framed.specs[1].nx == 3);
  REQUIRE(framed.specs[1].force_terms.size() == 1);  // its own air term, for its own grid
  REQUIRE(framed.specs[1].colliders.size() == 1);    // the first cloth's colliders, the floor among them
  REQUIRE(framed.framed.max.y() >= 1.0f);             // the second cloth starts 1 m up
  fs::remove_all(dir);
}

TEST_CASE("PinSchedule: a [[moving-pins]] node is pinned from its start and released at its release", "[scene_file]") {
  const fs::path dir = fresh_dir("schedule");
  const Settings s =
      read_text(dir, "nx = 4\nny = 4\npins = []\n[[moving-pins]]\nnode = [2, 1]\nstart = 0.5\nrelease = 1.0\n");
  const int node = 1 * 4 + 2;
  PinSchedule schedule(s);
  drape::PinSet<double> pins(drape::Pins({}, 16));
  const double dt = 0.1;
  double t = 0;  // accumulated as a run accumulates it: 0.5 and 1.0 are reached within rounding
  for (int step = 0; step <= 12; ++step, t += dt) {
    schedule.apply(t, dt, pins);
    INFO("step " << step << ", t = " << t);
    REQUIRE(pins.is_pinned(node) == (step >= 5 && step < 10));
  }
  fs::remove_all(dir);
}

TEST_CASE("mesh keys: generated and OBJ meshes, density, pins by group and box, bending; bad values named",
          "[scene_file][mesh]") {
  const fs::path dir = fresh_dir("mesh");
  using Catch::Contains;
  // A disk of 0.3 m radius, 5 cm edges: the library's disk_mesh().
  Settings s = read_text(dir, "shape = \"disk\"\nradius = 0.3\nedge-length = 0.05\ndensity = 0.25\n"
                              "pin-groups = [\"boundary\"]\nbending = 1e-4\nbending-kd = 1e-6\n");
  REQUIRE(s.cloth.mesh);
  const drape::ClothMesh<double>& disk = *s.cloth.mesh;
  CHECK(disk.positions == drape::disk_mesh(0.3, 0.05).positions);
  CHECK(disk.positions.colwise().norm().maxCoeff() == Approx(0.3));
  REQUIRE(s.cloth.areal_density);
  CHECK(*s.cloth.areal_density == 0.25);
  REQUIRE(s.cloth.pinned_nodes);
  CHECK(s.cloth.pinned_nodes->size() == disk.groups.at("boundary").size());
  const drape::Clothd cloth = make_cloth(s, s.cloth);
  CHECK(!cloth.is_grid());
  CHECK(cloth.masses().sum() == Approx(0.25 * M_PI * 0.09).epsilon(0.02));  // the polygon's area
  REQUIRE(bending_term(s));
  CHECK(bending_term(s)->name() == "dihedral bending");

  // The disk with a ring of vertices on a circle inside it, pinned by the ring's group.
  s = read_text(dir,
                "shape = \"disk\"\nradius = 0.3\nring-radius = 0.2\nedge-length = 0.05\npin-groups = [\"ring\"]\n");
  REQUIRE(s.cloth.mesh);
  CHECK(s.cloth.mesh->positions == drape::disk_mesh(0.3, 0.05, 0.2).positions);
  REQUIRE(s.cloth.pinned_nodes);
  CHECK(s.cloth.pinned_nodes->size() == s.cloth.mesh->groups.at("ring").size());

  // A rectangle with a hole pinned by a box around its left edge (x = 0 at the start).
  s = read_text(dir, "shape = \"rectangle-with-hole\"\nsize = [1.0, 0.6]\nhole-radius = 0.1\n"
                     "hole-centre = [0.5, 0.3]\nedge-length = 0.05\npin-box = [-0.01, -0.01, -0.01, 0.01, 0.01, 0.61]\n");
  REQUIRE(s.cloth.mesh);
  REQUIRE(s.cloth.pinned_nodes);
  CHECK(s.cloth.pinned_nodes->size() == s.cloth.mesh->groups.at("left").size());

  // An OBJ file next to the scene file, scaled from centimetres.
  std::ofstream(dir / "square.obj") << "v 0 0 0\nv 10 0 0\nv 10 0 10\nv 0 0 10\ng edge\nf 1 2 3 4\n";
  s = read_text(dir, "mesh = \"square.obj\"\nscale = 0.01\npin-groups = [\"edge\"]\n");
  REQUIRE(s.cloth.mesh);
  CHECK(s.cloth.mesh->quads.size() == 1);
  CHECK(s.cloth.mesh->positions.col(2).isApprox(drape::Vec3<double>(0.1, 0, 0.1)));

  // Bad values name the key and what is allowed.
  CHECK_THAT(error_of(dir, "shape = \"hexagon\"\n"), Contains("shape") && Contains("grid | disk | rectangle-with-hole"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\nradius = 0.3\nedge-length = 0.0005\n"),
             Contains("edge-length") && Contains("at most 100000 vertices"));
  CHECK(error_of(dir, "shape = \"disk\"\nradius = 0.3\nedge-length = 0.004\n").empty());  // 20k vertices
  CHECK_THAT(error_of(dir, "mesh = \"square.obj\"\nshape = \"disk\"\n"), Contains("shape") && Contains("with a mesh file"));
  CHECK_THAT(error_of(dir, "mesh = \"missing.obj\"\n"), Contains("missing.obj"));
  CHECK_THAT(error_of(dir, "mesh = \"square.obj\"\npin-groups = [\"hem\"]\n"),
             Contains("pin-groups") && Contains("'hem'") && Contains("a group of the mesh: edge"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\npin-box = [5.0, 5.0, 5.0, 6.0, 6.0, 6.0]\n"),
             Contains("pin-box") && Contains("holds no node"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\npin-box = [1.0, 0.0, 0.0, 0.0, 1.0, 1.0]\n"), Contains("pin-box"));
  CHECK_THAT(error_of(dir, "mesh = \"square.obj\"\nscale = -1.0\n"), Contains("scale") && Contains("> 0"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\ndensity = -0.2\n"), Contains("density") && Contains(">= 0"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\nbending = -1.0\n"), Contains("bending") && Contains(">= 0"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\nradius = 0.3\nedge-length = 0.05\nring-radius = 0.29\n"),
             Contains("ring-radius") && Contains("[0.05, 0.25]"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\nradius = 0.3\nedge-length = 0.05\nring-radius = -0.1\n"),
             Contains("ring-radius") && Contains("0 (no ring)"));
  CHECK_THAT(error_of(dir, "shape = \"rectangle-with-hole\"\nring-radius = 0.1\n"),
             Contains("ring-radius") && Contains("0 unless the cloth is the disk"));
  fs::remove_all(dir);
}

#if DRAPE_TEST_HAS_PATTERN_IO
TEST_CASE("pattern keys: a garment sewn from a sewing pattern in a fabric; bad values named",
          "[scene_file][mesh][garment]") {
  const fs::path dir = fresh_dir("pattern");
  using Catch::Contains;
  const std::string shirt = std::string(DRAPE_SOURCE_DIR) + "/scenes/garments/shirt_mean.json";
  const std::string garment = "pattern = \"" + shirt + "\"\nedge-length = 0.03\n";
  Settings s = read_text(dir, garment + "fabric = \"denim\"\nseam-stiffness = 800.0\nseam-closing-time = 0.6\n"
                                        "gravity = 9.81\nself-collision = true\n");
  REQUIRE(s.cloth.mesh);
  REQUIRE(s.cloth.areal_density);
  CHECK(*s.cloth.areal_density == drape::fabric_preset("denim").areal_density);
  CHECK(s.cloth.springs.structural.stiffness == drape::edge_spring_stiffness(drape::fabric_preset("denim")));
  CHECK(s.cloth.springs.bend.stiffness == 0);
  CHECK(s.cloth.gravity == 0);  // carried by the ramped term
  CHECK(s.cloth.self_collision.enabled);
  CHECK(s.cloth.self_collision.joined_nodes.size() > 50);
  REQUIRE(s.cloth.pinned_nodes);
  CHECK(s.cloth.pinned_nodes->empty());
  std::vector<std::string> names;
  for (const auto& term : prepare_scene(s).first.force_terms) names.push_back(term->name());
  CHECK(names == std::vector<std::string>{"seams", "dihedral bending", "seam hinges", "ramped gravity"});
  const auto& seams = dynamic_cast<const drape::SeamSprings<double>&>(*prepare_scene(s).first.force_terms[0]);
  CHECK(seams.stiffness() == 800.0);
  CHECK(seams.closing_time() == 0.6);
  CHECK(seams.pairs() == s.cloth.self_collision.joined_nodes);

  // Bad values name the key and what is allowed.
  CHECK_THAT(error_of(dir, garment + "fabric = \"tweed\"\n"), Contains("fabric") && Contains("cotton | denim | silk | jersey"));
  CHECK_THAT(error_of(dir, garment + "seam-stiffness = 0.0\n"), Contains("seam-stiffness") && Contains("> 0"));
  CHECK_THAT(error_of(dir, garment + "seam-closing-time = -1.0\n"), Contains("seam-closing-time") && Contains(">= 0"));
  CHECK_THAT(error_of(dir, garment + "density = 0.2\n"), Contains("density") && Contains("the fabric sets"));
  CHECK_THAT(error_of(dir, garment + "bending = 1e-4\n"), Contains("bending") && Contains("the fabric sets"));
  CHECK_THAT(error_of(dir, garment + "shape = \"disk\"\n"), Contains("shape") && Contains("with a pattern"));
  CHECK_THAT(error_of(dir, garment + "[[cloths]]\nnx = 3\n"), Contains("--pattern") && Contains("[[cloths]]"));
  std::ofstream(dir / "bad.json") << "{\"pattern\": {\"panels\": {}}}";
  CHECK_THAT(error_of(dir, "pattern = \"bad.json\"\n"), Contains("pattern") && Contains("bad.json"));
  fs::remove_all(dir);
}

TEST_CASE("[panel-offsets]: a panel's placement moved by its offset, the others where they were; bad tables named",
          "[scene_file][mesh][garment]") {
  const fs::path dir = fresh_dir("panel_offsets");
  using Catch::Contains;
  const std::string shirt = std::string(DRAPE_SOURCE_DIR) + "/scenes/garments/shirt_mean.json";
  const std::string garment = "pattern = \"" + shirt + "\"\nedge-length = 0.03\n";
  const Settings plain = read_text(dir, garment);
  const Settings moved = read_text(dir, garment + "[panel-offsets]\nleft_sleeve_f = [0.06, -0.02, 0.01]\n");
  REQUIRE(plain.cloth.mesh);
  REQUIRE(moved.cloth.mesh);
  const drape::Matrix3X<double>& x0 = plain.cloth.mesh->positions;
  const drape::Matrix3X<double>& x1 = moved.cloth.mesh->positions;
  REQUIRE(x0.cols() == x1.cols());
  const std::vector<int>& sleeve = plain.cloth.mesh->groups.at("panel left_sleeve_f");
  std::vector<char> in_sleeve(std::size_t(x0.cols()), 0);
  for (int i : sleeve) in_sleeve[std::size_t(i)] = 1;
  double off_offset = 0, others_moved = 0;
  for (drape::Index i = 0; i < x0.cols(); ++i) {
    const drape::Vec3<double> d = x1.col(i) - x0.col(i);
    if (in_sleeve[std::size_t(i)])
      off_offset = std::max(off_offset, (d - drape::Vec3<double>(0.06, -0.02, 0.01)).norm());
    else
      others_moved = std::max(others_moved, d.norm());
  }
  CHECK(sleeve.size() > 20);
  CHECK(off_offset < 1e-12);
  CHECK(others_moved == 0);
  CHECK(moved.cloth.mesh->rest_uv == plain.cloth.mesh->rest_uv);  // the panel's shape is its pattern's

  CHECK_THAT(error_of(dir, garment + "[panel-offsets]\nleft_sleeve = [0.06, 0.0, 0.0]\n"),
             Contains("[panel-offsets] left_sleeve") && Contains("left_sleeve_f") && Contains("right_btorso"));
  CHECK_THAT(error_of(dir, garment + "[panel-offsets]\nleft_sleeve_f = [0.06, 0.0]\n"),
             Contains("panel-offsets.left_sleeve_f"));
  CHECK_THAT(error_of(dir, garment + "[panel-offsets]\nleft_sleeve_f = [0.06, nan, 0.0]\n"),
             Contains("panel-offsets.left_sleeve_f") && Contains("finite"));
  CHECK_THAT(error_of(dir, garment + "panel-offsets = 3\n"), Contains("panel-offsets") && Contains("table"));
  CHECK_THAT(error_of(dir, "shape = \"disk\"\n[panel-offsets]\nfront = [0.0, 0.0, 0.1]\n"),
             Contains("[panel-offsets] front") && Contains("without --pattern"));
  fs::remove_all(dir);
}
#endif

TEST_CASE("[[cloths]] with mesh keys: a disk and an OBJ cloth beside the grid, errors named by table and key",
          "[scene_file][mesh][cloths]") {
  const fs::path dir = fresh_dir("cloths_mesh");
  using Catch::Contains;
  std::ofstream(dir / "square.obj") << "v 0 0 0\nv 10 0 0\nv 10 0 10\nv 0 0 10\ng edge\nf 1 2 3 4\n";
  const std::string first = "nx = 5\nny = 5\nself-collision = true\n";
  const Settings s = read_text(dir, first +
                                        "[[cloths]]\nshape = \"disk\"\nradius = 0.2\nedge-length = 0.05\ndensity = 0.3\n"
                                        "pin-groups = [\"boundary\"]\nbending = 1e-4\nposition = [0.0, 1.0, 0.0]\n"
                                        "[[cloths]]\nmesh = \"square.obj\"\nscale = 0.01\nposition = [0.0, 0.5, 0.0]\n"
                                        "pin-box = [-0.01, 0.49, -0.01, 0.01, 0.51, 0.2]\n");
  const std::vector<drape::ClothSpecd> specs = cloth_specs(s, s.cloth);
  REQUIRE(specs.size() == 3);
  CHECK(!specs[0].mesh);
  const auto has_bending = [](const drape::ClothSpecd& spec) {
    for (const auto& term : spec.force_terms)
      if (term->name() == "dihedral bending") return true;
    return false;
  };
  REQUIRE(specs[1].mesh);
  CHECK(specs[1].mesh->positions == drape::disk_mesh(0.2, 0.05).positions);
  REQUIRE(specs[1].areal_density);
  CHECK(*specs[1].areal_density == 0.3);
  REQUIRE(specs[1].pinned_nodes);
  CHECK(specs[1].pinned_nodes->size() == specs[1].mesh->groups.at("boundary").size());
  CHECK(has_bending(specs[1]));
  REQUIRE(specs[2].mesh);
  CHECK(specs[2].mesh->quads.size() == 1);
  CHECK(!specs[2].areal_density);
  CHECK(!has_bending(specs[2]));
  CHECK(specs[2].pinned_nodes == std::vector<int>{0, 3});  // the two vertices at x = 0 (the box's edge)
  for (const drape::ClothSpecd& spec : specs) (void)drape::Clothd(spec);

  CHECK_THAT(error_of(dir, first + "[[cloths]]\nshape = \"disk\"\nedge-length = 0.0001\n"),
             Contains("cloths[0].edge-length") && Contains("at most 100000 vertices"));
  CHECK_THAT(error_of(dir, first + "[[cloths]]\nmesh = \"square.obj\"\npin-groups = [\"hem\"]\n"),
             Contains("cloths[0].pin-groups") && Contains("'hem'"));
  CHECK_THAT(error_of(dir, first + "[[cloths]]\nshape = \"hexagon\"\n"),
             Contains("cloths[0].shape") && Contains("grid | disk | rectangle-with-hole"));
  CHECK_THAT(error_of(dir, first + "[[cloths]]\nshape = \"rectangle-with-hole\"\nsize = [1.0]\n"),
             Contains("cloths[0].size") && Contains("2 numbers"));
  CHECK_THAT(error_of(dir, first + "[[cloths]]\nmesh = \"none.obj\"\n"), Contains("cloths[0].mesh") && Contains("none.obj"));
  CHECK_THAT(error_of(dir, first + "[[cloths]]\nshape = \"disk\"\nbending = -2.0\n"), Contains("cloths[0].bending"));
  fs::remove_all(dir);
}
