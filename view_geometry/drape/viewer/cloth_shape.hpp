#pragma once
/// \file cloth_shape.hpp
/// What the viewer needs of a cloth's shape, for a grid and for any mesh alike: the checker
/// pattern's coordinates per node and the cloth's longest side.

#include <algorithm>
#include <array>
#include <vector>

#include "drape/model/cloth.hpp"

namespace drape::viewer {

/// Checker coordinates per node, one unit per checker step: (i, j) on a grid; on a mesh its pattern
/// (the rest shape's u, v, or x, z) over the mean edge length, so the checks have the same size.
template <class Scalar>
std::vector<std::array<float, 2>> checker_coordinates(const Cloth<Scalar>& cloth) {
  std::vector<std::array<float, 2>> pattern(static_cast<std::size_t>(cloth.node_count()));
  if (cloth.is_grid()) {
    const int nx = cloth.grid().nx();
    for (int n = 0; n < cloth.node_count(); ++n) pattern[static_cast<std::size_t>(n)] = {float(n % nx), float(n / nx)};
    return pattern;
  }
  const ClothMesh<Scalar>& mesh = cloth.mesh();
  const Matrix3X<Scalar> rest = mesh.rest_shape();
  const int second = mesh.rest_uv.cols() != 0 ? 1 : 2;  // a pattern's v, or a 3D mesh's z
  const SpringSet<Scalar>& springs = cloth.springs();
  Scalar edge = 0;
  int edges = 0;
  for (int s = 0; s < springs.size(); ++s)
    if (springs.category()[static_cast<std::size_t>(s)] == SpringCategory::Structural) {
      edge += springs.rest_length()[static_cast<std::size_t>(s)];
      ++edges;
    }
  const Scalar unit = edges > 0 && edge > 0 ? edge / Scalar(edges) : Scalar(1);
  for (int n = 0; n < cloth.node_count(); ++n)
    pattern[static_cast<std::size_t>(n)] = {float(rest(0, n) / unit), float(rest(second, n) / unit)};
  return pattern;
}

/// m: the longest side of the cloth's rest shape ((max(nx, ny) - 1) spacing on a grid).
template <class Scalar>
double longest_side(const Cloth<Scalar>& cloth) {
  if (cloth.is_grid())
    return double(std::max(cloth.grid().nx() - 1, cloth.grid().ny() - 1)) * double(cloth.grid().spacing());
  const Matrix3X<Scalar> rest = cloth.mesh().rest_shape();
  return double((rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).maxCoeff());
}

}  // namespace drape::viewer
