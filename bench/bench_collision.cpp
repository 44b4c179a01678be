/// \file bench_collision.cpp
/// The broad phase of cloth self-collision (`broad_phase`, serial): one refit of the triangle BVH
/// to a swept step and the list of overlapping triangle pairs, on an n x n cloth (spacing 0.1 m)
/// folded and crumpled so that much of it lies on other parts of itself, with a margin of 1 cm.
/// The tree is built once on the flat rest shape, as a simulation would. The fold repeats every
/// 12 columns whatever n, so the overlaps per node stay the same and the time per node should too.
/// Counters: `pairs` (triangle pairs per call), `ns_per_node` (wall-clock time of one refit and
/// query per node).
///
/// `fold_step` (2 threads): the implicit step at dt = 1/60 of scenes/fold_on_sphere.toml's cloth
/// (2.4 m square, 1.2 kg, on a sphere over a rough floor) at n x n nodes, from the state it has
/// folded into after 1.5 s (simulated once, untimed), with self-collision on (`self:1`) and off
/// (`self:0`, the same state and step without the handler). Counters: `proximity` pairs and
/// `impacts` per step.
///
/// `mesh_query` (serial): a mesh collider's queries against its size: an icosphere of radius 0.5 m
/// subdivided `level` times (20 4^level triangles: 1280 to 81920), 4096 points in a shell 5 cm
/// either side of its surface. `kind:0` the signed distance and normal (MeshDistance::closest),
/// `kind:1` the swept test of a 2 cm path from each point (first_contact, offset 5 mm), `kind:2`
/// the textbook baseline: the nearest of all triangles, each measured. Counter: `ns_per_query`.

#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "bench_common.hpp"
#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/mesh_distance.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/core/solid_generators.hpp"
#include "drape/core/grid.hpp"
#include "drape/integrators/make_integrator.hpp"

namespace drape_bench {
namespace {

/// Start and end of a swept step of the crumpled cloth.
struct CrumpledCloth {
  drape::Matrix3X<double> rest, start, end;
};

/// x (in cells) and layer of column i of a cloth Z-folded along x: every 12 columns go 6 cells
/// forward, 3 back and 3 forward again, so half of the cloth lies three layers deep however large
/// it is; each period starts two layers above the previous one.
std::array<int, 2> z_fold(int i) {
  const int period = i / 12, r = i % 12;
  if (r <= 6) return {6 * period + r, 2 * period};
  if (r <= 9) return {6 * period + 12 - r, 2 * period + 1};
  return {6 * period + r - 6, 2 * period + 2};
}

/// The grid Z-folded along x (1.5 cm between layers), every layer corrugated alike (5 cm waves,
/// so the layers stay parallel and a sloped triangle's box reaches the next layer but one), then
/// moving down by 4 mm with a 2 mm wobble.
CrumpledCloth crumpled_cloth(const drape::Grid<double>& grid) {
  const double h = grid.spacing(), gap = 0.015, pi = 3.14159265358979323846;
  CrumpledCloth c{grid.rest_positions(), {}, {}};
  c.start = c.rest;
  c.end = c.rest;
  for (int j = 0; j < grid.ny(); ++j)
    for (int i = 0; i < grid.nx(); ++i) {
      const std::array<int, 2> fold = z_fold(i);
      const double x = fold[0] * h, z = j * h;
      const double y = fold[1] * gap + 0.05 * std::sin(2 * pi * x / 1.1) * std::sin(2 * pi * z / 0.9);
      const int v = grid.node(i, j);
      c.start.col(v) = drape::Vec3<double>(x, y, z);
      c.end.col(v) = c.start.col(v) + drape::Vec3<double>(0.002 * std::sin(1.3 * i + 0.7 * j), -0.004,
                                                          0.002 * std::cos(0.9 * i - 1.1 * j));
    }
  return c;
}

void broad_phase(benchmark::State& st) {
  const int n = int(st.range(0));
  const drape::Grid<double> grid(n, n, 0.1, 0.03);
  const drape::MeshTopology topology(grid.node_count(), grid.triangles());
  const CrumpledCloth cloth = crumpled_cloth(grid);
  drape::TriangleBvh<double> bvh(topology, cloth.rest);
  std::vector<std::array<int, 2>> pairs;
  bvh.refit(cloth.start, cloth.end, 0.01);  // untimed: grows `pairs` to its size
  bvh.overlapping_pairs(pairs);
  const auto begin = std::chrono::steady_clock::now();
  for (auto _ : st) {
    bvh.refit(cloth.start, cloth.end, 0.01);
    bvh.overlapping_pairs(pairs);
    benchmark::DoNotOptimize(pairs.data());
    benchmark::ClobberMemory();
  }
  const std::chrono::duration<double, std::nano> elapsed = std::chrono::steady_clock::now() - begin;
  st.counters["pairs"] = double(pairs.size());
  st.counters["nodes"] = double(grid.node_count());
  st.counters["ns_per_node"] = elapsed.count() / double(st.iterations()) / double(grid.node_count());
  st.SetItemsProcessed(st.iterations() * grid.node_count());
}

/// scenes/fold_on_sphere.toml's cloth at n x n nodes (the same size and total mass).
drape::ClothSpec<double> fold_spec(int n, bool self_collision) {
  drape::ClothSpec<double> spec;
  spec.nx = spec.ny = n;
  spec.spacing = 2.4 / (n - 1);
  spec.node_mass = 1.2 / (double(n) * n);
  spec.springs = {{2000, 0.1}, {500, 0.05}, {2, 0.01}};
  spec.pinned_nodes = std::vector<int>{};
  spec.contact_thickness = 0.004;
  spec.self_collision.enabled = self_collision;
  spec.colliders.push_back(
      drape::Collider<double>::sphere(drape::Vec3<double>(1.2, -0.5, 1.2), 0.3).set_friction(0.3, 0.3));
  spec.colliders.push_back(drape::Collider<double>::plane(drape::Vec3<double>(0, -0.8, 0), drape::Vec3<double>(0, 1, 0))
                               .set_friction(1.0, 1.0));
  return spec;
}

drape::ImplicitOptions fold_options() {
  drape::ImplicitOptions options;
  options.dt = 1.0 / 60;
  options.threads = 2;
  return options;
}

/// The fold after 1.5 s with self-collision on, once per n.
const drape::State<double>& folded_state(int n) {
  static std::map<int, drape::State<double>> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const drape::Cloth<double> cloth(fold_spec(n, true));
  auto integrator = drape::make_integrator(cloth, drape::IntegratorKind::Implicit, fold_options());
  drape::State<double> s = cloth.initial_state();  // flat at y = 0, 0.2 m above the sphere's top
  for (int k = 0; k < 90; ++k) integrator->step(s);
  return cache.emplace(n, s).first->second;
}

void fold_step(benchmark::State& st) {
  const int n = int(st.range(0));
  const bool self = st.range(1) != 0;
  const drape::State<double>& folded = folded_state(n);
  const drape::Cloth<double> cloth(fold_spec(n, self));
  auto integrator = drape::make_integrator(cloth, drape::IntegratorKind::Implicit, fold_options());
  drape::State<double> s = folded;
  long long steps = 0, proximity = 0, impacts = 0, failures = 0;
  for (auto _ : st) {
    st.PauseTiming();
    s.positions = folded.positions;
    s.velocities = folded.velocities;
    s.time = folded.time;
    st.ResumeTiming();
    if (!integrator->step(s).ok()) ++failures;
    benchmark::DoNotOptimize(s.positions.data());
    ++steps;
    proximity += integrator->self_collision_report().proximity_pairs;
    impacts += integrator->self_collision_report().impacts;
  }
  st.counters["proximity"] = double(proximity) / double(steps);
  st.counters["impacts"] = double(impacts) / double(steps);
  st.counters["failures"] = double(failures);
}

void mesh_query(benchmark::State& st) {
  const int level = int(st.range(0));
  const int kind = int(st.range(1));
  const drape::ClothMesh<double> sphere = drape::icosphere_mesh<double>(0.5, level);
  const drape::MeshDistance<double> mesh(sphere.triangles, sphere.positions);
  constexpr int points = 4096;
  std::vector<drape::Vec3<double>> at(points), path(points);
  for (int k = 0; k < points; ++k) {  // spread over the sphere by the golden angle
    const double y = 1 - 2 * (k + 0.5) / points, r = std::sqrt(1 - y * y), phi = 2.39996322972865332 * k;
    const drape::Vec3<double> direction(r * std::cos(phi), y, r * std::sin(phi));
    at[std::size_t(k)] = (0.5 + 0.05 * std::sin(7.0 * k)) * direction;
    path[std::size_t(k)] = 0.02 * drape::Vec3<double>(std::sin(3.0 * k), std::cos(5.0 * k), -direction.y()).normalized();
  }
  const auto brute = [&](const drape::Vec3<double>& p) {
    double best = 1e300;
    for (const auto& t : sphere.triangles)
      best = std::min(best, drape::closest_point_on_triangle<double>(p, sphere.positions.col(t[0]),
                                                                      sphere.positions.col(t[1]),
                                                                      sphere.positions.col(t[2]))
                                .distance_squared);
    return best;
  };
  double sink = 0;
  for (auto _ : st)
    for (int k = 0; k < points; ++k) {
      const std::size_t i = std::size_t(k);
      if (kind == 0) sink += mesh.closest(at[i]).distance;
      if (kind == 1) sink += mesh.first_contact(at[i], path[i], 0.005, 1e-6);
      if (kind == 2) sink += brute(at[i]);
    }
  benchmark::DoNotOptimize(sink);
  st.counters["triangles"] = double(mesh.triangle_count());
  st.counters["ns_per_query"] =
      benchmark::Counter(double(points) * 1e-9, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

const bool registered = [] {
  auto* query = benchmark::RegisterBenchmark("mesh_query", mesh_query);
  query->Unit(benchmark::kMicrosecond)->MinTime(quick_min_time)->ArgNames({"level", "kind"});
  for (int level : {3, 4, 5, 6})
    for (int kind : {0, 1}) query->Args({level, kind});
  for (int level : {3, 4}) query->Args({level, 2});
  sized(benchmark::RegisterBenchmark("broad_phase", broad_phase), serial, benchmark::kMicrosecond);
  auto* fold = benchmark::RegisterBenchmark("fold_step", fold_step);
  fold->Unit(benchmark::kMillisecond)->MinTime(quick_min_time)->ArgNames({"n", "self"});
  for (int n : {33, 65, 129})
    for (int self : {0, 1}) fold->Args({n, self});
  return true;
}();

}  // namespace
}  // namespace drape_bench
