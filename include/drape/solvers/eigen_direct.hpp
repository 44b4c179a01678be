#pragma once
/// \file eigen_direct.hpp
/// Header-only sparse direct solvers from Eigen, on a scalar compressed-column copy of the block
/// system whose pattern (and the block -> scalar value map) is built once in `analyze()`:
/// - `ldlt`: `Eigen::SimplicialLDLT` with AMD ordering; symbolic analysis once, numeric
///   factorisation per step; reports `NotPositiveDefinite` when a pivot of D is <= 0.
/// - `lu`: `Eigen::SparseLU` with COLAMD ordering, for the non-symmetric Exact Jacobian.
/// Pinned DOFs must be eliminated (no filter). By name (ImplicitOptions::solver) both are opt-in:
/// include enable_ldlt.hpp or enable_lu.hpp once in the program (solver_registry.hpp says why).

#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "drape/solvers/linear_solver.hpp"

namespace drape {

namespace detail {

/// What the two Eigen direct solvers share: a scalar CSC copy of the block system whose pattern
/// and value map are built once in analyze(), refactorised and solved each step. `Derived`
/// supplies the factorisation type and `factorization_error()`.
template <class Scalar, class Factorization, class Derived>
class EigenDirectSolver : public LinearSolver<Scalar> {
 public:
  void analyze(const BlockSparseMatrix<Scalar>& a) override {
    m_matrix = a.template scalar_pattern<Scalar>(m_map);
    m_solver.analyzePattern(m_matrix);
    m_work.setZero(a.size());
    m_analyzed = a.size();
  }
  StepStatus solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                   const std::uint8_t* = nullptr) override {
    if (m_analyzed != a.size()) analyze(a);
    a.copy_values(m_matrix, m_map);
    m_solver.factorize(m_matrix);
    const StepError error = static_cast<const Derived&>(*this).factorization_error();
    if (error != StepError::None) return {error, 0, 0.0};
    x = m_solver.solve(b);
    if (!x.allFinite()) return {StepError::NonFiniteState, 0, 0.0};
    return {StepError::None, 0, relative_residual(a, b, x, m_work, 1)};
  }

 protected:
  Factorization m_solver;

 private:
  Eigen::SparseMatrix<Scalar> m_matrix;
  std::vector<int> m_map;
  VectorX<Scalar> m_work;
  Index m_analyzed = -1;
};

}  // namespace detail

template <class Scalar = double>
class EigenLdltSolver final
    : public detail::EigenDirectSolver<
          Scalar, Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>, Eigen::Lower, Eigen::AMDOrdering<int>>,
          EigenLdltSolver<Scalar>> {
 public:
  const char* name() const override { return "ldlt"; }
  bool requires_symmetric() const override { return true; }
  /// A zero or negative pivot of D means the matrix is not positive definite.
  StepError factorization_error() const {
    if (this->m_solver.info() != Eigen::Success) return StepError::NotPositiveDefinite;
    if (!(this->m_solver.vectorD().array() > Scalar(0)).all()) return StepError::NotPositiveDefinite;
    return StepError::None;
  }
};

template <class Scalar = double>
class EigenLuSolver final
    : public detail::EigenDirectSolver<Scalar, Eigen::SparseLU<Eigen::SparseMatrix<Scalar>, Eigen::COLAMDOrdering<int>>,
                                       EigenLuSolver<Scalar>> {
 public:
  const char* name() const override { return "lu"; }
  bool requires_symmetric() const override { return false; }
  StepError factorization_error() const {
    return this->m_solver.info() == Eigen::Success ? StepError::None : StepError::SolverFailure;
  }
};

}  // namespace drape
