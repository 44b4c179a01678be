#pragma once
/// \file multigrid.hpp
/// Geometric multigrid V-cycle on the cloth's lattice: the preconditioner of CG (pcg.hpp), in
/// double, or in float inside the double CG (single_precision_multigrid.hpp, the default).
///
/// Why: the implicit system is M plus dt^2 times a stiffness "Laplacian" of the lattice, so its
/// condition number grows with ks dt^2 / m and with the grid; block-Jacobi CG needed 120-190
/// iterations at dt = 1/60 with the default springs. Jacobi only damps the rough part of the
/// error; the V-cycle removes the smooth part on coarser lattices, so CG needs about ten iterations
/// at every grid size (drape's implicit.md, "Multigrid preconditioner").
///
/// - Levels, transfer operators and Galerkin coarse operators: multigrid_hierarchy.hpp.
/// - Smoother: block Jacobi (block_jacobi.hpp) with weight `omega`, `sweeps` times before and after
///   the coarse correction. With restriction \f$ R = P^T \f$ the cycle is a fixed symmetric
///   positive definite linear operator, which is what CG needs from a preconditioner.
/// - Coarsest level: solved exactly by dense Cholesky (dense_cholesky.hpp).
/// - Threads: every operation runs inside the caller's team, split by rows; levels smaller than
///   `min_team_rows` run on one thread. Every row sums its terms in a fixed order: results do not
///   depend on scheduling. After analyze(), nothing allocates.
/// - Constraints (pins under the filter, moving pins, contacts): the hierarchy is built from the
///   filtered operator \f$ S A S + I - S \f$ (the matrix CG's filtered iteration works with), so
///   constrained rows are identity rows on the finest level and their coupling is gone from the
///   coarse operators; CG filters the cycle's output (pcg.hpp). Built from A itself, the cycle
///   kept correcting constrained unknowns through the coarse levels: 94 instead of ~16 CG
///   iterations per step with moving pins, 2-3x with contacts. With routing
///   (multigrid_hierarchy.hpp), level 1 is summed from \f$ S A' S + I - S \f$, the routed
///   operator filtered the same way.

#include <algorithm>
#include <atomic>
#include <type_traits>
#include <vector>

#include "drape/config.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/dense_cholesky.hpp"
#include "drape/solvers/multigrid_hierarchy.hpp"
#include "drape/solvers/preconditioner.hpp"

namespace drape {

template <class Scalar = double>
class MultigridPreconditioner final : public Preconditioner<Scalar> {
 public:
  explicit MultigridPreconditioner(const MultigridSettings& settings = {}) : m_settings(settings) {}

  /// Builds the hierarchy for `system`'s pattern and layout. \throws InvalidParameter naming
  /// `preconditioner` if the system has no lattice layout, `grid layout` if the layout does not
  /// describe the matrix's rows, or a setting out of range.
  void analyze(const LinearSystem<Scalar>& system) override;
  /// Coarse operators, smoothers and the coarsest factorisation for `system`'s values.
  bool update_in_team(const LinearSystem<Scalar>& system) override { return update_in_team(system, system.matrix); }
  /// update_in_team() with level 1 summed from `fine`: `system.matrix`'s values in double for a
  /// float cycle (single_precision_multigrid.hpp), summed in double and rounded once. Then only the
  /// diagonal blocks of `system.matrix` are read, and they must hold the current values; only for
  /// a system with reads_fine_diagonal_only().
  template <class Source>
  bool update_in_team(const LinearSystem<Scalar>& system, const BlockSparseMatrix<Source>& fine);
  /// True if an update and a cycle on `system` (in the calling team) read no block of its matrix
  /// off the diagonal but through level 1's sums: the system has no constraints, a valid edge form
  /// (the fine residuals' product) and coarse levels, and the finest level runs on the team (or the
  /// team is one thread).
  bool reads_fine_diagonal_only(const LinearSystem<Scalar>& system) const {
    return level_count() > 1 && system.constraints.empty() && system.edges.valid() &&
           (team_level(0) || team_size() == 1);
  }
  /// One V-cycle from a zero initial guess: `z = B r`.
  void apply_in_team(const Scalar* r, Scalar* z) override;

  bool analyzed() const { return m_hierarchy.analyzed(); }
  const MultigridHierarchy<Scalar>& hierarchy() const { return m_hierarchy; }
  int level_count() const { return m_hierarchy.level_count(); }
  /// Block rows of each level, finest first.
  std::vector<int> level_rows() const;
  /// Operator of level l >= 1 (after update_in_team()).
  const BlockSparseMatrix<Scalar>& level_matrix(int l) const { return m_hierarchy.matrix(l); }
  /// See MultigridHierarchy::prolongation().
  Eigen::SparseMatrix<Scalar> prolongation(int l) const { return m_hierarchy.prolongation(l); }

 private:
  /// Vectors of one level: right-hand side, iterate (levels >= 1 own b and x; level 0 uses the
  /// caller's r and z), residual.
  struct LevelVectors {
    VectorX<Scalar> b, x, r;
  };

  const BlockSparseMatrix<Scalar>& matrix(int l) const { return l == 0 ? *m_fine : m_hierarchy.matrix(l); }
  /// `target` = S `source` S + I - S for `system`'s constraints, block by block (the team shares
  /// the rows; `target` has source's pattern and may be source itself).
  static void filter(const LinearSystem<Scalar>& system, const BlockSparseMatrix<Scalar>& source,
                     BlockSparseMatrix<Scalar>& target);
  /// The operator level l >= 1 is summed from.
  const BlockSparseMatrix<Scalar>& finer(int l) const {
    return l == 1 && m_hierarchy.routed() ? m_hierarchy.routed_matrix() : matrix(l - 1);
  }
  /// Level l's loops are shared by the team, or run by the one thread that calls them.
  bool team_level(int l) const { return m_hierarchy.rows(l) >= m_settings.min_team_rows; }
  const Scalar* rhs(int l) const { return l == 0 ? m_r_in : m_vectors[static_cast<std::size_t>(l)].b.data(); }
  Scalar* iterate(int l) { return l == 0 ? m_z_out : m_vectors[static_cast<std::size_t>(l)].x.data(); }
  /// r = b - A x on level l's rows.
  void residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const;
  /// x = omega D^-1 t (`first`) or x += omega D^-1 t on level l.
  void smooth(int l, const Scalar* t, bool first, bool team);
  /// One V-cycle from level l down, with a zero initial guess on level l.
  void cycle(int l, bool team);
  /// The dense Cholesky factor of the coarsest level; false if it is not positive definite.
  bool factorise_coarsest();

  MultigridSettings m_settings;
  MultigridHierarchy<Scalar> m_hierarchy;
  std::vector<BlockJacobi<Scalar>> m_smoothers;  // one per level but the coarsest
  std::vector<LevelVectors> m_vectors;
  const LinearSystem<Scalar>* m_system = nullptr;
  const BlockSparseMatrix<Scalar>* m_fine = nullptr;
  BlockSparseMatrix<Scalar> m_filtered;  // S A S + I - S of a system with constraints
  std::vector<Scalar> m_coarsest;        // dense Cholesky factor L (row-major, lower) of the coarsest level
  int m_coarsest_size = 0;
  std::atomic<int> m_failed{0};
  const Scalar* m_r_in = nullptr;
  Scalar* m_z_out = nullptr;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
std::vector<int> MultigridPreconditioner<Scalar>::level_rows() const {
  std::vector<int> rows;
  for (int l = 0; l < level_count(); ++l) rows.push_back(m_hierarchy.rows(l));
  return rows;
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  if (system.layout.empty())
    detail::fail_argument("preconditioner", "multigrid without a grid layout",
                          "block-jacobi, or multigrid for a system with LinearSystem::layout set "
                          "(JacobianAssembler::make_system() sets it)");
  m_settings.validate();
  m_hierarchy.analyze(system.layout, system.matrix, m_settings.max_direct_rows, m_settings.route_through_midpoints);
  const int levels = level_count();
  m_smoothers = std::vector<BlockJacobi<Scalar>>(static_cast<std::size_t>(levels));
  m_vectors.assign(static_cast<std::size_t>(levels), LevelVectors{});
  for (int l = 0; l < levels; ++l) {
    const Index n = 3 * static_cast<Index>(m_hierarchy.rows(l));
    LevelVectors& v = m_vectors[static_cast<std::size_t>(l)];
    v.r.setZero(n);
    if (l > 0) {
      v.b.setZero(n);
      v.x.setZero(n);
    }
    if (l + 1 < levels) m_smoothers[static_cast<std::size_t>(l)].resize(m_hierarchy.rows(l));
  }
  const Index n = 3 * static_cast<Index>(m_hierarchy.rows(levels - 1));
  m_coarsest_size = static_cast<int>(n);
  m_coarsest.assign(static_cast<std::size_t>(n * n), Scalar(0));
  m_system = &system;
  m_fine = &system.matrix;
  m_filtered = system.matrix;  // the pattern, for systems with constraints
}

template <class Scalar>
bool MultigridPreconditioner<Scalar>::factorise_coarsest() {
  const BlockSparseMatrix<Scalar>& m = matrix(level_count() - 1);
  const int n = m_coarsest_size;
  std::fill(m_coarsest.begin(), m_coarsest.end(), Scalar(0));
  for (int r = 0; r < m.block_rows(); ++r)
    for (int k = m.row_begin()[static_cast<std::size_t>(r)]; k < m.row_begin()[static_cast<std::size_t>(r) + 1]; ++k) {
      const int c = m.column()[static_cast<std::size_t>(k)];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          m_coarsest[static_cast<std::size_t>((3 * r + i) * n + 3 * c + j)] = m.block(k)(i, j);
    }
  return detail::cholesky_in_place(m_coarsest.data(), n);
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::filter(const LinearSystem<Scalar>& system,
                                             const BlockSparseMatrix<Scalar>& source,
                                             BlockSparseMatrix<Scalar>& target) {
  const ConstraintFilter<Scalar>& c = system.constraints;
  const int* rb = source.row_begin().data();
  const int* col = source.column().data();
  team_for(source.block_rows(), [&](int r) {
    const bool row_free = c.kind(r) == ConstraintKind::Free;
    const Mat3<Scalar> s_r = c.filter(r);
    for (int k = rb[r]; k < rb[r + 1]; ++k) {
      Mat3<Scalar> block = source.block(k);
      if (!row_free || c.kind(col[k]) != ConstraintKind::Free) block = (s_r * block * c.filter(col[k])).eval();
      if (col[k] == r && !row_free) block += Mat3<Scalar>::Identity() - s_r;
      target.block(k) = block;
    }
  });
}

template <class Scalar>
template <class Source>
bool MultigridPreconditioner<Scalar>::update_in_team(const LinearSystem<Scalar>& system,
                                                     const BlockSparseMatrix<Source>& fine) {
  DRAPE_ASSERT(analyzed() && system.block_rows() == m_hierarchy.rows(0), "multigrid: update before analyze()");
  if constexpr (!std::is_same_v<Source, Scalar>)
    DRAPE_ASSERT(reads_fine_diagonal_only(system), "multigrid: level 1 from another matrix on a system that needs its own");
  const int levels = level_count();
  const bool filtered = !system.constraints.empty();
  team_single([&] {
    m_system = &system;
    m_fine = filtered ? &m_filtered : &system.matrix;
    m_failed.store(0, std::memory_order_relaxed);
  });  // the single's barrier publishes both
  if (filtered) filter(system, system.matrix, m_filtered);
  // With constraints, the routed operator from A itself, then filtered like A: S A' S + I - S stays
  // positive definite (routing the filtered blocks would mix the rows' projections). Without, level
  // 1 is summed from A directly.
  if (m_hierarchy.routed() && filtered) {
    if (team_level(0))
      m_hierarchy.route(system.matrix, true);
    else
      team_single([&] { m_hierarchy.route(system.matrix, false); });
    filter(system, m_hierarchy.routed_matrix(), m_hierarchy.routed_matrix());
  }
  const auto galerkin = [&](int l, bool shared_level) {
    if (l == 1 && !filtered) {
      if (m_hierarchy.routed())
        m_hierarchy.galerkin_through_routing(fine, shared_level);
      else
        m_hierarchy.galerkin(1, fine, shared_level);
    } else {
      m_hierarchy.galerkin(l, finer(l), shared_level);
    }
  };
  // The finest levels with the whole team, the small ones on one thread (in order: each level's
  // operator is summed from the finer one's).
  int shared = 0;
  while (shared < levels - 1 && team_level(shared)) ++shared;
  for (int l = 0; l < shared; ++l) {
    if (l > 0) galerkin(l, true);
    if (!m_smoothers[static_cast<std::size_t>(l)].invert_rows(matrix(l), nullptr, true))
      m_failed.store(1, std::memory_order_relaxed);
  }
  team_single([&] {
    for (int l = std::max(shared, 1); l < levels; ++l) galerkin(l, false);
    for (int l = shared; l < levels - 1; ++l)
      if (!m_smoothers[static_cast<std::size_t>(l)].invert_rows(matrix(l), nullptr, false))
        m_failed.store(1, std::memory_order_relaxed);
    if (!factorise_coarsest()) m_failed.store(1, std::memory_order_relaxed);
  });  // the single's barrier: every thread sees the final flag
  return m_failed.load(std::memory_order_relaxed) == 0;
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const {
  const BlockSparseMatrix<Scalar>& m = matrix(l);
  // The finest level's edge form is the cheaper product (one 3x3 block per edge instead of two,
  // linalg/edge_operator.hpp), also on a team, where it costs a barrier per colour (measured
  // faster). Not when one thread of a team runs the level: the edge product shares
  // its loops with the team.
  if (l == 0 && (team || team_size() == 1) && m_fine == &m_system->matrix && m_system->edges.valid()) {
    m_system->edges.multiply_in_team(x, r);
    team_for_if(team, 3 * m.block_rows(), [&](int i) { r[i] = b[i] - r[i]; });
    return;
  }
  if (team) {
    const auto share = even_share(m.block_rows(), team_rank(), team_size());
    m.residual_rows(b, x, r, int(share.first), int(share.second));
    team_barrier();
  } else {
    m.residual_rows(b, x, r, 0, m.block_rows());
  }
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::smooth(int l, const Scalar* t, bool first, bool team) {
  const BlockJacobi<Scalar>& jacobi = m_smoothers[static_cast<std::size_t>(l)];
  const Scalar omega = Scalar(m_settings.omega);
  if (team) {
    const auto share = even_share(m_hierarchy.rows(l), team_rank(), team_size());
    jacobi.smooth_rows(t, omega, first, iterate(l), int(share.first), int(share.second));
    team_barrier();
  } else {
    jacobi.smooth_rows(t, omega, first, iterate(l), 0, m_hierarchy.rows(l));
  }
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::cycle(int l, bool team) {
  const int last = level_count() - 1;
  if (l == last) {  // coarsest: exact solve
    Scalar* x = iterate(l);
    std::copy(rhs(l), rhs(l) + m_coarsest_size, x);
    detail::cholesky_solve_in_place(m_coarsest.data(), m_coarsest_size, x);
    return;
  }
  Scalar* t = m_vectors[static_cast<std::size_t>(l)].r.data();
  // Pre-smoothing from x = 0, then the residual restricted: b_c = P^T (b - A x).
  smooth(l, rhs(l), true, team);
  for (int s = 1; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), iterate(l), t, team);
    smooth(l, t, false, team);
  }
  residual(l, rhs(l), iterate(l), t, team);
  m_hierarchy.restrict_to(l + 1, t, m_vectors[static_cast<std::size_t>(l) + 1].b.data(), team);
  // Coarse correction: the small levels on one thread, with a single barrier around them.
  if (team && (l + 1 == last || !team_level(l + 1)))
    team_single([&] { cycle(l + 1, false); });
  else
    cycle(l + 1, team);
  // x += P x_c, then post-smoothing (the adjoint of the pre-smoothing: the cycle stays symmetric).
  m_hierarchy.prolong_add(l + 1, m_vectors[static_cast<std::size_t>(l) + 1].x.data(), iterate(l), team);
  for (int s = 0; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), iterate(l), t, team);
    smooth(l, t, false, team);
  }
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
  team_single([&] {
    m_r_in = r;
    m_z_out = z;
  });
  if (level_count() == 1 || !team_level(0))
    team_single([&] { cycle(0, false); });
  else
    cycle(0, true);
}

}  // namespace drape
