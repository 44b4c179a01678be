#pragma once
/// \file mesh_topology.hpp
/// The connectivity a cloth self-collision pass needs from a triangle mesh: its unique edges, each
/// triangle's edges, and an *ownership* of nodes and edges by triangles that lets a broad phase
/// over triangle pairs visit every vertex-triangle and edge-edge pair exactly once.
///
/// Ownership: every node that belongs to a triangle is owned by the lowest-index triangle that
/// contains it, every edge by the lowest-index triangle that contains it. For each unordered pair
/// of distinct triangles {A, B} whose (swept, inflated) boxes overlap, the narrow phase tests
/// - the nodes A owns against triangle B and the nodes B owns against triangle A (vertex-triangle),
/// - the edges A owns against the edges B owns (edge-edge).
/// Why this visits every feature pair whose boxes overlap exactly once: a node's box (the box of
/// its start and end positions, inflated by the same margin) lies inside the box of every triangle
/// that contains it, in particular inside its owner's; so if node v's box overlaps triangle T's
/// box, the box of owner(v) overlaps T's too, and {owner(v), T} is a broad-phase pair unless
/// owner(v) = T (then v is a corner of T: not a collision pair). The pair {owner(v), T} is reported
/// once and v has one owner, so (v, T) comes up once, from the side that owns v. Likewise an edge's
/// box lies inside its owner's box: if edges e and f have overlapping boxes, {owner(e), owner(f)}
/// is a broad-phase pair unless both have the same owner (then e and f are two sides of one
/// triangle and share a node). Pairs of features that share a node still come up (a corner of A
/// against a triangle B that also contains it, two edges meeting at a node): the caller drops them
/// with triangle_has_node() and edges_share_node(); the broad phase must keep triangle pairs that
/// share nodes, since the far corner of A against B is a genuine pair when the cloth folds there.
///
/// Nothing here assumes a grid: several cloths concatenated into one node numbering are one mesh.
///
/// Joined nodes: pairs of distinct nodes that count as one node for adjacency (the two sides of a
/// garment's seam, sewn together). Every node has a representative, the lowest id of the nodes
/// joined to it directly or through a chain of pairs (itself if none), and the adjacency queries
/// compare representatives: a vertex joined to a corner of a triangle counts as a corner of it, two
/// edges with joined ends share a node. Ownership and the broad phase go by node ids and do not
/// change: joining only drops more pairs in the narrow phase. Without joined nodes every
/// representative is the node itself and the queries compare the ids as given.

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "drape/core/validation.hpp"

namespace drape {

/// A read-only run of ids inside a `MeshTopology` (a `std::span<const int>` for C++17).
class IdRange {
 public:
  IdRange(const int* first, const int* last) : m_first(first), m_last(last) {}
  const int* begin() const { return m_first; }
  const int* end() const { return m_last; }
  int size() const { return static_cast<int>(m_last - m_first); }
  bool empty() const { return m_first == m_last; }
  int operator[](int k) const { return m_first[k]; }

 private:
  const int* m_first;
  const int* m_last;
};

class MeshTopology {
 public:
  /// The mesh of `triangles` over nodes `0 .. node_count - 1`. Nodes no triangle uses are allowed
  /// (they take no part in cloth-cloth collision and have no owner).
  /// `joined`: pairs of nodes that count as one node for adjacency (see the file comment).
  /// \throws InvalidParameter naming `node_count` if it is negative, `triangles` if a triangle
  /// has an id outside [0, node_count) or repeats a node, or `joined` if a pair has an id outside
  /// [0, node_count) or joins a node to itself.
  MeshTopology(int node_count, std::vector<std::array<int, 3>> triangles,
               const std::vector<std::array<int, 2>>& joined = {});

  int node_count() const { return m_node_count; }
  int triangle_count() const { return static_cast<int>(m_triangles.size()); }
  int edge_count() const { return static_cast<int>(m_edges.size()); }

  /// The three node ids of triangle t, in the order given.
  const std::array<int, 3>& triangle(int t) const { return m_triangles[static_cast<std::size_t>(t)]; }
  const std::vector<std::array<int, 3>>& triangles() const { return m_triangles; }
  /// Edge e's nodes (a, b) with a < b. Edges are sorted by (a, b), so their ids depend only on the
  /// set of edges, not on the order of the triangles.
  const std::array<int, 2>& edge(int e) const { return m_edges[static_cast<std::size_t>(e)]; }
  const std::vector<std::array<int, 2>>& edges() const { return m_edges; }
  /// Triangle t's edge ids: entry k joins corners k and (k + 1) % 3.
  const std::array<int, 3>& triangle_edges(int t) const { return m_triangle_edges[static_cast<std::size_t>(t)]; }

  /// The nodes triangle t owns (the ones no lower-index triangle contains), in corner order.
  IdRange owned_nodes(int t) const { return range(m_owned_nodes, m_owned_node_begin, t); }
  /// The edges triangle t owns (the ones no lower-index triangle contains), in corner order.
  IdRange owned_edges(int t) const { return range(m_owned_edges, m_owned_edge_begin, t); }

  /// True if some pairs of nodes are joined.
  bool has_joined_nodes() const { return !m_representative.empty(); }
  /// The node that stands for `node` in the adjacency queries: the lowest id joined to it, directly
  /// or through a chain of pairs; `node` itself if it is joined to none.
  int representative(int node) const {
    return m_representative.empty() ? node : m_representative[static_cast<std::size_t>(node)];
  }

  /// True if `node` is a corner of triangle t, or joined to one.
  bool triangle_has_node(int t, int node) const {
    const std::array<int, 3>& c = joined_corners(t);
    const int v = representative(node);
    return c[0] == v || c[1] == v || c[2] == v;
  }
  /// True if edges e and f have a node in common (or are the same edge), or joined nodes.
  bool edges_share_node(int e, int f) const {
    const std::array<int, 2>& p = joined_ends(e);
    const std::array<int, 2>& q = joined_ends(f);
    return p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1];
  }
  /// True if triangles s and t have a node in common (or are the same triangle), or joined nodes.
  bool triangles_share_node(int s, int t) const {
    const std::array<int, 3>& c = triangle(s);
    return triangle_has_node(t, c[0]) || triangle_has_node(t, c[1]) || triangle_has_node(t, c[2]);
  }

 private:
  /// Triangle t's corners as representatives (the corners themselves without joined nodes).
  const std::array<int, 3>& joined_corners(int t) const {
    return m_representative.empty() ? triangle(t) : m_joined_triangles[static_cast<std::size_t>(t)];
  }
  /// Edge e's ends as representatives (the ends themselves without joined nodes).
  const std::array<int, 2>& joined_ends(int e) const {
    return m_representative.empty() ? edge(e) : m_joined_edges[static_cast<std::size_t>(e)];
  }
  static IdRange range(const std::vector<int>& ids, const std::vector<int>& begin, int t) {
    const int* base = ids.data();
    const std::size_t k = static_cast<std::size_t>(t);
    return {base + begin[k], base + begin[k + 1]};
  }

  int m_node_count;
  std::vector<std::array<int, 3>> m_triangles;
  std::vector<std::array<int, 2>> m_edges;
  std::vector<std::array<int, 3>> m_triangle_edges;
  // Owned features in CSR form: triangle t owns m_owned_nodes[m_owned_node_begin[t] ..
  // m_owned_node_begin[t + 1]), likewise for edges.
  std::vector<int> m_owned_nodes, m_owned_node_begin;
  std::vector<int> m_owned_edges, m_owned_edge_begin;
  // With joined nodes: each node's representative, and the triangles' corners and edges' ends as
  // representatives. All empty without.
  std::vector<int> m_representative;
  std::vector<std::array<int, 3>> m_joined_triangles;
  std::vector<std::array<int, 2>> m_joined_edges;
};

// ---------------------------------------------------------------------------------------------

inline MeshTopology::MeshTopology(int node_count, std::vector<std::array<int, 3>> triangles,
                                  const std::vector<std::array<int, 2>>& joined)
    : m_node_count(node_count), m_triangles(std::move(triangles)) {
  detail::require_at_least("node_count", node_count, 0);
  const std::size_t triangle_count = m_triangles.size();
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const std::array<int, 3>& c = m_triangles[t];
    const bool in_range = std::all_of(c.begin(), c.end(), [&](int v) { return v >= 0 && v < node_count; });
    if (!in_range || c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
      detail::fail_argument("triangles",
                            "triangle " + detail::to_text(t) + " = (" + detail::to_text(c[0]) + ", " +
                                detail::to_text(c[1]) + ", " + detail::to_text(c[2]) + ")",
                            "three distinct node ids in [0, " + detail::to_text(node_count) + ")");
  }

  // Every triangle side as (a, b, triangle, corner) with a < b; sorted, equal (a, b) are one edge.
  struct Side {
    int a, b, triangle, corner;
  };
  std::vector<Side> sides;
  sides.reserve(3 * triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      const int p = m_triangles[t][static_cast<std::size_t>(k)],
                q = m_triangles[t][static_cast<std::size_t>((k + 1) % 3)];
      sides.push_back({std::min(p, q), std::max(p, q), static_cast<int>(t), k});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& l, const Side& r) {
    return l.a != r.a ? l.a < r.a : l.b != r.b ? l.b < r.b : l.triangle < r.triangle;
  });
  m_triangle_edges.resize(triangle_count);
  for (std::size_t s = 0; s < sides.size(); ++s) {
    if (s == 0 || sides[s].a != sides[s - 1].a || sides[s].b != sides[s - 1].b)
      m_edges.push_back({sides[s].a, sides[s].b});
    m_triangle_edges[static_cast<std::size_t>(sides[s].triangle)][static_cast<std::size_t>(sides[s].corner)] =
        static_cast<int>(m_edges.size()) - 1;
  }

  // Ownership: walking the triangles in index order, the first to meet a feature owns it.
  std::vector<bool> node_taken(static_cast<std::size_t>(node_count), false);
  std::vector<bool> edge_taken(m_edges.size(), false);
  m_owned_node_begin.reserve(triangle_count + 1);
  m_owned_edge_begin.reserve(triangle_count + 1);
  m_owned_node_begin.push_back(0);
  m_owned_edge_begin.push_back(0);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      const int v = m_triangles[t][k];
      if (!node_taken[static_cast<std::size_t>(v)]) {
        node_taken[static_cast<std::size_t>(v)] = true;
        m_owned_nodes.push_back(v);
      }
      const int e = m_triangle_edges[t][k];
      if (!edge_taken[static_cast<std::size_t>(e)]) {
        edge_taken[static_cast<std::size_t>(e)] = true;
        m_owned_edges.push_back(e);
      }
    }
    m_owned_node_begin.push_back(static_cast<int>(m_owned_nodes.size()));
    m_owned_edge_begin.push_back(static_cast<int>(m_owned_edges.size()));
  }

  if (joined.empty()) return;
  for (std::size_t k = 0; k < joined.size(); ++k) {
    const std::array<int, 2>& p = joined[k];
    if (!(p[0] >= 0 && p[0] < node_count && p[1] >= 0 && p[1] < node_count && p[0] != p[1]))
      detail::fail_argument("joined",
                            "pair " + detail::to_text(k) + " = (" + detail::to_text(p[0]) + ", " +
                                detail::to_text(p[1]) + ")",
                            "two distinct node ids in [0, " + detail::to_text(node_count) + ")");
  }
  // Union-find whose roots are the lowest ids of their sets: every parent is lower than its child.
  std::vector<int>& parent = m_representative;
  parent.resize(static_cast<std::size_t>(node_count));
  for (int v = 0; v < node_count; ++v) parent[static_cast<std::size_t>(v)] = v;
  const auto root = [&parent](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {  // path halving keeps parents below children
      const int up = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
      parent[static_cast<std::size_t>(v)] = up;
      v = up;
    }
    return v;
  };
  for (const std::array<int, 2>& p : joined) {
    const int a = root(p[0]), b = root(p[1]);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  // In ascending order a node's parent (lower) already points at its root.
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = parent[static_cast<std::size_t>(parent[v])];

  m_joined_triangles.reserve(triangle_count);
  for (const std::array<int, 3>& c : m_triangles)
    m_joined_triangles.push_back({representative(c[0]), representative(c[1]), representative(c[2])});
  m_joined_edges.reserve(m_edges.size());
  for (const std::array<int, 2>& e : m_edges) m_joined_edges.push_back({representative(e[0]), representative(e[1])});
}

}  // namespace drape
