// drape-render: simulates the cloth and renders it to a folder of PNG frames, offscreen.
// Settings: drape/scene_file/settings.hpp (flags = scene-file keys). Documentation: docs/viewer.md.
//
// Exit codes: 0 done; 1 runtime error (output not writable, OpenGL/OSMesa failure, ffmpeg);
//             2 invalid settings or input files (nothing was run); 3 the simulation failed
//             (diverged or the linear solver failed; frames already written are kept).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <utility>
#include <unistd.h>
#include <vector>

#include "drape/integrators/make_integrator.hpp"
#include "drape/io/obj.hpp"
#include "drape/io/state_io.hpp"
#include "drape/io/usd.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/drape_measures.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/seam_springs.hpp"
#include "drape/realtime/realtime_driver.hpp"
#include "drape/scene/cloth_scene.hpp"
#include "drape/scene_file/build_scene.hpp"
#include "drape/scene_file/command_line.hpp"
#include "drape/scene_file/pin_schedule.hpp"
#include "drape/scene_file/settings.hpp"
#include "drape/viewer/camera.hpp"
#include "drape/viewer/cloth_shape.hpp"
#include "drape/viewer/cloth_renderer.hpp"
#include "drape/viewer/collider_mesh.hpp"
#include "drape/viewer/collider_surface.hpp"
#include "drape/viewer/offscreen_context.hpp"
#include "drape/viewer/png.hpp"

extern char** environ;

namespace {

using drape::scene_file::PinSchedule;
using drape::scene_file::Settings;
using drape::scene_file::SettingsError;

constexpr int exit_runtime_error = 1;
constexpr int exit_bad_settings = 2;
constexpr int exit_simulation_failed = 3;

/// Thrown to end the run with an exit code and a message already printed.
struct Stop {
  int exit_code;
};

[[noreturn]] void stop(int exit_code, const std::string& message) {
  std::fprintf(stderr, "drape-render: error: %s\n", message.c_str());
  throw Stop{exit_code};
}

std::string frame_name(const std::string& out, int frame, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%05d.%s", frame, ext);
  return out + name;
}

/// Creates the output folder and proves it writable (read-only folders and full disks fail here,
/// not after the first frame).
void prepare_output_folder(const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out))
    stop(exit_runtime_error, "cannot create output folder '" + out +
                                 "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  try {
    const std::string probe = out + "/.drape-render-probe";
    drape::write_file_atomically(probe, [](std::FILE* f) { return std::fputs("probe\n", f) >= 0; });
    fs::remove(probe, ec);
  } catch (const drape::FileWriteError& e) {
    stop(exit_runtime_error, "output folder '" + out + "' is not writable: " + e.what());
  }
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

/// The contact columns of a log row (ContactReport over the frame's steps).
struct ContactColumns {
  int contacts = 0, sticking = 0, sliding = 0;                     // the frame's last step
  int corrected = 0, after_solve = 0;                              // summed over the frame's steps
  int rounds = 0;                                                  // largest over the frame's steps
  double deepest = 0;                                              // largest over the frame's steps (m)
  drape::Vec3<double> normal_force = drape::Vec3<double>::Zero();  // averaged over the frame's steps (N)
  drape::Vec3<double> friction_force = drape::Vec3<double>::Zero();
  // Self-collision, summed over the frame's steps (proximity pairs: the last step's).
  int self_proximity = 0, self_impacts = 0, self_zone_steps = 0, self_unresolved = 0;
};

/// log.csv: one row per frame, flushed as it is written. The columns are the same for every run
/// (contact, pin and air columns are 0 without colliders, pins or air); docs/viewer.md.
class FrameLog {
 public:
  FrameLog(const std::string& path, bool enabled) : m_path(path) {
    if (!enabled) return;
    m_file = std::fopen(path.c_str(), "w");
    if (!m_file) stop(exit_runtime_error, "cannot write '" + path + "'");
    std::fputs(
        "frame,sim_time,wall_time,steps,dropped_time,achieved_factor,kinetic_energy,spring_energy,"
        "gravity_energy,total_energy,max_strain,solver_iterations,max_residual,contacts,sticking,sliding,"
        "corrected,after_solve,contact_rounds,deepest_penetration,normal_force,normal_force_y,friction_force,"
        "pin_reaction_y,air_power,self_proximity,self_impacts,self_zone_steps,self_unresolved\n",
        m_file);
  }
  ~FrameLog() {
    if (m_file) std::fclose(m_file);
  }
  FrameLog(const FrameLog&) = delete;
  FrameLog& operator=(const FrameLog&) = delete;

  bool enabled() const { return m_file != nullptr; }

  /// The energies are summed over the scene's cloths, the strain is the largest of them.
  void write(int frame, const drape::ClothScene<double>& scene, double wall, int steps, double dropped, double factor,
             long long iterations, double residual, const ContactColumns& c, double pin_reaction_y, double air_power) {
    if (!m_file) return;
    double ek = 0, es = 0, eg = 0, strain = 0;
    for (int k = 0; k < scene.cloth_count(); ++k) {
      const drape::Clothd& cloth = scene.cloth(k);
      const drape::Stated& state = scene.state(k);
      const double cloth_ek = drape::kinetic_energy(cloth, state);
      const double cloth_es = drape::spring_potential_energy(cloth, state.positions);
      const double cloth_eg = drape::gravitational_potential_energy(cloth, state.positions);
      const double cloth_strain = drape::max_strain(cloth, state.positions);
      // The first cloth's values as they are (a sum from 0 would print its -0 as 0).
      ek = k == 0 ? cloth_ek : ek + cloth_ek;
      es = k == 0 ? cloth_es : es + cloth_es;
      eg = k == 0 ? cloth_eg : eg + cloth_eg;
      strain = k == 0 ? cloth_strain : std::max(strain, cloth_strain);
    }
    if (std::fprintf(m_file, "%d,%.9g,%.6f,%d,%.9g,%.6g,%.9g,%.9g,%.9g,%.9g,%.6g,%lld,%.3g", frame, scene.state(0).time,
                     wall, steps, dropped, factor, ek, es, eg, ek + es + eg, strain, iterations, residual) < 0 ||
        std::fprintf(m_file, ",%d,%d,%d,%d,%d,%d,%.6g,%.9g,%.9g,%.9g,%.9g,%.9g", c.contacts, c.sticking, c.sliding,
                     c.corrected, c.after_solve, c.rounds, c.deepest, c.normal_force.norm(), c.normal_force.y(),
                     c.friction_force.norm(), pin_reaction_y, air_power) < 0 ||
        std::fprintf(m_file, ",%d,%d,%d,%d\n", c.self_proximity, c.self_impacts, c.self_zone_steps, c.self_unresolved) <
            0 ||
        std::fflush(m_file) != 0)
      throw drape::FileWriteError("cannot write '" + m_path + "'");
  }

 private:
  std::string m_path;
  std::FILE* m_file = nullptr;
};

/// The steps between two frames, as the log reports them.
struct FrameSteps {
  int steps = 0;
  double dropped = 0;
  long long iterations = 0;
  double residual = 0;
  ContactColumns contact;  // forces summed here, divided by the steps when logged
};

/// A run: the simulation, the renderer and the outputs, and the two ways of stepping through time.
class Run {
 public:
  /// `framed`: the box the fixed camera frames (framed_box()); `floor_y`: the floor's height.
  /// `cloth`: the first cloth (for the pins' reaction); `specs`: every cloth (render::cloth_specs()).
  Run(const Settings& s, const drape::Clothd& cloth, const std::vector<drape::ClothSpecd>& specs, drape::Stated start,
      const drape::viewer::Bounds& framed, double floor_y)
      : m_s(s),
        m_cloth(cloth),
        m_scene(specs, s.integrator, s.stepping, s.cloth.self_collision),
        m_state(m_scene.state(0)),
        m_context(s.output.debug_gl ? drape::viewer::GlDebugSink(drape::viewer::print_gl_debug_message)
                                    : drape::viewer::GlDebugSink{}),
        m_renderer(scene_pattern(m_scene), scene_triangles(m_scene), render_settings(s, cloth)),
        m_fixed_camera(
            drape::viewer::frame_bounds(framed, aspect(s), float(s.output.azimuth), float(s.output.elevation))),
        m_follow(aspect(s), float(s.output.azimuth), float(s.output.elevation), float(floor_y)),
        m_triangles(scene_triangles(m_scene)),
        m_log(s.output.out + "/log.csv", !s.output.no_csv),
        m_progress(!s.output.quiet && ::isatty(STDERR_FILENO)),
        m_forces(cloth, 1),
        m_pin_schedule(s) {
    m_state = std::move(start);
    m_t0 = m_state.time;
    m_previous_sim = m_t0;
    m_pin_schedule.apply(m_state.time, integrator().dt(), integrator().pins());  // those due at the start
    m_fixed_camera.floor_height = float(floor_y);
    m_renderer.set_camera(m_fixed_camera);
    // The colliders' meshes; a plane at the floor's height facing +y is the floor itself.
    for (const drape::Colliderd& c : cloth.colliders()) {
      if (drape::scene_file::is_floor(c, floor_y)) continue;
      m_solids.push_back({&c, drape::viewer::local_collider_mesh(c)});
    }
    if (!s.output.usd.empty()) start_usd(framed);
  }

  /// Frames 0 .. n-1 at t0 + k frame_time, rounded to whole steps: rendering speed does not matter.
  void offline() {
    const drape::scene_file::TimeLine& t = m_s.time;
    const int total =
        t.duration_given ? std::max(1, static_cast<int>(std::ceil(t.duration / t.frame_time - 1e-9)) + 1) : t.frames;
    m_total_frames = total;
    draw(all_positions(), m_state.time, {});
    for (int k = 1; k < total; ++k) {
      const long long target = std::llround(double(k) * t.frame_time / m_s.stepping.dt);
      FrameSteps done;
      while (m_steps_total < target) step(done);
      draw(all_positions(), m_state.time, done);
    }
    m_progress.finish();
  }

  /// The driver grants whole steps for the wall time each frame took; frames are drawn between the
  /// last two states at the driver's interpolation fraction.
  void realtime() {
    const drape::scene_file::TimeLine& t = m_s.time;
    m_total_frames = t.frames;
    draw(all_positions(), m_state.time, {});
    drape::RealtimeDriver<> driver(integrator().dt(), m_s.realtime);
    drape::Matrix3X<double> previous = all_positions(), between;
    double previous_time = m_state.time;
    driver.start();
    while (t.duration_given ? m_state.time - m_t0 < t.duration : m_frame < t.frames) {
      const drape::RealtimeFrame f = driver.next_frame();
      FrameSteps done;
      done.dropped = f.dropped;
      for (int k = 0; k < f.steps; ++k) {
        if (k == f.steps - 1) {
          previous = all_positions();
          previous_time = m_state.time;
        }
        step(done);
      }
      between = previous + f.interpolation * (all_positions() - previous);
      draw(between, previous_time + f.interpolation * (m_state.time - previous_time), done);
    }
    m_progress.finish();
  }

  /// Writes the USD file of the frames drawn (--usd), if asked for.
  void finish_usd() {
    if (m_usd) m_usd->finish();
  }

  const drape::Stated& state() const { return m_state; }
  int frames_written() const { return m_frame; }
  long long steps() const { return m_steps_total; }
  double wall_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_wall_start).count();
  }

 private:
  static float aspect(const Settings& s) { return float(s.output.width) / float(s.output.height); }

  /// Every cloth's triangles as one mesh, node ids one cloth after the other (ClothScene::node_offset).
  static std::vector<std::array<int, 3>> scene_triangles(const drape::ClothScene<double>& scene) {
    std::vector<std::array<int, 3>> triangles;
    for (int k = 0; k < scene.cloth_count(); ++k) {
      const int offset = scene.node_offset(k);
      for (const std::array<int, 3>& t : scene.cloth(k).triangles())
        triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
    return triangles;
  }
  /// Every cloth's checker coordinates (view_geometry's cloth_shape.hpp).
  static std::vector<std::array<float, 2>> scene_pattern(const drape::ClothScene<double>& scene) {
    std::vector<std::array<float, 2>> pattern;
    for (int k = 0; k < scene.cloth_count(); ++k) {
      const auto cloth = drape::viewer::checker_coordinates(scene.cloth(k));
      pattern.insert(pattern.end(), cloth.begin(), cloth.end());
    }
    return pattern;
  }
  /// Every cloth's positions, one after the other (the first cloth's own matrix when it is alone).
  const drape::Matrix3X<double>& all_positions() {
    if (m_scene.cloth_count() == 1) return m_state.positions;
    m_all.resize(3, m_scene.node_count());
    for (int k = 0; k < m_scene.cloth_count(); ++k)
      m_all.middleCols(m_scene.node_offset(k), m_scene.cloth(k).node_count()) = m_scene.state(k).positions;
    return m_all;
  }
  drape::Integrator<double>& integrator() { return m_scene.integrator(0); }
  const drape::Integrator<double>& integrator() const { return m_scene.integrator(0); }
  static drape::viewer::RenderSettings render_settings(const Settings& s, const drape::Clothd& cloth) {
    drape::viewer::RenderSettings rs;
    rs.width = s.output.width;
    rs.height = s.output.height;
    rs.samples = s.output.samples;
    rs.floor = !s.output.no_floor;
    rs.floor_cell = float(drape::viewer::longest_side(cloth) / 8.0);
    return rs;
  }

  /// One step; a failed one ends the run (exit code 3), keeping the frames written.
  void step(FrameSteps& done) {
    m_pin_schedule.apply(m_state.time, integrator().dt(), integrator().pins());
    const drape::StepStatus status = m_scene.step();
    if (!status) {
      m_progress.finish();
      stop(exit_simulation_failed,
           "the simulation failed while computing frame " + std::to_string(m_frame) + " (t = " + seconds(m_state.time) +
               " s, after " + std::to_string(m_steps_total) + " steps): " + drape::to_string(status.error) + ". The " +
               std::to_string(m_frame) + " frames before it are kept in '" + m_s.output.out + "'.");
    }
    ++m_steps_total;
    ++done.steps;
    done.iterations += status.iterations;
    done.residual = std::max(done.residual, status.residual);
    const drape::ContactReport<double>& report = integrator().contact_report();
    ContactColumns& c = done.contact;
    c.corrected += report.corrected;
    c.after_solve += report.after_solve;
    c.rounds = std::max(c.rounds, report.rounds);
    c.deepest = std::max(c.deepest, report.deepest);
    c.normal_force += report.normal_force;
    c.friction_force += report.friction_force;
    const drape::SelfCollisionReport& self = m_scene.collision_report();
    c.self_impacts += self.impacts;
    c.self_zone_steps += self.failsafe() ? 1 : 0;
    c.self_unresolved += self.unresolved;
  }

  /// The log's contact columns for a frame after `done`: the counts of the last step, the forces
  /// averaged over the frame's steps (a frame without steps repeats the last step's).
  ContactColumns contact_columns(const FrameSteps& done) const {
    const drape::ContactReport<double>& report = integrator().contact_report();
    ContactColumns c = done.contact;
    c.contacts = report.contacts;
    c.sticking = report.sticking;
    c.sliding = report.sliding;
    c.self_proximity = m_scene.collision_report().proximity_pairs;
    if (done.steps > 0) {
      c.normal_force /= done.steps;
      c.friction_force /= done.steps;
    } else if (m_steps_total > 0) {
      c.normal_force = report.normal_force;
      c.friction_force = report.friction_force;
    }
    return c;
  }

  /// The pins' reaction on the cloth (drape::pin_reaction, with one assembler for the run) and the
  /// power of the force terms besides springs and gravity (the air's), sum of f . v (W).
  /// The pins are the run's at the frame (the integrator's PinSet: with [[moving-pins]], those pinned now).
  std::pair<double, double> pin_reaction_y_and_air_power() {
    const std::vector<int>& pinned = integrator().pins().nodes();
    if (pinned.empty() && m_cloth.force_terms().empty()) return {0.0, 0.0};
    m_force.resize(3, m_cloth.node_count());
    double pin_y = 0;
    if (!pinned.empty()) {
      m_forces.force(m_state.positions, m_state.velocities, m_state.time, m_force);
      for (int p : pinned) pin_y -= m_force(1, p);
    }
    double power = 0;
    if (!m_cloth.force_terms().empty()) {
      m_force.setZero();
      for (const auto& term : m_cloth.force_terms())
        term->add_force(m_state.positions, m_state.velocities, m_state.time, m_force);
      power = m_force.cwiseProduct(m_state.velocities).sum();
    }
    return {pin_y, power};
  }

  /// The colliders at time t: their meshes to draw, and the extra points the follow camera frames.
  void place_solids(double t, std::vector<drape::viewer::SolidMesh>& meshes, drape::viewer::Bounds& box) const {
    meshes.clear();
    for (const Solid& solid : m_solids) {
      if (solid.local.empty()) continue;  // planes: once the camera is known
      const drape::RigidPose<double> pose = solid.collider->motion().pose(t);
      meshes.push_back(solid.collider->deforms()  // a key-framed mesh: its shape at t
                           ? drape::viewer::place_mesh(drape::viewer::local_collider_mesh(*solid.collider, 10, t), pose)
                           : drape::viewer::place_mesh(solid.local, pose));
      drape::viewer::extend(box, meshes.back());
    }
  }

  /// The USD file's meshes (--usd): each cloth ("cloth", "cloth_1", ... in the order of ClothScene),
  /// then each collider of the first cloth, the floor collider too, by its shape's name, a plane as
  /// a square around the framed box. Its temporary file is made now: an unwritable folder stops the
  /// run before the first step.
  void start_usd(const drape::viewer::Bounds& framed) {
    m_usd.emplace(m_s.output.usd, 1.0 / m_s.time.frame_time);
    for (int k = 0; k < m_scene.cloth_count(); ++k)
      m_usd_cloths.push_back(m_usd->add_mesh("cloth", m_scene.cloth(k).node_count(), m_scene.cloth(k).triangles(),
                                             {true, std::array<float, 3>{0.8f, 0.25f, 0.2f}}));
    const float half_size = std::max(1.0f, framed.size().norm());
    for (const drape::Colliderd& c : m_cloth.colliders()) {
      UsdCollider collider{&c, drape::viewer::local_collider_surface(c, framed.centre(), half_size, m_t0), -1};
      const bool plane = c.kind() == drape::ShapeKind::Plane;
      collider.mesh = m_usd->add_mesh(drape::to_string(c.kind()), Eigen::Index(collider.surface.points.size()),
                                      collider.surface.triangles, {plane, std::array<float, 3>{0.6f, 0.6f, 0.6f}});
      m_usd_colliders.push_back(std::move(collider));
    }
  }

  /// The frame's sample of every mesh of the USD file: the cloths' `positions`, the colliders at `time`.
  void add_usd_frame(const drape::Matrix3X<double>& positions, double time) {
    for (int k = 0; k < m_scene.cloth_count(); ++k)
      m_usd->set_points(m_usd_cloths[std::size_t(k)],
                        positions.middleCols(m_scene.node_offset(k), m_scene.cloth(k).node_count()));
    for (UsdCollider& c : m_usd_colliders) {
      if (c.collider->deforms())  // a key-framed mesh: its vertices at this time
        c.surface = drape::viewer::local_collider_surface(*c.collider, Eigen::Vector3f::Zero(), 1.0f, time);
      drape::viewer::place_points(c.surface.points, c.collider->motion().pose(time), m_placed);
      m_usd->set_points(c.mesh, m_placed);
    }
    m_usd->end_frame();
  }

  static std::string seconds(double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", t);
    return text;
  }

  /// Renders `positions` as the next frame, writes its files and its log row.
  void draw(const drape::Matrix3X<double>& positions, double time, const FrameSteps& done) {
    if (m_solids.empty()) {
      if (m_s.output.camera == drape::scene_file::CameraMode::Follow)
        m_renderer.set_camera(m_follow.update(positions, m_state.time - m_previous_sim));
    } else {
      drape::viewer::Bounds box;
      place_solids(time, m_meshes, box);
      if (m_s.output.camera == drape::scene_file::CameraMode::Follow) {
        drape::viewer::framed_points(positions, box, !m_meshes.empty(), m_framed);
        m_renderer.set_camera(m_follow.update(m_framed, m_state.time - m_previous_sim));
      }
      const drape::viewer::Camera& cam = m_renderer.camera();
      for (const Solid& solid : m_solids)
        if (solid.local.empty())
          m_meshes.push_back(drape::viewer::plane_quad(*solid.collider, time, cam.target, 2.0f * cam.scene_radius));
      m_renderer.set_solids(m_meshes);
    }
    m_renderer.update_positions(positions);
    drape::viewer::write_png(frame_name(m_s.output.out, m_frame, "png"), m_renderer.render());
    if (m_s.output.obj) drape::write_obj(frame_name(m_s.output.out, m_frame, "obj"), positions, m_triangles);
    if (m_usd) add_usd_frame(positions, time);
    const double wall = wall_seconds();
    const double factor = wall > m_previous_wall ? (m_state.time - m_previous_sim) / (wall - m_previous_wall) : 0.0;
    if (m_log.enabled()) {
      const auto [pin_y, air_power] = pin_reaction_y_and_air_power();
      m_log.write(m_frame, m_scene, wall, done.steps, done.dropped, factor, done.iterations, done.residual,
                  contact_columns(done), pin_y, air_power);
    }
    m_previous_wall = wall;
    m_previous_sim = m_state.time;
    ++m_frame;
    const double simulated = m_state.time - m_t0;
    const double overall = wall > 0 ? simulated / wall : 0.0;
    const double progress =
        m_s.time.duration_given && m_s.time.realtime ? simulated / m_s.time.duration : double(m_frame) / m_total_frames;
    const double eta = progress > 0 ? wall * (1 - progress) / progress : 0.0;
    m_progress.update(std::min(progress, 1.0), m_frame, m_state.time, overall, eta);
  }

  const Settings& m_s;
  const drape::Clothd& m_cloth;
  drape::ClothScene<double> m_scene;  // every cloth, its integrator and state; they collide when self-collision is on
  drape::Stated& m_state;             // the first cloth's
  drape::Matrix3X<double> m_all;      // every cloth's positions (all_positions())
  drape::viewer::OffscreenContext m_context;
  drape::viewer::ClothRenderer m_renderer;
  /// Frames the box the cloth can hang in; its floor height stays for the follow camera too.
  drape::viewer::Camera m_fixed_camera;
  drape::viewer::FollowCamera m_follow;
  std::vector<std::array<int, 3>> m_triangles;
  FrameLog m_log;
  ProgressBar m_progress;
  double m_t0 = 0;
  const std::chrono::steady_clock::time_point m_wall_start = std::chrono::steady_clock::now();
  double m_previous_sim = 0;  // simulated time of the previous frame
  double m_previous_wall = 0;
  int m_frame = 0;
  int m_total_frames = 1;
  long long m_steps_total = 0;
  drape::ForceAssembler<double> m_forces;  // for the pins' reaction in the log
  drape::Matrix3X<double> m_force;
  /// A collider to draw: its mesh in its own frame (empty for a plane, drawn as a quad).
  struct Solid {
    const drape::Colliderd* collider;
    std::vector<Eigen::Vector3f> local;
  };
  std::vector<Solid> m_solids;
  std::vector<drape::viewer::SolidMesh> m_meshes;
  drape::Matrix3X<double> m_framed;  // nodes and colliders for the follow camera
  PinSchedule m_pin_schedule;        // the [[moving-pins]] tables, applied before each step
  /// --usd: the writer, its cloth meshes (one per cloth of the scene) and its colliders.
  std::optional<drape::UsdAnimationWriter> m_usd;
  std::vector<int> m_usd_cloths;
  struct UsdCollider {
    const drape::Colliderd* collider;
    drape::viewer::IndexedMesh surface;  // in its own frame
    int mesh;
  };
  std::vector<UsdCollider> m_usd_colliders;
  Eigen::Matrix3Xf m_placed;  // a collider's points at the frame's time
};

/// Runs ffmpeg on the frames; true on success.
bool make_video(const Settings& s, int frames_written) {
  const std::string ext = s.output.video.substr(s.output.video.rfind('.'));
  char fps[32];
  std::snprintf(fps, sizeof fps, "%.6g", 1.0 / s.time.frame_time);
  std::vector<std::string> args = {"ffmpeg",
                                   "-nostdin",
                                   "-y",
                                   "-loglevel",
                                   "error",
                                   "-framerate",
                                   fps,
                                   "-i",
                                   s.output.out + "/frame_%05d.png",
                                   "-frames:v",
                                   std::to_string(frames_written)};
  if (ext == ".gif") {
    args.insert(args.end(), {"-vf", "split[a][b];[a]palettegen[p];[b][p]paletteuse"});
  } else if (ext == ".webm") {
    args.insert(args.end(), {"-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "35", "-pix_fmt", "yuv420p"});
  } else {  // .mp4 .mkv; yuv420p needs even sizes
    args.insert(args.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"});
  }
  args.push_back(s.output.video);
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, "ffmpeg", nullptr, nullptr, argv.data(), environ) != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// The names of the cloth's force terms besides springs and gravity, for the summary line.
std::string force_term_names(const drape::Clothd& cloth) {
  std::string names;
  for (const auto& term : cloth.force_terms()) names += (names.empty() ? "" : " + ") + term->name();
  return names;
}

/// A garment's seams at the end of a run: how many sewn pairs lie within the contact thickness of
/// each other (closed) and the widest gap, printed to stdout as "seams: ...". Nothing for a cloth
/// without seams.
void report_seams(const drape::Clothd& cloth, const drape::Stated& state) {
  for (const auto& term : cloth.force_terms()) {
    const auto* seams = dynamic_cast<const drape::SeamSprings<double>*>(term.get());
    if (seams == nullptr) continue;
    const double closed_within = cloth.contact_thickness();
    std::size_t closed = 0;
    for (const auto& [a, b] : seams->pairs())
      closed += (state.positions.col(a) - state.positions.col(b)).norm() <= closed_within ? 1 : 0;
    std::printf("seams: %zu of %zu sewn pairs within %.4g m, the widest %.4g m apart (t = %.4g s)\n", closed,
                seams->pairs().size(), closed_within, seams->widest_gap(state.positions), state.time);
  }
}

int run(const Settings& s) {
  // Inputs and outputs are checked before any simulation or rendering.
  drape::scene_file::PreparedScene scene = drape::scene_file::prepare_scene(s);
  const drape::Clothd cloth = drape::scene_file::make_cloth(s, scene.first);
  prepare_output_folder(s.output.out);

  Run run(s, cloth, scene.specs, std::move(scene.start), scene.framed, scene.floor_y);
  if (s.time.realtime)
    run.realtime();
  else
    run.offline();

  run.finish_usd();
  if (!s.output.save_state.empty()) drape::save_state(s.output.save_state, run.state());
  if (s.output.cusick_disk > 0) {
    // The specimen's radius: half its rest shape's longest side (a disk's diameter).
    const double specimen = 0.5 * drape::viewer::longest_side(cloth);
    const drape::DrapeMeasures<double> m = drape::measure_drape<double>(
        run.state().positions, cloth.triangles(), drape::Vec3<double>::Zero(), s.output.cusick_disk, specimen);
    std::printf("drape coefficient %.4f, %d folds (support disk radius %.4g m, specimen radius %.4g m, t = %.4g s)\n",
                m.drape_coefficient, m.fold_count, s.output.cusick_disk, specimen, run.state().time);
  }
  report_seams(cloth, run.state());
  const double wall = run.wall_seconds();
  if (!s.output.video.empty() && !make_video(s, run.frames_written()))
    stop(exit_runtime_error,
         "ffmpeg could not make '" + s.output.video + "' from the frames in '" + s.output.out + "'");
  if (!s.output.quiet) {
    const std::string forces = force_term_names(cloth);
    const std::size_t colliders = cloth.colliders().size();
    const std::string contact =
        colliders == 0 ? "" : ", " + std::to_string(colliders) + (colliders == 1 ? " collider" : " colliders");
    std::fprintf(stderr, "drape-render: %d frames in '%s', t = %.4g s simulated in %.3g s (%lld steps, %s, %s%s%s)%s%s\n",
                 run.frames_written(), s.output.out.c_str(), run.state().time, wall, run.steps(),
                 drape::to_string(s.integrator), s.time.realtime ? "real time" : "offline",
                 forces.empty() ? "" : (", with " + forces).c_str(), contact.c_str(),
                 s.output.video.empty() ? "" : (", video " + s.output.video).c_str(),
                 s.output.usd.empty() ? "" : (", USD " + s.output.usd).c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  int exit_code = 0;
  try {
    if (!drape::scene_file::parse_settings(argc, argv, settings, exit_code)) return exit_code;
  } catch (const SettingsError& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_bad_settings;
  }
  try {
    return run(settings);
  } catch (const Stop& s) { return s.exit_code; } catch (const SettingsError& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_bad_settings;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_bad_settings;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drape-render: error: %s\n", e.what());
    return exit_runtime_error;
  }
}
