#pragma once
/// \file tool_text.hpp
/// Text shared by the command-line bench tools (sim_second.cpp, refinement.cpp): durations in the
/// unit that fits.

#include <cstdio>
#include <string>

namespace drape_bench {

/// "2.36 s", "12.6 ms" or "876 us" (three significant digits below a second).
inline std::string duration(double seconds) {
  char text[32];
  if (seconds >= 1)
    std::snprintf(text, sizeof text, "%.2f s", seconds);
  else if (seconds >= 1e-3)
    std::snprintf(text, sizeof text, "%.3g ms", seconds * 1e3);
  else
    std::snprintf(text, sizeof text, "%.3g us", seconds * 1e6);
  return text;
}

}  // namespace drape_bench
