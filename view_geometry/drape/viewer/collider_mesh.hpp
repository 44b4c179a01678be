#pragma once
/// \file collider_mesh.hpp
/// Triangle meshes of the cloth's colliders for drawing and framing (drape-render): every shape but the plane
/// as a closed mesh whose vertices lie exactly on the collider's surface, placed by the
/// collider's pose at a given time; the plane as a large quad around a point.
///
/// Sphere, capsule and rounded box are all one shape: an inner box (half extents h - r) inflated
/// by a radius r (sphere: inner box a point; capsule: a segment along x; box: r = its rounding).
/// The mesh is a grid on each face of the outer box, mapped onto that surface (each grid point goes
/// to the inner box's nearest point plus r towards it); grid lines sit at the ends of the flat parts
/// and at equal angles across the rounded bands, so a plain box has one quad per face and a
/// sphere is a cube-sphere. The cylinder is a surface of revolution: a profile from the top cap's
/// centre over the rounded rims to the bottom cap's centre, turned about the y axis. Triangles are
/// flat shaded (face normals), outward.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "drape/contact/collider.hpp"
#include "drape/viewer/camera.hpp"
#include "drape/viewer/solid_mesh.hpp"

namespace drape::viewer {

namespace detail {

/// Appends abc to `triangles` facing outward (the shapes are convex about their local origin),
/// unless it is degenerate (a band's pole, a cap's centre); `size_squared`: the shape's squared size.
inline void add_outward(std::vector<Eigen::Vector3f>& triangles, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c, double size_squared) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (!(n.norm() > 1e-12 * std::max(1.0, size_squared))) return;
  const bool outward = n.dot(a + b + c) >= 0;
  triangles.push_back(a.cast<float>());
  triangles.push_back((outward ? b : c).cast<float>());
  triangles.push_back((outward ? c : b).cast<float>());
}

/// The cylinder of `radius` and `half_height` about y with rims rounded by `r`: the profile in
/// (distance from the axis, y) turned about y in 8 * `segments` steps, each rim 2 * `segments`.
inline std::vector<Eigen::Vector3f> cylinder_mesh(double radius, double half_height, double r, int segments) {
  constexpr double quarter_turn = 1.5707963267948966;
  std::vector<Eigen::Vector2d> profile{{0, half_height}};
  const int rim = r > 0 ? 2 * segments : 0;
  for (int j = 0; j <= rim; ++j) {  // upper rim, from the cap to the side
    const double angle = rim > 0 ? quarter_turn * (1 - double(j) / rim) : 0;
    profile.emplace_back(radius - r + r * std::cos(angle), half_height - r + r * std::sin(angle));
  }
  for (int j = rim; j >= 0; --j) {  // lower rim, the mirror image, from the side to the cap
    const Eigen::Vector2d upper = profile[std::size_t(j + 1)];
    profile.emplace_back(upper.x(), -upper.y());
  }
  profile.emplace_back(0, -half_height);
  const int around = 8 * segments;
  const auto point = [&](std::size_t i, int k) {
    const double angle = 4 * quarter_turn * (k % around) / around;  // the seam closes exactly
    return Eigen::Vector3d(profile[i].x() * std::cos(angle), profile[i].y(), profile[i].x() * std::sin(angle));
  };
  const double size_squared = radius * radius + half_height * half_height;
  std::vector<Eigen::Vector3f> triangles;
  for (std::size_t i = 0; i + 1 < profile.size(); ++i)
    for (int k = 0; k < around; ++k) {
      const Eigen::Vector3d p00 = point(i, k), p10 = point(i + 1, k), p11 = point(i + 1, k + 1),
                            p01 = point(i, k + 1);
      add_outward(triangles, p00, p10, p11, size_squared);
      add_outward(triangles, p00, p11, p01, size_squared);
    }
  return triangles;
}

}  // namespace detail

/// Triangles (three vertices each, in the collider's local frame) of the closed surface of
/// `collider`; empty for a plane. `segments`: grid segments per 45 degrees of a rounded band.
template <class Scalar>
std::vector<Eigen::Vector3f> local_collider_mesh(const Collider<Scalar>& collider, int segments = 10, Scalar t = 0) {
  Eigen::Vector3d outer = Eigen::Vector3d::Zero(), inner = Eigen::Vector3d::Zero();
  double r = 0;
  switch (collider.kind()) {
    case ShapeKind::Plane: return {};
    case ShapeKind::Sphere:
      r = double(collider.radius());
      inner.setZero();
      break;
    case ShapeKind::Capsule:
      r = double(collider.radius());
      inner = Eigen::Vector3d(double(collider.half_length()), 0, 0);
      break;
    case ShapeKind::Box:
      r = double(collider.rounding());
      outer = collider.half_extents().template cast<double>();
      inner = (outer.array() - r).max(0.0).matrix();
      break;
    case ShapeKind::Cylinder:
      return detail::cylinder_mesh(double(collider.radius()), double(collider.half_height()),
                                   double(collider.rounding()), segments);
    case ShapeKind::Mesh: {  // its own triangles (a deforming mesh's at time t)
      std::vector<Eigen::Vector3f> triangles;
      Matrix3X<Scalar> x;
      collider.mesh_positions(t, x);
      triangles.reserve(3 * collider.mesh()->triangles().size());
      for (const std::array<int, 3>& face : collider.mesh()->triangles())
        for (int k : face) triangles.push_back(x.col(k).template cast<float>());
      return triangles;
    }
  }
  outer = inner.array() + r;
  constexpr double quarter_turn_half = 0.78539816339744831;  // 45 degrees
  // Grid coordinates along each axis: the flat part's ends and equal angles across each band.
  std::vector<double> axis[3];
  for (int c = 0; c < 3; ++c) {
    std::vector<double> half;
    if (r > 0)
      for (int j = 0; j <= segments; ++j) half.push_back(inner[c] + r * std::tan(quarter_turn_half * j / segments));
    else
      half.push_back(inner[c]);
    for (auto it = half.rbegin(); it != half.rend(); ++it) axis[c].push_back(-*it);
    for (double v : half)
      if (v > axis[c].back()) axis[c].push_back(v);  // the middle value appears once
  }
  const auto surface = [&](const Eigen::Vector3d& q) -> Eigen::Vector3d {
    const Eigen::Vector3d nearest = q.cwiseMax(-inner).cwiseMin(inner);
    const Eigen::Vector3d d = q - nearest;
    const double length = d.norm();
    return length > 0 ? Eigen::Vector3d(nearest + r * d / length) : q;
  };
  std::vector<Eigen::Vector3f> triangles;
  const auto add = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    detail::add_outward(triangles, a, b, c, outer.squaredNorm());
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    for (double side : {-1.0, 1.0}) {
      const std::vector<double>&us = axis[u], &vs = axis[v];
      const auto point = [&](std::size_t i, std::size_t j) {
        Eigen::Vector3d q;
        q[a] = side * outer[a];
        q[u] = us[i];
        q[v] = vs[j];
        return surface(q);
      };
      for (std::size_t i = 0; i + 1 < us.size(); ++i)
        for (std::size_t j = 0; j + 1 < vs.size(); ++j) {
          const Eigen::Vector3d p00 = point(i, j), p10 = point(i + 1, j), p11 = point(i + 1, j + 1),
                                p01 = point(i, j + 1);
          add(p00, p10, p11);
          add(p00, p11, p01);
        }
    }
  }
  return triangles;
}

/// `local` (from local_collider_mesh()) placed by `pose`, with each triangle's face normal.
template <class Scalar>
SolidMesh place_mesh(const std::vector<Eigen::Vector3f>& local, const RigidPose<Scalar>& pose) {
  const Eigen::Matrix3f rotation = pose.rotation.template cast<float>();
  const Eigen::Vector3f translation = pose.translation.template cast<float>();
  SolidMesh mesh;
  mesh.vertices.reserve(local.size() * 6);
  for (std::size_t t = 0; t + 2 < local.size(); t += 3) {
    const Eigen::Vector3f a = rotation * local[t] + translation, b = rotation * local[t + 1] + translation,
                          c = rotation * local[t + 2] + translation;
    const Eigen::Vector3f n = rotation * (local[t + 1] - local[t]).cross(local[t + 2] - local[t]).normalized();
    for (const Eigen::Vector3f* p : {&a, &b, &c})
      mesh.vertices.insert(mesh.vertices.end(), {p->x(), p->y(), p->z(), n.x(), n.y(), n.z()});
  }
  return mesh;
}

/// A plane collider at time t drawn as a square of half side `half_size` centred at the point of
/// the plane nearest to `around`; casts no shadow.
template <class Scalar>
SolidMesh plane_quad(const Collider<Scalar>& plane, Scalar t, const Eigen::Vector3f& around, float half_size) {
  const RigidPose<Scalar> pose = plane.motion().pose(t);
  const Eigen::Matrix3f rotation = pose.rotation.template cast<float>();
  const Eigen::Vector3f n = rotation.col(1), e1 = rotation.col(0), e2 = rotation.col(2);
  const Eigen::Vector3f point = pose.translation.template cast<float>();
  const Eigen::Vector3f centre = around - n.dot(around - point) * n;
  SolidMesh mesh;
  mesh.casts_shadow = false;
  const Eigen::Vector3f corners[4] = {centre - half_size * (e1 + e2), centre + half_size * (e1 - e2),
                                      centre + half_size * (e1 + e2), centre - half_size * (e1 - e2)};
  for (int k : {0, 1, 2, 0, 2, 3})
    mesh.vertices.insert(mesh.vertices.end(), {corners[k].x(), corners[k].y(), corners[k].z(), n.x(), n.y(), n.z()});
  return mesh;
}

/// Extends `box` by the vertices of `mesh`.
inline void extend(Bounds& box, const SolidMesh& mesh) {
  for (std::size_t k = 0; k + 5 < mesh.vertices.size(); k += 6)
    box.extend(Eigen::Vector3f(mesh.vertices[k], mesh.vertices[k + 1], mesh.vertices[k + 2]));
}

}  // namespace drape::viewer
