#pragma once
/// \file validation.hpp
/// Argument checks for user-facing constructors and options. Each failure throws
/// `InvalidParameter` (a `std::invalid_argument`) whose message names the parameter, the value
/// received and the allowed range; the three are also available separately, so a front end (a
/// command line, a scene file) can report the error under its own name for the parameter.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace drape {

/// A parameter outside its allowed range. what(): "drape: parameter 'NAME' = VALUE is invalid;
/// allowed: ALLOWED".
class InvalidParameter : public std::invalid_argument {
 public:
  InvalidParameter(std::string parameter, std::string value, std::string allowed)
      : std::invalid_argument("drape: parameter '" + parameter + "' = " + value + " is invalid; allowed: " + allowed),
        m_parameter(std::move(parameter)),
        m_value(std::move(value)),
        m_allowed(std::move(allowed)) {}

  /// The parameter's name in the library's vocabulary (e.g. `shear.stiffness`, `dt`).
  const std::string& parameter() const { return m_parameter; }
  /// The rejected value as text.
  const std::string& value() const { return m_value; }
  /// The allowed values as text (e.g. `finite and > 0`, `[2, 10000]`, `cg | bicgstab`).
  const std::string& allowed() const { return m_allowed; }

 private:
  std::string m_parameter, m_value, m_allowed;
};

namespace detail {

template <class T>
std::string to_text(const T& value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

[[noreturn]] inline void fail_argument(const std::string& name, const std::string& value, const std::string& allowed) {
  throw InvalidParameter(name, value, allowed);
}

template <class S>
void require_positive_finite(const char* name, S value) {
  if (!(std::isfinite(value) && value > S(0))) fail_argument(name, to_text(value), "finite and > 0");
}

template <class S>
void require_nonnegative_finite(const char* name, S value) {
  if (!(std::isfinite(value) && value >= S(0))) fail_argument(name, to_text(value), "finite and >= 0");
}

template <class S>
void require_finite(const char* name, S value) {
  if (!std::isfinite(value)) fail_argument(name, to_text(value), "finite");
}

inline void require_at_least(const char* name, long long value, long long minimum) {
  if (value < minimum) fail_argument(name, to_text(value), ">= " + to_text(minimum));
}

inline void require_in_range(const char* name, long long value, long long lo, long long hi) {
  if (value < lo || value > hi) fail_argument(name, to_text(value), "[" + to_text(lo) + ", " + to_text(hi) + "]");
}

/// The time step: every integrator and the real-time driver check it here.
template <class S>
void require_time_step(S dt) {
  require_positive_finite("dt", dt);
}

}  // namespace detail
}  // namespace drape
