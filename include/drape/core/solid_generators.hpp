#pragma once
/// \file solid_generators.hpp
/// Closed triangle meshes of solids, for mesh colliders (contact/collider.hpp) and their tests and
/// benchmarks: a sphere (a subdivided icosahedron), a box and a torus. Each is closed, manifold and
/// wound counter-clockwise seen from outside (positive volume), centred at the origin.

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// The icosahedron subdivided `levels` times (each triangle into four, new vertices pushed out to
/// the sphere): 20 4^levels triangles, every vertex on the sphere of `radius`.
/// \throws InvalidParameter naming `radius` (finite, > 0) or `levels` ([0, 8]).
template <class Scalar = double>
ClothMesh<Scalar> icosphere_mesh(Scalar radius, int levels) {
  detail::require_positive_finite("radius", radius);
  detail::require_in_range("levels", levels, 0, 8);
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> x = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Eigen::Vector3d& p : x) p.normalize();
  std::vector<std::array<int, 3>> triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> middle;
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      const auto found = middle.find(key);
      if (found != middle.end()) return found->second;
      x.push_back((x[std::size_t(a)] + x[std::size_t(b)]).normalized());
      return middle[key] = static_cast<int>(x.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(4 * triangles.size());
    for (const std::array<int, 3>& c : triangles) {
      const int ab = midpoint(c[0], c[1]), bc = midpoint(c[1], c[2]), ca = midpoint(c[2], c[0]);
      finer.push_back({c[0], ab, ca});
      finer.push_back({c[1], bc, ab});
      finer.push_back({c[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles = std::move(finer);
  }
  ClothMesh<Scalar> mesh;
  mesh.positions.resize(3, static_cast<Index>(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i)
    mesh.positions.col(static_cast<Index>(i)) = (double(radius) * x[i]).template cast<Scalar>();
  mesh.triangles = std::move(triangles);
  return mesh;
}

/// The box of `half_extents` about the origin, each face split into `divisions` x `divisions`
/// squares of two triangles (divisions = 1: the 12 triangles of its faces).
/// \throws InvalidParameter naming `half_extents` (finite, > 0) or `divisions` ([1, 1000]).
template <class Scalar = double>
ClothMesh<Scalar> box_mesh(const Vec3<Scalar>& half_extents, int divisions = 1) {
  for (int k = 0; k < 3; ++k) detail::require_positive_finite("half_extents", half_extents[k]);
  detail::require_in_range("divisions", divisions, 1, 1000);
  const int n = divisions;
  std::map<std::array<int, 3>, int> id;  // lattice point (0..2n per axis) -> vertex
  std::vector<Eigen::Vector3d> x;
  const auto vertex = [&](const std::array<int, 3>& g) {
    const auto found = id.find(g);
    if (found != id.end()) return found->second;
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) p[k] = double(half_extents[k]) * (double(g[std::size_t(k)]) / n - 1.0);
    x.push_back(p);
    return id[g] = static_cast<int>(x.size()) - 1;
  };
  std::vector<std::array<int, 3>> triangles;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // u, v span the face so that u x v points out of the box.
      const int u = (axis + (side ? 1 : 2)) % 3, v = (axis + (side ? 2 : 1)) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const auto corner = [&](int di, int dj) {
            std::array<int, 3> g{};
            g[std::size_t(axis)] = side ? 2 * n : 0;
            g[std::size_t(u)] = 2 * (i + di);
            g[std::size_t(v)] = 2 * (j + dj);
            return vertex(g);
          };
          const int a = corner(0, 0), b = corner(1, 0), c = corner(1, 1), d = corner(0, 1);
          triangles.push_back({a, b, c});
          triangles.push_back({a, c, d});
        }
    }
  ClothMesh<Scalar> mesh;
  mesh.positions.resize(3, static_cast<Index>(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i) mesh.positions.col(static_cast<Index>(i)) = x[i].template cast<Scalar>();
  mesh.triangles = std::move(triangles);
  return mesh;
}

/// The torus about the y axis: a tube of radius `minor` whose centre circle has radius `major`,
/// `around` segments along the circle and `across` around the tube.
/// \throws InvalidParameter naming `minor` ((0, major)), `major` (finite, > 0), `around` or
/// `across` ([3, 10000]).
template <class Scalar = double>
ClothMesh<Scalar> torus_mesh(Scalar major, Scalar minor, int around, int across) {
  detail::require_positive_finite("major", major);
  if (!(minor > 0 && minor < major)) detail::fail_argument("minor", detail::to_text(minor), "(0, major)");
  detail::require_in_range("around", around, 3, 10000);
  detail::require_in_range("across", across, 3, 10000);
  const double pi = 3.14159265358979323846;
  ClothMesh<Scalar> mesh;
  mesh.positions.resize(3, static_cast<Index>(around) * across);
  const auto id = [&](int i, int j) { return (i % around) * across + (j % across); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const double phi = 2 * pi * i / around, theta = 2 * pi * j / across;
      const double r = double(major) + double(minor) * std::cos(theta);
      mesh.positions.col(id(i, j)) =
          Eigen::Vector3d(r * std::cos(phi), double(minor) * std::sin(theta), -r * std::sin(phi)).template cast<Scalar>();
    }
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  return mesh;
}

}  // namespace drape
