#pragma once
/// \file linear_solver.hpp
/// The interface every linear solver of the implicit integrator implements, and shared helpers.
///
/// Life cycle: `analyze(A)` once per pattern (symbolic work: ordering, symbolic factorisation,
/// workspaces), then `solve(A, b, x)` every step with new values in the same pattern. `x` holds the
/// warm start on entry (iterative solvers use it; direct solvers ignore it) and the solution on
/// exit. `filter` (optional, one byte per block row) marks rows whose unknowns are held at zero
/// (pinned nodes in PinTreatment::Filter); only solvers with `supports_filter()` accept it.

#include <cmath>
#include <cstdint>
#include <string>

#include "drape/integrators/step_status.hpp"
#include "drape/solvers/block_sparse_matrix.hpp"
#include "drape/solvers/grid_layout.hpp"

namespace drape {

/// Preconditioner of the iterative solvers.
enum class Preconditioner : std::uint8_t {
  BlockJacobi = 0,  ///< inverse 3x3 diagonal blocks: needs nothing but the matrix
  Multigrid = 1,    ///< geometric multigrid V-cycle (multigrid.hpp): needs the GridLayout; cg only
};

inline const char* to_string(Preconditioner p) { return p == Preconditioner::Multigrid ? "multigrid" : "block-jacobi"; }

/// Settings of the iterative solvers.
struct IterativeSettings {
  double tolerance = 1e-6;  ///< stop when |b - A x| <= tolerance |b|
  int max_iterations = 1000;
  int threads = 0;          ///< 0 = all available
  Preconditioner preconditioner = Preconditioner::BlockJacobi;
};

template <class Scalar = double>
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// The name it is selected by ("cg", "ldlt", ...).
  virtual const char* name() const = 0;
  /// True if the solver needs a symmetric matrix (Symmetric or Spd Jacobian).
  virtual bool requires_symmetric() const = 0;
  virtual bool supports_filter() const { return false; }
  /// Where the rows sit on the lattice; call before analyze(). Solvers that do not exploit the
  /// geometry ignore it.
  virtual void set_grid_layout(const GridLayout& /*layout*/) {}
  virtual void analyze(const BlockSparseMatrix<Scalar>& a) = 0;
  virtual StepStatus solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                           const std::uint8_t* filter = nullptr) = 0;
};

namespace detail {

/// `|b - A x| / |b|` (0 if b = 0), using `work` (size of b) as scratch: no allocation.
template <class Scalar>
double relative_residual(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, const VectorX<Scalar>& x,
                         VectorX<Scalar>& work, int threads) {
  a.multiply(x.data(), work.data(), threads);
  double rr = 0, bb = 0;
  for (Index i = 0; i < b.size(); ++i) {
    const double r = double(b[i]) - double(work[i]);
    rr += r * r;
    bb += double(b[i]) * double(b[i]);
  }
  return bb > 0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

}  // namespace detail
}  // namespace drape
