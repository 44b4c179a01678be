#pragma once
/// \file validation.hpp
/// Argument checks for user-facing constructors. Each throws `std::invalid_argument` with a
/// message that names the parameter, the value received and the allowed range.

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace drape::detail {

template <class T>
std::string to_text(const T& value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

[[noreturn]] inline void fail_argument(const std::string& name, const std::string& value,
                                       const std::string& allowed) {
  throw std::invalid_argument("drape: parameter '" + name + "' = " + value + " is invalid; allowed: " +
                              allowed);
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

}  // namespace drape::detail
