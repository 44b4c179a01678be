#pragma once
/// \file grid.hpp
/// The cloth's topology and rest geometry: an `nx x ny` lattice of mass points.
///
/// Conventions (drape's conventions.md): node `(i, j)` has id `j * nx + i`, `i` runs along +x,
/// `j` along +z, y is up. At rest the grid is flat and horizontal at height 0:
/// \f$ x_{(i,j)} = (i h, 0, j h) \f$ with spacing \f$h\f$.

#include <array>
#include <string>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// Integer grid coordinates of a node.
struct GridCoord {
  int i;  ///< column, along +x, in [0, nx)
  int j;  ///< row, along +z, in [0, ny)
};

template <class Scalar = double>
class Grid {
 public:
  /// Largest grid: node ids and DOF indices are `int`, and this keeps a cloth's memory in the
  /// gigabytes (the largest size measured is 257 x 257, drape's benchmarks.md).
  static constexpr int max_nodes_per_side = 10000;
  static constexpr long long max_nodes = 16'000'000;

  /// \throws InvalidParameter unless nx and ny are in [2, max_nodes_per_side], nx * ny <=
  /// max_nodes, and spacing and node_mass are finite and > 0.
  Grid(int nx, int ny, Scalar spacing, Scalar node_mass);

  /// The checks of the constructor, without building anything. \throws InvalidParameter.
  static void validate(int nx, int ny, Scalar spacing, Scalar node_mass);

  int nx() const { return m_nx; }
  int ny() const { return m_ny; }
  int node_count() const { return m_nx * m_ny; }
  Scalar spacing() const { return m_spacing; }
  /// Mass of every node (kg); the mass matrix is `diag(m_0, m_0, m_0, m_1, ...)`.
  const VectorX<Scalar>& masses() const { return m_masses; }
  Scalar total_mass() const { return m_masses.sum(); }

  int node(int i, int j) const { return j * m_nx + i; }
  GridCoord coord(int node_id) const { return {node_id % m_nx, node_id / m_nx}; }
  bool contains(int i, int j) const { return i >= 0 && i < m_nx && j >= 0 && j < m_ny; }

  /// Undeformed flat horizontal placement, `3 x node_count()`.
  Matrix3X<Scalar> rest_positions() const;

  /// Two triangles per cell, counter-clockwise seen from +y; cells are split along alternating
  /// diagonals so the mesh has no preferred direction.
  std::vector<std::array<int, 3>> triangles() const;

 private:
  int m_nx;
  int m_ny;
  Scalar m_spacing;
  VectorX<Scalar> m_masses;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void Grid<Scalar>::validate(int nx, int ny, Scalar spacing, Scalar node_mass) {
  const long long nodes = static_cast<long long>(nx) * ny;
  if (nodes > max_nodes) detail::fail_argument("nx * ny", detail::to_text(nodes), "<= " + detail::to_text(max_nodes));
  const std::string side = "[2, " + detail::to_text(max_nodes_per_side) +
                           "]: >= 2 and <= " + detail::to_text(max_nodes_per_side) + " nodes per side";
  if (nx < 2 || nx > max_nodes_per_side) detail::fail_argument("nx", detail::to_text(nx), side);
  if (ny < 2 || ny > max_nodes_per_side) detail::fail_argument("ny", detail::to_text(ny), side);
  detail::require_positive_finite("spacing", spacing);
  detail::require_positive_finite("node_mass", node_mass);
}

template <class Scalar>
Grid<Scalar>::Grid(int nx, int ny, Scalar spacing, Scalar node_mass) : m_nx(nx), m_ny(ny), m_spacing(spacing) {
  validate(nx, ny, spacing, node_mass);
  m_masses = VectorX<Scalar>::Constant(node_count(), node_mass);
}

template <class Scalar>
Matrix3X<Scalar> Grid<Scalar>::rest_positions() const {
  Matrix3X<Scalar> x(3, node_count());
  for (int j = 0; j < m_ny; ++j)
    for (int i = 0; i < m_nx; ++i)
      x.col(node(i, j)) = Vec3<Scalar>(Scalar(i) * m_spacing, Scalar(0), Scalar(j) * m_spacing);
  return x;
}

template <class Scalar>
std::vector<std::array<int, 3>> Grid<Scalar>::triangles() const {
  std::vector<std::array<int, 3>> tris;
  tris.reserve(static_cast<std::size_t>(2 * (m_nx - 1) * (m_ny - 1)));
  for (int j = 0; j + 1 < m_ny; ++j) {
    for (int i = 0; i + 1 < m_nx; ++i) {
      const int a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      // Counter-clockwise seen from +y: (x, z) plane with y up means a -> d -> c ordering.
      if ((i + j) % 2 == 0) {
        tris.push_back({a, d, c});
        tris.push_back({a, c, b});
      } else {
        tris.push_back({a, d, b});
        tris.push_back({b, d, c});
      }
    }
  }
  return tris;
}

}  // namespace drape
