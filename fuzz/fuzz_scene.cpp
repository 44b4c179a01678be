// libFuzzer target: drape-render's scene-file handling (toml++ parse, key lookup, typed values,
// validation) through drape::scene_file::read_settings(file). It must either accept the
// file or throw SettingsError; any other exception escapes and is reported as a crash (in
// drape-render it would end in std::terminate), as are crashes, leaks and undefined behaviour.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "drape/scene_file/command_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = "/tmp/drape_fuzz_scene_" + std::to_string(::getpid()) + ".toml";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    (void)drape::scene_file::read_settings(path);
  } catch (const drape::scene_file::SettingsError&) {
  }
  std::remove(path.c_str());
  return 0;
}
