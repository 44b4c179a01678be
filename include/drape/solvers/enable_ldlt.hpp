#pragma once
/// \file enable_ldlt.hpp
/// Makes the solver `ldlt` (Eigen SimplicialLDLT with AMD ordering, eigen_direct.hpp) available by
/// name and kind (ImplicitOptions::solver, make_linear_solver()) for double and float. Include it
/// in any one translation unit of the program: it registers the solver during static
/// initialisation. That translation unit compiles the factorisation (~2 s per scalar type), which
/// is why `ldlt` is opt-in (solver_registry.hpp).

#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/solver_registry.hpp"

namespace drape::detail {
inline const bool ldlt_solver_registered = register_solver<EigenLdltSolver>(LinearSolverKind::Ldlt);
}  // namespace drape::detail
