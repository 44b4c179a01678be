#pragma once
/// \file solver_kind.hpp
/// drape's linear solvers, in one table: the name each is selected by, its method, its
/// capabilities and what a program needs to have it. Selection by name, availability and the
/// factories are in solver_registry.hpp.
///
// clang-format off
/// | name       | method                                          | matrix | constraints     | needs                                   |
/// |------------|-------------------------------------------------|--------|-----------------|-----------------------------------------|
/// | `cg`       | PCG, block Jacobi or multigrid, warm-started    | SPD    | filtered        | header-only                             |
/// | `bicgstab` | BiCGSTAB with block Jacobi, warm-started        | any    | filtered        | header-only                             |
/// | `ldlt`     | Eigen SimplicialLDLT, AMD ordering              | SPD    | modified system | opt-in: `drape/solvers/enable_ldlt.hpp` |
/// | `lu`       | Eigen SparseLU, COLAMD ordering                 | any    | modified system | opt-in: `drape/solvers/enable_lu.hpp`   |
/// | `cholmod`  | CHOLMOD supernodal LL^T, AMD ordering           | SPD    | modified system | SuiteSparse (`drape::suitesparse`)      |
/// | `umfpack`  | UMFPACK LU                                      | any    | modified system | SuiteSparse (`drape::suitesparse`)      |
///
/// "filtered": the constraint filter inside the iteration (pcg.hpp); "modified system": the
/// equivalent unconstrained system of the same pattern (linalg/filtered_system.hpp).
// clang-format on

#include <array>
#include <cstdint>
#include <string>

#include "drape/core/enum_names.hpp"
#include "drape/solvers/linear_solver.hpp"

namespace drape {

enum class LinearSolverKind : std::uint8_t { Cg = 0, Bicgstab = 1, Ldlt = 2, Lu = 3, Cholmod = 4, Umfpack = 5 };
inline constexpr int linear_solver_kind_count = 6;

template <>
struct EnumNames<LinearSolverKind> {
  static constexpr const char* parameter = "solver";
  static constexpr std::array<EnumName<LinearSolverKind>, linear_solver_kind_count> values{
      {{LinearSolverKind::Cg, "cg"},
       {LinearSolverKind::Bicgstab, "bicgstab"},
       {LinearSolverKind::Ldlt, "ldlt"},
       {LinearSolverKind::Lu, "lu"},
       {LinearSolverKind::Cholmod, "cholmod"},
       {LinearSolverKind::Umfpack, "umfpack"}}};
};

/// What a program needs to have a solver.
enum class SolverRequirement : std::uint8_t {
  None,         ///< header-only, always there
  OptInHeader,  ///< include `drape/solvers/enable_<name>.hpp` in one source file (compile time)
  SuiteSparse,  ///< link the optional CMake target drape::suitesparse (GPL/LGPL)
};

struct LinearSolverInfo {
  LinearSolverKind kind;
  const char* method;
  SolverCapabilities capabilities;
  SolverRequirement requirement;
};

/// The row of the table for `kind`.
inline const LinearSolverInfo& solver_info(LinearSolverKind kind) {
  static constexpr std::array<LinearSolverInfo, linear_solver_kind_count> table{{
      {LinearSolverKind::Cg,
       "preconditioned conjugate gradients (block Jacobi or multigrid), warm-started",
       {true, true, true},
       SolverRequirement::None},
      {LinearSolverKind::Bicgstab,
       "BiCGSTAB with block Jacobi, warm-started",
       {false, true, true},
       SolverRequirement::None},
      {LinearSolverKind::Ldlt,
       "Eigen SimplicialLDLT, AMD ordering",
       {true, true, false},
       SolverRequirement::OptInHeader},
      {LinearSolverKind::Lu, "Eigen SparseLU, COLAMD ordering", {false, true, false}, SolverRequirement::OptInHeader},
      {LinearSolverKind::Cholmod,
       "CHOLMOD supernodal LL^T, AMD ordering",
       {true, true, false},
       SolverRequirement::SuiteSparse},
      {LinearSolverKind::Umfpack, "UMFPACK LU", {false, true, false}, SolverRequirement::SuiteSparse},
  }};
  return table[static_cast<std::size_t>(kind)];
}

/// What a program must do to have `kind`, as a sentence for error messages ("" if nothing).
inline std::string solver_requirement_text(LinearSolverKind kind) {
  switch (solver_info(kind).requirement) {
    case SolverRequirement::None: return "";
    case SolverRequirement::OptInHeader:
      return std::string("opt-in: #include <drape/solvers/enable_") + to_string(kind) +
             ".hpp> in one source file of the program";
    case SolverRequirement::SuiteSparse: return "needs SuiteSparse: link drape::suitesparse";
  }
  return "";
}

namespace detail {
/// Base of drape's own solvers: name and capabilities come from the table.
template <class Scalar, LinearSolverKind Kind>
class BuiltInSolver : public LinearSolver<Scalar> {
 public:
  std::string name() const final { return to_string(Kind); }
  SolverCapabilities capabilities() const final { return solver_info(Kind).capabilities; }
};
}  // namespace detail

}  // namespace drape
