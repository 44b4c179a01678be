#pragma once
/// \file linear_solver.hpp
/// The interface every linear solver of the implicit integrator implements (drape's own, listed in
/// solver_kind.hpp, and any a user writes), and the settings of the iterative ones.
///
/// Life cycle: `analyze(system)` once per pattern (symbolic work: ordering, symbolic
/// factorisation, workspaces, multigrid hierarchy), then `solve(system, x)` every step with new
/// values in the same pattern. `x` holds the warm start on entry (iterative solvers use it; direct
/// solvers ignore it) and the solution on exit. A solver that accepts constraints
/// (`capabilities().supports_constraints`) honours `system.constraints`; the others need every
/// constrained unknown eliminated from the system.

#include <string>

#include "drape/core/validation.hpp"
#include "drape/linalg/linear_system.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/preconditioner.hpp"
#include "drape/solvers/solve_status.hpp"

namespace drape {

/// What a solver can do; the implicit integrator checks its options against it.
struct SolverCapabilities {
  bool symmetric_only = false;        ///< needs a symmetric matrix (rejects the Exact Jacobian)
  bool supports_constraints = false;  ///< honours LinearSystem::constraints (e.g. filtered pins)
  bool iterative = false;             ///< warm-started from x; reports iterations
};

template <class Scalar = double>
class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  /// A name for messages (drape's solvers: the name they are selected by, "cg", "ldlt", ...).
  virtual std::string name() const = 0;
  virtual SolverCapabilities capabilities() const = 0;
  /// Set-up for systems with `system`'s pattern. \throws InvalidParameter if the solver cannot
  /// work on them (e.g. the multigrid preconditioner without a lattice layout).
  virtual void analyze(const LinearSystem<Scalar>& system) = 0;
  /// Solves `system` (pattern as in analyze(), which it calls itself if the size changed).
  virtual SolveStatus solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) = 0;
};

/// Settings of the iterative solvers.
struct IterativeSettings {
  double tolerance = 1e-6;  ///< stop when |S(b - A x)| <= tolerance |S b|
  int max_iterations = 1000;
  int threads = 0;  ///< 0 = all available
  PreconditionerKind preconditioner = PreconditionerKind::BlockJacobi;

  /// \throws InvalidParameter for tolerance outside (0, 1), max_iterations < 1 or threads < 0.
  void validate() const {
    if (!(std::isfinite(tolerance) && tolerance > 0 && tolerance < 1))
      detail::fail_argument("tolerance", detail::to_text(tolerance), "finite, > 0 and < 1");
    detail::require_at_least("max_iterations", max_iterations, 1);
    detail::require_at_least("threads", threads, 0);
  }
};

}  // namespace drape
