#pragma once
/// \file single_precision_algebraic_multigrid.hpp
/// The algebraic multigrid V-cycle (algebraic_multigrid.hpp) run in float as the preconditioner of
/// a double CG: mixed precision (PreconditionerKind::AlgebraicMultigridFloat, "amg-float"), as
/// single_precision_multigrid.hpp does for the geometric V-cycle.
///
/// Why: a V-cycle mostly streams its operators' blocks and its level vectors, and a preconditioner
/// only has to approximate A^-1: float's seven digits change nothing CG can see (the same
/// iterations, measured in drape's amg.md), while CG keeps the residual, the iterate and the product
/// with A in double, so the solution's accuracy is the double solve's. The float cycle moves about
/// half the bytes of the double one, and its update (Galerkin products, Lanczos steps, the coarsest
/// Cholesky factor) sums float blocks.
///
/// - analyze(): a float copy of the system's structure (pattern, edge form, layout) with its values
///   and constraints rounded, and AlgebraicMultigrid<float>'s analyze() on it: the float hierarchy
///   is aggregated from the rounded values when they are assembled, else at the first update (the
///   only update that allocates).
/// - update_in_team(): the matrix and the constraints rounded to float (the edge values too where
///   the float cycle reads the edge form, AlgebraicMultigrid::reads_edge_form()), then the float
///   V-cycle's update: the filtered fine operator, P, the Galerkin operators and the smoothers are
///   all formed in float.
/// - apply_in_team(): r rounded to float, one float V-cycle, z widened to double.
/// Every value is rounded on its own and AlgebraicMultigrid<float> gives the same bits for any team
/// size, so this preconditioner does too. After the first update, nothing allocates.

#include <vector>

#include "drape/linalg/linear_system.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/algebraic_multigrid.hpp"
#include "drape/solvers/detail/float_copy.hpp"
#include "drape/solvers/preconditioner.hpp"

namespace drape {

template <class Scalar = double>
class SinglePrecisionAlgebraicMultigrid final : public Preconditioner<Scalar> {
 public:
  explicit SinglePrecisionAlgebraicMultigrid(const AlgebraicMultigridSettings& settings = {}) : m_cycle(settings) {}

  /// \throws InvalidParameter like AlgebraicMultigrid::analyze().
  void analyze(const LinearSystem<Scalar>& system) override;
  /// The float copy of `system`'s values and constraints, then the float V-cycle's operators,
  /// smoothers and coarsest factor. False like AlgebraicMultigrid::update_in_team().
  bool update_in_team(const LinearSystem<Scalar>& system) override;
  /// `z = B r` with one float V-cycle.
  void apply_in_team(const Scalar* r, Scalar* z) override;

  /// The float V-cycle and the float system it works on (tests and diagnostics).
  const AlgebraicMultigrid<float>& cycle() const { return m_cycle; }
  const LinearSystem<float>& single_system() const { return m_single; }

 private:
  LinearSystem<float> m_single;
  AlgebraicMultigrid<float> m_cycle;
  std::vector<float> m_r, m_z;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void SinglePrecisionAlgebraicMultigrid<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  m_single = detail::float_structure(system);
  // The values too: AlgebraicMultigrid aggregates from them if they are assembled.
  const Scalar* from = system.matrix.values();
  float* to = m_single.matrix.values();
  for (std::size_t q = 0; q < 9 * static_cast<std::size_t>(system.matrix.block_count()); ++q)
    to[q] = static_cast<float>(from[q]);
  m_single.constraints.assign(system.constraints);
  m_r.assign(static_cast<std::size_t>(system.size()), 0.0f);
  m_z.assign(static_cast<std::size_t>(system.size()), 0.0f);
  m_cycle.analyze(m_single);
}

template <class Scalar>
bool SinglePrecisionAlgebraicMultigrid<Scalar>::update_in_team(const LinearSystem<Scalar>& system) {
  // The cycle's filter, Galerkin products and smoothers read every block of the fine matrix.
  detail::convert_in_team(system.matrix.values(), m_single.matrix.values(),
                          9 * static_cast<std::size_t>(system.matrix.block_count()));
  detail::round_edges_and_constraints_in_team(system, m_single, m_cycle.reads_edge_form(system));
  return m_cycle.update_in_team(m_single);
}

template <class Scalar>
void SinglePrecisionAlgebraicMultigrid<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
  detail::convert_in_team(r, m_r.data(), m_r.size());
  m_cycle.apply_in_team(m_r.data(), m_z.data());
  detail::convert_in_team(m_z.data(), z, m_z.size());
}

}  // namespace drape
