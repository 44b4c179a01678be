#pragma once
/// \file solver_registry.hpp
/// Linear solvers by name, for run-time selection:
///
/// | name       | method                                   | matrix            | needs        |
/// |------------|------------------------------------------|-------------------|--------------|
/// | `cg`       | block-Jacobi PCG, warm-started (pcg.hpp)   | SPD               | header-only  |
/// | `bicgstab` | block-Jacobi BiCGSTAB (bicgstab.hpp)       | any               | header-only  |
/// | `ldlt`     | Eigen SimplicialLDLT, AMD (eigen_direct.hpp) | symmetric, PD   | header-only  |
/// | `lu`       | Eigen SparseLU, COLAMD (eigen_direct.hpp)  | any               | header-only  |
/// | `cholmod`  | CHOLMOD supernodal LL^T, AMD (cholmod.hpp) | SPD               | SuiteSparse  |
/// | `umfpack`  | UMFPACK LU (umfpack.hpp)                   | any               | SuiteSparse  |
///
/// The SuiteSparse ones exist only when DRAPE_HAS_SUITESPARSE is defined (link drape::suitesparse).

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "drape/core/validation.hpp"
#include "drape/solvers/bicgstab.hpp"
#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/pcg.hpp"

#if defined(DRAPE_HAS_SUITESPARSE)
#include "drape/solvers/cholmod.hpp"
#include "drape/solvers/umfpack.hpp"
#endif

namespace drape {

/// Names of the solvers this build supports.
inline std::vector<std::string> available_solvers() {
  std::vector<std::string> names{"cg", "bicgstab", "ldlt", "lu"};
#if defined(DRAPE_HAS_SUITESPARSE)
  names.emplace_back("cholmod");
  names.emplace_back("umfpack");
#endif
  return names;
}

/// Names drape knows, whether or not this build has them.
inline std::vector<std::string> known_solvers() { return {"cg", "bicgstab", "ldlt", "lu", "cholmod", "umfpack"}; }

/// True if `name` needs a symmetric system matrix (rejects the Exact Jacobian).
inline bool solver_requires_symmetric(const std::string& name) {
  return name == "cg" || name == "ldlt" || name == "cholmod";
}

/// True if `name` can hold pinned DOFs by filtering (PinTreatment::Filter).
inline bool solver_supports_filter(const std::string& name) { return name == "cg" || name == "bicgstab"; }

namespace detail {
inline std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// \throws std::invalid_argument for an unknown name or one that needs SuiteSparse when absent.
inline void require_available_solver(const std::string& name) {
  const std::vector<std::string> available = available_solvers();
  if (std::find(available.begin(), available.end(), name) != available.end()) return;
  const std::vector<std::string> known = known_solvers();
  const bool known_name = std::find(known.begin(), known.end(), name) != known.end();
  fail_argument("solver", "'" + name + "'" + (known_name ? " (needs SuiteSparse: link drape::suitesparse)" : ""),
                "one of " + joined(available));
}
}  // namespace detail

/// A solver by name. \throws std::invalid_argument as detail::require_available_solver().
template <class Scalar = double>
std::unique_ptr<LinearSolver<Scalar>> make_linear_solver(const std::string& name, const IterativeSettings& settings = {}) {
  detail::require_available_solver(name);
  if (name == "cg") return std::make_unique<PcgSolver<Scalar>>(settings);
  if (name == "bicgstab") return std::make_unique<BicgstabSolver<Scalar>>(settings);
  if (name == "ldlt") return std::make_unique<EigenLdltSolver<Scalar>>();
  if (name == "lu") return std::make_unique<EigenLuSolver<Scalar>>();
#if defined(DRAPE_HAS_SUITESPARSE)
  if (name == "cholmod") return std::make_unique<CholmodSolver<Scalar>>();
  if (name == "umfpack") return std::make_unique<UmfpackSolver<Scalar>>();
#endif
  detail::fail_argument("solver", "'" + name + "'", "one of " + detail::joined(available_solvers()));
}

}  // namespace drape
