#pragma once
// Shapes to lay a cloth in for collision tests: along a path in the (z, y) plane, e.g. folded
// over itself.
#include <cmath>
#include <functional>

#include <Eigen/Core>

#include "drape/model/cloth.hpp"

namespace drape::test {

/// Positions of the cloth laid along a path in the (z, y) plane: node (i, j) at x = i h and at
/// arc length j h along `path(s)` (returns (z, y)).
template <class S>
Matrix3X<S> laid_along(const Cloth<S>& cloth, const std::function<Eigen::Vector2d(double)>& path) {
  const Grid<S>& grid = cloth.grid();
  Matrix3X<S> x(3, grid.node_count());
  for (int j = 0; j < grid.ny(); ++j)
    for (int i = 0; i < grid.nx(); ++i) {
      const Eigen::Vector2d zy = path(double(j) * double(grid.spacing()));
      x.col(grid.node(i, j)) = Vec3<S>(S(double(i) * double(grid.spacing())), S(zy.y()), S(zy.x()));
    }
  return x;
}

/// Flat on the floor (y = y0) up to `fold`, half a turn of radius r, then back over itself.
inline std::function<Eigen::Vector2d(double)> folded_path(double y0, double fold, double r) {
  return [=](double s) -> Eigen::Vector2d {
    if (s <= fold) return {s, y0};
    const double a = (s - fold) / r;
    if (a <= 3.14159265358979323846) return {fold + r * std::sin(a), y0 + r * (1 - std::cos(a))};
    return {fold - (s - fold - 3.14159265358979323846 * r), y0 + 2 * r};
  };
}

}  // namespace drape::test
