#include "drape/viewer/png.hpp"

#include <png.h>

#include <cstring>
#include <stdexcept>

#include "drape/io/atomic_file.hpp"

namespace drape::viewer {

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument("write_png('" + path + "'): image size and pixel buffer disagree");
  write_file_atomically(path, [&](std::FILE* file) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    // Returns 0 on any libpng or stdio error (e.g. ENOSPC); write_file_atomically then removes
    // the temporary file and reports the error.
    const int ok = png_image_write_to_stdio(&png, file, 0, image.rgb.data(), 0, nullptr);
    png_image_free(&png);
    return ok != 0;
  });
}

Image read_png(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw std::runtime_error("cannot read PNG '" + path + "': " + png.message);
  png.format = PNG_FORMAT_RGB;
  Image image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    throw std::runtime_error("cannot decode PNG '" + path + "': " + why);
  }
  return image;
}

}  // namespace drape::viewer
