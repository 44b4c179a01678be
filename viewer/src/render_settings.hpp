#pragma once
// drape-render's settings: every command-line flag, the same keys in a TOML scene file, the
// defaults, and the validation that runs before any work.

#include <stdexcept>
#include <string>
#include <vector>

#include "drape/integrators/implicit_euler.hpp"

namespace drape::render {

/// A bad value: the message names the flag and the allowed range. Exit code 2.
class SettingsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Settings {
  std::string scene;  // TOML file with the same keys as the flags

  // Simulation.
  std::string integrator = "rk2";  // rk2 | implicit
  std::string jacobian = "spd";    // exact | symmetric | spd (implicit only)
  std::string solver = "cg";       // see --help for the ones this build has (implicit only)
  double tolerance = 1e-6;
  int max_iterations = 2000;
  std::string pin_treatment = "eliminate";  // eliminate | filter
  std::string preconditioner = "multigrid"; // multigrid | block-jacobi (cg only)
  double dt = 0.0005;
  double structural_ks = 20000, structural_kd = 10;
  double shear_ks = 5000, shear_kd = 5;
  double bend_ks = 500, bend_kd = 1;
  int boundary = 2;          // 1: corner (0,0); 2: corners (0,0) and (nx-1,0)
  std::vector<int> pins;     // node ids j*nx+i; replaces --boundary when given
  bool pins_given = false;
  int nx = 33, ny = 33;
  double spacing = 0.1, mass = 0.03, gravity = 10;
  int threads = 0;

  // Time line.
  int frames = 120;
  double duration = 0;       // simulated s; if > 0 replaces --frames
  bool frames_given = false, duration_given = false;
  double frame_time = 1.0 / 30.0;
  bool realtime = false;
  double realtime_factor = 1;
  int max_steps_per_frame = 200;

  // Output.
  std::string out = "frames";
  int width = 640, height = 480, samples = 4;
  std::string camera = "follow";  // follow | fixed
  double azimuth = 25, elevation = 15;
  bool no_floor = false;
  bool obj = false;
  bool no_csv = false;
  std::string save_state, load_state;
  std::string video;
  bool debug_gl = false;
  bool quiet = false;
};

/// Parses the command line and the scene file it names (flags override the file), validates
/// everything. Returns false when the program should exit at once with `exit_code` (after --help,
/// or a parse error already reported on stderr).
/// \throws SettingsError for a bad value or an unknown/mistyped scene-file key.
bool parse_settings(int argc, char** argv, Settings& settings, int& exit_code);

/// The checks of parse_settings() on their own. \throws SettingsError.
void validate(const Settings& s);

/// The implicit integrator's options the settings ask for (not validated: see validate()).
drape::ImplicitOptions implicit_options(const Settings& s);

/// Integrator names, Jacobian variants and solvers this build offers.
std::vector<std::string> available_integrators();
std::vector<std::string> available_solver_names();

/// The executable path of `program` on PATH, or "" if it is not installed.
std::string find_on_path(const std::string& program);

}  // namespace drape::render
