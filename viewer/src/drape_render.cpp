// drape-render: simulates the cloth and renders it to a folder of PNG frames, offscreen.
// Settings: render_settings.hpp (flags = scene-file keys). Documentation: docs/viewer.md.
//
// Exit codes: 0 done; 1 runtime error (output not writable, OpenGL/OSMesa failure, ffmpeg);
//             2 invalid settings or input files (nothing was run); 3 the simulation failed
//             (diverged or the linear solver failed; frames already written are kept).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "drape/core/cloth.hpp"
#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/io/obj.hpp"
#include "drape/io/state_io.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/realtime/realtime_driver.hpp"
#include "drape/viewer/camera.hpp"
#include "drape/viewer/cloth_renderer.hpp"
#include "drape/viewer/offscreen_context.hpp"
#include "drape/viewer/png.hpp"
#include "render_settings.hpp"

extern char** environ;

namespace {

using drape::render::Settings;
using drape::render::SettingsError;
using Stepper = std::function<drape::StepStatus(drape::Stated&, double)>;

constexpr int exit_runtime_error = 1;
constexpr int exit_bad_settings = 2;
constexpr int exit_simulation_failed = 3;

drape::ClothSpecd make_spec(const Settings& s) {
  drape::ClothSpecd spec;
  spec.nx = s.nx;
  spec.ny = s.ny;
  spec.spacing = s.spacing;
  spec.node_mass = s.mass;
  spec.gravity = s.gravity;
  spec.dt = s.dt;
  spec.springs = {{s.structural_ks, s.structural_kd}, {s.shear_ks, s.shear_kd}, {s.bend_ks, s.bend_kd}};
  spec.boundary = s.boundary == 1 ? drape::BoundaryCondition::OneCorner : drape::BoundaryCondition::TwoCorners;
  if (s.pins_given) spec.pinned_nodes = s.pins;
  return spec;
}

/// The chosen integrator behind one call signature, so the loops below do not care which it is.
Stepper make_stepper(const Settings& s, const drape::Clothd& cloth) {
  if (s.integrator == "implicit") {
    auto implicit = std::make_shared<drape::ImplicitEuler<double>>(cloth, drape::render::implicit_options(s));
    return [implicit](drape::Stated& state, double dt) { return implicit->step(state, dt); };
  }
  auto rk2 = std::make_shared<drape::Rk2<double>>(cloth, s.threads);
  return [rk2](drape::Stated& state, double dt) { return rk2->step(state, dt); };
}

std::string frame_name(const std::string& out, int frame, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%05d.%s", frame, ext);
  return out + name;
}

/// One line on a terminal, rewritten in place; nothing when stderr is not a terminal.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : m_enabled(enabled) {}
  void update(double done_fraction, int frames, double sim_time, double factor, double eta) {
    if (!m_enabled) return;
    const auto now = std::chrono::steady_clock::now();
    if (done_fraction < 1.0 && now - m_last < std::chrono::milliseconds(100)) return;
    m_last = now;
    const int width = 30;
    const int filled = std::clamp(static_cast<int>(done_fraction * width), 0, width);
    std::fprintf(stderr, "\r[%s%s] %3.0f%%  %d frames  t = %.3f s  real-time factor %.3f  ETA %.0f s   ",
                 std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(width - filled), '.').c_str(), 100.0 * done_fraction, frames,
                 sim_time, factor, std::max(0.0, eta));
    std::fflush(stderr);
  }
  void finish() {
    if (m_enabled) std::fputc('\n', stderr);
  }

 private:
  bool m_enabled;
  std::chrono::steady_clock::time_point m_last{};
};

/// Runs ffmpeg on the frames; true on success.
bool make_video(const Settings& s, int frames_written) {
  const std::string ext = s.video.substr(s.video.rfind('.'));
  char fps[32];
  std::snprintf(fps, sizeof fps, "%.6g", 1.0 / s.frame_time);
  std::vector<std::string> args = {"ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", fps,
                                   "-i", s.out + "/frame_%05d.png", "-frames:v", std::to_string(frames_written)};
  if (ext == ".gif") {
    args.insert(args.end(), {"-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse"});
  } else if (ext == ".webm") {
    args.insert(args.end(), {"-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "35", "-pix_fmt", "yuv420p"});
  } else {  // .mp4 .mkv; yuv420p needs even sizes
    args.insert(args.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"});
  }
  args.push_back(s.video);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, argv.data(), environ) != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

int run(const Settings& s) {
  namespace fs = std::filesystem;
  const drape::Clothd cloth(make_spec(s));
  const int n = cloth.node_count();

  // Inputs and outputs are checked before any simulation or rendering.
  drape::Stated state = cloth.initial_state();
  if (!s.load_state.empty()) {
    try {
      state = drape::load_state<double>(s.load_state, n);
    } catch (const drape::StateFormatError& e) {
      std::fprintf(stderr, "drape-render: error: --load-state: %s\n", e.what());
      return exit_bad_settings;
    }
  }
  std::error_code ec;
  fs::create_directories(s.out, ec);
  if (ec || !fs::is_directory(s.out)) {
    std::fprintf(stderr, "drape-render: error: cannot create output folder '%s': %s\n", s.out.c_str(),
                 ec ? ec.message().c_str() : "a file of that name exists");
    return exit_runtime_error;
  }
  try {  // a probe file: read-only folders and full disks fail here, not after the first frame
    const std::string probe = s.out + "/.drape-render-probe";
    drape::write_file_atomically(probe, [](std::FILE* f) { return std::fputs("probe\n", f) >= 0; });
    fs::remove(probe, ec);
  } catch (const drape::FileWriteError& e) {
    std::fprintf(stderr, "drape-render: error: output folder '%s' is not writable: %s\n", s.out.c_str(), e.what());
    return exit_runtime_error;
  }

  Stepper step = make_stepper(s, cloth);
  drape::viewer::OffscreenContext context(s.debug_gl ? drape::viewer::GlDebugSink(drape::viewer::print_gl_debug_message)
                                                     : drape::viewer::GlDebugSink{});
  drape::viewer::RenderSettings rs;
  rs.width = s.width;
  rs.height = s.height;
  rs.samples = s.samples;
  rs.floor = !s.no_floor;
  rs.floor_cell = float(std::max(s.nx - 1, s.ny - 1) * s.spacing / 8.0);
  drape::viewer::ClothRenderer renderer(s.nx, s.ny, cloth.grid().triangles(), rs);
  const float aspect = float(s.width) / float(s.height);
  const drape::viewer::Bounds hanging = drape::viewer::hanging_bounds(cloth, state.positions);
  renderer.set_camera(drape::viewer::frame_bounds(hanging, aspect, float(s.azimuth), float(s.elevation)));
  const float floor_y = renderer.camera().floor_height;
  drape::viewer::FollowCamera follow(aspect, float(s.azimuth), float(s.elevation), floor_y);
  const auto triangles = cloth.grid().triangles();

  std::FILE* csv = nullptr;
  const std::string csv_path = s.out + "/log.csv";
  if (!s.no_csv) {
    csv = std::fopen(csv_path.c_str(), "w");
    if (!csv) {
      std::fprintf(stderr, "drape-render: error: cannot write '%s'\n", csv_path.c_str());
      return exit_runtime_error;
    }
    std::fputs("frame,sim_time,wall_time,steps,dropped_time,achieved_factor,kinetic_energy,spring_energy,"
               "gravity_energy,total_energy,max_strain,solver_iterations,max_residual\n", csv);
  }
  struct CsvCloser {
    std::FILE*& f;
    ~CsvCloser() {
      if (f) std::fclose(f);
    }
  } closer{csv};

  const double t0 = state.time;
  const bool duration_mode = s.duration_given;
  const int total_frames = duration_mode && !s.realtime
                               ? std::max(1, static_cast<int>(std::ceil(s.duration / s.frame_time - 1e-9)) + 1)
                               : s.frames;
  ProgressBar progress(!s.quiet && ::isatty(STDERR_FILENO));
  const auto wall_start = std::chrono::steady_clock::now();
  const auto wall_seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };

  // Per-frame bookkeeping shared by both modes.
  int frame = 0;
  long long steps_total = 0;
  double previous_wall = 0, previous_sim = t0;
  const auto emit_frame = [&](const drape::Matrix3X<double>& draw, int steps, double dropped, long long iterations,
                              double residual) {
    if (s.camera == "follow") renderer.set_camera(follow.update(draw, cloth.pins().nodes(), state.time - previous_sim));
    renderer.update_positions(draw);
    drape::viewer::write_png(frame_name(s.out, frame, "png"), renderer.render());
    if (s.obj) drape::write_obj(frame_name(s.out, frame, "obj"), draw, triangles);
    const double wall = wall_seconds();
    const double factor = wall > previous_wall ? (state.time - previous_sim) / (wall - previous_wall) : 0.0;
    if (csv) {
      const double ek = drape::kinetic_energy(cloth, state);
      const double es = drape::spring_potential_energy(cloth, state.positions);
      const double eg = drape::gravitational_potential_energy(cloth, state.positions);
      if (std::fprintf(csv, "%d,%.9g,%.6f,%d,%.9g,%.6g,%.9g,%.9g,%.9g,%.9g,%.6g,%lld,%.3g\n", frame, state.time, wall,
                       steps, dropped, factor, ek, es, eg, ek + es + eg, drape::max_strain(cloth, state.positions),
                       iterations, residual) < 0 ||
          std::fflush(csv) != 0)
        throw drape::FileWriteError("cannot write '" + csv_path + "'");
    }
    previous_wall = wall;
    previous_sim = state.time;
    ++frame;
    const double simulated = state.time - t0;
    const double overall = wall > 0 ? simulated / wall : 0.0;
    const double done = duration_mode && s.realtime ? simulated / s.duration : double(frame) / total_frames;
    const double eta = done > 0 ? wall * (1 - done) / done : 0.0;
    progress.update(std::min(done, 1.0), frame, state.time, overall, eta);
  };
  const auto fail = [&](const drape::StepStatus& status) {
    progress.finish();
    std::fprintf(stderr,
                 "drape-render: error: the simulation failed while computing frame %d (t = %.6g s, after %lld "
                 "steps): %s. The %d frames before it are kept in '%s'.\n",
                 frame, state.time, steps_total, drape::to_string(status.error), frame, s.out.c_str());
    return exit_simulation_failed;
  };

  emit_frame(state.positions, 0, 0.0, 0, 0.0);  // frame 0: the starting state
  if (!s.realtime) {
    // Offline: frame k shows t0 + k * frame_time, rounded to whole steps of dt.
    for (int k = 1; k < total_frames; ++k) {
      const long long target = std::llround(double(k) * s.frame_time / s.dt);
      int steps = 0;
      long long iterations = 0;
      double residual = 0;
      while (steps_total < target) {
        const drape::StepStatus status = step(state, s.dt);
        if (!status) return fail(status);
        ++steps_total;
        ++steps;
        iterations += status.iterations;
        residual = std::max(residual, status.residual);
      }
      emit_frame(state.positions, steps, 0.0, iterations, residual);
    }
  } else {
    // Real time: the driver grants whole steps for the wall time each frame took; frames are
    // drawn between the last two states at the driver's interpolation fraction.
    drape::RealtimeDriver<> driver(s.dt, s.realtime_factor, s.max_steps_per_frame);
    drape::Matrix3X<double> previous = state.positions, draw;
    driver.start();
    while (duration_mode ? state.time - t0 < s.duration : frame < s.frames) {
      const drape::RealtimeFrame f = driver.next_frame();
      long long iterations = 0;
      double residual = 0;
      for (int k = 0; k < f.steps; ++k) {
        if (k == f.steps - 1) previous = state.positions;
        const drape::StepStatus status = step(state, s.dt);
        if (!status) return fail(status);
        ++steps_total;
        iterations += status.iterations;
        residual = std::max(residual, status.residual);
      }
      draw = previous + f.interpolation * (state.positions - previous);
      emit_frame(draw, f.steps, f.dropped, iterations, residual);
    }
  }
  progress.finish();

  if (!s.save_state.empty()) drape::save_state(s.save_state, state);
  const double wall = wall_seconds();
  if (!s.video.empty() && !make_video(s, frame)) {
    std::fprintf(stderr, "drape-render: error: ffmpeg could not make '%s' from the frames in '%s'\n", s.video.c_str(),
                 s.out.c_str());
    return exit_runtime_error;
  }
  if (!s.quiet)
    std::fprintf(stderr, "drape-render: %d frames in '%s', t = %.4g s simulated in %.3g s (%lld steps, %s, %s)%s\n",
                 frame, s.out.c_str(), state.time, wall, steps_total, s.integrator.c_str(),
                 s.realtime ? "real time" : "offline", s.video.empty() ? "" : (", video " + s.video).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  int exit_code = 0;
  try {
    if (!drape::render::parse_settings(argc, argv, settings, exit_code)) return exit_code;
  } catch (const SettingsError& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_bad_settings;
  }
  try {
    return run(settings);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_bad_settings;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_runtime_error;
  }
}
