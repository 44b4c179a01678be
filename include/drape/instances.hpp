#pragma once
/// \file instances.hpp
/// Opt-in, for programs of many translation units: drape's class templates compiled once per
/// program instead of in every source that uses them. Every source that includes this header uses
/// the explicit instantiations it declares instead of compiling its own; the program defines them
/// once, in sources of its own:
/// \code
///   // drape_instances.cpp: what a program that simulates in double needs
///   #include "drape/instances.hpp"
///   namespace drape {
///   DRAPE_INSTANCES(template class, double)
///   DRAPE_SOLVER_INSTANCES(template class, float)
///   }
/// \endcode
/// A program that also simulates in float adds `DRAPE_MODEL_INSTANCES(template class, float)`.
/// The header declares both scalar types, so a missing definition fails to link. Compiled with the
/// same flags, the results are the bits of the header-only library. drape's tests, drape-render
/// and the Python module are built this way (drape's building.md says what it saves); a program
/// that does not include this header is unaffected.
///
/// Not in the lists: EdgeOperator (its AVX2 members exist for one scalar type each, and an
/// explicit instantiation compiles every member), function templates, and the SuiteSparse solvers.

#include "drape/drape.hpp"
#include "drape/solvers/eigen_direct.hpp"

// In each list, `HOW` is `template class` (definitions) or `extern template class` (declarations)
// and `S` the scalar type.

/// The linear algebra and the solvers. A double program needs them for float too: the
/// single-precision multigrid preconditioner runs float ones inside the double solve.
#define DRAPE_SOLVER_INSTANCES(HOW, S)                                              \
  HOW BlockSparseMatrix<S>;                                                         \
  HOW ConstraintFilter<S>;                                                          \
  HOW BlockJacobi<S>;                                                               \
  HOW MultigridHierarchy<S>;                                                        \
  HOW MultigridPreconditioner<S>;                                                   \
  HOW SinglePrecisionMultigrid<S>;                                                  \
  HOW PcgSolver<S>;                                                                 \
  HOW BicgstabSolver<S>;                                                            \
  HOW detail::DirectSolver<S, LinearSolverKind::Ldlt, detail::EigenLdltBackend<S>>; \
  HOW detail::DirectSolver<S, LinearSolverKind::Lu, detail::EigenLuBackend<S>>;

/// The cloth model, its forces, contacts and collisions, the integrators and the scene.
#define DRAPE_MODEL_INSTANCES(HOW, S) \
  HOW Grid<S>;                        \
  HOW SpringSet<S>;                   \
  HOW RigidMotion<S>;                 \
  HOW Collider<S>;                    \
  HOW PinPath<S>;                     \
  HOW PinSet<S>;                      \
  HOW Cloth<S>;                       \
  HOW TriangleBvh<S>;                 \
  HOW SpringFamilies<S>;              \
  HOW ForceAssembler<S>;              \
  HOW JacobianAssembler<S>;           \
  HOW WindField<S>;                   \
  HOW AirDrag<S>;                     \
  HOW AerodynamicForce<S>;            \
  HOW ContactHandler<S>;              \
  HOW SelfCollisionHandler<S>;        \
  HOW Integrator<S>;                  \
  HOW Rk2<S>;                         \
  HOW SymplecticEuler<S>;             \
  HOW ImplicitEuler<S>;               \
  HOW ClothScene<S>;

/// Both lists.
#define DRAPE_INSTANCES(HOW, S) DRAPE_SOLVER_INSTANCES(HOW, S) DRAPE_MODEL_INSTANCES(HOW, S)

namespace drape {
DRAPE_INSTANCES(extern template class, float)
DRAPE_INSTANCES(extern template class, double)
}  // namespace drape
