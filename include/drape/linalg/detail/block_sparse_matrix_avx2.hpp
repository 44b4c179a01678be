#pragma once
/// \file block_sparse_matrix_avx2.hpp
/// BlockSparseMatrix::residual_rows() (block_sparse_matrix.hpp) with AVX2, for double and float.

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
namespace drape::detail {

/// r = b - A x on the block rows [begin, end) of the block CSR arrays (row begins `rb`, columns
/// `col`, values `val`), a row in one register (row_avx2.hpp): each block times x as three columns
/// times broadcast x_j, summed (c0 x0 + c1 x1) + c2 x2 like block_times(); the fourth lane is never
/// stored.
template <class Scalar>
__attribute__((target("avx2"))) inline void block_residual_rows_avx2(const int* rb, const int* col, const Scalar* val,
                                                                     const Scalar* b, const Scalar* x, Scalar* r,
                                                                     int begin, int end) {
  for (int row = begin; row < end; ++row) {
    typename Lanes4Avx2<Scalar>::type y = load_row3_avx2(b + 3 * row);
    for (int k = rb[row]; k < rb[row + 1]; ++k) y = sub_avx2(y, block_times_avx2(val + 9 * k, x + 3 * col[k]));
    store_row3_avx2(r + 3 * row, y, false);
  }
}

}  // namespace drape::detail
#endif
