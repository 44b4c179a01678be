// Rendering in a drape built without OSMesa or libpng (no drape::viewer; python/CMakeLists.txt):
// SceneFile.renderer and Renderer exist with rendering.cpp's names and signatures (keep them in
// step), and each call raises RuntimeError saying what to install.

#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "helpers.hpp"

namespace drape::python {

using namespace nb::literals;

namespace {

[[noreturn]] void unavailable() {
  throw std::runtime_error(
      "drape: rendering is unavailable: drape was built without OSMesa/libpng. Install them (Debian: apt-get "
      "install libosmesa6-dev libpng-dev) and build drape again (pip install .)");
}

/// Never made: its constructors raise.
struct Renderer {};

using Image = nb::ndarray<nb::numpy, std::uint8_t, nb::shape<-1, -1, 3>>;

}  // namespace

void bind_rendering(nb::module_& m) {
  // A method of SceneFile (bind_scene_files()), after its others.
  nb::cpp_function_def([](nb::handle, nb::handle_t<PyClothScene>) -> Renderer* { unavailable(); },
                       nb::scope(m.attr("SceneFile")), nb::name("renderer"), nb::is_method(), "scene"_a,
                       "Unavailable: drape was built without OSMesa/libpng (raises RuntimeError).");

  nb::class_<Renderer>(m, "Renderer",
                       "drape-render's offscreen renderer, unavailable here: drape was built without OSMesa/libpng, "
                       "and every call raises RuntimeError.")
      .def(
          "__init__",
          [](Renderer*, nb::handle_t<PyClothScene>, int, int, int, double, double, const std::string&, bool,
             std::optional<double>) { unavailable(); },
          "scene"_a, nb::kw_only(), "width"_a = 640, "height"_a = 480, "samples"_a = 4, "azimuth"_a = 25.0,
          "elevation"_a = 15.0, "camera"_a = "follow", "floor"_a = true, "floor_height"_a = nb::none(),
          "Raises RuntimeError: rendering is unavailable.")
      .def(
          "__init__",
          [](Renderer*, nb::handle_t<drape::Clothd>, nb::handle_t<SharedState>, int, int, int, double, double,
             const std::string&, bool, std::optional<double>) { unavailable(); },
          "cloth"_a, "state"_a, nb::kw_only(), "width"_a = 640, "height"_a = 480, "samples"_a = 4, "azimuth"_a = 25.0,
          "elevation"_a = 15.0, "camera"_a = "follow", "floor"_a = true, "floor_height"_a = nb::none(),
          "Raises RuntimeError: rendering is unavailable.")
      .def(
          "render", [](Renderer&, const std::optional<std::string>&) -> Image { unavailable(); },
          "path"_a = nb::none(), "Raises RuntimeError: rendering is unavailable.")
      .def_prop_ro(
          "floor_height", [](const Renderer&) -> double { unavailable(); }, "Raises RuntimeError.")
      .def_prop_ro(
          "samples", [](const Renderer&) -> int { unavailable(); }, "Raises RuntimeError.");
}

}  // namespace drape::python
