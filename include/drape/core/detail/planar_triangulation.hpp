#pragma once
/// \file planar_triangulation.hpp
/// Part of core/mesh_generators.hpp: triangulations of points in the plane for the mesh generators.
/// Points are inserted one at a time into a convex start polygon and the mesh is kept Delaunay by
/// edge flips (Lawson's algorithm; de Berg et al., Computational Geometry, chapter 9). The
/// structure only ever changes by splits and flips of convex quadrilaterals, so it stays a valid
/// triangulation whatever the rounding; near-ties of the circle test are left unflipped, where
/// either diagonal is as good. Everything is in double whatever the mesh's Scalar, so a float and a
/// double mesh share their connectivity.
///
/// Constrained edges (a polygon's sides, garment/panel_mesher.hpp) are made edges by flipping the
/// edges that cross them (Sloan, "A fast algorithm for generating constrained Delaunay
/// triangulations", 1993) and never flipped afterwards, so flipping to Delaunay gives the
/// constrained Delaunay triangulation; the triangles they enclose are kept by parity.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numeric>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace drape::detail {

using Point2 = Eigen::Vector2d;

/// Twice the signed area of (a, b, c): > 0 counter-clockwise.
inline double orientation(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

/// Whether the closed segments (a, b) and (c, d) share a point.
inline bool segments_meet(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double d1 = orientation(c, d, a), d2 = orientation(c, d, b), d3 = orientation(a, b, c),
               d4 = orientation(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  const auto within = [](const Point2& p, const Point2& q, const Point2& r) {  // r on the line pq: inside its box?
    return r.x() >= std::min(p.x(), q.x()) && r.x() <= std::max(p.x(), q.x()) && r.y() >= std::min(p.y(), q.y()) &&
           r.y() <= std::max(p.y(), q.y());
  };
  return (d1 == 0 && within(c, d, a)) || (d2 == 0 && within(c, d, b)) || (d3 == 0 && within(a, b, c)) ||
         (d4 == 0 && within(a, b, d));
}

/// Whether d lies clearly inside the circle through the counter-clockwise a, b, c: the determinant
/// exceeds its possible rounding error many times over (a near-tie counts as outside).
inline bool inside_circumcircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const double adx = a.x() - d.x(), ady = a.y() - d.y(), bdx = b.x() - d.x(), bdy = b.y() - d.y();
  const double cdx = c.x() - d.x(), cdy = c.y() - d.y();
  const double alift = adx * adx + ady * ady, blift = bdx * bdx + bdy * bdy, clift = cdx * cdx + cdy * cdy;
  const double det =
      alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) + clift * (adx * bdy - bdx * ady);
  const double permanent = alift * (std::abs(bdx * cdy) + std::abs(cdx * bdy)) +
                           blift * (std::abs(cdx * ady) + std::abs(adx * cdy)) +
                           clift * (std::abs(adx * bdy) + std::abs(bdx * ady));
  return det > 1e-10 * permanent;
}

/// Index along the Hilbert curve of cell (x, y) of an n x n grid, n a power of two (the curve
/// visits neighbouring cells one after another, so points sorted by it are near in memory).
inline std::uint64_t hilbert_index(std::uint32_t n, std::uint32_t x, std::uint32_t y) {
  std::uint64_t d = 0;
  for (std::uint32_t s = n / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (x & s) > 0 ? 1u : 0u, ry = (y & s) > 0 ? 1u : 0u;
    d += std::uint64_t(s) * s * ((3u * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = n - 1 - x;
        y = n - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

/// The centre of the circle through a, b and c (not collinear).
inline Point2 circumcentre(const Point2& a, const Point2& b, const Point2& c) {
  const Point2 ab = b - a, ac = c - a;
  const double twice_area = orientation(a, b, c);
  return a + Point2(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
                    ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm()) /
                 (2 * twice_area);
}

/// How smoothing may move a vertex: anywhere, not at all, or along a side parallel to x or to y.
enum class VertexFreedom : char { Free, Fixed, AlongX, AlongY };

/// The sine of the smallest angle of (a, b, c), or -1 unless it is counter-clockwise.
inline double sine_of_smallest_angle(const Point2& a, const Point2& b, const Point2& c);

/// A triangulation of `points`: counter-clockwise triangles, and per triangle the triangle across
/// each edge k = (t[k], t[k + 1]), or -1 on the boundary.
class PlanarTriangulation {
 public:
  std::vector<Point2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 3>> neighbours;

  explicit PlanarTriangulation(std::vector<Point2> vertices) : points(std::move(vertices)) {}

  /// Starts with the convex counter-clockwise quadrilateral (a, b, c, d): triangles (a, b, c), (a, c, d).
  void start_with_quad(int a, int b, int c, int d);
  /// Adopts counter-clockwise triangles that form a manifold mesh and links their neighbours.
  void adopt(std::vector<std::array<int, 3>> faces);
  /// Inserts point v (inside or on the boundary of the triangulated region) and restores the
  /// Delaunay property around it.
  void insert(int v);
  /// As insert(), v known to lie in (or on an edge of) triangle t.
  void insert_into(int t, int v);
  /// The triangle holding q, by a visibility walk from triangle t; -1 if the walk leaves the
  /// triangulated region (q outside it, or hidden behind its boundary).
  int walk(int t, const Point2& q);
  /// Flips every interior edge whose opposite vertex lies inside its triangle's circumcircle.
  void flip_to_delaunay();
  /// Keeps the triangles with keep[t] != 0; edges towards the others become boundary.
  void keep_triangles(const std::vector<char>& keep);
  /// Makes each segment (a, b) an edge and constrains it: the edges crossing it are flipped away
  /// (in exact arithmetic this always ends, Sloan 1993) and no flip removes it afterwards. The
  /// segments are vertices of the triangulation inside its boundary; they cross neither each other
  /// nor any vertex. \throws std::logic_error if round-off defeats the recovery.
  void constrain(const std::vector<std::array<int, 2>>& segments);
  /// Whether the edge {a, b} is constrained.
  bool constrained(int a, int b) const;
  /// Per triangle, whether an odd number of constrained edges separate it from the triangulation's
  /// boundary: for constrained edges that form a closed polygon, the triangles inside it.
  std::vector<char> enclosed_by_constraints() const;
  /// Delaunay refinement without splitting constrained edges (after Ruppert 1995; Shewchuk,
  /// "Delaunay refinement algorithms for triangular mesh generation", 2002): while a triangle's
  /// smallest angle is below `min_angle_degrees`, inserts its circumcentre if a walk from the
  /// triangle reaches it inside the triangulated region and `accept(t, centre)` agrees; at most
  /// `max_new_vertices` new vertices (appended to `points`). The circumcentre is farther from every
  /// vertex than the triangle's shortest edge (for angles below 30 degrees), so no shorter edge is
  /// made. Returns the number inserted.
  template <class Accept>
  int refine(double min_angle_degrees, int max_new_vertices, Accept&& accept);
  /// `passes` times: moves every vertex that is free to move to where the smallest angle of its
  /// triangles is largest among a few smoothing targets (and, where that angle stays below 32
  /// degrees, a compass search), then flips to Delaunay. A vertex only moves to improve its worst
  /// angle, so no triangle turns over and the smallest angle around it never shrinks.
  void smooth(const std::vector<VertexFreedom>& freedom, int passes);

 private:
  int locate(const Point2& q);
  int outside_edge(int t, const Point2& q) const;
  int edge_towards(int t, int other) const;
  void relink(int t, int old_neighbour, int new_neighbour);
  void split_triangle(int t, int v, std::vector<std::array<int, 2>>& pending);
  void split_edge(int t, int k, int v, std::vector<std::array<int, 2>>& pending);
  void flip(int t, int k);
  bool flip_if_illegal(int t, int k, std::vector<std::array<int, 2>>& pending);
  void legalize(std::vector<std::array<int, 2>>& pending);
  void recover_edge(int a, int b, std::vector<int>& triangle_of);
  int triangle_with_edge(int u, int v, std::vector<int>& triangle_of) const;
  static std::uint64_t edge_key(int a, int b) {
    return (std::uint64_t(std::uint32_t(std::max(a, b))) << 32) | std::uint32_t(std::min(a, b));
  }

  int m_last = 0;       // where the next walk starts: the last triangle made
  unsigned m_turn = 0;  // which edge the walk tries first, turned each step so it cannot cycle
  std::unordered_set<std::uint64_t> m_constrained;  // edge_key of each constrained edge
};

// ---------------------------------------------------------------------------------------------

inline void PlanarTriangulation::start_with_quad(int a, int b, int c, int d) {
  triangles = {{a, b, c}, {a, c, d}};
  neighbours = {{-1, -1, 1}, {0, -1, -1}};
  m_last = 0;
}

inline void PlanarTriangulation::adopt(std::vector<std::array<int, 3>> faces) {
  triangles = std::move(faces);
  neighbours.assign(triangles.size(), {-1, -1, -1});
  std::vector<std::vector<std::array<int, 3>>> around(points.size());  // per lower vertex: (upper, t, k)
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles[t][static_cast<std::size_t>(k)], b = triangles[t][static_cast<std::size_t>((k + 1) % 3)];
      auto& list = around[static_cast<std::size_t>(std::min(a, b))];
      const auto match =
          std::find_if(list.begin(), list.end(), [&](const std::array<int, 3>& e) { return e[0] == std::max(a, b); });
      if (match == list.end()) {
        list.push_back({std::max(a, b), static_cast<int>(t), k});
      } else {
        neighbours[t][static_cast<std::size_t>(k)] = (*match)[1];
        neighbours[static_cast<std::size_t>((*match)[1])][static_cast<std::size_t>((*match)[2])] = static_cast<int>(t);
      }
    }
  m_last = 0;
}

inline int PlanarTriangulation::edge_towards(int t, int other) const {
  for (int k = 0; k < 3; ++k)
    if (neighbours[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)] == other) return k;
  throw std::logic_error("drape: planar triangulation: neighbours out of step");
}

inline void PlanarTriangulation::relink(int t, int old_neighbour, int new_neighbour) {
  if (t < 0) return;
  neighbours[static_cast<std::size_t>(t)][static_cast<std::size_t>(edge_towards(t, old_neighbour))] = new_neighbour;
}

inline int PlanarTriangulation::outside_edge(int t, const Point2& q) const {
  for (unsigned step = 0; step < 3; ++step) {
    const int k = static_cast<int>((step + m_turn) % 3);
    const std::array<int, 3>& f = triangles[static_cast<std::size_t>(t)];
    const Point2 &a = points[static_cast<std::size_t>(f[static_cast<std::size_t>(k)])],
                 &b = points[static_cast<std::size_t>(f[static_cast<std::size_t>((k + 1) % 3)])];
    if (orientation(a, b, q) < -1e-12 * (b - a).squaredNorm()) return k;
  }
  return -1;
}

inline int PlanarTriangulation::walk(int t, const Point2& q) {
  for (std::size_t step = 0; step < 4 * triangles.size() + 16 && t >= 0; ++step, ++m_turn) {
    const int k = outside_edge(t, q);
    if (k < 0) return t;
    t = neighbours[static_cast<std::size_t>(t)][static_cast<std::size_t>(k)];
  }
  return -1;
}

inline int PlanarTriangulation::locate(const Point2& q) {
  // Visibility walk from the last triangle made; points come in a space-filling order, so it is short.
  const int found = walk(m_last, q);
  if (found >= 0) return found;
  for (std::size_t s = 0; s < triangles.size(); ++s)
    if (outside_edge(static_cast<int>(s), q) < 0) return static_cast<int>(s);
  throw std::logic_error("drape: planar triangulation: a point outside the start polygon");
}

inline void PlanarTriangulation::insert(int v) { insert_into(locate(points[static_cast<std::size_t>(v)]), v); }

inline void PlanarTriangulation::insert_into(int t, int v) {
  const Point2& q = points[static_cast<std::size_t>(v)];
  std::vector<std::array<int, 2>> pending;
  for (int k = 0; k < 3; ++k) {
    const std::array<int, 3>& f = triangles[static_cast<std::size_t>(t)];
    const Point2 &a = points[static_cast<std::size_t>(f[static_cast<std::size_t>(k)])],
                 &b = points[static_cast<std::size_t>(f[static_cast<std::size_t>((k + 1) % 3)])];
    if (std::abs(orientation(a, b, q)) <= 1e-12 * (b - a).squaredNorm()) {
      split_edge(t, k, v, pending);
      legalize(pending);
      return;
    }
  }
  split_triangle(t, v, pending);
  legalize(pending);
}

inline void PlanarTriangulation::split_triangle(int t, int v, std::vector<std::array<int, 2>>& pending) {
  const std::array<int, 3> f = triangles[static_cast<std::size_t>(t)], n = neighbours[static_cast<std::size_t>(t)];
  const int t1 = static_cast<int>(triangles.size()), t2 = t1 + 1;
  triangles[static_cast<std::size_t>(t)] = {f[0], f[1], v};
  neighbours[static_cast<std::size_t>(t)] = {n[0], t1, t2};
  triangles.push_back({f[1], f[2], v});
  neighbours.push_back({n[1], t2, t});
  triangles.push_back({f[2], f[0], v});
  neighbours.push_back({n[2], t, t1});
  relink(n[1], t, t1);
  relink(n[2], t, t2);
  pending.push_back({t, 0});
  pending.push_back({t1, 0});
  pending.push_back({t2, 0});
  m_last = t;
}

inline void PlanarTriangulation::split_edge(int t, int k, int v, std::vector<std::array<int, 2>>& pending) {
  const std::size_t ts = static_cast<std::size_t>(t);
  const int a = triangles[ts][static_cast<std::size_t>(k)], b = triangles[ts][static_cast<std::size_t>((k + 1) % 3)],
            c = triangles[ts][static_cast<std::size_t>((k + 2) % 3)];
  const int u = neighbours[ts][static_cast<std::size_t>(k)],
            t_bc = neighbours[ts][static_cast<std::size_t>((k + 1) % 3)],
            t_ca = neighbours[ts][static_cast<std::size_t>((k + 2) % 3)];
  const int t1 = static_cast<int>(triangles.size());
  const int u1 = u >= 0 ? t1 + 1 : -1;
  triangles[ts] = {a, v, c};
  neighbours[ts] = {u, t1, t_ca};
  triangles.push_back({v, b, c});
  neighbours.push_back({u1, t_bc, t});
  relink(t_bc, t, t1);
  pending.push_back({t, 2});
  pending.push_back({t1, 1});
  if (u >= 0) {
    // u = (b, a, d) becomes (v, a, d) and (b, v, d).
    const std::size_t us = static_cast<std::size_t>(u);
    const int ku = edge_towards(u, t);
    const int d = triangles[us][static_cast<std::size_t>((ku + 2) % 3)];
    const int u_ad = neighbours[us][static_cast<std::size_t>((ku + 1) % 3)],
              u_db = neighbours[us][static_cast<std::size_t>((ku + 2) % 3)];
    triangles[us] = {v, a, d};
    neighbours[us] = {t, u_ad, u1};
    triangles.push_back({b, v, d});
    neighbours.push_back({t1, u, u_db});
    relink(u_db, u, u1);
    pending.push_back({u, 1});
    pending.push_back({u1, 2});
  }
  m_last = t;
}

inline void PlanarTriangulation::flip(int t, int k) {
  // t = (a, b, c) and n = (b, a, d) share edge (a, b); the flip makes (a, d, c) and (d, b, c).
  const std::size_t ts = static_cast<std::size_t>(t);
  const int n = neighbours[ts][static_cast<std::size_t>(k)];
  const std::size_t ns = static_cast<std::size_t>(n);
  const int kn = edge_towards(n, t);
  const int a = triangles[ts][static_cast<std::size_t>(k)], b = triangles[ts][static_cast<std::size_t>((k + 1) % 3)],
            c = triangles[ts][static_cast<std::size_t>((k + 2) % 3)],
            d = triangles[ns][static_cast<std::size_t>((kn + 2) % 3)];
  const int t_bc = neighbours[ts][static_cast<std::size_t>((k + 1) % 3)],
            t_ca = neighbours[ts][static_cast<std::size_t>((k + 2) % 3)];
  const int n_ad = neighbours[ns][static_cast<std::size_t>((kn + 1) % 3)],
            n_db = neighbours[ns][static_cast<std::size_t>((kn + 2) % 3)];
  triangles[ts] = {a, d, c};
  neighbours[ts] = {n_ad, n, t_ca};
  triangles[ns] = {d, b, c};
  neighbours[ns] = {n_db, t_bc, t};
  relink(n_ad, n, t);
  relink(t_bc, t, n);
}

inline bool PlanarTriangulation::flip_if_illegal(int t, int k, std::vector<std::array<int, 2>>& pending) {
  const std::size_t ts = static_cast<std::size_t>(t);
  const int n = neighbours[ts][static_cast<std::size_t>(k)];
  if (n < 0) return false;
  const std::size_t ns = static_cast<std::size_t>(n);
  const int kn = edge_towards(n, t);
  // t = (a, b, c) and n = (b, a, d) share edge (a, b); the flip makes (a, d, c) and (d, b, c).
  const int a = triangles[ts][static_cast<std::size_t>(k)], b = triangles[ts][static_cast<std::size_t>((k + 1) % 3)],
            c = triangles[ts][static_cast<std::size_t>((k + 2) % 3)],
            d = triangles[ns][static_cast<std::size_t>((kn + 2) % 3)];
  const Point2 &pa = points[static_cast<std::size_t>(a)], &pb = points[static_cast<std::size_t>(b)],
               &pc = points[static_cast<std::size_t>(c)], &pd = points[static_cast<std::size_t>(d)];
  if (!inside_circumcircle(pa, pb, pc, pd)) return false;
  if (!m_constrained.empty() && constrained(a, b)) return false;
  if (!(orientation(pa, pd, pc) > 0 && orientation(pd, pb, pc) > 0)) return false;  // not convex
  flip(t, k);
  // The four outer edges may have become illegal; the new diagonal is legal.
  pending.push_back({t, 0});
  pending.push_back({t, 2});
  pending.push_back({n, 0});
  pending.push_back({n, 1});
  return true;
}

inline void PlanarTriangulation::legalize(std::vector<std::array<int, 2>>& pending) {
  // Each flip strictly improves the triangulation (the smallest angles grow), so this ends; the cap
  // only guards against a rounding pathology.
  std::size_t flips = 0;
  const std::size_t cap = 64 * triangles.size() + 1024;
  while (!pending.empty() && flips < cap) {
    const std::array<int, 2> e = pending.back();
    pending.pop_back();
    if (flip_if_illegal(e[0], e[1], pending)) ++flips;
  }
  pending.clear();
}

inline void PlanarTriangulation::flip_to_delaunay() {
  std::vector<std::array<int, 2>> pending;
  pending.reserve(3 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (neighbours[t][static_cast<std::size_t>(k)] > static_cast<int>(t)) pending.push_back({static_cast<int>(t), k});
  legalize(pending);
}

inline void PlanarTriangulation::keep_triangles(const std::vector<char>& keep) {
  std::vector<int> new_id(triangles.size(), -1);
  int kept = 0;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (keep[t]) new_id[t] = kept++;
  std::vector<std::array<int, 3>> faces, links;
  faces.reserve(static_cast<std::size_t>(kept));
  links.reserve(static_cast<std::size_t>(kept));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    if (!keep[t]) continue;
    faces.push_back(triangles[t]);
    std::array<int, 3> n = neighbours[t];
    for (int& m : n) m = m < 0 ? -1 : new_id[static_cast<std::size_t>(m)];
    links.push_back(n);
  }
  triangles = std::move(faces);
  neighbours = std::move(links);
  m_last = 0;
}

inline bool PlanarTriangulation::constrained(int a, int b) const { return m_constrained.count(edge_key(a, b)) != 0; }

inline int PlanarTriangulation::triangle_with_edge(int u, int v, std::vector<int>& triangle_of) const {
  // Counter-clockwise around u from the triangle last seen there (u is inside the boundary: its
  // triangles close a ring) to the one that runs the edge u -> v.
  int t = triangle_of[static_cast<std::size_t>(u)];
  for (std::size_t step = 0; step < triangles.size() + 1 && t >= 0; ++step) {
    const std::array<int, 3>& f = triangles[static_cast<std::size_t>(t)];
    const int i = f[0] == u ? 0 : f[1] == u ? 1 : 2;
    if (f[static_cast<std::size_t>((i + 1) % 3)] == v) {
      triangle_of[static_cast<std::size_t>(u)] = t;
      return t;
    }
    t = neighbours[static_cast<std::size_t>(t)][static_cast<std::size_t>((i + 2) % 3)];
  }
  return -1;
}

inline void PlanarTriangulation::recover_edge(int a, int b, std::vector<int>& triangle_of) {
  const Point2 &pa = points[static_cast<std::size_t>(a)], &pb = points[static_cast<std::size_t>(b)];
  const auto side = [&](int v) { return orientation(pa, pb, points[static_cast<std::size_t>(v)]); };
  const auto fail = [&](const char* why) {
    throw std::logic_error("drape: planar triangulation: segment (" + std::to_string(a) + ", " + std::to_string(b) +
                           ") " + why);
  };
  // The triangle around a whose corner holds the segment's direction, then the edges the segment
  // crosses in order, each as (left, right) of a -> b.
  int t = triangle_of[static_cast<std::size_t>(a)];
  int left = -1, right = -1;
  for (std::size_t step = 0; step < triangles.size() + 1; ++step) {
    const std::array<int, 3>& f = triangles[static_cast<std::size_t>(t)];
    const int i = f[0] == a ? 0 : f[1] == a ? 1 : 2;
    const int u = f[static_cast<std::size_t>((i + 1) % 3)], w = f[static_cast<std::size_t>((i + 2) % 3)];
    if (u == b || w == b) return;  // already an edge
    if (side(u) < 0 && side(w) > 0) {
      right = u;
      left = w;
      break;
    }
    t = neighbours[static_cast<std::size_t>(t)][static_cast<std::size_t>((i + 2) % 3)];
    if (t < 0) fail("starts on the boundary");
  }
  if (left < 0) fail("leaves its first vertex through no triangle (it passes through a vertex)");
  std::vector<std::array<int, 2>> crossing;
  for (std::size_t step = 0; step < triangles.size() + 1; ++step) {
    crossing.push_back({left, right});
    const std::size_t ts = static_cast<std::size_t>(t);
    const int k = triangles[ts][0] == right ? 0 : triangles[ts][1] == right ? 1 : 2;  // edge (right, left)
    const int n = neighbours[ts][static_cast<std::size_t>(k)];
    if (n < 0) fail("leaves the triangulated region");
    const int kn = edge_towards(n, t);
    const int d = triangles[static_cast<std::size_t>(n)][static_cast<std::size_t>((kn + 2) % 3)];
    if (d == b) break;
    const double s = side(d);
    if (s == 0) fail("passes through a vertex");
    (s > 0 ? left : right) = d;
    t = n;
  }
  // Flip the crossing edges away: a crossing edge whose quadrilateral is convex is flipped, and
  // its new diagonal queued again if it still crosses; one in a non-convex quadrilateral waits.
  std::deque<std::array<int, 2>> queue(crossing.begin(), crossing.end());
  const std::size_t cap = 64 * crossing.size() * crossing.size() + 64;
  for (std::size_t step = 0; !queue.empty(); ++step) {
    if (step > cap) fail("is not recovered by flips (round-off)");
    const std::array<int, 2> e = queue.front();
    queue.pop_front();
    const int tt = triangle_with_edge(e[1], e[0], triangle_of);  // right -> left: the triangle on a's side
    if (tt < 0) fail("crosses an edge no triangle holds");
    const std::size_t ts = static_cast<std::size_t>(tt);
    const int k = triangles[ts][0] == e[1] ? 0 : triangles[ts][1] == e[1] ? 1 : 2;
    const int n = neighbours[ts][static_cast<std::size_t>(k)];
    const int kn = edge_towards(n, tt);
    const int c = triangles[ts][static_cast<std::size_t>((k + 2) % 3)],
              d = triangles[static_cast<std::size_t>(n)][static_cast<std::size_t>((kn + 2) % 3)];
    const Point2 &pu = points[static_cast<std::size_t>(e[1])], &pv = points[static_cast<std::size_t>(e[0])],
                 &pc = points[static_cast<std::size_t>(c)], &pd = points[static_cast<std::size_t>(d)];
    if (!(orientation(pu, pd, pc) > 0 && orientation(pd, pv, pc) > 0)) {
      queue.push_back(e);  // not convex yet
      continue;
    }
    if (constrained(e[0], e[1])) fail("crosses a constrained edge");
    flip(tt, k);  // (u, v, c), (v, u, d) -> (u, d, c), (d, v, c)
    triangle_of[static_cast<std::size_t>(e[1])] = tt;
    triangle_of[static_cast<std::size_t>(e[0])] = n;
    const double sc = side(c), sd = side(d);
    const bool still_crosses = c != a && c != b && d != a && d != b && ((sc > 0 && sd < 0) || (sc < 0 && sd > 0)) &&
                               orientation(pc, pd, pa) * orientation(pc, pd, pb) < 0;
    if (still_crosses) queue.push_back(sc > 0 ? std::array<int, 2>{c, d} : std::array<int, 2>{d, c});
  }
}

inline void PlanarTriangulation::constrain(const std::vector<std::array<int, 2>>& segments) {
  std::vector<int> triangle_of(points.size(), -1);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int v : triangles[t]) triangle_of[static_cast<std::size_t>(v)] = static_cast<int>(t);
  for (const std::array<int, 2>& s : segments) {
    if (triangle_of[static_cast<std::size_t>(s[0])] < 0 || triangle_of[static_cast<std::size_t>(s[1])] < 0)
      throw std::logic_error("drape: planar triangulation: a constrained segment's vertex is in no triangle");
    recover_edge(s[0], s[1], triangle_of);
    m_constrained.insert(edge_key(s[0], s[1]));
  }
}

inline std::vector<char> PlanarTriangulation::enclosed_by_constraints() const {
  // Breadth first from the boundary triangles: crossing a constrained edge costs one, any other
  // edge nothing (a 0-1 search), so each triangle gets the fewest constrained edges between it and
  // the boundary.
  const int unseen = -1;
  std::vector<int> depth(triangles.size(), unseen);
  std::deque<int> queue;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int n : neighbours[t])
      if (n < 0 && depth[t] == unseen) {
        depth[t] = 0;
        queue.push_back(static_cast<int>(t));
      }
  std::vector<char> settled(triangles.size(), 0);
  while (!queue.empty()) {
    const int t = queue.front();
    queue.pop_front();
    const std::size_t ts = static_cast<std::size_t>(t);
    if (settled[ts]) continue;
    settled[ts] = 1;
    for (int k = 0; k < 3; ++k) {
      const int n = neighbours[ts][static_cast<std::size_t>(k)];
      if (n < 0 || settled[static_cast<std::size_t>(n)]) continue;
      const bool wall = constrained(triangles[ts][static_cast<std::size_t>(k)],
                                    triangles[ts][static_cast<std::size_t>((k + 1) % 3)]);
      const int d = depth[ts] + (wall ? 1 : 0);
      int& dn = depth[static_cast<std::size_t>(n)];
      if (dn != unseen && dn <= d) continue;
      dn = d;
      if (wall) {
        queue.push_back(n);
      } else {
        queue.push_front(n);
      }
    }
  }
  std::vector<char> inside(triangles.size(), 0);
  for (std::size_t t = 0; t < triangles.size(); ++t) inside[t] = depth[t] % 2 == 1 ? 1 : 0;
  return inside;
}

inline double sine_of_smallest_angle(const Point2& a, const Point2& b, const Point2& c) {
  const double twice_area = orientation(a, b, c);
  if (!(twice_area > 0)) return -1;
  const double ab = (b - a).norm(), bc = (c - b).norm(), ca = (a - c).norm();
  return twice_area * std::min({ab, bc, ca}) / (ab * bc * ca);  // the smallest angle faces the shortest edge
}

template <class Accept>
int PlanarTriangulation::refine(double min_angle_degrees, int max_new_vertices, Accept&& accept) {
  const double bound = std::sin(min_angle_degrees * 3.14159265358979323846 / 180);
  int added = 0;
  // Sweeps over the triangles, those made by the sweep's own insertions included, until one
  // inserts nothing.
  for (bool again = true; again && added < max_new_vertices;) {
    again = false;
    for (std::size_t t = 0; t < triangles.size() && added < max_new_vertices; ++t) {
      const std::array<int, 3>& f = triangles[t];
      const Point2 &a = points[static_cast<std::size_t>(f[0])], &b = points[static_cast<std::size_t>(f[1])],
                   &c = points[static_cast<std::size_t>(f[2])];
      if (sine_of_smallest_angle(a, b, c) >= bound) continue;
      const Point2 centre = circumcentre(a, b, c);
      const int holder = walk(static_cast<int>(t), centre);
      if (holder < 0 || !accept(static_cast<int>(t), centre)) continue;
      points.push_back(centre);
      insert_into(holder, static_cast<int>(points.size()) - 1);
      ++added;
      again = true;
    }
  }
  return added;
}

inline void PlanarTriangulation::smooth(const std::vector<VertexFreedom>& freedom, int passes) {
  const std::size_t n = points.size();
  const double good_enough = std::sin(32 * 3.14159265358979323846 / 180);
  std::vector<int> start, incident, ring;
  for (int pass = 0; pass < passes; ++pass) {
    // The triangles around every vertex, in compressed rows.
    start.assign(n + 1, 0);
    for (const std::array<int, 3>& f : triangles)
      for (int v : f) ++start[static_cast<std::size_t>(v) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    incident.resize(static_cast<std::size_t>(start[n]));
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int v : triangles[t])
        incident[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<int>(t);

    for (std::size_t v = 0; v < n; ++v) {
      if (freedom[v] == VertexFreedom::Fixed || start[v] == start[v + 1]) continue;
      const auto around = [&](auto&& visit) {
        for (int s = start[v]; s < start[v + 1]; ++s) {
          const std::array<int, 3>& f = triangles[static_cast<std::size_t>(incident[static_cast<std::size_t>(s)])];
          visit(points[static_cast<std::size_t>(f[0])], points[static_cast<std::size_t>(f[1])],
                points[static_cast<std::size_t>(f[2])], f);
        }
      };
      const auto worst_at = [&](const Point2& where) {
        const Point2 was = points[v];
        points[v] = where;
        double worst = 1;
        around([&](const Point2& a, const Point2& b, const Point2& c, const std::array<int, 3>&) {
          worst = std::min(worst, sine_of_smallest_angle(a, b, c));
        });
        points[v] = was;
        return worst;
      };
      const auto constrained = [&](Point2 where) {
        if (freedom[v] == VertexFreedom::AlongX) where.y() = points[v].y();
        if (freedom[v] == VertexFreedom::AlongY) where.x() = points[v].x();
        return where;
      };
      // Candidates: the mean of the neighbours (Laplacian), the area-weighted mean of the
      // circumcentres (optimal Delaunay triangulation smoothing, Chen and Xu 2004), and halfway
      // points; the one whose worst angle is largest wins if it beats staying.
      ring.clear();
      Point2 circumcentres = Point2::Zero();
      double area = 0;
      around([&](const Point2& a, const Point2& b, const Point2& c, const std::array<int, 3>& f) {
        for (int w : f)
          if (w != static_cast<int>(v)) ring.push_back(w);
        const double twice_area = orientation(a, b, c);
        circumcentres += twice_area * circumcentre(a, b, c);
        area += twice_area;
      });
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      Point2 laplacian = Point2::Zero();
      for (int w : ring) laplacian += points[static_cast<std::size_t>(w)];
      laplacian /= static_cast<double>(ring.size());
      const Point2 here = points[v], odt = circumcentres / area;
      Point2 best_point = here;
      double best = worst_at(here);
      for (const Point2& candidate : {odt, laplacian, Point2(0.5 * (here + odt)), Point2(0.5 * (here + laplacian)),
                                      Point2(0.5 * (odt + laplacian))}) {
        const Point2 where = constrained(candidate);
        const double worst = worst_at(where);
        if (worst > best) {
          best = worst;
          best_point = where;
        }
      }
      if (best < good_enough) {
        // Still a thin triangle here: a compass search for the position of the largest worst angle.
        double spacing = 0;
        for (int w : ring) spacing += (points[static_cast<std::size_t>(w)] - best_point).norm();
        spacing /= static_cast<double>(ring.size());
        for (double step = 0.1 * spacing; step > 0.005 * spacing; step *= 0.5) {
          for (bool improved = true; improved;) {
            improved = false;
            for (const Point2& move : {Point2(step, 0), Point2(-step, 0), Point2(0, step), Point2(0, -step)}) {
              const Point2 where = constrained(best_point + move);
              const double worst = worst_at(where);
              if (worst > best * (1 + 1e-12)) {
                best = worst;
                best_point = where;
                improved = true;
              }
            }
          }
        }
      }
      points[v] = best_point;
    }
    flip_to_delaunay();
  }
}

}  // namespace drape::detail
