#include "render_settings.hpp"

#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>
#include <type_traits>
#include <unistd.h>

// drape-render offers every solver by name, including the opt-in direct ones.
#include "drape/solvers/enable_ldlt.hpp"
#include "drape/solvers/enable_lu.hpp"
#include "drape/integrators/implicit_euler.hpp"

namespace drape::render {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

[[noreturn]] void fail(const std::string& flag, const std::string& value, const std::string& allowed) {
  throw SettingsError(flag + " = " + value + " is invalid; allowed: " + allowed);
}

void require_positive(const char* flag, double v) {
  if (!(std::isfinite(v) && v > 0)) fail(flag, number(v), "finite and > 0");
}
void require_nonnegative(const char* flag, double v) {
  if (!(std::isfinite(v) && v >= 0)) fail(flag, number(v), "finite and >= 0");
}
void require_range(const char* flag, long long v, long long lo, long long hi) {
  if (v < lo || v > hi) fail(flag, std::to_string(v), "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}
void require_one_of(const char* flag, const std::string& v, const std::vector<std::string>& allowed) {
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : " | ") + a;
    fail(flag, "'" + v + "'", list);
  }
}

std::string joined(const std::vector<std::string>& v, const char* sep = " | ") {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
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
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) bad_key(file, key, "is out of range");
    return static_cast<int>(v);
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!n.is_boolean()) bad_key(file, key, "must be true or false");
    return *n.value<bool>();
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!n.is_string()) bad_key(file, key, "must be a string");
    return *n.value<std::string>();
  } else {
    static_assert(std::is_same_v<T, std::vector<int>>, "unsupported setting type");
    const toml::array* a = n.as_array();
    if (!a) bad_key(file, key, "must be an array of integers");
    std::vector<int> out;
    for (const toml::node& e : *a) out.push_back(from_toml<int>(e, key, file));
    return out;
  }
}

/// Every setting: the CLI11 option and how to apply its scene-file value.
struct Binding {
  CLI::Option* option;
  std::function<void(const toml::node&, const std::string& file)> apply;
};

}  // namespace

std::vector<std::string> available_integrators() { return {"rk2", "implicit"}; }
std::vector<std::string> available_solver_names() { return drape::available_solvers(); }

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

drape::ImplicitOptions implicit_options(const Settings& s) {
  drape::ImplicitOptions o;
  o.jacobian = s.jacobian == "exact" ? JacobianVariant::Exact
               : s.jacobian == "symmetric" ? JacobianVariant::Symmetric : JacobianVariant::Spd;
  o.solver = s.solver;
  o.preconditioner = s.preconditioner == "block-jacobi" ? Preconditioner::BlockJacobi : Preconditioner::Multigrid;
  o.tolerance = s.tolerance;
  o.max_iterations = s.max_iterations;
  o.threads = s.threads;
  o.pins = s.pin_treatment == "filter" ? PinTreatment::Filter : PinTreatment::Eliminate;
  return o;
}

void validate(const Settings& s) {
  require_one_of("--integrator", s.integrator, available_integrators());
  require_one_of("--jacobian", s.jacobian, {"exact", "symmetric", "spd"});
  require_one_of("--solver", s.solver, drape::available_solvers());
  if (!(s.tolerance > 0 && s.tolerance < 1)) fail("--tolerance", number(s.tolerance), "(0, 1)");
  require_range("--max-iterations", s.max_iterations, 1, 100'000'000);
  require_one_of("--pin-treatment", s.pin_treatment, {"eliminate", "filter"});
  require_one_of("--preconditioner", s.preconditioner, {"multigrid", "block-jacobi"});
  require_range("--nx", s.nx, 2, 10000);
  require_range("--ny", s.ny, 2, 10000);
  if (static_cast<long long>(s.nx) * s.ny > 16'000'000LL)
    fail("--nx x --ny", std::to_string(static_cast<long long>(s.nx) * s.ny), "<= 16000000 nodes");
  require_positive("--spacing", s.spacing);
  require_positive("--mass", s.mass);
  require_nonnegative("--gravity", s.gravity);
  require_nonnegative("--structural-ks", s.structural_ks);
  require_nonnegative("--structural-kd", s.structural_kd);
  require_nonnegative("--shear-ks", s.shear_ks);
  require_nonnegative("--shear-kd", s.shear_kd);
  require_nonnegative("--bend-ks", s.bend_ks);
  require_nonnegative("--bend-kd", s.bend_kd);
  require_range("--boundary", s.boundary, 1, 2);
  for (int p : s.pins) require_range("--pins", p, 0, static_cast<long long>(s.nx) * s.ny - 1);
  require_range("--threads", s.threads, 0, 1024);
  require_positive("--frame-time", s.frame_time);
  if (s.frame_time > 10) fail("--frame-time", number(s.frame_time), "(0, 10] s");
  require_positive("--dt", s.dt);
  if (s.dt > s.frame_time)
    fail("--dt", number(s.dt), "finite, > 0 and <= --frame-time (" + number(s.frame_time) + " s)");
  require_range("--frames", s.frames, 1, 10'000'000);
  require_nonnegative("--duration", s.duration);
  if (s.frames_given && s.duration_given) throw SettingsError("--frames and --duration exclude each other; give one");
  if (s.duration_given && s.duration == 0) fail("--duration", "0", "finite and > 0");
  require_positive("--realtime-factor", s.realtime_factor);
  if (s.realtime_factor > 1000) fail("--realtime-factor", number(s.realtime_factor), "(0, 1000]");
  require_range("--max-steps-per-frame", s.max_steps_per_frame, 1, 100'000'000);
  require_range("--width", s.width, 16, 8192);
  require_range("--height", s.height, 16, 8192);
  require_range("--samples", s.samples, 1, 16);
  require_one_of("--camera", s.camera, {"follow", "fixed"});
  if (!std::isfinite(s.azimuth)) fail("--azimuth", number(s.azimuth), "finite degrees");
  if (!(s.elevation >= -85 && s.elevation <= 85)) fail("--elevation", number(s.elevation), "[-85, 85] degrees");
  if (s.out.empty()) fail("--out", "''", "a folder path");
  if (!s.video.empty()) {
    const std::string ext = s.video.size() >= 4 ? s.video.substr(s.video.rfind('.') == std::string::npos ? 0 : s.video.rfind('.')) : "";
    require_one_of("--video (extension)", ext, {".mp4", ".gif", ".webm", ".mkv"});
    if (find_on_path("ffmpeg").empty())
      throw SettingsError("--video needs ffmpeg on PATH, which is not installed (apt-get install ffmpeg)");
  }
  if (s.integrator == "implicit") {
    // Combinations (e.g. the Exact Jacobian with a symmetric-only solver) are the library's rules.
    try {
      implicit_options(s).validate();
    } catch (const std::invalid_argument& e) {
      throw SettingsError(std::string("--jacobian/--solver/--pin-treatment: ") + e.what());
    }
  }
}

bool parse_settings(int argc, char** argv, Settings& s, int& exit_code) {
  CLI::App app{
      "drape-render: simulate a hanging mass-spring cloth and render it to PNG frames offscreen (OSMesa).\n"
      "Every flag is also a key of the TOML scene file given with --scene; flags override the file."};
  app.option_defaults()->always_capture_default();
  app.get_formatter()->column_width(34);
  std::map<std::string, Binding> keys;

  const auto bind = [&](const std::string& key, auto& field, const std::string& help, const char* group) -> CLI::Option* {
    using T = std::remove_reference_t<decltype(field)>;
    CLI::Option* opt;
    if constexpr (std::is_same_v<T, bool>)
      opt = app.add_flag("--" + key, field, help);
    else
      opt = app.add_option("--" + key, field, help);
    opt->group(group);
    keys[key] = {opt, [&field, key](const toml::node& n, const std::string& file) { field = from_toml<T>(n, key, file); }};
    return opt;
  };

  app.add_option("--scene", s.scene, "TOML scene file; its keys are the flag names without '--'")->group("Scene");
  const char* sim = "Simulation";
  bind("integrator", s.integrator, "rk2 (explicit midpoint) | implicit (linearised implicit Euler)", sim);
  bind("jacobian", s.jacobian, "implicit: exact | symmetric | spd", sim);
  bind("solver", s.solver, "implicit: linear solver, one of " + joined(drape::available_solvers()), sim);
  bind("tolerance", s.tolerance, "implicit: relative residual of iterative solvers, (0, 1)", sim);
  bind("max-iterations", s.max_iterations, "implicit: iteration cap of iterative solvers, >= 1", sim);
  bind("pin-treatment", s.pin_treatment, "implicit: eliminate | filter (pinned DOFs)", sim);
  bind("preconditioner", s.preconditioner, "implicit, cg: multigrid | block-jacobi", sim);
  bind("dt", s.dt, "time step in s, > 0 and <= --frame-time", sim);
  bind("structural-ks", s.structural_ks, "structural stiffness in N/m, >= 0", sim);
  bind("structural-kd", s.structural_kd, "structural damping in N s/m, >= 0", sim);
  bind("shear-ks", s.shear_ks, "shear stiffness in N/m, >= 0", sim);
  bind("shear-kd", s.shear_kd, "shear damping in N s/m, >= 0", sim);
  bind("bend-ks", s.bend_ks, "bend stiffness in N/m, >= 0", sim);
  bind("bend-kd", s.bend_kd, "bend damping in N s/m, >= 0", sim);
  bind("boundary", s.boundary, "1: corner (0,0) pinned; 2: corners (0,0) and (nx-1,0) pinned", sim);
  CLI::Option* pins = bind("pins", s.pins, "pinned node ids (id = j*nx + i), replaces --boundary (scene file: pins = [] pins nothing)", sim);
  pins->expected(1, 1 << 30);
  bind("nx", s.nx, "nodes along x, [2, 10000]", sim);
  bind("ny", s.ny, "nodes along z, [2, 10000]", sim);
  bind("spacing", s.spacing, "rest distance between neighbours in m, > 0", sim);
  bind("mass", s.mass, "mass of every node in kg, > 0", sim);
  bind("gravity", s.gravity, "gravitational acceleration in m/s^2 (along -y), >= 0", sim);
  bind("threads", s.threads, "threads for the simulation, 0 = all cores", sim);
  bind("load-state", s.load_state, "start from a state saved with --save-state", sim);

  const char* time = "Time line";
  CLI::Option* frames = bind("frames", s.frames, "frames to render, [1, 10000000]", time);
  CLI::Option* duration = bind("duration", s.duration, "simulated seconds to render instead of --frames, > 0 (unset: use --frames)", time);
  bind("frame-time", s.frame_time, "simulated seconds per frame, (0, 10]", time);
  bind("realtime", s.realtime, "pace the simulation against the wall clock (frames render as fast as they can)", time);
  bind("realtime-factor", s.realtime_factor, "realtime: simulated seconds per wall-clock second, (0, 1000]", time);
  bind("max-steps-per-frame", s.max_steps_per_frame, "realtime: cap on steps per frame; time beyond it is dropped", time);

  const char* output = "Output";
  bind("out", s.out, "output folder for frame_NNNNN.png, log.csv (created if missing)", output);
  bind("width", s.width, "image width in pixels, [16, 8192]", output);
  bind("height", s.height, "image height in pixels, [16, 8192]", output);
  bind("samples", s.samples, "multisample anti-aliasing samples, [1, 16]", output);
  bind("camera", s.camera, "follow: frame the cloth every frame (smoothed); fixed: frame where it can hang, once", output);
  bind("azimuth", s.azimuth, "camera azimuth in degrees (0 = from +z, 90 = from +x)", output);
  bind("elevation", s.elevation, "camera elevation in degrees, [-85, 85] (< 0: from below)", output);
  bind("no-floor", s.no_floor, "do not draw the floor and the cloth's shadow", output);
  bind("obj", s.obj, "also write frame_NNNNN.obj (the mesh) for every frame", output);
  bind("no-csv", s.no_csv, "do not write the per-frame log.csv", output);
  bind("save-state", s.save_state, "save the final state (positions, velocities, time) to this file", output);
  bind("video", s.video, "assemble the frames into a video (.mp4 .gif .webm .mkv) with ffmpeg", output);
  bind("debug-gl", s.debug_gl, "report OpenGL errors and warnings (KHR_debug)", output);
  bind("quiet", s.quiet, "no progress bar and no summary line", output);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);
    return false;
  }
  s.frames_given = frames->count() > 0;
  s.duration_given = duration->count() > 0;
  s.pins_given = pins->count() > 0;

  if (!s.scene.empty()) {
    toml::table table;
    try {
      table = toml::parse_file(s.scene);
    } catch (const toml::parse_error& e) {
      std::ostringstream where;
      where << e.source().begin;
      throw SettingsError("scene file '" + s.scene + "': " + std::string(e.description()) + " (" + where.str() + ")");
    }
    for (const auto& [k, node] : table) {
      const std::string key(k.str());
      const auto it = keys.find(key);
      if (it == keys.end()) {
        std::string hint;
        std::string dashed = key;
        std::replace(dashed.begin(), dashed.end(), '_', '-');
        if (keys.count(dashed)) hint = " (did you mean '" + dashed + "'?)";
        throw SettingsError("scene file '" + s.scene + "': unknown key '" + key + "'" + hint +
                            "; the keys are the flag names of --help without '--'");
      }
      if (it->second.option->count() > 0) continue;  // the command line wins
      // ... also over the file's alternative to what it set.
      if ((key == "frames" && duration->count() > 0) || (key == "duration" && frames->count() > 0) ||
          (key == "pins" && keys["boundary"].option->count() > 0))
        continue;
      it->second.apply(node, s.scene);
      if (key == "frames") s.frames_given = true;
      if (key == "duration") s.duration_given = true;
      if (key == "pins") s.pins_given = true;
    }
  }
  validate(s);
  return true;
}

}  // namespace drape::render
