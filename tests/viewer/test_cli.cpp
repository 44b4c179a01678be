// Runs the built drape-render (path in the DRAPE_RENDER environment variable, set by CTest) and
// checks its exit codes, messages and output files.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "drape/io/state_io.hpp"
#include "drape/viewer/png.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const char* exe = std::getenv("DRAPE_RENDER");
  REQUIRE(exe != nullptr);
  const std::string cmd = std::string(exe) + " " + args + " 2>&1";
  Result r;
  std::FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, got);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("drape_test_cli_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A cheap scene: 8 x 8 nodes, tiny images.
const std::string small = "--nx 8 --ny 8 --width 32 --height 24 --samples 1 --quiet ";

}  // namespace

TEST_CASE("drape-render rejects bad values before any work, naming the flag and the range", "[cli]") {
  const fs::path out = fs::temp_directory_path() / "drape_test_cli_never_created";
  fs::remove_all(out);
  const std::string o = " --out " + out.string();
  struct Case {
    const char* args;
    const char* flag;
    const char* range;
  };
  const Case cases[] = {
      {"--dt -1", "--dt", "> 0"},
      {"--dt 0", "--dt", "> 0"},
      {"--dt 0.1 --frame-time 0.05", "--dt", "<= --frame-time"},
      {"--nx 1", "--nx", "[2, 10000]"},
      {"--frames 0", "--frames", "[1, 10000000]"},
      {"--shear-ks -5", "--shear-ks", ">= 0"},
      {"--bend-kd nan", "--bend-kd", ">= 0"},
      {"--mass 0", "--mass", "> 0"},
      {"--boundary 3", "--boundary", "[1, 2]"},
      {"--pins 0 1089", "--pins", "[0, 1088]"},
      {"--integrator euler", "--integrator", "rk2 | implicit"},
      {"--integrator implicit --jacobian full", "--jacobian", "exact | symmetric | spd"},
      {"--integrator implicit --solver magic", "--solver", "cg"},
      {"--integrator implicit --solver magic", "--solver", "ldlt"},  // the opt-in solvers are offered
      {"--integrator implicit --preconditioner amg", "--preconditioner", "multigrid | block-jacobi"},
      {"--realtime --realtime-factor 0", "--realtime-factor", "> 0"},
      {"--realtime --max-steps-per-frame 0", "--max-steps-per-frame", "[1, 100000000]"},
      {"--width 8", "--width", "[16, 8192]"},
      {"--elevation 90", "--elevation", "[-85, 85]"},
      {"--camera orbit", "--camera", "follow | fixed"},
      {"--frames 3 --duration 1", "--duration", "exclude"},
      // The air's settings, checked by the library (AirSettings::validate), named by their flags.
      {"--air-drag -1", "--air-drag", ">= 0"},
      {"--wind 0 nan 0", "--wind", "finite"},
      {"--air-density -1", "--air-density", ">= 0"},
      {"--drag-coefficient -0.5", "--drag-coefficient", ">= 0"},
      {"--lift-coefficient inf", "--lift-coefficient", ">= 0"},
      {"--gust-amplitude -2", "--gust-amplitude", ">= 0"},
      {"--gust-period 0", "--gust-period", "> 0"},
      {"--gust-wavelength -1", "--gust-wavelength", "> 0"},
      {"--gust-waves 65", "--gust-waves", "[1, 64]"},
  };
  for (const Case& c : cases) {
    const Result r = run(std::string(c.args) + o);
    INFO(c.args << "\n" << r.output);
    REQUIRE(r.code == 2);
    REQUIRE_THAT(r.output, Catch::Contains(c.flag) && Catch::Contains(c.range));
  }
  // Parse errors come from CLI11 and also name the flag.
  for (const char* args : {"--dt abc", "--no-such-flag", "--frames", "--wind 1 2", "--gust-seed -1"}) {
    const Result r = run(std::string(args) + o);
    INFO(args << "\n" << r.output);
    REQUIRE(r.code != 0);
    REQUIRE_THAT(r.output, Catch::Contains(std::string(args).substr(0, std::string(args).find(' '))));
  }
  REQUIRE(!fs::exists(out));  // nothing was done
}

TEST_CASE("--help lists every flag with its default", "[cli]") {
  const Result r = run("--help");
  REQUIRE(r.code == 0);
  for (const char* s : {"--dt", "0.0005", "--structural-ks", "20000", "--boundary", "--pins", "--realtime-factor",
                        "--max-steps-per-frame", "--save-state", "--load-state", "--video", "--debug-gl", "--obj",
                        "--integrator", "rk2", "--jacobian", "--solver", "--scene", "--frame-time", "--wind",
                        "m/s", "--air-drag", "N s/m", "--air-density", "kg/m^3", "--drag-coefficient",
                        "--lift-coefficient", "--gust-amplitude", "--gust-period", "--gust-wavelength", "--gust-waves",
                        "--gust-seed", "[air] drag_coefficient", "[air.gusts] seed"})
    REQUIRE_THAT(r.output, Catch::Contains(s));
}

TEST_CASE("scene files: same keys as the flags, flags win, unknown keys are errors", "[cli]") {
  const fs::path dir = fresh_dir("scene");
  const fs::path scene = dir / "scene.toml";
  std::ofstream(scene) << "nx = 8\nny = 8\nwidth = 32\nheight = 24\nsamples = 1\nframes = 2\nboundary = 1\n"
                          "structural-ks = 2000.0\ndt = 0.001\nquiet = true\n";
  const Result a = run("--scene " + scene.string() + " --frames 3 --out " + (dir / "a").string());
  INFO(a.output);
  REQUIRE(a.code == 0);
  REQUIRE(fs::exists(dir / "a" / "frame_00002.png"));  // --frames 3 overrode frames = 2
  REQUIRE(!fs::exists(dir / "a" / "frame_00003.png"));
  const drape::viewer::Image img = drape::viewer::read_png((dir / "a" / "frame_00000.png").string());
  REQUIRE(img.width == 32);  // width = 32 from the file
  REQUIRE(img.height == 24);

  std::ofstream(dir / "typo.toml") << "stifness = 3\n";
  Result r = run("--scene " + (dir / "typo.toml").string() + " --out " + (dir / "b").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("unknown key 'stifness'") && Catch::Contains("typo.toml"));

  std::ofstream(dir / "underscore.toml") << "frame_time = 0.1\n";
  r = run("--scene " + (dir / "underscore.toml").string() + " --out " + (dir / "b").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("did you mean 'frame-time'"));

  std::ofstream(dir / "type.toml") << "dt = \"fast\"\n";
  r = run("--scene " + (dir / "type.toml").string() + " --out " + (dir / "b").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("key 'dt' must be a number"));

  std::ofstream(dir / "range.toml") << "dt = -0.5\n";
  r = run("--scene " + (dir / "range.toml").string() + " --out " + (dir / "b").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("--dt = -0.5") && Catch::Contains("> 0"));

  std::ofstream(dir / "broken.toml") << "dt = = 1\n";
  r = run("--scene " + (dir / "broken.toml").string() + " --out " + (dir / "b").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("broken.toml") && Catch::Contains("line 1"));
  REQUIRE(!fs::exists(dir / "b"));
  fs::remove_all(dir);
}

TEST_CASE("a render writes complete frames, OBJ files and one CSV row per frame", "[cli]") {
  const fs::path dir = fresh_dir("render");
  const Result r = run(small + "--frames 4 --obj --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.code == 0);
  int png = 0, obj = 0;
  for (const auto& e : fs::directory_iterator(dir / "out")) {
    const std::string ext = e.path().extension().string();
    INFO(e.path());
    REQUIRE((ext == ".png" || ext == ".obj" || ext == ".csv"));  // no temporary files left
    if (ext == ".png") {
      ++png;
      const drape::viewer::Image img = drape::viewer::read_png(e.path().string());
      REQUIRE(img.width == 32);
    }
    obj += ext == ".obj";
  }
  REQUIRE(png == 4);
  REQUIRE(obj == 4);
  const std::string csv = read_text(dir / "out" / "log.csv");
  REQUIRE(csv.rfind("frame,sim_time,wall_time,steps,dropped_time,achieved_factor,kinetic_energy,", 0) == 0);
  REQUIRE(std::count(csv.begin(), csv.end(), '\n') == 5);
  fs::remove_all(dir);
}

TEST_CASE("save and load state: a resumed render ends bit-identical to an uninterrupted one", "[cli]") {
  const fs::path dir = fresh_dir("resume");
  const std::string common = small + "--dt 0.001 --frame-time 0.01 --no-csv ";
  // Uninterrupted: frames 0..4 = 40 steps. Interrupted: frames 0..2 (20 steps), then 0..2 again.
  Result r = run(common + "--frames 5 --out " + (dir / "a").string() + " --save-state " + (dir / "a.state").string());
  REQUIRE(r.code == 0);
  r = run(common + "--frames 3 --out " + (dir / "b").string() + " --save-state " + (dir / "b.state").string());
  REQUIRE(r.code == 0);
  r = run(common + "--frames 3 --out " + (dir / "c").string() + " --load-state " + (dir / "b.state").string() +
          " --save-state " + (dir / "c.state").string());
  INFO(r.output);
  REQUIRE(r.code == 0);
  const drape::State<double> a = drape::load_state<double>((dir / "a.state").string(), 64);
  const drape::State<double> c = drape::load_state<double>((dir / "c.state").string(), 64);
  REQUIRE(a.time == c.time);
  REQUIRE((a.positions.array() == c.positions.array()).all());
  REQUIRE((a.velocities.array() == c.velocities.array()).all());
  REQUIRE(read_text(dir / "a.state") == read_text(dir / "c.state"));

  // A state from another grid size is refused before any work.
  r = run("--nx 9 --ny 9 --quiet --out " + (dir / "d").string() + " --load-state " + (dir / "b.state").string());
  REQUIRE(r.code == 2);
  REQUIRE_THAT(r.output, Catch::Contains("has 64 nodes but the cloth has 81"));
  REQUIRE(!fs::exists(dir / "d" / "frame_00000.png"));
  fs::remove_all(dir);
}

TEST_CASE("divergence stops the render, keeps the frames written and exits non-zero", "[cli]") {
  const fs::path dir = fresh_dir("diverge");
  // RK2 at dt = 20 ms is far beyond its stability limit (~1 ms) for these springs.
  const Result r = run(small + "--integrator rk2 --dt 0.02 --frame-time 0.04 --frames 200 --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.code == 3);
  REQUIRE_THAT(r.output, Catch::Contains("failed while computing frame") && Catch::Contains("non-finite"));
  REQUIRE(fs::exists(dir / "out" / "frame_00000.png"));
  REQUIRE(!fs::exists(dir / "out" / "frame_00199.png"));
  fs::remove_all(dir);
}

TEST_CASE("an output folder that cannot be written is a clear error", "[cli]") {
  const fs::path dir = fresh_dir("unwritable");
  std::ofstream(dir / "a_file") << "x";
  Result r = run(small + "--frames 1 --out " + (dir / "a_file").string());
  REQUIRE(r.code == 1);
  REQUIRE_THAT(r.output, Catch::Contains("output folder") && Catch::Contains("a_file"));
  if (fs::is_directory("/sys/kernel")) {  // read-only even for root
    r = run(small + "--frames 1 --out /sys/kernel");
    REQUIRE(r.code == 1);
    REQUIRE_THAT(r.output, Catch::Contains("not writable"));
  }
  fs::remove_all(dir);
}

TEST_CASE("real-time mode paces the run and logs steps and dropped time per frame", "[cli]") {
  const fs::path dir = fresh_dir("realtime");
  const Result r = run(small + "--realtime --realtime-factor 0.5 --max-steps-per-frame 5 --frames 6 --out " +
                       (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.code == 0);
  std::ifstream csv(dir / "out" / "log.csv");
  std::string line;
  std::getline(csv, line);
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    std::stringstream ls(line);
    std::string field;
    std::vector<double> v;
    while (std::getline(ls, field, ',')) v.push_back(std::stod(field));
    REQUIRE(v.size() == 13);
    REQUIRE(v[3] <= 5);   // steps within the cap
    REQUIRE(v[4] >= 0);   // dropped time
  }
  REQUIRE(rows == 6);

  // Pacing: the driver never runs ahead of factor x wall time (a bound, not a speed measurement).
  const Result paced = run(small + "--realtime --realtime-factor 2 --duration 0.4 --out " + (dir / "paced").string());
  INFO(paced.output);
  REQUIRE(paced.code == 0);
  std::ifstream log(dir / "paced" / "log.csv");
  std::getline(log, line);
  double sim = 0, wall = 0;
  while (std::getline(log, line)) {
    std::stringstream ls(line);
    std::string field;
    std::vector<double> v;
    while (std::getline(ls, field, ',')) v.push_back(std::stod(field));
    sim = v[1];
    wall = v[2];
    REQUIRE(sim <= 2.0 * wall + 1e-3);
  }
  REQUIRE(sim >= 0.4);  // --duration reached
  REQUIRE(wall >= 0.2);
  fs::remove_all(dir);
}

TEST_CASE("--video assembles the frames with ffmpeg when it is installed", "[cli]") {
  bool have_ffmpeg = false;
  if (const char* path = std::getenv("PATH")) {
    std::stringstream dirs(path);
    std::string d;
    while (std::getline(dirs, d, ':')) have_ffmpeg = have_ffmpeg || fs::exists(fs::path(d) / "ffmpeg");
  }
  const fs::path dir = fresh_dir("video");
  const Result r = run(small + "--frames 4 --out " + (dir / "out").string() + " --video " + (dir / "cloth.gif").string());
  INFO(r.output);
  if (have_ffmpeg) {
    REQUIRE(r.code == 0);
    REQUIRE(fs::file_size(dir / "cloth.gif") > 100);
  } else {
    REQUIRE(r.code == 2);  // refused before any work
    REQUIRE_THAT(r.output, Catch::Contains("--video needs ffmpeg"));
  }
  const Result bad = run(small + "--frames 2 --out " + (dir / "out").string() + " --video " + (dir / "cloth.avi").string());
  REQUIRE(bad.code == 2);
  REQUIRE_THAT(bad.output, Catch::Contains("--video") && Catch::Contains(".mp4"));
  fs::remove_all(dir);
}

namespace {

/// One air setting: its flag, its key in [air] or [air.gusts], a base value and another one.
struct AirSetting {
  const char* flag;
  const char* table;
  const char* key;
  const char* base;
  const char* other;
  const char* base_toml;  // the same values as TOML
  const char* other_toml;
};

// Every setting is active in the base (drag, both coefficients, gusts), so each one changes the run.
const AirSetting air_settings[] = {
    {"--wind", "air", "wind", "3 0 1", "3 1 1", "[3, 0, 1]", "[3.0, 1.0, 1.0]"},
    {"--air-drag", "air", "drag", "0.01", "0.05", "0.01", "0.05"},
    {"--air-density", "air", "density", "1.2", "0.9", "1.2", "0.9"},
    {"--drag-coefficient", "air", "drag_coefficient", "1", "1.3", "1", "1.3"},
    {"--lift-coefficient", "air", "lift_coefficient", "0.4", "0.1", "0.4", "0.1"},
    {"--gust-amplitude", "air.gusts", "amplitude", "2", "1", "2", "1"},
    {"--gust-period", "air.gusts", "period", "1.5", "0.7", "1.5", "0.7"},
    {"--gust-wavelength", "air.gusts", "wavelength", "5", "2", "5", "2"},
    {"--gust-waves", "air.gusts", "waves", "3", "5", "3", "5"},
    {"--gust-seed", "air.gusts", "seed", "7", "8", "7", "8"},
};

/// The base settings as flags, setting `changed` (if >= 0) to its other value.
std::string air_flags(int changed) {
  std::string args;
  for (int k = 0; k < int(std::size(air_settings)); ++k) {
    const AirSetting& a = air_settings[k];
    args += std::string(" ") + a.flag + " " + (k == changed ? a.other : a.base);
  }
  return args + " ";
}

/// The same as a scene file's [air] and [air.gusts] tables.
std::string air_tables(int changed) {
  std::string text;
  for (const char* table : {"air", "air.gusts"}) {
    text += std::string("[") + table + "]\n";
    for (int k = 0; k < int(std::size(air_settings)); ++k) {
      const AirSetting& a = air_settings[k];
      if (std::string(a.table) == table) text += std::string(a.key) + " = " + (k == changed ? a.other_toml : a.base_toml) + "\n";
    }
  }
  return text;
}

}  // namespace

TEST_CASE("air: every flag and its [air] / [air.gusts] key set the same setting; flags win over the file", "[cli][air]") {
  const fs::path dir = fresh_dir("air");
  const std::string common = small + "--integrator implicit --dt 0.005 --frame-time 0.02 --frames 4 --no-csv ";
  int runs = 0;
  // Runs drape-render and returns its final state as text (17 digits: equal text, equal bits).
  const auto state = [&](const std::string& args) {
    const fs::path out = dir / std::to_string(runs++);
    const Result r = run(common + args + " --out " + out.string() + " --save-state " + (out / "state").string());
    INFO(args << "\n" << r.output);
    REQUIRE(r.code == 0);
    return read_text(out / "state");
  };
  const auto scene = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return " --scene " + (dir / name).string();
  };
  const std::string still = state("");
  const std::string base_flags = state(air_flags(-1));
  const std::string base_file = scene("base.toml", air_tables(-1));
  REQUIRE(state(base_file) == base_flags);
  REQUIRE(base_flags != still);
  for (int k = 0; k < int(std::size(air_settings)); ++k) {
    const AirSetting& a = air_settings[k];
    INFO(a.flag << " / [" << a.table << "] " << a.key);
    const std::string by_flag = state(air_flags(k));
    REQUIRE(by_flag != base_flags);                                                   // the setting matters
    REQUIRE(state(scene("changed.toml", air_tables(k))) == by_flag);                  // the key sets it too
    REQUIRE(state(base_file + " " + a.flag + " " + a.other) == by_flag);              // the flag wins
  }
  fs::remove_all(dir);
}

TEST_CASE("air: bad values and keys in the scene file are errors naming the key", "[cli][air]") {
  const fs::path dir = fresh_dir("air_errors");
  struct Case {
    const char* toml;
    const char* extra_args;
    std::vector<const char*> expected;
  };
  const Case cases[] = {
      {"[air]\ndensity = -1\n", "", {"air.density = -1", ">= 0"}},
      {"[air]\ndrag = -0.5\n", "", {"air.drag = -0.5", ">= 0"}},
      {"[air]\nwind = [1, nan, 0]\n", "", {"air.wind = nan", "finite"}},
      {"[air.gusts]\nwaves = 0\n", "", {"air.gusts.waves = 0", "[1, 64]"}},
      {"[air.gusts]\nperiod = 0.0\n", "", {"air.gusts.period = 0", "> 0"}},
      {"[air]\nfoo = 1\n", "", {"unknown key 'air.foo'"}},
      {"[air.gusts]\nspeed = 1\n", "", {"unknown key 'air.gusts.speed'"}},
      {"[air.weather]\nrain = 1\n", "", {"unknown key 'air.weather'"}},
      {"[air]\ndrag-coefficient = 1\n", "", {"did you mean 'drag_coefficient' in table [air]"}},
      {"air-drag = 0.1\n", "", {"unknown key 'air-drag'", "did you mean 'drag' in table [air]"}},
      {"gust-seed = 3\n", "", {"did you mean 'seed' in table [air.gusts]"}},
      {"air = 3\n", "", {"key 'air' must be a table"}},
      {"[air]\ngusts = 2\n", "", {"key 'air.gusts' must be a table"}},
      {"[air]\nwind = [1, 2]\n", "", {"key 'air.wind' must be an array of 3 numbers"}},
      {"[air]\nwind = [1, \"2\", 3]\n", "", {"key 'air.wind' must be a number"}},
      {"[air.gusts]\nwaves = 2.5\n", "", {"key 'air.gusts.waves' must be an integer"}},
      {"[air.gusts]\nseed = -1\n", "", {"key 'air.gusts.seed' must be an integer >= 0"}},
      // A flag's value is named by the flag even when the file has the table.
      {"[air]\ndrag = 0.1\n", "--air-density -3", {"--air-density = -3", ">= 0"}},
  };
  for (const Case& c : cases) {
    std::ofstream(dir / "air.toml") << c.toml;
    const Result r = run(small + "--scene " + (dir / "air.toml").string() + " " + c.extra_args + " --out " +
                         (dir / "out").string());
    INFO(c.toml << c.extra_args << "\n" << r.output);
    REQUIRE(r.code == 2);
    for (const char* e : c.expected) REQUIRE_THAT(r.output, Catch::Contains(e));
  }
  REQUIRE(!fs::exists(dir / "out"));  // nothing was run
  // A bad value in the file that a flag overrides is never used.
  std::ofstream(dir / "air.toml") << "[air]\ndrag = -1\n";
  const Result r = run(small + "--frames 1 --scene " + (dir / "air.toml").string() + " --air-drag 0.5 --out " +
                       (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.code == 0);
  fs::remove_all(dir);
}

TEST_CASE("air: still air adds no force term, so the default run is unchanged", "[cli][air]") {
  const fs::path dir = fresh_dir("still_air");
  // Not --quiet: the summary line names the force terms added besides springs and gravity.
  const std::string common = "--nx 8 --ny 8 --width 32 --height 24 --samples 1 --frames 3 --no-csv ";
  int runs = 0;
  const auto render = [&](const std::string& args, std::string& state) {
    const fs::path out = dir / std::to_string(runs++);
    const Result r = run(common + args + " --out " + out.string() + " --save-state " + (out / "state").string());
    INFO(args << "\n" << r.output);
    REQUIRE(r.code == 0);
    state = read_text(out / "state");
    return r.output;
  };
  std::string defaults, windy, dragged, aero;
  const std::string none = render("", defaults);
  REQUIRE_THAT(none, Catch::Contains("drape-render: 3 frames"));
  REQUIRE_THAT(none, !Catch::Contains("air drag") && !Catch::Contains("aerodynamic"));
  // Wind and gusts alone exert no force (nothing couples the cloth to the air): no term, same bits.
  const std::string wind_only = render("--wind 5 0 2 --gust-amplitude 3 --air-density 2", windy);
  REQUIRE_THAT(wind_only, !Catch::Contains("air drag") && !Catch::Contains("aerodynamic"));
  REQUIRE(windy == defaults);
  REQUIRE_THAT(render("--wind 5 0 2 --air-drag 0.05", dragged), Catch::Contains("with air drag)"));
  REQUIRE(dragged != defaults);
  REQUIRE_THAT(render("--wind 5 0 2 --lift-coefficient 0.3", aero), Catch::Contains("with aerodynamic force)"));
  REQUIRE(aero != defaults);
  fs::remove_all(dir);
}

TEST_CASE("scenes/flag.toml runs its whole length without a failed step", "[cli][air]") {
  // This file is tests/viewer/test_cli.cpp; the scene is scenes/flag.toml of the same tree.
  const fs::path scene = fs::path(__FILE__).parent_path().parent_path().parent_path() / "scenes" / "flag.toml";
  REQUIRE(fs::exists(scene));
  const fs::path dir = fresh_dir("flag");
  const Result r = run("--scene " + scene.string() + " --width 32 --height 24 --samples 1 --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.code == 0);  // a failed step would exit with 3
  REQUIRE_THAT(r.output, Catch::Contains("181 frames") && Catch::Contains("with air drag + aerodynamic force"));
  fs::remove_all(dir);
}
