#pragma once
/// \file umfpack.hpp
/// Sparse LU through UMFPACK (SuiteSparse), via Eigen's UmfPackSupport wrapper: the direct path for
/// the non-symmetric Exact Jacobian. Symbolic analysis once per cloth, numeric factorisation per
/// step. Only usable when the program links the optional CMake target `drape::suitesparse`.

#if !defined(DRAPE_HAS_SUITESPARSE)
#error "drape/solvers/umfpack.hpp needs SuiteSparse: link the CMake target drape::suitesparse"
#endif

#include <vector>

#include <Eigen/UmfPackSupport>

#include "drape/solvers/cholmod.hpp"  // detail::pin_openblas_to_one_thread
#include "drape/solvers/linear_solver.hpp"

namespace drape {

template <class Scalar = double>
class UmfpackSolver final : public LinearSolver<Scalar> {
 public:
  UmfpackSolver() { detail::pin_openblas_to_one_thread(); }

  const char* name() const override { return "umfpack"; }
  bool requires_symmetric() const override { return false; }
  void analyze(const BlockSparseMatrix<Scalar>& a) override {
    m_matrix = a.template scalar_pattern<double>(m_map);
    m_solver.analyzePattern(m_matrix);
    m_b.setZero(a.size());
    m_work.setZero(a.size());
    m_analyzed = a.size();
  }
  StepStatus solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                   const std::uint8_t* = nullptr) override {
    if (m_analyzed != a.size()) analyze(a);
    a.copy_values(m_matrix, m_map);
    m_solver.factorize(m_matrix);
    if (m_solver.info() != Eigen::Success) return {StepError::SolverFailure, 0, 0.0};
    m_b = b.template cast<double>();
    x = m_solver.solve(m_b).template cast<Scalar>();
    if (!x.allFinite()) return {StepError::NonFiniteState, 0, 0.0};
    return {StepError::None, 0, detail::relative_residual(a, b, x, m_work, 1)};
  }

 private:
  Eigen::SparseMatrix<double> m_matrix;
  std::vector<int> m_map;
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> m_solver;
  Eigen::VectorXd m_b;
  VectorX<Scalar> m_work;
  Index m_analyzed = -1;
};

}  // namespace drape
