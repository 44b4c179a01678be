#pragma once
/// \file obj.hpp
/// Wavefront OBJ export of the cloth mesh. Coordinates are printed with max_digits10 significant
/// digits, so reading them back gives the same floating-point values bit for bit.

#include <array>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/io/atomic_file.hpp"

namespace drape {

/// Writes vertices `x` (`3 x n`: a Matrix3X, a Map, any Eigen expression) and 0-based `triangles`
/// as an OBJ file, atomically. \throws FileWriteError if the file cannot be written.
template <class Derived>
void write_obj(const std::string& path, const Eigen::MatrixBase<Derived>& x,
               const std::vector<std::array<int, 3>>& triangles) {
  using Scalar = typename Derived::Scalar;
  static_assert(Derived::RowsAtCompileTime == 3 || Derived::RowsAtCompileTime == Eigen::Dynamic,
                "write_obj: x must be 3 x n");
  write_file_atomically(path, [&](std::FILE* f) {
    const int digits = std::numeric_limits<Scalar>::max_digits10;
    if (std::fprintf(f, "# drape cloth: %d vertices, %d triangles\n", static_cast<int>(x.cols()),
                     static_cast<int>(triangles.size())) < 0)
      return false;
    for (Index i = 0; i < x.cols(); ++i)
      if (std::fprintf(f, "v %.*g %.*g %.*g\n", digits, double(x(0, i)), digits, double(x(1, i)), digits,
                       double(x(2, i))) < 0)
        return false;
    for (const auto& t : triangles)
      if (std::fprintf(f, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1) < 0) return false;
    return true;
  });
}

}  // namespace drape
