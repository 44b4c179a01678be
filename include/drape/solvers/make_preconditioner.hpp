#pragma once
/// \file make_preconditioner.hpp
/// The one place an iterative solver's preconditioner is made from its kind (PreconditionerKind,
/// preconditioner.hpp) and the settings of the multigrid kinds.

#include <memory>
#include <type_traits>

#include "drape/solvers/algebraic_multigrid.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/multigrid.hpp"
#include "drape/solvers/preconditioner.hpp"
#include "drape/solvers/single_precision_algebraic_multigrid.hpp"
#include "drape/solvers/single_precision_multigrid.hpp"

namespace drape {

/// A new preconditioner of `kind` for a `Scalar` solve. MultigridFloat and AlgebraicMultigridFloat in
/// a float solve are the plain V-cycles (they are already in float). `multigrid` configures the
/// geometric kinds, `amg` the algebraic ones.
template <class Scalar = double>
std::unique_ptr<Preconditioner<Scalar>> make_preconditioner(PreconditionerKind kind,
                                                            const MultigridSettings& multigrid = {},
                                                            const AlgebraicMultigridSettings& amg = {}) {
  switch (kind) {
    case PreconditionerKind::Multigrid: return std::make_unique<MultigridPreconditioner<Scalar>>(multigrid);
    case PreconditionerKind::MultigridFloat:
      if constexpr (std::is_same_v<Scalar, float>)
        return std::make_unique<MultigridPreconditioner<Scalar>>(multigrid);
      else
        return std::make_unique<SinglePrecisionMultigrid<Scalar>>(multigrid);
    case PreconditionerKind::AlgebraicMultigrid: return std::make_unique<AlgebraicMultigrid<Scalar>>(amg);
    case PreconditionerKind::AlgebraicMultigridFloat:
      if constexpr (std::is_same_v<Scalar, float>)
        return std::make_unique<AlgebraicMultigrid<Scalar>>(amg);
      else
        return std::make_unique<SinglePrecisionAlgebraicMultigrid<Scalar>>(amg);
    case PreconditionerKind::BlockJacobi: break;
  }
  return std::make_unique<BlockJacobi<Scalar>>();
}

}  // namespace drape
