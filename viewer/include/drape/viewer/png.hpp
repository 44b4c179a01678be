#pragma once
/// \file png.hpp
/// PNG files through libpng's simplified API. Writing goes through drape::write_file_atomically,
/// so a frame file is either complete or absent.

#include <string>

#include "drape/viewer/image.hpp"

namespace drape::viewer {

/// Writes `image` as an 8-bit RGB PNG.
/// \throws drape::FileWriteError naming `path` if it cannot be written (missing or read-only
/// folder, full disk); no file named `path` is left behind in that case.
void write_png(const std::string& path, const Image& image);

/// Reads any PNG as 8-bit RGB.
/// \throws std::runtime_error naming `path` if it is missing or not a valid PNG.
Image read_png(const std::string& path);

}  // namespace drape::viewer
