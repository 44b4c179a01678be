#pragma once
/// \file cholmod.hpp
/// Sparse Cholesky through CHOLMOD (SuiteSparse), via Eigen's CholmodSupport wrapper.
///
/// Only usable when the program links the optional CMake target `drape::suitesparse` (which
/// defines DRAPE_HAS_SUITESPARSE and links CHOLMOD, UMFPACK and OpenBLAS). CHOLMOD's supernodal
/// module is GPL: programs that link it are bound by the GPL; the header-only core is not.
///
/// Configuration (measured in docs/implicit.md): the symbolic analysis (ordering + elimination
/// tree + supernodes) runs once per cloth in `analyze()`; each step only refactorises numerically
/// and solves. The ordering is fixed to one method (AMD by default) instead of CHOLMOD's default of
/// trying several; OpenBLAS is pinned to one thread, because the pthread build keeps its threads
/// spinning after each call and starves drape's own threads (docs/implicit.md, DESIGN.md).

#if !defined(DRAPE_HAS_SUITESPARSE)
#error "drape/solvers/cholmod.hpp needs SuiteSparse: link the CMake target drape::suitesparse"
#endif

#include <cstdint>
#include <vector>

#include <Eigen/CholmodSupport>

#include "drape/solvers/linear_solver.hpp"

#if defined(DRAPE_HAS_OPENBLAS)
extern "C" void openblas_set_num_threads(int);
#endif

namespace drape {

enum class CholmodFactorization : std::uint8_t {
  Supernodal = 0,  ///< supernodal LL^T (BLAS-3 on dense supernodes)
  Simplicial = 1,  ///< simplicial LDL^T (column by column, no BLAS)
};

enum class CholmodOrdering : std::uint8_t {
  Amd = 0,      ///< approximate minimum degree
  Metis = 1,    ///< METIS nested dissection
  Natural = 2,  ///< no reordering
  Default = 3,  ///< CHOLMOD's own default: try AMD, then METIS if AMD fills in a lot, keep the best
};

namespace detail {
/// Pins OpenBLAS to one thread (once per process).
inline void pin_openblas_to_one_thread() {
#if defined(DRAPE_HAS_OPENBLAS)
  static const bool done = (openblas_set_num_threads(1), true);
  (void)done;
#endif
}
}  // namespace detail

template <class Scalar = double>
class CholmodSolver final : public LinearSolver<Scalar> {
 public:
  explicit CholmodSolver(CholmodFactorization factorization = CholmodFactorization::Supernodal,
                         CholmodOrdering ordering = CholmodOrdering::Amd)
      : m_factorization(factorization), m_ordering(ordering) {
    detail::pin_openblas_to_one_thread();
    m_solver.setMode(factorization == CholmodFactorization::Supernodal ? Eigen::CholmodSupernodalLLt : Eigen::CholmodLDLt);
    cholmod_common& c = m_solver.cholmod();
    if (ordering != CholmodOrdering::Default) {
      c.nmethods = 1;
      c.method[0].ordering = ordering == CholmodOrdering::Amd     ? CHOLMOD_AMD
                             : ordering == CholmodOrdering::Metis ? CHOLMOD_METIS
                                                                  : CHOLMOD_NATURAL;
      c.postorder = 1;
    }
  }

  const char* name() const override { return "cholmod"; }
  bool requires_symmetric() const override { return true; }
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
    if (m_solver.info() != Eigen::Success) return {StepError::NotPositiveDefinite, 0, 0.0};
    m_b = b.template cast<double>();
    x = m_solver.solve(m_b).template cast<Scalar>();
    if (m_solver.info() != Eigen::Success) return {StepError::SolverFailure, 0, 0.0};
    if (!x.allFinite()) return {StepError::NonFiniteState, 0, 0.0};
    return {StepError::None, 0, detail::relative_residual(a, b, x, m_work, 1)};
  }

  /// CHOLMOD's settings, for experiments beyond the two enums.
  cholmod_common& common() { return m_solver.cholmod(); }

 private:
  CholmodFactorization m_factorization;
  CholmodOrdering m_ordering;
  Eigen::SparseMatrix<double> m_matrix;
  std::vector<int> m_map;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> m_solver;
  Eigen::VectorXd m_b;
  VectorX<Scalar> m_work;
  Index m_analyzed = -1;
};

}  // namespace drape
