#pragma once
/// \file force_assembler_avx2.hpp
/// ForceAssembler's spring pass (force_assembler.hpp) with AVX2, for double and float: one run of a
/// grid's springs, and a range of a general spring list.

#include <cmath>
#include <cstddef>
#include <cstring>

#include "drape/core/types.hpp"
#include "drape/physics/spring_kernel.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/vector_sqrt.hpp"

namespace drape {

template <class Scalar>
struct NodeView;

#if DRAPE_AVX2_DISPATCH
namespace detail {

template <class V, class Scalar>
__attribute__((target("avx2"), always_inline)) inline V load_avx2(const Scalar* p) {
  V r;
  std::memcpy(&r, p, sizeof r);
  return r;
}

template <class V, class Scalar>
__attribute__((target("avx2"), always_inline)) inline V broadcast_avx2(Scalar s) {
  V r;
  for (std::size_t i = 0; i < sizeof(V) / sizeof(Scalar); ++i) r[i] = s;
  return r;
}

/// One run of the spring pass with AVX2 (springs a + j to b + j, j < count, forces into f[k][j]),
/// 4 doubles or 8 floats per instruction with every intermediate in registers. The operations of
/// the baseline loops in their order, spring_force_factor's included, and no fused multiply-add
/// (the AVX2 target has none): the same bits. The tail goes through the scalar kernel. Called once
/// per run, not inlined: the baseline-compiled loop over runs may not inline an AVX2 function.
template <class Scalar>
__attribute__((target("avx2"))) inline void spring_run_avx2(const NodeView<Scalar>& x, const NodeView<Scalar>& v,
                                                            Index a, Index b, Index count, Scalar rest_length,
                                                            Scalar stiffness, Scalar damping, Scalar* const f[3]) {
  using V = typename Avx2Vector<Scalar>::type;
  constexpr Index lanes = Index(sizeof(V) / sizeof(Scalar));
  const V one = broadcast_avx2<V>(Scalar(1)), l = broadcast_avx2<V>(rest_length);
  const V ks = broadcast_avx2<V>(stiffness), kd = broadcast_avx2<V>(damping);
  Index j = 0;
  for (; j + lanes <= count; j += lanes) {
    const V d0 = load_avx2<V>(x.p[0] + b + j) - load_avx2<V>(x.p[0] + a + j);
    const V d1 = load_avx2<V>(x.p[1] + b + j) - load_avx2<V>(x.p[1] + a + j);
    const V d2 = load_avx2<V>(x.p[2] + b + j) - load_avx2<V>(x.p[2] + a + j);
    const V w0 = load_avx2<V>(v.p[0] + b + j) - load_avx2<V>(v.p[0] + a + j);
    const V w1 = load_avx2<V>(v.p[1] + b + j) - load_avx2<V>(v.p[1] + a + j);
    const V w2 = load_avx2<V>(v.p[2] + b + j) - load_avx2<V>(v.p[2] + a + j);
    const V length = sqrt_avx2(d0 * d0 + d1 * d1 + d2 * d2);
    const V w_dot_d = w0 * d0 + w1 * d1 + w2 * d2;
    const V inverse_length = one / length;
    const V c = (ks * (length - l) + kd * (w_dot_d * inverse_length)) * inverse_length;
    const V f0 = c * d0, f1 = c * d1, f2 = c * d2;
    std::memcpy(f[0] + j, &f0, sizeof f0);
    std::memcpy(f[1] + j, &f1, sizeof f1);
    std::memcpy(f[2] + j, &f2, sizeof f2);
  }
  for (; j < count; ++j) {
    const Scalar d0 = x.p[0][b + j] - x.p[0][a + j];
    const Scalar d1 = x.p[1][b + j] - x.p[1][a + j];
    const Scalar d2 = x.p[2][b + j] - x.p[2][a + j];
    const Scalar length = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
    const Scalar w_dot_d = (v.p[0][b + j] - v.p[0][a + j]) * d0 + (v.p[1][b + j] - v.p[1][a + j]) * d1 +
                           (v.p[2][b + j] - v.p[2][a + j]) * d2;
    const Scalar c = spring_force_factor(length, w_dot_d, rest_length, stiffness, damping);
    f[0][j] = c * d0;
    f[1][j] = c * d1;
    f[2][j] = c * d2;
  }
}

/// `lanes` values p[index[0]], ..., p[index[lanes - 1]] as one vector.
template <class V, class Scalar>
__attribute__((target("avx2"), always_inline)) inline V gather_avx2(const Scalar* p, const int* index) {
  V r;
  for (std::size_t i = 0; i < sizeof(V) / sizeof(Scalar); ++i) r[i] = p[index[i]];
  return r;
}

/// Springs s in [begin, end) of a spring list (nodes a[s] and b[s], each spring its own rest
/// length, stiffness and damping), forces into f[k][s], with AVX2: the spring pass of
/// ForceAssembler for a cloth that is not a grid. The node values are gathered; the arithmetic is
/// spring_run_avx2's (the baseline's operations in their order: the same bits).
template <class Scalar>
__attribute__((target("avx2"))) inline void spring_list_avx2(const NodeView<Scalar>& x, const NodeView<Scalar>& v,
                                                             const int* a, const int* b, const Scalar* rest,
                                                             const Scalar* stiffness, const Scalar* damping,
                                                             Index begin, Index end, Scalar* const f[3]) {
  using V = typename Avx2Vector<Scalar>::type;
  constexpr Index lanes = Index(sizeof(V) / sizeof(Scalar));
  const V one = broadcast_avx2<V>(Scalar(1));
  Index s = begin;
  for (; s + lanes <= end; s += lanes) {
    const int *ia = a + s, *ib = b + s;
    const V d0 = gather_avx2<V>(x.p[0], ib) - gather_avx2<V>(x.p[0], ia);
    const V d1 = gather_avx2<V>(x.p[1], ib) - gather_avx2<V>(x.p[1], ia);
    const V d2 = gather_avx2<V>(x.p[2], ib) - gather_avx2<V>(x.p[2], ia);
    const V w0 = gather_avx2<V>(v.p[0], ib) - gather_avx2<V>(v.p[0], ia);
    const V w1 = gather_avx2<V>(v.p[1], ib) - gather_avx2<V>(v.p[1], ia);
    const V w2 = gather_avx2<V>(v.p[2], ib) - gather_avx2<V>(v.p[2], ia);
    const V length = sqrt_avx2(d0 * d0 + d1 * d1 + d2 * d2);
    const V w_dot_d = w0 * d0 + w1 * d1 + w2 * d2;
    const V inverse_length = one / length;
    const V c = (load_avx2<V>(stiffness + s) * (length - load_avx2<V>(rest + s)) +
                 load_avx2<V>(damping + s) * (w_dot_d * inverse_length)) *
                inverse_length;
    const V f0 = c * d0, f1 = c * d1, f2 = c * d2;
    std::memcpy(f[0] + s, &f0, sizeof f0);
    std::memcpy(f[1] + s, &f1, sizeof f1);
    std::memcpy(f[2] + s, &f2, sizeof f2);
  }
  for (; s < end; ++s) {
    const Index i = a[s], j = b[s];
    const Scalar d0 = x.p[0][j] - x.p[0][i], d1 = x.p[1][j] - x.p[1][i], d2 = x.p[2][j] - x.p[2][i];
    const Scalar w_dot_d = (v.p[0][j] - v.p[0][i]) * d0 + (v.p[1][j] - v.p[1][i]) * d1 + (v.p[2][j] - v.p[2][i]) * d2;
    const Scalar c =
        spring_force_factor(std::sqrt(d0 * d0 + d1 * d1 + d2 * d2), w_dot_d, rest[s], stiffness[s], damping[s]);
    f[0][s] = c * d0;
    f[1][s] = c * d1;
    f[2][s] = c * d2;
  }
}

}  // namespace detail
#endif

}  // namespace drape
