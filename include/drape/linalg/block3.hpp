#pragma once
/// \file block3.hpp
/// Kernels on one 3x3 block, written once for every block product in drape (block-CSR rows, the
/// edge operator, block Jacobi, the multigrid smoother).
///
/// Storage: a block is 9 contiguous scalars, column-major (an `Eigen::Map<Mat3>`). A symmetric
/// block can also be stored in 6 scalars, its lower triangle row by row:
/// (0,0) (1,0) (1,1) (2,0) (2,1) (2,2).
/// Each product sums a row left to right, \f$ (m_{i0} x_0 + m_{i1} x_1) + m_{i2} x_2 \f$, so every
/// caller gets the same bits for the same block and vector.

#include <array>

#include <Eigen/LU>  // 3x3 inverse

#include "drape/core/types.hpp"

namespace drape {

/// \f$ m x \f$ for the column-major block `m` (9 scalars) and the 3-vector `x`.
template <class Scalar>
inline std::array<Scalar, 3> block_times(const Scalar* m, const Scalar* x) {
  return {m[0] * x[0] + m[3] * x[1] + m[6] * x[2], m[1] * x[0] + m[4] * x[1] + m[7] * x[2],
          m[2] * x[0] + m[5] * x[1] + m[8] * x[2]};
}

/// The column-major block (9 scalars) of a symmetric block stored in 6 (see the file comment).
template <class Scalar>
inline void expand_symmetric_block(const Scalar* c, Scalar* full) {
  // The 3x3 layout, row by row:
  // clang-format off
  full[0] = c[0]; full[1] = c[1]; full[2] = c[3];
  full[3] = c[1]; full[4] = c[2]; full[5] = c[4];
  full[6] = c[3]; full[7] = c[4]; full[8] = c[5];
  // clang-format on
}

/// `inverse` = the inverse of block `m` (both column-major); false if it is singular (the inverse
/// is then not finite).
template <class Scalar>
inline bool invert_block(const Scalar* m, Scalar* inverse) {
  Eigen::Map<Mat3<Scalar>> out(inverse);
  out = Eigen::Map<const Mat3<Scalar>>(m).inverse();
  return out.allFinite();
}

}  // namespace drape
