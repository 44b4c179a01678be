#include "tables.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

#include "error_names.hpp"
#include "resolve_mesh.hpp"
#include "toml_values.hpp"

namespace drape::scene_file::detail {

namespace {

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : ", ") + w;
  return text;
}

/// Every key of the table `t` (`key` is "colliders[k]") is one of `allowed`, else a SettingsError
/// naming the unknown key, with the allowed key it misspells ('-' for '_' or back) and `has_keys`
/// ("a pin has the keys ..."). `misplaced(name)`, if given, throws first for a key that belongs
/// elsewhere.
void check_keys(const toml::table& t, const std::string& key, const std::string& file,
                const std::vector<std::string>& allowed, const std::string& has_keys,
                const std::function<void(const std::string&)>& misplaced = {}) {
  const auto is_allowed = [&](const std::string& k) {
    return std::find(allowed.begin(), allowed.end(), k) != allowed.end();
  };
  for (const auto& [k, node] : t) {
    const std::string name(k.str());
    if (is_allowed(name)) continue;
    if (misplaced) misplaced(name);
    std::string underscored = name, dashed = name;
    std::replace(underscored.begin(), underscored.end(), '-', '_');
    std::replace(dashed.begin(), dashed.end(), '_', '-');
    std::string hint;
    for (const std::string& guess : {underscored, dashed})
      if (hint.empty() && guess != name && is_allowed(guess)) hint = " (did you mean '" + guess + "'?)";
    throw SettingsError("scene file '" + file + "': unknown key '" + key + "." + name + "'" + hint + "; " + has_keys);
  }
}

/// The scene file's array of tables `name` ([[name]]): `read(table, "name[k]")` for each, in order.
/// `array_form` and `table_form` show the expected form in the messages when it is not one.
template <class Read>
void for_each_table(const toml::node& node, const std::string& file, const std::string& name,
                    const std::string& array_form, const std::string& table_form, Read&& read) {
  const toml::array* list = node.as_array();
  if (!list) bad_key(file, name, "must be an array of tables (" + array_form + ")");
  for (std::size_t k = 0; k < list->size(); ++k) {
    const std::string key = name + "[" + std::to_string(k) + "]";
    const toml::table* table = (*list)[k].as_table();
    if (!table) bad_key(file, key, "must be a table (" + table_form + ")");
    read(*table, key);
  }
}

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
      {drape::ShapeKind::Cylinder,
       {{"center", "radius", "half_height"}, {"rotation_axis", "rotation_angle", "rounding"}}},
      {drape::ShapeKind::Mesh, {{"file"}, {"center", "scale", "rotation_axis", "rotation_angle", "frames"}}},
  };
  return keys.at(kind);
}

/// "a box", "an ..." for messages.
std::string a_shape(drape::ShapeKind kind) { return std::string("a ") + drape::to_string(kind); }

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
  check_keys(t, key, file, allowed, a_shape(kind) + " has the keys " + joined(allowed), [&](const std::string& name) {
    for (const auto& other : drape::EnumNames<ShapeKind>::values) {
      const ShapeKeys& o = shape_keys(other.value);
      if (std::count(o.required.begin(), o.required.end(), name) +
          std::count(o.optional.begin(), o.optional.end(), name))
        bad_key(file, key + "." + name,
                "does not belong to " + a_shape(kind) + " (it is " + a_shape(other.value) + "'s); " + a_shape(kind) +
                    " has the keys " + joined(allowed));
    }
  });
  for (const std::string& k : own.required)
    if (!t.get(k)) bad_key(file, key + "." + k, "is missing; " + a_shape(kind) + " needs " + joined(own.required));

  const auto vector = [&](const char* k, std::array<double, 3> fallback = {0, 0, 0}) {
    const toml::node* n = t.get(k);
    return vec3(n ? from_toml<std::array<double, 3>>(*n, key + "." + k, file) : fallback);
  };
  const auto scalar = [&](const char* k, double fallback = 0) {
    const toml::node* n = t.get(k);
    return n ? from_toml<double>(*n, key + "." + k, file) : fallback;
  };
  // Read every value first (type errors name the key), then build.
  const drape::Vec3<double> velocity = vector("velocity"), angular_velocity = vector("angular_velocity");
  const bool moving = t.get("velocity") || t.get("angular_velocity");
  // Either friction coefficient defaults to the other; both to 0.
  double static_friction = scalar("static_friction"), kinetic_friction = scalar("kinetic_friction");
  if (!t.get("kinetic_friction")) kinetic_friction = static_friction;
  if (!t.get("static_friction")) static_friction = kinetic_friction;

  // The library's names for this shape's keys (its InvalidParameter::parameter()).
  std::map<std::string, std::string> key_of = {
      {"collider radius", "radius"},
      {"collider normal", "normal"},
      {"collider half extents", "half_extents"},
      {"collider half height", "half_height"},
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
        return drape::Colliderd::sphere(vector("center"), scalar("radius"));
      case ShapeKind::Capsule: {
        const drape::Vec3<double> a = vector("a"), b = vector("b");
        key_of["collider position"] = a.allFinite() ? "b" : "a";  // the library checks a first
        return drape::Colliderd::capsule(a, b, scalar("radius"));
      }
      case ShapeKind::Box:
      case ShapeKind::Cylinder:
      case ShapeKind::Mesh: break;
    }
    // Box, cylinder and mesh: a centre, turned about an axis.
    key_of["collider position"] = "center";
    const drape::Vec3<double> axis = vector("rotation_axis", {0, 1, 0});
    const double angle = scalar("rotation_angle");
    if (!(axis.allFinite() && axis.norm() > 0))
      fail("scene file '" + file + "': " + key + ".rotation_axis",
           "[" + number(axis[0]) + ", " + number(axis[1]) + ", " + number(axis[2]) + "]",
           "finite and non-zero");
    if (!std::isfinite(angle))
      fail("scene file '" + file + "': " + key + ".rotation_angle", number(angle), "finite degrees");
    const drape::Mat3<double> rotation =
        Eigen::AngleAxisd(angle * (3.14159265358979323846 / 180.0), axis.normalized()).toRotationMatrix();
    if (kind == ShapeKind::Mesh) {
      // The OBJ file's vertices in metres (scale per file unit), relative to the scene file.
      const std::string path = scene_relative(from_toml<std::string>(*t.get("file"), key + ".file", file), file);
      const KeyName name = [&](const std::string& k) { return "scene file '" + file + "': " + key + "." + k; };
      const double scale = scalar("scale", 1.0);
      const drape::ClothMesh<double> mesh = read_obj_mesh(path, scale, false, name, "file");
      const toml::node* frames_node = t.get("frames");
      if (!frames_node) {
        try {
          return drape::Colliderd::mesh(mesh, vector("center"), rotation);
        } catch (const InvalidParameter& e) {
          if (e.parameter().rfind("collider mesh", 0) != 0) throw;
          // The element as the file has it: "collider mesh.triangles[3]" -> "file 'x.obj'.triangles[3]".
          fail(name("file") + " '" + path + "'" + e.parameter().substr(13), e.value(), e.allowed());
        }
      }
      // Key frames: frames = [{time = 0.0, file = "a.obj"}, ...], each an OBJ of the same faces.
      std::vector<drape::Matrix3X<double>> positions;
      std::vector<double> times;
      std::vector<std::string> frame_paths;
      for_each_table(*frames_node, file, key + ".frames", "frames = [{time = 0.0, file = \"a.obj\"}, ...]",
                     "{time = 0.0, file = \"a.obj\"}", [&](const toml::table& frame, const std::string& where) {
                       const std::string at = where.substr(key.size() + 1);  // "frames[j]"
                       check_keys(frame, where, file, {"time", "file"}, "a key frame has the keys time, file",
                                  [](const std::string&) {});
                       for (const char* k : {"time", "file"})
                         if (!frame.get(k)) bad_key(file, where + "." + k, "is missing; a key frame needs time and file");
                       times.push_back(from_toml<double>(*frame.get("time"), where + ".time", file));
                       frame_paths.push_back(
                           scene_relative(from_toml<std::string>(*frame.get("file"), where + ".file", file), file));
                       const drape::ClothMesh<double> m = read_obj_mesh(frame_paths.back(), scale, false, name, at + ".file");
                       if (m.triangles != mesh.triangles || m.quads != mesh.quads)
                         fail(name(at + ".file") + " '" + frame_paths.back() + "'", "faces other than the mesh's",
                              "the faces of " + key + ".file '" + path + "' (the same vertices in the same order)");
                       positions.push_back(m.positions);
                     });
      try {
        return drape::Colliderd::animated_mesh(mesh, positions, times, vector("center"), rotation);
      } catch (const InvalidParameter& e) {
        const std::string& p = e.parameter();
        if (p == "collider frames") bad_key(file, key + ".frames", "is empty; give at least one key frame");
        if (p == "collider frame times") {  // "times[j] = 1"
          const std::string j = e.value().substr(6, e.value().find(']') - 6);
          fail(name("frames[" + j + "].time"), number(times[std::stoul(j)]), e.allowed());
        }
        if (p.rfind("collider frames[", 0) == 0) {  // "collider frames[j].triangles[3]"
          const std::size_t close = p.find(']');
          const std::string j = p.substr(16, close - 16);
          fail(name("frames[" + j + "].file") + " '" + frame_paths[std::stoul(j)] + "'" + p.substr(close + 1), e.value(),
               e.allowed());
        }
        throw;
      }
    }
    if (kind == ShapeKind::Cylinder)
      return drape::Colliderd::cylinder(vector("center"), scalar("radius"), scalar("half_height"), rotation,
                                        scalar("rounding"));
    return drape::Colliderd::box(vector("center"), vector("half_extents"), rotation, scalar("rounding"));
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
    if (n && n->is_number()) value = number(*n->value<double>());
    if (n && n->is_array() && e.parameter() != "capsule axis") {
      const drape::Vec3<double> v = vector(it->second.c_str());
      value = "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
    }
    fail("scene file '" + file + "': " + key + "." + it->second, value, e.allowed());
  }
}


const std::vector<std::string>& pin_table_keys() {
  static const std::vector<std::string> keys = {"node",          "id",    "times",  "positions",
                                                "interpolation", "start", "release"};
  return keys;
}

/// "[a, b, c]" for messages.
std::string list_text(const std::vector<double>& values) {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : ", ") + number(v);
  return "[" + text + "]";
}

/// One [[moving-pins]] table (`key` is "moving-pins[k]"): checks its keys, reads its values and builds the path
/// with the library's PinPath::keyframes; every error names the key, e.g. moving-pins[1].times. The node
/// is checked against the grid later (pin_node(), from validate()): flags may change nx and ny.
PinSpec pin_from_table(const toml::table& t, const std::string& key, const std::string& file) {
  const std::vector<std::string>& allowed = pin_table_keys();
  check_keys(t, key, file, allowed, "a pin has the keys " + joined(allowed));
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
      fail(where + ".start", number(pin.start), "finite and >= 0 (s)");
  }
  if (const toml::node* n = t.get("release")) {
    const double release = from_toml<double>(*n, key + ".release", file);
    if (!(std::isfinite(release) && release > pin.start))
      fail(where + ".release", number(release), "finite and > start (" + number(pin.start) + " s)");
    pin.release = release;
  }
  return pin;
}


/// One [[cloths]] table (`key` is "cloths[k]"): checks its keys and reads its values; the values
/// are checked when the cloth is built from the first one (cloth_specs(), from validate()).
ExtraCloth cloth_from_table(const toml::table& t, const std::string& key, const std::string& file) {
  static const std::vector<std::string> allowed = {
      "nx",        "ny",          "spacing",     "mass",        "pins",        "position",     "rotation",
      "structural-ks", "structural-kd", "shear-ks", "shear-kd", "bend-ks",  "bend-kd",      "mesh",
      "shape",     "radius",      "ring-radius", "size",        "hole-radius", "hole-centre", "edge-length",
      "scale",
      "rest-from-uv", "density",  "pin-groups",  "pin-box",     "bending",     "bending-kd"};
  check_keys(t, key, file, allowed,
             "a cloth has the keys " + joined(allowed) + " (the rest it takes from the first cloth)");
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
  // Its mesh, as the first cloth's keys of the same names (MeshSource); the OBJ file relative to
  // the scene file's folder.
  MeshSource& m = c.mesh;
  if (const toml::node* n = t.get("mesh")) m.file = scene_relative(from_toml<std::string>(*n, key + ".mesh", file), file);
  const auto pair = [&](const char* name, std::array<double, 2>& out) {
    if (const toml::node* n = t.get(name)) {
      const std::vector<double> v = from_toml<std::vector<double>>(*n, key + "." + name, file);
      if (v.size() != 2) bad_key(file, key + "." + name, "must be an array of 2 numbers");
      out = {v[0], v[1]};
    }
  };
  if (const toml::node* n = t.get("shape")) m.shape = from_toml<std::string>(*n, key + ".shape", file);
  pair("size", m.size);
  pair("hole-centre", m.hole_centre);
  const std::pair<const char*, double*> numbers[] = {
      {"radius", &m.radius},   {"ring-radius", &m.ring_radius}, {"hole-radius", &m.hole_radius},
      {"edge-length", &m.edge_length}, {"scale", &m.scale},     {"density", &m.density},
      {"bending", &m.bending}, {"bending-kd", &m.bending_kd}};
  for (const auto& [name, value] : numbers)
    if (const toml::node* n = t.get(name)) *value = from_toml<double>(*n, key + "." + name, file);
  if (const toml::node* n = t.get("rest-from-uv")) m.rest_from_uv = from_toml<bool>(*n, key + ".rest-from-uv", file);
  if (const toml::node* n = t.get("pin-groups"))
    m.pin_groups = from_toml<std::vector<std::string>>(*n, key + ".pin-groups", file);
  if (const toml::node* n = t.get("pin-box")) m.pin_box = from_toml<std::vector<double>>(*n, key + ".pin-box", file);
  return c;
}

}  // namespace

/// The scene file's [[colliders]], appended to the scene's.
void read_colliders(const toml::node& node, Settings& s) {
  for_each_table(node, s.scene, "colliders", "[[colliders]] with a shape each", "[[colliders]] with a shape = ...",
                 [&](const toml::table& table, const std::string& key) {
                   s.cloth.colliders.push_back(collider_from_table(table, key, s.scene));
                   s.collider_keys.push_back(key);
                 });
}

/// The scene file's [[moving-pins]], appended to the settings' moving pins.
void read_moving_pins(const toml::node& node, Settings& s) {
  for_each_table(node, s.scene, "moving-pins", "[[moving-pins]] with a node each",
                 "[[moving-pins]] with node = [i, j] or id = k",
                 [&](const toml::table& table, const std::string& key) {
                   s.moving_pins.push_back(pin_from_table(table, key, s.scene));
                 });
}

/// The scene file's [[cloths]], one per cloth after the first.
void read_cloths(const toml::node& node, Settings& s) {
  for_each_table(node, s.scene, "cloths", "[[cloths]], one per cloth after the first",
                 "[[cloths]] with nx, ny, position, ...",
                 [&](const toml::table& table, const std::string& key) {
                   s.extra_cloths.push_back(cloth_from_table(table, key, s.scene));
                 });
}

void read_panel_offsets(const toml::node& node, Settings& s) {
  const toml::table* table = node.as_table();
  if (!table) bad_key(s.scene, "panel-offsets", "must be a table ([panel-offsets] with NAME = [x, y, z])");
  for (const auto& [name, value] : *table) {
    const std::string key = "panel-offsets." + std::string(name.str());
    const std::array<double, 3> offset = from_toml<std::array<double, 3>>(value, key, s.scene);
    for (double c : offset)
      if (!std::isfinite(c)) bad_key(s.scene, key, "must be three finite numbers (m)");
    s.mesh.panel_offsets.emplace_back(std::string(name.str()), offset);
  }
}

}  // namespace drape::scene_file::detail
