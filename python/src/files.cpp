// The scene-and-files bindings: drape-render's scene files (the scene-file library,
// drape::scene_file), state files and OBJ meshes, and the errors reading and writing them raise.
// The only binding file that calls the scene-file library (files.hpp).

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/variant.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "drape/io/obj.hpp"
#include "drape/io/state_io.hpp"
#include "drape/scene_file/command_line.hpp"
#include "drape/scene_file/pin_schedule.hpp"
#include "files.hpp"
#include "helpers.hpp"

namespace drape::python {

using namespace nb::literals;

int SceneFile::frame_count() const {
  const drape::scene_file::TimeLine& t = settings->time;
  return t.duration_given ? std::max(1, static_cast<int>(std::ceil(t.duration / t.frame_time - 1e-9)) + 1) : t.frames;
}

namespace {

/// The triangles of an (m, 3) array of node ids.
std::vector<std::array<int, 3>> triangles_of(
    const nb::ndarray<const int, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>& a) {
  std::vector<std::array<int, 3>> triangles(a.shape(0));
  std::copy(a.data(), a.data() + 3 * a.shape(0), triangles.data()->data());
  return triangles;
}

// ---- scene files --------------------------------------------------------------------------------

SceneFile load_scene(const std::string& path, const std::vector<std::string>& flags) {
  auto settings = std::make_shared<const drape::scene_file::Settings>(drape::scene_file::read_settings(path, flags));
  SceneFile file;
  file.prepared = drape::scene_file::prepare_scene(*settings);
  file.settings = std::move(settings);
  return file;
}

/// The library's spec of a scene-file cloth as Python's ClothSpec: the air's force terms are
/// the air again (drape-render builds them from the same settings).
ClothSpecWithAir python_spec(const drape::ClothSpecd& spec, const drape::AirSettings& air) {
  ClothSpecWithAir out;
  static_cast<drape::ClothSpecd&>(out) = spec;
  out.force_terms.clear();
  out.air = air;
  return out;
}

/// A new scene of the file's cloths, starting where drape-render starts, its first cloth following
/// the file's [[moving-pins]] tables.
PyClothScene* make_scene(const SceneFile& f) {
  // The schedule keeps pointers into the settings: the step hook keeps both.
  std::shared_ptr<const drape::scene_file::Settings> settings = f.settings;
  auto schedule = std::make_shared<drape::scene_file::PinSchedule>(*settings);
  return new PyClothScene(f.prepared.specs, settings->integrator, settings->stepping, settings->cloth.self_collision,
                          f.prepared.start, [settings, schedule](drape::ClothScene<double>& scene) {
                            schedule->apply(scene.state(0).time, scene.integrator(0).dt(), scene.integrator(0).pins());
                          });
}

}  // namespace

// ---- the bindings -------------------------------------------------------------------------------

void bind_file_errors(nb::module_& m) {
  nb::exception<drape::scene_file::SettingsError>(m, "SceneFileError", PyExc_ValueError).attr("__doc__") =
      "A scene file or drape-render flag is invalid; the message names the key or flag.";
  nb::exception<drape::StateFormatError>(m, "StateFormatError", PyExc_ValueError).attr("__doc__") =
      "A state file is missing, truncated, corrupt or of another cloth; the message names the file.";
  nb::exception<drape::FileWriteError>(m, "FileWriteError", PyExc_OSError).attr("__doc__") =
      "An output file could not be written (no file is left behind); the message names it and the reason.";
}

void bind_io(nb::module_& m) {
  m.def(
      "write_obj",
      [](const std::string& path, const NodeInput& positions,
         const nb::ndarray<const int, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>& triangles) {
        const Eigen::Map<const drape::Matrix3X<double>> x(positions.data(), 3, Index(positions.shape(0)));
        drape::write_obj(path, x, triangles_of(triangles));
      },
      "path"_a, "positions"_a, "triangles"_a,
      "Writes an OBJ mesh atomically (complete or absent), coordinates with 17 digits (read back bit for "
      "bit); raises FileWriteError.");
  m.def(
      "save_state", [](const std::string& path, const SharedState& state) { drape::save_state(path, state.shared); },
      "path"_a, "state"_a, "Writes the state at full precision, atomically; raises FileWriteError.");
  m.def(
      "load_state",
      [](const std::string& path, int expected_nodes) {
        return SharedState(drape::load_state<double>(path, expected_nodes));
      },
      "path"_a, "expected_nodes"_a = -1,
      "Reads a state file (bit-identical values); raises StateFormatError naming the file.");
}

void bind_scene_files(nb::module_& m) {
  nb::class_<SceneFile>(m, "SceneFile",
                        "A drape-render scene file (TOML; docs/viewer.md), parsed and checked by drape-render's own "
                        "code, and the scene it describes.")
      .def_prop_ro(
          "path", [](const SceneFile& f) { return f.settings->scene; }, "The file.")
      .def_prop_ro(
          "integrator", [](const SceneFile& f) { return std::string(drape::to_string(f.settings->integrator)); },
          "'rk2', 'implicit' or 'symplectic'.")
      .def_prop_ro(
          "options", [](const SceneFile& f) { return f.settings->stepping; },
          "ImplicitOptions (dt and threads for every integrator).")
      .def_prop_ro(
          "collisions", [](const SceneFile& f) { return f.settings->cloth.self_collision; },
          "SelfCollisionSettings of the scene (self-collision keys).")
      .def_prop_ro(
          "cloth_specs",
          [](const SceneFile& f) {
            std::vector<ClothSpecWithAir> specs;
            for (const drape::ClothSpecd& spec : f.prepared.specs) specs.push_back(python_spec(spec, f.settings->air));
            return specs;
          },
          "Every cloth's ClothSpec: the first (with the floor collider if the file asks for it), then one per "
          "[[cloths]] table.")
      .def_prop_ro(
          "start", [](const SceneFile& f) { return SharedState(f.prepared.start); },
          "The first cloth's start State (its initial state, or the file's load-state).")
      .def_prop_ro(
          "frame_time", [](const SceneFile& f) { return f.settings->time.frame_time; }, "s between frames.")
      .def_prop_ro("frame_count", &SceneFile::frame_count, "Frames of an offline run, the first at the start.")
      .def_prop_ro(
          "seconds", [](const SceneFile& f) { return double(f.frame_count() - 1) * f.settings->time.frame_time; },
          "Simulated seconds of an offline run: (frame_count - 1) * frame_time.")
      .def_prop_ro(
          "realtime", [](const SceneFile& f) { return f.settings->time.realtime; },
          "True if drape-render would pace it against the wall clock.")
      .def_prop_ro(
          "width", [](const SceneFile& f) { return f.settings->output.width; }, "Image width (pixels).")
      .def_prop_ro(
          "height", [](const SceneFile& f) { return f.settings->output.height; }, "Image height (pixels).")
      .def_prop_ro(
          "floor_height", [](const SceneFile& f) { return f.prepared.floor_y; }, "m: y of the floor.")
      .def("make_scene", &make_scene,
           "A new ClothScene of the file's cloths, integrator and collisions, starting where drape-render "
           "starts; its first cloth follows the file's [[moving-pins]] tables.");
  // SceneFile.renderer: bind_rendering() adds it.

  m.def("load_scene", &load_scene, "path"_a, "flags"_a = std::vector<std::string>(),
        "Reads a drape-render scene file; `flags` are drape-render flags applied over it (e.g. ['--threads', '1']). "
        "Raises SceneFileError naming the key or flag, or InvalidParameter.");
}

}  // namespace drape::python
