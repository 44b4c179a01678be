/// \file memory.cpp
/// Heap bytes per node of the cloth and of each integrator, measured: glibc's count of bytes in
/// use (mallinfo2: small blocks plus mmap'd large ones) before and after building each object and
/// taking a few steps (buffers an integrator sizes on its first step count too). The state
/// (positions and velocities, 48 bytes per node) is counted apart.
///
///   build/bench/bench/drape_memory [n ...]        (default 257)
///
/// Scene: the default cloth, two corners pinned, n x n nodes; the implicit step with its default
/// options (dt = 1/60, multigrid-preconditioned CG); 2 threads (their team's buffers included).

#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "drape/integrators/make_integrator.hpp"

namespace {

long long heap_in_use() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<long long>(info.uordblks + info.hblkhd);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes;
  for (int k = 1; k < argc; ++k) sizes.push_back(std::atoi(argv[k]));
  if (sizes.empty()) sizes.push_back(257);
  std::printf("| n x n | object | heap bytes | bytes per node |\n|---|---|---|---|\n");
  for (const int n : sizes) {
    if (n < 2) {
      std::fprintf(stderr, "drape_memory: sizes >= 2\n");
      return 2;
    }
    const double nodes = double(n) * n;
    auto row = [&](const char* what, long long bytes) {
      std::printf("| %d | %s | %lld | %.0f |\n", n, what, bytes, double(bytes) / nodes);
    };
    const long long before_cloth = heap_in_use();
    drape::ClothSpec<double> spec;
    spec.nx = spec.ny = n;
    auto cloth = std::make_unique<drape::Cloth<double>>(spec);
    row("cloth (grid, springs, pins)", heap_in_use() - before_cloth);
    const long long before_state = heap_in_use();
    drape::State<double> state = cloth->initial_state();
    row("state (positions, velocities)", heap_in_use() - before_state);
    for (const drape::IntegratorKind kind :
         {drape::IntegratorKind::Rk2, drape::IntegratorKind::Symplectic, drape::IntegratorKind::Implicit}) {
      drape::State<double> s = state;
      const long long before = heap_in_use();
      {
        drape::ImplicitOptions options;  // the explicit steps at the default 0.5 ms, the implicit at 1/60
        if (kind == drape::IntegratorKind::Implicit) options.dt = 1.0 / 60;
        options.threads = 2;
        auto stepper = drape::make_integrator(*cloth, kind, options);
        const long long built = heap_in_use() - before;
        for (int k = 0; k < 3; ++k)
          if (!stepper->step(s).ok()) {
            std::fprintf(stderr, "drape_memory: a %s step failed\n", drape::to_string(kind));
            return 1;
          }
        const std::string what = drape::to_string(kind);
        row((what + ", built").c_str(), built);
        row((what + ", after 3 steps").c_str(), heap_in_use() - before);
      }
    }
  }
}
