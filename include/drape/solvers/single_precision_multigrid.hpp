#pragma once
/// \file single_precision_multigrid.hpp
/// The multigrid V-cycle (multigrid.hpp) run in float as the preconditioner of a double CG: mixed
/// precision (PreconditionerKind::MultigridFloat).
///
/// Why: at dt = 1/60 a step is about ten V-cycles, and a V-cycle mostly streams the system's
/// values and its level vectors; at 33 x 33 they no longer fit a 512 KiB L2, so the step waits on
/// bytes. A preconditioner only has to approximate A^-1: float's
/// seven digits change nothing CG can see (the same iterations, measured), while CG keeps the
/// residual, the iterate and the product with A in double, so the solution's accuracy is the
/// double solve's. The V-cycle's loops have float AVX2 versions (four or eight lanes), so it
/// costs no more instructions than the double one and moves about half its bytes.
///
/// - analyze(): a float copy of the system's structure (pattern, edge form, layout, constraints)
///   and the float V-cycle's hierarchy on it.
/// - update_in_team(): the edge values and constrained rows rounded to float, then the float
///   V-cycle's update. Level 1's operator is summed in double from the double matrix and rounded
///   once, the coarser ones in float; of the fine block rows only the diagonal (the smoother's) is
///   rounded. Where the cycle reads the fine block rows themselves (constraints filtered into them,
///   no edge form, a one-level hierarchy, or the finest level run by one thread of a team), the
///   whole matrix is rounded and level 1 summed from it.
/// - apply_in_team(): r rounded to float, one float V-cycle, z widened to double.
/// Everything is split over the team in fixed shares: results depend on the thread count only.
/// After analyze(), nothing allocates.

#include <vector>

#include "drape/linalg/linear_system.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/detail/float_copy.hpp"
#include "drape/solvers/multigrid.hpp"
#include "drape/solvers/preconditioner.hpp"

namespace drape {

template <class Scalar = double>
class SinglePrecisionMultigrid final : public Preconditioner<Scalar> {
 public:
  explicit SinglePrecisionMultigrid(const MultigridSettings& settings = {}) : m_cycle(settings) {}

  /// \throws InvalidParameter like MultigridPreconditioner::analyze().
  void analyze(const LinearSystem<Scalar>& system) override;
  /// The float copy of `system`'s values, then the float V-cycle's operators and smoothers.
  bool update_in_team(const LinearSystem<Scalar>& system) override;
  /// `z = B r` with one float V-cycle.
  void apply_in_team(const Scalar* r, Scalar* z) override;

  /// The float V-cycle and the float system it works on (tests and diagnostics).
  const MultigridPreconditioner<float>& cycle() const { return m_cycle; }
  const LinearSystem<float>& single_system() const { return m_single; }

 private:
  LinearSystem<float> m_single;
  MultigridPreconditioner<float> m_cycle;
  std::vector<float> m_r, m_z;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void SinglePrecisionMultigrid<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  m_single = detail::float_structure(system);
  m_r.assign(static_cast<std::size_t>(system.size()), 0.0f);
  m_z.assign(static_cast<std::size_t>(system.size()), 0.0f);
  m_cycle.analyze(m_single);
}

template <class Scalar>
bool SinglePrecisionMultigrid<Scalar>::update_in_team(const LinearSystem<Scalar>& system) {
  detail::round_edges_and_constraints_in_team(system, m_single);
  if (!m_cycle.reads_fine_diagonal_only(m_single)) {
    detail::convert_in_team(system.matrix.values(), m_single.matrix.values(),
                            9 * static_cast<std::size_t>(system.matrix.block_count()));
    return m_cycle.update_in_team(m_single);
  }
  // The cycle reads the fine matrix's diagonal blocks (the smoother) and level 1's sums: those
  // from the system's own matrix, so only the diagonal is rounded (a ninth of the blocks at 33 x 33).
  const int* diagonal = system.matrix.diagonal().data();
  const Scalar* from = system.matrix.values();
  float* to = m_single.matrix.values();
  team_for(system.block_rows(), [&](int r) {
    const std::size_t k = 9 * static_cast<std::size_t>(diagonal[r]);
    for (std::size_t q = k; q < k + 9; ++q) to[q] = static_cast<float>(from[q]);
  });
  return m_cycle.update_in_team(m_single, system.matrix);
}

template <class Scalar>
void SinglePrecisionMultigrid<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
  detail::convert_in_team(r, m_r.data(), m_r.size());
  m_cycle.apply_in_team(m_r.data(), m_z.data());
  detail::convert_in_team(m_z.data(), z, m_z.size());
}

}  // namespace drape
