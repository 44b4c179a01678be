/// \file refinement.cpp
/// Refinement study: the same square cloth (the default one, 3.2 m a side, two corners
/// pinned) sampled at n x n nodes, the implicit step at dt = 1/60; CG iterations and time per step
/// against the node count, with the multigrid preconditioner (the default) and with block Jacobi.
///
///   build/bench/bench/drape_refinement [n ...] [--steps S] [--threads T] [--repetitions R]
///                                      [--preconditioner multigrid|block-jacobi] [--bend-exponent P]
///                                      [--trace]
///
/// Defaults: n = 33 65 129 257, S = 60 (1 simulated second from the flat cloth at rest), T = 2,
/// R = 3, both preconditioners (`--preconditioner`, repeatable, picks some), P = 0; `--trace` also
/// prints every step's iteration count.
///
/// Scaling (spacing h = side / (n - 1); the defaults are the material at h0 = 0.1 m): node mass
/// m = m0 (h / h0)^2, the same mass per area; structural and shear ks and kd unchanged, the same
/// membrane stiffness and viscosity (a strip of width W under strain e holds W / h springs of
/// force ks e h: a tension of ks e per metre whatever h, and kd e' per metre under a strain rate
/// e'); bend ks and kd times (h0 / h)^P. P = 0 keeps the bend springs' share of the membrane
/// stiffness; no P keeps a bending stiffness as well, for there is none to keep: a bend spring
/// across two links turned by an angle a is shortened by h a^2 / 4, an energy quartic in the
/// curvature (docs/performance.md, "Iterations against grid size"). CG's iteration cap is raised to 100000, so block Jacobi's counts
/// are not cut off. Time per step: each run of S steps timed whole (stepping only, not the set-up), the median of R
/// runs divided by S. Prints markdown tables.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/solvers/pcg.hpp"
#include "refined_cloth.hpp"
#include "tool_text.hpp"

namespace {

struct Options {
  std::vector<int> sizes;
  std::vector<drape::PreconditionerKind> preconditioners;
  int steps = 60, threads = 2, repetitions = 3;
  double bend_exponent = 0;
  bool trace = false;  // print every step's iterations
  double dt = 1.0 / 60;
};

/// Mean relative stretch (L - l) / l of the structural springs: unlike the largest one, which sits
/// at a pin (a point load, whose strain grows as the grid refines), a mean over the cloth converges.
double mean_structural_strain(const drape::Cloth<double>& cloth, const drape::Matrix3X<double>& x) {
  const drape::SpringSet<double>& sp = cloth.springs();
  double sum = 0;
  int count = 0;
  for (int k = 0; k < sp.size(); ++k) {
    if (sp.category()[k] != drape::SpringCategory::Structural) continue;
    const double l = sp.rest_length()[k];
    sum += ((x.col(sp.b()[k]) - x.col(sp.a()[k])).norm() - l) / l;
    ++count;
  }
  return sum / count;
}

/// The radius of curvature that 1% of the lattice's bends are tighter than: at each interior node,
/// the angle a between its two links along i (and along j) bends the cloth with radius h / a.
/// A smooth shape keeps this radius as the grid refines; creases as sharp as the grid make it
/// shrink with h.
double tightest_bend_radius(const drape::Cloth<double>& cloth, const drape::Matrix3X<double>& x) {
  const drape::Grid<double>& g = cloth.grid();
  std::vector<double> angles;
  const auto turn = [&](int a, int b, int c) {
    const drape::Vec3<double> u = x.col(b) - x.col(a), v = x.col(c) - x.col(b);
    angles.push_back(std::acos(std::clamp(u.dot(v) / (u.norm() * v.norm()), -1.0, 1.0)));
  };
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 1; i + 1 < g.nx(); ++i) turn(g.node(i - 1, j), g.node(i, j), g.node(i + 1, j));
  for (int j = 1; j + 1 < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) turn(g.node(i, j - 1), g.node(i, j), g.node(i, j + 1));
  const auto p99 = angles.begin() + static_cast<std::ptrdiff_t>(angles.size() * 99 / 100);
  std::nth_element(angles.begin(), p99, angles.end());
  return g.spacing() / *p99;
}

struct Run {
  bool ok = true;
  std::string failure;
  long long iterations = 0, first_half = 0;  // summed over the steps; over the first steps / 2
  int max_iterations = 0;
  double seconds_per_step = 0;             // median over repetitions
  double max_strain = 0, mean_strain = 0;  // over all springs; over the structural ones
  double bend_radius = 0;                  // tightest_bend_radius() at the end
  drape::Vec3<double> corner = drape::Vec3<double>::Zero();
  std::vector<int> levels;    // multigrid: block rows per level, finest first
  std::vector<int> per_step;  // iterations of each step (the last run's; every run's are the same)
};

Run run(const drape::Cloth<double>& cloth, drape::PreconditionerKind preconditioner, const Options& o) {
  Run out;
  std::vector<double> walls;
  const int corner = cloth.grid().node(0, cloth.grid().ny() - 1);  // free: the pins are (0, 0), (nx - 1, 0)
  for (int r = 0; r < o.repetitions; ++r) {
    drape::ImplicitOptions options;
    options.dt = o.dt;
    options.threads = o.threads;
    options.preconditioner = preconditioner;
    options.max_iterations = 100000;
    drape::ImplicitEuler<double> integrator(cloth, options);
    if (const auto* pcg = dynamic_cast<const drape::PcgSolver<double>*>(&integrator.solver()))
      if (const auto* mg = dynamic_cast<const drape::MultigridPreconditioner<double>*>(&pcg->preconditioner()))
        out.levels = mg->level_rows();
    drape::State<double> s = cloth.initial_state();
    out.iterations = out.first_half = 0;
    out.per_step.clear();
    out.max_iterations = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < o.steps; ++k) {
      const drape::StepStatus status = integrator.step(s);
      if (!status.ok()) {
        out.ok = false;
        out.failure = "step " + std::to_string(k) + " failed: " + drape::to_string(status.error);
        return out;
      }
      out.iterations += status.iterations;
      if (k < o.steps / 2) out.first_half += status.iterations;
      out.per_step.push_back(status.iterations);
      out.max_iterations = std::max(out.max_iterations, status.iterations);
    }
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    out.max_strain = drape::max_strain(cloth, s.positions);
    out.mean_strain = mean_structural_strain(cloth, s.positions);
    out.corner = s.positions.col(corner);
    out.bend_radius = tightest_bend_radius(cloth, s.positions);
  }
  std::sort(walls.begin(), walls.end());
  out.seconds_per_step = walls[walls.size() / 2] / o.steps;
  return out;
}

/// Least-squares slope of log(y) against log(x).
double exponent(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = double(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double lx = std::log(x[k]), ly = std::log(y[k]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

int usage(const char* problem) {
  std::fprintf(stderr,
               "drape_refinement: %s\n"
               "usage: drape_refinement [n ...] [--steps S] [--threads T] [--repetitions R]\n"
               "                        [--preconditioner multigrid|block-jacobi] [--bend-exponent P] [--trace]\n"
               "  n >= 3 nodes per side (default 33 65 129 257), S >= 1 (default 60 = 1 s at dt 1/60),\n"
               "  T >= 1 (default 2), R >= 1 (default 3), P in [0, 4] (default 0)\n",
               problem);
  return 2;
}

/// Parses a whole decimal integer; false for anything else ("12x", "", "-").
bool parse_int(const char* text, int& out) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < -1000000000L || value > 1000000000L) return false;
  out = int(value);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    const bool has_value = k + 1 < argc;
    if (arg == "--steps" || arg == "--threads" || arg == "--repetitions") {
      if (!has_value) return usage((arg + " needs a value").c_str());
      int& target = arg == "--steps" ? o.steps : arg == "--threads" ? o.threads : o.repetitions;
      if (!parse_int(argv[++k], target) || target < 1)
        return usage((arg + " '" + argv[k] + "': expected an integer >= 1").c_str());
    } else if (arg == "--preconditioner") {
      if (!has_value) return usage("--preconditioner needs a value");
      drape::PreconditionerKind kind;
      if (!drape::try_parse(argv[++k], kind))
        return usage(("--preconditioner '" + std::string(argv[k]) + "': expected " +
                      drape::joined_names<drape::PreconditionerKind>())
                         .c_str());
      o.preconditioners.push_back(kind);
    } else if (arg == "--bend-exponent") {
      if (!has_value) return usage("--bend-exponent needs a value");
      char* end = nullptr;
      o.bend_exponent = std::strtod(argv[++k], &end);
      if (end == argv[k] || *end != '\0' || !(o.bend_exponent >= 0 && o.bend_exponent <= 4))
        return usage(("--bend-exponent '" + std::string(argv[k]) + "': expected a number in [0, 4]").c_str());
    } else if (arg == "--trace") {
      o.trace = true;
    } else if (arg.size() > 1 && arg[0] == '-') {
      return usage(("unknown option '" + arg + "'").c_str());
    } else {
      int n = 0;
      if (!parse_int(arg.c_str(), n) || n < 3)
        return usage(("size '" + arg + "': expected an integer >= 3 (nodes per side)").c_str());
      o.sizes.push_back(n);
    }
  }
  if (o.sizes.empty()) o.sizes = {33, 65, 129, 257};
  if (o.preconditioners.empty())
    o.preconditioners = {drape::PreconditionerKind::Multigrid, drape::PreconditionerKind::BlockJacobi};

  try {
    for (const int n : o.sizes) drape_bench::refined_default_spec(n, o.bend_exponent).validate();  // before any output
    const drape::ClothSpec<double> base;
    const double side = (base.nx - 1) * base.spacing;
    std::printf(
        "Refinement study: a %g m x %g m cloth, two corners pinned, implicit step at dt = %.4g s, %d steps "
        "(%g s) from the flat cloth at rest, %d thread(s), median of %d runs; CG tolerance %g, cap 100000\n",
        side, side, o.dt, o.steps, o.steps * o.dt, o.threads, o.repetitions, drape::ImplicitOptions{}.tolerance);
    std::printf(
        "Scaling with h = %g / (n - 1): node mass %g kg * (h / %g)^2; structural and shear ks, kd fixed; "
        "bend ks, kd * (%g / h)^%g\n\n",
        side, base.node_mass, base.spacing, base.spacing, o.bend_exponent);

    std::printf(
        "| n x n | nodes | spacing | node mass | structural ks, kd | shear ks, kd | bend ks, kd | "
        "ks dt^2 / m (structural) |\n|---|---|---|---|---|---|---|---|\n");
    for (const int n : o.sizes) {
      const drape::ClothSpec<double> spec = drape_bench::refined_default_spec(n, o.bend_exponent);
      const auto& k = spec.springs;
      std::printf("| %d | %d | %.4g m | %.4g g | %g, %g | %g, %g | %.4g, %.4g | %.4g |\n", n, n * n, spec.spacing,
                  spec.node_mass * 1e3, k.structural.stiffness, k.structural.damping, k.shear.stiffness,
                  k.shear.damping, k.bend.stiffness, k.bend.damping,
                  k.structural.stiffness * o.dt * o.dt / spec.node_mass);
    }
    std::printf(
        "\n| n x n | preconditioner | CG iterations per step: mean (max) | mean, first / second half | time per step "
        "| per node | strain at the end: max (mean) | 1%% of bends tighter than | free corner (0, n-1) at the end (m) "
        "| moved from the previous n's |\n|---|---|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);

    struct Series {
      std::vector<double> nodes, iterations, seconds;
      std::vector<std::vector<int>> levels;
      std::vector<std::string> traces;
    };
    std::vector<Series> series(o.preconditioners.size());
    // The free corner of the previous size, per preconditioner (NaN before the first).
    std::vector<drape::Vec3<double>> last_corner(o.preconditioners.size(), drape::Vec3<double>::Constant(std::nan("")));
    for (const int n : o.sizes) {
      const drape::Cloth<double> cloth(drape_bench::refined_default_spec(n, o.bend_exponent));
      for (std::size_t p = 0; p < o.preconditioners.size(); ++p) {
        const drape::PreconditionerKind kind = o.preconditioners[p];
        const Run r = run(cloth, kind, o);
        if (!r.ok) {
          std::printf("| %d | %s | %s | - | - | - | - | - | - | - |\n", n, drape::to_string(kind), r.failure.c_str());
          std::fflush(stdout);
          continue;
        }
        Series& s = series[p];
        char moved[48] = "-";
        if (std::isfinite(last_corner[p].x()))
          std::snprintf(moved, sizeof moved, "%.1f mm", (r.corner - last_corner[p]).norm() * 1e3);
        last_corner[p] = r.corner;
        const double mean = double(r.iterations) / o.steps;
        char halves[48] = "-";
        const int first = o.steps / 2;
        if (first > 0)
          std::snprintf(halves, sizeof halves, "%.1f / %.1f", double(r.first_half) / first,
                        double(r.iterations - r.first_half) / (o.steps - first));
        std::printf("| %d | %s | %.1f (%d) | %s | %s | %s | %.1f%% (%.2f%%) | %.3g m | (%.4f, %.4f, %.4f) | %s |\n", n,
                    drape::to_string(kind), mean, r.max_iterations, halves,
                    drape_bench::duration(r.seconds_per_step).c_str(),
                    drape_bench::duration(r.seconds_per_step / (double(n) * n)).c_str(), 100 * r.max_strain,
                    100 * r.mean_strain, r.bend_radius, r.corner.x(), r.corner.y(), r.corner.z(), moved);
        std::fflush(stdout);
        s.nodes.push_back(double(n) * n);
        s.iterations.push_back(mean);
        s.seconds.push_back(r.seconds_per_step);
        s.levels.push_back(r.levels);
        std::string trace = std::to_string(n) + ":";
        for (const int it : r.per_step) trace += " " + std::to_string(it);
        s.traces.push_back(trace);
      }
    }

    std::printf("\n");
    for (std::size_t p = 0; p < o.preconditioners.size(); ++p) {
      const Series& s = series[p];
      if (s.nodes.size() >= 2)
        std::printf("%s: mean iterations ~ nodes^%.2f, time per step ~ nodes^%.2f (least squares over %zu sizes)\n",
                    drape::to_string(o.preconditioners[p]), exponent(s.nodes, s.iterations),
                    exponent(s.nodes, s.seconds), s.nodes.size());
      for (std::size_t k = 0; k < s.levels.size(); ++k) {
        if (s.levels[k].empty()) continue;
        std::string rows;
        for (const int l : s.levels[k]) rows += (rows.empty() ? "" : ", ") + std::to_string(l);
        std::printf("multigrid levels at %.0f nodes: %zu (block rows %s)\n", s.nodes[k], s.levels[k].size(),
                    rows.c_str());
      }
      if (o.trace)
        for (const std::string& t : s.traces)
          std::printf("%s iterations per step at n = %s\n", drape::to_string(o.preconditioners[p]), t.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drape_refinement: %s\n", e.what());
    return 2;
  }
  return 0;
}
