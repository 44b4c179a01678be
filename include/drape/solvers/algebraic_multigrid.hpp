#pragma once
/// \file algebraic_multigrid.hpp
/// Smoothed-aggregation algebraic multigrid V-cycle: the preconditioner of CG (pcg.hpp) for systems
/// without a lattice (PreconditionerKind::AlgebraicMultigrid, "amg"). The geometric multigrid
/// (multigrid.hpp) coarsens the cloth's lattice; this one coarsens the matrix's block graph
/// (aggregation_hierarchy.hpp), so it works on any mesh: triangle meshes, cut patterns, several
/// cloths in one system. The method, its parameters and measurements: drape's amg.md.
///
/// - analyze(): the hierarchy's patterns (aggregates, P, A P, P^T A P and the lists of block
///   products each value sums). Aggregation reads the values: a system whose diagonal blocks are not
///   all assembled yet (JacobianAssembler::make_system() gives zeros, and ImplicitEuler analyzes
///   before its first step) has its hierarchy built by the first update_in_team() instead, once,
///   on one thread of the team. That is the only update that allocates.
/// - update_in_team(): every step, values only: the filtered fine operator; per level the
///   block-Jacobi inverses, \f$ \rho(D^{-1} A_l) \f$ estimated by `spectral_steps` Lanczos steps from a
///   fixed start, P smoothed with the new values, the Galerkin operator; the coarsest level's dense
///   Cholesky factor.
/// - apply_in_team(): one V-cycle from a zero guess: block-Jacobi sweeps before and after the coarse
///   correction (the smoother of the geometric multigrid, block_jacobi.hpp), restriction P^T, the
///   coarsest level solved exactly (dense_cholesky.hpp). The pre- and post-smoothing are adjoint, so
///   the cycle is a symmetric operator; it is positive definite when each level's smoother is
///   convergent, \f$ \omega \rho(D^{-1} A_l) < 2 \f$: the weight is at most 4/3 over the Lanczos
///   estimate, which is below \f$ \rho \f$ but within 10% of it after six steps (drape's amg.md).
/// - Constraints: like the geometric multigrid, the finest level is \f$ \hat A = S A S + I - S \f$;
///   the coarse spaces are filtered too (aggregation_hierarchy.hpp), so coarse corrections do not
///   fight pins and contacts. CG filters the cycle's output (pcg.hpp).
/// - Threads: levels with at least `min_team_rows` rows are shared by the team, the smaller ones run
///   on one thread. Every value is summed in a fixed order by one thread, so update and cycle give
///   the same bits for any team size.
/// - A level that cannot coarsen further above `max_direct_rows` rows (e.g. a block-diagonal matrix)
///   is the coarsest and is solved by one block-Jacobi step instead of Cholesky.

#include <algorithm>
#include <atomic>
#include <vector>

#include "drape/config.hpp"
#include "drape/core/types.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/aggregation_hierarchy.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/dense_cholesky.hpp"
#include "drape/solvers/preconditioner.hpp"

namespace drape {

template <class Scalar = double>
class AlgebraicMultigrid final : public Preconditioner<Scalar> {
 public:
  explicit AlgebraicMultigrid(const AlgebraicMultigridSettings& settings = {}) : m_settings(settings) {}

  /// The hierarchy's structure for `system`'s pattern (from its values if they are assembled,
  /// else at the first update). \throws InvalidParameter naming a setting out of range.
  void analyze(const LinearSystem<Scalar>& system) override;
  /// Operators, smoothers and the coarsest factor for `system`'s values and constraints. False if a
  /// diagonal block is singular or the coarsest level is not positive definite.
  bool update_in_team(const LinearSystem<Scalar>& system) override;
  /// One V-cycle from a zero initial guess: `z = B r`.
  void apply_in_team(const Scalar* r, Scalar* z) override;

  const AlgebraicMultigridSettings& settings() const { return m_settings; }
  /// True once the hierarchy exists (after analyze() of an assembled system, or the first update).
  bool built() const { return m_hierarchy.built(); }
  const AggregationHierarchy<Scalar>& hierarchy() const { return m_hierarchy; }
  int level_count() const { return m_hierarchy.level_count(); }
  /// Block rows of each level, finest first.
  std::vector<int> level_rows() const;
  /// Operator of level l (level 0: the filtered fine operator of the last update).
  const BlockSparseMatrix<Scalar>& level_matrix(int l) const { return matrix(l); }
  /// The block-Jacobi weight of level l in the last update.
  Scalar smoother_omega(int l) const { return m_omega[static_cast<std::size_t>(l)]; }
  /// Blocks stored over all levels divided by the fine matrix's (the operator complexity).
  double operator_complexity() const;
  /// True if an update and the cycles for `system` (or for its copy in another precision) may read
  /// its edge form: they do where the team shares the fine level of a hierarchy of two levels or
  /// more and there are no constraints (before the hierarchy is built, whatever its levels). A float
  /// copy of the system rounds its edge values only then (single_precision_algebraic_multigrid.hpp).
  template <class SystemScalar>
  bool reads_edge_form(const LinearSystem<SystemScalar>& system) const {
    return system.edges.valid() && system.constraints.empty() && system.block_rows() >= m_settings.min_team_rows &&
           (!built() || level_count() > 1);
  }

 private:
  struct LevelVectors {
    VectorX<Scalar> b, x, r;
  };

  /// Structure and first values from `system` (calling thread; allocates).
  void build(const LinearSystem<Scalar>& system);
  const BlockSparseMatrix<Scalar>& matrix(int l) const { return l == 0 ? *m_fine : m_hierarchy.matrix(l); }
  bool team_level(int l) const { return m_hierarchy.rows(l) >= m_settings.min_team_rows; }
  bool direct_coarsest() const { return m_hierarchy.rows(level_count() - 1) <= m_settings.max_direct_rows; }
  /// `m_filtered` = S A S + I - S for `system`'s constraints (rows shared if `shared`).
  void filter(const LinearSystem<Scalar>& system, bool shared);
  /// Level l's block-Jacobi inverses; unless l is the coarsest, \f$ \rho(D^{-1} A_l) \f$ estimated and
  /// from it the smoother's weight and that of the prolongator to level l + 1. False if a diagonal
  /// block is singular or the estimate is not finite and positive.
  bool update_level(int l, bool shared);
  /// The largest eigenvalue of the Lanczos tridiagonal of \f$ D^{-1} A_l \f$ after `spectral_steps`
  /// steps from a fixed start (a lower bound of the spectral radius, close after a few steps).
  double spectral_radius(int l, bool shared);
  /// The sum over rows [0, rows) of `chunk(begin, end)`, the sum of a chunk of rows: fixed chunks
  /// added in order, the same bits for any team (every thread gets the sum).
  template <class Chunk>
  double chunked_sum(int rows, bool shared, Chunk&& chunk);
  bool factorise_coarsest();
  const Scalar* rhs(int l) const { return l == 0 ? m_r_in : m_vectors[static_cast<std::size_t>(l)].b.data(); }
  Scalar* iterate(int l) { return l == 0 ? m_z_out : m_vectors[static_cast<std::size_t>(l)].x.data(); }
  void residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const;
  void smooth(int l, const Scalar* t, bool first, bool team);
  void cycle(int l, bool team);

  static constexpr int chunk_rows = 512;

  AlgebraicMultigridSettings m_settings;
  AggregationHierarchy<Scalar> m_hierarchy;
  std::vector<BlockJacobi<Scalar>> m_smoothers;  // per level (the coarsest's: its solve if not direct)
  std::vector<Scalar> m_omega;                   // per level: the smoother's weight
  std::vector<Scalar> m_prolongator_omega;       // per level l >= 1: the weight of P to it
  std::vector<LevelVectors> m_vectors;
  VectorX<Scalar> m_lanczos[4];  // Lanczos vectors and a zero vector, as long as level 0's
  std::vector<Scalar> m_diagonal;  // the Lanczos level's diagonal blocks
  std::vector<double> m_chunks;  // chunked_sum()'s partial sums
  const LinearSystem<Scalar>* m_system = nullptr;  // of the last update
  const BlockSparseMatrix<Scalar>* m_fine = nullptr;
  BlockSparseMatrix<Scalar> m_filtered;  // S A S + I - S of a system with constraints
  std::vector<Scalar> m_coarsest;        // dense Cholesky factor (row-major, lower) of the coarsest level
  int m_coarsest_size = 0;
  bool m_pending = false;  // analyze() saw no values: build at the first update
  std::atomic<int> m_failed{0};
  const Scalar* m_r_in = nullptr;
  Scalar* m_z_out = nullptr;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
std::vector<int> AlgebraicMultigrid<Scalar>::level_rows() const {
  std::vector<int> rows;
  for (int l = 0; l < level_count(); ++l) rows.push_back(m_hierarchy.rows(l));
  return rows;
}

template <class Scalar>
double AlgebraicMultigrid<Scalar>::operator_complexity() const {
  double blocks = 0;
  for (int l = 0; l < level_count(); ++l) blocks += matrix(l).block_count();
  return blocks / matrix(0).block_count();
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  m_settings.validate();
  m_hierarchy.clear();
  m_filtered = system.matrix;  // the pattern, for systems with constraints
  m_fine = &system.matrix;
  bool assembled = system.block_rows() > 0;
  for (int r = 0; r < system.block_rows() && assembled; ++r)
    assembled = system.matrix.block(system.matrix.diagonal()[static_cast<std::size_t>(r)]).trace() != Scalar(0);
  m_pending = !assembled;
  if (assembled) build(system);
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::build(const LinearSystem<Scalar>& system) {
  const bool constrained = !system.constraints.empty();
  if (constrained) filter(system, false);
  m_system = &system;
  m_fine = constrained ? &m_filtered : &system.matrix;
  const int rows = system.block_rows();
  const std::size_t max_levels = static_cast<std::size_t>(m_settings.max_levels);
  m_hierarchy.start(rows, system.constraints, m_settings);
  m_smoothers = std::vector<BlockJacobi<Scalar>>(max_levels);
  m_omega.assign(max_levels, Scalar(0));
  m_prolongator_omega.assign(max_levels, Scalar(0));
  for (VectorX<Scalar>& v : m_lanczos) v.setZero(3 * static_cast<Index>(rows));
  m_diagonal.assign(9 * static_cast<std::size_t>(rows), Scalar(0));
  m_chunks.assign(static_cast<std::size_t>(rows / chunk_rows + 1), 0.0);
  // Level by level: each level's weights come from its operator, the next level from those.
  double epsilon = m_settings.strength;
  for (int l = 0;; ++l) {
    m_smoothers[static_cast<std::size_t>(l)].resize(m_hierarchy.rows(l));
    if (l + 1 >= m_settings.max_levels || m_hierarchy.rows(l) <= m_settings.max_direct_rows ||
        !m_hierarchy.add_level(l == 0 ? system.matrix : matrix(l), m_settings, epsilon)) {
      update_level(l, false);
      break;
    }
    update_level(l, false);
    m_hierarchy.update(l + 1, matrix(l), m_prolongator_omega[static_cast<std::size_t>(l) + 1], false);
    epsilon *= 0.5;
  }
  const int levels = level_count();
  m_vectors.assign(static_cast<std::size_t>(levels), LevelVectors{});
  for (int l = 0; l < levels; ++l) {
    const Index n = 3 * static_cast<Index>(m_hierarchy.rows(l));
    LevelVectors& v = m_vectors[static_cast<std::size_t>(l)];
    v.r.setZero(n);
    if (l > 0) {
      v.b.setZero(n);
      v.x.setZero(n);
    }
  }
  m_coarsest_size = direct_coarsest() ? 3 * m_hierarchy.rows(levels - 1) : 0;
  m_coarsest.assign(static_cast<std::size_t>(m_coarsest_size) * static_cast<std::size_t>(m_coarsest_size),
                    Scalar(0));
  m_pending = false;
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::filter(const LinearSystem<Scalar>& system, bool shared) {
  const ConstraintFilter<Scalar>& c = system.constraints;
  const BlockSparseMatrix<Scalar>& a = system.matrix;
  const int* rb = a.row_begin().data();
  const int* col = a.column().data();
  team_for_if(shared, a.block_rows(), [&](int r) {
    const bool row_free = c.kind(r) == ConstraintKind::Free;
    const Mat3<Scalar> s_r = c.filter(r);
    for (int k = rb[r]; k < rb[r + 1]; ++k) {
      Mat3<Scalar> block = a.block(k);
      if (!row_free || c.kind(col[k]) != ConstraintKind::Free) block = (s_r * block * c.filter(col[k])).eval();
      if (col[k] == r && !row_free) block += Mat3<Scalar>::Identity() - s_r;
      m_filtered.block(k) = block;
    }
  });
}

template <class Scalar>
template <class Chunk>
double AlgebraicMultigrid<Scalar>::chunked_sum(int rows, bool shared, Chunk&& chunk) {
  const int chunks = (rows + chunk_rows - 1) / chunk_rows;
  team_for_if(shared, chunks, [&](int c) {
    m_chunks[static_cast<std::size_t>(c)] = chunk(c * chunk_rows, std::min(rows, (c + 1) * chunk_rows));
  });
  double sum = 0;
  for (int c = 0; c < chunks; ++c) sum += m_chunks[static_cast<std::size_t>(c)];
  if (shared) team_barrier();  // every thread has read the chunks before any writes them again
  return sum;
}

template <class Scalar>
double AlgebraicMultigrid<Scalar>::spectral_radius(int l, bool shared) {
  // Lanczos on D^-1 A, self-adjoint in the D inner product: v_1 fixed, |v_1|_D = 1;
  // w = D^-1 A v_j - alpha_j v_j - beta_j v_{j-1}, alpha_j = v_j . A v_j, beta_{j+1} = |w|_D.
  const BlockSparseMatrix<Scalar>& a = matrix(l);
  const BlockJacobi<Scalar>& jacobi = m_smoothers[static_cast<std::size_t>(l)];
  const int rows = a.block_rows();
  const int* diagonal = a.diagonal().data();
  const Scalar* values = a.values();
  Scalar* v = m_lanczos[0].data();
  Scalar* previous = m_lanczos[1].data();
  Scalar* w = m_lanczos[2].data();
  const Scalar* zero = m_lanczos[3].data();  // never written
  Scalar* d = m_diagonal.data();  // the diagonal blocks, contiguous (the matrix's are scattered)
  const auto d_dot = [&](int begin, int end, const Scalar* x) {  // sum of x_r . D_r x_r
    double s = 0;
    for (int r = begin; r < end; ++r) {
      const std::array<Scalar, 3> t = block_times(d + 9 * static_cast<std::size_t>(r), x + 3 * r);
      s += double(x[3 * r]) * t[0] + double(x[3 * r + 1]) * t[1] + double(x[3 * r + 2]) * t[2];
    }
    return s;
  };
  team_for_if(shared, rows, [&](int r) {
    for (int q = 0; q < 9; ++q) d[9 * static_cast<std::size_t>(r) + q] = values[9 * diagonal[r] + q];
    for (int i = 3 * r; i < 3 * r + 3; ++i) {
      // A fixed start with every frequency: a multiplicative hash of the index mapped to [-1, 1).
      const unsigned hash = static_cast<unsigned>(i + 1) * 2654435761u;
      v[i] = Scalar(double(hash >> 8) / double(1u << 23) - 1.0);
      previous[i] = Scalar(0);
    }
  });
  const double start_norm =
      std::sqrt(chunked_sum(rows, shared, [&](int begin, int end) { return d_dot(begin, end, v); }));
  team_for_if(shared, 3 * rows, [&](int i) { v[i] = Scalar(v[i] / start_norm); });
  constexpr int max_steps = 40;
  std::array<double, max_steps> alpha{}, beta{};  // beta[j]: coupling of steps j - 1 and j
  int steps = 0;
  // A v: the fine level's edge form where the team shares it (as in residual()), else the block
  // rows' residual kernel with b = 0, which gives -A v.
  const bool edge_form = l == 0 && shared && m_fine == &m_system->matrix && m_system->edges.valid();
  const Scalar sign = edge_form ? Scalar(1) : Scalar(-1);
  for (int j = 0; j < m_settings.spectral_steps; ++j) {
    if (edge_form) m_system->edges.multiply_in_team(v, w);
    alpha[static_cast<std::size_t>(j)] = chunked_sum(rows, shared, [&](int begin, int end) {
      if (!edge_form) a.residual_rows(zero, v, w, begin, end);
      double s = 0;
      for (int i = 3 * begin; i < 3 * end; ++i) s += double(v[i]) * double(w[i]);
      return double(sign) * s;
    });
    steps = j + 1;
    const Scalar aj = Scalar(alpha[static_cast<std::size_t>(j)]), bj = Scalar(beta[static_cast<std::size_t>(j)]);
    const double next = chunked_sum(rows, shared, [&](int begin, int end) {
      for (int r = begin; r < end; ++r) {
        const std::array<Scalar, 3> t = jacobi.times(r, w + 3 * r);
        for (int q = 0; q < 3; ++q)
          w[3 * r + q] = sign * t[static_cast<std::size_t>(q)] - aj * v[3 * r + q] - bj * previous[3 * r + q];
      }
      return d_dot(begin, end, w);
    });
    if (j + 1 == m_settings.spectral_steps || !(next > 1e-20 * alpha[0] * alpha[0])) break;  // or invariant
    const double b = std::sqrt(next);
    beta[static_cast<std::size_t>(j) + 1] = b;
    team_for_if(shared, 3 * rows, [&](int i) {
      previous[i] = v[i];
      v[i] = Scalar(w[i] / b);
    });
  }
  // The tridiagonal's largest eigenvalue by bisection on its Sturm sequence (count of eigenvalues < x).
  double lo = alpha[0], hi = alpha[0];
  for (int j = 0; j < steps; ++j) {
    const double reach = std::abs(beta[static_cast<std::size_t>(j)]) +
                         (j + 1 < steps ? std::abs(beta[static_cast<std::size_t>(j) + 1]) : 0.0);
    lo = std::min(lo, alpha[static_cast<std::size_t>(j)] - reach);
    hi = std::max(hi, alpha[static_cast<std::size_t>(j)] + reach);
  }
  const auto below = [&](double x) {
    int count = 0;
    double q = 1;
    for (int j = 0; j < steps; ++j) {
      const double b2 = j > 0 ? beta[static_cast<std::size_t>(j)] * beta[static_cast<std::size_t>(j)] : 0.0;
      q = alpha[static_cast<std::size_t>(j)] - x - (j > 0 ? b2 / q : 0.0);
      if (q == 0) q = -1e-300;
      if (q < 0) ++count;
    }
    return count;
  };
  for (int it = 0; it < 100 && hi - lo > 1e-6 * std::abs(hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (below(mid) == steps ? hi : lo) = mid;
  }
  return hi;
}

template <class Scalar>
bool AlgebraicMultigrid<Scalar>::update_level(int l, bool shared) {
  bool regular = m_smoothers[static_cast<std::size_t>(l)].invert_rows(matrix(l), nullptr, shared);
  if (l + 1 == level_count()) return regular;  // the coarsest: solved, not smoothed
  const double rho = spectral_radius(l, shared);
  if (!(rho > 0) || !std::isfinite(rho)) return false;
  const Scalar omega = std::min(Scalar(m_settings.omega), Scalar(4.0 / (3.0 * rho)));
  const Scalar prolongator = Scalar(m_settings.prolongator_weight / rho);
  const auto store = [&] {
    m_omega[static_cast<std::size_t>(l)] = omega;
    if (l + 1 < m_settings.max_levels) m_prolongator_omega[static_cast<std::size_t>(l) + 1] = prolongator;
  };
  if (shared)
    team_single(store);
  else
    store();
  return regular;
}

template <class Scalar>
bool AlgebraicMultigrid<Scalar>::factorise_coarsest() {
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
bool AlgebraicMultigrid<Scalar>::update_in_team(const LinearSystem<Scalar>& system) {
  const bool pending = m_pending;
  DRAPE_ASSERT(pending || (built() && system.block_rows() == m_hierarchy.rows(0)), "amg: update before analyze()");
  team_barrier();  // every thread has read the flag before the build clears it
  if (pending) team_single([&] { build(system); });  // the first values: the structure, once (allocates)
  const int levels = level_count();
  const bool constrained = !system.constraints.empty();
  team_single([&] {
    m_system = &system;
    m_fine = constrained ? &m_filtered : &system.matrix;
    m_failed.store(0, std::memory_order_relaxed);
  });  // the single's barrier publishes them
  const auto fail_unless = [&](bool ok) {
    if (!ok) m_failed.store(1, std::memory_order_relaxed);
  };
  if (team_level(0)) {
    if (constrained) filter(system, true);
    m_hierarchy.set_constraints(system.constraints, true);
  } else {
    team_single([&] {
      if (constrained) filter(system, false);
      m_hierarchy.set_constraints(system.constraints, false);
    });
  }
  // In order (each level is summed from the finer one): with the whole team while the finer level
  // is large, then the rest on one thread.
  int l = 0;
  for (; l < levels && (l == 0 || team_level(l - 1)); ++l) {
    if (l > 0)
      fail_unless(m_hierarchy.update(l, matrix(l - 1), m_prolongator_omega[static_cast<std::size_t>(l)], true));
    if (team_level(l))
      fail_unless(update_level(l, true));
    else
      team_single([&] { fail_unless(update_level(l, false)); });
  }
  team_single([&] {
    for (int k = l; k < levels; ++k) {
      fail_unless(m_hierarchy.update(k, matrix(k - 1), m_prolongator_omega[static_cast<std::size_t>(k)], false));
      fail_unless(update_level(k, false));
    }
    if (direct_coarsest()) fail_unless(factorise_coarsest());
  });  // the single's barrier: every thread sees the final flag
  return m_failed.load(std::memory_order_relaxed) == 0;
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const {
  const BlockSparseMatrix<Scalar>& m = matrix(l);
  // The fine level's edge form reads half the blocks (linalg/edge_operator.hpp). Only where the
  // whole team shares the level, whatever its size, so the bits do not depend on the team.
  if (l == 0 && team && m_fine == &m_system->matrix && m_system->edges.valid()) {
    m_system->edges.multiply_in_team(x, r);
    team_for(3 * m.block_rows(), [&](int i) { r[i] = b[i] - r[i]; });
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
void AlgebraicMultigrid<Scalar>::smooth(int l, const Scalar* t, bool first, bool team) {
  const BlockJacobi<Scalar>& jacobi = m_smoothers[static_cast<std::size_t>(l)];
  const Scalar omega = m_omega[static_cast<std::size_t>(l)];
  if (team) {
    const auto share = even_share(m_hierarchy.rows(l), team_rank(), team_size());
    jacobi.smooth_rows(t, omega, first, iterate(l), int(share.first), int(share.second));
    team_barrier();
  } else {
    jacobi.smooth_rows(t, omega, first, iterate(l), 0, m_hierarchy.rows(l));
  }
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::cycle(int l, bool team) {
  const int last = level_count() - 1;
  if (l == last) {
    Scalar* x = iterate(l);
    if (direct_coarsest()) {  // exact solve
      std::copy(rhs(l), rhs(l) + m_coarsest_size, x);
      detail::cholesky_solve_in_place(m_coarsest.data(), m_coarsest_size, x);
    } else {  // a level that did not coarsen: one unweighted block-Jacobi step (SPD)
      m_smoothers[static_cast<std::size_t>(l)].smooth_rows(rhs(l), Scalar(1), true, x, 0, m_hierarchy.rows(l));
    }
    return;
  }
  Scalar* t = m_vectors[static_cast<std::size_t>(l)].r.data();
  LevelVectors& coarse = m_vectors[static_cast<std::size_t>(l) + 1];
  // Pre-smoothing from x = 0, then the residual restricted: b_c = P^T (b - A x).
  smooth(l, rhs(l), true, team);
  for (int s = 1; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), iterate(l), t, team);
    smooth(l, t, false, team);
  }
  residual(l, rhs(l), iterate(l), t, team);
  m_hierarchy.restrict_to(l + 1, t, coarse.b.data(), team);
  if (team && (l + 1 == last || !team_level(l + 1)))
    team_single([&] { cycle(l + 1, false); });
  else
    cycle(l + 1, team);
  // x += P x_c, then post-smoothing, the adjoint of the pre-smoothing: the cycle stays symmetric.
  m_hierarchy.prolong_add(l + 1, coarse.x.data(), iterate(l), team);
  for (int s = 0; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), iterate(l), t, team);
    smooth(l, t, false, team);
  }
}

template <class Scalar>
void AlgebraicMultigrid<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
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
