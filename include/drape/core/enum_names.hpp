#pragma once
/// \file enum_names.hpp
/// Text names of the option enums (Jacobian variant, linear solver, preconditioner, pin treatment,
/// integrator, ...): one table per enum, beside the enum, and one `to_string()` / `parse()` for all
/// of them. Command-line flags, scene files and the library use the same names and the same
/// error message, so the lists cannot drift apart.
///
/// \code
///   enum class Colour : std::uint8_t { Red, Green };
///   template <> struct EnumNames<Colour> {
///     static constexpr const char* parameter = "colour";   // named in parse()'s error
///     static constexpr std::array<EnumName<Colour>, 2> values{{{Colour::Red, "red"}, {Colour::Green, "green"}}};
///   };
///   drape::to_string(Colour::Red);        // "red"
///   drape::parse<Colour>("green");        // Colour::Green
///   drape::parse<Colour>("blue");         // throws InvalidParameter: 'colour' = 'blue' ...; allowed: red, green
/// \endcode

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "drape/core/validation.hpp"

namespace drape {

template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

/// Specialise with `parameter` and `values` (see the file comment); empty for enums without names.
template <class Enum>
struct EnumNames {};

/// The name of `value` ("unknown" for a value outside the table).
template <class Enum, class = decltype(EnumNames<Enum>::values)>
const char* to_string(Enum value) {
  for (const EnumName<Enum>& e : EnumNames<Enum>::values)
    if (e.value == value) return e.name;
  return "unknown";
}

/// Every name, in table order, joined by `separator`.
template <class Enum>
std::string joined_names(const char* separator = ", ") {
  std::string out;
  for (const EnumName<Enum>& e : EnumNames<Enum>::values) out += (out.empty() ? "" : separator) + std::string(e.name);
  return out;
}

/// Every name, in table order.
template <class Enum>
std::vector<std::string> names() {
  std::vector<std::string> out;
  for (const EnumName<Enum>& e : EnumNames<Enum>::values) out.emplace_back(e.name);
  return out;
}

/// The value named `text`; false (and `out` unchanged) if no value has that name.
template <class Enum>
bool try_parse(std::string_view text, Enum& out) {
  for (const EnumName<Enum>& e : EnumNames<Enum>::values)
    if (text == e.name) {
      out = e.value;
      return true;
    }
  return false;
}

/// The value named `text`.
/// \throws InvalidParameter naming `EnumNames<Enum>::parameter` and listing every name.
template <class Enum>
Enum parse(std::string_view text) {
  Enum value{};
  if (!try_parse(text, value))
    detail::fail_argument(EnumNames<Enum>::parameter, "'" + std::string(text) + "'", joined_names<Enum>());
  return value;
}

}  // namespace drape
