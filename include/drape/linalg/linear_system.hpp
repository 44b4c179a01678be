#pragma once
/// \file linear_system.hpp
/// `LinearSystem`: everything a linear solver is handed, in one object: the matrix (block CSR, and
/// optionally its edge form), where the rows sit on the cloth's lattice, the constraints on the
/// unknowns, and the right-hand side. The solvers know nothing else about the cloth: whoever
/// assembles a system (physics/jacobian_assembler.hpp) fills it, a solver reads it.
///
/// The system solved is \f$ A x = b \f$ subject to the constraints \f$ x_r = S_r y_r + z_r \f$
/// (constraint_filter.hpp).

#include <cmath>

#include "drape/core/types.hpp"
#include "drape/linalg/block_sparse_matrix.hpp"
#include "drape/linalg/constraint_filter.hpp"
#include "drape/linalg/edge_operator.hpp"
#include "drape/linalg/grid_layout.hpp"

namespace drape {

template <class Scalar = double>
struct LinearSystem {
  /// A in block CSR: every solver can use it.
  BlockSparseMatrix<Scalar> matrix;
  /// The same A per edge (edge_operator.hpp), when `edges.valid()`: a cheaper product.
  EdgeOperator<Scalar> edges;
  /// Where the block rows sit on a lattice (the multigrid preconditioner needs it); may be empty.
  GridLayout layout;
  /// Constrained rows; empty (every row free) unless filled.
  ConstraintFilter<Scalar> constraints;
  /// b, size() scalars.
  VectorX<Scalar> rhs;

  int size() const { return matrix.size(); }
  int block_rows() const { return matrix.block_rows(); }

  /// `y = A x` over `threads` threads, through the edge form when it is valid (fewer bytes), else
  /// the block rows. Ignores the constraints.
  void multiply(const Scalar* x, Scalar* y, int threads = 1) const {
    if (edges.valid())
      edges.multiply(x, y, threads);
    else
      matrix.multiply(x, y, threads);
  }
};

/// \f$ |S(b - A x)| / |S b| \f$ (the numerator alone if S b = 0): the residual on the directions
/// the constraints leave free (all of them without constraints). `work` (size of b) is scratch: no
/// allocation.
template <class Scalar>
double relative_residual(const LinearSystem<Scalar>& system, const VectorX<Scalar>& x, VectorX<Scalar>& work,
                         int threads = 1) {
  system.multiply(x.data(), work.data(), threads);
  const VectorX<Scalar>& b = system.rhs;
  double rr = 0, bb = 0;
  if (system.constraints.empty()) {
    for (Index i = 0; i < b.size(); ++i) {
      const double r = double(b[i]) - double(work[i]);
      rr += r * r;
      bb += double(b[i]) * double(b[i]);
    }
    return bb > 0 ? std::sqrt(rr / bb) : std::sqrt(rr);
  }
  for (int row = 0; row < system.block_rows(); ++row) {
    Vec3<Scalar> r = b.template segment<3>(3 * row) - work.template segment<3>(3 * row);
    Vec3<Scalar> br = b.template segment<3>(3 * row);
    system.constraints.project_row(row, r.data());
    system.constraints.project_row(row, br.data());
    rr += double(r.squaredNorm());
    bb += double(br.squaredNorm());
  }
  return bb > 0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

}  // namespace drape
