#pragma once
/// \file block_sparse_matrix_avx2.hpp
/// BlockSparseMatrix::residual_rows() (block_sparse_matrix.hpp) with AVX2, for double and float.

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// BlockSparseMatrix::residual_rows() for double with AVX2: a block times x as three columns
/// (m_0j, m_1j, m_2j, *) times broadcast x_j, summed (c0 x0 + c1 x1) + c2 x2 like block_times();
/// the fourth lane is never stored.
__attribute__((target("avx2"))) inline void block_residual_rows_avx2(const int* rb, const int* col, const double* val,
                                                                     const double* b, const double* x, double* r,
                                                                     int begin, int end) {
  for (int row = begin; row < end; ++row) {
    __m256d y =
        _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(b + 3 * row)), _mm_load_sd(b + 3 * row + 2), 1);
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const double* m = val + 9 * k;
      const double* xc = x + 3 * col[k];
      const __m256d c0 = _mm256_loadu_pd(m), c1 = _mm256_loadu_pd(m + 3);
      const __m256d c2 = _mm256_permute4x64_pd(_mm256_loadu_pd(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
      const __m256d t = _mm256_add_pd(
          _mm256_add_pd(_mm256_mul_pd(c0, _mm256_broadcast_sd(xc)), _mm256_mul_pd(c1, _mm256_broadcast_sd(xc + 1))),
          _mm256_mul_pd(c2, _mm256_broadcast_sd(xc + 2)));
      y = _mm256_sub_pd(y, t);
    }
    _mm_storeu_pd(r + 3 * row, _mm256_castpd256_pd128(y));
    _mm_store_sd(r + 3 * row + 2, _mm256_extractf128_pd(y, 1));
  }
}

/// The float twin: a row and a block's columns in one `__m128` each, summed (c0 x0 + c1 x1) + c2 x2 likewise.
__attribute__((target("avx2"))) inline void block_residual_rows_avx2(const int* rb, const int* col, const float* val,
                                                                     const float* b, const float* x, float* r,
                                                                     int begin, int end) {
  for (int row = begin; row < end; ++row) {
    __m128 y = load_row3_avx2(b + 3 * row);
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const float* m = val + 9 * k;
      const float* xc = x + 3 * col[k];
      const __m128 c0 = _mm_loadu_ps(m), c1 = _mm_loadu_ps(m + 3);
      const __m128 c2 = _mm_permute_ps(_mm_loadu_ps(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
      const __m128 p0 = _mm_mul_ps(c0, _mm_broadcast_ss(xc)), p1 = _mm_mul_ps(c1, _mm_broadcast_ss(xc + 1)),
                   p2 = _mm_mul_ps(c2, _mm_broadcast_ss(xc + 2));
      y = _mm_sub_ps(y, _mm_add_ps(_mm_add_ps(p0, p1), p2));
    }
    store_row3_avx2(r + 3 * row, y, false);
  }
}

}  // namespace drape::detail
#endif
