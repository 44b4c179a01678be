#pragma once
/// \file mesh_generators.hpp
/// Meshes the examples and tests need, made in the library: the grid (the lattice of grid.hpp as a
/// mesh, marked so that a cloth made of it keeps the grid's springs and fast paths).

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/grid.hpp"

namespace drape {

/// The nx x ny grid of grid.hpp (node (i, j) at (i h, 0, j h), id j nx + i, its triangles), marked
/// as a lattice. \throws InvalidParameter as Grid's constructor.
template <class Scalar = double>
ClothMesh<Scalar> grid_mesh(int nx, int ny, Scalar spacing) {
  const Grid<Scalar> grid(nx, ny, spacing, Scalar(1));
  ClothMesh<Scalar> mesh;
  mesh.positions = grid.rest_positions();
  mesh.triangles = grid.triangles();
  mesh.lattice = LatticeShape<Scalar>{nx, ny, spacing};
  return mesh;
}

}  // namespace drape
