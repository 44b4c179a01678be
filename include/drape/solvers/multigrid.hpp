#pragma once
/// \file multigrid.hpp
/// Geometric multigrid V-cycle on the cloth's lattice: the default preconditioner of CG (pcg.hpp).
///
/// Why: the implicit system is M plus dt^2 times a stiffness "Laplacian" of the lattice, so its
/// condition number grows with ks dt^2 / m and with the grid; block-Jacobi CG needed 120-190
/// iterations at dt = 1/60 with the default springs. Jacobi only damps the rough part of the
/// error; the V-cycle removes the smooth part on coarser lattices, so CG needs about ten iterations
/// at every grid size (docs/implicit.md, "Multigrid preconditioner").
///
/// - Hierarchy (analyze(), once per pattern): each coarser level keeps every other lattice line
///   along i and j (and always the last one). The prolongation P is bilinear interpolation on the
///   lattice, applied to each of the three components; a coarse node that is not in the system (an
///   eliminated pin) gets no correction. Coarsening stops at `max_direct_rows` block rows or when
///   neither direction can be halved; that level is solved exactly by dense Cholesky.
/// - Operators (update_in_team(), every solve): Galerkin \f$ A_{l+1} = P^T A_l P \f$. Every coarse
///   block is a fixed weighted sum of fine blocks, so the weights are listed once and each solve
///   only sums; the matrix is symmetric, so only blocks on or above the diagonal are summed and the
///   others are their transposes. Coarse operators therefore follow the deformation exactly and
///   stay symmetric positive definite.
/// - Smoother: block Jacobi with weight `omega`, `sweeps` times before and after the coarse
///   correction. With restriction \f$ R = P^T \f$ the cycle is a fixed symmetric positive definite
///   linear operator, which is what CG needs from a preconditioner.
/// - Threads: every operation runs inside the caller's OpenMP team (orphaned `omp for`), split by
///   rows, and every row sums its terms in a fixed order: results do not depend on scheduling.
///   After analyze(), nothing allocates.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/LU>  // 3x3 inverse

#include "drape/config.hpp"
#include "drape/core/team.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/solvers/block_sparse_matrix.hpp"
#include "drape/solvers/grid_layout.hpp"

namespace drape {

struct MultigridSettings {
  int sweeps = 1;              ///< block-Jacobi sweeps before and after the coarse correction
  double omega = 0.8;          ///< Jacobi weight, in (0, 1]
  int max_direct_rows = 16;    ///< coarsest level: at most this many block rows (dense Cholesky)
  /// Levels with fewer block rows run on one thread of the team: below this a loop costs less
  /// than the barriers around it.
  int min_team_rows = 2048;
};

template <class Scalar = double>
class MultigridPreconditioner {
 public:
  explicit MultigridPreconditioner(const MultigridSettings& settings = {}) : m_settings(settings) {}

  /// Builds the hierarchy for matrices with `a`'s pattern whose block rows sit on `layout`.
  /// \throws std::invalid_argument if the layout does not describe `a`'s rows.
  void analyze(const GridLayout& layout, const BlockSparseMatrix<Scalar>& a);
  bool analyzed() const { return !m_levels.empty(); }
  int level_count() const { return static_cast<int>(m_levels.size()); }
  /// Block rows of each level, finest first.
  std::vector<int> level_rows() const;
  /// Operator of level l >= 1 (after update_in_team()).
  const BlockSparseMatrix<Scalar>& level_matrix(int l) const { return m_levels[static_cast<std::size_t>(l)].a; }
  /// Scalar prolongation from level l >= 1 to level l - 1, `3 rows(l-1) x 3 rows(l)` (allocates:
  /// tests and diagnostics).
  Eigen::SparseMatrix<Scalar> prolongation(int l) const;

  /// Coarse operators, inverse diagonal blocks and the coarsest factorisation for the values of
  /// `a` (same pattern as in analyze()). Call from every thread of the team (or serially).
  /// Returns false on every thread if a diagonal block is singular or the coarsest level is not
  /// positive definite.
  bool update_in_team(const BlockSparseMatrix<Scalar>& a);

  /// `z = B r`: one V-cycle from a zero initial guess. Call from every thread of the team, after
  /// update_in_team(); `r` and `z` (a.size() scalars) must be complete and visible to all threads
  /// on entry; on return `z` is complete (the last loop ends with a barrier).
  void apply_in_team(const Scalar* r, Scalar* z);

 private:
  struct Level {
    BlockSparseMatrix<Scalar> a;  // levels >= 1 (level 0 is the caller's matrix)
    // Prolongation from this level to the next finer one: per fine row, [p_begin[r], p_begin[r+1])
    // of (p_row, p_weight) on this level.
    std::vector<int> p_begin, p_row;
    std::vector<Scalar> p_weight;
    // Restriction (the transpose): per row of this level, (r_row, r_weight) on the finer level.
    std::vector<int> r_begin, r_row;
    std::vector<Scalar> r_weight;
    // Galerkin sums: block upper[u] of this level = sum over [g_begin[u], g_begin[u+1]) of
    // g_weight * (finer level's block g_block).
    std::vector<int> upper, g_begin, g_block;
    std::vector<Scalar> g_weight;
    std::vector<Scalar> inv_diag;   // 9 per row
    VectorX<Scalar> b, x, r;        // right-hand side, iterate, residual (levels >= 1 own b and x)
    int rows = 0;
  };

  const BlockSparseMatrix<Scalar>& matrix(int level) const { return level == 0 ? *m_fine : m_levels[level].a; }
  /// Level l's loops are shared by the team, or run by the one thread that calls them.
  bool team_level(int l) const { return m_levels[static_cast<std::size_t>(l)].rows >= m_settings.min_team_rows; }
  const Scalar* rhs(int l) const { return l == 0 ? m_r_in : m_levels[static_cast<std::size_t>(l)].b.data(); }
  Scalar* iterate(int l) { return l == 0 ? m_z_out : m_levels[static_cast<std::size_t>(l)].x.data(); }
  /// Coarse blocks of level l (>= 1) from level l - 1; inverse diagonal blocks of level l.
  void galerkin(int l, bool team);
  void invert_diagonal(int l, bool team);
  /// r = b - A x on level l's rows.
  void residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const;
  /// x = omega D^-1 t (`first`) or x += omega D^-1 t on level l.
  void jacobi(int l, const Scalar* t, bool first, bool team);
  /// One V-cycle from level l down, with a zero initial guess on level l.
  void cycle(int l, bool team);

  MultigridSettings m_settings;
  std::vector<Level> m_levels;
  const BlockSparseMatrix<Scalar>* m_fine = nullptr;
  std::vector<Scalar> m_coarsest;  // dense Cholesky factor L (row-major, lower) of the coarsest level
  int m_coarsest_size = 0;
  std::atomic<int> m_failed{0};
  const Scalar* m_r_in = nullptr;
  Scalar* m_z_out = nullptr;
};

// ---------------------------------------------------------------------------------------------

namespace detail {

/// Dense Cholesky `A = L L^T` of the n x n row-major matrix `a`, in place (L in the lower
/// triangle). False if `a` is not positive definite. A few dozen rows: plain loops compile in a
/// fraction of the time Eigen's blocked LLT takes, and run as fast at this size.
template <class Scalar>
bool cholesky_in_place(Scalar* a, int n) {
  for (int j = 0; j < n; ++j) {
    Scalar d = a[j * n + j];
    for (int k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0) || !std::isfinite(d)) return false;
    const Scalar l = std::sqrt(d);
    a[j * n + j] = l;
    for (int i = j + 1; i < n; ++i) {
      Scalar s = a[i * n + j];
      for (int k = 0; k < j; ++k) s -= a[i * n + k] * a[j * n + k];
      a[i * n + j] = s / l;
    }
  }
  return true;
}

/// Solves `L L^T x = b` with the factor of cholesky_in_place(); `x` holds b on entry.
template <class Scalar>
void cholesky_solve_in_place(const Scalar* l, int n, Scalar* x) {
  for (int i = 0; i < n; ++i) {
    Scalar s = x[i];
    for (int k = 0; k < i; ++k) s -= l[i * n + k] * x[k];
    x[i] = s / l[i * n + i];
  }
  for (int i = n - 1; i >= 0; --i) {
    Scalar s = x[i];
    for (int k = i + 1; k < n; ++k) s -= l[k * n + i] * x[k];
    x[i] = s / l[i * n + i];
  }
}

/// One lattice direction of n nodes coarsened: coarse nodes at the even indices and the last one.
struct CoarseAxis {
  int fine = 0, coarse = 0;
  std::vector<int> position;                    // fine index of each coarse node
  std::vector<std::array<int, 2>> parent;       // per fine index: one or two coarse nodes (-1 = none)
  bool halves() const { return coarse < fine; }
};

inline CoarseAxis coarsen_axis(int n) {
  CoarseAxis axis;
  axis.fine = n;
  if (n < 3) {  // cannot be halved: keep every node
    for (int i = 0; i < n; ++i) {
      axis.position.push_back(i);
      axis.parent.push_back({i, -1});
    }
    axis.coarse = n;
    return axis;
  }
  std::vector<int> coarse_of(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i)
    if (i % 2 == 0 || i == n - 1) {
      coarse_of[static_cast<std::size_t>(i)] = static_cast<int>(axis.position.size());
      axis.position.push_back(i);
    }
  for (int i = 0; i < n; ++i) {
    const int c = coarse_of[static_cast<std::size_t>(i)];
    // An odd index below n - 1 lies midway between two coarse nodes.
    axis.parent.push_back(c >= 0 ? std::array<int, 2>{c, -1}
                                 : std::array<int, 2>{coarse_of[static_cast<std::size_t>(i - 1)],
                                                      coarse_of[static_cast<std::size_t>(i + 1)]});
  }
  axis.coarse = static_cast<int>(axis.position.size());
  return axis;
}

}  // namespace detail

template <class Scalar>
std::vector<int> MultigridPreconditioner<Scalar>::level_rows() const {
  std::vector<int> rows;
  for (const Level& l : m_levels) rows.push_back(l.rows);
  return rows;
}

template <class Scalar>
Eigen::SparseMatrix<Scalar> MultigridPreconditioner<Scalar>::prolongation(int l) const {
  const Level& coarse = m_levels[static_cast<std::size_t>(l)];
  const int fine_rows = m_levels[static_cast<std::size_t>(l) - 1].rows;
  std::vector<Eigen::Triplet<Scalar>> t;
  for (int rf = 0; rf < fine_rows; ++rf)
    for (int e = coarse.p_begin[static_cast<std::size_t>(rf)]; e < coarse.p_begin[static_cast<std::size_t>(rf) + 1]; ++e)
      for (int k = 0; k < 3; ++k)
        t.emplace_back(3 * rf + k, 3 * coarse.p_row[static_cast<std::size_t>(e)] + k, coarse.p_weight[static_cast<std::size_t>(e)]);
  Eigen::SparseMatrix<Scalar> p(3 * fine_rows, 3 * coarse.rows);
  p.setFromTriplets(t.begin(), t.end());
  return p;
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::analyze(const GridLayout& layout, const BlockSparseMatrix<Scalar>& a) {
  if (layout.nx < 1 || layout.ny < 1 ||
      layout.row_of_node.size() != static_cast<std::size_t>(layout.nx) * static_cast<std::size_t>(layout.ny))
    detail::fail_argument("grid layout", detail::to_text(layout.row_of_node.size()) + " nodes",
                          "nx * ny nodes, one row index (or -1) each");
  int rows = 0;
  for (int r : layout.row_of_node) rows = std::max(rows, r + 1);
  if (rows != a.block_rows())
    detail::fail_argument("grid layout", detail::to_text(rows) + " rows",
                          detail::to_text(a.block_rows()) + " rows (the matrix's)");
  if (!(m_settings.omega > 0 && m_settings.omega <= 1))
    detail::fail_argument("multigrid omega", detail::to_text(m_settings.omega), "(0, 1]");
  detail::require_at_least("multigrid sweeps", m_settings.sweeps, 1);
  if (!(m_settings.max_direct_rows >= 1 && m_settings.max_direct_rows <= 256))
    detail::fail_argument("multigrid max_direct_rows", detail::to_text(m_settings.max_direct_rows),
                          "1 to 256 (the coarsest level is factorised densely)");

  m_levels.clear();
  m_levels.reserve(32);  // levels hold the matrices the next level's set-up points at
  m_levels.emplace_back();
  m_levels[0].rows = a.block_rows();
  GridLayout fine = layout;
  const BlockSparseMatrix<Scalar>* fine_matrix = &a;
  while (m_levels.back().rows > m_settings.max_direct_rows) {
    const detail::CoarseAxis ax = detail::coarsen_axis(fine.nx), ay = detail::coarsen_axis(fine.ny);
    if (!ax.halves() && !ay.halves()) break;
    GridLayout coarse;
    coarse.nx = ax.coarse;
    coarse.ny = ay.coarse;
    coarse.row_of_node.assign(static_cast<std::size_t>(coarse.nx) * static_cast<std::size_t>(coarse.ny), -1);
    int coarse_rows = 0;
    for (int J = 0; J < coarse.ny; ++J)
      for (int I = 0; I < coarse.nx; ++I)
        if (fine.row_of_node[static_cast<std::size_t>(ay.position[J]) * fine.nx + ax.position[I]] >= 0)
          coarse.row_of_node[static_cast<std::size_t>(J) * coarse.nx + I] = coarse_rows++;
    if (coarse_rows == 0) break;

    Level level;
    level.rows = coarse_rows;
    const int fine_rows = m_levels.back().rows;
    // Prolongation rows: bilinear weights, product of the two axes' (1 or 1/2, 1/2).
    std::vector<std::vector<std::pair<int, Scalar>>> p(static_cast<std::size_t>(fine_rows));
    for (int j = 0; j < fine.ny; ++j)
      for (int i = 0; i < fine.nx; ++i) {
        const int rf = fine.row_of_node[static_cast<std::size_t>(j) * fine.nx + i];
        if (rf < 0) continue;
        const std::array<int, 2>& pi = ax.parent[static_cast<std::size_t>(i)];
        const std::array<int, 2>& pj = ay.parent[static_cast<std::size_t>(j)];
        const Scalar wi = pi[1] >= 0 ? Scalar(0.5) : Scalar(1), wj = pj[1] >= 0 ? Scalar(0.5) : Scalar(1);
        for (int J : pj) {
          if (J < 0) continue;
          for (int I : pi) {
            if (I < 0) continue;
            const int rc = coarse.row_of_node[static_cast<std::size_t>(J) * coarse.nx + I];
            if (rc >= 0) p[static_cast<std::size_t>(rf)].emplace_back(rc, wi * wj);
          }
        }
      }
    std::vector<std::vector<std::pair<int, Scalar>>> rt(static_cast<std::size_t>(coarse_rows));
    level.p_begin.push_back(0);
    for (int rf = 0; rf < fine_rows; ++rf) {
      for (const auto& [rc, w] : p[static_cast<std::size_t>(rf)]) {
        level.p_row.push_back(rc);
        level.p_weight.push_back(w);
        rt[static_cast<std::size_t>(rc)].emplace_back(rf, w);
      }
      level.p_begin.push_back(static_cast<int>(level.p_row.size()));
    }
    level.r_begin.push_back(0);
    for (int rc = 0; rc < coarse_rows; ++rc) {
      for (const auto& [rf, w] : rt[static_cast<std::size_t>(rc)]) {
        level.r_row.push_back(rf);
        level.r_weight.push_back(w);
      }
      level.r_begin.push_back(static_cast<int>(level.r_row.size()));
    }
    // Coarse pattern: (I, J) for every fine block (i, j) and parents I of i, J of j.
    const std::vector<int>& frb = fine_matrix->row_begin();
    const std::vector<int>& fcol = fine_matrix->column();
    std::vector<std::vector<int>> columns(static_cast<std::size_t>(coarse_rows));
    for (int i = 0; i < fine_rows; ++i)
      for (int k = frb[static_cast<std::size_t>(i)]; k < frb[static_cast<std::size_t>(i) + 1]; ++k)
        for (const auto& pi : p[static_cast<std::size_t>(i)])
          for (const auto& pj : p[static_cast<std::size_t>(fcol[static_cast<std::size_t>(k)])])
            columns[static_cast<std::size_t>(pi.first)].push_back(pj.first);
    level.a = BlockSparseMatrix<Scalar>(std::move(columns));
    // Galerkin weights of every coarse block on or above the diagonal, grouped by coarse block
    // (counting sort: count, then fill).
    std::vector<int> first(static_cast<std::size_t>(level.a.block_count()) + 1, 0);
    const auto for_each_term = [&](auto&& term) {
      for (int i = 0; i < fine_rows; ++i)
        for (int k = frb[static_cast<std::size_t>(i)]; k < frb[static_cast<std::size_t>(i) + 1]; ++k)
          for (const auto& [I, wi] : p[static_cast<std::size_t>(i)])
            for (const auto& [J, wj] : p[static_cast<std::size_t>(fcol[static_cast<std::size_t>(k)])])
              if (I <= J) term(level.a.find(I, J), k, wi * wj);
    };
    for_each_term([&](int K, int, Scalar) { ++first[static_cast<std::size_t>(K) + 1]; });
    for (std::size_t K = 0; K + 1 < first.size(); ++K) first[K + 1] += first[K];
    std::vector<int> fill(first.begin(), first.end() - 1);
    std::vector<int> term_block(static_cast<std::size_t>(first.back()));
    std::vector<Scalar> term_weight(static_cast<std::size_t>(first.back()));
    for_each_term([&](int K, int k, Scalar w) {
      const int at = fill[static_cast<std::size_t>(K)]++;
      term_block[static_cast<std::size_t>(at)] = k;
      term_weight[static_cast<std::size_t>(at)] = w;
    });
    level.g_begin.push_back(0);
    for (int K = 0; K < level.a.block_count(); ++K) {
      if (first[static_cast<std::size_t>(K)] == first[static_cast<std::size_t>(K) + 1]) continue;
      level.upper.push_back(K);
      level.g_block.insert(level.g_block.end(), term_block.begin() + first[static_cast<std::size_t>(K)],
                           term_block.begin() + first[static_cast<std::size_t>(K) + 1]);
      level.g_weight.insert(level.g_weight.end(), term_weight.begin() + first[static_cast<std::size_t>(K)],
                            term_weight.begin() + first[static_cast<std::size_t>(K) + 1]);
      level.g_begin.push_back(static_cast<int>(level.g_block.size()));
    }
    level.b.setZero(3 * coarse_rows);
    level.x.setZero(3 * coarse_rows);
    level.r.setZero(3 * coarse_rows);
    level.inv_diag.assign(9 * static_cast<std::size_t>(coarse_rows), Scalar(0));
    m_levels.push_back(std::move(level));
    fine_matrix = &m_levels.back().a;
    fine = std::move(coarse);
  }
  Level& finest = m_levels[0];
  finest.r.setZero(a.size());
  finest.inv_diag.assign(9 * static_cast<std::size_t>(finest.rows), Scalar(0));
  const Index n = 3 * static_cast<Index>(m_levels.back().rows);
  m_coarsest_size = static_cast<int>(n);
  m_coarsest.assign(static_cast<std::size_t>(n * n), Scalar(0));
  m_fine = &a;
}

namespace detail {
/// `body(i)` for i in [0, n): shared by the team (`omp for`, ends with a barrier) or all by the caller.
template <class Body>
void for_rows(bool team, int n, Body&& body) {
  if (team) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int i = 0; i < n; ++i) body(i);
  } else {
    for (int i = 0; i < n; ++i) body(i);
  }
}
}  // namespace detail

template <class Scalar>
void MultigridPreconditioner<Scalar>::galerkin(int l, bool team) {
  Level& level = m_levels[static_cast<std::size_t>(l)];
  const Scalar* fine = matrix(l - 1).values();
  Scalar* coarse = level.a.values();
  const int* transposed = level.a.transposed().data();
  detail::for_rows(team, static_cast<int>(level.upper.size()), [&](int u) {
    Scalar s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int e = level.g_begin[static_cast<std::size_t>(u)]; e < level.g_begin[static_cast<std::size_t>(u) + 1]; ++e) {
      const Scalar w = level.g_weight[static_cast<std::size_t>(e)];
      const Scalar* f = fine + 9 * level.g_block[static_cast<std::size_t>(e)];
      for (int q = 0; q < 9; ++q) s[q] += w * f[q];
    }
    const int K = level.upper[static_cast<std::size_t>(u)];
    Scalar* c = coarse + 9 * K;
    for (int q = 0; q < 9; ++q) c[q] = s[q];
    const int T = transposed[K];
    if (T != K) {
      Scalar* t = coarse + 9 * T;
      for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row) t[3 * col + row] = s[3 * row + col];
    }
  });
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::invert_diagonal(int l, bool team) {
  const BlockSparseMatrix<Scalar>& m = matrix(l);
  Scalar* inv = m_levels[static_cast<std::size_t>(l)].inv_diag.data();
  detail::for_rows(team, m.block_rows(), [&](int r) {
    Eigen::Map<Mat3<Scalar>> d(inv + 9 * r);
    d = m.block(m.diagonal()[static_cast<std::size_t>(r)]).inverse();
    if (!d.allFinite()) m_failed.store(1, std::memory_order_relaxed);
  });
}

template <class Scalar>
bool MultigridPreconditioner<Scalar>::update_in_team(const BlockSparseMatrix<Scalar>& a) {
  DRAPE_ASSERT(analyzed() && a.block_rows() == m_levels[0].rows, "multigrid: update() before analyze()");
  const int levels = level_count();
#if defined(_OPENMP)
#pragma omp single
#endif
  {
    m_fine = &a;
    m_failed.store(0, std::memory_order_relaxed);
  }  // the single's barrier publishes both
  // The finest levels with the whole team, the small ones on one thread (in order: each level's
  // operator is summed from the finer one's).
  int shared = 0;
  while (shared < levels - 1 && team_level(shared)) ++shared;
  for (int l = 0; l < shared; ++l) {
    if (l > 0) galerkin(l, true);
    invert_diagonal(l, true);
  }
#if defined(_OPENMP)
#pragma omp single
#endif
  {
    for (int l = std::max(shared, 1); l < levels; ++l) galerkin(l, false);
    for (int l = shared; l < levels - 1; ++l) invert_diagonal(l, false);
    const BlockSparseMatrix<Scalar>& m = matrix(levels - 1);
    const int n = m_coarsest_size;
    std::fill(m_coarsest.begin(), m_coarsest.end(), Scalar(0));
    for (int r = 0; r < m.block_rows(); ++r)
      for (int k = m.row_begin()[static_cast<std::size_t>(r)]; k < m.row_begin()[static_cast<std::size_t>(r) + 1]; ++k) {
        const int c = m.column()[static_cast<std::size_t>(k)];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            m_coarsest[static_cast<std::size_t>((3 * r + i) * n + 3 * c + j)] = m.block(k)(i, j);
      }
    if (!detail::cholesky_in_place(m_coarsest.data(), n)) m_failed.store(1, std::memory_order_relaxed);
  }  // implicit barrier: every thread sees the final flag
  return m_failed.load(std::memory_order_relaxed) == 0;
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::residual(int l, const Scalar* b, const Scalar* x, Scalar* r, bool team) const {
  const BlockSparseMatrix<Scalar>& m = matrix(l);
  // On one thread the finest level's per-spring edge form is the cheaper product (one 3x3 block
  // per spring instead of two, block_sparse_matrix.hpp); with a team it would cost a barrier per
  // spring colour, so the team uses block rows. (Never inside an `omp single`: the edge product
  // shares its loops with the team.)
  if (l == 0 && !team && m.edge_form_valid() && team_size() == 1) {
    detail::edge_multiply_in_team(m, x, r);
    for (int i = 0; i < 3 * m.block_rows(); ++i) r[i] = b[i] - r[i];
    return;
  }
  const int* rb = m.row_begin().data();
  const int* col = m.column().data();
  const Scalar* val = m.values();
  detail::for_rows(team, m.block_rows(), [&](int row) {
    Scalar y0 = b[3 * row], y1 = b[3 * row + 1], y2 = b[3 * row + 2];
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const Scalar* v = val + 9 * k;
      const Scalar* xc = x + 3 * col[k];
      y0 -= v[0] * xc[0] + v[3] * xc[1] + v[6] * xc[2];
      y1 -= v[1] * xc[0] + v[4] * xc[1] + v[7] * xc[2];
      y2 -= v[2] * xc[0] + v[5] * xc[1] + v[8] * xc[2];
    }
    r[3 * row] = y0;
    r[3 * row + 1] = y1;
    r[3 * row + 2] = y2;
  });
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::jacobi(int l, const Scalar* t, bool first, bool team) {
  Scalar* x = iterate(l);
  const Scalar* inv = m_levels[static_cast<std::size_t>(l)].inv_diag.data();
  const Scalar omega = Scalar(m_settings.omega);
  detail::for_rows(team, m_levels[static_cast<std::size_t>(l)].rows, [&](int row) {
    const Scalar* d = inv + 9 * row;
    const Scalar* tr = t + 3 * row;
    const Scalar u0 = omega * (d[0] * tr[0] + d[3] * tr[1] + d[6] * tr[2]);
    const Scalar u1 = omega * (d[1] * tr[0] + d[4] * tr[1] + d[7] * tr[2]);
    const Scalar u2 = omega * (d[2] * tr[0] + d[5] * tr[1] + d[8] * tr[2]);
    Scalar* xr = x + 3 * row;
    if (first) {
      xr[0] = u0; xr[1] = u1; xr[2] = u2;
    } else {
      xr[0] += u0; xr[1] += u1; xr[2] += u2;
    }
  });
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
  Level& level = m_levels[static_cast<std::size_t>(l)];
  Level& coarse = m_levels[static_cast<std::size_t>(l) + 1];
  Scalar* t = level.r.data();
  // Pre-smoothing from x = 0, then the residual restricted: b_c = P^T (b - A x).
  jacobi(l, rhs(l), true, team);
  for (int s = 1; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), iterate(l), t, team);
    jacobi(l, t, false, team);
  }
  residual(l, rhs(l), iterate(l), t, team);
  Scalar* bc = coarse.b.data();
  detail::for_rows(team, coarse.rows, [&](int rc) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = coarse.r_begin[static_cast<std::size_t>(rc)]; e < coarse.r_begin[static_cast<std::size_t>(rc) + 1]; ++e) {
      const Scalar w = coarse.r_weight[static_cast<std::size_t>(e)];
      const Scalar* tf = t + 3 * coarse.r_row[static_cast<std::size_t>(e)];
      s0 += w * tf[0]; s1 += w * tf[1]; s2 += w * tf[2];
    }
    bc[3 * rc] = s0; bc[3 * rc + 1] = s1; bc[3 * rc + 2] = s2;
  });
  // Coarse correction: the small levels on one thread, with a single barrier around them.
  if (team && (l + 1 == last || !team_level(l + 1))) {
#if defined(_OPENMP)
#pragma omp single
#endif
    cycle(l + 1, false);
  } else {
    cycle(l + 1, team);
  }
  // x += P x_c, then post-smoothing (the adjoint of the pre-smoothing: the cycle stays symmetric).
  Scalar* x = iterate(l);
  const Scalar* xc = coarse.x.data();
  detail::for_rows(team, level.rows, [&](int rf) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = coarse.p_begin[static_cast<std::size_t>(rf)]; e < coarse.p_begin[static_cast<std::size_t>(rf) + 1]; ++e) {
      const Scalar w = coarse.p_weight[static_cast<std::size_t>(e)];
      const Scalar* c = xc + 3 * coarse.p_row[static_cast<std::size_t>(e)];
      s0 += w * c[0]; s1 += w * c[1]; s2 += w * c[2];
    }
    x[3 * rf] += s0; x[3 * rf + 1] += s1; x[3 * rf + 2] += s2;
  });
  for (int s = 0; s < m_settings.sweeps; ++s) {
    residual(l, rhs(l), x, t, team);
    jacobi(l, t, false, team);
  }
}

template <class Scalar>
void MultigridPreconditioner<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
#if defined(_OPENMP)
#pragma omp single
#endif
  {
    m_r_in = r;
    m_z_out = z;
  }
  if (level_count() == 1 || !team_level(0)) {
#if defined(_OPENMP)
#pragma omp single
#endif
    cycle(0, false);
  } else {
    cycle(0, true);
  }
}

}  // namespace drape
