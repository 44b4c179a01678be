#pragma once
/// \file solve_status.hpp
/// What a linear solve reports. A solver never hides a failure: a status that is not ok() says why.

#include <array>
#include <cstdint>

#include "drape/core/enum_names.hpp"

namespace drape {

enum class SolveError : std::uint8_t {
  None = 0,
  NonFiniteResult,      ///< the solution (or a quantity on the way to it) is NaN or Inf
  NotPositiveDefinite,  ///< a solver for symmetric positive definite matrices met one that is not
  NoConvergence,        ///< an iterative solver hit its iteration cap above its tolerance
  SolverFailure,        ///< any other failure (a singular matrix or preconditioner block, a breakdown)
};

template <>
struct EnumNames<SolveError> {
  static constexpr const char* parameter = "solve error";
  static constexpr std::array<EnumName<SolveError>, 5> values{
      {{SolveError::None, "ok"},
       {SolveError::NonFiniteResult, "non-finite result"},
       {SolveError::NotPositiveDefinite, "not positive definite"},
       {SolveError::NoConvergence, "no convergence"},
       {SolveError::SolverFailure, "solver failure"}}};
};

struct SolveStatus {
  SolveError error = SolveError::None;
  int iterations = 0;     ///< iterations of an iterative solver (0 for direct solvers)
  double residual = 0.0;  ///< final relative residual |b - A x| / |b| (of the filtered system)

  bool ok() const { return error == SolveError::None; }
  explicit operator bool() const { return ok(); }
};

}  // namespace drape
