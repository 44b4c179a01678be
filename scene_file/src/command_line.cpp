#include "drape/scene_file/command_line.hpp"

#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>
#include <type_traits>
#include <utility>

// drape-render offers every solver by name, including the opt-in direct ones.
#include "drape/solvers/enable_ldlt.hpp"
#include "drape/solvers/enable_lu.hpp"
#include "error_names.hpp"
#include "resolve_mesh.hpp"
#include "tables.hpp"
#include "toml_values.hpp"

namespace drape::scene_file {

namespace {

using namespace detail;

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

void set_boundary(Settings& s, int number) {
  require_range("--boundary", number, 1, 2);
  s.cloth.boundary = static_cast<drape::BoundaryCondition>(number);
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

  /// An option made by the caller, whose scene-file value `apply` reads.
  void keyed(const std::string& key, CLI::Option* option,
             std::function<void(const toml::node&, const std::string& file)> apply) {
    m_keys[key] = {option, std::move(apply)};
  }

  CLI::App& app() { return m_app; }

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

// ---- the flags, grouped as --help shows them --------------------------------------------------

void bind_simulation(Bindings& bind, Settings& s) {
  drape::ClothSpecd& c = s.cloth;
  drape::ImplicitOptions& i = s.stepping;
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
}

void bind_air(Bindings& bind, Settings& s) {
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
}

void bind_contact(Bindings& bind, Settings& s) {
  drape::ClothSpecd& c = s.cloth;
  drape::ImplicitOptions& i = s.stepping;
  const char* contact = "Contact (scene file: also the tables [[colliders]], docs/viewer.md)";
  bind.value("contact-thickness", c.contact_thickness,
             "cloth half-thickness in m: nodes rest this far from a collider's surface, >= 0", contact);
  bind.value("contact-rounds", i.contact_rounds,
             "implicit: linear solves per step while the contact set changes, [1, 32]", contact);
  CLI::Option* sphere = bind.app().add_option("--sphere", s.sphere,
                                       "X Y Z R: a frictionless sphere collider of radius R (m) centred at (X, Y, Z), "
                                       "after the [[colliders]] of the scene file; scene file: sphere = [x, y, z, r]");
  sphere->expected(4)->type_name("FLOAT")->default_str("none")->group(contact);
  bind.keyed("sphere", sphere, [&s](const toml::node& n, const std::string& file) {
    s.sphere = from_toml<std::vector<double>>(n, "sphere", file);
    if (s.sphere.size() != 4) bad_key(file, "sphere", "must be an array of 4 numbers [x, y, z, r]");
  });
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
}

void bind_self_collision(Bindings& bind, Settings& s) {
  drape::ClothSpecd& c = s.cloth;
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
}

/// A flag of `count` numbers, an array of `count` numbers in the scene file.
template <std::size_t N>
void bind_numbers(Bindings& bind, const std::string& key, std::array<double, N>& field, const std::string& help,
                  const char* group) {
  CLI::Option* opt = bind.app().add_option_function<std::vector<double>>(
      "--" + key, [&field](const std::vector<double>& v) { std::copy(v.begin(), v.end(), field.begin()); }, help);
  std::string defaults;
  for (double v : field) defaults += (defaults.empty() ? "" : " ") + number(v);
  opt->expected(int(N))->type_name("FLOAT")->default_str(defaults)->group(group);
  bind.keyed(key, opt, [&field, key](const toml::node& n, const std::string& file) {
    const std::vector<double> v = from_toml<std::vector<double>>(n, key, file);
    if (v.size() != N) bad_key(file, key, "must be an array of " + std::to_string(N) + " numbers");
    std::copy(v.begin(), v.end(), field.begin());
  });
}

void bind_mesh(Bindings& bind, Settings& s) {
  MeshSource& m = s.mesh;
  const char* mesh = "Cloth mesh (instead of the nx x ny grid; docs/mesh.md)";
  CLI::Option* file = bind.app().add_option("--mesh", m.file,
                                            "OBJ file of the cloth's mesh (scene file: relative to the scene file's "
                                            "folder); its triangles and quads, groups, and vt with --rest-from-uv");
  file->group(mesh);
  bind.keyed("mesh", file, [&m](const toml::node& n, const std::string& scene) {
    m.file = scene_relative(from_toml<std::string>(n, "mesh", scene), scene);
  });
  bind.value("shape", m.shape, "grid (nx, ny, spacing) | disk (--radius) | rectangle-with-hole (--size, --hole-*)",
             mesh);
  bind.value("radius", m.radius, "disk: radius in m, > 0", mesh);
  bind.value("ring-radius", m.ring_radius,
             "disk: a ring of vertices exactly on this circle (m; a support's edge, where the cloth bends), 0 "
             "(none) or in [edge-length, radius - edge-length]",
             mesh);
  bind_numbers(bind, "size", m.size, "W H: rectangle-with-hole: width (x) and height (z) in m", mesh);
  bind.value("hole-radius", m.hole_radius, "rectangle-with-hole: the hole's radius in m", mesh);
  bind_numbers(bind, "hole-centre", m.hole_centre, "X Z: rectangle-with-hole: the hole's centre in m from the corner",
               mesh);
  bind.value("edge-length", m.edge_length, "disk, rectangle-with-hole: target edge length in m, > 0", mesh);
  bind.value("scale", m.scale, "--mesh: metres per unit of the OBJ file, > 0", mesh);
  bind.value("rest-from-uv", m.rest_from_uv, "--mesh: the rest shape is the flat pattern of the file's vt", mesh);
  bind.value("density", m.density, "mass per area in kg/m^2 (lumped per node) instead of --mass per node, >= 0 (0: off)",
             mesh);
  CLI::Option* groups = bind.converted<std::vector<std::string>>(
      "pin-groups", "", [&m](const std::vector<std::string>& names) { m.pin_groups = names; },
      "pin the nodes of these groups of the mesh (an OBJ file's g and o; generated meshes: boundary, hole, ...)", mesh);
  groups->expected(1, 1 << 30);
  CLI::Option* box = bind.converted<std::vector<double>>(
      "pin-box", "", [&m](const std::vector<double>& corners) { m.pin_box = corners; },
      "X0 Y0 Z0 X1 Y1 Z1: pin the nodes that start inside this box (m)", mesh);
  box->expected(6)->type_name("FLOAT");
  bind.value("bending", m.bending, "dihedral-angle bending stiffness in N m, >= 0 (0: off; docs/bending.md)", mesh);
  bind.value("bending-kd", m.bending_kd, "dihedral-angle bending damping in N m s, >= 0", mesh);
  CLI::Option* pattern = bind.app().add_option("--pattern", m.pattern,
                                               "GarmentCode JSON sewing pattern: the cloth is the garment sewn from it "
                                               "(scene file: relative to the scene file's folder; docs/garments.md)");
  pattern->group(mesh);
  bind.keyed("pattern", pattern, [&m](const toml::node& n, const std::string& scene) {
    m.pattern = scene_relative(from_toml<std::string>(n, "pattern", scene), scene);
  });
  bind.value("fabric", m.fabric, "--pattern: the garment's fabric: cotton | denim | silk | jersey (docs/fabrics.md)",
             mesh);
  bind.value("seam-stiffness", m.seam_stiffness, "--pattern: seam spring per sewn pair in N/m, > 0", mesh);
  bind.value("seam-closing-time", m.seam_closing_time,
             "--pattern: s until the seams are closed and gravity comes on, >= 0", mesh);
}

void bind_placement(Bindings& bind, Settings& s) {
  const char* placement = "Placement and more cloths (scene file: also the tables [[cloths]], docs/viewer.md)";
  bind.vector_as("--position", "position", s.position,
                 "X Y Z: where the cloth's node 0 starts, m (the flat grid spans +x and +z from there)", placement);
  bind.vector_as("--rotation", "rotation", s.rotation,
                 "RX RY RZ: the flat grid turned by these degrees about x, then y, then z (fixed axes)", placement);
}

/// The two ways of giving a run's length, which exclude each other.
struct TimeOptions {
  CLI::Option* frames;
  CLI::Option* duration;
};

TimeOptions bind_time_line(Bindings& bind, Settings& s) {
  const char* time = "Time line";
  TimeOptions options;
  options.frames = bind.value("frames", s.time.frames, "frames to render, [1, 10000000]", time);
  options.duration = bind.value(
      "duration", s.time.duration, "simulated seconds to render instead of --frames, > 0 (unset: use --frames)", time);
  bind.value("frame-time", s.time.frame_time, "simulated seconds per frame, (0, 10]", time);
  bind.value("realtime", s.time.realtime,
             "pace the simulation against the wall clock (frames render as fast as they can)", time);
  bind.value("realtime-factor", s.realtime.realtime_factor, "realtime: simulated seconds per wall-clock second, > 0",
             time);
  bind.value("max-steps-per-frame", s.realtime.max_steps_per_frame,
             "realtime: cap on steps per frame, [1, 100000000]; time beyond it is dropped", time);
  return options;
}

void bind_output(Bindings& bind, Settings& s) {
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
  bind.value("usd", o.usd,
             "also write the animation of every cloth and collider to this .usda file (one USD file, one time "
             "sample per frame; its folder must exist)",
             output);
  bind.value("no-csv", o.no_csv, "do not write the per-frame log.csv", output);
  bind.value("save-state", o.save_state, "save the final state (positions, velocities, time) to this file", output);
  bind.value("video", o.video, "assemble the frames into a video (.mp4 .gif .webm .mkv) with ffmpeg", output);
  bind.value("debug-gl", o.debug_gl, "report OpenGL errors and warnings (KHR_debug)", output);
  bind.value("quiet", o.quiet, "no progress bar and no summary line", output);
  bind.value("cusick-disk", o.cusick_disk,
             "R: print the Cusick drape coefficient and folds of the last frame over a support disk of radius R "
             "(m) centred on x = z = 0, >= 0 (0: off; docs/cusick.md)",
             output);
}

// ---- the scene file ----------------------------------------------------------------------------

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
      "cloths in tables [[cloths]], a pattern's panels' offsets in the table [panel-offsets]");
}

/// Applies the keys of a scene-file table (`prefix` "" for the top level, "air." for [air], ...)
/// that no flag overrides; records which keys it applied.
void apply_table(const toml::table& table, const std::string& prefix, std::map<std::string, Binding>& keys, Settings& s,
                 const CLI::Option* frames, const CLI::Option* duration, FileKeys& from_file) {
  for (const auto& [k, node] : table) {
    const std::string key = prefix + std::string(k.str());
    if (key == "colliders") {  // [[colliders]]: no flag
      read_colliders(node, s);
      continue;
    }
    if (key == "moving-pins") {  // [[moving-pins]]: no flag
      read_moving_pins(node, s);
      continue;
    }
    if (key == "cloths") {  // [[cloths]]: no flag
      read_cloths(node, s);
      continue;
    }
    if (key == "panel-offsets") {  // [panel-offsets]: no flag
      read_panel_offsets(node, s);
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

/// drape-render's command line: every flag bound to a field of one Settings, with its scene-file key.
struct CommandLine {
  CLI::App app{
      "drape-render: simulate a hanging mass-spring cloth and render it to PNG frames offscreen (OSMesa).\n"
      "Every flag is also a key of the TOML scene file given with --scene; flags override the file.\n"
      "The air's flags are keys of the tables [air] and [air.gusts], named in their help."};
  std::map<std::string, Binding> keys;
  TimeOptions time{};

  explicit CommandLine(Settings& s) {
    app.option_defaults()->always_capture_default();
    app.get_formatter()->column_width(34);
    Bindings bind(app, keys);
    app.add_option("--scene", s.scene, "TOML scene file; its keys are the flag names without '--'")->group("Scene");
    bind_simulation(bind, s);
    bind_air(bind, s);
    bind_contact(bind, s);
    bind_self_collision(bind, s);
    bind_placement(bind, s);
    bind_mesh(bind, s);
    time = bind_time_line(bind, s);
    bind_output(bind, s);
  }

  /// After the flags are parsed: the scene file's keys that no flag sets, --sphere after the file's
  /// colliders, the placement, then every check (validate()).
  void finish(Settings& s) {
    s.time.frames_given = time.frames->count() > 0;
    s.time.duration_given = time.duration->count() > 0;
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
      apply_table(table, "", keys, s, time.frames, time.duration, from_file);
      s.floor.height_given = s.floor.height_given || from_file.keys.count("floor-height") > 0;
    }
    add_sphere(s);
    s.cloth.placement.position = vec3(s.position);
    s.cloth.placement.rotation_degrees = vec3(s.rotation);
    resolve_mesh(s);
    detail::validate(s, from_file);
  }
};

}  // namespace

bool parse_settings(int argc, char** argv, Settings& s, int& exit_code) {
  CommandLine line(s);
  try {
    line.app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = line.app.exit(e);
    return false;
  }
  line.finish(s);
  return true;
}

Settings read_settings(const std::string& scene, const std::vector<std::string>& flags) {
  Settings s;
  s.scene = scene;  // a --scene among the flags replaces it
  CommandLine line(s);
  std::vector<std::string> args(flags.rbegin(), flags.rend());  // CLI11 takes a vector's arguments from its end
  try {
    line.app.parse(args);
  } catch (const CLI::CallForHelp&) {
    throw SettingsError("flags: --help lists drape-render's flags (drape-render --help); it sets nothing");
  } catch (const CLI::ParseError& e) {
    throw SettingsError(std::string("flags: ") + e.what());
  }
  line.finish(s);
  return s;
}

}  // namespace drape::scene_file
