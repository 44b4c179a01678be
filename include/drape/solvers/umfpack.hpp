#pragma once
/// \file umfpack.hpp
/// Sparse LU through UMFPACK (SuiteSparse), via Eigen's UmfPackSupport wrapper: the direct path for
/// the non-symmetric Exact Jacobian (the shared body is direct_solver.hpp). Only usable when the
/// program links the optional CMake target `drape::suitesparse`.

#if !defined(DRAPE_HAS_SUITESPARSE)
#error "drape/solvers/umfpack.hpp needs SuiteSparse: link the CMake target drape::suitesparse"
#endif

#include <Eigen/UmfPackSupport>

#include "drape/solvers/cholmod.hpp"  // detail::pin_openblas_to_one_thread
#include "drape/solvers/direct_solver.hpp"

namespace drape {

namespace detail {

struct UmfpackBackend {
  using Real = double;
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> solver;

  UmfpackBackend() { pin_openblas_to_one_thread(); }
  void analyze(const Eigen::SparseMatrix<double>& a) { solver.analyzePattern(a); }
  SolveError factorize(const Eigen::SparseMatrix<double>& a) {
    solver.factorize(a);
    return solver.info() == Eigen::Success ? SolveError::None : SolveError::SolverFailure;
  }
  bool solve(const VectorX<double>& b, VectorX<double>& x) {
    x = solver.solve(b);
    return true;
  }
};

}  // namespace detail

template <class Scalar = double>
using UmfpackSolver = detail::DirectSolver<Scalar, LinearSolverKind::Umfpack, detail::UmfpackBackend>;

}  // namespace drape
