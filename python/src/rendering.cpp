// The rendering bindings: drape-render's offscreen renderer (drape::viewer, OSMesa) drawing
// cloths and their colliders to numpy images and PNG files, and SceneFile.renderer. Compiled when
// drape::viewer is built (python/CMakeLists.txt); rendering_unavailable.cpp otherwise.

#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bindings.hpp"
#include "drape/viewer/camera.hpp"
#include "drape/viewer/cloth_shape.hpp"
#include "drape/viewer/cloth_renderer.hpp"
#include "drape/viewer/collider_mesh.hpp"
#include "drape/viewer/offscreen_context.hpp"
#include "drape/viewer/png.hpp"
#include "files.hpp"
#include "helpers.hpp"

namespace drape::python {

using namespace nb::literals;

namespace {

// ---- rendering ----------------------------------------------------------------------------------

/// One OSMesa context for the process, current on the thread that made it (OSMesa contexts are
/// per thread; drape::viewer renders into its own framebuffers, so renderers can share it).
/// Never destroyed: it outlives the interpreter.
class GlContext {
 public:
  static void require_current() {
    static GlContext* context = new GlContext();
    if (std::this_thread::get_id() != context->m_thread)
      throw std::runtime_error(
          "drape: rendering happens on the thread that first rendered (OSMesa's context is "
          "current there only)");
  }
  static bool on_context_thread() { return instance_thread() && *instance_thread() == std::this_thread::get_id(); }

 private:
  GlContext() : m_thread(std::this_thread::get_id()) { instance_thread() = &m_thread; }
  static const std::thread::id*& instance_thread() {
    static const std::thread::id* thread = nullptr;
    return thread;
  }
  drape::viewer::OffscreenContext m_context;
  std::thread::id m_thread;
};

struct RenderOptions {
  int width = 640, height = 480, samples = 4;
  double azimuth = 25, elevation = 15;
  bool follow = true;
  bool floor = true;
  std::optional<double> floor_height;
};

/// Draws cloths and their colliders as drape-render draws them: the first cloth's colliders as
/// solids (the floor plane as the floor), a fixed camera or one that follows the cloths.
class Renderer {
 public:
  struct Source {
    const drape::Clothd* cloth;
    SharedState* state;
  };

  Renderer(std::vector<Source> sources, nb::object owner, const RenderOptions& options,
           std::optional<drape::viewer::Bounds> framed)
      : m_sources(std::move(sources)), m_owner(std::move(owner)), m_options(options) {
    check_options();
    GlContext::require_current();
    const float aspect = float(options.width) / float(options.height);
    const drape::Clothd& first = *m_sources.front().cloth;
    if (!framed) framed = default_framing();
    const double floor_y =
        options.floor_height ? *options.floor_height
        : plane_floor()
            ? *plane_floor()
            : double(drape::viewer::frame_bounds(*framed, aspect, float(options.azimuth), float(options.elevation))
                         .floor_height);
    drape::viewer::RenderSettings rs;
    rs.width = options.width;
    rs.height = options.height;
    rs.samples = options.samples;
    rs.floor = options.floor;
    rs.floor_cell = float(drape::viewer::longest_side(first) / 8.0);
    std::vector<std::array<float, 2>> pattern;
    std::vector<std::array<int, 3>> triangles;
    int offset = 0;
    for (const Source& s : m_sources) {
      const auto p = drape::viewer::checker_coordinates(*s.cloth);
      pattern.insert(pattern.end(), p.begin(), p.end());
      for (const std::array<int, 3>& t : s.cloth->triangles())
        triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
      offset += s.cloth->node_count();
    }
    m_renderer = std::make_unique<drape::viewer::ClothRenderer>(pattern, triangles, rs);
    m_fixed = drape::viewer::frame_bounds(*framed, aspect, float(options.azimuth), float(options.elevation));
    m_fixed.floor_height = float(floor_y);
    m_follow.emplace(aspect, float(options.azimuth), float(options.elevation), float(floor_y));
    m_renderer->set_camera(m_fixed);
    for (const drape::Colliderd& c : first.colliders()) {
      if (drape::scene_file::is_floor(c, floor_y)) continue;
      m_solids.push_back({&c, drape::viewer::local_collider_mesh(c)});
    }
    m_floor_y = floor_y;
  }

  ~Renderer() {
    // GL objects can only be deleted where the context is current; elsewhere they are left.
    if (m_renderer && !GlContext::on_context_thread()) (void)m_renderer.release();
  }

  /// Renders the sources' current positions; writes `path` (PNG) if given; returns the image.
  nb::ndarray<nb::numpy, std::uint8_t, nb::shape<-1, -1, 3>> render(const std::optional<std::string>& path) {
    GlContext::require_current();
    drape::Matrix3X<double> positions(3, node_count());
    Index offset = 0;
    for (const Source& s : m_sources) {
      positions.middleCols(offset, s.cloth->node_count()) = s.state->shared.positions;
      offset += s.cloth->node_count();
    }
    const double time = m_sources.front().state->shared.time;
    const double elapsed = m_previous_time ? time - *m_previous_time : 0.0;
    m_previous_time = time;
    std::vector<drape::viewer::SolidMesh> meshes;
    drape::viewer::Bounds box;
    for (const Solid& solid : m_solids) {
      if (solid.local.empty()) continue;  // planes: once the camera is known
      meshes.push_back(drape::viewer::place_mesh(solid.local, solid.collider->motion().pose(time)));
      drape::viewer::extend(box, meshes.back());
    }
    if (m_options.follow) {
      drape::Matrix3X<double> framed;
      drape::viewer::framed_points(positions, box, !meshes.empty(), framed);
      m_renderer->set_camera(m_follow->update(framed, elapsed));
    }
    const drape::viewer::Camera& cam = m_renderer->camera();
    for (const Solid& solid : m_solids)
      if (solid.local.empty())
        meshes.push_back(drape::viewer::plane_quad(*solid.collider, time, cam.target, 2.0f * cam.scene_radius));
    m_renderer->set_solids(meshes);
    m_renderer->update_positions(positions);
    auto* image = new drape::viewer::Image(m_renderer->render());
    nb::capsule owner(image, [](void* p) noexcept { delete static_cast<drape::viewer::Image*>(p); });
    if (path) drape::viewer::write_png(*path, *image);
    return {image->rgb.data(), {std::size_t(image->height), std::size_t(image->width), 3}, owner};
  }

  double floor_height() const { return m_floor_y; }
  int samples() const { return m_renderer->samples(); }

 private:
  struct Solid {
    const drape::Colliderd* collider;
    std::vector<Eigen::Vector3f> local;
  };

  void check_options() const {
    const auto in = [](const char* name, long long v, long long lo, long long hi) {
      drape::detail::require_in_range(name, v, lo, hi);
    };
    in("width", m_options.width, 16, 8192);
    in("height", m_options.height, 16, 8192);
    in("samples", m_options.samples, 1, 16);
    drape::detail::require_finite("azimuth", m_options.azimuth);
    if (!(m_options.elevation >= -85 && m_options.elevation <= 85))
      drape::detail::fail_argument("elevation", drape::detail::to_text(m_options.elevation), "[-85, 85] degrees");
    if (m_options.floor_height) drape::detail::require_finite("floor_height", *m_options.floor_height);
  }

  Index node_count() const {
    Index n = 0;
    for (const Source& s : m_sources) n += s.cloth->node_count();
    return n;
  }

  /// The highest static plane collider facing +y, drawn as the floor (drape-render's default).
  std::optional<double> plane_floor() const {
    std::optional<double> y;
    for (const drape::Colliderd& c : m_sources.front().cloth->colliders()) {
      const double height = c.motion().pose(0).translation.y();
      if (drape::scene_file::is_floor(c, height) && (!y || height > *y)) y = height;
    }
    return y;
  }

  /// Where the first cloth can hang from its pins, the other cloths where they are, the colliders now.
  drape::viewer::Bounds default_framing() const {
    const Source& first = m_sources.front();
    drape::viewer::Bounds box =
        drape::viewer::hanging_bounds(*first.cloth, first.state->shared.positions, first.cloth->pins().nodes());
    for (std::size_t k = 1; k < m_sources.size(); ++k) {
      const drape::Matrix3X<double>& x = m_sources[k].state->shared.positions;
      for (Index i = 0; i < x.cols(); ++i) box.extend(x.col(i).cast<float>());
    }
    for (const drape::Colliderd& c : first.cloth->colliders()) {
      const std::vector<Eigen::Vector3f> local = drape::viewer::local_collider_mesh(c);
      if (!local.empty())
        drape::viewer::extend(box, drape::viewer::place_mesh(local, c.motion().pose(first.state->shared.time)));
    }
    return box;
  }

  std::vector<Source> m_sources;
  nb::object m_owner;  // keeps the cloths and states alive
  RenderOptions m_options;
  std::unique_ptr<drape::viewer::ClothRenderer> m_renderer;
  drape::viewer::Camera m_fixed;
  std::optional<drape::viewer::FollowCamera> m_follow;
  std::vector<Solid> m_solids;
  std::optional<double> m_previous_time;
  double m_floor_y = 0;
};

RenderOptions render_options(int width, int height, int samples, double azimuth, double elevation,
                             const std::string& camera, bool floor, std::optional<double> floor_height) {
  if (camera != "follow" && camera != "fixed")
    drape::detail::fail_argument("camera", "'" + camera + "'", "follow | fixed");
  return {width, height, samples, azimuth, elevation, camera == "follow", floor, floor_height};
}

std::vector<Renderer::Source> scene_sources(PyClothScene& scene) {
  std::vector<Renderer::Source> sources;
  for (int k = 0; k < scene.scene().cloth_count(); ++k) sources.push_back({&scene.scene().cloth(k), &scene.state(k)});
  return sources;
}

}  // namespace

void bind_rendering(nb::module_& m) {
  // A method of SceneFile (bind_scene_files()), after its others.
  nb::cpp_function_def(
      [](const SceneFile& f, nb::handle_t<PyClothScene> scene) {
        const drape::scene_file::Output& o = f.settings->output;
        RenderOptions options{o.width,     o.height,          o.samples,
                              o.azimuth,   o.elevation,       o.camera == drape::scene_file::CameraMode::Follow,
                              !o.no_floor, f.prepared.floor_y};
        return new Renderer(scene_sources(nb::cast<PyClothScene&>(scene)), nb::borrow(scene), options,
                            f.prepared.framed);
      },
      nb::scope(nb::type<SceneFile>()), nb::name("renderer"), nb::is_method(), "scene"_a,
      "A Renderer of `scene` with the file's image size, camera and floor, framed as drape-render frames.");

  nb::class_<Renderer>(m, "Renderer",
                       "drape-render's offscreen renderer (OSMesa, no display): cloths, their colliders and a floor, "
                       "to numpy images and PNG files. Renders on the thread that first rendered.")
      .def(
          "__init__",
          [](Renderer* self, nb::handle_t<PyClothScene> scene, int width, int height, int samples, double azimuth,
             double elevation, const std::string& camera, bool floor, std::optional<double> floor_height) {
            new (self) Renderer(scene_sources(nb::cast<PyClothScene&>(scene)), nb::borrow(scene),
                                render_options(width, height, samples, azimuth, elevation, camera, floor, floor_height),
                                std::nullopt);
          },
          "scene"_a, nb::kw_only(), "width"_a = 640, "height"_a = 480, "samples"_a = 4, "azimuth"_a = 25.0,
          "elevation"_a = 15.0, "camera"_a = "follow", "floor"_a = true, "floor_height"_a = nb::none(),
          "Draws every cloth of a ClothScene. camera: 'follow' (frames the cloths each render, smoothed over "
          "simulated time) or 'fixed' (frames where the first cloth can hang, once).")
      .def(
          "__init__",
          [](Renderer* self, nb::handle_t<drape::Clothd> cloth, nb::handle_t<SharedState> state, int width, int height,
             int samples, double azimuth, double elevation, const std::string& camera, bool floor,
             std::optional<double> floor_height) {
            const drape::Clothd& c = nb::cast<const drape::Clothd&>(cloth);
            SharedState& s = nb::cast<SharedState&>(state);
            if (s.node_count() != c.node_count())
              drape::detail::fail_argument("state", std::to_string(s.node_count()) + " nodes",
                                           std::to_string(c.node_count()) + " nodes (the cloth's)");
            new (self) Renderer({{&c, &s}}, nb::make_tuple(cloth, state),
                                render_options(width, height, samples, azimuth, elevation, camera, floor, floor_height),
                                std::nullopt);
          },
          "cloth"_a, "state"_a, nb::kw_only(), "width"_a = 640, "height"_a = 480, "samples"_a = 4, "azimuth"_a = 25.0,
          "elevation"_a = 15.0, "camera"_a = "follow", "floor"_a = true, "floor_height"_a = nb::none(),
          "Draws one cloth in `state` (read at each render).")
      .def("render", &Renderer::render, "path"_a = nb::none(),
           "Renders the current positions; writes a PNG atomically if `path` is given (FileWriteError if it cannot). "
           "Returns the image, (height, width, 3) uint8, row 0 at the top.")
      .def_prop_ro("floor_height", &Renderer::floor_height, "m: y of the floor drawn.")
      .def_prop_ro("samples", &Renderer::samples, "MSAA samples in use.");
}

}  // namespace drape::python
