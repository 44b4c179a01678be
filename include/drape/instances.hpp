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
///   DRAPE_INSTANCES(template, double)
///   DRAPE_SOLVER_INSTANCES(template, float)
///   }
/// \endcode
/// A program that also simulates in float adds `DRAPE_MODEL_INSTANCES(template, float)`.
/// The header declares both scalar types, so a missing definition fails to link. Compiled with the
/// same flags, the results are the bits of the header-only library. drape's tests, drape-render
/// and the Python module are built this way (drape's building.md says what it saves); a program
/// that does not include this header is unaffected.
///
/// Not in the lists: EdgeOperator and most function templates, compiled in each source that uses
/// them.

#include "drape/drape.hpp"
#include "drape/solvers/eigen_direct.hpp"

// In each list, `HOW` is `template` (definitions) or `extern template` (declarations) and `S` the
// scalar type.

#if defined(DRAPE_HAS_SUITESPARSE)
#define DRAPE_SUITESPARSE_INSTANCES(HOW, S)                                           \
  HOW class detail::DirectSolver<S, LinearSolverKind::Cholmod, detail::CholmodBackend>; \
  HOW class detail::DirectSolver<S, LinearSolverKind::Umfpack, detail::UmfpackBackend>;
#else
#define DRAPE_SUITESPARSE_INSTANCES(HOW, S)
#endif

/// The linear algebra and the solvers. A double program needs them for float too: the
/// single-precision multigrid preconditioners run float ones inside the double solve.
#define DRAPE_SOLVER_INSTANCES(HOW, S)                                                          \
  HOW class BlockSparseMatrix<S>;                                                               \
  HOW class ConstraintFilter<S>;                                                                \
  HOW class BlockJacobi<S>;                                                                     \
  HOW class MultigridHierarchy<S>;                                                              \
  HOW class MultigridPreconditioner<S>;                                                         \
  HOW class SinglePrecisionMultigrid<S>;                                                        \
  HOW class AggregationHierarchy<S>;                                                            \
  HOW class AlgebraicMultigrid<S>;                                                              \
  HOW class SinglePrecisionAlgebraicMultigrid<S>;                                               \
  HOW class PcgSolver<S>;                                                                       \
  HOW class BicgstabSolver<S>;                                                                  \
  HOW class detail::DirectSolver<S, LinearSolverKind::Ldlt, detail::EigenLdltBackend<S>>;       \
  HOW class detail::DirectSolver<S, LinearSolverKind::Lu, detail::EigenLuBackend<S>>;           \
  DRAPE_SUITESPARSE_INSTANCES(HOW, S)                                                           \
  HOW std::unique_ptr<LinearSolver<S>> make_linear_solver<S>(LinearSolverKind, const IterativeSettings&);

/// The cloth model, its forces, contacts and collisions, the integrators and the scene.
#define DRAPE_MODEL_INSTANCES(HOW, S)    \
  HOW struct Placement<S>;               \
  HOW class Grid<S>;                     \
  HOW class SpringSet<S>;                \
  HOW class RigidMotion<S>;              \
  HOW class Collider<S>;                 \
  HOW class PinPath<S>;                  \
  HOW class PinSet<S>;                   \
  HOW class Cloth<S>;                    \
  HOW class TriangleBvh<S>;              \
  HOW class SpringFamilies<S>;           \
  HOW class ForceAssembler<S>;           \
  HOW class JacobianAssembler<S>;        \
  HOW class WindField<S>;                \
  HOW class AirDrag<S>;                  \
  HOW class AerodynamicForce<S>;         \
  HOW class ContactHandler<S>;           \
  HOW class SelfCollisionHandler<S>;     \
  HOW class Integrator<S>;               \
  HOW class ExplicitIntegrator<S>;       \
  HOW class Rk2<S>;                      \
  HOW class SymplecticEuler<S>;          \
  HOW class ImplicitEuler<S>;            \
  HOW class ClothScene<S>;               \
  HOW std::unique_ptr<Integrator<S>> make_integrator<S>(const Cloth<S>&, IntegratorKind, const ImplicitOptions&);

/// Both lists.
#define DRAPE_INSTANCES(HOW, S) DRAPE_SOLVER_INSTANCES(HOW, S) DRAPE_MODEL_INSTANCES(HOW, S)

namespace drape {
DRAPE_INSTANCES(extern template, float)
DRAPE_INSTANCES(extern template, double)
}  // namespace drape
