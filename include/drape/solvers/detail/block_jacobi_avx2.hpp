#pragma once
/// \file block_jacobi_avx2.hpp
/// BlockJacobi::smooth_rows() (block_jacobi.hpp) with AVX2, for double and float.

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// BlockJacobi::smooth_rows() for double with AVX2: D_r^-1 t_r as three columns times broadcast
/// t_r components, summed (c0 t0 + c1 t1) + c2 t2 like block_times(), then scaled and stored or
/// added: the baseline's operations in its order (no FMA), so the same bits.
__attribute__((target("avx2"))) inline void jacobi_smooth_rows_avx2(const double* inverse, const double* t,
                                                                    double omega, bool first, double* x, int begin,
                                                                    int end) {
  const __m256d w = _mm256_set1_pd(omega);
  for (int row = begin; row < end; ++row) {
    const double* m = inverse + 9 * row;
    const double* tr = t + 3 * row;
    const __m256d c0 = _mm256_loadu_pd(m), c1 = _mm256_loadu_pd(m + 3);
    const __m256d c2 = _mm256_permute4x64_pd(_mm256_loadu_pd(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
    const __m256d d = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(c0, _mm256_broadcast_sd(tr)), _mm256_mul_pd(c1, _mm256_broadcast_sd(tr + 1))),
        _mm256_mul_pd(c2, _mm256_broadcast_sd(tr + 2)));
    store_row3_avx2(x + 3 * row, _mm256_mul_pd(w, d), !first);
  }
}

/// The float twin: the three columns in one `__m128` each, (c0 t0 + c1 t1) + c2 t2 scaled like the double one.
__attribute__((target("avx2"))) inline void jacobi_smooth_rows_avx2(const float* inverse, const float* t, float omega,
                                                                    bool first, float* x, int begin, int end) {
  const __m128 w = _mm_set1_ps(omega);
  for (int row = begin; row < end; ++row) {
    const float* m = inverse + 9 * row;
    const float* tr = t + 3 * row;
    const __m128 c0 = _mm_loadu_ps(m), c1 = _mm_loadu_ps(m + 3);
    const __m128 c2 = _mm_permute_ps(_mm_loadu_ps(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
    const __m128 p0 = _mm_mul_ps(c0, _mm_broadcast_ss(tr)), p1 = _mm_mul_ps(c1, _mm_broadcast_ss(tr + 1)),
                 p2 = _mm_mul_ps(c2, _mm_broadcast_ss(tr + 2));
    store_row3_avx2(x + 3 * row, _mm_mul_ps(w, _mm_add_ps(_mm_add_ps(p0, p1), p2)), !first);
  }
}

}  // namespace drape::detail
#endif
