// libFuzzer target: drape-render's command-line handling (CLI11 parsing, flag values, validation)
// through drape::scene_file::parse_settings(). The input is split into arguments at newlines. Any
// outcome but success, a CLI11 parse error turned into an exit code, or SettingsError is a bug.
// --scene is skipped (fuzz_scene covers scene files) so that no input makes the parser read
// arbitrary files such as /dev/zero.
#include <cstdint>
#include <string>
#include <vector>

#include "drape/scene_file/command_line.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"drape-render"};
  std::string current;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[i]));
    }
  }
  args.push_back(current);
  if (args.size() > 64) return 0;
  for (const std::string& a : args)
    if (a.find("--scene") != std::string::npos) return 0;
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  drape::scene_file::Settings settings;
  int exit_code = 0;
  try {
    drape::scene_file::parse_settings(static_cast<int>(args.size()), argv.data(), settings, exit_code);
  } catch (const drape::scene_file::SettingsError&) {
  }
  return 0;
}
