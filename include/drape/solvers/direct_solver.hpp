#pragma once
/// \file direct_solver.hpp
/// What every sparse direct solver of drape does, written once: a scalar compressed-column copy
/// of the block system whose pattern (and the block -> scalar value map) is built in analyze()
/// together with the symbolic factorisation; each solve copies the values, refactorises
/// numerically, solves and reports the relative residual. A back end (eigen_direct.hpp,
/// cholmod.hpp, umfpack.hpp) only supplies the factorisation:
/// \code
///   struct Backend {
///     using Real = ...;                                          // the factorisation's scalar
///     void analyze(const Eigen::SparseMatrix<Real>& a);          // symbolic, once
///     SolveError factorize(const Eigen::SparseMatrix<Real>& a);  // numeric, every solve
///     bool solve(const VectorX<Real>& b, VectorX<Real>& x);      // false: the solve failed
///   };
/// \endcode
/// Constrained rows (filtered pins, contacts) are solved through the modified system of
/// filtered_system.hpp: same pattern, so the symbolic factorisation stays valid.

#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/config.hpp"
#include "drape/linalg/filtered_system.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/solver_kind.hpp"

namespace drape::detail {

template <class Scalar, LinearSolverKind Kind, class Backend>
class DirectSolver final : public BuiltInSolver<Scalar, Kind> {
 public:
  using Real = typename Backend::Real;

  /// Arguments go to the back end's constructor (e.g. CHOLMOD's factorisation and ordering).
  template <class... Args>
  explicit DirectSolver(Args&&... args) : m_backend(std::forward<Args>(args)...) {}

  void analyze(const LinearSystem<Scalar>& system) override {
    m_matrix = system.matrix.template scalar_pattern<Real>(m_map);
    m_backend.analyze(m_matrix);
    m_b.setZero(system.size());
    m_x.setZero(system.size());
    m_work.setZero(system.size());
    m_analyzed = system.size();
  }

  SolveStatus solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) override {
    if (m_analyzed != system.size()) analyze(system);
    const bool constrained = !system.constraints.empty();
    if (constrained) filtered_system(system, m_filtered, m_filtered_rhs, m_work);
    (constrained ? m_filtered : system.matrix).copy_values(m_matrix, m_map);
    const VectorX<Scalar>& rhs = constrained ? m_filtered_rhs : system.rhs;
    const SolveError factorized = m_backend.factorize(m_matrix);
    if (factorized != SolveError::None) return {factorized, 0, 0.0};
    if constexpr (std::is_same_v<Real, Scalar>) {
      if (!m_backend.solve(rhs, x)) return {SolveError::SolverFailure, 0, 0.0};
    } else {
      m_b = rhs.template cast<Real>();
      const bool solved = m_backend.solve(m_b, m_x);
      x = m_x.template cast<Scalar>();
      if (!solved) return {SolveError::SolverFailure, 0, 0.0};
    }
    if (constrained) system.constraints.impose(x.data());  // x = y + z (S y = y up to rounding)
    if (!x.allFinite()) return {SolveError::NonFiniteResult, 0, 0.0};
    return {SolveError::None, 0, relative_residual(system, x, m_work, 1)};
  }

  /// The factorisation (for settings beyond drape's, e.g. CHOLMOD's cholmod_common).
  Backend& backend() { return m_backend; }

 private:
  Backend m_backend;
  Eigen::SparseMatrix<Real> m_matrix;
  std::vector<int> m_map;
  VectorX<Real> m_b, m_x;
  VectorX<Scalar> m_work;
  BlockSparseMatrix<Scalar> m_filtered;  // S A S + I - S, with constraints only
  VectorX<Scalar> m_filtered_rhs;
  Index m_analyzed = -1;
};

}  // namespace drape::detail
