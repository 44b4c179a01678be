#pragma once
/// \file preconditioner.hpp
/// The interface of the iterative solvers' preconditioners (block_jacobi.hpp, multigrid.hpp,
/// algebraic_multigrid.hpp, and their float versions inside a double solve):
/// \f$ z = B r \f$ with \f$ B \approx A^{-1} \f$ symmetric positive definite when A is, which is
/// what CG needs. Everything runs inside the solver's thread team: each call is made by every
/// thread of the team (or by the one thread of a serial solve).

#include <array>
#include <cstdint>

#include "drape/core/enum_names.hpp"
#include "drape/linalg/linear_system.hpp"

namespace drape {

/// Which preconditioner an iterative solver uses.
enum class PreconditionerKind : std::uint8_t {
  BlockJacobi = 0,  ///< inverse 3x3 diagonal blocks: needs nothing but the matrix
  Multigrid = 1,    ///< geometric multigrid V-cycle on the lattice: needs LinearSystem::layout
  /// The same V-cycle in float inside a double solve (single_precision_multigrid.hpp): fewer bytes
  /// per cycle; for a float solve, the same as Multigrid.
  MultigridFloat = 2,
  /// Smoothed-aggregation algebraic multigrid V-cycle (algebraic_multigrid.hpp): needs nothing but
  /// the matrix, so it works on any mesh.
  AlgebraicMultigrid = 3,
  /// The same algebraic V-cycle in float inside a double solve
  /// (single_precision_algebraic_multigrid.hpp); for a float solve, the same as AlgebraicMultigrid.
  AlgebraicMultigridFloat = 4,
};

/// True if `kind` needs the system's lattice layout (LinearSystem::layout): the geometric V-cycles.
constexpr bool needs_grid_layout(PreconditionerKind kind) {
  return kind == PreconditionerKind::Multigrid || kind == PreconditionerKind::MultigridFloat;
}

template <>
struct EnumNames<PreconditionerKind> {
  static constexpr const char* parameter = "preconditioner";
  static constexpr std::array<EnumName<PreconditionerKind>, 5> values{
      {{PreconditionerKind::Multigrid, "multigrid"},
       {PreconditionerKind::MultigridFloat, "multigrid-float"},
       {PreconditionerKind::BlockJacobi, "block-jacobi"},
       {PreconditionerKind::AlgebraicMultigrid, "amg"},
       {PreconditionerKind::AlgebraicMultigridFloat, "amg-float"}}};
};

template <class Scalar = double>
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  /// Set-up for systems with `system`'s pattern and layout (once; may allocate).
  /// \throws InvalidParameter if the preconditioner cannot work on such systems.
  virtual void analyze(const LinearSystem<Scalar>& system) = 0;
  /// Takes the current values of `system` (same pattern as in analyze()). Returns false on every
  /// thread if the preconditioner cannot be built from them (a singular block; for multigrid, a
  /// coarse level that is not positive definite). The team waits at the end.
  virtual bool update_in_team(const LinearSystem<Scalar>& system) = 0;
  /// `z = B r` (system size() scalars each). `r` must be complete on entry; `z` is complete on
  /// return (the team waits at the end). Constrained rows are not treated specially: the solver
  /// filters z afterwards.
  virtual void apply_in_team(const Scalar* r, Scalar* z) = 0;
};

}  // namespace drape
