#pragma once
/// \file row_avx2.hpp
/// Four values of one scalar type in one AVX2 register (`__m256d` for double, `__m128` for float):
/// overloads by type, so that a kernel is written once over float and double and runs the same
/// instructions on half the bytes for float. A block row's three values take lanes 0-2 (the fourth
/// lane unused): they are loaded and stored without touching the value after them (the next row's,
/// or past the end of the vector), and a 3x3 block times a row is three columns times broadcast
/// values, summed in block_times()'s order (no fused multiply-add), so it gives block3.hpp's bits.

#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// The register of four `Scalar` values: `__m256d` for double, `__m128` for float.
template <class Scalar>
struct Lanes4Avx2;
template <>
struct Lanes4Avx2<double> {
  using type = __m256d;
};
template <>
struct Lanes4Avx2<float> {
  using type = __m128;
};

/// The four values at `p` (no alignment needed).
__attribute__((target("avx2"), always_inline)) inline __m256d load4_avx2(const double* p) { return _mm256_loadu_pd(p); }
__attribute__((target("avx2"), always_inline)) inline __m128 load4_avx2(const float* p) { return _mm_loadu_ps(p); }

/// The value at `p` in every lane.
__attribute__((target("avx2"), always_inline)) inline __m256d broadcast4_avx2(const double* p) {
  return _mm256_broadcast_sd(p);
}
__attribute__((target("avx2"), always_inline)) inline __m128 broadcast4_avx2(const float* p) {
  return _mm_broadcast_ss(p);
}

/// `s` in every lane.
__attribute__((target("avx2"), always_inline)) inline __m256d set4_avx2(double s) { return _mm256_set1_pd(s); }
__attribute__((target("avx2"), always_inline)) inline __m128 set4_avx2(float s) { return _mm_set1_ps(s); }

/// Lane by lane a + b, a - b, a * b.
__attribute__((target("avx2"), always_inline)) inline __m256d add_avx2(__m256d a, __m256d b) {
  return _mm256_add_pd(a, b);
}
__attribute__((target("avx2"), always_inline)) inline __m128 add_avx2(__m128 a, __m128 b) { return _mm_add_ps(a, b); }
__attribute__((target("avx2"), always_inline)) inline __m256d sub_avx2(__m256d a, __m256d b) {
  return _mm256_sub_pd(a, b);
}
__attribute__((target("avx2"), always_inline)) inline __m128 sub_avx2(__m128 a, __m128 b) { return _mm_sub_ps(a, b); }
__attribute__((target("avx2"), always_inline)) inline __m256d mul_avx2(__m256d a, __m256d b) {
  return _mm256_mul_pd(a, b);
}
__attribute__((target("avx2"), always_inline)) inline __m128 mul_avx2(__m128 a, __m128 b) { return _mm_mul_ps(a, b); }

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

/// The columns of the 3x3 block at `m` (column-major) in lanes 0-2 of c0, c1, c2; their fourth
/// lanes hold other values of the block and are never stored.
__attribute__((target("avx2"), always_inline)) inline void block_columns_avx2(const double* m, __m256d& c0,
                                                                              __m256d& c1, __m256d& c2) {
  c0 = _mm256_loadu_pd(m);
  c1 = _mm256_loadu_pd(m + 3);
  c2 = _mm256_permute4x64_pd(_mm256_loadu_pd(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
}
__attribute__((target("avx2"), always_inline)) inline void block_columns_avx2(const float* m, __m128& c0, __m128& c1,
                                                                              __m128& c2) {
  c0 = _mm_loadu_ps(m);
  c1 = _mm_loadu_ps(m + 3);
  c2 = _mm_permute_ps(_mm_loadu_ps(m + 5), 0x39);  // m6 m7 m8 m5: stays in the block
}

/// The 3x3 block at `m` (column-major) times the three values at `v`, in lanes 0-2:
/// (c0 v0 + c1 v1) + c2 v2, block_times()'s order.
template <class Scalar>
__attribute__((target("avx2"), always_inline)) inline typename Lanes4Avx2<Scalar>::type block_times_avx2(
    const Scalar* m, const Scalar* v) {
  using Lanes = typename Lanes4Avx2<Scalar>::type;
  Lanes c0, c1, c2;
  block_columns_avx2(m, c0, c1, c2);
  const Lanes p0 = mul_avx2(c0, broadcast4_avx2(v)), p1 = mul_avx2(c1, broadcast4_avx2(v + 1));
  const Lanes p2 = mul_avx2(c2, broadcast4_avx2(v + 2));
  return add_avx2(add_avx2(p0, p1), p2);
}

}  // namespace drape::detail
#endif
