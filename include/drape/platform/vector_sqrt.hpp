#pragma once
/// \file vector_sqrt.hpp
/// Square roots several per instruction and correctly rounded: of an array in place (baseline
/// instruction set) and of one AVX2 register.
///
/// Compilers do not vectorise `std::sqrt` unless errno is switched off (`-fno-math-errno`), and
/// Eigen's packet sqrt for float is an approximation (rsqrt and a Newton step) whose last bits
/// differ between CPU vendors. These call the processor's exact square root instructions
/// directly: SSE2 (2 doubles, 4 floats) in the baseline version, AVX2 (4 doubles, 8 floats) in the
/// other (instruction_set.hpp). An exact square root has one answer, so both versions, and the
/// scalar tail, give the same bits.

#include <cmath>
#include <cstring>

#include <Eigen/Core>

#include "drape/platform/instruction_set.hpp"

namespace drape::detail {

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))

using Double2 = double __attribute__((vector_size(16)));
using Float4 = float __attribute__((vector_size(16)));

/// Baseline: SSE2's sqrtpd and SSE's sqrtps.
template <class Scalar>
inline void sqrt_in_place(Scalar* a, Eigen::Index n) {
  constexpr Eigen::Index lanes = 16 / sizeof(Scalar);
  Eigen::Index j = 0;
  for (; j + lanes <= n; j += lanes) {
    if constexpr (sizeof(Scalar) == 8) {
      Double2 p;
      std::memcpy(&p, a + j, sizeof p);
      p = __builtin_ia32_sqrtpd(p);
      std::memcpy(a + j, &p, sizeof p);
    } else {
      Float4 p;
      std::memcpy(&p, a + j, sizeof p);
      p = __builtin_ia32_sqrtps(p);
      std::memcpy(a + j, &p, sizeof p);
    }
  }
  for (; j < n; ++j) a[j] = std::sqrt(a[j]);
}

#else

/// Other platforms: Eigen's packet sqrt (exact for double; for float Eigen may approximate).
template <class Scalar>
inline void sqrt_in_place(Scalar* a, Eigen::Index n) {
  Eigen::Map<Eigen::Array<Scalar, Eigen::Dynamic, 1> > m(a, n);
  m = m.sqrt();
}

#endif

#if DRAPE_AVX2_DISPATCH

using Double4 = double __attribute__((vector_size(32)));
using Float8 = float __attribute__((vector_size(32)));

/// The 256-bit vector of `Scalar`: 4 doubles or 8 floats.
template <class Scalar>
struct Avx2Vector;
template <>
struct Avx2Vector<double> {
  using type = Double4;
};
template <>
struct Avx2Vector<float> {
  using type = Float8;
};

/// AVX2 version: vsqrtpd / vsqrtps on one 256-bit register, for loops that keep their values in
/// registers (force_assembler.hpp). A 256-bit builtin may only be inlined into a function compiled
/// for AVX2, so these carry the target attribute and are inlined into their AVX2 callers.
__attribute__((target("avx2"), always_inline)) inline Double4 sqrt_avx2(Double4 p) {
  return __builtin_ia32_sqrtpd256(p);
}
__attribute__((target("avx2"), always_inline)) inline Float8 sqrt_avx2(Float8 p) { return __builtin_ia32_sqrtps256(p); }

#endif

}  // namespace drape::detail
