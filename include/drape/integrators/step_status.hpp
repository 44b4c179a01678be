#pragma once
/// \file step_status.hpp
/// What a time step reports. A step that fails leaves the state exactly as it was.

#include <cstdint>

#include "drape/solvers/solve_status.hpp"

namespace drape {

enum class StepError : std::uint8_t {
  None = 0,
  NonFiniteState,       ///< the new state would contain NaN or Inf (diverged, or a zero-length spring)
  NotPositiveDefinite,  ///< the linear solver found the system matrix not positive definite
  NoConvergence,        ///< the iterative solver hit its iteration cap above tolerance
  SolverFailure,        ///< any other failure of the linear solver
};

inline const char* to_string(StepError e) {
  switch (e) {
    case StepError::None: return "ok";
    case StepError::NonFiniteState: return "non-finite state (the simulation diverged: reduce dt or stiffness)";
    case StepError::NotPositiveDefinite: return "system matrix not positive definite (try the SPD Jacobian)";
    case StepError::NoConvergence: return "linear solver did not converge within its iteration cap";
    case StepError::SolverFailure: return "linear solver failed";
  }
  return "unknown";
}

/// The step error a failed linear solve causes.
inline StepError step_error(SolveError e) {
  switch (e) {
    case SolveError::None: return StepError::None;
    case SolveError::NonFiniteResult: return StepError::NonFiniteState;
    case SolveError::NotPositiveDefinite: return StepError::NotPositiveDefinite;
    case SolveError::NoConvergence: return StepError::NoConvergence;
    case SolveError::SolverFailure: return StepError::SolverFailure;
  }
  return StepError::SolverFailure;
}

struct StepStatus {
  StepError error = StepError::None;
  int iterations = 0;     ///< linear-solver iterations (0 for direct solvers and RK2)
  double residual = 0.0;  ///< final relative residual of the linear solve (0 for RK2)

  bool ok() const { return error == StepError::None; }
  explicit operator bool() const { return ok(); }
};

}  // namespace drape
