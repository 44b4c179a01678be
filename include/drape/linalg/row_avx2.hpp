#pragma once
/// \file row_avx2.hpp
/// A block row's three values in one AVX2 register (the fourth lane unused) and back, without
/// touching the value after them (the next row's, or past the end of the vector).

#include "drape/core/instruction_set.hpp"

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

}  // namespace drape::detail
#endif
