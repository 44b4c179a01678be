#pragma once
/// \file multigrid_hierarchy_avx2.hpp
/// MultigridHierarchy's Galerkin sums and transfers (multigrid_hierarchy.hpp) with AVX2, for double
/// and float.

#include <type_traits>

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/solvers/detail/coarse_block.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>

namespace drape::detail {

/// MultigridHierarchy::galerkin() from double fine blocks with AVX2, coarse blocks upper[u] for u in
/// [begin, end): values 0-3 and 4-7 of the nine as two vectors, the ninth alone, each summed over
/// the fine blocks in the same order as the baseline loop (no FMA): the same bits. `Weight` and
/// `Out` are double, or float for the float hierarchy's level 1 summed from the double matrix
/// (single_precision_multigrid.hpp): the float weights widened, the sums rounded once at the store.
template <class Weight, class Out>
__attribute__((target("avx2"))) inline void galerkin_blocks_avx2(const int* upper, const int* g_begin,
                                                                 const int* g_block, const Weight* g_weight,
                                                                 const int* transposed, const double* fine,
                                                                 Out* coarse, int begin, int end) {
  for (int u = begin; u < end; ++u) {
    __m256d s0 = _mm256_setzero_pd(), s1 = _mm256_setzero_pd();
    double s8 = 0;
    for (int e = g_begin[u]; e < g_begin[u + 1]; ++e) {
      const double weight = static_cast<double>(g_weight[e]);
      const __m256d w = _mm256_set1_pd(weight);
      const double* f = fine + 9 * g_block[e];
      s0 = _mm256_add_pd(s0, _mm256_mul_pd(w, _mm256_loadu_pd(f)));
      s1 = _mm256_add_pd(s1, _mm256_mul_pd(w, _mm256_loadu_pd(f + 4)));
      s8 += weight * f[8];
    }
    alignas(32) Out s[9];
    if constexpr (std::is_same_v<Out, double>) {
      _mm256_store_pd(s, s0);
      _mm256_storeu_pd(s + 4, s1);
    } else {
      _mm_store_ps(s, _mm256_cvtpd_ps(s0));
      _mm_storeu_ps(s + 4, _mm256_cvtpd_ps(s1));
    }
    s[8] = static_cast<Out>(s8);
    store_coarse_block(s, upper[u], transposed, coarse);
  }
}

/// The float twin: values 0-7 as one vector, the ninth alone, each summed in the baseline's order.
__attribute__((target("avx2"))) inline void galerkin_blocks_avx2(const int* upper, const int* g_begin,
                                                                 const int* g_block, const float* g_weight,
                                                                 const int* transposed, const float* fine,
                                                                 float* coarse, int begin, int end) {
  for (int u = begin; u < end; ++u) {
    __m256 s07 = _mm256_setzero_ps();
    float ninth = 0;
    for (int e = g_begin[u]; e < g_begin[u + 1]; ++e) {
      const float* f = fine + 9 * g_block[e];
      s07 = _mm256_add_ps(s07, _mm256_mul_ps(_mm256_broadcast_ss(g_weight + e), _mm256_loadu_ps(f)));
      ninth += g_weight[e] * f[8];
    }
    alignas(32) float s[9];
    _mm256_store_ps(s, s07);
    s[8] = ninth;
    store_coarse_block(s, upper[u], transposed, coarse);
  }
}

/// MultigridHierarchy's transfers with AVX2, rows [begin, end) of `to`: the weighted sum of
/// `from`'s rows [index_begin[r], index_begin[r + 1]) of (index_row, index_weight), a row in one
/// register (row_avx2.hpp), stored (`add` false: restriction) or added (prolongation); the
/// baseline's order, no FMA.
template <class Scalar>
__attribute__((target("avx2"))) inline void transfer_rows_avx2(const int* index_begin, const int* index_row,
                                                               const Scalar* index_weight, const Scalar* from,
                                                               Scalar* to, bool add, int begin, int end) {
  for (int r = begin; r < end; ++r) {
    typename Lanes4Avx2<Scalar>::type s = set4_avx2(Scalar(0));
    for (int e = index_begin[r]; e < index_begin[r + 1]; ++e)
      s = add_avx2(s, mul_avx2(broadcast4_avx2(index_weight + e), load_row3_avx2(from + 3 * index_row[e])));
    store_row3_avx2(to + 3 * r, s, add);
  }
}

}  // namespace drape::detail
#endif
