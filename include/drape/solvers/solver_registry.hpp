#pragma once
/// \file solver_registry.hpp
/// drape's linear solvers by kind or name, for run-time selection: which ones this program has,
/// and a factory for each (the table of solvers is solver_kind.hpp).
///
/// Built in: cg and bicgstab always; cholmod and umfpack when DRAPE_HAS_SUITESPARSE is defined
/// (link drape::suitesparse). Opt-in: Eigen's sparse direct solvers take seconds to compile
/// (SparseLU ~8 s, simplicial LDLT ~2 s per scalar type, measured with g++ -O3). A registry that named
/// them in code would compile them into every translation unit that constructs an ImplicitEuler,
/// whether or not it ever uses them. Instead, including `enable_lu.hpp` / `enable_ldlt.hpp` in any
/// one translation unit of a program registers that solver for double and float during static
/// initialisation (before main()); until then it is rejected with a message naming the header.

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "drape/core/enum_names.hpp"
#include "drape/core/validation.hpp"
#include "drape/solvers/bicgstab.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/pcg.hpp"
#include "drape/solvers/solver_kind.hpp"

#if defined(DRAPE_HAS_SUITESPARSE)
#include "drape/solvers/cholmod.hpp"
#include "drape/solvers/umfpack.hpp"
#endif

namespace drape {

namespace detail {

template <class Scalar>
using SolverFactory = std::unique_ptr<LinearSolver<Scalar>> (*)();

template <class Scalar, template <class> class Solver>
std::unique_ptr<LinearSolver<Scalar>> make_direct() {
  return std::make_unique<Solver<Scalar>>();
}

/// The opt-in solvers registered in this program, by kind. A plain flag table: asking what is
/// available instantiates no solver (that would compile every solver into every translation unit).
inline std::array<bool, linear_solver_kind_count>& registered_opt_ins() {
  static std::array<bool, linear_solver_kind_count> registered{};
  return registered;
}

/// The opt-in solvers' factories for `Scalar`, by kind (null: not registered).
template <class Scalar>
std::array<SolverFactory<Scalar>, linear_solver_kind_count>& opt_in_factories() {
  static std::array<SolverFactory<Scalar>, linear_solver_kind_count> factories{};
  return factories;
}

/// Registers the direct solver `Solver<double>` and `Solver<float>` as `kind` (the enable_*.hpp
/// headers call it from an inline variable's initialiser, which runs once per program).
template <template <class> class Solver>
bool register_solver(LinearSolverKind kind) {
  opt_in_factories<double>()[static_cast<std::size_t>(kind)] = &make_direct<double, Solver>;
  opt_in_factories<float>()[static_cast<std::size_t>(kind)] = &make_direct<float, Solver>;
  registered_opt_ins()[static_cast<std::size_t>(kind)] = true;
  return true;
}

}  // namespace detail

/// True if this program has `kind`: the built-in ones always, the SuiteSparse ones when built with
/// them, the opt-in ones once their header is included somewhere in the program.
inline bool solver_available(LinearSolverKind kind) {
  switch (solver_info(kind).requirement) {
    case SolverRequirement::None: return true;
    case SolverRequirement::SuiteSparse:
#if defined(DRAPE_HAS_SUITESPARSE)
      return true;
#else
      return false;
#endif
    case SolverRequirement::OptInHeader: return detail::registered_opt_ins()[static_cast<std::size_t>(kind)];
  }
  return false;
}

/// The kinds this program has, in table order.
inline std::vector<LinearSolverKind> available_solvers() {
  std::vector<LinearSolverKind> kinds;
  for (const EnumName<LinearSolverKind>& e : EnumNames<LinearSolverKind>::values)
    if (solver_available(e.value)) kinds.push_back(e.value);
  return kinds;
}

/// \throws InvalidParameter naming `solver` if this program lacks `kind`: the message says what it
/// needs (a header to include, or SuiteSparse) and lists the solvers it has.
inline void require_solver_available(LinearSolverKind kind) {
  if (solver_available(kind)) return;
  std::string have;
  for (LinearSolverKind k : available_solvers()) have += (have.empty() ? "" : ", ") + std::string(to_string(k));
  detail::fail_argument("solver", "'" + std::string(to_string(kind)) + "' (" + solver_requirement_text(kind) + ")",
                        have);
}

/// A new solver of `kind`; `settings` configure the iterative ones.
/// \throws InvalidParameter as require_solver_available(), or if an opt-in solver is asked for with
/// a scalar type other than double and float.
template <class Scalar = double>
std::unique_ptr<LinearSolver<Scalar>> make_linear_solver(LinearSolverKind kind,
                                                         const IterativeSettings& settings = {}) {
  require_solver_available(kind);
  switch (kind) {
    case LinearSolverKind::Cg: return std::make_unique<PcgSolver<Scalar>>(settings);
    case LinearSolverKind::Bicgstab: return std::make_unique<BicgstabSolver<Scalar>>(settings);
#if defined(DRAPE_HAS_SUITESPARSE)
    case LinearSolverKind::Cholmod: return std::make_unique<CholmodSolver<Scalar>>();
    case LinearSolverKind::Umfpack: return std::make_unique<UmfpackSolver<Scalar>>();
#endif
    default: break;
  }
  const detail::SolverFactory<Scalar> make = detail::opt_in_factories<Scalar>()[static_cast<std::size_t>(kind)];
  if (!make)
    detail::fail_argument("solver", "'" + std::string(to_string(kind)) + "' for this scalar type", "double or float");
  return make();
}

/// make_linear_solver() by name. \throws InvalidParameter for an unknown name, listing the names.
template <class Scalar = double>
std::unique_ptr<LinearSolver<Scalar>> make_linear_solver(std::string_view name,
                                                         const IterativeSettings& settings = {}) {
  return make_linear_solver<Scalar>(parse<LinearSolverKind>(name), settings);
}

}  // namespace drape
