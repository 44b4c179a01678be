#pragma once
/// \file block_jacobi_avx2.hpp
/// BlockJacobi::smooth_rows() with AVX2, for double and float.

#include "drape/linalg/detail/row_avx2.hpp"
#include "drape/platform/instruction_set.hpp"

#if DRAPE_AVX2_DISPATCH
namespace drape::detail {

/// x_r = omega D_r^-1 t_r (`first`) or x_r += it, on the rows [begin, end), `inverse` holding the
/// D_r^-1 (9 values each, column-major): D_r^-1 t_r as three columns times broadcast t_r
/// components, summed (c0 t0 + c1 t1) + c2 t2 like block_times(), then scaled and stored or
/// added: the baseline's operations in its order (no FMA), so the same bits.
template <class Scalar>
__attribute__((target("avx2"))) inline void jacobi_smooth_rows_avx2(const Scalar* inverse, const Scalar* t,
                                                                    Scalar omega, bool first, Scalar* x, int begin,
                                                                    int end) {
  const typename Lanes4Avx2<Scalar>::type w = set4_avx2(omega);
  for (int row = begin; row < end; ++row) {
    const typename Lanes4Avx2<Scalar>::type d = block_times_avx2(inverse + 9 * row, t + 3 * row);
    store_row3_avx2(x + 3 * row, mul_avx2(w, d), !first);
  }
}

}  // namespace drape::detail
#endif
