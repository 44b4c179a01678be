#pragma once
/// \file settings.hpp
/// A scene's settings: the library's own option structs (the scene, the integrator's options, the
/// real-time driver's settings, the air), which the library validates, plus the time line and the
/// output of a run. Every field is a command-line flag of drape-render and a key of a TOML scene
/// file (command_line.hpp): the same name at the top level, except the air's, which are keys of the
/// tables [air] and [air.gusts]. The colliders are tables [[colliders]] of the scene file (no
/// flag), plus --sphere and the floor; moving pins are tables [[moving-pins]], more cloths tables
/// [[cloths]] (no flag).

#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "drape/model/cloth.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/core/pin_path.hpp"
#include "drape/fwd.hpp"
// Every program that links drape_scene_file (drape-render, the Python module, the tests, the
// fuzzers) uses drape's compiled instances (drape_instances) instead of compiling them in each source.
#include "drape/instances.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/physics/air.hpp"
#include "drape/realtime/realtime_driver.hpp"
#include "drape/scene_file/mesh_source.hpp"

namespace drape::scene_file {

/// A bad value: the message names the flag and the allowed range. Exit code 2.
class SettingsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class CameraMode : std::uint8_t {
  Follow,  ///< frame the cloth every frame (smoothed)
  Fixed,   ///< frame where the cloth can hang, once
};

/// When frames are taken.
struct TimeLine {
  int frames = 120;
  double duration = 0;  ///< simulated s; if given, replaces `frames`
  bool frames_given = false, duration_given = false;
  double frame_time = 1.0 / 30.0;  ///< simulated s between frames (offline) and the video's frame period
  bool realtime = false;           ///< pace against the wall clock (RealtimeDriver)
};

/// What is written where (field names are the flag names).
struct Output {
  std::string out = "frames";  ///< folder for frame_NNNNN.png and log.csv
  int width = 640, height = 480, samples = 4;
  CameraMode camera = CameraMode::Follow;
  double azimuth = 25, elevation = 15;
  bool no_floor = false;
  bool obj = false;
  /// --usd FILE.usda: the animation of every cloth and collider as one USD file (drape/io/usd.hpp),
  /// written when the run ends; empty: none.
  std::string usd;
  bool no_csv = false;
  std::string save_state;
  std::string video;
  bool debug_gl = false;
  bool quiet = false;
  /// --cusick-disk R: m; > 0: report the Cusick drape coefficient and folds of the last frame
  /// over a support disk of radius R centred on x = z = 0 (physics/drape_measures.hpp).
  double cusick_disk = 0;
};

/// The floor the viewer draws, and whether it is a collider.
struct Floor {
  bool collider = false;  ///< --floor-collider: a plane collider where the floor is drawn
  double friction = 0;    ///< --floor-friction: its static and kinetic friction coefficient
  /// --floor-height (m); unset: the highest static plane collider facing +y, else just below the
  /// box the fixed camera frames (the cloth hanging from its pins, and the colliders).
  double height = std::numeric_limits<double>::quiet_NaN();
  bool height_given = false;
};

/// A table [[moving-pins]] of the scene file: a node pinned from `start` on, following `path`, released at
/// `release`. Added to the cloth's pins (--boundary, --pins); for a node that is both, this path
/// wins from `start` on and `release` frees it. Times are absolute simulated times (s).
struct PinSpec {
  std::string key;                              ///< "moving-pins[k]", for error messages
  std::optional<std::array<int, 2>> grid_node;  ///< node = [i, j]; unset: `id`
  int id = -1;                                  ///< id = k (= j*nx + i)
  /// Key frames (times, positions, interpolation), or holding the node where it is when pinned.
  drape::PinPath<double> path;
  std::vector<drape::Vec3<double>> key_positions;  ///< the key frames' positions (m), for the camera
  double start = 0;                                ///< s: pinned from this time on
  std::optional<double> release;                   ///< s: freed at this time, > start
};

/// A table [[cloths]] of the scene file: one more cloth in the scene. It starts from the first
/// cloth's settings (springs, mass per node, spacing, thickness, gravity, colliders, air) and has
/// its own grid, springs, pins and placement; a key it does not set keeps the first cloth's value,
/// but `pins` (none by default: the cloth is free).
struct ExtraCloth {
  std::string key;  ///< "cloths[k]", for error messages
  std::optional<int> nx, ny;
  std::optional<double> spacing, mass;
  /// structural-ks, structural-kd, shear-ks, shear-kd, bend-ks, bend-kd, in that order.
  std::array<std::optional<double>, 6> springs;
  std::vector<int> pins;                    ///< node ids, j*nx + i
  std::array<double, 3> position{0, 0, 0};  ///< m: where its node 0 starts
  std::array<double, 3> rotation{0, 0, 0};  ///< degrees about x, then y, then z
  /// Its mesh when it is not the nx x ny grid, density, pins by group and box, bending: the first
  /// cloth's keys of the same names (mesh_source.hpp).
  MeshSource mesh;
};

struct Settings {
  std::string scene;       ///< TOML file with the same keys as the flags
  std::string load_state;  ///< start from this saved state

  drape::ClothSpecd cloth;                  ///< the scene (library defaults): the first cloth
  /// The first cloth's mesh when it is not the grid, its density, pins by group and box, bending
  /// (turned into cloth.mesh, cloth.areal_density and cloth.pinned_nodes as the settings are read).
  MeshSource mesh;
  std::array<double, 3> position{0, 0, 0};  ///< --position: the first cloth's placement (m)
  std::array<double, 3> rotation{0, 0, 0};  ///< --rotation: degrees about x, then y, then z
  /// The [[cloths]] tables of the scene file: more cloths, colliding with the first and each other
  /// when --self-collision is on (drape::ClothScene).
  std::vector<ExtraCloth> extra_cloths;
  drape::IntegratorKind integrator = drape::IntegratorKind::Rk2;
  drape::ImplicitOptions stepping;  ///< dt and threads (every integrator), the implicit options
  /// The driver's settings; the viewer caps at 200 steps per frame (the library's default is 64).
  drape::RealtimeSettings realtime{1.0, 200};
  /// Wind, gusts, linear drag and aerodynamic drag and lift; still and inactive by default (no
  /// force term is added, drape::air_force_terms()).
  drape::AirSettings air;
  /// The scene's colliders are in cloth.colliders: the [[colliders]] tables in order, then --sphere
  /// (the floor collider is added at run time, floor_collider()). Here, for each, the key or flag
  /// that made it ("colliders[2]", "--sphere"), for error messages.
  std::vector<std::string> collider_keys;
  std::vector<double> sphere;  ///< --sphere X Y Z R; empty if not given
  Floor floor;
  /// The [[moving-pins]] tables of the scene file, in order (checked against the grid by validate()).
  std::vector<PinSpec> moving_pins;

  TimeLine time;
  Output output;
};

}  // namespace drape::scene_file

template <>
struct drape::EnumNames<drape::scene_file::CameraMode> {
  static constexpr const char* parameter = "camera";
  static constexpr std::array<EnumName<drape::scene_file::CameraMode>, 2> values{
      {{drape::scene_file::CameraMode::Follow, "follow"}, {drape::scene_file::CameraMode::Fixed, "fixed"}}};
};
