#pragma once
/// \file state_io.hpp
/// Saving and loading a `State` (positions, velocities, time) at full precision, to resume a
/// simulation bit for bit.
///
/// Format, version 1 (plain text, one record per line, `#` starts a comment line):
/// \code
///   drape-state 1
///   scalar double            (or float: the Scalar the state was saved from)
///   nodes 1089
///   time 1.2345000000000002
///   <x> <y> <z> <vx> <vy> <vz>    one line per node, node id order (id = j * nx + i)
///   ...
///   end
/// \endcode
/// Numbers are printed with `max_digits10` significant digits (17 for double, 9 for float), which
/// read back to the same binary value, so a saved state resumes bit-identically. Loading a file
/// saved from the other scalar type converts the values (exact from float to double, rounded the
/// other way). The trailing `end` line detects truncated files.

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "drape/core/state.hpp"
#include "drape/io/atomic_file.hpp"

namespace drape {

/// Thrown when a state file cannot be read or is malformed; the message names the file (and the
/// line when relevant) and what was wrong.
class StateFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int state_format_version = 1;

/// Writes `state` to `path` atomically (complete or absent).
/// \throws FileWriteError if the file cannot be written.
template <class Scalar>
void save_state(const std::string& path, const State<Scalar>& state);

/// Reads a state written by save_state().
/// \param expected_nodes if >= 0, the node count the file must have (the cloth's).
/// \throws StateFormatError naming `path` if it is missing, truncated, corrupt, of an unknown
/// version, or has the wrong number of nodes.
template <class Scalar>
State<Scalar> load_state(const std::string& path, int expected_nodes = -1);

// ---------------------------------------------------------------------------------------------

namespace detail {

template <class Scalar>
constexpr const char* scalar_name() {
  static_assert(std::is_same_v<Scalar, float> || std::is_same_v<Scalar, double>,
                "drape state files store float or double");
  return std::is_same_v<Scalar, float> ? "float" : "double";
}

/// Parses one number of the file's scalar type; false if `token` is not entirely a finite-or-not
/// floating-point literal.
inline bool parse_scalar(const std::string& token, bool file_is_float, double& out) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  // Parse in the file's own type so the decimal text rounds to exactly the saved value.
  if (file_is_float)
    out = double(std::strtof(token.c_str(), &end));
  else
    out = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size();
}

}  // namespace detail

template <class Scalar>
void save_state(const std::string& path, const State<Scalar>& state) {
  const int digits = std::numeric_limits<Scalar>::max_digits10;
  const Index n = state.positions.cols();
  if (state.velocities.cols() != n)
    throw std::invalid_argument("drape: save_state: positions and velocities have different node counts");
  write_file_atomically(path, [&](std::FILE* f) {
    if (std::fprintf(f, "drape-state %d\nscalar %s\nnodes %ld\ntime %.*g\n", state_format_version,
                     detail::scalar_name<Scalar>(), static_cast<long>(n), digits, double(state.time)) < 0)
      return false;
    for (Index i = 0; i < n; ++i) {
      const auto x = state.positions.col(i);
      const auto v = state.velocities.col(i);
      if (std::fprintf(f, "%.*g %.*g %.*g %.*g %.*g %.*g\n", digits, double(x[0]), digits, double(x[1]), digits,
                       double(x[2]), digits, double(v[0]), digits, double(v[1]), digits, double(v[2])) < 0)
        return false;
    }
    return std::fputs("end\n", f) >= 0;
  });
}

template <class Scalar>
State<Scalar> load_state(const std::string& path, int expected_nodes) {
  std::ifstream in(path);
  if (!in) throw StateFormatError("cannot open state file '" + path + "'");
  int line_no = 0;
  std::string line;
  const auto fail = [&](const std::string& what) -> void {
    throw StateFormatError("state file '" + path + "', line " + std::to_string(line_no) + ": " + what);
  };
  // Next non-comment, non-empty line; fails with `what_missing` at end of file.
  const auto next = [&](const std::string& what_missing) {
    while (std::getline(in, line)) {
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      return;
    }
    fail("file ends early (truncated): expected " + what_missing);
  };
  // "key value" header line.
  const auto header = [&](const std::string& key) {
    next("'" + key + " ...'");
    std::istringstream ls(line);
    std::string k, value, extra;
    if (!(ls >> k >> value) || k != key || (ls >> extra)) fail("expected '" + key + " <value>', found '" + line + "'");
    return value;
  };

  const std::string magic = header("drape-state");
  if (magic != std::to_string(state_format_version))
    fail("unsupported format version " + magic + " (this build reads version " + std::to_string(state_format_version) +
         ")");
  const std::string scalar = header("scalar");
  if (scalar != "float" && scalar != "double") fail("scalar must be 'float' or 'double', found '" + scalar + "'");
  const bool file_is_float = scalar == "float";
  const std::string nodes_text = header("nodes");
  char* end = nullptr;
  const long nodes = std::strtol(nodes_text.c_str(), &end, 10);
  if (end != nodes_text.c_str() + nodes_text.size() || nodes < 0 || nodes > 200'000'000L)
    fail("node count must be an integer in [0, 200000000], found '" + nodes_text + "'");
  if (expected_nodes >= 0 && nodes != expected_nodes)
    fail("has " + std::to_string(nodes) + " nodes but the cloth has " + std::to_string(expected_nodes) +
         " (saved from a different grid size?)");
  double t = 0;
  const std::string time_text = header("time");
  // Each node line takes at least 12 bytes ("0 0 0 0 0 0\n"): a count the rest of the file cannot
  // hold is a truncated or corrupt file, reported before allocating memory for it.
  // tellg() is -1 when the header line already reached the end of the file: nothing follows.
  const std::streamoff here = in.tellg();
  std::streamoff remaining = 0;
  if (here >= 0) {
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(here);
    remaining = size >= here ? size - here : 0;
  }
  if (nodes > remaining / 12)
    fail("declares " + std::to_string(nodes) + " nodes but only " + std::to_string(remaining) +
         " bytes follow, too few for them (truncated or corrupt file)");
  if (!detail::parse_scalar(time_text, file_is_float, t)) fail("time is not a number: '" + time_text + "'");

  State<Scalar> state;
  state.time = Scalar(t);
  state.positions.resize(3, nodes);
  state.velocities.resize(3, nodes);
  for (long i = 0; i < nodes; ++i) {
    next("node " + std::to_string(i) + " of " + std::to_string(nodes));
    std::istringstream ls(line);
    std::string token;
    double v[6];
    for (int c = 0; c < 6; ++c) {
      if (!(ls >> token)) {
        if (in.eof())
          fail("file ends early (truncated) inside node " + std::to_string(i) + " of " + std::to_string(nodes));
        fail("node " + std::to_string(i) + ": expected 6 numbers (x y z vx vy vz), found " + std::to_string(c));
      }
      if (!detail::parse_scalar(token, file_is_float, v[c]))
        fail("node " + std::to_string(i) + ": '" + token + "' is not a number");
    }
    if (ls >> token) fail("node " + std::to_string(i) + ": more than 6 numbers on the line");
    for (int c = 0; c < 3; ++c) {
      state.positions(c, i) = Scalar(v[c]);
      state.velocities(c, i) = Scalar(v[c + 3]);
    }
  }
  next("'end' after " + std::to_string(nodes) + " nodes");
  if (line != "end")
    fail("expected 'end' after " + std::to_string(nodes) + " nodes, found '" + line + "' (more nodes than declared?)");
  return state;
}

}  // namespace drape
