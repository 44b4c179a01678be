// How the spring constants and dt behave with RK2 on the default scene, for both boundary
// conditions: is the run stable for 6 s, how far do springs stretch while the cloth swings, and how
// far at rest. The numbers in docs/parameters.md come from this program.
//
//   parameter_study KS_STRUCT KS_SHEAR KS_BEND KD_STRUCT KD_SHEAR KD_BEND DT
//
// "At rest" is reached by a further 6 s in which velocities are scaled by 0.995 per step: a
// measurement device only (the library has no such damping), so the strain is that of the static
// hanging shape, not of a swing.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "drape/drape.hpp"

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr, "usage: %s KS_STRUCT KS_SHEAR KS_BEND KD_STRUCT KD_SHEAR KD_BEND DT\n", argv[0]);
    return 2;
  }
  double a[7];
  for (int k = 0; k < 7; ++k) a[k] = std::atof(argv[k + 1]);
  try {
    for (auto bc : {drape::BoundaryCondition::OneCorner, drape::BoundaryCondition::TwoCorners}) {
      drape::ClothSpecd spec;
      spec.boundary = bc;
      spec.springs = {{a[0], a[3]}, {a[1], a[4]}, {a[2], a[5]}};
      const drape::Clothd cloth(spec);
      drape::Rk2d rk2(cloth, {a[6], 1});
      drape::Stated s = cloth.initial_state();
      const long steps = std::lround(6.0 / rk2.dt());
      double swing_max = 0;
      bool stable = true;
      for (long k = 0; k < steps && stable; ++k) {
        stable = rk2.step(s).ok();
        swing_max = std::max(swing_max, drape::max_strain(cloth, s.positions));
      }
      if (!stable) {
        std::printf("bc %d: diverged at t = %.3f s\n", static_cast<int>(bc), s.time);
        continue;
      }
      for (long k = 0; k < steps && stable; ++k) {
        stable = rk2.step(s).ok();
        s.velocities *= 0.995;
      }
      const auto& sp = cloth.springs();
      std::vector<double> strain;
      for (int q = 0; q < sp.size(); ++q)
        strain.push_back(((s.positions.col(sp.b()[q]) - s.positions.col(sp.a()[q])).norm() - sp.rest_length()[q]) /
                         sp.rest_length()[q]);
      std::sort(strain.begin(), strain.end());
      std::printf(
          "bc %d: stable; strain while swinging max %.1f %%; at rest max %.1f %%, 99th percentile %.2f %%, "
          "median %.2f %%; pin reaction %.1f N; lowest y %.2f m\n",
          static_cast<int>(bc), 100 * swing_max, 100 * strain.back(), 100 * strain[strain.size() * 99 / 100],
          100 * strain[strain.size() / 2], drape::pin_reaction(cloth, s).norm(), s.positions.row(1).minCoeff());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
