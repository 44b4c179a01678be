#pragma once
/// \file dense_cholesky.hpp
/// Dense Cholesky factorisation and solve for a few dozen unknowns: the exact solve on the
/// coarsest multigrid level. Plain loops compile in a fraction of the time Eigen's blocked LLT
/// takes, and run as fast at this size.

#include <cmath>

namespace drape::detail {

/// `A = L L^T` of the n x n row-major matrix `a`, in place (L in the lower triangle). False if `a`
/// is not positive definite.
template <class Scalar>
bool cholesky_in_place(Scalar* a, int n) {
  for (int j = 0; j < n; ++j) {
    Scalar d = a[j * n + j];
    for (int k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0) || !std::isfinite(d)) return false;
    const Scalar l = std::sqrt(d);
    a[j * n + j] = l;
    for (int i = j + 1; i < n; ++i) {
      Scalar s = a[i * n + j];
      for (int k = 0; k < j; ++k) s -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = s / l;
    }
  }
  return true;
}

/// Solves `L L^T x = b` with the factor of cholesky_in_place(); `x` holds b on entry.
template <class Scalar>
void cholesky_solve_in_place(const Scalar* l, int n, Scalar* x) {
  for (int i = 0; i < n; ++i) {
    Scalar s = x[i];
    for (int k = 0; k < i; ++k) s -= l[i * n + k] * x[k];
    x[i] = s / l[i * n + i];
  }
  for (int i = n - 1; i >= 0; --i) {
    Scalar s = x[i];
    for (int k = i + 1; k < n; ++k) s -= l[k * n + i] * x[k];
    x[i] = s / l[i * n + i];
  }
}

}  // namespace drape::detail
