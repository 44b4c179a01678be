#pragma once
/// \file bounding_volume_hierarchy.hpp
/// The broad phase of cloth self-collision: a bounding volume hierarchy of axis-aligned boxes over
/// a mesh's triangles, refitted to each step's motion, that lists the pairs of triangles whose
/// boxes overlap. With the feature ownership of mesh_topology.hpp those pairs give every
/// vertex-triangle and edge-edge pair the narrow phase has to look at, each once. nearest() finds
/// the triangle closest to a point (mesh_distance.hpp: the signed distance of a mesh collider).
///
/// Built once, refitted every call: the tree is split top-down (median of the triangle centroids
/// along the longest axis of their box) on the positions it is built from, normally the rest
/// shape, where triangles that are near on the surface are near in the tree. A cloth's topology
/// never changes, so the tree stays valid however the cloth moves; refit() only recomputes boxes,
/// bottom-up, in O(n). The price: when the cloth deforms far from the shape the tree was built on
/// (crumpled, folded several times), sibling boxes grow and overlap more and the traversal visits
/// more box pairs; the answer stays exact, only slower. rebuild() splits again on the current
/// positions for callers who see that happen (the split is O(n log n), no allocation, and costs
/// about one query). It is no sure gain: on the benchmark's folded cloth, a tree split on the
/// folded shape answered half again as slowly (365 against 240 ns per node at 257 x 257) as the
/// one split on the rest shape, whose leaves each hold a patch of one layer.

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "drape/collision/mesh_topology.hpp"
#include "drape/config.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar>
class TriangleBvh {
 public:
  /// An axis-aligned box; two boxes overlap if they overlap or touch on every axis.
  struct Box {
    Vec3<Scalar> lo, hi;
    bool overlaps(const Box& other) const {
      return lo.x() <= other.hi.x() && other.lo.x() <= hi.x() && lo.y() <= other.hi.y() && other.lo.y() <= hi.y() &&
             lo.z() <= other.hi.z() && other.lo.z() <= hi.z();
    }
  };

  /// Triangles per leaf. In the broad_phase benchmark (bench/bench_collision.cpp, 257 x 257) a
  /// query took 480, 290, 260, 235 and 260 ns per node with leaves of 1, 2, 4, 8 and 16 on the
  /// folded cloth, 220, 135, 115, 108 and 113 on a flat one: small leaves spend the time descending,
  /// large ones testing triangle pairs whose boxes are apart.
  static constexpr int default_leaf_size = 8;
  static constexpr int max_leaf_size = 16;

  /// The tree of `topology`'s triangles split on `positions` (`3 x topology.node_count()`, usually
  /// the rest shape), with boxes fitted to `positions` without margin. The tree keeps its own copy
  /// of the triangles: the topology need not outlive it.
  /// \throws InvalidParameter naming `positions` if the column count differs from the node count or
  /// a coordinate is not finite, or `leaf_size` if it is outside [1, max_leaf_size].
  TriangleBvh(const MeshTopology& topology, const ConstRef3X<Scalar>& positions, int leaf_size = default_leaf_size);

  /// Splits the tree again on `positions` and fits the boxes to them without margin. The same
  /// checks as the constructor; no allocation.
  void rebuild(const ConstRef3X<Scalar>& positions);

  /// Each triangle's box becomes the box of its corners at `x_start` and `x_end` (it holds the
  /// triangle throughout a linear motion between them) grown by `margin` on every side; then the
  /// boxes of the tree, bottom-up. Two triangles' grown boxes overlap when their swept boxes are at
  /// most `2 * margin` apart along every axis. Positions must be finite (not checked per call: a
  /// box with a NaN overlaps nothing). O(n), no allocation.
  void refit(const ConstRef3X<Scalar>& x_start, const ConstRef3X<Scalar>& x_end, Scalar margin);
  /// The boxes of the triangles at rest at `x`, grown by `margin`.
  void refit(const ConstRef3X<Scalar>& x, Scalar margin) { refit(x, x, margin); }

  /// Every unordered pair {a, b} of distinct triangles whose boxes overlap, as {a, b} with a < b,
  /// each once, including pairs that share nodes: a triangle's far corner against its neighbour is
  /// a genuine collision pair when the cloth folds along their common edge, so adjacency is left
  /// to the narrow phase, feature by feature (MeshTopology::triangle_has_node, edges_share_node,
  /// which also answer for joined nodes).
  /// The order is the traversal's: a function of the tree (the positions it was built from and the
  /// leaf size) and of the boxes, the same on every run. `out` is cleared first and reused: no
  /// allocation once its capacity suffices.
  void overlapping_pairs(std::vector<std::array<int, 2>>& out) const;

  /// Branch and bound for the triangle nearest a point p: the boxes are visited nearer first and
  /// skipped once they are farther than `best_squared` (the squared distance to beat: infinity, or
  /// a bound the caller knows). `closer(t, best_squared)` measures triangle t and, if it is nearer
  /// than `best_squared`, lowers it and returns true. Returns the last triangle that did, -1 if
  /// none. The boxes are the last refit's (without margin, they hold the triangles).
  template <class Closer>
  int nearest(const Vec3<Scalar>& p, Scalar& best_squared, Closer&& closer) const;
  /// Calls `visit(t)` for every triangle whose box (the last refit's) overlaps `box`.
  template <class Visit>
  void for_each_overlapping(const Box& box, Visit&& visit) const;

  int triangle_count() const { return static_cast<int>(m_order.size()); }
  int leaf_size() const { return m_leaf_size; }
  /// Boxes in the tree, leaves included.
  int volume_count() const { return static_cast<int>(m_volumes.size()); }
  /// The box of the whole mesh (empty if there are no triangles: lo > hi).
  Box bounds() const { return m_volumes.empty() ? empty_box() : m_volumes.front().box; }

 private:
  // A box of the tree over the contiguous slots [first, first + count) of m_order. Stored in
  // depth-first order: the left child of volume v is v + 1, the right one is `right`; a volume is a
  // leaf if count <= leaf size. Children come after their parent, so a backward sweep refits.
  struct Volume {
    Box box;
    int first;
    int count;
    int right;
  };

  /// The squared distance from p to the box (0 inside).
  static Scalar distance_squared(const Box& box, const Vec3<Scalar>& p) {
    const Vec3<Scalar> out = (box.lo - p).cwiseMax(p - box.hi).cwiseMax(Scalar(0));
    return out.squaredNorm();
  }
  static Box empty_box() {
    return {Vec3<Scalar>::Constant(std::numeric_limits<Scalar>::infinity()),
            Vec3<Scalar>::Constant(-std::numeric_limits<Scalar>::infinity())};
  }
  void check_positions(const ConstRef3X<Scalar>& positions) const;
  int split(int first, int count);
  bool is_leaf(const Volume& v) const { return v.count <= m_leaf_size; }
  void self_pairs(int v, std::vector<std::array<int, 2>>& out) const;
  void cross_pairs(int a, int b, std::vector<std::array<int, 2>>& out) const;
  void emit(int slot_a, int slot_b, std::vector<std::array<int, 2>>& out) const {
    const int ta = m_order[static_cast<std::size_t>(slot_a)], tb = m_order[static_cast<std::size_t>(slot_b)];
    out.push_back(ta < tb ? std::array<int, 2>{ta, tb} : std::array<int, 2>{tb, ta});
  }

  int m_node_count;
  int m_leaf_size;
  std::vector<std::array<int, 3>> m_triangles;  // by triangle id
  std::vector<int> m_order;                     // slot -> triangle id, leaves contiguous
  std::vector<std::array<int, 3>> m_corners;    // by slot: the corners of m_order[slot]
  std::vector<Box> m_boxes;                     // by slot
  std::vector<Vec3<Scalar>> m_centroids;        // by triangle id, during a split
  std::vector<Volume> m_volumes;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
TriangleBvh<Scalar>::TriangleBvh(const MeshTopology& topology, const ConstRef3X<Scalar>& positions, int leaf_size)
    : m_node_count(topology.node_count()), m_leaf_size(leaf_size), m_triangles(topology.triangles()) {
  detail::require_in_range("leaf_size", leaf_size, 1, max_leaf_size);
  const std::size_t n = m_triangles.size();
  m_order.resize(n);
  m_corners.resize(n);
  m_boxes.resize(n);
  m_centroids.resize(n);
  // A binary tree with at most n leaves has at most 2n - 1 volumes: rebuild() never reallocates.
  m_volumes.reserve(2 * n + 1);
  rebuild(positions);
}

template <class Scalar>
void TriangleBvh<Scalar>::check_positions(const ConstRef3X<Scalar>& positions) const {
  if (positions.cols() != m_node_count)
    detail::fail_argument("positions", detail::to_text(positions.cols()) + " columns",
                          detail::to_text(m_node_count) + " columns (one per node)");
  if (!positions.allFinite()) detail::fail_argument("positions", "not finite", "finite coordinates");
}

template <class Scalar>
void TriangleBvh<Scalar>::rebuild(const ConstRef3X<Scalar>& positions) {
  check_positions(positions);
  const std::size_t n = m_triangles.size();
  for (std::size_t t = 0; t < n; ++t) {
    const std::array<int, 3>& c = m_triangles[t];
    m_centroids[t] = (positions.col(c[0]) + positions.col(c[1]) + positions.col(c[2])) / Scalar(3);
    m_order[t] = static_cast<int>(t);
  }
  m_volumes.clear();
  if (n > 0) split(0, static_cast<int>(n));
  for (std::size_t s = 0; s < n; ++s) m_corners[s] = m_triangles[static_cast<std::size_t>(m_order[s])];
  refit(positions, positions, Scalar(0));
}

// Builds the subtree over slots [first, first + count) and returns its volume's index. The median
// split sorts by (centroid along the axis, triangle id): a strict total order, so every volume's
// set of triangles is fixed by the positions alone; within a leaf the slots are put in id order,
// which makes the whole layout independent of how the standard library partitions.
template <class Scalar>
int TriangleBvh<Scalar>::split(int first, int count) {
  const int v = static_cast<int>(m_volumes.size());
  m_volumes.push_back({empty_box(), first, count, -1});
  const auto begin = m_order.begin() + first, end = begin + count;
  if (count <= m_leaf_size) {
    std::sort(begin, end);
    return v;
  }
  Vec3<Scalar> lo = m_centroids[static_cast<std::size_t>(*begin)], hi = lo;
  for (auto it = begin; it != end; ++it) {
    lo = lo.cwiseMin(m_centroids[static_cast<std::size_t>(*it)]);
    hi = hi.cwiseMax(m_centroids[static_cast<std::size_t>(*it)]);
  }
  int axis = 0;
  const Vec3<Scalar> extent = hi - lo;
  if (extent.y() > extent[axis]) axis = 1;
  if (extent.z() > extent[axis]) axis = 2;
  const int half = count / 2;
  std::nth_element(begin, begin + half, end, [&](int a, int b) {
    const Scalar ca = m_centroids[static_cast<std::size_t>(a)][axis],
                 cb = m_centroids[static_cast<std::size_t>(b)][axis];
    return ca != cb ? ca < cb : a < b;
  });
  split(first, half);
  const int right = split(first + half, count - half);
  m_volumes[static_cast<std::size_t>(v)].right = right;
  return v;
}

template <class Scalar>
void TriangleBvh<Scalar>::refit(const ConstRef3X<Scalar>& x_start, const ConstRef3X<Scalar>& x_end, Scalar margin) {
  DRAPE_ASSERT(x_start.cols() == m_node_count && x_end.cols() == m_node_count, "refit: one column per node");
  DRAPE_ASSERT(margin >= Scalar(0), "refit: margin >= 0");
  const std::size_t n = m_corners.size();
  const Vec3<Scalar> grow = Vec3<Scalar>::Constant(margin);
  for (std::size_t s = 0; s < n; ++s) {
    const std::array<int, 3>& c = m_corners[s];
    Vec3<Scalar> lo = x_start.col(c[0]).cwiseMin(x_end.col(c[0]));
    Vec3<Scalar> hi = x_start.col(c[0]).cwiseMax(x_end.col(c[0]));
    for (std::size_t k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(x_start.col(c[k])).cwiseMin(x_end.col(c[k]));
      hi = hi.cwiseMax(x_start.col(c[k])).cwiseMax(x_end.col(c[k]));
    }
    m_boxes[s] = {lo - grow, hi + grow};
  }
  for (std::size_t v = m_volumes.size(); v-- > 0;) {
    Volume& volume = m_volumes[v];
    if (is_leaf(volume)) {
      const Box* box = &m_boxes[static_cast<std::size_t>(volume.first)];
      volume.box = box[0];
      for (int k = 1; k < volume.count; ++k) {
        volume.box.lo = volume.box.lo.cwiseMin(box[k].lo);
        volume.box.hi = volume.box.hi.cwiseMax(box[k].hi);
      }
    } else {
      const Box& left = m_volumes[v + 1].box;
      const Box& right = m_volumes[static_cast<std::size_t>(volume.right)].box;
      volume.box = {left.lo.cwiseMin(right.lo), left.hi.cwiseMax(right.hi)};
    }
  }
}

template <class Scalar>
void TriangleBvh<Scalar>::overlapping_pairs(std::vector<std::array<int, 2>>& out) const {
  out.clear();
  if (!m_volumes.empty()) self_pairs(0, out);
}

// The pairs inside volume v: those inside each child and those across the two.
template <class Scalar>
void TriangleBvh<Scalar>::self_pairs(int v, std::vector<std::array<int, 2>>& out) const {
  const Volume& volume = m_volumes[static_cast<std::size_t>(v)];
  if (is_leaf(volume)) {
    const int end = volume.first + volume.count;
    for (int a = volume.first; a < end; ++a)
      for (int b = a + 1; b < end; ++b)
        if (m_boxes[static_cast<std::size_t>(a)].overlaps(m_boxes[static_cast<std::size_t>(b)])) emit(a, b, out);
    return;
  }
  self_pairs(v + 1, out);
  self_pairs(volume.right, out);
  cross_pairs(v + 1, volume.right, out);
}

// The pairs with one triangle in volume a and the other in volume b (disjoint volumes).
template <class Scalar>
void TriangleBvh<Scalar>::cross_pairs(int a, int b, std::vector<std::array<int, 2>>& out) const {
  const Volume& va = m_volumes[static_cast<std::size_t>(a)];
  const Volume& vb = m_volumes[static_cast<std::size_t>(b)];
  if (!va.box.overlaps(vb.box)) return;
  const bool leaf_a = is_leaf(va), leaf_b = is_leaf(vb);
  if (leaf_a && leaf_b) {
    for (int i = va.first; i < va.first + va.count; ++i) {
      const Box& box = m_boxes[static_cast<std::size_t>(i)];
      if (!box.overlaps(vb.box)) continue;
      for (int j = vb.first; j < vb.first + vb.count; ++j)
        if (box.overlaps(m_boxes[static_cast<std::size_t>(j)])) emit(i, j, out);
    }
    return;
  }
  // Descend the larger volume, so the two sides stay of similar size.
  if (leaf_b || (!leaf_a && va.count >= vb.count)) {
    cross_pairs(a + 1, b, out);
    cross_pairs(va.right, b, out);
  } else {
    cross_pairs(a, b + 1, out);
    cross_pairs(a, vb.right, out);
  }
}

template <class Scalar>
template <class Closer>
int TriangleBvh<Scalar>::nearest(const Vec3<Scalar>& p, Scalar& best_squared, Closer&& closer) const {
  int best = -1;
  if (m_volumes.empty()) return best;
  // The median split keeps the depth below log2(n) + 2: a stack of 64 holds any tree that fits memory.
  std::array<std::pair<int, Scalar>, 64> stack;
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = {0, distance_squared(m_volumes.front().box, p)};
  while (top > 0) {
    const auto [v, reach] = stack[static_cast<std::size_t>(--top)];
    if (reach > best_squared) continue;
    const Volume& volume = m_volumes[static_cast<std::size_t>(v)];
    if (is_leaf(volume)) {
      for (int s = volume.first; s < volume.first + volume.count; ++s)
        if (distance_squared(m_boxes[static_cast<std::size_t>(s)], p) <= best_squared &&
            closer(m_order[static_cast<std::size_t>(s)], best_squared))
          best = m_order[static_cast<std::size_t>(s)];
      continue;
    }
    const int left = v + 1, right = volume.right;
    const Scalar d_left = distance_squared(m_volumes[static_cast<std::size_t>(left)].box, p);
    const Scalar d_right = distance_squared(m_volumes[static_cast<std::size_t>(right)].box, p);
    // The nearer child goes on top, so it is searched first and the farther one is likely pruned.
    if (d_left <= d_right) {
      stack[static_cast<std::size_t>(top++)] = {right, d_right};
      stack[static_cast<std::size_t>(top++)] = {left, d_left};
    } else {
      stack[static_cast<std::size_t>(top++)] = {left, d_left};
      stack[static_cast<std::size_t>(top++)] = {right, d_right};
    }
  }
  return best;
}

template <class Scalar>
template <class Visit>
void TriangleBvh<Scalar>::for_each_overlapping(const Box& box, Visit&& visit) const {
  if (m_volumes.empty()) return;
  std::array<int, 64> stack;
  int top = 0;
  stack[static_cast<std::size_t>(top++)] = 0;
  while (top > 0) {
    const int v = stack[static_cast<std::size_t>(--top)];
    const Volume& volume = m_volumes[static_cast<std::size_t>(v)];
    if (!volume.box.overlaps(box)) continue;
    if (is_leaf(volume)) {
      for (int s = volume.first; s < volume.first + volume.count; ++s)
        if (m_boxes[static_cast<std::size_t>(s)].overlaps(box)) visit(m_order[static_cast<std::size_t>(s)]);
      continue;
    }
    stack[static_cast<std::size_t>(top++)] = volume.right;
    stack[static_cast<std::size_t>(top++)] = v + 1;
  }
}

}  // namespace drape
