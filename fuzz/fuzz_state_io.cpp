// libFuzzer target: drape::load_state() on arbitrary bytes. It must either return a state with
// the declared node count or throw StateFormatError; any other exception, crash, leak or
// undefined behaviour is a bug. A state that loads must save and load back bit-identically.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "drape/io/state_io.hpp"

namespace {

std::string temp_path(const char* what) {
  return "/tmp/drape_fuzz_state_" + std::to_string(::getpid()) + "_" + what;
}

template <class Scalar>
void check(const std::string& path) {
  drape::State<Scalar> s;
  try {
    s = drape::load_state<Scalar>(path);
  } catch (const drape::StateFormatError&) {
    return;  // the expected outcome for nearly every input
  }
  if (s.positions.cols() != s.velocities.cols()) __builtin_trap();
  // Round trip: what loads saves and loads back to the same bits (compared when finite: NaN
  // payloads are not preserved by the text format, and need not be).
  const std::string again = temp_path("again");
  drape::save_state(again, s);
  const drape::State<Scalar> t = drape::load_state<Scalar>(again, static_cast<int>(s.positions.cols()));
  std::remove(again.c_str());
  if (s.positions.size() > 0 && s.positions.allFinite() && s.velocities.allFinite() &&
      (std::memcmp(s.positions.data(), t.positions.data(), sizeof(Scalar) * std::size_t(s.positions.size())) != 0 ||
       std::memcmp(s.velocities.data(), t.velocities.data(), sizeof(Scalar) * std::size_t(s.velocities.size())) != 0))
    __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = temp_path("in");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  check<double>(path);
  check<float>(path);
  std::remove(path.c_str());
  return 0;
}
