#pragma once
/// \file collider_surface.hpp
/// The colliders as meshes of shared points and fixed triangles in their own frame, to export
/// with their motion (drape-render's USD file, drape/io/usd.hpp): each shape's closed mesh of
/// collider_mesh.hpp with equal corners merged, a mesh collider's own vertices and faces, a plane
/// as a finite square. Placed by the
/// collider's pose at each time, the points move and the triangles stay.

#include <Eigen/Core>
#include <array>
#include <map>
#include <tuple>
#include <vector>

#include "drape/contact/collider.hpp"
#include "drape/viewer/collider_mesh.hpp"

namespace drape::viewer {

/// A triangle mesh whose triangles share points (0-based ids, outward counter-clockwise).
struct IndexedMesh {
  std::vector<Eigen::Vector3f> points;
  std::vector<std::array<int, 3>> triangles;
};

/// `soup` (three corners per triangle, as local_collider_mesh() gives) with bit-equal corners
/// made one point: a collider's faces meet at corners computed the same way, so the closed mesh
/// becomes one connected surface.
inline IndexedMesh merge_corners(const std::vector<Eigen::Vector3f>& soup) {
  IndexedMesh mesh;
  std::map<std::tuple<float, float, float>, int> ids;
  std::array<int, 3> triangle{};
  for (std::size_t k = 0; k < soup.size(); ++k) {
    const Eigen::Vector3f& p = soup[k];
    const auto [it, added] = ids.emplace(std::make_tuple(p.x(), p.y(), p.z()), int(mesh.points.size()));
    if (added) mesh.points.push_back(p);
    triangle[k % 3] = it->second;
    if (k % 3 == 2) mesh.triangles.push_back(triangle);
  }
  return mesh;
}

/// The surface of `collider` in its local frame, to be placed by `collider.motion().pose(t)`:
/// the closed mesh of local_collider_mesh() (`segments` per 45 degrees of a rounded band) with
/// shared points; for a plane, the square of half side `plane_half_size` in it (two triangles
/// facing its normal, local +y) centred where `plane_around` (world, at time `t0`) projects onto it.
template <class Scalar>
IndexedMesh local_collider_surface(const Collider<Scalar>& collider, const Eigen::Vector3f& plane_around,
                                   float plane_half_size, Scalar t0 = Scalar(0), int segments = 10) {
  if (collider.kind() == ShapeKind::Mesh) {  // its own vertices and faces (a deforming mesh's at t0)
    Matrix3X<Scalar> x;
    collider.mesh_positions(t0, x);
    IndexedMesh mesh;
    for (Index i = 0; i < x.cols(); ++i) mesh.points.push_back(x.col(i).template cast<float>());
    mesh.triangles = collider.mesh()->triangles();
    return mesh;
  }
  if (collider.kind() != ShapeKind::Plane) return merge_corners(local_collider_mesh(collider, segments));
  const RigidPose<Scalar> pose = collider.motion().pose(t0);
  Eigen::Vector3f centre = pose.rotation.template cast<float>().transpose() *
                           (plane_around - pose.translation.template cast<float>());
  centre.y() = 0;  // on the plane
  const float h = plane_half_size;
  IndexedMesh mesh;
  for (const auto& [x, z] : {std::array<float, 2>{-h, h}, {h, h}, {h, -h}, {-h, -h}})
    mesh.points.push_back(centre + Eigen::Vector3f(x, 0, z));
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

/// `local` points placed by `pose`, as the columns of `out` (3 x n, resized).
template <class Scalar>
void place_points(const std::vector<Eigen::Vector3f>& local, const RigidPose<Scalar>& pose, Eigen::Matrix3Xf& out) {
  const Eigen::Matrix3f rotation = pose.rotation.template cast<float>();
  const Eigen::Vector3f translation = pose.translation.template cast<float>();
  out.resize(3, Eigen::Index(local.size()));
  for (std::size_t i = 0; i < local.size(); ++i) out.col(Eigen::Index(i)) = rotation * local[i] + translation;
}

}  // namespace drape::viewer
