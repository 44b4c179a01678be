#include "render_settings.hpp"

#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>
#include <unistd.h>

// drape-render offers every solver by name, including the opt-in direct ones.
#include "drape/solvers/enable_ldlt.hpp"
#include "drape/solvers/enable_lu.hpp"

namespace drape::render {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}
std::string number_text(double v) { return number(v); }

[[noreturn]] void fail(const std::string& flag, const std::string& value, const std::string& allowed) {
  throw SettingsError(flag + " = " + value + " is invalid; allowed: " + allowed);
}

void require_range(const char* flag, long long v, long long lo, long long hi) {
  if (v < lo || v > hi) fail(flag, std::to_string(v), "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

/// The flag of each library parameter (InvalidParameter::parameter()), for error messages.
const std::map<std::string, std::string>& flag_of_parameter() {
  static const std::map<std::string, std::string> flags = {
      {"nx", "--nx"},
      {"ny", "--ny"},
      {"nx * ny", "--nx x --ny"},
      {"spacing", "--spacing"},
      {"node_mass", "--mass"},
      {"gravity", "--gravity"},
      {"structural.stiffness", "--structural-ks"},
      {"structural.damping", "--structural-kd"},
      {"shear.stiffness", "--shear-ks"},
      {"shear.damping", "--shear-kd"},
      {"bend.stiffness", "--bend-ks"},
      {"bend.damping", "--bend-kd"},
      {"pinned node", "--pins"},
      {"boundary_condition", "--boundary"},
      {"dt", "--dt"},
      {"threads", "--threads"},
      {"tolerance", "--tolerance"},
      {"max_iterations", "--max-iterations"},
      {"integrator", "--integrator"},
      {"jacobian", "--jacobian"},
      {"solver", "--solver"},
      {"preconditioner", "--preconditioner"},
      {"pin_treatment", "--pin-treatment"},
      {"realtime_factor", "--realtime-factor"},
      {"max_steps_per_frame", "--max-steps-per-frame"},
      {"camera", "--camera"},
      {"wind", "--wind"},
      {"air drag", "--air-drag"},
      {"air density", "--air-density"},
      {"drag coefficient", "--drag-coefficient"},
      {"lift coefficient", "--lift-coefficient"},
      {"gust amplitude", "--gust-amplitude"},
      {"gust period", "--gust-period"},
      {"gust wavelength", "--gust-wavelength"},
      {"gust waves", "--gust-waves"},
      {"contact thickness", "--contact-thickness"},
      {"contact_rounds", "--contact-rounds"},
      {"self friction", "--self-friction"},
      {"self impulse rounds", "--self-impulse-rounds"},
      {"self separation rate", "--self-separation-rate"},
      {"placement.position", "--position"},
      {"placement.rotation", "--rotation"},
  };
  return flags;
}

/// The scene-file key of each library parameter whose key is not its flag without "--" (the air's,
/// in the tables [air] and [air.gusts]), for error messages about values from the file.
const std::map<std::string, std::string>& key_of_parameter() {
  static const std::map<std::string, std::string> keys = {
      {"wind", "air.wind"},
      {"air drag", "air.drag"},
      {"air density", "air.density"},
      {"drag coefficient", "air.drag_coefficient"},
      {"lift coefficient", "air.lift_coefficient"},
      {"gust amplitude", "air.gusts.amplitude"},
      {"gust period", "air.gusts.period"},
      {"gust wavelength", "air.gusts.wavelength"},
      {"gust waves", "air.gusts.waves"},
  };
  return keys;
}

/// The scene-file keys whose values were taken from the file (not overridden by a flag).
struct FileKeys {
  std::string file;
  std::set<std::string> keys;
};

/// Runs a library check; its InvalidParameter becomes a SettingsError naming the flag, or the
/// scene-file key when the value came from the file under a key that is not the flag's name.
[[noreturn]] void fail_named(const InvalidParameter& e, const FileKeys& from_file = {}) {
  const auto key = key_of_parameter().find(e.parameter());
  if (key != key_of_parameter().end() && from_file.keys.count(key->second))
    fail("scene file '" + from_file.file + "': " + key->second, e.value(), e.allowed());
  const auto it = flag_of_parameter().find(e.parameter());
  if (it == flag_of_parameter().end()) throw SettingsError(e.what());
  fail(it->second, e.value(), e.allowed());
}

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

// ---- scene-file values -------------------------------------------------------------------------

[[noreturn]] void bad_key(const std::string& file, const std::string& key, const std::string& what) {
  throw SettingsError("scene file '" + file + "': key '" + key + "' " + what);
}

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

/// The keys of a [[colliders]] table: every shape's, then each shape's own (required, optional).
struct ShapeKeys {
  std::vector<std::string> required, optional;
};
const std::vector<std::string>& common_collider_keys() {
  static const std::vector<std::string> keys = {"shape", "velocity", "angular_velocity", "static_friction",
                                                "kinetic_friction"};
  return keys;
}
const ShapeKeys& shape_keys(drape::ShapeKind kind) {
  static const std::map<drape::ShapeKind, ShapeKeys> keys = {
      {drape::ShapeKind::Plane, {{"point", "normal"}, {}}},
      {drape::ShapeKind::Sphere, {{"center", "radius"}, {}}},
      {drape::ShapeKind::Capsule, {{"a", "b", "radius"}, {}}},
      {drape::ShapeKind::Box, {{"center", "half_extents"}, {"rotation_axis", "rotation_angle", "rounding"}}},
  };
  return keys.at(kind);
}

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : ", ") + w;
  return text;
}

/// "a box", "an ..." for messages.
std::string a_shape(drape::ShapeKind kind) { return std::string("a ") + drape::to_string(kind); }

drape::Vec3<double> vec3(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

/// One [[colliders]] table (`key` is "colliders[k]"): checks its keys, reads its values and builds
/// the collider with the library's factories; every error names the key, e.g. colliders[1].radius.
drape::Colliderd collider_from_table(const toml::table& t, const std::string& key, const std::string& file) {
  using drape::ShapeKind;
  const toml::node* shape_node = t.get("shape");
  if (!shape_node)
    bad_key(file, key + ".shape", "is missing; the shape is one of " + drape::joined_names<ShapeKind>(" | "));
  const std::string shape_name = from_toml<std::string>(*shape_node, key + ".shape", file);
  ShapeKind kind{};
  if (!drape::try_parse(shape_name, kind))
    fail("scene file '" + file + "': " + key + ".shape", "'" + shape_name + "'", drape::joined_names<ShapeKind>(" | "));
  const ShapeKeys& own = shape_keys(kind);
  std::vector<std::string> allowed = common_collider_keys();
  allowed.insert(allowed.end(), own.required.begin(), own.required.end());
  allowed.insert(allowed.end(), own.optional.begin(), own.optional.end());
  const auto is_allowed = [&](const std::string& k) {
    return std::find(allowed.begin(), allowed.end(), k) != allowed.end();
  };
  for (const auto& [k, node] : t) {
    const std::string name(k.str());
    if (is_allowed(name)) continue;
    for (const auto& other : drape::EnumNames<ShapeKind>::values) {
      const ShapeKeys& o = shape_keys(other.value);
      if (std::count(o.required.begin(), o.required.end(), name) +
          std::count(o.optional.begin(), o.optional.end(), name))
        bad_key(file, key + "." + name,
                "does not belong to " + a_shape(kind) + " (it is " + a_shape(other.value) + "'s); " + a_shape(kind) +
                    " has the keys " + joined(allowed));
    }
    std::string underscored = name;
    std::replace(underscored.begin(), underscored.end(), '-', '_');
    const std::string hint =
        underscored != name && is_allowed(underscored) ? " (did you mean '" + underscored + "'?)" : "";
    throw SettingsError("scene file '" + file + "': unknown key '" + key + "." + name + "'" + hint + "; " +
                        a_shape(kind) + " has the keys " + joined(allowed));
  }
  for (const std::string& k : own.required)
    if (!t.get(k)) bad_key(file, key + "." + k, "is missing; " + a_shape(kind) + " needs " + joined(own.required));

  const auto vector = [&](const char* k, std::array<double, 3> fallback = {0, 0, 0}) {
    const toml::node* n = t.get(k);
    return vec3(n ? from_toml<std::array<double, 3>>(*n, key + "." + k, file) : fallback);
  };
  const auto number = [&](const char* k, double fallback = 0) {
    const toml::node* n = t.get(k);
    return n ? from_toml<double>(*n, key + "." + k, file) : fallback;
  };
  // Read every value first (type errors name the key), then build.
  const drape::Vec3<double> velocity = vector("velocity"), angular_velocity = vector("angular_velocity");
  const bool moving = t.get("velocity") || t.get("angular_velocity");
  // Either friction coefficient defaults to the other; both to 0.
  double static_friction = number("static_friction"), kinetic_friction = number("kinetic_friction");
  if (!t.get("kinetic_friction")) kinetic_friction = static_friction;
  if (!t.get("static_friction")) static_friction = kinetic_friction;

  // The library's names for this shape's keys (its InvalidParameter::parameter()).
  std::map<std::string, std::string> key_of = {
      {"collider radius", "radius"},
      {"collider normal", "normal"},
      {"collider half extents", "half_extents"},
      {"collider rounding", "rounding"},
      {"collider velocity", "velocity"},
      {"collider angular velocity", "angular_velocity"},
      {"static friction", "static_friction"},
      {"kinetic friction", "kinetic_friction"},
      {"capsule axis", "b"},
      {"collider rotation", "rotation_angle"},
  };
  const auto build = [&]() -> drape::Colliderd {
    switch (kind) {
      case ShapeKind::Plane:
        key_of["collider position"] = "point";
        return drape::Colliderd::plane(vector("point"), vector("normal"));
      case ShapeKind::Sphere:
        key_of["collider position"] = "center";
        return drape::Colliderd::sphere(vector("center"), number("radius"));
      case ShapeKind::Capsule: {
        const drape::Vec3<double> a = vector("a"), b = vector("b");
        key_of["collider position"] = a.allFinite() ? "b" : "a";  // the library checks a first
        return drape::Colliderd::capsule(a, b, number("radius"));
      }
      case ShapeKind::Box: break;
    }
    key_of["collider position"] = "center";
    const drape::Vec3<double> axis = vector("rotation_axis", {0, 1, 0});
    const double angle = number("rotation_angle");
    if (!(axis.allFinite() && axis.norm() > 0))
      fail("scene file '" + file + "': " + key + ".rotation_axis",
           "[" + number_text(axis[0]) + ", " + number_text(axis[1]) + ", " + number_text(axis[2]) + "]",
           "finite and non-zero");
    if (!std::isfinite(angle))
      fail("scene file '" + file + "': " + key + ".rotation_angle", number_text(angle), "finite degrees");
    const drape::Mat3<double> rotation =
        Eigen::AngleAxisd(angle * (3.14159265358979323846 / 180.0), axis.normalized()).toRotationMatrix();
    return drape::Colliderd::box(vector("center"), vector("half_extents"), rotation, number("rounding"));
  };
  try {
    drape::Colliderd collider = build();
    collider.set_friction(static_friction, kinetic_friction);
    if (moving) collider.moving(velocity, angular_velocity);
    return collider;
  } catch (const InvalidParameter& e) {
    // A static coefficient not given took the kinetic one's value: the error is the typed one's.
    // (The library checks the static one first, so a kinetic error always has its own value.)
    if (e.parameter() == "static friction" && !t.get("static_friction")) key_of["static friction"] = "kinetic_friction";
    const auto it = key_of.find(e.parameter());
    if (it == key_of.end()) throw SettingsError("scene file '" + file + "': " + key + ": " + e.what());
    // The value as the file has it (the library writes 17 digits): a number, or [x, y, z].
    std::string value = e.value();
    const toml::node* n = t.get(it->second);
    if (n && n->is_number()) value = number_text(*n->value<double>());
    if (n && n->is_array() && e.parameter() != "capsule axis") {
      const drape::Vec3<double> v = vector(it->second.c_str());
      value = "[" + number_text(v[0]) + ", " + number_text(v[1]) + ", " + number_text(v[2]) + "]";
    }
    fail("scene file '" + file + "': " + key + "." + it->second, value, e.allowed());
  }
}

/// The scene file's `colliders`: an array of tables ([[colliders]]), appended to the scene's.
void apply_colliders(const toml::node& node, Settings& s) {
  const toml::array* list = node.as_array();
  if (!list) bad_key(s.scene, "colliders", "must be an array of tables ([[colliders]] with a shape each)");
  for (std::size_t k = 0; k < list->size(); ++k) {
    const std::string key = "colliders[" + std::to_string(k) + "]";
    const toml::table* table = (*list)[k].as_table();
    if (!table) bad_key(s.scene, key, "must be a table ([[colliders]] with a shape = ...)");
    s.cloth.colliders.push_back(collider_from_table(*table, key, s.scene));
    s.collider_keys.push_back(key);
  }
}

// ---- moving pins ([[moving-pins]] tables) ------------------------------------------------------------

const std::vector<std::string>& pin_table_keys() {
  static const std::vector<std::string> keys = {"node",          "id",    "times",  "positions",
                                                "interpolation", "start", "release"};
  return keys;
}

/// "[a, b, c]" for messages.
std::string list_text(const std::vector<double>& values) {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : ", ") + number_text(v);
  return "[" + text + "]";
}

/// One [[moving-pins]] table (`key` is "moving-pins[k]"): checks its keys, reads its values and builds the path
/// with the library's PinPath::keyframes; every error names the key, e.g. moving-pins[1].times. The node
/// is checked against the grid later (pin_node(), from validate()): flags may change nx and ny.
PinSpec pin_from_table(const toml::table& t, const std::string& key, const std::string& file) {
  const std::vector<std::string>& allowed = pin_table_keys();
  for (const auto& [k, node] : t) {
    const std::string name(k.str());
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw SettingsError("scene file '" + file + "': unknown key '" + key + "." + name + "'; a pin has the keys " +
                          joined(allowed));
  }
  const std::string where = "scene file '" + file + "': " + key;
  PinSpec pin;
  pin.key = key;
  const toml::node* node = t.get("node");
  const toml::node* id = t.get("id");
  if (node && id)
    throw SettingsError(where + ": keys '" + key + ".node' and '" + key + ".id' exclude each other; give one");
  if (!node && !id)
    bad_key(file, key + ".node", "is missing; a pin names its node with node = [i, j] or id = k (k = j*nx + i)");
  if (node) {
    const std::vector<int> ij = from_toml<std::vector<int>>(*node, key + ".node", file);
    if (ij.size() != 2) bad_key(file, key + ".node", "must be an array of 2 integers [i, j]");
    pin.grid_node = std::array<int, 2>{ij[0], ij[1]};
  } else {
    pin.id = from_toml<int>(*id, key + ".id", file);
  }

  // Key frames: times and positions together, or neither (the pin holds the node where it is).
  const toml::node* times_node = t.get("times");
  const toml::node* positions_node = t.get("positions");
  if (times_node && !positions_node)
    bad_key(file, key + ".positions", "is missing; key frames need times and positions, one [x, y, z] per time");
  if (positions_node && !times_node)
    bad_key(file, key + ".times", "is missing; key frames need times and positions, one [x, y, z] per time");
  drape::Interpolation interpolation = drape::Interpolation::Smooth;
  if (const toml::node* n = t.get("interpolation")) {
    const std::string name = from_toml<std::string>(*n, key + ".interpolation", file);
    if (!drape::try_parse(name, interpolation))
      fail(where + ".interpolation", "'" + name + "'", drape::joined_names<drape::Interpolation>(" | "));
  }
  if (times_node) {
    const std::vector<double> times = from_toml<std::vector<double>>(*times_node, key + ".times", file);
    const toml::array* list = positions_node->as_array();
    if (!list) bad_key(file, key + ".positions", "must be an array of positions [[x, y, z], ...]");
    std::vector<drape::Vec3<double>> positions;
    for (std::size_t k = 0; k < list->size(); ++k)
      positions.push_back(
          vec3(from_toml<std::array<double, 3>>((*list)[k], key + ".positions[" + std::to_string(k) + "]", file)));
    try {
      pin.path = drape::PinPath<double>::keyframes(times, positions, interpolation);
    } catch (const InvalidParameter& e) {
      // The library's names for the keys (its InvalidParameter::parameter()).
      if (e.parameter() == "pin path times") fail(where + ".times", list_text(times), e.allowed());
      if (e.parameter() == "pin path positions") fail(where + ".positions", e.value(), e.allowed());
      if (e.parameter() == "interpolation") fail(where + ".interpolation", e.value(), e.allowed());
      throw SettingsError(where + ": " + e.what());
    }
    pin.key_positions = positions;
  }

  if (const toml::node* n = t.get("start")) {
    pin.start = from_toml<double>(*n, key + ".start", file);
    if (!(std::isfinite(pin.start) && pin.start >= 0))
      fail(where + ".start", number_text(pin.start), "finite and >= 0 (s)");
  }
  if (const toml::node* n = t.get("release")) {
    const double release = from_toml<double>(*n, key + ".release", file);
    if (!(std::isfinite(release) && release > pin.start))
      fail(where + ".release", number_text(release), "finite and > start (" + number_text(pin.start) + " s)");
    pin.release = release;
  }
  return pin;
}

/// The scene file's [[moving-pins]]: an array of tables, appended to the settings' moving pins.
void apply_pin_tables(const toml::node& node, Settings& s) {
  const toml::array* list = node.as_array();
  if (!list) bad_key(s.scene, "moving-pins", "must be an array of tables ([[moving-pins]] with a node each)");
  for (std::size_t k = 0; k < list->size(); ++k) {
    const std::string key = "moving-pins[" + std::to_string(k) + "]";
    const toml::table* table = (*list)[k].as_table();
    if (!table) bad_key(s.scene, key, "must be a table ([[moving-pins]] with node = [i, j] or id = k)");
    s.moving_pins.push_back(pin_from_table(*table, key, s.scene));
  }
}

// ---- more cloths ([[cloths]] tables) ----------------------------------------------------------------

/// One [[cloths]] table (`key` is "cloths[k]"): checks its keys and reads its values; the values
/// are checked when the cloth is built from the first one (cloth_specs(), from validate()).
ExtraCloth cloth_from_table(const toml::table& t, const std::string& key, const std::string& file) {
  static const std::vector<std::string> allowed = {"nx",       "ny",       "spacing",       "mass",          "pins",
                                                   "position", "rotation", "structural-ks", "structural-kd", "shear-ks",
                                                   "shear-kd", "bend-ks",  "bend-kd"};
  for (const auto& [k, node] : t) {
    const std::string name(k.str());
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw SettingsError("scene file '" + file + "': unknown key '" + key + "." + name + "'; a cloth has the keys " +
                          joined(allowed) + " (the rest it takes from the first cloth)");
  }
  ExtraCloth c;
  c.key = key;
  if (const toml::node* n = t.get("nx")) c.nx = from_toml<int>(*n, key + ".nx", file);
  if (const toml::node* n = t.get("ny")) c.ny = from_toml<int>(*n, key + ".ny", file);
  if (const toml::node* n = t.get("spacing")) c.spacing = from_toml<double>(*n, key + ".spacing", file);
  if (const toml::node* n = t.get("mass")) c.mass = from_toml<double>(*n, key + ".mass", file);
  if (const toml::node* n = t.get("pins")) c.pins = from_toml<std::vector<int>>(*n, key + ".pins", file);
  const char* spring_keys[] = {"structural-ks", "structural-kd", "shear-ks", "shear-kd", "bend-ks", "bend-kd"};
  for (std::size_t k = 0; k < 6; ++k)
    if (const toml::node* n = t.get(spring_keys[k]))
      c.springs[k] = from_toml<double>(*n, key + "." + spring_keys[k], file);
  if (const toml::node* n = t.get("position"))
    c.position = from_toml<std::array<double, 3>>(*n, key + ".position", file);
  if (const toml::node* n = t.get("rotation"))
    c.rotation = from_toml<std::array<double, 3>>(*n, key + ".rotation", file);
  return c;
}

/// The scene file's [[cloths]]: an array of tables.
void apply_cloth_tables(const toml::node& node, Settings& s) {
  const toml::array* list = node.as_array();
  if (!list) bad_key(s.scene, "cloths", "must be an array of tables ([[cloths]], one per cloth after the first)");
  for (std::size_t k = 0; k < list->size(); ++k) {
    const std::string key = "cloths[" + std::to_string(k) + "]";
    const toml::table* table = (*list)[k].as_table();
    if (!table) bad_key(s.scene, key, "must be a table ([[cloths]] with nx, ny, position, ...)");
    s.extra_cloths.push_back(cloth_from_table(*table, key, s.scene));
  }
}

/// --sphere X Y Z R (scene-file key `sphere = [x, y, z, r]`), after the file's colliders.
void add_sphere(Settings& s) {
  if (s.sphere.empty()) return;
  if (s.sphere.size() != 4) fail("--sphere", std::to_string(s.sphere.size()) + " numbers", "4 numbers: X Y Z R");
  try {
    s.cloth.colliders.push_back(drape::Colliderd::sphere({s.sphere[0], s.sphere[1], s.sphere[2]}, s.sphere[3]));
  } catch (const InvalidParameter& e) {
    const bool radius = e.parameter() == "collider radius";
    fail(radius ? "--sphere (radius)" : "--sphere (centre)", radius ? number(s.sphere[3]) : e.value(), e.allowed());
  }
  s.collider_keys.push_back("--sphere");
}

/// Every setting: its CLI11 option and how to apply its scene-file value.
struct Binding {
  CLI::Option* option;
  std::function<void(const toml::node&, const std::string& file)> apply;
};

/// The flags and scene-file keys, bound to the fields of a Settings.
class Bindings {
 public:
  Bindings(CLI::App& app, std::map<std::string, Binding>& keys) : m_app(app), m_keys(keys) {}

  /// A number, string or switch, stored as is.
  template <class T>
  CLI::Option* value(const std::string& key, T& field, const std::string& help, const char* group) {
    return value_as("--" + key, key, field, help, group);
  }

  /// The same for a flag whose scene-file key is not its name (`key` may be a dotted path into a
  /// table, "air.gusts.seed").
  template <class T>
  CLI::Option* value_as(const std::string& flag, const std::string& key, T& field, const std::string& help,
                        const char* group) {
    CLI::Option* opt;
    if constexpr (std::is_same_v<T, bool>)
      opt = m_app.add_flag(flag, field, help);
    else
      opt = m_app.add_option(flag, field, help);
    opt->group(group);
    m_keys[key] = {opt,
                   [&field, key](const toml::node& n, const std::string& file) { field = from_toml<T>(n, key, file); }};
    return opt;
  }

  /// A vector (x, y, z): three numbers after the flag, an array of three in the scene file.
  CLI::Option* vector_as(const std::string& flag, const std::string& key, std::array<double, 3>& field,
                         const std::string& help, const char* group) {
    CLI::Option* opt = m_app.add_option_function<std::vector<double>>(
        flag,
        [&field](const std::vector<double>& v) {
          field = {v.at(0), v.at(1), v.at(2)};
        },
        help);
    opt->expected(3)->type_name("FLOAT")->default_str(number(field[0]) + " " + number(field[1]) + " " +
                                                      number(field[2]));
    opt->group(group);
    m_keys[key] = {opt, [&field, key](const toml::node& n, const std::string& file) {
                     field = from_toml<std::array<double, 3>>(n, key, file);
                   }};
    return opt;
  }

  /// An option enum, by the library's names (core/enum_names.hpp).
  template <class Enum>
  CLI::Option* name(const std::string& key, Enum& field, const std::string& help, const char* group) {
    const std::string flag = "--" + key;
    CLI::Option* opt = m_app.add_option_function<std::string>(
        flag, [&field](const std::string& text) { field = parse_option<Enum>(text); }, help);
    opt->default_str(drape::to_string(field))->group(group);
    m_keys[key] = {opt, [&field, key](const toml::node& n, const std::string& file) {
                     field = parse_option<Enum>(from_toml<std::string>(n, key, file));
                   }};
    return opt;
  }

  /// A value converted by `set` (which also checks it).
  template <class T, class Set>
  CLI::Option* converted(const std::string& key, const std::string& default_text, Set set, const std::string& help,
                         const char* group) {
    CLI::Option* opt = m_app.add_option_function<T>("--" + key, set, help);
    opt->default_str(default_text)->group(group);
    m_keys[key] = {opt, [set, key](const toml::node& n, const std::string& file) { set(from_toml<T>(n, key, file)); }};
    return opt;
  }

 private:
  CLI::App& m_app;
  std::map<std::string, Binding>& m_keys;
};

/// The tables of a scene file (every other key is a setting).
bool is_table_key(const std::string& key) { return key == "air" || key == "air.gusts"; }

/// "air.gusts.seed" -> "'seed' in table [air.gusts]", "dt" -> "'dt'", for messages.
std::string key_in_table(const std::string& key) {
  const std::size_t dot = key.rfind('.');
  return dot == std::string::npos ? "'" + key + "'"
                                  : "'" + key.substr(dot + 1) + "' in table [" + key.substr(0, dot) + "]";
}

[[noreturn]] void unknown_key(const std::string& file, const std::string& key,
                              const std::map<std::string, Binding>& keys) {
  std::string hint;
  // frame_time -> frame-time (flag names), air.drag-coefficient -> air.drag_coefficient (air keys).
  const std::size_t dot = key.rfind('.');
  const std::size_t tail = dot == std::string::npos ? 0 : dot + 1;
  std::string dashed = key, underscored = key;
  std::replace(dashed.begin() + long(tail), dashed.end(), '_', '-');
  std::replace(underscored.begin() + long(tail), underscored.end(), '-', '_');
  for (const std::string& guess : {dashed, underscored})
    if (hint.empty() && guess != key && keys.count(guess)) hint = " (did you mean " + key_in_table(guess) + "?)";
  // A flag's name used as a key where the key is in a table: air-drag -> 'drag' in table [air].
  for (const auto& [other, binding] : keys)
    if (hint.empty() && other != key && binding.option->get_name() == "--" + dashed)
      hint = " (did you mean " + key_in_table(other) + "?)";
  throw SettingsError(
      "scene file '" + file + "': unknown key '" + key + "'" + hint +
      "; the keys are the flag names of --help without '--', the air's in the tables [air] and "
      "[air.gusts], the colliders' in tables [[colliders]], the moving pins' in tables [[moving-pins]], more "
      "cloths in tables [[cloths]]");
}

/// Applies the keys of a scene-file table (`prefix` "" for the top level, "air." for [air], ...)
/// that no flag overrides; records which keys it applied.
void apply_table(const toml::table& table, const std::string& prefix, std::map<std::string, Binding>& keys, Settings& s,
                 const CLI::Option* frames, const CLI::Option* duration, FileKeys& from_file) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix + std::string(k.str());
    if (key == "colliders") {  // [[colliders]]: no flag
      apply_colliders(node, s);
      continue;
    }
    if (key == "moving-pins") {  // [[moving-pins]]: no flag
      apply_pin_tables(node, s);
      continue;
    }
    if (key == "cloths") {  // [[cloths]]: no flag
      apply_cloth_tables(node, s);
      continue;
    }
    if (is_table_key(key)) {
      const toml::table* sub = node.as_table();
      if (!sub) bad_key(s.scene, key, "must be a table ([" + key + "])");
      apply_table(*sub, key + ".", keys, s, frames, duration, from_file);
      continue;
    }
    const auto it = keys.find(key);
    if (it == keys.end()) unknown_key(s.scene, key, keys);
    if (it->second.option->count() > 0) continue;  // the command line wins
    // ... also over the file's alternative to what it set.
    if ((key == "frames" && duration->count() > 0) || (key == "duration" && frames->count() > 0) ||
        (key == "pins" && keys["boundary"].option->count() > 0))
      continue;
    it->second.apply(node, s.scene);
    from_file.keys.insert(key);
    if (key == "frames") s.time.frames_given = true;
    if (key == "duration") s.time.duration_given = true;
  }
}

void set_boundary(Settings& s, int number) {
  require_range("--boundary", number, 1, 2);
  s.cloth.boundary = static_cast<drape::BoundaryCondition>(number);
}

}  // namespace

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

namespace {

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
  if (!o.video.empty()) {
    const std::size_t dot = o.video.rfind('.');
    const std::string ext = dot == std::string::npos ? "" : o.video.substr(dot);
    const std::vector<std::string> allowed = {".mp4", ".gif", ".webm", ".mkv"};
    if (std::find(allowed.begin(), allowed.end(), ext) == allowed.end())
      fail("--video (extension)", "'" + ext + "'", ".mp4 | .gif | .webm | .mkv");
    if (find_on_path("ffmpeg").empty())
      throw SettingsError("--video needs ffmpeg on PATH, which is not installed (apt-get install ffmpeg)");
  }
}

}  // namespace

void validate(const Settings& s) { validate(s, {}); }

std::optional<double> fixed_floor_height(const Settings& s) {
  if (s.floor.height_given) return s.floor.height;
  std::optional<double> y;
  for (const drape::Colliderd& c : s.cloth.colliders) {
    const double height = c.motion().pose(0).translation.y();
    if (is_floor(c, height) && (!y || height > *y)) y = height;
  }
  return y;
}

bool is_floor(const drape::Colliderd& collider, double floor_height) {
  if (collider.kind() != drape::ShapeKind::Plane || !collider.motion().is_static()) return false;
  const drape::RigidPose<double> pose = collider.motion().pose(0);
  const drape::Vec3<double> normal = pose.rotation.col(1);
  return (normal - drape::Vec3<double>::UnitY()).norm() <= 1e-12 &&
         std::abs(pose.translation.y() - floor_height) <= 1e-9 * std::max(1.0, std::abs(floor_height));
}

drape::Colliderd floor_collider(const Settings& s, double y) {
  try {
    return drape::Colliderd::plane({0.0, y, 0.0}, drape::Vec3<double>::UnitY())
        .set_friction(s.floor.friction, s.floor.friction);
  } catch (const InvalidParameter& e) {
    const bool friction = e.parameter() == "static friction" || e.parameter() == "kinetic friction";
    fail(friction ? "--floor-friction" : "--floor-height", e.value(), e.allowed());
  }
}

drape::Clothd make_cloth(const Settings& s, const drape::ClothSpecd& spec) {
  try {
    return drape::Clothd(spec);
  } catch (const InvalidParameter& e) {
    const std::string& name = e.parameter();
    if (name.rfind("colliders[", 0) != 0) fail_named(e);
    const std::size_t k = std::stoul(name.substr(10));
    const std::string what = k < s.collider_keys.size() ? s.collider_keys[k]
                             : s.floor.height_given     ? "--floor-height (of --floor-collider)"
                                                        : "--floor-collider";
    fail(what.rfind("colliders[", 0) == 0 ? "scene file '" + s.scene + "': " + what : what, e.value(), e.allowed());
  }
}

int pin_node(const Settings& s, const PinSpec& pin) {
  const int nx = s.cloth.nx, ny = s.cloth.ny;
  const std::string where = "scene file '" + s.scene + "': " + pin.key;
  if (pin.grid_node) {
    const auto [i, j] = *pin.grid_node;
    if (i < 0 || i >= nx || j < 0 || j >= ny)
      fail(where + ".node", "[" + std::to_string(i) + ", " + std::to_string(j) + "]",
           "a node of the grid: [i, j] with i in [0, " + std::to_string(nx - 1) + "] and j in [0, " +
               std::to_string(ny - 1) + "] (nx = " + std::to_string(nx) + ", ny = " + std::to_string(ny) + ")");
    return j * nx + i;
  }
  if (pin.id < 0 || pin.id >= nx * ny)
    fail(where + ".id", std::to_string(pin.id),
         "a node of the grid: an id in [0, " + std::to_string(nx * ny - 1) + "] (id = j*nx + i)");
  return pin.id;
}

std::vector<drape::ClothSpecd> cloth_specs(const Settings& s, const drape::ClothSpecd& first) {
  std::vector<drape::ClothSpecd> specs = {first};
  for (const ExtraCloth& c : s.extra_cloths) {
    drape::ClothSpecd spec = first;
    spec.nx = c.nx.value_or(first.nx);
    spec.ny = c.ny.value_or(first.ny);
    spec.spacing = c.spacing.value_or(first.spacing);
    spec.node_mass = c.mass.value_or(first.node_mass);
    spec.pinned_nodes = c.pins;
    double* springs[] = {&spec.springs.structural.stiffness, &spec.springs.structural.damping,
                         &spec.springs.shear.stiffness,      &spec.springs.shear.damping,
                         &spec.springs.bend.stiffness,       &spec.springs.bend.damping};
    for (std::size_t k = 0; k < 6; ++k)
      if (c.springs[k]) *springs[k] = *c.springs[k];
    spec.placement.position = vec3(c.position);
    spec.placement.rotation_degrees = vec3(c.rotation);
    const std::string where = "scene file '" + s.scene + "': " + c.key;
    try {
      spec.validate();
      spec.force_terms.clear();  // the air's terms are built for a grid: this cloth's own
      if (s.air.active()) {
        const drape::Grid<double> grid(spec.nx, spec.ny, spec.spacing, spec.node_mass);
        spec.force_terms = drape::air_force_terms<double>(s.air, grid.triangles());
      }
      (void)drape::Clothd(spec);  // pins clear of the colliders
    } catch (const InvalidParameter& e) {
      const std::map<std::string, std::string> key_of = {{"nx", "nx"},
                                                         {"ny", "ny"},
                                                         {"spacing", "spacing"},
                                                         {"node_mass", "mass"},
                                                         {"pinned node", "pins"},
                                                         {"placement.position", "position"},
                                                         {"placement.rotation", "rotation"},
                                                         {"structural.stiffness", "structural-ks"},
                                                         {"structural.damping", "structural-kd"},
                                                         {"shear.stiffness", "shear-ks"},
                                                         {"shear.damping", "shear-kd"},
                                                         {"bend.stiffness", "bend-ks"},
                                                         {"bend.damping", "bend-kd"}};
      const auto it = key_of.find(e.parameter());
      fail(where + "." + (it != key_of.end() ? it->second : e.parameter()), e.value(), e.allowed());
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

std::vector<std::shared_ptr<const drape::ForceTerm<double>>> air_force_terms(const Settings& s) {
  s.air.validate();
  if (!s.air.active()) return {};
  const drape::Grid<double> grid(s.cloth.nx, s.cloth.ny, s.cloth.spacing, s.cloth.node_mass);
  return drape::air_force_terms<double>(s.air, grid.triangles());
}

bool parse_settings(int argc, char** argv, Settings& s, int& exit_code) {
  CLI::App app{
      "drape-render: simulate a hanging mass-spring cloth and render it to PNG frames offscreen (OSMesa).\n"
      "Every flag is also a key of the TOML scene file given with --scene; flags override the file.\n"
      "The air's flags are keys of the tables [air] and [air.gusts], named in their help."};
  app.option_defaults()->always_capture_default();
  app.get_formatter()->column_width(34);
  std::map<std::string, Binding> keys;
  Bindings bind(app, keys);
  drape::ClothSpecd& c = s.cloth;
  drape::ImplicitOptions& i = s.stepping;

  app.add_option("--scene", s.scene, "TOML scene file; its keys are the flag names without '--'")->group("Scene");
  const char* sim = "Simulation";
  bind.name("integrator", s.integrator,
            "rk2 (explicit midpoint) | implicit (linearised implicit Euler) | symplectic (semi-implicit Euler)", sim);
  bind.name("jacobian", i.jacobian, "implicit: " + drape::joined_names<drape::JacobianVariant>(" | "), sim);
  std::string solvers;
  for (drape::LinearSolverKind k : drape::available_solvers())
    solvers += (solvers.empty() ? "" : " | ") + std::string(drape::to_string(k));
  bind.name("solver", i.solver, "implicit: linear solver, one of " + solvers, sim);
  bind.value("tolerance", i.tolerance, "implicit: relative residual of iterative solvers, (0, 1)", sim);
  bind.value("max-iterations", i.max_iterations, "implicit: iteration cap of iterative solvers, >= 1", sim);
  bind.name("pin-treatment", i.pin_treatment,
            "implicit: " + drape::joined_names<drape::PinTreatment>(" | ") + " (pinned DOFs)", sim);
  bind.name("preconditioner", i.preconditioner,
            "implicit, cg: " + drape::joined_names<drape::PreconditionerKind>(" | "), sim);
  bind.value("dt", i.dt, "time step in s, > 0 and <= --frame-time", sim);
  bind.value("structural-ks", c.springs.structural.stiffness, "structural stiffness in N/m, >= 0", sim);
  bind.value("structural-kd", c.springs.structural.damping, "structural damping in N s/m, >= 0", sim);
  bind.value("shear-ks", c.springs.shear.stiffness, "shear stiffness in N/m, >= 0", sim);
  bind.value("shear-kd", c.springs.shear.damping, "shear damping in N s/m, >= 0", sim);
  bind.value("bend-ks", c.springs.bend.stiffness, "bend stiffness in N/m, >= 0", sim);
  bind.value("bend-kd", c.springs.bend.damping, "bend damping in N s/m, >= 0", sim);
  bind.converted<int>(
      "boundary", std::to_string(static_cast<int>(c.boundary)), [&s](int number) { set_boundary(s, number); },
      "1: corner (0,0) pinned; 2: corners (0,0) and (nx-1,0) pinned", sim);
  CLI::Option* pins = bind.converted<std::vector<int>>(
      "pins", "", [&c](const std::vector<int>& nodes) { c.pinned_nodes = nodes; },
      "pinned node ids (id = j*nx + i), replaces --boundary (scene file: pins = [] pins nothing; moving pins: "
      "[[moving-pins]] tables, docs/viewer.md)",
      sim);
  pins->expected(1, 1 << 30);
  bind.value("nx", c.nx, "nodes along x, [2, 10000]", sim);
  bind.value("ny", c.ny, "nodes along z, [2, 10000]", sim);
  bind.value("spacing", c.spacing, "rest distance between neighbours in m, > 0", sim);
  bind.value("mass", c.node_mass, "mass of every node in kg, > 0", sim);
  bind.value("gravity", c.gravity, "gravitational acceleration in m/s^2 (along -y), >= 0", sim);
  bind.value("threads", i.threads, "threads for the simulation, 0 = all cores", sim);
  bind.value("load-state", s.load_state, "start from a state saved with --save-state", sim);

  const char* air = "Air (scene file: tables [air] and [air.gusts])";
  drape::AirSettings& a = s.air;
  bind.vector_as("--wind", "air.wind", a.wind,
                 "X Y Z: mean wind in m/s (moves the cloth only through --air-drag or the aerodynamic coefficients); "
                 "[air] wind = [x, y, z]",
                 air);
  bind.value_as("--air-drag", "air.drag", a.drag,
                "linear drag on every node in N s/m, -c (v - wind), >= 0 (0: off); [air] drag", air);
  bind.value_as("--air-density", "air.density", a.aerodynamics.density,
                "air density in kg/m^3 for the aerodynamic force, >= 0; [air] density", air);
  bind.value_as("--drag-coefficient", "air.drag_coefficient", a.aerodynamics.drag_coefficient,
                "aerodynamic drag coefficient C_d of every triangle, >= 0 (a flat plate: ~1.2; the aerodynamic "
                "force is on when C_d or C_l > 0); [air] drag_coefficient",
                air);
  bind.value_as("--lift-coefficient", "air.lift_coefficient", a.aerodynamics.lift_coefficient,
                "aerodynamic lift coefficient C_l of every triangle, >= 0; [air] lift_coefficient", air);
  bind.value_as("--gust-amplitude", "air.gusts.amplitude", a.gusts.amplitude,
                "largest gust speed in m/s added to the wind, >= 0 (0: no gusts); [air.gusts] amplitude", air);
  bind.value_as("--gust-period", "air.gusts.period", a.gusts.period,
                "typical time between gusts in s, > 0; [air.gusts] period", air);
  bind.value_as("--gust-wavelength", "air.gusts.wavelength", a.gusts.wavelength,
                "typical size of a gust in m, > 0; [air.gusts] wavelength", air);
  bind.value_as("--gust-waves", "air.gusts.waves", a.gusts.waves,
                "travelling waves summed into the gusts, [1, 64]; [air.gusts] waves", air);
  bind.value_as("--gust-seed", "air.gusts.seed", a.gusts.seed,
                "seed of the gusts (the same seed gives the same gusts everywhere), >= 0; [air.gusts] seed", air)
      ->check(  // CLI11 would read -1 into the unsigned seed as 2^64 - 1, and 2^64 as 2^64 - 1
          [](const std::string& text) {
            const std::string bad = text + " is invalid; allowed: an integer in [0, 2^64 - 1]";
            if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return bad;
            errno = 0;
            static_assert(sizeof(unsigned long long) == sizeof(std::uint64_t), "strtoull reads the whole seed");
            std::strtoull(text.c_str(), nullptr, 10);
            return errno == ERANGE ? bad : std::string();
          },
          "", "");

  const char* contact = "Contact (scene file: also the tables [[colliders]], docs/viewer.md)";
  bind.value("contact-thickness", c.contact_thickness,
             "cloth half-thickness in m: nodes rest this far from a collider's surface, >= 0", contact);
  bind.value("contact-rounds", i.contact_rounds,
             "implicit: linear solves per step while the contact set changes, [1, 32]", contact);
  CLI::Option* sphere = app.add_option("--sphere", s.sphere,
                                       "X Y Z R: a frictionless sphere collider of radius R (m) centred at (X, Y, Z), "
                                       "after the [[colliders]] of the scene file; scene file: sphere = [x, y, z, r]");
  sphere->expected(4)->type_name("FLOAT")->default_str("none")->group(contact);
  keys["sphere"] = {sphere, [&s](const toml::node& n, const std::string& file) {
                      s.sphere = from_toml<std::vector<double>>(n, "sphere", file);
                      if (s.sphere.size() != 4) bad_key(file, "sphere", "must be an array of 4 numbers [x, y, z, r]");
                    }};
  bind.value("floor-collider", s.floor.collider,
             "the floor the viewer draws is also a plane collider (at the floor's height, see --floor-height)",
             contact);
  bind.value("floor-friction", s.floor.friction, "static and kinetic friction coefficient of --floor-collider, >= 0",
             contact);
  bind.value("floor-height", s.floor.height,
             "y of the floor (drawn, and --floor-collider) in m; default: the highest static plane collider facing +y, "
             "else just below the box the camera frames",
             contact)
      ->default_str("auto");

  const char* self = "Self-collision (docs/contact.md)";
  drape::SelfCollisionSettings<double>& sc = c.self_collision;
  bind.value("self-collision", sc.enabled,
             "the cloth collides with itself: layers keep 2 x --contact-thickness apart and never pass through", self);
  bind.value("self-friction", sc.friction, "Coulomb friction coefficient between layers, >= 0", self);
  bind.value("self-impulse-rounds", sc.impulse_rounds,
             "rounds of continuous collision tests with impulses before impact zones take over, [0, 64]", self);
  bind.value("self-separation-rate", sc.separation_rate,
             "fraction of the missing distance between layers closer than 2 x --contact-thickness restored per "
             "step, (0, 1]",
             self);

  const char* placement = "Placement and more cloths (scene file: also the tables [[cloths]], docs/viewer.md)";
  bind.vector_as("--position", "position", s.position,
                 "X Y Z: where the cloth's node 0 starts, m (the flat grid spans +x and +z from there)", placement);
  bind.vector_as("--rotation", "rotation", s.rotation,
                 "RX RY RZ: the flat grid turned by these degrees about x, then y, then z (fixed axes)", placement);

  const char* time = "Time line";
  CLI::Option* frames = bind.value("frames", s.time.frames, "frames to render, [1, 10000000]", time);
  CLI::Option* duration = bind.value(
      "duration", s.time.duration, "simulated seconds to render instead of --frames, > 0 (unset: use --frames)", time);
  bind.value("frame-time", s.time.frame_time, "simulated seconds per frame, (0, 10]", time);
  bind.value("realtime", s.time.realtime,
             "pace the simulation against the wall clock (frames render as fast as they can)", time);
  bind.value("realtime-factor", s.realtime.realtime_factor, "realtime: simulated seconds per wall-clock second, > 0",
             time);
  bind.value("max-steps-per-frame", s.realtime.max_steps_per_frame,
             "realtime: cap on steps per frame, [1, 100000000]; time beyond it is dropped", time);

  const char* output = "Output";
  Output& o = s.output;
  bind.value("out", o.out, "output folder for frame_NNNNN.png, log.csv (created if missing)", output);
  bind.value("width", o.width, "image width in pixels, [16, 8192]", output);
  bind.value("height", o.height, "image height in pixels, [16, 8192]", output);
  bind.value("samples", o.samples, "multisample anti-aliasing samples, [1, 16]", output);
  bind.name("camera", o.camera, "follow: frame the cloth every frame (smoothed); fixed: frame where it can hang, once",
            output);
  bind.value("azimuth", o.azimuth, "camera azimuth in degrees (0 = from +z, 90 = from +x)", output);
  bind.value("elevation", o.elevation, "camera elevation in degrees, [-85, 85] (< 0: from below)", output);
  bind.value("no-floor", o.no_floor, "do not draw the floor and the cloth's shadow", output);
  bind.value("obj", o.obj, "also write frame_NNNNN.obj (the mesh) for every frame", output);
  bind.value("no-csv", o.no_csv, "do not write the per-frame log.csv", output);
  bind.value("save-state", o.save_state, "save the final state (positions, velocities, time) to this file", output);
  bind.value("video", o.video, "assemble the frames into a video (.mp4 .gif .webm .mkv) with ffmpeg", output);
  bind.value("debug-gl", o.debug_gl, "report OpenGL errors and warnings (KHR_debug)", output);
  bind.value("quiet", o.quiet, "no progress bar and no summary line", output);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);
    return false;
  }
  s.time.frames_given = frames->count() > 0;
  s.time.duration_given = duration->count() > 0;
  s.floor.height_given = keys["floor-height"].option->count() > 0;

  FileKeys from_file{s.scene, {}};
  if (!s.scene.empty()) {
    toml::table table;
    try {
      table = toml::parse_file(s.scene);
    } catch (const toml::parse_error& e) {
      std::ostringstream where;
      where << e.source().begin;
      throw SettingsError("scene file '" + s.scene + "': " + std::string(e.description()) + " (" + where.str() + ")");
    }
    apply_table(table, "", keys, s, frames, duration, from_file);
    s.floor.height_given = s.floor.height_given || from_file.keys.count("floor-height") > 0;
  }
  add_sphere(s);
  s.cloth.placement.position = vec3(s.position);
  s.cloth.placement.rotation_degrees = vec3(s.rotation);
  validate(s, from_file);
  return true;
}

}  // namespace drape::render
