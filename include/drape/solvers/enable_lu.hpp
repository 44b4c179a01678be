#pragma once
/// \file enable_lu.hpp
/// Makes the solver `lu` (Eigen SparseLU with COLAMD ordering, eigen_direct.hpp) available by name
/// and kind (ImplicitOptions::solver, make_linear_solver()) for double and float. Include it in any
/// one translation unit of the program: it registers the solver during static initialisation. That
/// translation unit compiles SparseLU (~8 s per scalar type), which is why `lu` is opt-in
/// (solver_registry.hpp).

#include "drape/solvers/eigen_direct.hpp"
#include "drape/solvers/solver_registry.hpp"

namespace drape::detail {
inline const bool lu_solver_registered = register_solver<EigenLuSolver>(LinearSolverKind::Lu);
}  // namespace drape::detail
