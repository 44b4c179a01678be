#pragma once
// Typed values of a TOML scene file: each read names its key when the type is wrong.

#include <toml++/toml.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file::detail {

/// \throws SettingsError "scene file '`file`': key '`key`' `what`".
[[noreturn]] inline void bad_key(const std::string& file, const std::string& key, const std::string& what) {
  throw SettingsError("scene file '" + file + "': key '" + key + "' " + what);
}

/// A file named in the scene file `scene`: as given when absolute, else relative to the scene
/// file's folder.
inline std::string scene_relative(const std::filesystem::path& path, const std::string& scene) {
  return (path.is_absolute() ? path : std::filesystem::path(scene).parent_path() / path).string();
}

/// The value of `n` as a T: double, int, bool, std::uint64_t, std::string, std::vector<double>,
/// std::array<double, 3>, std::vector<int> or std::vector<std::string>. \throws SettingsError naming `key`.
template <class T>
T from_toml(const toml::node& n, const std::string& key, const std::string& file) {
  if constexpr (std::is_same_v<T, double>) {
    if (!n.is_number()) bad_key(file, key, "must be a number");
    return *n.value<double>();
  } else if constexpr (std::is_same_v<T, int>) {
    if (!n.is_integer()) bad_key(file, key, "must be an integer");
    const std::int64_t v = *n.value<std::int64_t>();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      bad_key(file, key, "is out of range");
    return static_cast<int>(v);
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!n.is_boolean()) bad_key(file, key, "must be true or false");
    return *n.value<bool>();
  } else if constexpr (std::is_same_v<T, std::uint64_t>) {
    if (!n.is_integer() || *n.value<std::int64_t>() < 0) bad_key(file, key, "must be an integer >= 0");
    return static_cast<std::uint64_t>(*n.value<std::int64_t>());
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!n.is_string()) bad_key(file, key, "must be a string");
    return *n.value<std::string>();
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    const toml::array* a = n.as_array();
    if (!a) bad_key(file, key, "must be an array of numbers");
    std::vector<double> out;
    for (const toml::node& e : *a) out.push_back(from_toml<double>(e, key, file));
    return out;
  } else if constexpr (std::is_same_v<T, std::array<double, 3>>) {
    const toml::array* a = n.as_array();
    if (!a || a->size() != 3) bad_key(file, key, "must be an array of 3 numbers [x, y, z]");
    return {from_toml<double>((*a)[0], key, file), from_toml<double>((*a)[1], key, file),
            from_toml<double>((*a)[2], key, file)};
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    const toml::array* a = n.as_array();
    if (!a) bad_key(file, key, "must be an array of strings");
    std::vector<std::string> out;
    for (const toml::node& e : *a) out.push_back(from_toml<std::string>(e, key, file));
    return out;
  } else {
    static_assert(std::is_same_v<T, std::vector<int>>, "unsupported setting type");
    const toml::array* a = n.as_array();
    if (!a) bad_key(file, key, "must be an array of integers");
    std::vector<int> out;
    for (const toml::node& e : *a) out.push_back(from_toml<int>(e, key, file));
    return out;
  }
}

// ---- colliders ([[colliders]] tables) ----------------------------------------------------------

}  // namespace drape::scene_file::detail
