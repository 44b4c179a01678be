// Runs the built drape-render (path in the DRAPE_RENDER environment variable, set by CTest) and
// checks its exit codes, messages and output files.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
  };
  for (const Case& c : cases) {
    const Result r = run(std::string(c.args) + o);
    INFO(c.args << "\n" << r.output);
    REQUIRE(r.code == 2);
    REQUIRE_THAT(r.output, Catch::Contains(c.flag) && Catch::Contains(c.range));
  }
  // Parse errors come from CLI11 and also name the flag.
  for (const char* args : {"--dt abc", "--no-such-flag", "--frames"}) {
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
                        "--integrator", "rk2", "--jacobian", "--solver", "--scene", "--frame-time"})
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
