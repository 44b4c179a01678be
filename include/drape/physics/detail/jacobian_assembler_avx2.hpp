#pragma once
/// \file jacobian_assembler_avx2.hpp
/// The first pass of JacobianAssembler's system assembly (jacobian_assembler.hpp) with AVX2, for
/// the symmetric Jacobian variants in double.

#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// Pass 1 of the system assembly for four springs with AVX2 (symmetric variants, double): the
/// spring's C (6 values, into `c`, grouped as EdgeOperator::value_index()) and g (into `g`, grouped
/// likewise), from positions and velocities gathered out of the 3 x n storage. linearise_spring's
/// operations and the pass's in their order (Eigen sums a 3-vector's squares and products left to
/// right) and no FMA: the bits of the scalar pass.
__attribute__((target("avx2"))) inline void symmetric_spring_group_avx2(const double* x, const double* v, const int* ia,
                                                                        const int* ib, const double* rest,
                                                                        const double* ks, const double* kd, double dt,
                                                                        bool spd, double* c, double* g) {
  const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ia));
  const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(ib));
  const __m128i a3 = _mm_add_epi32(a, _mm_add_epi32(a, a)), b3 = _mm_add_epi32(b, _mm_add_epi32(b, b));
  // The masked gather with a zero source: GCC 12 warns about the plain one's uninitialised source.
  const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), zero = _mm256_setzero_pd();
  __m256d d[3], w[3], u[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = _mm256_sub_pd(_mm256_mask_i32gather_pd(zero, x + k, b3, all, 8),
                         _mm256_mask_i32gather_pd(zero, x + k, a3, all, 8));
    w[k] = _mm256_sub_pd(_mm256_mask_i32gather_pd(zero, v + k, b3, all, 8),
                         _mm256_mask_i32gather_pd(zero, v + k, a3, all, 8));
  }
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d length = _mm256_sqrt_pd(
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])), _mm256_mul_pd(d[2], d[2])));
  const __m256d inverse_length = _mm256_div_pd(one, length);
  for (int k = 0; k < 3; ++k) u[k] = _mm256_mul_pd(d[k], inverse_length);
  const __m256d wu =
      _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(w[0], u[0]), _mm256_mul_pd(w[1], u[1])), _mm256_mul_pd(w[2], u[2]));
  const __m256d l = _mm256_loadu_pd(rest), k_s = _mm256_loadu_pd(ks), k_d = _mm256_loadu_pd(kd);
  const __m256d phi = _mm256_add_pd(_mm256_mul_pd(k_s, _mm256_sub_pd(length, l)), _mm256_mul_pd(k_d, wu));
  __m256d t = _mm256_sub_pd(one, _mm256_mul_pd(l, inverse_length));
  if (spd) t = _mm256_max_pd(zero, t);  // (t < 0) ? 0 : t, as std::max(t, 0)
  const __m256d k_uu = _mm256_mul_pd(k_s, _mm256_sub_pd(one, t)), k_i = _mm256_mul_pd(k_s, t);
  const __m256d vdt = _mm256_set1_pd(dt), dt2 = _mm256_set1_pd(dt * dt);
  const __m256d p = _mm256_add_pd(_mm256_mul_pd(vdt, k_d), _mm256_mul_pd(dt2, k_uu));
  const __m256d q = _mm256_mul_pd(dt2, k_i);
  const __m256d g_u = _mm256_add_pd(_mm256_mul_pd(vdt, phi), _mm256_mul_pd(_mm256_mul_pd(dt2, k_uu), wu));
  const __m256d pu0 = _mm256_mul_pd(p, u[0]), pu1 = _mm256_mul_pd(p, u[1]), pu2 = _mm256_mul_pd(p, u[2]);
  _mm256_storeu_pd(c, _mm256_add_pd(_mm256_mul_pd(pu0, u[0]), q));
  _mm256_storeu_pd(c + 4, _mm256_mul_pd(pu1, u[0]));
  _mm256_storeu_pd(c + 8, _mm256_add_pd(_mm256_mul_pd(pu1, u[1]), q));
  _mm256_storeu_pd(c + 12, _mm256_mul_pd(pu2, u[0]));
  _mm256_storeu_pd(c + 16, _mm256_mul_pd(pu2, u[1]));
  _mm256_storeu_pd(c + 20, _mm256_add_pd(_mm256_mul_pd(pu2, u[2]), q));
  for (int k = 0; k < 3; ++k)
    _mm256_storeu_pd(g + 4 * k, _mm256_add_pd(_mm256_mul_pd(g_u, u[k]), _mm256_mul_pd(q, w[k])));
}

}  // namespace drape::detail
#endif
