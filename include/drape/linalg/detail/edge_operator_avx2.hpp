#pragma once
/// \file edge_operator_avx2.hpp
/// The loads and stores of EdgeOperator's AVX2 product (edge_operator.hpp), overloaded for double
/// (four edges in 256-bit vectors) and float (in 128-bit ones): x_a - x_b of a group of four edges
/// as one vector per component, and the update of their rows, for each GroupShape. The product's
/// loop over colours and groups (EdgeOperator::add_symmetric_edge_products_avx2) is written once
/// over both.

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// Row r of x as (x0, x1, x2, 0) (row_avx2.hpp); zero for an end outside the system (r < 0).
__attribute__((target("avx2"), always_inline)) inline __m256d load_row_avx2(const double* x, int r) {
  return r >= 0 ? load_row3_avx2(x + 3 * r) : _mm256_setzero_pd();
}
/// y_r += (t0, t1), t2 (`Add`) or y_r -= them; nothing for r < 0.
template <bool Add>
__attribute__((target("avx2"), always_inline)) inline void update_row_avx2(double* y, int r, __m128d t01, __m128d t2) {
  if (r < 0) return;
  double* yr = y + 3 * r;
  const __m128d y01 = _mm_loadu_pd(yr), y2 = _mm_load_sd(yr + 2);
  _mm_storeu_pd(yr, Add ? _mm_add_pd(y01, t01) : _mm_sub_pd(y01, t01));
  _mm_store_sd(yr + 2, Add ? _mm_add_sd(y2, t2) : _mm_sub_sd(y2, t2));
}
/// x_a - x_b of four edges whose ends are the rows a..a+3 and b..b+3, one vector per component:
/// three whole loads per end instead of four gathers, and a 4 x 3 transpose.
__attribute__((target("avx2"), always_inline)) inline void load_consecutive_differences_avx2(const double* x, int a,
                                                                                             int b, __m256d& dx,
                                                                                             __m256d& dy, __m256d& dz) {
  const double *xa = x + 3 * a, *xb = x + 3 * b;
  // d0 = (x0 y0 z0 x1), d1 = (y1 z1 x2 y2), d2 = (z2 x3 y3 z3).
  const __m256d d0 = _mm256_sub_pd(_mm256_loadu_pd(xa), _mm256_loadu_pd(xb));
  const __m256d d1 = _mm256_sub_pd(_mm256_loadu_pd(xa + 4), _mm256_loadu_pd(xb + 4));
  const __m256d d2 = _mm256_sub_pd(_mm256_loadu_pd(xa + 8), _mm256_loadu_pd(xb + 8));
  // Blends give (x0 x3 x2 x1), (y1 y0 y3 y2), (z2 z1 z0 z3); one permutation each puts them in order.
  dx = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(d0, d1, 0b0100), d2, 0b0010), 0x6C);
  dy = _mm256_permute_pd(_mm256_blend_pd(_mm256_blend_pd(d0, d1, 0b1001), d2, 0b0100), 0b0101);
  dz = _mm256_permute4x64_pd(_mm256_blend_pd(_mm256_blend_pd(d0, d1, 0b0010), d2, 0b1001), 0xC6);
}
/// y_{a+i} += t_i and y_{b+i} -= t_i for i < 4, t given by components: the inverse of
/// load_consecutive_differences_avx2's transpose (its permutations are their own inverses).
__attribute__((target("avx2"), always_inline)) inline void update_consecutive_rows_avx2(double* y, int a, int b,
                                                                                        __m256d tx, __m256d ty,
                                                                                        __m256d tz) {
  const __m256d px = _mm256_permute4x64_pd(tx, 0x6C), py = _mm256_permute_pd(ty, 0b0101);
  const __m256d pz = _mm256_permute4x64_pd(tz, 0xC6);
  const __m256d t0 = _mm256_blend_pd(_mm256_blend_pd(px, py, 0b0010), pz, 0b0100);  // (tx0 ty0 tz0 tx1)
  const __m256d t1 = _mm256_blend_pd(_mm256_blend_pd(py, pz, 0b0010), px, 0b0100);  // (ty1 tz1 tx2 ty2)
  const __m256d t2 = _mm256_blend_pd(_mm256_blend_pd(pz, px, 0b0010), py, 0b0100);  // (tz2 tx3 ty3 tz3)
  double *ya = y + 3 * a, *yb = y + 3 * b;
  _mm256_storeu_pd(ya, _mm256_add_pd(_mm256_loadu_pd(ya), t0));
  _mm256_storeu_pd(ya + 4, _mm256_add_pd(_mm256_loadu_pd(ya + 4), t1));
  _mm256_storeu_pd(ya + 8, _mm256_add_pd(_mm256_loadu_pd(ya + 8), t2));
  _mm256_storeu_pd(yb, _mm256_sub_pd(_mm256_loadu_pd(yb), t0));
  _mm256_storeu_pd(yb + 4, _mm256_sub_pd(_mm256_loadu_pd(yb + 4), t1));
  _mm256_storeu_pd(yb + 8, _mm256_sub_pd(_mm256_loadu_pd(yb + 8), t2));
}
/// Four rows' differences (x, y, z, unused) as one vector per component (a 4 x 3 transpose).
__attribute__((target("avx2"), always_inline)) inline void transpose_differences_avx2(__m256d d0, __m256d d1,
                                                                                      __m256d d2, __m256d d3,
                                                                                      __m256d& dx, __m256d& dy,
                                                                                      __m256d& dz) {
  const __m256d lo01 = _mm256_unpacklo_pd(d0, d1), hi01 = _mm256_unpackhi_pd(d0, d1);
  const __m256d lo23 = _mm256_unpacklo_pd(d2, d3), hi23 = _mm256_unpackhi_pd(d2, d3);
  dx = _mm256_permute2f128_pd(lo01, lo23, 0x20);
  dy = _mm256_permute2f128_pd(hi01, hi23, 0x20);
  dz = _mm256_permute2f128_pd(lo01, lo23, 0x31);
}
/// x_a - x_b of an AdjacentPairs group (edge m joins rows a + 2m and a + 2m + 1): each edge's six
/// values are one window of x; nothing outside rows [a, a + 8) is read.
__attribute__((target("avx2"), always_inline)) inline void load_adjacent_pair_differences_avx2(const double* x, int a,
                                                                                               __m256d& dx,
                                                                                               __m256d& dy,
                                                                                               __m256d& dz) {
  const double* p = x + 3 * a;
  __m256d d[4];
  for (int m = 0; m < 4; ++m) {
    // (xa ya za xb) minus (za xb yb zb) turned to (xb yb zb za).
    const __m256d second = _mm256_permute4x64_pd(_mm256_loadu_pd(p + 6 * m + 2), 0x39);
    d[m] = _mm256_sub_pd(_mm256_loadu_pd(p + 6 * m), second);
  }
  transpose_differences_avx2(d[0], d[1], d[2], d[3], dx, dy, dz);
}
/// y_a += t and y_b -= t (as y_b + (-t), the same bits) for an AdjacentPairs group: per edge one
/// four-value and one two-value update of its six values, (tx ty tz -tx) and (-ty -tz).
__attribute__((target("avx2"), always_inline)) inline void update_adjacent_pairs_avx2(double* y, int a, __m256d tx,
                                                                                      __m256d ty, __m256d tz) {
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d ntx = _mm256_xor_pd(tx, sign), nty = _mm256_xor_pd(ty, sign), ntz = _mm256_xor_pd(tz, sign);
  const __m256d xy02 = _mm256_unpacklo_pd(tx, ty), xy13 = _mm256_unpackhi_pd(tx, ty);     // (tx0 ty0 tx2 ty2)
  const __m256d zx02 = _mm256_unpacklo_pd(tz, ntx), zx13 = _mm256_unpackhi_pd(tz, ntx);   // (tz0 -tx0 tz2 -tx2)
  const __m256d yz02 = _mm256_unpacklo_pd(nty, ntz), yz13 = _mm256_unpackhi_pd(nty, ntz);  // (-ty0 -tz0 -ty2 -tz2)
  const __m256d first[4] = {_mm256_permute2f128_pd(xy02, zx02, 0x20), _mm256_permute2f128_pd(xy13, zx13, 0x20),
                            _mm256_permute2f128_pd(xy02, zx02, 0x31), _mm256_permute2f128_pd(xy13, zx13, 0x31)};
  const __m128d second[4] = {_mm256_castpd256_pd128(yz02), _mm256_castpd256_pd128(yz13), _mm256_extractf128_pd(yz02, 1),
                             _mm256_extractf128_pd(yz13, 1)};
  double* p = y + 3 * a;
  for (int m = 0; m < 4; ++m) {
    _mm256_storeu_pd(p + 6 * m, _mm256_add_pd(_mm256_loadu_pd(p + 6 * m), first[m]));
    _mm_storeu_pd(p + 6 * m + 4, _mm_add_pd(_mm_loadu_pd(p + 6 * m + 4), second[m]));
  }
}
/// x_a - x_b of a TwoApartPairs group (rows a, a+2; a+1, a+3; a+4, a+6; a+5, a+7): rows a, a+1
/// minus rows a+2, a+3 are six values in a row, (dx0 dy0 dz0 dx1) and (dy1 dz1), the same from a+4.
__attribute__((target("avx2"), always_inline)) inline void load_two_apart_differences_avx2(const double* x, int a,
                                                                                           __m256d& dx, __m256d& dy,
                                                                                           __m256d& dz) {
  const double* p = x + 3 * a;
  const __m256d first = _mm256_sub_pd(_mm256_loadu_pd(p), _mm256_loadu_pd(p + 6));
  const __m256d third = _mm256_sub_pd(_mm256_loadu_pd(p + 12), _mm256_loadu_pd(p + 18));
  const __m128d second = _mm_sub_pd(_mm_loadu_pd(p + 4), _mm_loadu_pd(p + 10));
  const __m128d fourth = _mm_sub_pd(_mm_loadu_pd(p + 16), _mm_loadu_pd(p + 22));
  const __m256d lo = _mm256_permute2f128_pd(first, third, 0x20);  // (dx0 dy0 dx2 dy2)
  const __m256d hi = _mm256_permute2f128_pd(first, third, 0x31);  // (dz0 dx1 dz2 dx3)
  const __m256d tails = _mm256_insertf128_pd(_mm256_castpd128_pd256(second), fourth, 1);  // (dy1 dz1 dy3 dz3)
  dx = _mm256_blend_pd(lo, hi, 0b1010);
  dy = _mm256_shuffle_pd(lo, tails, 0b0101);
  dz = _mm256_shuffle_pd(hi, tails, 0b1010);
}
/// y_a += t and y_b -= t for a TwoApartPairs group: the inverse of the load's transpose, then the
/// six values of rows a, a+1 (and a+4, a+5) added and those of rows a+2, a+3 (a+6, a+7) subtracted.
__attribute__((target("avx2"), always_inline)) inline void update_two_apart_pairs_avx2(double* y, int a, __m256d tx,
                                                                                       __m256d ty, __m256d tz) {
  const __m256d lo = _mm256_unpacklo_pd(tx, ty);        // (tx0 ty0 tx2 ty2)
  const __m256d hi = _mm256_shuffle_pd(tz, tx, 0b1010);  // (tz0 tx1 tz2 tx3)
  const __m256d first = _mm256_permute2f128_pd(lo, hi, 0x20), third = _mm256_permute2f128_pd(lo, hi, 0x31);
  const __m256d tails = _mm256_unpackhi_pd(ty, tz);  // (ty1 tz1 ty3 tz3)
  const __m128d second = _mm256_castpd256_pd128(tails), fourth = _mm256_extractf128_pd(tails, 1);
  double* p = y + 3 * a;
  _mm256_storeu_pd(p, _mm256_add_pd(_mm256_loadu_pd(p), first));
  _mm_storeu_pd(p + 4, _mm_add_pd(_mm_loadu_pd(p + 4), second));
  _mm256_storeu_pd(p + 6, _mm256_sub_pd(_mm256_loadu_pd(p + 6), first));
  _mm_storeu_pd(p + 10, _mm_sub_pd(_mm_loadu_pd(p + 10), second));
  _mm256_storeu_pd(p + 12, _mm256_add_pd(_mm256_loadu_pd(p + 12), third));
  _mm_storeu_pd(p + 16, _mm_add_pd(_mm_loadu_pd(p + 16), fourth));
  _mm256_storeu_pd(p + 18, _mm256_sub_pd(_mm256_loadu_pd(p + 18), third));
  _mm_storeu_pd(p + 22, _mm_sub_pd(_mm_loadu_pd(p + 22), fourth));
}

/// x_a - x_b of a Gathered group (edge i joins rows[2i] and rows[2i + 1]): row by row, then
/// transposed.
__attribute__((target("avx2"), always_inline)) inline void load_gathered_differences_avx2(const double* x,
                                                                                          const int* rows, __m256d& dx,
                                                                                          __m256d& dy, __m256d& dz) {
  transpose_differences_avx2(_mm256_sub_pd(load_row_avx2(x, rows[0]), load_row_avx2(x, rows[1])),
                             _mm256_sub_pd(load_row_avx2(x, rows[2]), load_row_avx2(x, rows[3])),
                             _mm256_sub_pd(load_row_avx2(x, rows[4]), load_row_avx2(x, rows[5])),
                             _mm256_sub_pd(load_row_avx2(x, rows[6]), load_row_avx2(x, rows[7])), dx, dy, dz);
}
/// y_a += t and y_b -= t for a Gathered group, row by row: back to (tx, ty) pairs and tz per edge.
__attribute__((target("avx2"), always_inline)) inline void update_gathered_rows_avx2(double* y, const int* rows,
                                                                                     __m256d tx, __m256d ty,
                                                                                     __m256d tz) {
  const __m256d txy02 = _mm256_unpacklo_pd(tx, ty), txy13 = _mm256_unpackhi_pd(tx, ty);
  const __m128d tz01 = _mm256_castpd256_pd128(tz), tz23 = _mm256_extractf128_pd(tz, 1);
  const __m128d pair[4] = {_mm256_castpd256_pd128(txy02), _mm256_castpd256_pd128(txy13),
                           _mm256_extractf128_pd(txy02, 1), _mm256_extractf128_pd(txy13, 1)};
  const __m128d z[4] = {tz01, _mm_unpackhi_pd(tz01, tz01), tz23, _mm_unpackhi_pd(tz23, tz23)};
  for (int i = 0; i < 4; ++i) {
    update_row_avx2<true>(y, rows[2 * i], pair[i], z[i]);
    update_row_avx2<false>(y, rows[2 * i + 1], pair[i], z[i]);
  }
}

// The float twins of the helpers above (overloads by pointer type): four edges of a group in one
// 128-bit vector, lanes and masks as in the double ones. Pairs of floats move as 64-bit halves, so
// that no load or store reaches past the rows the group owns.

/// Two floats at p as the low half of a vector (the high half zero).
__attribute__((target("avx2"), always_inline)) inline __m128 load_pair_avx2(const float* p) {
  return _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(p));
}
/// Two floats at p and two at q as one vector (p0 p1 q0 q1).
__attribute__((target("avx2"), always_inline)) inline __m128 load_pairs_avx2(const float* p, const float* q) {
  return _mm_loadh_pi(load_pair_avx2(p), reinterpret_cast<const __m64*>(q));
}
/// Lanes 0, 1 of v to p and lanes 2, 3 to q: the inverse of load_pairs_avx2.
__attribute__((target("avx2"), always_inline)) inline void store_pairs_avx2(float* p, float* q, __m128 v) {
  _mm_storel_pi(reinterpret_cast<__m64*>(p), v);
  _mm_storeh_pi(reinterpret_cast<__m64*>(q), v);
}
/// Row r of x as (x0, x1, x2, 0) from its three floats alone (row_avx2.hpp); zero for r < 0.
__attribute__((target("avx2"), always_inline)) inline __m128 load_row_avx2(const float* x, int r) {
  return r >= 0 ? load_row3_avx2(x + 3 * r) : _mm_setzero_ps();
}
/// y_r += (t0, t1, t2) (`Add`) or y_r -= them, t = (t0 t1 t2 unused); nothing for r < 0.
template <bool Add>
__attribute__((target("avx2"), always_inline)) inline void update_row_avx2(float* y, int r, __m128 t) {
  if (r < 0) return;
  const __m128 yv = load_row3_avx2(y + 3 * r);
  store_row3_avx2(y + 3 * r, Add ? _mm_add_ps(yv, t) : _mm_sub_ps(yv, t), false);
}
/// load_consecutive_differences_avx2 for float: three whole loads per end (rows a..a+3 are twelve
/// floats) and the same blends, the permutations in _mm_permute_ps's encoding (2 bits per lane).
__attribute__((target("avx2"), always_inline)) inline void load_consecutive_differences_avx2(const float* x, int a,
                                                                                             int b, __m128& dx,
                                                                                             __m128& dy, __m128& dz) {
  const float *xa = x + 3 * a, *xb = x + 3 * b;
  // d0 = (x0 y0 z0 x1), d1 = (y1 z1 x2 y2), d2 = (z2 x3 y3 z3).
  const __m128 d0 = _mm_sub_ps(_mm_loadu_ps(xa), _mm_loadu_ps(xb));
  const __m128 d1 = _mm_sub_ps(_mm_loadu_ps(xa + 4), _mm_loadu_ps(xb + 4));
  const __m128 d2 = _mm_sub_ps(_mm_loadu_ps(xa + 8), _mm_loadu_ps(xb + 8));
  dx = _mm_permute_ps(_mm_blend_ps(_mm_blend_ps(d0, d1, 0b0100), d2, 0b0010), 0x6C);
  dy = _mm_permute_ps(_mm_blend_ps(_mm_blend_ps(d0, d1, 0b1001), d2, 0b0100), 0xB1);  // swaps pairs
  dz = _mm_permute_ps(_mm_blend_ps(_mm_blend_ps(d0, d1, 0b0010), d2, 0b1001), 0xC6);
}
/// update_consecutive_rows_avx2 for float: y_{a+i} += t_i, y_{b+i} -= t_i for i < 4.
__attribute__((target("avx2"), always_inline)) inline void update_consecutive_rows_avx2(float* y, int a, int b,
                                                                                        __m128 tx, __m128 ty,
                                                                                        __m128 tz) {
  const __m128 px = _mm_permute_ps(tx, 0x6C), py = _mm_permute_ps(ty, 0xB1), pz = _mm_permute_ps(tz, 0xC6);
  const __m128 t0 = _mm_blend_ps(_mm_blend_ps(px, py, 0b0010), pz, 0b0100);  // (tx0 ty0 tz0 tx1)
  const __m128 t1 = _mm_blend_ps(_mm_blend_ps(py, pz, 0b0010), px, 0b0100);  // (ty1 tz1 tx2 ty2)
  const __m128 t2 = _mm_blend_ps(_mm_blend_ps(pz, px, 0b0010), py, 0b0100);  // (tz2 tx3 ty3 tz3)
  float *ya = y + 3 * a, *yb = y + 3 * b;
  _mm_storeu_ps(ya, _mm_add_ps(_mm_loadu_ps(ya), t0));
  _mm_storeu_ps(ya + 4, _mm_add_ps(_mm_loadu_ps(ya + 4), t1));
  _mm_storeu_ps(ya + 8, _mm_add_ps(_mm_loadu_ps(ya + 8), t2));
  _mm_storeu_ps(yb, _mm_sub_ps(_mm_loadu_ps(yb), t0));
  _mm_storeu_ps(yb + 4, _mm_sub_ps(_mm_loadu_ps(yb + 4), t1));
  _mm_storeu_ps(yb + 8, _mm_sub_ps(_mm_loadu_ps(yb + 8), t2));
}
/// Four rows' differences (x, y, z, unused) as one vector per component (a 4 x 3 transpose).
__attribute__((target("avx2"), always_inline)) inline void transpose_differences_avx2(__m128 d0, __m128 d1, __m128 d2,
                                                                                      __m128 d3, __m128& dx,
                                                                                      __m128& dy, __m128& dz) {
  const __m128 lo01 = _mm_unpacklo_ps(d0, d1), lo23 = _mm_unpacklo_ps(d2, d3);  // (x0 x1 y0 y1), (x2 x3 y2 y3)
  const __m128 hi01 = _mm_unpackhi_ps(d0, d1), hi23 = _mm_unpackhi_ps(d2, d3);  // (z0 z1 . .), (z2 z3 . .)
  dx = _mm_movelh_ps(lo01, lo23);
  dy = _mm_movehl_ps(lo23, lo01);
  dz = _mm_movelh_ps(hi01, hi23);
}
/// load_adjacent_pair_differences_avx2 for float: nothing outside rows [a, a + 8) is read.
__attribute__((target("avx2"), always_inline)) inline void load_adjacent_pair_differences_avx2(const float* x, int a,
                                                                                               __m128& dx, __m128& dy,
                                                                                               __m128& dz) {
  const float* p = x + 3 * a;
  __m128 d[4];
  for (int m = 0; m < 4; ++m) {
    // (xa ya za xb) minus (za xb yb zb) turned to (xb yb zb za).
    const __m128 second = _mm_permute_ps(_mm_loadu_ps(p + 6 * m + 2), 0x39);
    d[m] = _mm_sub_ps(_mm_loadu_ps(p + 6 * m), second);
  }
  transpose_differences_avx2(d[0], d[1], d[2], d[3], dx, dy, dz);
}
/// update_adjacent_pairs_avx2 for float: per edge (tx ty tz -tx) as one vector, and the (-ty -tz)
/// of two edges as one vector of two halves.
__attribute__((target("avx2"), always_inline)) inline void update_adjacent_pairs_avx2(float* y, int a, __m128 tx,
                                                                                      __m128 ty, __m128 tz) {
  const __m128 sign = _mm_set1_ps(-0.0f);
  const __m128 ntx = _mm_xor_ps(tx, sign), nty = _mm_xor_ps(ty, sign), ntz = _mm_xor_ps(tz, sign);
  const __m128 xy01 = _mm_unpacklo_ps(tx, ty), xy23 = _mm_unpackhi_ps(tx, ty);     // (tx0 ty0 tx1 ty1)
  const __m128 zx01 = _mm_unpacklo_ps(tz, ntx), zx23 = _mm_unpackhi_ps(tz, ntx);   // (tz0 -tx0 tz1 -tx1)
  const __m128 yz01 = _mm_unpacklo_ps(nty, ntz), yz23 = _mm_unpackhi_ps(nty, ntz);  // (-ty0 -tz0 -ty1 -tz1)
  const __m128 first[4] = {_mm_movelh_ps(xy01, zx01), _mm_movehl_ps(zx01, xy01), _mm_movelh_ps(xy23, zx23),
                           _mm_movehl_ps(zx23, xy23)};
  float* p = y + 3 * a;
  for (int m = 0; m < 4; ++m) _mm_storeu_ps(p + 6 * m, _mm_add_ps(_mm_loadu_ps(p + 6 * m), first[m]));
  store_pairs_avx2(p + 4, p + 10, _mm_add_ps(load_pairs_avx2(p + 4, p + 10), yz01));
  store_pairs_avx2(p + 16, p + 22, _mm_add_ps(load_pairs_avx2(p + 16, p + 22), yz23));
}
/// load_two_apart_differences_avx2 for float: (dx0 dy0 dz0 dx1) and (dx2 dy2 dz2 dx3) whole, the
/// (dy1 dz1) and (dy3 dz3) of both halves of the window in one vector.
__attribute__((target("avx2"), always_inline)) inline void load_two_apart_differences_avx2(const float* x, int a,
                                                                                           __m128& dx, __m128& dy,
                                                                                           __m128& dz) {
  const float* p = x + 3 * a;
  const __m128 first = _mm_sub_ps(_mm_loadu_ps(p), _mm_loadu_ps(p + 6));
  const __m128 third = _mm_sub_ps(_mm_loadu_ps(p + 12), _mm_loadu_ps(p + 18));
  const __m128 tails = _mm_sub_ps(load_pairs_avx2(p + 4, p + 16), load_pairs_avx2(p + 10, p + 22));
  const __m128 lo = _mm_movelh_ps(first, third);  // (dx0 dy0 dx2 dy2)
  const __m128 hi = _mm_movehl_ps(third, first);  // (dz0 dx1 dz2 dx3)
  dx = _mm_blend_ps(lo, hi, 0b1010);
  // (dy0 dy2 dy1 dy3), then lanes 1 and 2 swapped.
  dy = _mm_permute_ps(_mm_shuffle_ps(lo, tails, _MM_SHUFFLE(2, 0, 3, 1)), _MM_SHUFFLE(3, 1, 2, 0));
  dz = _mm_blend_ps(hi, tails, 0b1010);
}
/// update_two_apart_pairs_avx2 for float: the inverse of the load's transpose, rows a, a+1 (and
/// a+4, a+5) added to and rows a+2, a+3 (a+6, a+7) subtracted from.
__attribute__((target("avx2"), always_inline)) inline void update_two_apart_pairs_avx2(float* y, int a, __m128 tx,
                                                                                       __m128 ty, __m128 tz) {
  const __m128 swapped_ty = _mm_permute_ps(ty, 0xB1);       // (ty1 ty0 ty3 ty2)
  const __m128 lo = _mm_blend_ps(tx, swapped_ty, 0b1010);   // (tx0 ty0 tx2 ty2)
  const __m128 hi = _mm_blend_ps(tz, tx, 0b1010);           // (tz0 tx1 tz2 tx3)
  const __m128 tails = _mm_blend_ps(swapped_ty, tz, 0b1010);  // (ty1 tz1 ty3 tz3)
  const __m128 first = _mm_movelh_ps(lo, hi), third = _mm_movehl_ps(hi, lo);
  float* p = y + 3 * a;
  _mm_storeu_ps(p, _mm_add_ps(_mm_loadu_ps(p), first));
  _mm_storeu_ps(p + 6, _mm_sub_ps(_mm_loadu_ps(p + 6), first));
  _mm_storeu_ps(p + 12, _mm_add_ps(_mm_loadu_ps(p + 12), third));
  _mm_storeu_ps(p + 18, _mm_sub_ps(_mm_loadu_ps(p + 18), third));
  store_pairs_avx2(p + 4, p + 16, _mm_add_ps(load_pairs_avx2(p + 4, p + 16), tails));
  store_pairs_avx2(p + 10, p + 22, _mm_sub_ps(load_pairs_avx2(p + 10, p + 22), tails));
}

/// load_gathered_differences_avx2 for float.
__attribute__((target("avx2"), always_inline)) inline void load_gathered_differences_avx2(const float* x,
                                                                                          const int* rows, __m128& dx,
                                                                                          __m128& dy, __m128& dz) {
  transpose_differences_avx2(_mm_sub_ps(load_row_avx2(x, rows[0]), load_row_avx2(x, rows[1])),
                             _mm_sub_ps(load_row_avx2(x, rows[2]), load_row_avx2(x, rows[3])),
                             _mm_sub_ps(load_row_avx2(x, rows[4]), load_row_avx2(x, rows[5])),
                             _mm_sub_ps(load_row_avx2(x, rows[6]), load_row_avx2(x, rows[7])), dx, dy, dz);
}
/// update_gathered_rows_avx2 for float: back to (tx ty tz 0) per edge, a 4 x 4 transpose with a
/// zero fourth row.
__attribute__((target("avx2"), always_inline)) inline void update_gathered_rows_avx2(float* y, const int* rows,
                                                                                     __m128 tx, __m128 ty, __m128 tz) {
  const __m128 zero = _mm_setzero_ps();
  const __m128 xy01 = _mm_unpacklo_ps(tx, ty), xy23 = _mm_unpackhi_ps(tx, ty);  // (tx0 ty0 tx1 ty1)
  const __m128 z01 = _mm_unpacklo_ps(tz, zero), z23 = _mm_unpackhi_ps(tz, zero);  // (tz0 0 tz1 0)
  const __m128 t[4] = {_mm_movelh_ps(xy01, z01), _mm_movehl_ps(z01, xy01), _mm_movelh_ps(xy23, z23),
                       _mm_movehl_ps(z23, xy23)};
  for (int i = 0; i < 4; ++i) {
    update_row_avx2<true>(y, rows[2 * i], t[i]);
    update_row_avx2<false>(y, rows[2 * i + 1], t[i]);
  }
}

}  // namespace drape::detail
#endif
