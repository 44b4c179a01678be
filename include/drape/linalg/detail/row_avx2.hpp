#pragma once
/// \file row_avx2.hpp
/// A block row's three values in one AVX2 register (the fourth lane unused; `__m256d` for double,
/// `__m128` for float) and back, without touching the value after them (the next row's, or past
/// the end of the vector).

#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// (x0, x1, x2, 0) from the three values at `x`.
__attribute__((target("avx2"), always_inline)) inline __m256d load_row3_avx2(const double* x) {
  return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(x)), _mm_load_sd(x + 2), 1);
}

/// The first three lanes of `v` stored at `x` (`add` false) or added to the values there.
__attribute__((target("avx2"), always_inline)) inline void store_row3_avx2(double* x, __m256d v, bool add) {
  __m128d v01 = _mm256_castpd256_pd128(v), v2 = _mm256_extractf128_pd(v, 1);
  if (add) {
    v01 = _mm_add_pd(_mm_loadu_pd(x), v01);
    v2 = _mm_add_sd(_mm_load_sd(x + 2), v2);
  }
  _mm_storeu_pd(x, v01);
  _mm_store_sd(x + 2, v2);
}

/// (x0, x1, x2, 0) from the three floats at `x`. The first two as one 64-bit load that may be
/// unaligned and may alias floats (GCC's _mm_load_sd dereferences a double*).
__attribute__((target("avx2"), always_inline)) inline __m128 load_row3_avx2(const float* x) {
  return _mm_movelh_ps(_mm_castsi128_ps(_mm_loadu_si64(x)), _mm_load_ss(x + 2));
}

/// The first three lanes of `v` stored at `x` (`add` false) or added to the values there.
__attribute__((target("avx2"), always_inline)) inline void store_row3_avx2(float* x, __m128 v, bool add) {
  if (add) v = _mm_add_ps(load_row3_avx2(x), v);  // lane 3 is x's 0 plus v's: never stored
  _mm_storeu_si64(x, _mm_castps_si128(v));
  _mm_store_ss(x + 2, _mm_movehl_ps(v, v));
}

}  // namespace drape::detail
#endif
