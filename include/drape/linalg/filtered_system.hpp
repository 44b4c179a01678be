#pragma once
/// \file filtered_system.hpp
/// A constrained system rewritten as an unconstrained one of the same block pattern, for solvers
/// that cannot filter (the direct solvers). With \f$ x_r = S_r y_r + z_r \f$ (constraint_filter.hpp),
/// \f[ (S A S + I - S)\, y = S\, (b - A z), \qquad x = y + z, \f]
/// whose solution meets the constraints and \f$ S (b - A x) = 0 \f$: the same x the filtered
/// iterative solvers converge to (Ascher & Boxerman 2003 call it the modified system). \f$ S \f$
/// is block diagonal, so the pattern does not change and a symbolic factorisation done once
/// stays valid; \f$ S A S + I - S \f$ is symmetric positive definite when A is.

#include "drape/linalg/block3.hpp"
#include "drape/linalg/linear_system.hpp"

namespace drape {

/// Writes \f$ S A S + I - S \f$ into `matrix` (same pattern as `system.matrix`, values replaced)
/// and \f$ S (b - A z) \f$ into `rhs`; `work` is scratch of size `system.size()`.
template <class Scalar>
void filtered_system(const LinearSystem<Scalar>& system, BlockSparseMatrix<Scalar>& matrix, VectorX<Scalar>& rhs,
                     VectorX<Scalar>& work) {
  const ConstraintFilter<Scalar>& c = system.constraints;
  const BlockSparseMatrix<Scalar>& a = system.matrix;
  if (matrix.block_count() != a.block_count()) matrix = a;
  std::copy(a.values(), a.values() + 9 * a.block_count(), matrix.values());
  for (int r = 0; r < a.block_rows(); ++r) {
    const bool row_free = c.kind(r) == ConstraintKind::Free;
    for (int k = a.row_begin()[r]; k < a.row_begin()[r + 1]; ++k) {
      const int col = a.column()[k];
      if (row_free && c.kind(col) == ConstraintKind::Free) continue;
      Mat3<Scalar> block = a.block(k);
      if (!row_free) block = c.filter(r) * block;
      if (c.kind(col) != ConstraintKind::Free) block = block * c.filter(col);
      if (col == r && !row_free) block += Mat3<Scalar>::Identity() - c.filter(r);
      matrix.block(k) = block;
    }
  }
  // rhs = S (b - A z)
  for (int r = 0; r < a.block_rows(); ++r) work.template segment<3>(3 * r) = c.value(r);
  rhs.resize(system.size());
  a.multiply(work.data(), rhs.data(), 1);
  rhs = system.rhs - rhs;
  c.project(rhs.data());
}

}  // namespace drape
