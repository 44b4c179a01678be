/// \file cg_iterations.cpp
/// How many iterations the default implicit solver needs along a trajectory: the benchmark scene
/// (N x N, both corners pinned) simulated from the flat start with the default ImplicitOptions on
/// one thread, printing the mean iterations per step over windows [0, 0.25], (0.25, 0.5], ... s.
/// Shows whether the timed state's iteration count is typical (docs/benchmarks.md).
///
///   build/bench/bench/drape_cg_iterations [N=33] [dt=1/60] [t_end=8] [multigrid|block-jacobi]

#include <cstdio>
#include <cstdlib>
#include <string>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 33;
  const double dt = argc > 2 ? std::atof(argv[2]) : 1.0 / 60.0;
  const double t_end = argc > 3 ? std::atof(argv[3]) : 8.0;
  drape::ImplicitOptions options;
  if (argc > 4 && !drape::try_parse(argv[4], options.preconditioner)) {
    std::fprintf(stderr, "preconditioner: '%s', expected %s\n", argv[4],
                 drape::joined_names<drape::PreconditionerKind>().c_str());
    return 2;
  }
  drape::ClothSpec<double> spec;
  spec.nx = spec.ny = n;
  const drape::Cloth<double> cloth(spec);
  drape::State<double> state = cloth.initial_state();
  options.dt = dt;
  options.threads = 1;
  drape::ImplicitEuler<double> integrator(cloth, options);
  std::printf("%d x %d, dt = %g, solver %s (%s, %s), tolerance %g\n", n, n, dt, drape::to_string(options.solver),
              drape::to_string(options.jacobian), drape::to_string(options.preconditioner), options.tolerance);
  long long iterations = 0, steps = 0;
  double window_end = 0.25, window_start = 0;
  while (state.time < t_end - 1e-12) {
    const drape::StepStatus status = integrator.step(state);
    if (!status.ok()) {
      std::printf("step failed at t = %g: %s\n", state.time, drape::to_string(status.error));
      return 1;
    }
    iterations += status.iterations;
    ++steps;
    if (state.time >= window_end - 1e-12 || state.time >= t_end - 1e-12) {
      std::printf("t in (%.2f, %.2f] s: %.1f iterations per step (%lld steps)\n", window_start, state.time,
                  double(iterations) / double(steps), steps);
      iterations = steps = 0;
      window_start = state.time;
      window_end *= 2;
    }
  }
  return 0;
}
