#pragma once
/// \file mesh_distance.hpp
/// The signed distance from a point to a closed triangle mesh, with its closest point and its
/// outward normal: what a collider made of a mesh (contact/collider.hpp) answers its queries with.
///
/// - Closest point: a bounding volume hierarchy over the triangles (bounding_volume_hierarchy.hpp)
///   searched branch and bound, nearer box first; the point-triangle distance of
///   primitive_distance.hpp. O(log n) boxes per query on a mesh of n triangles.
/// - Sign: the angle-weighted pseudo-normal of the closest feature (Baerentzen & Aanaes 2005): the
///   face's normal if the closest point is inside a face, the sum of the two face normals on an
///   edge, the face normals weighted by their angles at a vertex. On a closed, consistently
///   oriented mesh (every edge in two faces that run it opposite ways) (p - c) . n >= 0 exactly
///   when p is outside, so the sign is right everywhere, at edges and corners too.
/// - Open meshes (a body scan with holes, a sheet): where the closest point is on the border (an
///   edge of one face, or a vertex on such an edge) the pseudo-normal says nothing about inside
///   and outside; there the generalised winding number decides (Jacobson, Kavan & Sorkine-Hornung
///   2013: the solid angles of all triangles over 4 pi, 1 inside a closed surface, 0 outside,
///   in between across a hole; inside when above 1/2). It sums every triangle, O(n), and is taken
///   only for points nearest the border. Elsewhere on an open mesh the sign is the side of the
///   nearest face, as on a closed one.
/// - Normal: the gradient of the signed distance wherever it has one: the face's normal where the
///   closest point is inside a face (the distance then that of the face's plane), else the unit
///   vector from the closest point to p (towards p outside, away from it inside). At the surface
///   itself (p within rounding of an edge or corner) it is the feature's pseudo-normal.
/// set_positions() moves the vertices (an animated mesh): normals recomputed, the tree refitted
/// (its split is kept: the topology does not change), O(n), no allocation.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/collision/primitive_distance.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar>
class MeshDistance {
 public:
  /// The point of the mesh nearest a query point, and the signed distance to it.
  struct Closest {
    Scalar distance;        ///< signed: negative inside
    Vec3<Scalar> normal;    ///< outward unit normal (the distance's gradient)
    int triangle;           ///< the triangle the closest point lies on
    Vec3<Scalar> weights;   ///< its barycentric coordinates on that triangle
  };

  /// `triangles` over the columns of `positions` (3 x n). The mesh is assumed valid (ids in range,
  /// finite coordinates, no zero-area triangle, no edge of more than two triangles, consistent
  /// orientation): validate it first (ClothMesh::validate() names the defect).
  /// \throws InvalidParameter naming `positions` or `triangles` for what the tree itself rejects.
  MeshDistance(std::vector<std::array<int, 3>> triangles, const Matrix3X<Scalar>& positions);

  /// New vertex positions, same topology: normals recomputed and the tree refitted.
  /// \throws InvalidParameter naming `positions` (column count, finite).
  void set_positions(const Matrix3X<Scalar>& positions);

  /// The closest point of the mesh to p, its signed distance and outward normal.
  Closest closest(const Vec3<Scalar>& p) const;

  const Matrix3X<Scalar>& positions() const { return m_positions; }
  const std::vector<std::array<int, 3>>& triangles() const { return m_topology.triangles(); }
  int triangle_count() const { return m_topology.triangle_count(); }
  /// The largest distance of a vertex from the local origin.
  Scalar bounding_radius() const { return m_bounding_radius; }
  /// The first s in [0, 1] at which the point p0 + s path comes within `offset` >= 0 of the surface
  /// (within `tolerance` of it), 0 if p0 is there already or inside; -1 if the path never does.
  /// Each triangle's distance is convex along a line, so per triangle near the path (the tree's
  /// boxes against the path's, grown by the offset) Newton steps from s = 0 never pass its first
  /// root and a tangent that misses proves a miss; the least root is the answer. Exact however
  /// thin the part and however fast the point: no sampling.
  Scalar first_contact(const Vec3<Scalar>& p0, const Vec3<Scalar>& path, Scalar offset, Scalar tolerance) const;
  /// The generalised winding number of the surface about p (brute force over the triangles).
  double winding_number(const Vec3<Scalar>& p) const;
  /// True if every edge lies in two triangles.
  bool closed() const { return m_closed; }
  /// The enclosed volume by the divergence theorem: > 0 if the faces wind counter-clockwise seen
  /// from outside (meaningful on a closed mesh).
  Scalar signed_volume() const;

 private:
  void update_normals();

  MeshTopology m_topology;
  Matrix3X<Scalar> m_positions;
  TriangleBvh<Scalar> m_tree;
  std::vector<Vec3<Scalar>> m_face_normals;    // unit, per triangle
  std::vector<Vec3<Scalar>> m_edge_normals;    // per edge of m_topology: sum of its faces' normals
  std::vector<Vec3<Scalar>> m_vertex_normals;  // angle-weighted sums
  std::vector<char> m_border_edge;              // per edge: in one triangle only
  std::vector<char> m_border_vertex;            // per vertex: on a border edge
  bool m_closed = true;
  Scalar m_bounding_radius = 0;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
MeshDistance<Scalar>::MeshDistance(std::vector<std::array<int, 3>> triangles, const Matrix3X<Scalar>& positions)
    : m_topology(static_cast<int>(positions.cols()), std::move(triangles)),
      m_positions(positions),
      m_tree(m_topology, positions),
      m_face_normals(static_cast<std::size_t>(m_topology.triangle_count())),
      m_edge_normals(static_cast<std::size_t>(m_topology.edge_count())),
      m_vertex_normals(static_cast<std::size_t>(positions.cols())),
      m_border_edge(static_cast<std::size_t>(m_topology.edge_count()), 0),
      m_border_vertex(static_cast<std::size_t>(positions.cols()), 0) {
  std::vector<int> uses(static_cast<std::size_t>(m_topology.edge_count()), 0);
  for (int t = 0; t < m_topology.triangle_count(); ++t)
    for (int e : m_topology.triangle_edges(t)) ++uses[static_cast<std::size_t>(e)];
  for (int e = 0; e < m_topology.edge_count(); ++e)
    if (uses[static_cast<std::size_t>(e)] == 1) {
      m_border_edge[static_cast<std::size_t>(e)] = 1;
      for (int v : m_topology.edge(e)) m_border_vertex[static_cast<std::size_t>(v)] = 1;
      m_closed = false;
    }
  update_normals();
}

template <class Scalar>
void MeshDistance<Scalar>::set_positions(const Matrix3X<Scalar>& positions) {
  if (positions.cols() != m_positions.cols())
    detail::fail_argument("positions", detail::to_text(positions.cols()) + " columns",
                          detail::to_text(m_positions.cols()) + " columns (one per vertex)");
  if (!positions.allFinite()) detail::fail_argument("positions", "not finite", "finite coordinates");
  m_positions = positions;
  m_tree.refit(m_positions, Scalar(0));
  update_normals();
}

template <class Scalar>
void MeshDistance<Scalar>::update_normals() {
  std::fill(m_edge_normals.begin(), m_edge_normals.end(), Vec3<Scalar>::Zero());
  std::fill(m_vertex_normals.begin(), m_vertex_normals.end(), Vec3<Scalar>::Zero());
  m_bounding_radius = m_positions.cols() > 0 ? m_positions.colwise().norm().maxCoeff() : Scalar(0);
  for (int t = 0; t < m_topology.triangle_count(); ++t) {
    const std::array<int, 3>& c = m_topology.triangle(t);
    const Vec3<Scalar> corner[3] = {m_positions.col(c[0]), m_positions.col(c[1]), m_positions.col(c[2])};
    const Vec3<Scalar> cross = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
    const Scalar length = cross.norm();
    const Vec3<Scalar> n = length > 0 ? Vec3<Scalar>(cross / length) : Vec3<Scalar>::Zero();
    m_face_normals[static_cast<std::size_t>(t)] = n;
    for (int k = 0; k < 3; ++k) {
      m_edge_normals[static_cast<std::size_t>(m_topology.triangle_edges(t)[static_cast<std::size_t>(k)])] += n;
      const Vec3<Scalar> e1 = corner[(k + 1) % 3] - corner[k], e2 = corner[(k + 2) % 3] - corner[k];
      const Scalar angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      m_vertex_normals[static_cast<std::size_t>(c[static_cast<std::size_t>(k)])] += angle * n;
    }
  }
}

template <class Scalar>
Scalar MeshDistance<Scalar>::first_contact(const Vec3<Scalar>& p0, const Vec3<Scalar>& path, Scalar offset,
                                           Scalar tolerance) const {
  if (closest(p0).distance - offset <= tolerance) return Scalar(0);
  const Vec3<Scalar> p1 = p0 + path;
  const Vec3<Scalar> grow = Vec3<Scalar>::Constant(offset + tolerance);
  const typename TriangleBvh<Scalar>::Box reach{p0.cwiseMin(p1) - grow, p0.cwiseMax(p1) + grow};
  Scalar first = 2;  // above 1: none yet
  m_tree.for_each_overlapping(reach, [&](int t) {
    const std::array<int, 3>& c = m_topology.triangle(t);
    Scalar s = 0;
    for (int step = 0; step < 100 && s < first; ++step) {
      const Vec3<Scalar> p = p0 + s * path;
      const PointTriangleClosest<Scalar> q =
          closest_point_on_triangle<Scalar>(p, m_positions.col(c[0]), m_positions.col(c[1]), m_positions.col(c[2]));
      const Scalar d = std::sqrt(q.distance_squared), gap = d - offset;
      if (gap <= tolerance) {
        first = s;
        return;
      }
      const Vec3<Scalar> point = q.weights[0] * m_positions.col(c[0]) + q.weights[1] * m_positions.col(c[1]) +
                                 q.weights[2] * m_positions.col(c[2]);
      const Scalar closing = -(p - point).dot(path) / d;
      if (!(gap < closing * (1 - s))) return;  // the tangent misses: so does the convex distance
      s = std::min(s + gap / closing, Scalar(1));
    }
  });
  return first <= 1 ? first : Scalar(-1);
}

template <class Scalar>
double MeshDistance<Scalar>::winding_number(const Vec3<Scalar>& p) const {
  // Van Oosterom & Strackee's solid angle of each triangle seen from p.
  double sum = 0;
  const Eigen::Vector3d q = p.template cast<double>();
  for (const std::array<int, 3>& c : m_topology.triangles()) {
    const Eigen::Vector3d a = m_positions.col(c[0]).template cast<double>() - q;
    const Eigen::Vector3d b = m_positions.col(c[1]).template cast<double>() - q;
    const Eigen::Vector3d d = m_positions.col(c[2]).template cast<double>() - q;
    const double la = a.norm(), lb = b.norm(), ld = d.norm();
    const double below = la * lb * ld + a.dot(b) * ld + b.dot(d) * la + d.dot(a) * lb;
    sum += 2 * std::atan2(a.dot(b.cross(d)), below);
  }
  return sum / (4 * 3.14159265358979323846);
}

template <class Scalar>
Scalar MeshDistance<Scalar>::signed_volume() const {
  Scalar volume = 0;
  for (const std::array<int, 3>& c : m_topology.triangles())
    volume += m_positions.col(c[0]).dot(m_positions.col(c[1]).cross(m_positions.col(c[2])));
  return volume / Scalar(6);
}

template <class Scalar>
typename MeshDistance<Scalar>::Closest MeshDistance<Scalar>::closest(const Vec3<Scalar>& p) const {
  // Of triangles at the same distance up to rounding (a point over the edge or corner of flat
  // faces) a face interior wins: its normal is exact, while the direction from an edge point
  // carries the rounding of both, which tilts a resting node's normal at random and feeds on itself.
  const Scalar slack = 1 + 64 * std::numeric_limits<Scalar>::epsilon();
  Scalar best = std::numeric_limits<Scalar>::infinity(), bound = best;
  bool best_inside = false;
  Vec3<Scalar> weights = Vec3<Scalar>::Zero();
  const int t = m_tree.nearest(p, bound, [&](int triangle, Scalar& reach) {
    const std::array<int, 3>& c = m_topology.triangle(triangle);
    const PointTriangleClosest<Scalar> q =
        closest_point_on_triangle<Scalar>(p, m_positions.col(c[0]), m_positions.col(c[1]), m_positions.col(c[2]));
    const bool inside = q.weights.minCoeff() > 0;
    const bool tie = q.distance_squared <= best * slack && best <= q.distance_squared * slack;
    if (tie ? !(inside && !best_inside) && !(inside == best_inside && q.distance_squared < best)
            : q.distance_squared > best)
      return false;
    best = q.distance_squared;
    best_inside = inside;
    reach = best * slack;
    weights = q.weights;
    return true;
  });
  if (t < 0) return {std::numeric_limits<Scalar>::infinity(), Vec3<Scalar>::UnitY(), -1, weights};
  const std::array<int, 3>& c = m_topology.triangle(t);
  // The feature the closest point lies on: barycentric weights of exactly zero mark an edge
  // (one zero) or a vertex (two), as primitive_distance.hpp computes them.
  Vec3<Scalar> pseudo;
  bool border = false;
  const int zeros = int(weights[0] == 0) + int(weights[1] == 0) + int(weights[2] == 0);
  if (zeros >= 2) {
    int k = 0;
    weights.maxCoeff(&k);
    const std::size_t v = static_cast<std::size_t>(c[static_cast<std::size_t>(k)]);
    pseudo = m_vertex_normals[v];
    border = m_border_vertex[v] != 0;
  } else if (zeros == 1) {
    const int opposite = weights[0] == 0 ? 0 : (weights[1] == 0 ? 1 : 2);
    const std::size_t e = static_cast<std::size_t>(m_topology.triangle_edges(t)[std::size_t((opposite + 1) % 3)]);
    pseudo = m_edge_normals[e];
    border = m_border_edge[e] != 0;
  } else {
    pseudo = m_face_normals[static_cast<std::size_t>(t)];
  }
  if (zeros == 0) {
    // Inside a face: the face's normal and plane distance, exactly. (p - c) / |p - c| is the same
    // vector with the rounding of c in it, which would tilt a resting node's normal at random.
    const Vec3<Scalar>& n = m_face_normals[static_cast<std::size_t>(t)];
    const Scalar height = n.dot(p - m_positions.col(c[0]));
    return {height, n, t, weights};
  }
  const Vec3<Scalar> point =
      weights[0] * m_positions.col(c[0]) + weights[1] * m_positions.col(c[1]) + weights[2] * m_positions.col(c[2]);
  const Vec3<Scalar> away = p - point;
  const Scalar length = away.norm();
  const Scalar sign = (border ? winding_number(p) > 0.5 : away.dot(pseudo) < 0) ? Scalar(-1) : Scalar(1);
  // Within rounding of the surface the direction to p means nothing: the feature's normal.
  const Scalar scale = std::max(m_bounding_radius, Scalar(1));
  if (!(length > Scalar(64) * std::numeric_limits<Scalar>::epsilon() * scale)) {
    const Scalar n = pseudo.norm();
    return {sign * length, n > 0 ? Vec3<Scalar>(pseudo / n) : m_face_normals[static_cast<std::size_t>(t)], t, weights};
  }
  return {sign * length, sign * away / length, t, weights};
}

}  // namespace drape
