#pragma once
/// \file eigen_direct.hpp
/// Header-only sparse direct solvers from Eigen (the shared body is direct_solver.hpp):
/// - `ldlt`: `Eigen::SimplicialLDLT` with AMD ordering; reports `NotPositiveDefinite` when a pivot
///   of D is <= 0.
/// - `lu`: `Eigen::SparseLU` with COLAMD ordering, for the non-symmetric Exact Jacobian.
/// By name (ImplicitOptions::solver) both are opt-in: include enable_ldlt.hpp or enable_lu.hpp
/// once in the program (solver_registry.hpp says why).

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "drape/solvers/direct_solver.hpp"

namespace drape {

namespace detail {

template <class Scalar>
struct EigenLdltBackend {
  using Real = Scalar;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>, Eigen::Lower, Eigen::AMDOrdering<int>> solver;

  void analyze(const Eigen::SparseMatrix<Scalar>& a) { solver.analyzePattern(a); }
  /// A zero or negative pivot of D means the matrix is not positive definite.
  SolveError factorize(const Eigen::SparseMatrix<Scalar>& a) {
    solver.factorize(a);
    if (solver.info() != Eigen::Success) return SolveError::NotPositiveDefinite;
    if (!(solver.vectorD().array() > Scalar(0)).all()) return SolveError::NotPositiveDefinite;
    return SolveError::None;
  }
  bool solve(const VectorX<Scalar>& b, VectorX<Scalar>& x) {
    x = solver.solve(b);
    return true;
  }
};

template <class Scalar>
struct EigenLuBackend {
  using Real = Scalar;
  Eigen::SparseLU<Eigen::SparseMatrix<Scalar>, Eigen::COLAMDOrdering<int>> solver;

  void analyze(const Eigen::SparseMatrix<Scalar>& a) { solver.analyzePattern(a); }
  SolveError factorize(const Eigen::SparseMatrix<Scalar>& a) {
    solver.factorize(a);
    return solver.info() == Eigen::Success ? SolveError::None : SolveError::SolverFailure;
  }
  bool solve(const VectorX<Scalar>& b, VectorX<Scalar>& x) {
    x = solver.solve(b);
    return true;
  }
};

}  // namespace detail

template <class Scalar = double>
using EigenLdltSolver = detail::DirectSolver<Scalar, LinearSolverKind::Ldlt, detail::EigenLdltBackend<Scalar>>;
template <class Scalar = double>
using EigenLuSolver = detail::DirectSolver<Scalar, LinearSolverKind::Lu, detail::EigenLuBackend<Scalar>>;

}  // namespace drape
