#pragma once
/// \file coarse_block.hpp
/// Where the multigrid's Galerkin sums (multigrid_hierarchy.hpp and its AVX2 version) put a coarse
/// block: the block and its mirror.

namespace drape::detail {

/// Coarse block `cb` = s (9 values, column-major) and, unless it is on the diagonal, its mirror
/// block transposed[cb] = s^T: the Galerkin sums compute the blocks on or above the diagonal only.
template <class Scalar>
inline void store_coarse_block(const Scalar* s, int cb, const int* transposed, Scalar* coarse) {
  Scalar* c = coarse + 9 * cb;
  for (int q = 0; q < 9; ++q) c[q] = s[q];
  const int ct = transposed[cb];
  if (ct != cb) {
    Scalar* t = coarse + 9 * ct;
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) t[3 * col + row] = s[3 * row + col];
  }
}

}  // namespace drape::detail
