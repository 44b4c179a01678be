#pragma once
// How the scene-file library names a bad value in its SettingsError: the flag, or the scene-file
// key it came from, the value as given and the allowed range ("--dt = -1 is invalid; allowed: ...").

#include <map>
#include <set>
#include <string>

#include "drape/core/enum_names.hpp"
#include "drape/core/validation.hpp"
#include "drape/scene_file/settings.hpp"

namespace drape::scene_file::detail {

/// `v` with 10 significant digits, as messages and --help write numbers.
std::string number(double v);

/// The vector of a setting's [x, y, z].
inline drape::Vec3<double> vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

/// \throws SettingsError "`flag` = `value` is invalid; allowed: `allowed`".
[[noreturn]] void fail(const std::string& flag, const std::string& value, const std::string& allowed);

/// \throws SettingsError naming `flag` when `v` is outside [lo, hi].
void require_range(const char* flag, long long v, long long lo, long long hi);

/// The flag of each library parameter (InvalidParameter::parameter()), for error messages.
const std::map<std::string, std::string>& flag_of_parameter();

/// The scene-file keys whose values were taken from the file (not overridden by a flag).
struct FileKeys {
  std::string file;
  std::set<std::string> keys;
};

/// The library's InvalidParameter as a SettingsError naming the flag, or the scene-file key when
/// the value came from the file under a key that is not the flag's name.
[[noreturn]] void fail_named(const InvalidParameter& e, const FileKeys& from_file = {});

/// Runs a library check; its InvalidParameter becomes a SettingsError (fail_named()).
template <class Check>
void checked(Check&& check, const FileKeys& from_file = {}) {
  try {
    check();
  } catch (const InvalidParameter& e) { fail_named(e, from_file); }
}

/// The library's parse of an option name; its error names the flag and lists the names.
template <class Enum>
Enum parse_option(const std::string& text) {
  Enum value{};
  if (!drape::try_parse(text, value)) {
    const auto it = flag_of_parameter().find(drape::EnumNames<Enum>::parameter);
    fail(it == flag_of_parameter().end() ? std::string(drape::EnumNames<Enum>::parameter) : it->second,
         "'" + text + "'", drape::joined_names<Enum>(" | "));
  }
  return value;
}

/// The checks of validate(), naming the scene-file keys of `from_file` where a value came from the file.
void validate(const Settings& s, const FileKeys& from_file);

}  // namespace drape::scene_file::detail
