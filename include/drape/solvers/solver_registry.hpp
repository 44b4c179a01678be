#pragma once
/// \file solver_registry.hpp
/// Linear solvers by name, for run-time selection:
///
/// | name       | method                                     | matrix          | needs                                   |
/// |------------|--------------------------------------------|-----------------|-----------------------------------------|
/// | `cg`       | block-Jacobi PCG, warm-started (pcg.hpp)   | SPD             | header-only                             |
/// | `bicgstab` | block-Jacobi BiCGSTAB (bicgstab.hpp)       | any             | header-only                             |
/// | `ldlt`     | Eigen SimplicialLDLT, AMD (eigen_direct.hpp) | symmetric, PD | opt-in: `drape/solvers/enable_ldlt.hpp` |
/// | `lu`       | Eigen SparseLU, COLAMD (eigen_direct.hpp)  | any             | opt-in: `drape/solvers/enable_lu.hpp`   |
/// | `cholmod`  | CHOLMOD supernodal LL^T, AMD (cholmod.hpp) | SPD             | SuiteSparse                             |
/// | `umfpack`  | UMFPACK LU (umfpack.hpp)                   | any             | SuiteSparse                             |
///
/// The SuiteSparse ones exist only when DRAPE_HAS_SUITESPARSE is defined (link drape::suitesparse).
///
/// Opt-in solvers: Eigen's sparse direct solvers take seconds to compile (SparseLU ~8 s, simplicial
/// LDLT ~2 s per scalar type; bench/analysis.md). A registry that named them in code would compile
/// them into every translation unit that constructs an ImplicitEuler, whether or not it ever uses
/// them. Instead, including `enable_lu.hpp` / `enable_ldlt.hpp` in any one translation unit of a
/// program registers that solver for double and float during static initialisation (before
/// main()); until then its name is rejected with a message naming the header.

#include <algorithm>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drape/core/validation.hpp"
#include "drape/solvers/bicgstab.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/pcg.hpp"

#if defined(DRAPE_HAS_SUITESPARSE)
#include "drape/solvers/cholmod.hpp"
#include "drape/solvers/umfpack.hpp"
#endif

namespace drape {

namespace detail {

template <class Scalar>
using SolverFactory = std::unique_ptr<LinearSolver<Scalar>> (*)();

/// Opt-in solvers registered so far for one scalar type, in registration order.
template <class Scalar>
std::vector<std::pair<std::string, SolverFactory<Scalar>>>& registered_solvers() {
  static std::vector<std::pair<std::string, SolverFactory<Scalar>>> table;
  return table;
}

/// Registers `Solver<double>` and `Solver<float>` under `name` (the enable_*.hpp headers call it
/// from an inline variable's initialiser, which runs once per program). Returns true.
template <template <class> class Solver>
bool register_solver(const char* name) {
  registered_solvers<double>().emplace_back(name, []() -> std::unique_ptr<LinearSolver<double>> {
    return std::make_unique<Solver<double>>();
  });
  registered_solvers<float>().emplace_back(name, []() -> std::unique_ptr<LinearSolver<float>> {
    return std::make_unique<Solver<float>>();
  });
  return true;
}

template <class Scalar>
SolverFactory<Scalar> registered_solver(const std::string& name) {
  for (const auto& [registered, make] : registered_solvers<Scalar>())
    if (registered == name) return make;
  return nullptr;
}

/// What a known solver that this program lacks needs.
inline std::string solver_requirement(const std::string& name) {
  if (name == "ldlt" || name == "lu")
    return "opt-in: #include <drape/solvers/enable_" + name + ".hpp> in one source file of the program";
  return "needs SuiteSparse: link drape::suitesparse";
}

}  // namespace detail

/// Names drape knows, whether or not this program has them.
inline std::vector<std::string> known_solvers() { return {"cg", "bicgstab", "ldlt", "lu", "cholmod", "umfpack"}; }

/// Names of the solvers this program supports (the built-in ones, the opt-in ones registered so
/// far, and the SuiteSparse ones when built with them), in the order of known_solvers().
inline std::vector<std::string> available_solvers() {
  std::vector<std::string> names;
  for (const std::string& name : known_solvers()) {
    bool available = name == "cg" || name == "bicgstab" || detail::registered_solver<double>(name) != nullptr;
#if defined(DRAPE_HAS_SUITESPARSE)
    available = available || name == "cholmod" || name == "umfpack";
#endif
    if (available) names.push_back(name);
  }
  return names;
}

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

/// \throws std::invalid_argument for an unknown name, or a known one this program lacks (the
/// message says what it needs: a header to include, or SuiteSparse).
inline void require_available_solver(const std::string& name) {
  const std::vector<std::string> available = available_solvers();
  if (std::find(available.begin(), available.end(), name) != available.end()) return;
  const std::vector<std::string> known = known_solvers();
  const bool known_name = std::find(known.begin(), known.end(), name) != known.end();
  fail_argument("solver", "'" + name + "'" + (known_name ? " (" + solver_requirement(name) + ")" : ""),
                "one of " + joined(available));
}
}  // namespace detail

/// A solver by name. \throws std::invalid_argument as detail::require_available_solver(), or if an
/// opt-in solver is asked for with a scalar type other than double and float.
template <class Scalar = double>
std::unique_ptr<LinearSolver<Scalar>> make_linear_solver(const std::string& name, const IterativeSettings& settings = {}) {
  detail::require_available_solver(name);
  if (name == "cg") return std::make_unique<PcgSolver<Scalar>>(settings);
  if (name == "bicgstab") return std::make_unique<BicgstabSolver<Scalar>>(settings);
#if defined(DRAPE_HAS_SUITESPARSE)
  if (name == "cholmod") return std::make_unique<CholmodSolver<Scalar>>();
  if (name == "umfpack") return std::make_unique<UmfpackSolver<Scalar>>();
#endif
  if (const detail::SolverFactory<Scalar> make = detail::registered_solver<Scalar>(name)) return make();
  detail::fail_argument("solver", "'" + name + "' for this scalar type", "double or float");
}

}  // namespace drape
