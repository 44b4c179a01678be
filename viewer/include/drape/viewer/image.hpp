#pragma once
/// \file image.hpp
/// An 8-bit RGB image in memory, rows top to bottom.

#include <cstdint>
#include <vector>

namespace drape::viewer {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes, row 0 at the top

  const std::uint8_t* pixel(int x, int y) const { return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
};

}  // namespace drape::viewer
