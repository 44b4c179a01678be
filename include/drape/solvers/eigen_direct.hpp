#pragma once
/// \file eigen_direct.hpp
/// Header-only sparse direct solvers from Eigen, on a scalar compressed-column copy of the block
/// system whose pattern (and the block -> scalar value map) is built once in `analyze()`:
/// - `ldlt`: `Eigen::SimplicialLDLT` with AMD ordering; symbolic analysis once, numeric
///   factorisation per step; reports `NotPositiveDefinite` when a pivot of D is <= 0.
/// - `lu`: `Eigen::SparseLU` with COLAMD ordering, for the non-symmetric Exact Jacobian.
/// Pinned DOFs must be eliminated (no filter).

#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "drape/solvers/linear_solver.hpp"

namespace drape {

template <class Scalar = double>
class EigenLdltSolver final : public LinearSolver<Scalar> {
 public:
  const char* name() const override { return "ldlt"; }
  bool requires_symmetric() const override { return true; }
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
    if (m_solver.info() != Eigen::Success) return {StepError::NotPositiveDefinite, 0, 0.0};
    if (!(m_solver.vectorD().array() > Scalar(0)).all()) return {StepError::NotPositiveDefinite, 0, 0.0};
    x = m_solver.solve(b);
    if (!x.allFinite()) return {StepError::NonFiniteState, 0, 0.0};
    return {StepError::None, 0, detail::relative_residual(a, b, x, m_work, 1)};
  }

 private:
  Eigen::SparseMatrix<Scalar> m_matrix;
  std::vector<int> m_map;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>, Eigen::Lower, Eigen::AMDOrdering<int>> m_solver;
  VectorX<Scalar> m_work;
  Index m_analyzed = -1;
};

template <class Scalar = double>
class EigenLuSolver final : public LinearSolver<Scalar> {
 public:
  const char* name() const override { return "lu"; }
  bool requires_symmetric() const override { return false; }
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
    if (m_solver.info() != Eigen::Success) return {StepError::SolverFailure, 0, 0.0};
    x = m_solver.solve(b);
    if (!x.allFinite()) return {StepError::NonFiniteState, 0, 0.0};
    return {StepError::None, 0, detail::relative_residual(a, b, x, m_work, 1)};
  }

 private:
  Eigen::SparseMatrix<Scalar> m_matrix;
  std::vector<int> m_map;
  Eigen::SparseLU<Eigen::SparseMatrix<Scalar>, Eigen::COLAMDOrdering<int>> m_solver;
  VectorX<Scalar> m_work;
  Index m_analyzed = -1;
};

}  // namespace drape
