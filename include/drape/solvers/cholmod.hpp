#pragma once
/// \file cholmod.hpp
/// Sparse Cholesky through CHOLMOD (SuiteSparse), via Eigen's CholmodSupport wrapper (the shared
/// body is direct_solver.hpp).
///
/// Only usable when the program links the optional CMake target `drape::suitesparse` (which
/// defines DRAPE_HAS_SUITESPARSE and links CHOLMOD, UMFPACK and OpenBLAS). CHOLMOD's supernodal
/// module is GPL: programs that link it are bound by the GPL; the header-only core is not.
///
/// Configuration (measured in drape's implicit.md): the symbolic analysis (ordering + elimination
/// tree + supernodes) runs once per cloth; each step only refactorises numerically and solves.
/// The ordering is fixed to one method (AMD by default) instead of CHOLMOD's default of trying
/// several; OpenBLAS is pinned to one thread, because the pthread build keeps its threads
/// spinning after each call and starves drape's own threads (drape's implicit.md).

#if !defined(DRAPE_HAS_SUITESPARSE)
#error "drape/solvers/cholmod.hpp needs SuiteSparse: link the CMake target drape::suitesparse"
#endif

#include <cstdint>

#include <Eigen/CholmodSupport>

#include "drape/solvers/direct_solver.hpp"

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

struct CholmodBackend {
  using Real = double;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> solver;

  explicit CholmodBackend(CholmodFactorization factorization = CholmodFactorization::Supernodal,
                          CholmodOrdering ordering = CholmodOrdering::Amd) {
    pin_openblas_to_one_thread();
    solver.setMode(factorization == CholmodFactorization::Supernodal ? Eigen::CholmodSupernodalLLt
                                                                     : Eigen::CholmodLDLt);
    cholmod_common& c = solver.cholmod();
    if (ordering != CholmodOrdering::Default) {
      c.nmethods = 1;
      c.method[0].ordering = ordering == CholmodOrdering::Amd     ? CHOLMOD_AMD
                             : ordering == CholmodOrdering::Metis ? CHOLMOD_METIS
                                                                  : CHOLMOD_NATURAL;
      c.postorder = 1;
    }
  }
  /// CHOLMOD's settings, for experiments beyond the two enums.
  cholmod_common& common() { return solver.cholmod(); }

  void analyze(const Eigen::SparseMatrix<double>& a) { solver.analyzePattern(a); }
  SolveError factorize(const Eigen::SparseMatrix<double>& a) {
    solver.factorize(a);
    return solver.info() == Eigen::Success ? SolveError::None : SolveError::NotPositiveDefinite;
  }
  bool solve(const VectorX<double>& b, VectorX<double>& x) {
    x = solver.solve(b);
    return solver.info() == Eigen::Success;
  }
};

}  // namespace detail

/// `CholmodSolver<double> s(CholmodFactorization::Simplicial, CholmodOrdering::Metis)` for other
/// settings than the defaults; `s.backend().common()` for CHOLMOD's own.
template <class Scalar = double>
using CholmodSolver = detail::DirectSolver<Scalar, LinearSolverKind::Cholmod, detail::CholmodBackend>;

}  // namespace drape
