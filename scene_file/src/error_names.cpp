#include "error_names.hpp"

#include <sstream>

namespace drape::scene_file::detail {

std::string number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

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

namespace {

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

}  // namespace

[[noreturn]] void fail_named(const InvalidParameter& e, const FileKeys& from_file) {
  const auto key = key_of_parameter().find(e.parameter());
  if (key != key_of_parameter().end() && from_file.keys.count(key->second))
    fail("scene file '" + from_file.file + "': " + key->second, e.value(), e.allowed());
  const auto it = flag_of_parameter().find(e.parameter());
  if (it == flag_of_parameter().end()) throw SettingsError(e.what());
  fail(it->second, e.value(), e.allowed());
}

}  // namespace drape::scene_file::detail
