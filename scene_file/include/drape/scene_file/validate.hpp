#pragma once
/// \file validate.hpp
/// The checks of a scene's settings before anything runs: the library's own checks of its option
/// structs, the [[moving-pins]] nodes against the grid, the [[cloths]], the floor, the time line and
/// the output; each error names the flag or scene-file key and the allowed range.

#include <string>

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file {

/// Every check of read_settings() and parse_settings() but the one that needs the whole cloth,
/// colliders clear of the pins (make_cloth()). \throws SettingsError naming the flag.
void validate(const Settings& s);

/// The executable path of `program` on PATH, or "" if it is not installed (--video needs ffmpeg).
std::string find_on_path(const std::string& program);

}  // namespace drape::scene_file
