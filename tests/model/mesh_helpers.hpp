#pragma once
// Irregular cloth meshes for tests: a jittered lattice whose cells are split along random diagonals.

#include <random>

#include "drape/core/cloth_mesh.hpp"

namespace drape::test {

/// An n x n patch `h` apart in the x-z plane (y up), interior vertices moved by up to a quarter of
/// `h`, each cell split along a random diagonal, counter-clockwise seen from +y. Not a lattice.
template <class S>
ClothMesh<S> irregular_patch(int n, S h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  std::bernoulli_distribution flip(0.5);
  ClothMesh<S> mesh;
  mesh.positions.resize(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool interior = i > 0 && j > 0 && i + 1 < n && j + 1 < n;
      const double dx = interior ? jitter(rng) : 0.0, dz = interior ? jitter(rng) : 0.0;
      mesh.positions.col(j * n + i) = Vec3<S>(S((i + dx) * double(h)), S(0), S((j + dz) * double(h)));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      if (flip(rng)) {
        mesh.triangles.push_back({a, d, c});
        mesh.triangles.push_back({a, c, b});
      } else {
        mesh.triangles.push_back({a, d, b});
        mesh.triangles.push_back({b, d, c});
      }
    }
  return mesh;
}

/// The same patch without jitter, every cell split along the same diagonal: the regular mesh
/// irregular_patch() perturbs. Not a lattice either (it takes the mesh path, not the grid's).
template <class S>
ClothMesh<S> regular_patch(int n, S h) {
  ClothMesh<S> mesh;
  mesh.positions.resize(3, n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) mesh.positions.col(j * n + i) = Vec3<S>(S(i) * h, S(0), S(j) * h);
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      mesh.triangles.push_back({a, d, c});
      mesh.triangles.push_back({a, c, b});
    }
  return mesh;
}

}  // namespace drape::test
