/// \file usd_export.cpp
/// The cost of the USD animation file (drape/io/usd.hpp) against its baseline, one OBJ file per
/// frame (drape/io/obj.hpp, drape-render's --obj), for the same frames in the same run: wall time
/// to take the frames, to write the file, its size, and the process's peak resident memory.
///
///   build/release/bench/drape_usd_export [n] [frames] [folder]    (default 256 120 /tmp)
///
/// The cloth: an n x n grid 1 cm apart, sagging a little more every frame (every point moves).
/// Each format is written 3 times, interleaved; the medians are printed. Memory of the USD writer
/// stays at one frame whatever the number of frames; the peak is printed after all runs.

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "drape/io/obj.hpp"
#include "drape/io/usd.hpp"
#include "tool_text.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Frame k of the cloth: the grid lowered by 1 mm per frame, more so far from x = 0.
void frame_points(int n, int k, drape::Matrix3X<double>& x) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) x.col(j * n + i) << 0.01 * i, -0.001 * k * (1 + 0.01 * i), 0.01 * j;
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 256;
  const int frames = argc > 2 ? std::atoi(argv[2]) : 120;
  const std::filesystem::path folder = argc > 3 ? argv[3] : "/tmp";
  if (n < 2 || frames < 1) {
    std::fprintf(stderr, "drape_usd_export: n >= 2 and frames >= 1\n");
    return 2;
  }
  std::vector<std::array<int, 3>> triangles;
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      triangles.push_back({a, a + 1, a + n + 1});
      triangles.push_back({a, a + n + 1, a + n});
    }
  drape::Matrix3X<double> x(3, n * n);
  const std::filesystem::path obj_folder = folder / "drape_usd_export_obj";
  const std::string usd_path = (folder / "drape_usd_export.usda").string();
  std::filesystem::create_directories(obj_folder);
  std::vector<double> obj_total, usd_frames, usd_finish;
  std::uintmax_t obj_bytes = 0;
  for (int run = 0; run < 3; ++run) {
    Clock::time_point start = Clock::now();
    obj_bytes = 0;
    for (int k = 0; k < frames; ++k) {
      frame_points(n, k, x);
      const std::string path = (obj_folder / ("frame_" + std::to_string(k) + ".obj")).string();
      drape::write_obj(path, x, triangles);
      obj_bytes += std::filesystem::file_size(path);
    }
    obj_total.push_back(seconds_since(start));

    start = Clock::now();
    drape::UsdAnimationWriter usd(usd_path, 30.0);
    const int cloth = usd.add_mesh("cloth", n * n, triangles);
    for (int k = 0; k < frames; ++k) {
      frame_points(n, k, x);
      usd.set_points(cloth, x);
      usd.end_frame();
    }
    usd_frames.push_back(seconds_since(start));
    start = Clock::now();
    usd.finish();
    usd_finish.push_back(seconds_since(start));
  }
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("%d x %d points, %d frames (medians of 3 runs)\n", n, n, frames);
  std::printf("OBJ per frame: %s for all frames, %.1f MB\n", drape_bench::duration(median(obj_total)).c_str(),
              double(obj_bytes) / 1e6);
  std::printf("USD file:      %s to take the frames, %s for finish(), %.1f MB\n",
              drape_bench::duration(median(usd_frames)).c_str(), drape_bench::duration(median(usd_finish)).c_str(),
              double(std::filesystem::file_size(usd_path)) / 1e6);
  std::printf("peak resident memory of the process: %.1f MB (one frame of doubles: %.1f MB)\n",
              double(usage.ru_maxrss) / 1024.0, 24.0 * n * n / 1e6);
  std::filesystem::remove_all(obj_folder);
  std::filesystem::remove(usd_path);
  return 0;
}
