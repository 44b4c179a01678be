#include "drape/scene_file/validate.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "drape/scene_file/build_scene.hpp"
#include "error_names.hpp"

namespace drape::scene_file {

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

void validate(const Settings& s) { detail::validate(s, {}); }

namespace detail {

void validate(const Settings& s, const FileKeys& from_file) {
  // The library's settings, by the library's rules.
  checked([&] { s.cloth.validate(); });
  checked([&] {
    if (s.integrator == drape::IntegratorKind::Implicit)
      s.stepping.validate();
    else
      s.stepping.IntegratorOptions::validate();
  });
  checked([&] { s.realtime.validate(); });
  if (!s.extra_cloths.empty()) {
    if (!s.mesh.pattern.empty())
      fail("--pattern", "'" + s.mesh.pattern + "' with [[cloths]]", "a garment scene of one cloth: no [[cloths]] tables");
    (void)cloth_specs(s, s.cloth);
    if (!s.load_state.empty())
      fail("--load-state", "'" + s.load_state + "'", "a state of one cloth: not with [[cloths]]");
    if (!s.output.save_state.empty())
      fail("--save-state", "'" + s.output.save_state + "'", "a state of one cloth: not with [[cloths]]");
  }
  checked([&] { s.air.validate(); }, from_file);
  // The [[moving-pins]] tables were checked as they were read; here their nodes against the grid (flags
  // may have changed nx and ny), one table per node.
  std::map<int, const PinSpec*> pinned;
  for (const PinSpec& pin : s.moving_pins) {
    const int node = pin_node(s, pin);
    const auto [it, added] = pinned.emplace(node, &pin);
    if (!added)
      fail("scene file '" + s.scene + "': " + pin.key + (pin.grid_node ? ".node" : ".id"),
           pin.grid_node ? "[" + std::to_string((*pin.grid_node)[0]) + ", " + std::to_string((*pin.grid_node)[1]) + "]"
                         : std::to_string(pin.id),
           "a node no other [[moving-pins]] table names (" + it->second->key + " names node " + std::to_string(node) +
               ")");
  }
  // The colliders were checked as they were read; here the floor's settings. That no collider
  // touches a pinned node at the start is drape::Cloth's check, when drape-render builds the cloth
  // (make_cloth(), before anything runs): it needs the whole grid.
  if (s.cloth.colliders.size() != s.collider_keys.size())
    throw SettingsError("internal: every collider needs its key");  // a caller that filled only one
  if (s.floor.height_given && !std::isfinite(s.floor.height)) fail("--floor-height", number(s.floor.height), "finite");
  if (s.floor.collider) (void)floor_collider(s, 0.0);
  // The viewer's own.
  const TimeLine& t = s.time;
  if (!(std::isfinite(t.frame_time) && t.frame_time > 0 && t.frame_time <= 10))
    fail("--frame-time", number(t.frame_time), "(0, 10] s");
  if (s.stepping.dt > t.frame_time)
    fail("--dt", number(s.stepping.dt), "finite, > 0 and <= --frame-time (" + number(t.frame_time) + " s)");
  require_range("--frames", t.frames, 1, 10'000'000);
  if (!(std::isfinite(t.duration) && t.duration >= 0)) fail("--duration", number(t.duration), "finite and >= 0");
  if (t.frames_given && t.duration_given) throw SettingsError("--frames and --duration exclude each other; give one");
  if (t.duration_given && t.duration == 0) fail("--duration", "0", "finite and > 0");
  const Output& o = s.output;
  require_range("--width", o.width, 16, 8192);
  require_range("--height", o.height, 16, 8192);
  require_range("--samples", o.samples, 1, 16);
  if (!std::isfinite(o.azimuth)) fail("--azimuth", number(o.azimuth), "finite degrees");
  if (!(o.elevation >= -85 && o.elevation <= 85)) fail("--elevation", number(o.elevation), "[-85, 85] degrees");
  if (o.out.empty()) fail("--out", "''", "a folder path");
  if (!(std::isfinite(o.cusick_disk) && o.cusick_disk >= 0)) fail("--cusick-disk", number(o.cusick_disk), ">= 0 m");
  if (!o.video.empty()) {
    const std::size_t dot = o.video.rfind('.');
    const std::string ext = dot == std::string::npos ? "" : o.video.substr(dot);
    const std::vector<std::string> allowed = {".mp4", ".gif", ".webm", ".mkv"};
    if (std::find(allowed.begin(), allowed.end(), ext) == allowed.end())
      fail("--video (extension)", "'" + ext + "'", ".mp4 | .gif | .webm | .mkv");
    if (find_on_path("ffmpeg").empty())
      throw SettingsError("--video needs ffmpeg on PATH, which is not installed (apt-get install ffmpeg)");
  }
  if (!o.usd.empty()) {
    // Checked before anything runs: the file is written when the run ends.
    const std::string name = from_file.keys.count("usd") ? "scene file '" + from_file.file + "': usd" : "--usd";
    const std::filesystem::path file(o.usd);
    if (file.extension() != ".usda")
      fail(name + " (extension)", "'" + file.extension().string() + "'", ".usda (USD's text format)");
    const std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
    // The --out folder is created when the run starts.
    const auto normal = [](const std::filesystem::path& p) {
      const std::filesystem::path n = p.lexically_normal();
      return n.has_filename() ? n : n.parent_path();  // "frames/" as "frames"
    };
    const bool is_out = normal(folder) == normal(o.out);
    std::error_code ec;
    if (!is_out && !std::filesystem::is_directory(folder, ec))
      fail(name, "'" + o.usd + "'", "a .usda file in an existing folder or in --out ('" + folder.string() +
                                        "' is not a folder)");
  }
}

}  // namespace detail

}  // namespace drape::scene_file
