// The broad phase of cloth self-collision: the mesh topology (edges, feature ownership) and the
// triangle BVH, each checked against brute force on flat, folded, crumpled and random meshes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <initializer_list>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/core/grid.hpp"

using drape::Matrix3X;
using drape::MeshTopology;
using drape::TriangleBvh;
using Pair = std::array<int, 2>;
using Triangles = std::vector<std::array<int, 3>>;

namespace {

/// A box written out independently of the BVH's: corners' min and max over both times, +- margin.
template <class S>
struct TestBox {
  std::array<S, 3> lo, hi;
};

template <class S>
TestBox<S> swept_box(const Matrix3X<S>& xs, const Matrix3X<S>& xe, std::initializer_list<int> nodes, S margin) {
  TestBox<S> b;
  for (int k = 0; k < 3; ++k) {
    S lo = xs(k, *nodes.begin()), hi = lo;
    for (int v : nodes) {
      lo = std::min({lo, xs(k, v), xe(k, v)});
      hi = std::max({hi, xs(k, v), xe(k, v)});
    }
    b.lo[static_cast<std::size_t>(k)] = lo - margin;
    b.hi[static_cast<std::size_t>(k)] = hi + margin;
  }
  return b;
}

template <class S>
bool boxes_overlap(const TestBox<S>& a, const TestBox<S>& b) {
  for (std::size_t k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;  // touching counts
}

template <class S>
std::vector<TestBox<S>> triangle_boxes(const Triangles& tris, const Matrix3X<S>& xs, const Matrix3X<S>& xe, S margin) {
  std::vector<TestBox<S>> boxes;
  for (const auto& t : tris) boxes.push_back(swept_box(xs, xe, {t[0], t[1], t[2]}, margin));
  return boxes;
}

/// Every pair of distinct triangles whose boxes overlap, sorted.
template <class S>
std::vector<Pair> brute_force_pairs(const Triangles& tris, const Matrix3X<S>& xs, const Matrix3X<S>& xe, S margin) {
  const auto boxes = triangle_boxes(tris, xs, xe, margin);
  std::vector<Pair> out;
  for (int a = 0; a < int(tris.size()); ++a)
    for (int b = a + 1; b < int(tris.size()); ++b)
      if (boxes_overlap(boxes[std::size_t(a)], boxes[std::size_t(b)])) out.push_back({a, b});
  return out;
}

/// The BVH's pairs after checking their form (a < b, no duplicates), sorted for comparison.
std::vector<Pair> checked_sorted(std::vector<Pair> pairs) {
  for (const Pair& p : pairs) REQUIRE(p[0] < p[1]);
  std::sort(pairs.begin(), pairs.end());
  REQUIRE(std::adjacent_find(pairs.begin(), pairs.end()) == pairs.end());
  return pairs;
}

/// Grid rest positions with every coordinate moved by up to `amplitude` (fixed seed).
template <class S>
Matrix3X<S> crumpled(const drape::Grid<S>& grid, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3X<S> x = grid.rest_positions();
  for (drape::Index i = 0; i < x.size(); ++i) x.data()[i] += S(amplitude * u(rng));
  return x;
}

/// The grid folded over itself across z = fold: the far part mirrored onto the near one, lifted by
/// `gap`, so the two layers overlap in x and z.
template <class S>
Matrix3X<S> folded(const drape::Grid<S>& grid, S fold, S gap) {
  Matrix3X<S> x = grid.rest_positions();
  for (drape::Index v = 0; v < x.cols(); ++v)
    if (x(2, v) > fold) {
      x(2, v) = 2 * fold - x(2, v);
      x(1, v) = gap;
    }
  return x;
}

/// `x` plus a random motion of up to `amplitude` per coordinate: the end of a swept step.
template <class S>
Matrix3X<S> moved(const Matrix3X<S>& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix3X<S> y = x;
  for (drape::Index i = 0; i < y.size(); ++i) y.data()[i] += S(amplitude * u(rng));
  return y;
}

template <class S>
std::vector<Pair> bvh_pairs(const TriangleBvh<S>& bvh) {
  std::vector<Pair> out;
  bvh.overlapping_pairs(out);
  return out;
}

int shared_node_pairs(const MeshTopology& topo, const std::vector<Pair>& pairs) {
  return int(
      std::count_if(pairs.begin(), pairs.end(), [&](const Pair& p) { return topo.triangles_share_node(p[0], p[1]); }));
}

/// Two grids' meshes in one numbering, triangles in a random order: a mesh nothing grid-like holds.
Triangles two_cloths_shuffled(int n0, int n1, unsigned seed) {
  Triangles tris = drape::Grid<double>(n0, n0, 0.1, 0.03).triangles();
  for (auto t : drape::Grid<double>(n1, n1, 0.1, 0.03).triangles())
    tris.push_back({t[0] + n0 * n0, t[1] + n0 * n0, t[2] + n0 * n0});
  std::mt19937 rng(seed);
  std::shuffle(tris.begin(), tris.end(), rng);
  return tris;
}

}  // namespace

// ------------------------------------------------------------------------------------- topology

TEST_CASE("a grid's topology has the expected edges, each triangle's sides among them", "[collision][topology]") {
  for (const auto& size : {std::array<int, 2>{2, 2}, {5, 4}, {3, 7}, {33, 33}}) {
    const int nx = size[0], ny = size[1];
    const drape::Grid<double> grid(nx, ny, 0.1, 0.03);
    const MeshTopology topo(grid.node_count(), grid.triangles());
    INFO(nx << " x " << ny);
    REQUIRE(topo.node_count() == nx * ny);
    REQUIRE(topo.triangle_count() == 2 * (nx - 1) * (ny - 1));
    REQUIRE(topo.edge_count() == (nx - 1) * ny + nx * (ny - 1) + (nx - 1) * (ny - 1));
    for (int e = 0; e < topo.edge_count(); ++e) {
      REQUIRE(topo.edge(e)[0] < topo.edge(e)[1]);
      if (e > 0) REQUIRE(topo.edge(e - 1) < topo.edge(e));  // sorted, hence unique and deterministic
    }
    for (int t = 0; t < topo.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int p = topo.triangle(t)[std::size_t(k)], q = topo.triangle(t)[std::size_t((k + 1) % 3)];
        const auto& e = topo.edge(topo.triangle_edges(t)[std::size_t(k)]);
        REQUIRE(e == std::array<int, 2>{std::min(p, q), std::max(p, q)});
      }
  }
}

TEST_CASE("edge ids depend on the set of edges, not on the triangles' order", "[collision][topology]") {
  const drape::Grid<double> grid(6, 5, 0.1, 0.03);
  Triangles shuffled = grid.triangles();
  std::mt19937 rng(7);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  for (auto& t : shuffled) std::rotate(t.begin(), t.begin() + 1, t.end());
  REQUIRE(MeshTopology(grid.node_count(), shuffled).edges() ==
          MeshTopology(grid.node_count(), grid.triangles()).edges());
}

TEST_CASE("every used node and every edge is owned once, by the lowest triangle containing it",
          "[collision][topology]") {
  // A grid, two shuffled grids in one mesh, and a random soup with unused nodes.
  std::vector<std::pair<int, Triangles>> meshes;
  meshes.emplace_back(35, drape::Grid<double>(7, 5, 0.1, 0.03).triangles());
  meshes.emplace_back(36 + 16, two_cloths_shuffled(6, 4, 3));
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> node(0, 39);
  Triangles soup;
  while (soup.size() < 50) {
    const std::array<int, 3> t{node(rng), node(rng), node(rng)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) soup.push_back(t);
  }
  meshes.emplace_back(45, soup);  // nodes 40..44 unused

  for (const auto& [node_count, tris] : meshes) {
    const MeshTopology topo(node_count, tris);
    std::vector<int> node_owner(std::size_t(node_count), -1), edge_owner(std::size_t(topo.edge_count()), -1);
    for (int t = topo.triangle_count() - 1; t >= 0; --t) {  // ends at the lowest
      for (int v : topo.triangle(t)) node_owner[std::size_t(v)] = t;
      for (int e : topo.triangle_edges(t)) edge_owner[std::size_t(e)] = t;
    }
    std::vector<int> node_seen(std::size_t(node_count), 0), edge_seen(std::size_t(topo.edge_count()), 0);
    for (int t = 0; t < topo.triangle_count(); ++t) {
      for (int v : topo.owned_nodes(t)) {
        REQUIRE(node_owner[std::size_t(v)] == t);
        ++node_seen[std::size_t(v)];
      }
      for (int e : topo.owned_edges(t)) {
        REQUIRE(edge_owner[std::size_t(e)] == t);
        ++edge_seen[std::size_t(e)];
      }
    }
    for (int v = 0; v < node_count; ++v)
      REQUIRE(node_seen[std::size_t(v)] == (node_owner[std::size_t(v)] >= 0 ? 1 : 0));
    for (int e = 0; e < topo.edge_count(); ++e) REQUIRE(edge_seen[std::size_t(e)] == 1);
  }
  const MeshTopology grid_topo(35, meshes[0].second);
  REQUIRE(grid_topo.owned_nodes(0).size() == 3);  // the first triangle owns all it touches
  REQUIRE(grid_topo.owned_edges(0).size() == 3);
}

TEST_CASE("adjacency helpers agree with the corners and ends", "[collision][topology]") {
  const MeshTopology topo(5, {{0, 1, 2}, {1, 3, 2}, {3, 4, 2}});
  // Edges (sorted): (0,1) (0,2) (1,2) (1,3) (2,3) (2,4) (3,4).
  REQUIRE(topo.edge_count() == 7);
  REQUIRE(topo.edge(3) == std::array<int, 2>{1, 3});
  REQUIRE(topo.triangles_share_node(0, 2));  // node 2
  REQUIRE_FALSE(MeshTopology(6, {{0, 1, 2}, {3, 4, 5}}).triangles_share_node(0, 1));
  // Every combination on a small grid, against the corner and end lists.
  const drape::Grid<double> grid(4, 3, 0.1, 0.03);
  const MeshTopology g(grid.node_count(), grid.triangles());
  const auto has = [](const auto& list, int v) { return std::find(list.begin(), list.end(), v) != list.end(); };
  for (int t = 0; t < g.triangle_count(); ++t) {
    for (int v = 0; v < g.node_count(); ++v) REQUIRE(g.triangle_has_node(t, v) == has(g.triangle(t), v));
    for (int u = 0; u < g.triangle_count(); ++u) {
      const auto& c = g.triangle(u);
      REQUIRE(g.triangles_share_node(t, u) ==
              (has(g.triangle(t), c[0]) || has(g.triangle(t), c[1]) || has(g.triangle(t), c[2])));
    }
  }
  for (int e = 0; e < g.edge_count(); ++e)
    for (int f = 0; f < g.edge_count(); ++f)
      REQUIRE(g.edges_share_node(e, f) == (has(g.edge(e), g.edge(f)[0]) || has(g.edge(e), g.edge(f)[1])));
}

TEST_CASE("a topology rejects bad node ids and degenerate triangles by name", "[collision][topology][validation]") {
  using Catch::Matchers::Contains;
  REQUIRE_THROWS_WITH(MeshTopology(3, {{0, 1, 3}}),
                      Contains("'triangles'") && Contains("triangle 0") && Contains("[0, 3)"));
  REQUIRE_THROWS_WITH(MeshTopology(4, {{0, 1, 2}, {-1, 1, 2}}), Contains("'triangles'") && Contains("triangle 1"));
  REQUIRE_THROWS_WITH(MeshTopology(4, {{0, 1, 2}, {2, 3, 2}}), Contains("'triangles'") && Contains("distinct"));
  REQUIRE_THROWS_WITH(MeshTopology(-1, {}), Contains("'node_count'"));
  REQUIRE_THROWS_AS(MeshTopology(4, {{0, 4, 2}}), drape::InvalidParameter);
  const MeshTopology empty(0, {});
  REQUIRE(empty.triangle_count() == 0);
  REQUIRE(empty.edge_count() == 0);
}

// ------------------------------------------------------------------------------------------ BVH

TEMPLATE_TEST_CASE("the BVH's pairs are exactly the overlapping boxes, on flat, folded and crumpled cloth",
                   "[collision][bvh]", float, double) {
  using S = TestType;
  const drape::Grid<S> grid(20, 18, S(0.1), S(0.03));
  const Triangles tris = grid.triangles();
  const MeshTopology topo(grid.node_count(), tris);
  const Matrix3X<S> rest = grid.rest_positions();

  struct Case {
    const char* name;
    Matrix3X<S> start, end;
    S margin;
    bool deformed;  // expect many more pairs than the flat cloth
  };
  const Matrix3X<S> fold = folded(grid, S(0.85), S(0.03));
  const Matrix3X<S> crumple = crumpled(grid, 0.12, 5);
  const std::vector<Case> cases = {
      {"flat, no margin (boxes touch)", rest, rest, S(0), false},
      {"flat, margin", rest, rest, S(0.02), false},
      {"folded, margin", fold, fold, S(0.02), true},
      {"folded, swept", fold, moved(fold, 0.03, 9), S(0.005), true},
      {"crumpled, margin", crumple, crumple, S(0.01), true},
      {"crumpled, swept", crumple, moved(crumple, 0.05, 13), S(0.01), true},
  };
  const std::size_t flat_pairs = brute_force_pairs(tris, rest, rest, S(0.02)).size();
  for (const Case& c : cases) {
    const std::vector<Pair> expected = brute_force_pairs(tris, c.start, c.end, c.margin);
    for (int leaf : {1, 2, 3, 4, 8, 16}) {
      INFO(c.name << ", leaf size " << leaf);
      TriangleBvh<S> bvh(topo, rest, leaf);  // built on the rest shape, refitted to the case
      bvh.refit(c.start, c.end, c.margin);
      REQUIRE(checked_sorted(bvh_pairs(bvh)) == expected);
      // Built on the deformed shape: the same set.
      bvh.rebuild(c.end);
      bvh.refit(c.start, c.end, c.margin);
      REQUIRE(checked_sorted(bvh_pairs(bvh)) == expected);
    }
    // Not vacuous: neighbours share nodes; the fold and the crumple bring distant triangles together.
    INFO(c.name);
    REQUIRE(shared_node_pairs(topo, expected) > 0);
    if (c.deformed) REQUIRE(expected.size() > flat_pairs + 200);
  }
}

TEMPLATE_TEST_CASE("a folded cloth's layers overlap only within reach of the margin", "[collision][bvh]", float,
                   double) {
  using S = TestType;
  const drape::Grid<S> grid(10, 10, S(0.1), S(0.03));
  const MeshTopology topo(grid.node_count(), grid.triangles());
  const Matrix3X<S> x = folded(grid, S(0.45), S(0.05));  // layers 5 cm apart, 9 cm folded over
  TriangleBvh<S> bvh(topo, grid.rest_positions());
  bvh.refit(x, S(0.02));  // boxes 4 cm apart: only the neighbours across the fold line
  const int near = int(bvh_pairs(bvh).size());
  bvh.refit(x, S(0.03));  // boxes overlap across the layers
  const std::vector<Pair> across = bvh_pairs(bvh);
  REQUIRE(int(across.size()) > near + 100);
  REQUIRE(checked_sorted(across) == brute_force_pairs(grid.triangles(), x, x, S(0.03)));
}

TEMPLATE_TEST_CASE("the BVH's output is deterministic and reuses the caller's vector", "[collision][bvh]", float,
                   double) {
  using S = TestType;
  const drape::Grid<S> grid(16, 16, S(0.1), S(0.03));
  const MeshTopology topo(grid.node_count(), grid.triangles());
  const Matrix3X<S> x0 = crumpled(grid, 0.1, 21), x1 = moved(x0, 0.04, 22);
  TriangleBvh<S> a(topo, grid.rest_positions()), b(topo, grid.rest_positions());
  a.refit(x0, x1, S(0.01));
  b.refit(x0, x1, S(0.01));
  std::vector<Pair> out;
  a.overlapping_pairs(out);
  const std::vector<Pair> first = out;
  REQUIRE(!first.empty());
  const auto* data = out.data();
  const std::size_t capacity = out.capacity();
  a.overlapping_pairs(out);  // same tree, same boxes: the same list, in the same vector
  REQUIRE(out == first);
  REQUIRE(out.data() == data);
  REQUIRE(out.capacity() == capacity);
  REQUIRE(bvh_pairs(b) == first);    // a second tree from the same positions
  a.rebuild(grid.rest_positions());  // rebuilt from the same positions
  a.refit(x0, x1, S(0.01));
  REQUIRE(bvh_pairs(a) == first);
  a.rebuild(x1);
  a.refit(x0, x1, S(0.01));
  a.rebuild(grid.rest_positions());  // and back
  a.refit(x0, x1, S(0.01));
  REQUIRE(bvh_pairs(a) == first);
}

TEMPLATE_TEST_CASE("the BVH handles tiny, empty and degenerate meshes", "[collision][bvh]", float, double) {
  using S = TestType;
  const MeshTopology none(3, {});
  TriangleBvh<S> empty(none, Matrix3X<S>::Zero(3, 3));
  empty.refit(Matrix3X<S>::Zero(3, 3), S(1));
  std::vector<Pair> out{{0, 1}};
  empty.overlapping_pairs(out);
  REQUIRE(out.empty());
  REQUIRE(empty.volume_count() == 0);

  const MeshTopology one(3, {{0, 1, 2}});
  TriangleBvh<S> single(one, Matrix3X<S>::Random(3, 3));
  single.overlapping_pairs(out);
  REQUIRE(out.empty());

  // Every node at one point: all centroids tie, the split falls back on triangle ids.
  const drape::Grid<S> grid(6, 6, S(0.1), S(0.03));
  const MeshTopology topo(grid.node_count(), grid.triangles());
  const Matrix3X<S> point = Matrix3X<S>::Ones(3, grid.node_count());
  TriangleBvh<S> bvh(topo, point, 2);
  bvh.refit(point, S(0));
  const int t = topo.triangle_count();
  REQUIRE(int(checked_sorted(bvh_pairs(bvh)).size()) == t * (t - 1) / 2);
}

TEMPLATE_TEST_CASE("the tree depends on the split order alone: ties go by triangle index, leaves list ids in order",
                   "[collision][bvh]", float, double) {
  using S = TestType;
  // 32 separate triangles, split on: a row along x in index order; one point (every centroid
  // tied); a row in which each leaf's triangles come in reverse order. All three trees have the
  // same leaves, so refitted to the same boxes their traversals list the same pairs in the same order.
  const int t = 32;
  Triangles tris;
  for (int k = 0; k < t; ++k) tris.push_back({3 * k, 3 * k + 1, 3 * k + 2});
  const MeshTopology topo(3 * t, tris);
  const Matrix3X<S> point = Matrix3X<S>::Zero(3, 3 * t);
  for (int leaf : {1, 2, 4}) {
    Matrix3X<S> row = point, reversed = point;
    for (int v = 0; v < 3 * t; ++v) {
      const int k = v / 3;
      row(0, v) = S(k) + S(0.1) * S(v % 3);
      reversed(0, v) = S(k - k % leaf + leaf - 1 - k % leaf) + S(0.1) * S(v % 3);
    }
    TriangleBvh<S> by_row(topo, row, leaf), tied(topo, point, leaf), by_reversed(topo, reversed, leaf);
    by_row.refit(point, S(0));
    tied.refit(point, S(0));
    by_reversed.refit(point, S(0));
    const std::vector<Pair> expected = bvh_pairs(by_row);
    INFO("leaf size " << leaf);
    REQUIRE(expected.size() == std::size_t(t * (t - 1) / 2));
    REQUIRE(bvh_pairs(tied) == expected);
    REQUIRE(bvh_pairs(by_reversed) == expected);
  }
}

TEMPLATE_TEST_CASE("the BVH rejects positions of the wrong size and a bad leaf size", "[collision][bvh][validation]",
                   float, double) {
  using S = TestType;
  using Catch::Matchers::Contains;
  const drape::Grid<S> grid(4, 4, S(0.1), S(0.03));
  const MeshTopology topo(grid.node_count(), grid.triangles());
  REQUIRE_THROWS_WITH(TriangleBvh<S>(topo, Matrix3X<S>::Zero(3, 15)), Contains("'positions'") && Contains("16"));
  REQUIRE_THROWS_WITH(TriangleBvh<S>(topo, grid.rest_positions(), 0), Contains("'leaf_size'"));
  Matrix3X<S> bad = grid.rest_positions();
  bad(1, 5) = std::numeric_limits<S>::quiet_NaN();
  REQUIRE_THROWS_WITH(TriangleBvh<S>(topo, bad), Contains("'positions'"));
  TriangleBvh<S> bvh(topo, grid.rest_positions());
  REQUIRE_THROWS_AS(bvh.rebuild(Matrix3X<S>::Zero(3, 17)), drape::InvalidParameter);
}

// -------------------------------------------------------------------- features through ownership

/// Vertex-triangle pairs (node, triangle) and edge-edge pairs (e < f) of non-adjacent features whose
/// swept boxes overlap: by brute force over all features, and by the owned features of the BVH's
/// triangle pairs. Both lists unsorted, as produced.
template <class S>
struct FeaturePairs {
  std::vector<Pair> vertex_triangle, edge_edge;
};

template <class S>
FeaturePairs<S> brute_force_features(const MeshTopology& topo, const Matrix3X<S>& xs, const Matrix3X<S>& xe, S margin) {
  FeaturePairs<S> out;
  const auto tri_boxes = triangle_boxes(topo.triangles(), xs, xe, margin);
  std::vector<bool> used(std::size_t(topo.node_count()), false);
  for (const auto& t : topo.triangles())
    for (int v : t) used[std::size_t(v)] = true;
  for (int v = 0; v < topo.node_count(); ++v) {
    if (!used[std::size_t(v)]) continue;
    const TestBox<S> vb = swept_box(xs, xe, {v}, margin);
    for (int t = 0; t < topo.triangle_count(); ++t)
      if (!topo.triangle_has_node(t, v) && boxes_overlap(vb, tri_boxes[std::size_t(t)]))
        out.vertex_triangle.push_back({v, t});
  }
  std::vector<TestBox<S>> edge_boxes;
  for (const auto& e : topo.edges()) edge_boxes.push_back(swept_box(xs, xe, {e[0], e[1]}, margin));
  for (int e = 0; e < topo.edge_count(); ++e)
    for (int f = e + 1; f < topo.edge_count(); ++f)
      if (!topo.edges_share_node(e, f) && boxes_overlap(edge_boxes[std::size_t(e)], edge_boxes[std::size_t(f)]))
        out.edge_edge.push_back({e, f});
  return out;
}

template <class S>
FeaturePairs<S> features_through_ownership(const MeshTopology& topo, const std::vector<Pair>& triangle_pairs,
                                           const Matrix3X<S>& xs, const Matrix3X<S>& xe, S margin) {
  FeaturePairs<S> out;
  const auto tri_boxes = triangle_boxes(topo.triangles(), xs, xe, margin);
  const auto vertex_triangle = [&](int a, int b) {  // a's nodes against triangle b
    for (int v : topo.owned_nodes(a))
      if (!topo.triangle_has_node(b, v) && boxes_overlap(swept_box(xs, xe, {v}, margin), tri_boxes[std::size_t(b)]))
        out.vertex_triangle.push_back({v, b});
  };
  for (const Pair& p : triangle_pairs) {
    vertex_triangle(p[0], p[1]);
    vertex_triangle(p[1], p[0]);
    for (int e : topo.owned_edges(p[0]))
      for (int f : topo.owned_edges(p[1])) {
        const auto& ee = topo.edge(e);
        const auto& ff = topo.edge(f);
        if (!topo.edges_share_node(e, f) &&
            boxes_overlap(swept_box(xs, xe, {ee[0], ee[1]}, margin), swept_box(xs, xe, {ff[0], ff[1]}, margin)))
          out.edge_edge.push_back({std::min(e, f), std::max(e, f)});
      }
  }
  return out;
}

std::vector<Pair> sorted(std::vector<Pair> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEMPLATE_TEST_CASE("owned features over the BVH's pairs visit every overlapping VT and EE pair once",
                   "[collision][bvh][topology]", float, double) {
  using S = TestType;
  // Two crumpled cloths in one mesh, triangles shuffled, moving; and a random triangle soup.
  std::vector<std::pair<int, Triangles>> meshes;
  meshes.emplace_back(9 * 9 + 7 * 7, two_cloths_shuffled(9, 7, 17));
  std::mt19937 rng(19);
  std::uniform_int_distribution<int> node(0, 59);
  Triangles soup;
  while (soup.size() < 80) {
    const std::array<int, 3> t{node(rng), node(rng), node(rng)};
    if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) soup.push_back(t);
  }
  meshes.emplace_back(64, soup);

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const MeshTopology topo(meshes[m].first, meshes[m].second);
    Matrix3X<S> xs(3, topo.node_count());
    if (m == 0) {  // the second cloth laid over the first, both crumpled
      const drape::Grid<S> g0(9, 9, S(0.1), S(0.03)), g1(7, 7, S(0.1), S(0.03));
      xs.leftCols(81) = crumpled(g0, 0.08, 23);
      xs.rightCols(49) = crumpled(g1, 0.08, 29);
      xs.rightCols(49).array().colwise() += Eigen::Array<S, 3, 1>(S(0.05), S(0.04), S(0.1));
    } else {
      xs = moved(Matrix3X<S>(Matrix3X<S>::Zero(3, topo.node_count())), 0.5, 31);
    }
    const Matrix3X<S> xe = moved(xs, m == 0 ? 0.03 : 0.1, 37);
    const S margin = m == 0 ? S(0.01) : S(0.02);

    const FeaturePairs<S> expected = brute_force_features(topo, xs, xe, margin);
    INFO("mesh " << m);
    REQUIRE(expected.vertex_triangle.size() > 100);
    REQUIRE(expected.edge_edge.size() > 100);
    for (int leaf : {1, 4}) {
      TriangleBvh<S> bvh(topo, xs, leaf);
      bvh.refit(xs, xe, margin);
      const FeaturePairs<S> found = features_through_ownership(topo, bvh_pairs(bvh), xs, xe, margin);
      // Sorting keeps duplicates, so equality with the duplicate-free brute force means "each once".
      REQUIRE(sorted(found.vertex_triangle) == expected.vertex_triangle);
      REQUIRE(sorted(found.edge_edge) == expected.edge_edge);
    }
  }
}
