/// \file mesh_step.cpp
/// The step on an irregular mesh against the grid of the same vertex count, in the same run. Disk
/// meshes (disk_mesh(): near-equilateral triangles) of about 1k, 4k, 16k and 64k vertices against
/// n x n grids (n = 32, 64, 128, 256) of the same area, the default cloth's 3.2 m square: the
/// default material (3 kg/m^2 as areal density, its structural and bend springs; the disk has no
/// shear springs, being triangles), each hanging from two pins 90 degrees apart on its edge (the
/// grid: its corners (0, 0) and (n - 1, 0)), released flat.
///
/// Per cloth: the implicit step at dt = 1/60 with its default solver (CG with the float geometric
/// multigrid on the grid, the float algebraic multigrid `amg-float` on the disk, chosen
/// automatically), the time of the first step with the integrator's set-up and of S later steps, CG
/// iterations per step; on the grid also with `amg`. The symplectic step at a dt stable for both
/// (0.2 sqrt(m / ks) of the lightest node and stiffest spring), per step over 200 steps. Median over
/// R repetitions. Prints a markdown table (docs/mesh.md).
///
/// With `--preconditioner P` (repeatable): instead, the implicit step of the disk and of the grid
/// with each P named (`amg`, `amg-float`, ...; a geometric one gives way to its algebraic
/// counterpart on the disk), the preconditioners taking turns within each repetition, so a load
/// on the machine falls on all of them alike (docs/amg.md).
///
///   build/bench/drape_mesh_step [n ...] [--steps S] [--threads T] [--repetitions R] [--preconditioner P]...
///
/// Defaults: n = 32 64 128 256, S = 30, T = 1, R = 3.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "drape/core/mesh_generators.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/model/cloth.hpp"
#include "refined_cloth.hpp"
#include "tool_text.hpp"

namespace {

struct Options {
  std::vector<int> sizes;
  std::vector<drape::PreconditionerKind> preconditioners;  // empty: the default table
  int steps = 30, threads = 1, repetitions = 3;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// A disk of the grid's area with about n x n vertices, the same material by area.
drape::ClothSpec<double> disk_spec(int n) {
  const drape::ClothSpec<double> base;
  const double side = (base.nx - 1) * base.spacing, radius = side / std::sqrt(M_PI);
  // Equilateral triangles of edge e hold 2 / (sqrt(3) e^2) vertices per square metre.
  const double edge = side / n * std::sqrt(2 / std::sqrt(3.0));
  drape::ClothSpec<double> spec = base;
  spec.mesh = drape::disk_mesh(radius, edge);
  spec.areal_density = base.node_mass / (base.spacing * base.spacing);
  spec.springs.shear = {0, 0};
  const drape::Matrix3X<double>& x = spec.mesh->positions;
  std::vector<int> pins;
  for (const double sign : {-1.0, 1.0}) {  // 45 degrees either side of -z
    const drape::Vec3<double> target(sign * radius / std::sqrt(2.0), 0, -radius / std::sqrt(2.0));
    drape::Index nearest = 0;
    (x.colwise() - target).colwise().squaredNorm().minCoeff(&nearest);
    pins.push_back(int(nearest));
  }
  spec.pinned_nodes = pins;
  return spec;
}

struct ImplicitRun {
  double first_step = 0, step = 0, iterations = 0;
  bool ok = true;
};

/// One run: the integrator made and its first step, timed together, then S steps.
void implicit_once(const drape::Cloth<double>& cloth, const Options& o, drape::PreconditionerKind preconditioner,
                   std::vector<double>& firsts, std::vector<double>& steps, ImplicitRun& out) {
  drape::ImplicitOptions options;
  options.dt = 1.0 / 60;
  options.threads = o.threads;
  options.preconditioner = preconditioner;
  drape::State<double> s = cloth.initial_state();
  auto start = std::chrono::steady_clock::now();
  drape::ImplicitEuler<double> integrator(cloth, options);
  out.ok = out.ok && integrator.step(s).ok();
  firsts.push_back(seconds_since(start));
  long long iterations = 0;
  start = std::chrono::steady_clock::now();
  for (int k = 0; k < o.steps; ++k) {
    const drape::StepStatus status = integrator.step(s);
    out.ok = out.ok && status.ok();
    iterations += status.iterations;
  }
  steps.push_back(seconds_since(start) / o.steps);
  out.iterations = double(iterations) / o.steps;
}

/// R runs of `cloth` with each of `kinds`, the kinds taking turns within each repetition; medians.
std::vector<ImplicitRun> implicit_runs(const drape::Cloth<double>& cloth, const Options& o,
                                       const std::vector<drape::PreconditionerKind>& kinds) {
  std::vector<ImplicitRun> out(kinds.size());
  std::vector<std::vector<double>> firsts(kinds.size()), steps(kinds.size());
  for (int r = 0; r < o.repetitions; ++r)
    for (std::size_t k = 0; k < kinds.size(); ++k) implicit_once(cloth, o, kinds[k], firsts[k], steps[k], out[k]);
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    out[k].first_step = median(firsts[k]);
    out[k].step = median(steps[k]);
  }
  return out;
}

ImplicitRun implicit_run(const drape::Cloth<double>& cloth, const Options& o,
                         drape::PreconditionerKind preconditioner) {
  return implicit_runs(cloth, o, {preconditioner})[0];
}

/// 0.2 sqrt(m / ks) for the lightest node and the stiffest spring.
double stable_dt(const drape::Cloth<double>& cloth) {
  const auto& ks = cloth.springs().stiffness();
  return 0.2 * std::sqrt(cloth.masses().minCoeff() / *std::max_element(ks.begin(), ks.end()));
}

double symplectic_step(const drape::Cloth<double>& cloth, const Options& o, double dt) {
  std::vector<double> t;
  for (int r = 0; r < o.repetitions; ++r) {
    drape::SymplecticEuler<double> integrator(cloth, drape::IntegratorOptions{dt, o.threads});
    drape::State<double> s = cloth.initial_state();
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < 200; ++k)
      if (!integrator.step(s).ok()) return -1;
    t.push_back(seconds_since(start) / 200);
  }
  return median(t);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--steps" && k + 1 < argc) o.steps = std::atoi(argv[++k]);
    else if (a == "--threads" && k + 1 < argc) o.threads = std::atoi(argv[++k]);
    else if (a == "--repetitions" && k + 1 < argc) o.repetitions = std::atoi(argv[++k]);
    else if (a == "--preconditioner" && k + 1 < argc) {
      drape::PreconditionerKind kind{};
      if (!drape::try_parse(argv[++k], kind)) {
        std::fprintf(stderr, "%s: --preconditioner '%s': expected %s\n", argv[0], argv[k],
                     drape::joined_names<drape::PreconditionerKind>().c_str());
        return 2;
      }
      o.preconditioners.push_back(kind);
    } else if (!a.empty() && a[0] != '-') o.sizes.push_back(std::atoi(a.c_str()));
    else {
      std::fprintf(stderr,
                   "usage: %s [n ...] [--steps S] [--threads T] [--repetitions R] [--preconditioner P]...\n",
                   argv[0]);
      return 2;
    }
  }
  if (o.sizes.empty()) o.sizes = {32, 64, 128, 256};
  std::printf("implicit dt = 1/60, %d steps after the first, %d thread(s), median of %d\n\n", o.steps, o.threads,
              o.repetitions);
  if (!o.preconditioners.empty()) {
    std::printf("| vertices disk / grid | preconditioner | CG iterations disk / grid | implicit step disk / grid | "
                "first step with set-up disk / grid |\n|---|---|---|---|---|\n");
    for (const int n : o.sizes) {
      const drape::Cloth<double> grid(drape_bench::refined_default_spec(n)), disk(disk_spec(n));
      const std::vector<ImplicitRun> d = implicit_runs(disk, o, o.preconditioners);
      const std::vector<ImplicitRun> g = implicit_runs(grid, o, o.preconditioners);
      for (std::size_t k = 0; k < o.preconditioners.size(); ++k) {
        std::printf("| %d / %d | %s | %.1f / %.1f | %s / %s%s | %s / %s |\n", disk.node_count(), grid.node_count(),
                    drape::to_string(o.preconditioners[k]), d[k].iterations, g[k].iterations,
                    drape_bench::duration(d[k].step).c_str(), drape_bench::duration(g[k].step).c_str(),
                    d[k].ok && g[k].ok ? "" : " (a step failed)", drape_bench::duration(d[k].first_step).c_str(),
                    drape_bench::duration(g[k].first_step).c_str());
      }
      std::fflush(stdout);
    }
    return 0;
  }
  std::printf("| vertices disk / grid | implicit step disk / grid (ratio) | CG iterations disk (amg-float) / grid "
              "(multigrid-float, amg) | first step with set-up disk / grid | symplectic step disk / grid (ratio) "
              "|\n|---|---|---|---|---|\n");
  for (const int n : o.sizes) {
    const drape::Cloth<double> grid(drape_bench::refined_default_spec(n)), disk(disk_spec(n));
    const ImplicitRun d = implicit_run(disk, o, drape::PreconditionerKind::MultigridFloat);
    const ImplicitRun g = implicit_run(grid, o, drape::PreconditionerKind::MultigridFloat);
    const ImplicitRun ga = implicit_run(grid, o, drape::PreconditionerKind::AlgebraicMultigrid);
    const double dt = std::min(stable_dt(disk), stable_dt(grid));
    const double sd = symplectic_step(disk, o, dt), sg = symplectic_step(grid, o, dt);
    std::printf("| %d / %d | %s / %s (%.2f)%s | %.1f / %.1f, %.1f | %s / %s | %s / %s (%.2f) |\n", disk.node_count(),
                grid.node_count(), drape_bench::duration(d.step).c_str(),
                drape_bench::duration(g.step).c_str(), d.step / g.step,
                d.ok && g.ok && ga.ok ? "" : " (a step failed)", d.iterations, g.iterations, ga.iterations,
                drape_bench::duration(d.first_step).c_str(), drape_bench::duration(g.first_step).c_str(),
                drape_bench::duration(sd).c_str(), drape_bench::duration(sg).c_str(), sd / sg);
    std::fflush(stdout);
  }
  return 0;
}
