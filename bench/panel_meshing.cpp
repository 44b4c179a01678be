/// \file panel_meshing.cpp
/// The panel mesher (garment/panel_mesher.hpp) measured: the time to mesh a 60 cm x 70 cm
/// rectangle at edge lengths of 1 and 1.5 cm (median and fastest of R runs; the mesher runs on one
/// thread), and the angles and edge lengths of the test panels of tests/garment/panel_outlines.hpp
/// (the T-shirt front at 2, 1.5, 1 and 0.5 cm, the others at 1 cm), each outline given
/// counter-clockwise; the smallest angle of four of them with outlines sampled 0.3 to 1.9 edge
/// lengths apart. Prints markdown tables (docs/panel_meshing.md).
///
///   build/release/bench/drape_panel_meshing [--repetitions R]      (default R = 7)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "drape/garment/panel_mesher.hpp"
#include "garment/panel_outlines.hpp"
#include "tool_text.hpp"

namespace {

using namespace panel_outlines;

struct Timed {
  drape::PanelMesh panel;
  double median = 0, fastest = 0;  // seconds
};

Timed mesh_timed(const Eigen::Matrix2Xd& outline, double h, int repetitions) {
  Timed out;
  std::vector<double> seconds;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    out.panel = drape::mesh_panel(outline, h);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  out.median = seconds[seconds.size() / 2];
  out.fastest = seconds.front();
  return out;
}

void quality_row(const char* name, const std::vector<Piece>& pieces, double h, int repetitions) {
  const Eigen::Matrix2Xd outline = sample(pieces, h);
  const Timed run = mesh_timed(outline, h, repetitions);
  const Measures f = measure(outline, run.panel, h);
  std::printf("| %s | %.3g | %ld | %ld | %ld | %.1f | %.1f | %.1f | %.2f / %.2f / %.3f / %.2f / %.2f | %.2f | %.3f | %s |\n",
              name, h * 100, static_cast<long>(outline.cols()), static_cast<long>(run.panel.rest.cols()),
              static_cast<long>(run.panel.triangles.cols()), f.min_angle, f.min_angle_off_sharp_corners,
              f.sharpest_corner, f.shortest_edge, f.edge_5, f.median_edge, f.edge_95, f.longest_edge,
              f.nearest_interior_vertex, f.triangles_per_ideal, drape_bench::duration(run.median).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  int repetitions = 7;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repetitions" && i + 1 < argc) {
      repetitions = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: %s [--repetitions R]\n", argv[0]);
      return 2;
    }
  }
  std::ifstream load_file("/proc/loadavg");
  std::string load = "unknown";
  if (load_file) load_file >> load;
  std::printf("Median and fastest of %d runs, one thread; 1-minute load average %s at the start.\n\n", repetitions,
              load.c_str());

  std::printf("| panel | h (cm) | outline points | vertices | triangles | median | fastest |\n|---|---|---|---|---|---|---|\n");
  for (double h : {0.015, 0.01}) {
    const Eigen::Matrix2Xd outline = sample(rectangle(0.6, 0.7), h);
    const Timed run = mesh_timed(outline, h, repetitions);
    std::printf("| 60 cm x 70 cm | %.3g | %ld | %ld | %ld | %s | %s |\n", h * 100, static_cast<long>(outline.cols()),
                static_cast<long>(run.panel.rest.cols()), static_cast<long>(run.panel.triangles.cols()),
                drape_bench::duration(run.median).c_str(), drape_bench::duration(run.fastest).c_str());
  }

  std::printf("\n| panel | h (cm) | outline points | vertices | triangles | smallest angle | off corners < 60 | "
              "sharpest corner | edges min / 5 %% / median / 95 %% / max (h) | nearest interior vertex (h) | "
              "triangles / ideal | median time |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (double h : {0.02, 0.015, 0.01, 0.005}) quality_row("T-shirt front", tshirt_front(), h, repetitions);
  quality_row("square 50 cm", square(0.5), 0.01, repetitions);
  quality_row("disk, radius 30 cm", disk(0.3), 0.01, repetitions);
  quality_row("L of 60 cm", l_shape(0.6), 0.01, repetitions);
  quality_row("star, 5 tips of 30 degrees", star(5, 0.3, 0.1), 0.01, repetitions);
  quality_row("star, 7 tips", star(7, 0.3, 0.15), 0.01, repetitions);
  quality_row("waistband 1 m x 4 cm", rectangle(1.0, 0.04), 0.015, repetitions);

  // The outline sampled closer or wider than the edge length.
  const double h = 0.01;
  std::printf("\n| outline spacing (h) | square 50 cm | disk, radius 30 cm | L of 60 cm | star, 7 tips |\n"
              "|---|---|---|---|---|\n");
  for (double spacing : {0.3, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 1.9}) {
    std::printf("| %.2f |", spacing);
    for (const std::vector<Piece>& pieces : {square(0.5), disk(0.3), l_shape(0.6), star(7, 0.3, 0.15)}) {
      const Eigen::Matrix2Xd outline = sample(pieces, spacing * h);
      std::printf(" %.1f |", measure(outline, drape::mesh_panel(outline, h), h).min_angle);
    }
    std::printf("\n");
  }
  return 0;
}
