#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/io/usd.hpp"

namespace {

namespace fs = std::filesystem;

/// A fresh empty folder for one test case.
fs::path fresh_folder(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("drape_test_usd_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The files in `dir`, by name.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

/// A unit square of two triangles in the xz plane, lifted by `y`.
drape::Matrix3X<double> square(double y) {
  drape::Matrix3X<double> x(3, 4);
  x << 0, 1, 1, 0,  //
      y, y, y, y,   //
      0, 0, 1, 1;
  return x;
}

const std::vector<std::array<int, 3>> square_triangles = {{0, 1, 2}, {0, 2, 3}};

}  // namespace

TEST_CASE("a usda file holds fixed faces and one points sample per frame", "[usd]") {
  const fs::path dir = fresh_folder("format");
  const std::string path = (dir / "scene.usda").string();
  drape::UsdAnimationWriter usd(path, 30.0);
  const int cloth = usd.add_mesh("cloth", 4, square_triangles);
  // A quad face, a name that is no identifier.
  const int quad = usd.add_mesh("2 plane-quad", 4, std::vector<int>{4}, std::vector<int>{0, 1, 2, 3}, {false, {}});
  const int again = usd.add_mesh("cloth", 4, square_triangles);
  CHECK(usd.mesh_name(quad) == "_2_plane_quad");
  CHECK(usd.mesh_name(again) == "cloth_1");
  for (int frame = 0; frame < 3; ++frame) {
    usd.set_points(cloth, square(0.5 * frame));
    usd.set_points(quad, square(0.1));
    usd.set_points(again, square(1.0 / 3.0).cast<float>());
    usd.end_frame();
  }
  REQUIRE(usd.frame_count() == 3);
  REQUIRE_FALSE(fs::exists(path));  // written by finish() only
  usd.finish();
  const std::string text = read_text(path);
  CHECK(text.rfind("#usda 1.0\n(\n    defaultPrim = \"drape\"\n    endTimeCode = 2\n    framesPerSecond = 30\n"
                   "    metersPerUnit = 1\n    startTimeCode = 0\n    timeCodesPerSecond = 30\n    upAxis = \"Y\"\n)\n\n"
                   "def Xform \"drape\"\n{\n    def Mesh \"cloth\"\n    {\n",
                   0) == 0);
  using Catch::Matchers::Contains;
  CHECK_THAT(text, Contains("        int[] faceVertexCounts = [3, 3]\n"
                            "        int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]\n"
                            "        point3f[] points.timeSamples = {\n"
                            "            0: [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)],\n"
                            "            1: [(0, 0.5, 0), (1, 0.5, 0), (1, 0.5, 1), (0, 0.5, 1)],\n"
                            "            2: [(0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)],\n"
                            "        }\n"));
  CHECK_THAT(text, Contains("        float3[] extent.timeSamples = {\n"
                            "            0: [(0, 0, 0), (1, 0, 1)],\n"
                            "            1: [(0, 0.5, 0), (1, 0.5, 1)],\n"));
  // A mesh that does not move: its points and extent once, for every time code.
  CHECK_THAT(text, Contains("    def Mesh \"_2_plane_quad\"\n    {\n        uniform bool doubleSided = false\n"
                            "        float3[] extent = [(0, 0.100000001, 0), (1, 0.100000001, 1)]\n"
                            "        int[] faceVertexCounts = [4]\n        int[] faceVertexIndices = [0, 1, 2, 3]\n"
                            "        point3f[] points = [(0, 0.100000001, 0), (1, 0.100000001, 0), (1, 0.100000001, 1), "
                            "(0, 0.100000001, 1)]\n"));
  // Single precision with max_digits10 digits: 1/3 as the float nearest to it.
  CHECK_THAT(text, Contains("        point3f[] points = [(0, 0.333333343, 0), (1, 0.333333343, 0),"));
  CHECK(std::stof("0.333333343") == float(1.0 / 3.0));
  CHECK_THAT(text, Contains("        uniform token subdivisionScheme = \"none\"\n    }\n"));
  CHECK(text.substr(text.size() - 8) == "    }\n}\n");
  CHECK(files_in(dir) == std::vector<std::string>{"scene.usda"});  // no temporary file left
  fs::remove_all(dir);
}

TEST_CASE("a usda writer refuses points that are not finite and leaves no file", "[usd]") {
  const fs::path dir = fresh_folder("nan");
  const std::string path = (dir / "scene.usda").string();
  std::ofstream(path) << "an earlier file\n";
  {
    drape::UsdAnimationWriter usd(path, 60.0);
    const int cloth = usd.add_mesh("cloth", 4, square_triangles);
    usd.set_points(cloth, square(0));
    usd.end_frame();
    drape::Matrix3X<double> x = square(0);
    x(1, 2) = std::numeric_limits<double>::quiet_NaN();
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(usd.set_points(cloth, x), Contains("cloth") && Contains("point 2 of frame 1") &&
                                                    Contains("nan") && Contains("finite"));
    x(1, 2) = 1e39;  // finite as a double, infinite as a float
    CHECK_THROWS_AS(usd.set_points(cloth, x), drape::InvalidParameter);
    x(1, 2) = -std::numeric_limits<double>::infinity();
    CHECK_THROWS_AS(usd.set_points(cloth, x), drape::InvalidParameter);
    CHECK_THROWS_AS(usd.set_points(cloth, square(0).leftCols(3)), drape::InvalidParameter);
    CHECK_THROWS_AS(usd.end_frame(), std::logic_error);  // the cloth has no points in frame 1
  }  // never finished
  CHECK(read_text(path) == "an earlier file\n");
  CHECK(files_in(dir) == std::vector<std::string>{"scene.usda"});
  fs::remove_all(dir);
}

TEST_CASE("a usda file that cannot be written is not written at all", "[usd]") {
  const fs::path dir = fresh_folder("fail");
  // The target is a folder: the file cannot take its place.
  const fs::path target = dir / "scene.usda";
  fs::create_directories(target / "inside");
  drape::UsdAnimationWriter usd(target.string(), 30.0);
  const int cloth = usd.add_mesh("cloth", 4, square_triangles);
  usd.set_points(cloth, square(0));
  usd.end_frame();
  CHECK_THROWS_AS(usd.finish(), drape::FileWriteError);
  CHECK(fs::is_directory(target / "inside"));
  CHECK(files_in(dir) == std::vector<std::string>{"scene.usda"});  // no temporary file left
  // A folder that does not exist fails when the writer is made, before any frame.
  CHECK_THROWS_AS(drape::UsdAnimationWriter((dir / "missing" / "scene.usda").string(), 30.0), drape::FileWriteError);
  fs::remove_all(dir);
}

TEST_CASE("a usda writer checks its meshes' faces and frame rate", "[usd]") {
  const fs::path dir = fresh_folder("checks");
  const std::string path = (dir / "scene.usda").string();
  using Catch::Matchers::Contains;
  CHECK_THROWS_AS(drape::UsdAnimationWriter(path, 0.0), drape::InvalidParameter);
  CHECK_THROWS_AS(drape::UsdAnimationWriter(path, std::nan("")), drape::InvalidParameter);
  drape::UsdAnimationWriter usd(path, 24.0);
  CHECK_THROWS_WITH(usd.add_mesh("cloth", 3, square_triangles), Contains("'cloth'") && Contains("[0, 2]"));
  CHECK_THROWS_WITH(usd.add_mesh("cloth", 4, std::vector<int>{3, 2}, std::vector<int>{0, 1, 2, 0, 2}),
                    Contains("face 1") && Contains(">= 3"));
  CHECK_THROWS_WITH(usd.add_mesh("cloth", 4, std::vector<int>{3}, std::vector<int>{0, 1, 2, 3}),
                    Contains("4 indices") && Contains("3"));
  CHECK_THROWS_AS(usd.finish(), std::logic_error);  // no mesh, no frame
  CHECK(drape::usd_identifier("") == "mesh");
  CHECK(drape::usd_identifier("cloths[1]") == "cloths_1_");
  fs::remove_all(dir);
}
