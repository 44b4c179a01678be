#pragma once
/// \file mesh_sweep.hpp
/// A triangle mesh whose vertices move during a step (an animated body: contact/collider.hpp's
/// key-framed mesh colliders): its surface at the step's start and at its end (a MeshDistance each:
/// signed distance, closest point, normal) and a tree of the boxes each triangle sweeps between
/// them, for the continuous test of a point's path against the moving triangles. Every vertex moves
/// on a straight line across the step, as the cloth's nodes do.
///
/// The swept test is continuous_collision.hpp's vertex-triangle test (never late, never far) on
/// every triangle whose swept box meets the path's box grown by the offset: no sampling, so a node
/// cannot pass through a thin, fast part (a hand, an arm moving fast) between two samples.
/// update() refits, never rebuilds: no allocation after construction.

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/continuous_collision.hpp"
#include "drape/collision/mesh_distance.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/core/types.hpp"

namespace drape {

template <class Scalar>
class MeshSweep {
 public:
  /// `triangles` over the columns of `positions`, both ends of the step at `positions`.
  MeshSweep(const std::vector<std::array<int, 3>>& triangles, const Matrix3X<Scalar>& positions)
      : m_topology(static_cast<int>(positions.cols()), triangles),
        m_start(triangles, positions),
        m_end(triangles, positions),
        m_swept(m_topology, positions) {}

  /// The step from vertex positions `start` to `end` (3 x n each): both surfaces and the swept boxes.
  /// \throws InvalidParameter naming `positions` (column count, finite).
  void update(const Matrix3X<Scalar>& start, const Matrix3X<Scalar>& end) {
    // Step after step, this step's start is the last one's end: its surface is taken over.
    if (start.cols() == m_end.positions().cols() && start == m_end.positions())
      std::swap(m_start, m_end);
    else
      m_start.set_positions(start);
    m_end.set_positions(end);
    m_swept.refit(m_start.positions(), m_end.positions(), Scalar(0));
  }

  const MeshDistance<Scalar>& start() const { return m_start; }
  const MeshDistance<Scalar>& end() const { return m_end; }

  /// The first s in [0, 1] at which the point moving from p0 to p1 comes within `offset` >= 0 of
  /// the moving surface: 0 if p0 is within it (or inside) at the start, -1 if it never comes so
  /// close. `tolerance`: how far above the offset the start still counts as a contact.
  Scalar first_contact(const Vec3<Scalar>& p0, const Vec3<Scalar>& p1, Scalar offset, Scalar tolerance) const {
    if (m_start.closest(p0).distance - offset <= tolerance) return Scalar(0);
    const Vec3<Scalar> grow = Vec3<Scalar>::Constant(offset + tolerance);
    const typename TriangleBvh<Scalar>::Box reach{p0.cwiseMin(p1) - grow, p0.cwiseMax(p1) + grow};
    const Matrix3X<Scalar>& a = m_start.positions();
    const Matrix3X<Scalar>& b = m_end.positions();
    Scalar first = 2;  // above 1: none yet
    m_swept.for_each_overlapping(reach, [&](int t) {
      const std::array<int, 3>& c = m_topology.triangle(t);
      const std::optional<Scalar> hit = vertex_triangle_impact<Scalar>(
          {p0, a.col(c[0]), a.col(c[1]), a.col(c[2])}, {p1, b.col(c[0]), b.col(c[1]), b.col(c[2])}, offset);
      if (hit && *hit < first) first = *hit;
    });
    return first <= 1 ? first : Scalar(-1);
  }

  /// The velocity across the step of the surface point with barycentric `weights` on triangle t:
  /// its displacement from start to end over dt.
  Vec3<Scalar> surface_velocity(int t, const Vec3<Scalar>& weights, Scalar dt) const {
    const std::array<int, 3>& c = m_topology.triangle(t);
    Vec3<Scalar> moved = Vec3<Scalar>::Zero();
    for (int k = 0; k < 3; ++k)
      moved += weights[k] * (m_end.positions().col(c[std::size_t(k)]) - m_start.positions().col(c[std::size_t(k)]));
    return moved / dt;
  }

 private:
  MeshTopology m_topology;
  MeshDistance<Scalar> m_start, m_end;
  TriangleBvh<Scalar> m_swept;
};

}  // namespace drape
