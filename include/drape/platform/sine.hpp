#pragma once
/// \file sine.hpp
/// Sine and cosine for the wind's travelling waves, without libm: branch-free, so a loop over many
/// arguments vectorises (SSE2 takes two at a time), inlined, and the same bits on every platform
/// (libm's results differ between versions). The argument is reduced modulo 2 pi with 2 pi in three
/// parts (Cody-Waite), r in [-pi, pi] is folded to [-pi/2, pi/2] (sin r = sin(pi - r)), and the
/// Taylor series to the x^21 term, whose remainder is below 1.3e-18 there, does the rest.
/// Absolute error below 1e-15 for |x| < 6e6 (tested against std::sin); beyond that the reduction
/// is inexact (n 2 pi needs more bits), which wind phases never reach (omega t at 6e6 is a month).

#include <algorithm>
#include <cmath>

namespace drape::detail {

/// sin(u) for u in [-pi/2, pi/2]: the odd Taylor polynomial of degree 21.
inline double sine_near_zero(double u) {
  const double z = u * u;
  double p = 0x1.71b8ef6dcf572p-66;  // 1/21!
  p = p * z - 0x1.2f49b46814157p-57;
  p = p * z + 0x1.952c77030ad4ap-49;
  p = p * z - 0x1.ae7f3e733b81fp-41;
  p = p * z + 0x1.6124613a86d09p-33;
  p = p * z - 0x1.ae64567f544e4p-26;
  p = p * z + 0x1.71de3a556c734p-19;
  p = p * z - 0x1.a01a01a01a01ap-13;
  p = p * z + 0x1.1111111111111p-7;
  p = p * z - 0x1.5555555555555p-3;  // -1/3!
  return u + u * (z * p);
}

/// x - 2 pi n with n the nearest integer to x / (2 pi): in [-pi, pi].
inline double reduce_two_pi(double x) {
  constexpr double round_magic = 0x1.8p52;  // adding and subtracting it rounds to an integer
  const double n = (x * 0x1.45f306dc9c883p-3 + round_magic) - round_magic;
  // 2 pi = a + b + c with a and b of 30 bits: n a and n b are exact for |n| < 2^23.
  return ((x - n * 0x1.921fb54p+2) - n * 0x1.10b46118p-28) - n * 0x1.313198a2e037p-59;
}

/// sin(x), branch-free.
inline double sine(double x) {
  const double r = reduce_two_pi(x);
  const double a = std::abs(r);
  // pi - a in two parts; pi_hi - a is exact when it matters (a >= pi / 2). It can be slightly
  // negative (a rounds above pi), so the sign of r multiplies rather than replaces its sign.
  const double folded = std::min(a, (0x1.921fb54442d18p+1 - a) + 0x1.1a62633145c07p-53);
  return std::copysign(1.0, r) * sine_near_zero(folded);
}

/// cos(x) = sin(pi/2 - |r|), branch-free.
inline double cosine(double x) {
  const double a = std::abs(reduce_two_pi(x));
  return sine_near_zero((0x1.921fb54442d18p+0 - a) + 0x1.1a62633145c07p-54);
}

}  // namespace drape::detail
