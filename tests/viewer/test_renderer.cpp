#include <catch2/catch.hpp>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "drape/integrators/rk2.hpp"
#include "drape/io/atomic_file.hpp"
#include "drape/model/cloth.hpp"
#include "drape/viewer/camera.hpp"
#include "drape/viewer/cloth_renderer.hpp"
#include "drape/viewer/collider_mesh.hpp"
#include "drape/viewer/offscreen_context.hpp"
#include "drape/viewer/png.hpp"

namespace fs = std::filesystem;
using namespace drape::viewer;

namespace {

constexpr int width = 64, height = 48;

drape::ClothSpec<double> small_cloth() {
  drape::ClothSpec<double> spec;
  spec.nx = 9;
  spec.ny = 9;
  return spec;
}

/// The flat grid bent into a dome: normals vary, so a Lambert shader must give many shades.
drape::Matrix3X<double> dome(const drape::Cloth<double>& cloth, double height_m) {
  drape::Matrix3X<double> x = cloth.grid().rest_positions();
  const double w = (cloth.grid().nx() - 1) * cloth.grid().spacing();
  for (drape::Index i = 0; i < x.cols(); ++i)
    x(1, i) = height_m * std::sin(M_PI * x(0, i) / w) * std::sin(M_PI * x(2, i) / w);
  return x;
}

RenderSettings plain_settings() {
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.floor = false;    // every non-background pixel is cloth
  rs.pattern = false;  // shading only from the lighting
  return rs;
}

struct Counts {
  int cloth = 0, front = 0, back = 0;
  std::set<int> shades;  // distinct luminances of cloth pixels
};

Counts classify(const Image& img, const RenderSettings& rs) {
  Counts c;
  const int bg[3] = {int(std::lround(rs.background.x() * 255)), int(std::lround(rs.background.y() * 255)),
                     int(std::lround(rs.background.z() * 255))};
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      if (std::abs(p[0] - bg[0]) + std::abs(p[1] - bg[1]) + std::abs(p[2] - bg[2]) <= 6) continue;
      ++c.cloth;
      if (p[0] > p[2] + 10) ++c.front;  // front colour is red-dominant
      if (p[2] > p[0] + 10) ++c.back;   // back colour is blue-dominant
      c.shades.insert((299 * p[0] + 587 * p[1] + 114 * p[2]) / 1000);
    }
  return c;
}

Image render(ClothRenderer& r, const drape::Cloth<double>& cloth, const drape::Matrix3X<double>& x, float elevation) {
  Bounds b;
  for (drape::Index i = 0; i < x.cols(); ++i) b.extend(x.col(i).cast<float>());
  r.set_camera(frame_bounds(b, float(width) / float(height), 30.0f, elevation));
  r.update_positions(x);
  (void)cloth;
  return r.render();
}

struct DebugLog {
  std::vector<std::string> errors, all;
  GlDebugSink sink() {
    return [this](const std::string& severity, const std::string& type, const std::string& text) {
      all.push_back(severity + " " + type + " " + text);
      if (type == "error") errors.push_back(text);
    };
  }
};

}  // namespace

TEST_CASE("offscreen render: cloth present, shaded, front from above and back from below", "[viewer]") {
  DebugLog log;
  OffscreenContext context(log.sink());
  REQUIRE(context.version().find("Core Profile") != std::string::npos);
  const drape::Cloth<double> cloth(small_cloth());
  const RenderSettings rs = plain_settings();
  ClothRenderer renderer(cloth.grid().nx(), cloth.grid().ny(), cloth.grid().triangles(), rs);
  const drape::Matrix3X<double> x = dome(cloth, 0.3);

  const Counts above = classify(render(renderer, cloth, x, 40.0f), rs);
  INFO("above: cloth " << above.cloth << " front " << above.front << " back " << above.back << " shades "
                       << above.shades.size());
  REQUIRE(above.cloth > width * height / 10);  // the camera frames it: a good part of the image
  REQUIRE(above.front > 0.9 * above.cloth);   // the top side, in the front colour
  REQUIRE(above.shades.size() >= 15);         // Lambert shading, not one flat colour

  const Counts below = classify(render(renderer, cloth, x, -40.0f), rs);
  INFO("below: cloth " << below.cloth << " front " << below.front << " back " << below.back << " shades "
                       << below.shades.size());
  REQUIRE(below.cloth > width * height / 10);  // visible from below: no face culling
  REQUIRE(below.back > 0.9 * below.cloth);     // the underside, in the back colour, lit too
  REQUIRE(below.shades.size() >= 15);
  REQUIRE(log.errors.empty());  // the renderer itself raises no GL errors
}

TEST_CASE("different states give different images, the same state the same image", "[viewer]") {
  OffscreenContext context;
  const drape::Cloth<double> cloth(small_cloth());
  RenderSettings rs = plain_settings();
  rs.floor = true;
  rs.pattern = true;
  ClothRenderer renderer(cloth.grid().nx(), cloth.grid().ny(), cloth.grid().triangles(), rs);
  const drape::Matrix3X<double> flat = cloth.grid().rest_positions();
  Bounds b;
  for (drape::Index i = 0; i < flat.cols(); ++i) b.extend(flat.col(i).cast<float>());
  b.extend(Eigen::Vector3f(0, -0.8f, 0));
  renderer.set_camera(frame_bounds(b, float(width) / float(height), 30.0f, 25.0f));
  renderer.update_positions(flat);
  const Image a = renderer.render();
  renderer.update_positions(dome(cloth, -0.5));
  const Image c = renderer.render();
  renderer.update_positions(flat);
  const Image a2 = renderer.render();
  int differing = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3)
    differing += a.rgb[i] != c.rgb[i] || a.rgb[i + 1] != c.rgb[i + 1] || a.rgb[i + 2] != c.rgb[i + 2];
  REQUIRE(differing > width * height / 20);
  REQUIRE(a.rgb == a2.rgb);  // positions are re-uploaded each frame; nothing else changes
}

TEST_CASE("--debug-gl: the KHR_debug callback reports GL errors", "[viewer]") {
  DebugLog log;
  OffscreenContext context(log.sink());
  REQUIRE(context.debug_enabled());
  glBindBuffer(GL_ARRAY_BUFFER, 987654u);  // never generated: GL_INVALID_OPERATION in a core profile
  REQUIRE(glGetError() == GL_INVALID_OPERATION);
  INFO("messages: " << log.all.size());
  REQUIRE(log.errors.size() == 1);
}

TEST_CASE("PNG frames appear atomically and decode to the rendered pixels", "[viewer]") {
  const fs::path dir = fs::temp_directory_path() / "drape_test_png_frames";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Image img;
  img.width = 37;  // odd width: no row padding assumptions
  img.height = 11;
  img.rgb.resize(37 * 11 * 3);
  for (std::size_t i = 0; i < img.rgb.size(); ++i) img.rgb[i] = static_cast<std::uint8_t>((i * 7919) % 251);
  for (int k = 0; k < 5; ++k) write_png((dir / ("frame_" + std::to_string(k) + ".png")).string(), img);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++files;
    const std::string name = entry.path().filename().string();
    INFO(name);
    REQUIRE(entry.path().extension() == ".png");  // no temporary names left behind
    const Image back = read_png(entry.path().string());
    REQUIRE(back.width == img.width);
    REQUIRE(back.height == img.height);
    REQUIRE(back.rgb == img.rgb);
  }
  REQUIRE(files == 5);

  SECTION("a folder that does not exist: a clear error, no file") {
    const std::string path = (dir / "missing" / "frame.png").string();
    REQUIRE_THROWS_AS(write_png(path, img), drape::FileWriteError);
    REQUIRE_THROWS_WITH(write_png(path, img), Catch::Contains("missing/frame.png"));
    REQUIRE(!fs::exists(path));
  }
  SECTION("the temporary file cannot be created: a clear error, no file") {
    // A directory where the temporary file should go cannot be opened as a file.
    fs::create_directories(dir / "frame_x.png.tmp");
    REQUIRE_THROWS_AS(write_png((dir / "frame_x.png").string(), img), drape::FileWriteError);
    REQUIRE(!fs::exists(dir / "frame_x.png"));
  }
  SECTION("not a PNG: read_png names the file") {
    std::FILE* f = std::fopen((dir / "junk.png").string().c_str(), "wb");
    std::fputs("not a png", f);
    std::fclose(f);
    REQUIRE_THROWS_WITH(read_png((dir / "junk.png").string()), Catch::Contains("junk.png"));
  }
  fs::remove_all(dir);
}

TEST_CASE("the follow camera keeps every node of a falling cloth inside the image", "[viewer][camera]") {
  drape::ClothSpec<double> spec;
  spec.nx = 12;
  spec.ny = 12;
  spec.spacing = 0.25;
  for (const drape::BoundaryCondition bc : {drape::BoundaryCondition::OneCorner, drape::BoundaryCondition::TwoCorners}) {
    spec.boundary = bc;
    const drape::Cloth<double> cloth(spec);
    drape::Rk2<double> rk2(cloth, {0.001, 1});
    for (const float elevation : {15.0f, -30.0f, 60.0f}) {
      drape::State<double> s = cloth.initial_state();
      FollowCamera follow(4.0f / 3.0f, 25.0f, elevation, -10.0f);
      int checked = 0;
      for (int frame = 0; frame < 45; ++frame) {  // 1.5 s at 30 fps: the fast fall and swing
        for (int k = 0; k < 33; ++k) REQUIRE(rk2.step(s).ok());
        const Camera cam = follow.update(s.positions, 0.033);
        const Eigen::Matrix4f m = cam.projection * cam.view;
        int outside = 0;
        for (drape::Index i = 0; i < s.positions.cols(); ++i) {
          const Eigen::Vector4f c = m * Eigen::Vector4f(float(s.positions(0, i)), float(s.positions(1, i)),
                                                       float(s.positions(2, i)), 1.0f);
          outside += !(c.w() > 0 && std::abs(c.x() / c.w()) <= 1.0f && std::abs(c.y() / c.w()) <= 1.0f);
          ++checked;
        }
        INFO("bc " << int(bc) << " elevation " << elevation << " frame " << frame);
        REQUIRE(outside == 0);
      }
      REQUIRE(checked == 45 * 144);
    }
  }
}

TEST_CASE("collider meshes: every vertex on the surface, faces outward, placed by the pose at t",
          "[viewer][colliders]") {
  using C = drape::Collider<double>;
  const drape::Mat3<double> tilt = Eigen::AngleAxisd(0.4, drape::Vec3<double>(1, 2, 3).normalized()).toRotationMatrix();
  struct Case {
    const char* name;
    C collider;
  };
  const Case cases[] = {
      {"sphere", C::sphere({1, 2, 3}, 0.7)},
      {"capsule", C::capsule({0, 0, 0}, {1, 1, 0}, 0.2)},
      {"box", C::box({0, -1, 0}, {0.5, 0.3, 0.8}, tilt)},
      {"rounded box", C::box({0, -1, 0}, {0.5, 0.3, 0.8}, tilt, 0.1)},
      {"fully rounded box", C::box({0, 0, 0}, {0.3, 0.3, 0.6}, drape::Mat3<double>::Identity(), 0.3)},
      {"moving sphere", C::sphere({1, 2, 3}, 0.5).moving({1, 0, -2}, {0, 3, 0})},
      {"spinning box", C::box({0, 1, 0}, {0.4, 0.2, 0.3}, tilt, 0.05).moving({0, 0, 0}, {1, 2, 0.5})},
      {"cylinder", C::cylinder({0, -1, 0}, 0.6, 0.1, tilt)},
      {"rounded cylinder", C::cylinder({1, 0, 0}, 0.5, 0.3, tilt, 0.1).moving({0, 1, 0}, {2, 0, 1})},
      {"cylinder with half-torus rims", C::cylinder({0, 0, 0}, 0.5, 0.2, drape::Mat3<double>::Identity(), 0.2)},
      {"cylinder rounded to a capsule", C::cylinder({0, 0, 0}, 0.3, 0.6, drape::Mat3<double>::Identity(), 0.3)},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    const std::vector<Eigen::Vector3f> local = local_collider_mesh(c.collider);
    REQUIRE(local.size() >= 36);  // a plain box: 2 triangles per face
    REQUIRE(local.size() % 3 == 0);
    for (double t : {0.0, 0.7}) {
      const SolidMesh mesh = place_mesh(local, c.collider.motion().pose(t));
      REQUIRE(mesh.vertices.size() == local.size() * 6);
      double worst = 0, least_alignment = 1;
      for (std::size_t k = 0; k < mesh.vertices.size(); k += 18) {  // one triangle
        drape::Vec3<double> centroid = drape::Vec3<double>::Zero();
        for (int v = 0; v < 3; ++v) {
          const drape::Vec3<double> p(mesh.vertices[k + 6 * v], mesh.vertices[k + 6 * v + 1],
                                      mesh.vertices[k + 6 * v + 2]);
          worst = std::max(worst, std::abs(c.collider.query(p, t).distance));
          centroid += p / 3;
        }
        const drape::Vec3<double> n(mesh.vertices[k + 3], mesh.vertices[k + 4], mesh.vertices[k + 5]);
        least_alignment = std::min(least_alignment, n.dot(c.collider.query(centroid, t).normal));
      }
      INFO("t = " << t << ", largest |distance| of a vertex " << worst << ", least n . normal " << least_alignment);
      REQUIRE(worst < 1e-5);            // on the surface (float precision)
      REQUIRE(least_alignment > 0.95);  // flat faces, outward
    }
  }
  REQUIRE(local_collider_mesh(C::plane({0, 0, 0}, {0, 1, 0})).empty());
  // A plane: a square on the plane around the point given, facing along the normal.
  const C slope = C::plane({0, -1, 0}, {1, 1, 0});
  const SolidMesh quad = plane_quad(slope, 0.0, Eigen::Vector3f(2, 3, 4), 5.0f);
  REQUIRE(!quad.casts_shadow);
  REQUIRE(quad.vertices.size() == 36);
  for (std::size_t k = 0; k < 36; k += 6) {
    const drape::Vec3<double> p(quad.vertices[k], quad.vertices[k + 1], quad.vertices[k + 2]);
    REQUIRE(std::abs(slope.query(p, 0.0).distance) < 1e-5);
    REQUIRE(quad.vertices[k + 3] == Approx(std::sqrt(0.5)).margin(1e-6));
  }
}

TEST_CASE("cylinder meshes: closed, outward, holding the solid's volume less the facets' chords",
          "[viewer][colliders]") {
  using C = drape::Collider<double>;
  constexpr double pi = 3.14159265358979323846;
  // Sharp, rounded, rims a half torus, a capsule.
  for (const auto& [rounding, h] : {std::pair{0.0, 0.2}, {0.05, 0.2}, {0.2, 0.2}, {0.3, 0.5}}) {
    INFO("rounding " << rounding << ", half height " << h);
    const double r = 0.3;
    const std::vector<Eigen::Vector3f> mesh =
        local_collider_mesh(C::cylinder({0, 0, 0}, r, h, drape::Mat3<double>::Identity(), rounding));
    // The volume by the divergence theorem: only a closed mesh with outward faces gives the solid's.
    double volume = 0;
    for (std::size_t k = 0; k + 2 < mesh.size(); k += 3)
      volume += double(mesh[k].dot(mesh[k + 1].cross(mesh[k + 2]))) / 6;
    // Pappus: 2 pi times the first moment about the axis of the profile (x >= 0): the rectangle
    // inside the rims, the side band beside it and the two quarter discs of the rims.
    const double a = r - rounding;
    const double moment = a * a * h + (r * r - a * a) * (h - rounding) +
                          2 * (a * pi * rounding * rounding / 4 + rounding * rounding * rounding / 3);
    const double exact = 2 * pi * moment;
    INFO("mesh volume " << volume << ", solid " << exact);
    CHECK(volume <= exact);
    CHECK(volume >= 0.995 * exact);
  }
  // A plain cylinder: 80 sides, each a quad of the side and a triangle of each cap.
  CHECK(local_collider_mesh(C::cylinder({0, 0, 0}, 1, 1)).size() == 3 * 80 * 4);
}

TEST_CASE("solids are drawn in their own colour, over the cloth where they are in front", "[viewer][colliders]") {
  OffscreenContext context;
  const drape::Cloth<double> cloth(small_cloth());
  const RenderSettings rs = plain_settings();
  ClothRenderer renderer(cloth.grid().nx(), cloth.grid().ny(), cloth.grid().triangles(), rs);
  const drape::Matrix3X<double> x = cloth.grid().rest_positions();
  Bounds b;
  for (drape::Index i = 0; i < x.cols(); ++i) b.extend(x.col(i).cast<float>());
  renderer.set_camera(frame_bounds(b, float(width) / float(height), 30.0f, 40.0f));
  renderer.update_positions(x);
  const Image without = renderer.render();
  // A box standing on the middle of the cloth, in front of it from every direction above.
  const drape::Collider<double> box =
      drape::Collider<double>::box(b.centre().cast<double>() + drape::Vec3<double>(0, 0.15, 0), {0.15, 0.15, 0.15});
  renderer.set_solids({place_mesh(local_collider_mesh(box), box.motion().pose(0.0))});
  const Image with = renderer.render();
  const std::uint8_t* centre = with.pixel(width / 2, height / 2);
  const std::uint8_t* cloth_centre = without.pixel(width / 2, height / 2);
  INFO("with the box " << int(centre[0]) << " " << int(centre[1]) << " " << int(centre[2]) << ", without "
                       << int(cloth_centre[0]) << " " << int(cloth_centre[1]) << " " << int(cloth_centre[2]));
  REQUIRE(cloth_centre[0] > cloth_centre[2] + 40);  // the red cloth
  REQUIRE(std::abs(centre[0] - centre[2]) < 20);    // a grey box
  REQUIRE(std::abs(centre[1] - centre[2]) < 20);
  int grey = 0, shades = 0;
  std::set<int> seen;
  for (int yy = 0; yy < height; ++yy)
    for (int xx = 0; xx < width; ++xx) {
      const std::uint8_t* p = with.pixel(xx, yy);
      if (std::abs(p[0] - p[2]) < 20 && std::abs(p[1] - p[2]) < 20 && p[0] < 220) {
        ++grey;
        seen.insert(p[0] / 8);
      }
    }
  shades = int(seen.size());
  REQUIRE(grey > 100);
  REQUIRE(shades >= 2);  // lit faces in different shades
  // No solids again: the image without them.
  renderer.set_solids({});
  const Image again = renderer.render();
  const bool same = again.rgb == without.rgb;
  REQUIRE(same);
}

TEST_CASE("a solid casts its shadow on the floor unless told not to", "[viewer][colliders]") {
  OffscreenContext context;
  const drape::Cloth<double> cloth(small_cloth());
  RenderSettings rs = plain_settings();
  rs.floor = true;
  ClothRenderer renderer(cloth.grid().nx(), cloth.grid().ny(), cloth.grid().triangles(), rs);
  // The cloth far off to the side; a sphere floating above the floor in the middle of the view.
  drape::Matrix3X<double> x = cloth.grid().rest_positions();
  x.row(0).array() += 50.0;
  renderer.update_positions(x);
  Bounds b;
  b.extend(Eigen::Vector3f(-1, -1, -1));
  b.extend(Eigen::Vector3f(1, 1, 1));
  renderer.set_camera(frame_bounds(b, float(width) / float(height), 30.0f, 50.0f));
  const drape::Collider<double> ball = drape::Collider<double>::sphere({0, 0.3, 0}, 0.4);
  SolidMesh mesh = place_mesh(local_collider_mesh(ball), ball.motion().pose(0.0));
  renderer.set_solids({mesh});
  const Image shadowed = renderer.render();
  mesh.casts_shadow = false;
  renderer.set_solids({mesh});
  const Image plain = renderer.render();
  int darker = 0;
  for (std::size_t k = 0; k < plain.rgb.size(); ++k) darker += shadowed.rgb[k] + 20 < plain.rgb[k];
  INFO(darker << " darker channels");
  REQUIRE(darker > 30);
}
