#pragma once
// Brute-force checks of a triangle mesh for cloth self-collision tests: does any pair of triangles
// intersect, and how close do primitives that share no vertex come. Every pair is decided, after
// an axis-aligned box reject; pairs whose extents along x are apart are rejected together by a
// sweep over the boxes sorted along x (the same answers as testing all pairs one by one: the
// `_all_pairs` versions, which test_geometry compares them with). Simple on purpose and
// independent of drape's broad phase: they are the reference the collision code is judged by.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "drape/collision/primitive_distance.hpp"
#include "drape/core/types.hpp"

namespace drape::test {

namespace check_detail {

using Wide = long double;
using Wide3 = std::array<Wide, 3>;
using Wide2 = std::array<Wide, 2>;

template <class S>
Wide3 widen(const Vec3<S>& x) {
  return {Wide(x[0]), Wide(x[1]), Wide(x[2])};
}

/// Sign of the orientation determinant det[a - d, b - d, c - d], or 0 when its magnitude is within
/// the rounding bound of the long double evaluation (Shewchuk's static bound, doubled), so a sign
/// that is not 0 is certain.
inline int orientation(const Wide3& a, const Wide3& b, const Wide3& c, const Wide3& d) {
  const Wide adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
  const Wide bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
  const Wide cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
  const Wide det = adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
  const Wide permanent = (std::abs(bdx * cdy) + std::abs(cdx * bdy)) * std::abs(adz) +
                         (std::abs(cdx * ady) + std::abs(adx * cdy)) * std::abs(bdz) +
                         (std::abs(adx * bdy) + std::abs(bdx * ady)) * std::abs(cdz);
  const Wide bound = 8 * std::numeric_limits<Wide>::epsilon() * permanent;
  return det > bound ? 1 : det < -bound ? -1 : 0;
}

/// Sign of det[a - c, b - c] in 2D, 0 within its rounding bound.
inline int orientation(const Wide2& a, const Wide2& b, const Wide2& c) {
  const Wide left = (a[0] - c[0]) * (b[1] - c[1]), right = (a[1] - c[1]) * (b[0] - c[0]);
  const Wide bound = 4 * std::numeric_limits<Wide>::epsilon() * (std::abs(left) + std::abs(right));
  const Wide det = left - right;
  return det > bound ? 1 : det < -bound ? -1 : 0;
}

/// No two of the signs strictly opposite (zeros agree with both).
inline bool no_opposite(int s0, int s1, int s2) {
  return !((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0));
}

inline bool strictly_one_side(const std::array<int, 3>& s) {
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

/// Closed 2D segments ab and cd meet. An uncertain (0) orientation counts as touching; when all
/// four are 0 the segments are collinear and meet iff their boxes overlap.
inline bool segments_meet(const Wide2& a, const Wide2& b, const Wide2& c, const Wide2& d) {
  const int d1 = orientation(c, d, a), d2 = orientation(c, d, b);
  const int d3 = orientation(a, b, c), d4 = orientation(a, b, d);
  if (d1 * d2 > 0 || d3 * d4 > 0) return false;
  if (d1 == 0 && d2 == 0 && d3 == 0 && d4 == 0)
    for (int k = 0; k < 2; ++k)
      if (std::max(a[k], b[k]) < std::min(c[k], d[k]) || std::max(c[k], d[k]) < std::min(a[k], b[k])) return false;
  return true;
}

/// p in the closed 2D triangle t (a degenerate t counts every point on its line as inside).
inline bool point_in_triangle(const Wide2& p, const std::array<Wide2, 3>& t) {
  return no_opposite(orientation(t[0], t[1], p), orientation(t[1], t[2], p), orientation(t[2], t[0], p));
}

/// The 2D projection of x that drops coordinate `axis`.
inline Wide2 drop(const Wide3& x, int axis) { return {x[axis == 0 ? 1 : 0], x[axis == 2 ? 1 : 2]}; }

/// Closed triangles a and b (nearly) in one plane: they meet only if their projections along each
/// axis meet, and the projection along the plane's dominant normal axis is faithful.
inline bool coplanar_triangles_meet(const std::array<Wide3, 3>& a, const std::array<Wide3, 3>& b) {
  for (int axis = 0; axis < 3; ++axis) {
    const std::array<Wide2, 3> pa = {drop(a[0], axis), drop(a[1], axis), drop(a[2], axis)};
    const std::array<Wide2, 3> pb = {drop(b[0], axis), drop(b[1], axis), drop(b[2], axis)};
    bool meet = point_in_triangle(pa[0], pb) || point_in_triangle(pb[0], pa);
    for (int i = 0; i < 3 && !meet; ++i)
      for (int j = 0; j < 3 && !meet; ++j) meet = segments_meet(pa[i], pa[(i + 1) % 3], pb[j], pb[(j + 1) % 3]);
    if (!meet) return false;
  }
  return true;
}

/// Closed segment pq meets the closed triangle t.
inline bool segment_meets_triangle(const Wide3& p, const Wide3& q, const std::array<Wide3, 3>& t) {
  const int sp = orientation(t[0], t[1], t[2], p), sq = orientation(t[0], t[1], t[2], q);
  if (sp * sq > 0) return false;
  if (sp == 0 && sq == 0) {
    // In the triangle's plane as far as rounding can tell: compare projections.
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<Wide2, 3> pt = {drop(t[0], axis), drop(t[1], axis), drop(t[2], axis)};
      const Wide2 pp = drop(p, axis), pq = drop(q, axis);
      bool meet = point_in_triangle(pp, pt);
      for (int j = 0; j < 3 && !meet; ++j) meet = segments_meet(pp, pq, pt[j], pt[(j + 1) % 3]);
      if (!meet) return false;
    }
    return true;
  }
  // The segment reaches the plane at one point; it is in t iff the line pq passes the three edges
  // on one side (Pluecker sides).
  return no_opposite(orientation(p, q, t[0], t[1]), orientation(p, q, t[1], t[2]), orientation(p, q, t[2], t[0]));
}

template <class S>
struct Box3 {
  Vec3<S> low, high;
};

template <class S>
Box3<S> box_of(const Vec3<S>& a, const Vec3<S>& b) {
  return {a.cwiseMin(b), a.cwiseMax(b)};
}

template <class S>
Box3<S> box_of(const Vec3<S>& a, const Vec3<S>& b, const Vec3<S>& c) {
  return {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c)};
}

template <class S>
bool boxes_overlap(const Box3<S>& a, const Box3<S>& b) {
  return (a.low.array() <= b.high.array()).all() && (b.low.array() <= a.high.array()).all();
}

/// Squared distance between two boxes (0 if they overlap).
template <class S>
S box_distance_squared(const Box3<S>& a, const Box3<S>& b) {
  const Vec3<S> gap = (a.low - b.high).cwiseMax(b.low - a.high).cwiseMax(Vec3<S>::Zero());
  return gap.squaredNorm();
}

/// visit(i, j) for every pair of boxes i != j (each pair once) whose extents along x are at most
/// reach() apart; reach() is read again for every box, so a bound that shrinks as the visits go
/// on prunes more. Sorted by their low x, the boxes after box a are ever farther from it along x.
template <class S, class Reach, class Visit>
void sweep_along_x(const std::vector<Box3<S>>& boxes, Reach reach, Visit visit) {
  std::vector<int> order(boxes.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return boxes[std::size_t(a)].low.x() < boxes[std::size_t(b)].low.x(); });
  for (std::size_t a = 0; a < order.size(); ++a) {
    const S high = boxes[std::size_t(order[a])].high.x(), limit = reach();
    for (std::size_t b = a + 1; b < order.size() && boxes[std::size_t(order[b])].low.x() - high <= limit; ++b)
      visit(order[a], order[b]);
  }
}

}  // namespace check_detail

/// Do the closed triangles a0 a1 a2 and b0 b1 b2 intersect? Conservative: it never answers false
/// for triangles that intersect or touch. Orientations are evaluated in long double with a
/// rounding bound, and one within the bound counts as 0, i.e. touching: degenerate and
/// near-touching configurations count as intersecting.
template <class S>
bool triangles_intersect(const Vec3<S>& a0, const Vec3<S>& a1, const Vec3<S>& a2, const Vec3<S>& b0, const Vec3<S>& b1,
                         const Vec3<S>& b2) {
  using check_detail::orientation;
  const std::array<check_detail::Wide3, 3> a = {check_detail::widen(a0), check_detail::widen(a1),
                                                check_detail::widen(a2)};
  const std::array<check_detail::Wide3, 3> b = {check_detail::widen(b0), check_detail::widen(b1),
                                                check_detail::widen(b2)};
  std::array<int, 3> b_side, a_side;
  for (int i = 0; i < 3; ++i) {
    b_side[i] = orientation(a[0], a[1], a[2], b[i]);
    a_side[i] = orientation(b[0], b[1], b[2], a[i]);
  }
  if (check_detail::strictly_one_side(b_side) || check_detail::strictly_one_side(a_side)) return false;
  const auto all_zero = [](const std::array<int, 3>& s) { return s[0] == 0 && s[1] == 0 && s[2] == 0; };
  if (all_zero(b_side) && all_zero(a_side)) return check_detail::coplanar_triangles_meet(a, b);
  // Not coplanar (a certain sign says so): the intersection, a segment or a point, has an end on an
  // edge of one of the triangles.
  for (int i = 0; i < 3; ++i) {
    if (check_detail::segment_meets_triangle(a[i], a[(i + 1) % 3], b)) return true;
    if (check_detail::segment_meets_triangle(b[i], b[(i + 1) % 3], a)) return true;
  }
  return false;
}

struct MeshIntersection {
  bool found;
  int tri_a;  ///< the first pair (tri_a < tri_b) in the order of the triangle list; -1 if none
  int tri_b;
};

/// Do triangles i and j share no vertex, and intersect? With `same`, vertices a and b count as one
/// when same[a] == same[b] (a garment's sewn vertices: sewn_vertex_classes()).
template <class S>
bool disjoint_triangles_intersect(const Matrix3X<S>& x, const std::array<int, 3>& ti, const std::array<int, 3>& tj,
                                  const std::vector<int>* same = nullptr) {
  for (int a : ti)
    for (int b : tj)
      if (a == b || (same && (*same)[std::size_t(a)] == (*same)[std::size_t(b)])) return false;
  return triangles_intersect<S>(x.col(ti[0]), x.col(ti[1]), x.col(ti[2]), x.col(tj[0]), x.col(tj[1]), x.col(tj[2]));
}

/// Per vertex of `n`, the smallest vertex sewn to it through `pairs`, directly or along a chain
/// (a panel corner where two seams meet): vertices of one class count as one vertex. Written here by
/// plain relaxation, apart from the library's union-find.
inline std::vector<int> sewn_vertex_classes(int n, const std::vector<std::array<int, 2>>& pairs) {
  std::vector<int> same(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) same[std::size_t(v)] = v;
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& [a, b] : pairs) {
      const int low = std::min(same[std::size_t(a)], same[std::size_t(b)]);
      for (int v : {a, b})
        if (same[std::size_t(v)] != low) {
          same[std::size_t(v)] = low;
          changed = true;
        }
    }
  }
  return same;
}

/// The first pair of triangles (in the order of the triangle list) that share no vertex and
/// intersect (triangles_intersect): every pair whose boxes overlap is tested. `same`: as
/// disjoint_triangles_intersect().
template <class S>
MeshIntersection first_intersection(const Matrix3X<S>& x, const std::vector<std::array<int, 3>>& triangles,
                                    const std::vector<int>* same = nullptr) {
  std::vector<check_detail::Box3<S>> boxes;
  boxes.reserve(triangles.size());
  for (const auto& t : triangles) boxes.push_back(check_detail::box_of<S>(x.col(t[0]), x.col(t[1]), x.col(t[2])));
  std::vector<std::pair<int, int>> overlapping;
  check_detail::sweep_along_x(
      boxes, [] { return S(0); },
      [&](int i, int j) {
        if (check_detail::boxes_overlap(boxes[std::size_t(i)], boxes[std::size_t(j)]))
          overlapping.emplace_back(std::min(i, j), std::max(i, j));
      });
  std::sort(overlapping.begin(), overlapping.end());
  for (const auto& [i, j] : overlapping)
    if (disjoint_triangles_intersect(x, triangles[std::size_t(i)], triangles[std::size_t(j)], same)) return {true, i, j};
  return {false, -1, -1};
}

/// first_intersection() by testing all pairs one by one (the reference the sweep is checked against).
template <class S>
MeshIntersection first_intersection_all_pairs(const Matrix3X<S>& x, const std::vector<std::array<int, 3>>& triangles) {
  const int count = int(triangles.size());
  std::vector<check_detail::Box3<S>> boxes;
  for (const auto& t : triangles) boxes.push_back(check_detail::box_of<S>(x.col(t[0]), x.col(t[1]), x.col(t[2])));
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j)
      if (check_detail::boxes_overlap(boxes[std::size_t(i)], boxes[std::size_t(j)]) &&
          disjoint_triangles_intersect(x, triangles[std::size_t(i)], triangles[std::size_t(j)]))
        return {true, i, j};
  return {false, -1, -1};
}

namespace check_detail {

/// The edges of the triangles, each once, as (smaller, larger) node ids.
inline std::vector<std::array<int, 2>> edges_of(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<std::array<int, 2>> edges;
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) edges.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

/// Squared distance of vertex v to triangle t, if t does not contain v and their boxes are not
/// farther apart than sqrt(best); best otherwise.
template <class S>
S vertex_triangle(const Matrix3X<S>& x, Index v, const std::array<int, 3>& t, const Box3<S>& t_box, S best) {
  if (t[0] == v || t[1] == v || t[2] == v) return best;
  const Vec3<S> p = x.col(v);
  if (box_distance_squared(Box3<S>{p, p}, t_box) > best) return best;
  return std::min(best, closest_point_on_triangle<S>(p, x.col(t[0]), x.col(t[1]), x.col(t[2])).distance_squared);
}

/// Squared distance of edges e and f, if they share no vertex and their boxes are not farther
/// apart than sqrt(best); best otherwise.
template <class S>
S edge_edge(const Matrix3X<S>& x, const std::array<int, 2>& e, const std::array<int, 2>& f, const Box3<S>& e_box,
            const Box3<S>& f_box, S best) {
  if (e[0] == f[0] || e[0] == f[1] || e[1] == f[0] || e[1] == f[1]) return best;
  if (box_distance_squared(e_box, f_box) > best) return best;
  return std::min(best,
                  closest_points_on_segments<S>(x.col(e[0]), x.col(e[1]), x.col(f[0]), x.col(f[1])).distance_squared);
}

/// A little more than sqrt(best_squared): the sweeps' reach, so that no rounding of theirs skips a
/// pair the box test would keep.
template <class S>
S generous_reach(S best_squared) {
  return std::sqrt(best_squared) * S(1.001);
}

}  // namespace check_detail

/// The smallest distance between a vertex and a triangle that does not contain it, or between two
/// edges that share no vertex (infinity if there is no such pair). Every vertex of x counts; the
/// edges are those of the triangles. Pairs whose boxes are farther apart than the smallest distance
/// so far are skipped, along x by sweeps.
template <class S>
S min_nonadjacent_distance(const Matrix3X<S>& x, const std::vector<std::array<int, 3>>& triangles) {
  using check_detail::Box3;
  S best = std::numeric_limits<S>::infinity();  // squared
  // Vertex-triangle: for each triangle, the vertices whose x is within reach of its box's.
  std::vector<Index> by_x(std::size_t(x.cols()));
  std::iota(by_x.begin(), by_x.end(), Index(0));
  std::sort(by_x.begin(), by_x.end(), [&](Index a, Index b) { return x(0, a) < x(0, b); });
  for (const auto& t : triangles) {
    const Box3<S> box = check_detail::box_of<S>(x.col(t[0]), x.col(t[1]), x.col(t[2]));
    const S reach = check_detail::generous_reach(best);
    auto v = std::lower_bound(by_x.begin(), by_x.end(), box.low.x() - reach,
                              [&](Index a, S value) { return x(0, a) < value; });
    for (; v != by_x.end() && x(0, *v) <= box.high.x() + reach; ++v)
      best = check_detail::vertex_triangle(x, *v, t, box, best);
  }
  // Edge-edge.
  const std::vector<std::array<int, 2>> edges = check_detail::edges_of(triangles);
  std::vector<Box3<S>> edge_boxes;
  for (const auto& e : edges) edge_boxes.push_back(check_detail::box_of<S>(x.col(e[0]), x.col(e[1])));
  check_detail::sweep_along_x(
      edge_boxes, [&] { return check_detail::generous_reach(best); },
      [&](int a, int b) {  // in the order of the list, as the closest points' rounding depends on it
        const std::size_t i = std::size_t(std::min(a, b)), j = std::size_t(std::max(a, b));
        best = check_detail::edge_edge(x, edges[i], edges[j], edge_boxes[i], edge_boxes[j], best);
      });
  return std::sqrt(best);
}

/// min_nonadjacent_distance() by testing all pairs one by one (the reference the sweeps are
/// checked against).
template <class S>
S min_nonadjacent_distance_all_pairs(const Matrix3X<S>& x, const std::vector<std::array<int, 3>>& triangles) {
  using check_detail::Box3;
  S best = std::numeric_limits<S>::infinity();  // squared
  for (Index v = 0; v < x.cols(); ++v)
    for (const auto& t : triangles)
      best = check_detail::vertex_triangle(x, v, t, check_detail::box_of<S>(x.col(t[0]), x.col(t[1]), x.col(t[2])), best);
  const std::vector<std::array<int, 2>> edges = check_detail::edges_of(triangles);
  for (std::size_t i = 0; i < edges.size(); ++i)
    for (std::size_t j = i + 1; j < edges.size(); ++j) {
      const auto& e = edges[i];
      const auto& f = edges[j];
      best = check_detail::edge_edge(x, e, f, check_detail::box_of<S>(x.col(e[0]), x.col(e[1])),
                                     check_detail::box_of<S>(x.col(f[0]), x.col(f[1])), best);
    }
  return std::sqrt(best);
}

}  // namespace drape::test
