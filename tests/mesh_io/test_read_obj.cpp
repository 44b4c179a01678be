// The OBJ reader (drape::mesh_io, docs/mesh.md): quad and triangle meshes, groups, a uv pattern as
// the rest shape, the scale; every defect of a file rejected with the file, the line and the element.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "drape/mesh_io/read_obj.hpp"

namespace fs = std::filesystem;
using namespace drape;
using namespace drape::mesh_io;
using Catch::Matchers::Contains;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("drape_test_mesh_io_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Writes `text` (bytes as given: no newline translation) to dir/file and returns the path.
std::string write(const fs::path& dir, const std::string& file, const std::string& text) {
  std::ofstream(dir / file, std::ios::binary) << text;
  return (dir / file).string();
}

struct Failure {
  std::string message;
  int line = -1;
};

/// The ObjError read_obj() throws for `path`; an empty message if it reads the file.
template <class S = double>
Failure failure_of(const std::string& path, const ObjOptions& options = {}) {
  try {
    (void)read_obj<S>(path, options);
  } catch (const ObjError& e) { return {e.what(), e.line()}; }
  return {};
}

// 3 x 3 vertices one unit apart in the plane y = 0, 2 x 2 quads.
const std::string quad_mesh = R"(# a 2 x 2 patch
v 0 0 0
v 1 0 0
v 2 0 0
v 0 0 1
v 1 0 1
v 2 0 1
v 0 0 2
v 1 0 2
v 2 0 2
f 1 4 5 2
f 2 5 6 3
f 4 7 8 5
f 5 8 9 6
)";

// Two squares side by side, two triangles each, in an object and two groups (one with two names).
const std::string grouped_triangles = R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
o cloth
g left
f 1 2 3
f 1 3 4
g right hem
f 2 5 6
f 2 6 3
)";

// A square folded in 3D whose pattern is the flat uv square of side 2 (vertex 1 has its uv twice,
// with the same value: not a seam).
const std::string folded_with_uv = R"(v 0 0 0
v 1 0 0
v 1 0.5 0.8
v 0 0.5 0.8
vt 0 0
vt 2 0
vt 2 2
vt 0 2
vt 0 0
vn 0 0 1
f 1/1/1 2/2/1 3/3/1
f 1/5 3/3 4/4
)";

}  // namespace

TEMPLATE_TEST_CASE("a quad mesh: the vertices in file order and the faces as quads", "[mesh_io]", float, double) {
  using S = TestType;
  const fs::path dir = fresh_dir("quads");
  const MeshRead<S> read = read_obj<S>(write(dir, "patch.obj", quad_mesh));
  const ClothMesh<S>& mesh = read.mesh;
  REQUIRE(mesh.vertex_count() == 9);
  CHECK(mesh.triangles.empty());
  REQUIRE(mesh.quads.size() == 4);
  CHECK(mesh.quads[0] == std::array<int, 4>{0, 3, 4, 1});
  CHECK(mesh.quads[3] == std::array<int, 4>{4, 7, 8, 5});
  CHECK(mesh.positions.col(5) == Vec3<S>(2, 0, 1));
  CHECK(mesh.rest_uv.cols() == 0);
  CHECK(mesh.groups.empty());
  CHECK(read.warnings.empty());
  CHECK(mesh.vertex_areas().sum() == Approx(4.0));
}

TEMPLATE_TEST_CASE("scale: positions are the file's coordinates times the metres per unit", "[mesh_io]", float,
                   double) {
  using S = TestType;
  const fs::path dir = fresh_dir("scale");
  ObjOptions options;
  options.scale = 0.25;
  const ClothMesh<S> mesh = read_obj<S>(write(dir, "patch.obj", quad_mesh), options).mesh;
  CHECK(mesh.positions.col(8) == Vec3<S>(0.5, 0, 0.5));
  CHECK(mesh.vertex_areas().sum() == Approx(0.25));
}

TEST_CASE("a triangle mesh with groups: each g and o name holds the vertices of its faces", "[mesh_io]") {
  const fs::path dir = fresh_dir("groups");
  const ClothMesh<double> mesh = read_obj(write(dir, "two_squares.obj", grouped_triangles)).mesh;
  REQUIRE(mesh.triangles.size() == 4);
  CHECK(mesh.quads.empty());
  CHECK(mesh.triangles[2] == std::array<int, 3>{1, 4, 5});
  const std::map<std::string, std::vector<int>> groups{
      {"cloth", {0, 1, 2, 3, 4, 5}}, {"left", {0, 1, 2, 3}}, {"right", {1, 2, 4, 5}}, {"hem", {1, 2, 4, 5}}};
  CHECK(mesh.groups == groups);

  // An `o` line starts outside any group: the second object's face is not in `top`. A `g` line
  // without a name ends the groups; an object's name is the rest of its line, trimmed.
  const std::string two_objects =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 2 0\no a\ng top\nf 1 2 3\no  b c \nf 1 3 4\ng \nf 4 3 5\n";
  const std::map<std::string, std::vector<int>> expected{
      {"a", {0, 1, 2}}, {"top", {0, 1, 2}}, {"b c", {0, 2, 3, 4}}};
  CHECK(read_obj(write(dir, "two_objects.obj", two_objects)).mesh.groups == expected);
}

TEMPLATE_TEST_CASE("rest_from_uv: the vt coordinates times uv_scale are the flat pattern of the rest shape",
                   "[mesh_io]", float, double) {
  using S = TestType;
  const fs::path dir = fresh_dir("uv");
  const std::string path = write(dir, "folded.obj", folded_with_uv);
  ObjOptions options;
  options.rest_from_uv = true;
  options.uv_scale = 0.5;
  const ClothMesh<S> mesh = read_obj<S>(path, options).mesh;
  REQUIRE(mesh.rest_uv.cols() == 4);
  Matrix2X<S> pattern(2, 4);
  pattern << 0, 1, 1, 0, 0, 0, 1, 1;
  CHECK(mesh.rest_uv == pattern);
  CHECK(mesh.positions.col(2) == Vec3<S>(1, S(0.5), S(0.8)));  // the start stays folded
  CHECK(mesh.vertex_areas().sum() == Approx(1.0));              // the pattern's area

  // Without the option the uv are not read: the rest shape is the folded square.
  const ClothMesh<S> as_is = read_obj<S>(path).mesh;
  CHECK(as_is.rest_uv.cols() == 0);
  CHECK(as_is.vertex_areas().sum() == Approx(std::sqrt(0.89)));
}

TEST_CASE("relative and forward indices, CRLF lines and unused vertices", "[mesh_io]") {
  const fs::path dir = fresh_dir("indices");
  // -3 -2 -1: the last three vertices before the face; 4 is defined after its face.
  const std::string text = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf -3 -2 -1\r\nf 2 4 3\r\nv 1 1 0\r\nv 5 5 5\r\n";
  const std::string path = write(dir, "relative.obj", text);
  const MeshRead<double> read = read_obj(path);
  REQUIRE(read.mesh.triangles.size() == 2);
  CHECK(read.mesh.triangles[0] == std::array<int, 3>{0, 1, 2});
  CHECK(read.mesh.triangles[1] == std::array<int, 3>{1, 3, 2});
  // Vertex 5 belongs to no face: a warning naming the file, and the mesh keeps it.
  REQUIRE(read.warnings.size() == 1);
  CHECK_THAT(read.warnings[0], Contains(path) && Contains("belong to no face"));
  CHECK(read.mesh.vertex_count() == 5);
}

TEST_CASE("parse_obj reads text in memory under the name it is given", "[mesh_io]") {
  CHECK(parse_obj<float>(quad_mesh, "patch").mesh.quads.size() == 4);
  try {
    (void)parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "memory");
    FAIL("a face of two corners is read");
  } catch (const ObjError& e) {
    CHECK(e.path() == "memory");
    CHECK(e.line() == 4);
    CHECK(e.parameter() == "memory:4 (face 1)");
    CHECK(e.value() == "2 corners");
  }
}

TEST_CASE("a file that cannot be read and bad options are rejected", "[mesh_io]") {
  const fs::path dir = fresh_dir("unreadable");
  const std::string missing = (dir / "missing.obj").string();
  const Failure none = failure_of(missing);
  CHECK_THAT(none.message, Contains("'" + missing + "'") && Contains("cannot be opened (No such file"));
  CHECK(none.line == 0);
  const Failure directory = failure_of(dir.string());
  CHECK_THAT(directory.message, Contains("'" + dir.string() + "'") && Contains("cannot be read (Is a directory)"));

  const std::string path = write(dir, "patch.obj", quad_mesh);
  ObjOptions options;
  options.scale = 0;
  CHECK_THROWS_WITH(read_obj(path, options), Contains("'ObjOptions::scale' = 0") && Contains("> 0"));
  options.scale = 1;
  options.uv_scale = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(read_obj(path, options), Contains("'ObjOptions::uv_scale' = nan"));
}

namespace {

struct BadFile {
  const char* name;
  std::string text;
  bool rest_from_uv;
  int line;              // of the defect
  std::string element;   // the parameter after the file's path
  std::string value;     // part of the rejected value
  std::string allowed;   // part of the allowed values
};

const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";        // lines 1-3
const std::string square = triangle + "v 1 1 0\n";                  // lines 1-4
const std::string square_uv = square + "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n";  // lines 1-8

const std::vector<BadFile> bad_files{
    // What the reader checks, at the line.
    {"index past the vertices", triangle + "f 1 2 9\n", false, 4, ":4 (face 1)", "corner 3: vertex index 9",
     "1 to 3 (the file's vertices)"},
    {"index 0", triangle + "f 1 0 2\n", false, 4, ":4 (face 1)", "corner 2: vertex index 0", "vertex indices from 1"},
    {"not a number", triangle + "f 1 2 x\n", false, 4, ":4 (face 1)", "corner 3: vertex index 0 (or not a number)",
     "from 1"},
    {"relative index before the first vertex", triangle + "f -1 -2 -4\n", false, 4, ":4 (face 1)",
     "corner 3: vertex index -4", "from -1 (the last before the face) down to -3"},
    {"nan coordinate", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", false, 2, ":2 (vertex 2)", "the number 'nan'",
     "x y z as finite numbers"},
    {"inf coordinate", "v 0 0 0\nv 1 0 0\nv 0 -inf 0\nf 1 2 3\n", false, 3, ":3 (vertex 3)", "the number '-inf'",
     "finite numbers"},
    {"coordinate that overflows", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", false, 1, ":1 (vertex 1)",
     "the number '1e999' (read as inf)", "finite numbers"},
    {"coordinate tinyobjloader reads as nan", "v 0 0 0\nv 0e1000 0 0\nv 0 1 0\nf 1 2 3\n", false, 2,
     ":2 (vertex 2)", "'0e1000' (read as nan)", "finite numbers"},
    {"coordinate with a unit", "v 0 0 0\nv 1cm 0 0\nv 0 1 0\nf 1 2 3\n", false, 2, ":2 (vertex 2)",
     "the number '1cm'", "finite numbers"},
    {"exponent past the int range", "v 0 0 0\nv 1 0 0\nv 0 1e2147483648 0\nf 1 2 3\n", false, 3, ":3 (vertex 3)",
     "the number '1e2147483648' (read as ", "finite numbers"},
    {"CRLF lines", "v 0 0 0\r\nv 1 0 0\r\nv nan 0 0\r\nf 1 2 3\r\n", false, 3, ":3 (vertex 3)", "'nan'", "finite"},
    {"CR lines", "v 0 0 0\rv nan 0 0\rv 0 1 0\rf 1 2 3\r", false, 2, ":2 (vertex 2)", "'nan'", "finite"},
    {"two coordinates", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", false, 2, ":2 (vertex 2)", "2 of 3 numbers", "x y z"},
    {"face of two corners", triangle + "f 1 2 3\nf 1 2\n", false, 5, ":5 (face 2)", "2 corners",
     "3 (a triangle) or 4 (a quad)"},
    {"face of one corner", triangle + "f 1\n", false, 4, ":4 (face 1)", "1 corner", "3 (a triangle) or 4"},
    {"polygon of five corners", square + "v 2 0 0\nf 1 2 5 4 3\n", false, 6, ":6 (face 1)", "5 corners",
     "larger polygons are split"},
    // What ClothMesh::validate() rejects, at the line of the face or vertex.
    {"degenerate triangle", triangle + "v 2 0 0\nf 1 2 3\nf 1 4 2\n", false, 6, ":6 (face 2: triangles[1])",
     "degenerate (zero-area) triangle", "faces of positive area"},
    {"corner twice", triangle + "f 1 2 2\n", false, 4, ":4 (face 1: triangles[0])", "vertex 1 twice",
     "distinct corners"},
    {"non-manifold edge", square + "v 1 -1 0\nf 1 2 3\nf 2 1 5\nf 1 2 4\n", false, 8, ":8 (face 3: triangles[2])",
     "of a third face (non-manifold)", "at most two faces"},
    {"inconsistent orientation", square + "f 1 2 3\nf 2 3 4\n", false, 6, ":6 (face 2: triangles[1])",
     "edge (1, 2) run the same way as by triangles[0] (inconsistent orientation)", "opposite directions"},
    {"quad against a triangle", square + "f 2 4 3\nf 1 2 4 3\n", false, 6, ":6 (face 2: quads[0])",
     "edge (1, 3) run the same way as by triangles[0]", "opposite directions"},
    {"empty mesh", triangle, false, 0, " (mesh)", "3 vertices and 0 triangles", "at least one face"},
    {"empty file", "", false, 0, " (mesh)", "0 vertices", "at least one face"},
    // A pattern from the uv.
    {"uv seam", square_uv + "vt 5 5\nf 1/1 2/2 4/4\nf 1/1 4/5 3/3\n", true, 11, ":11 (face 2)",
     "corner 2: vertex 4 with uv (5, 5) here and (1, 1) on line 10 (a seam of the uv layout)", "one uv per vertex"},
    {"corner without uv", square_uv + "f 1/1 2/2 4/4\nf 1/1 4 3/3\n", true, 10, ":10 (face 2)",
     "corner 2: no texture coordinate", "v/vt or v/vt/vn on every corner"},
    {"uv index past the texture coordinates", square_uv + "f 1/1 2/2 4/9\n", true, 9, ":9 (face 1)",
     "corner 3: texture coordinate index 9", "1 to 4 (the file's texture coordinates)"},
    {"nan uv", square + "vt 0 0\nvt nan 0\nvt 0 1\nf 1/1 2/2 3/3\n", true, 6, ":6 (texture coordinate 2)",
     "the number 'nan'", "u v as finite numbers"},
    {"uv of one number", square + "vt 0 0\nvt 1\nvt 0 1\nf 1/1 2/2 3/3\n", true, 6, ":6 (texture coordinate 2)",
     "1 of 2 numbers", "u v"},
    {"degenerate pattern", square_uv + "vt 2 0\nf 1/1 2/2 4/5\n", true, 10, ":10 (face 1: triangles[0])",
     "degenerate (zero-area) triangle in the rest shape", "positive area"},
};

}  // namespace

TEST_CASE("every defect of a file is rejected naming the file, the line and the element", "[mesh_io][errors]") {
  const fs::path dir = fresh_dir("bad");
  for (const BadFile& bad : bad_files) {
    INFO(bad.name);
    const std::string path = write(dir, "bad.obj", bad.text);
    ObjOptions options;
    options.rest_from_uv = bad.rest_from_uv;
    for (const Failure& failure : {failure_of<double>(path, options), failure_of<float>(path, options)}) {
      CHECK_THAT(failure.message, Contains("parameter '" + path + bad.element + "'") && Contains(bad.value) &&
                                      Contains("allowed: ") && Contains(bad.allowed));
      CHECK(failure.line == bad.line);
    }
  }
}

TEST_CASE("a uv seam is no defect when the rest shape is the 3D mesh", "[mesh_io][errors]") {
  const fs::path dir = fresh_dir("seam_as_is");
  const std::string path = write(dir, "seam.obj", square_uv + "vt 5 5\nf 1/1 2/2 4/4\nf 1/1 4/5 3/3\n");
  CHECK(read_obj(path).mesh.triangles.size() == 2);
}

TEMPLATE_TEST_CASE("coordinates that overflow once scaled or in float are found at their vertex's line", "[mesh_io]",
                   float, double) {
  using S = TestType;
  const fs::path dir = fresh_dir("overflow");
  const std::string path = write(dir, "big.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
  ObjOptions options;
  options.scale = 1e10;
  const Failure scaled = failure_of<S>(path, options);
  CHECK_THAT(scaled.message, Contains(path + ":2 (vertex 2: positions[1])") && Contains("non-finite coordinate"));
  CHECK(scaled.line == 2);
  if (std::is_same_v<S, float>) CHECK(failure_of<S>(path).line == 2);

  options.scale = 1;
  options.rest_from_uv = true;
  options.uv_scale = 1e300;
  const std::string uv_path = write(dir, "big_uv.obj", square_uv + "vt 1e10 0\nf 1/1 2/5 3/3\n");
  const Failure uv = failure_of<S>(uv_path, options);
  CHECK_THAT(uv.message, Contains(uv_path + ":9 (texture coordinate 5: rest_uv[1])"));
  CHECK(uv.line == 9);
}
