// Soak run (not a unit test; scripts/soak.sh drives it): the default scene for many steps
// with one integrator. Checks after every step that the step succeeded (a failed step would leave
// the state unchanged and is reported), and every `check_every` steps that the state is finite and
// the total energy stays bounded by its starting value; reports peak RSS and current RSS after the
// warm-up and at the end, so memory growth shows.
//   drape_soak rk2|implicit STEPS [DT] [THREADS]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include "drape/fwd.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/diagnostics.hpp"

namespace {

/// A field of /proc/self/status in kB (VmRSS: resident now; VmHWM: peak resident), -1 if absent.
long status_kb(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field + ":", 0) == 0) return std::strtol(line.c_str() + field.size() + 1, nullptr, 10);
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: drape_soak rk2|implicit STEPS [DT] [THREADS]\n");
    return 2;
  }
  const std::string integrator = argv[1];
  drape::IntegratorKind kind{};
  if (!drape::try_parse(integrator, kind)) {
    std::fprintf(stderr, "drape_soak: integrator must be rk2 or implicit\n");
    return 2;
  }
  const long long steps = std::atoll(argv[2]);
  const drape::Clothd cloth{drape::ClothSpecd{}};
  drape::ImplicitOptions o;
  o.dt = argc > 3 ? std::atof(argv[3]) : (kind == drape::IntegratorKind::Rk2 ? drape::IntegratorOptions{}.dt : 1.0 / 60);
  o.threads = argc > 4 ? std::atoi(argv[4]) : 1;
  const double dt = o.dt;
  const int threads = o.threads;
  const std::unique_ptr<drape::Integrator<double>> stepper = drape::make_integrator(cloth, kind, o);
  drape::Stated s = cloth.initial_state();
  const auto energy = [&] {
    return drape::kinetic_energy(cloth, s) + drape::spring_potential_energy(cloth, s.positions) +
           drape::gravitational_potential_energy(cloth, s.positions);
  };
  const double e0 = energy();
  double e_min = e0, e_max = e0;
  const long long check_every = 1000, report_every = std::max<long long>(1, std::min<long long>(steps / 10, 20000));
  const long long warmup = std::min<long long>(steps, 1000);
  long rss_start = -1, hwm_start = -1;
  long long iterations = 0;
  const auto t_start = std::chrono::steady_clock::now();
  std::printf("soak: %s, %lld steps of dt = %.6g s (%.1f s simulated), %d thread(s), E0 = %.6g J\n",
              integrator.c_str(), steps, dt, double(steps) * dt, threads, e0);
  for (long long k = 1; k <= steps; ++k) {
    const drape::StepStatus status = stepper->step(s);
    if (!status) {
      std::printf("soak: FAILED at step %lld (t = %.6g s): %s\n", k, s.time, drape::to_string(status.error));
      return 1;
    }
    iterations += status.iterations;
    if (k % check_every == 0 || k == steps) {
      if (!(s.positions.allFinite() && s.velocities.allFinite())) {
        std::printf("soak: FAILED: non-finite state at step %lld\n", k);
        return 1;
      }
      const double e = energy();
      e_min = std::min(e_min, e);
      e_max = std::max(e_max, e);
    }
    if (k == warmup) {
      rss_start = status_kb("VmRSS");
      hwm_start = status_kb("VmHWM");
    }
    if (k % report_every == 0) {
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
      std::printf("soak: step %lld, t = %.1f s, E = %.6g J, RSS %ld kB (peak %ld kB), %.0f s wall\n", k, s.time,
                  energy(), status_kb("VmRSS"), status_kb("VmHWM"), wall);
      std::fflush(stdout);
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  const long rss_end = status_kb("VmRSS"), hwm_end = status_kb("VmHWM");
  // Damped springs and fixed pins: the energy can only fall from its start (0 J at the flat start);
  // allow rounding of 1e-9 of the energy range.
  const bool bounded = e_max <= e0 + 1e-9 * (std::abs(e_min) + 1.0);
  std::printf("soak: %s: %lld steps in %.0f s (%.1f us/step), all finite; energy in [%.6g, %.6g] J, start %.6g J: %s\n",
              integrator.c_str(), steps, wall, 1e6 * wall / double(steps), e_min, e_max, e0,
              bounded ? "bounded" : "GREW");
  if (integrator == "implicit") std::printf("soak: %.2f solver iterations per step\n", double(iterations) / double(steps));
  std::printf("soak: RSS after %lld steps %ld kB (peak %ld kB); at the end %ld kB (peak %ld kB): %s\n", warmup, rss_start,
              hwm_start, rss_end, hwm_end, hwm_end <= hwm_start ? "no growth" : "GREW");
  return bounded && hwm_end <= hwm_start ? 0 : 1;
}
