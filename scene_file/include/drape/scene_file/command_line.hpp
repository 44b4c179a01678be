#pragma once
/// \file command_line.hpp
/// Reading a scene's settings from drape-render's command line and the TOML scene file it names
/// (flags override the file), or from a scene file and flags given as a list (the Python package,
/// the sweeps). Every error names the flag or the scene-file key, the value and the allowed range.

#include <string>
#include <vector>

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file {

/// Parses the command line and the scene file it names (flags override the file), validates
/// everything (validate()) but the one check that needs the whole cloth, colliders clear of the
/// pins (make_cloth()). Returns false when the program should exit at once with `exit_code` (after
/// --help, or a parse error already reported).
/// \throws SettingsError for a bad value or an unknown/mistyped scene-file key.
bool parse_settings(int argc, char** argv, Settings& settings, int& exit_code);

/// The settings of the scene file `scene` with drape-render's `flags` applied over it (e.g.
/// {"--threads", "1"}), validated as parse_settings() validates them.
/// \throws SettingsError for a bad value, key or flag (naming it).
Settings read_settings(const std::string& scene, const std::vector<std::string>& flags = {});

}  // namespace drape::scene_file
