#pragma once
/// \file multigrid_hierarchy.hpp
/// The levels of the geometric multigrid preconditioner (multigrid.hpp): coarser lattices, the
/// transfer operators between them and the Galerkin coarse operators.
///
/// - Coarsening (analyze(), once per pattern): each coarser level keeps every other lattice line
///   along i and j (and always the last one). The prolongation P is bilinear interpolation on the
///   lattice, applied to each of the three components; a coarse node that is not in the system (an
///   eliminated pin) gets no correction. Coarsening stops at `max_direct_rows` block rows or when
///   neither direction can be halved.
/// - Restriction is \f$ R = P^T \f$.
/// - Operators (galerkin(), every solve): \f$ A_{l+1} = P^T A_l P \f$. Every coarse block is a fixed
///   weighted sum of fine blocks, so the weights are listed once and each solve only sums; the
///   matrix is symmetric, so only blocks on or above the diagonal are summed and the others are
///   their transposes. Coarse operators therefore follow the deformation exactly and stay
///   symmetric positive definite.

#include <algorithm>
#include <array>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/core/instruction_set.hpp"
#include "drape/core/team.hpp"
#include "drape/core/validation.hpp"
#include "drape/linalg/block_sparse_matrix.hpp"
#include "drape/linalg/grid_layout.hpp"

#if DRAPE_AVX2_DISPATCH
#include <immintrin.h>
#endif

namespace drape {

struct MultigridSettings {
  int sweeps = 1;            ///< block-Jacobi sweeps before and after the coarse correction
  double omega = 0.8;        ///< Jacobi weight, in (0, 1]
  int max_direct_rows = 16;  ///< coarsest level: at most this many block rows (dense Cholesky)
  /// Levels with fewer block rows run on one thread of the team: below this a loop costs less
  /// than the barriers around it.
  int min_team_rows = 2048;

  /// \throws InvalidParameter naming the first setting out of range.
  void validate() const {
    if (!(omega > 0 && omega <= 1)) detail::fail_argument("multigrid omega", detail::to_text(omega), "(0, 1]");
    detail::require_at_least("multigrid sweeps", sweeps, 1);
    if (!(max_direct_rows >= 1 && max_direct_rows <= 256))
      detail::fail_argument("multigrid max_direct_rows", detail::to_text(max_direct_rows),
                            "1 to 256 (the coarsest level is factorised densely)");
  }
};

namespace detail {

/// One lattice direction of n nodes coarsened: coarse nodes at the even indices and the last one.
struct CoarseAxis {
  int fine = 0, coarse = 0;
  std::vector<int> position;               // fine index of each coarse node
  std::vector<std::array<int, 2>> parent;  // per fine index: one or two coarse nodes (-1 = none)
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

namespace detail {
/// Coarse block `cb` = s (9 values, column-major) and, unless it is on the diagonal, its mirror
/// block transposed[cb] = s^T: the Galerkin sums compute the blocks on or above the diagonal only.
template <class Scalar>
inline void store_coarse_block(const Scalar* s, int cb, const int* transposed, Scalar* coarse) {
  Scalar* c = coarse + 9 * cb;
  for (int q = 0; q < 9; ++q) c[q] = s[q];
  const int ct = transposed[cb];
  if (ct != cb) {
    Scalar* t = coarse + 9 * ct;
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) t[3 * col + row] = s[3 * row + col];
  }
}
}  // namespace detail

#if DRAPE_AVX2_DISPATCH
namespace detail {
/// MultigridHierarchy::galerkin() for double with AVX2, coarse blocks upper[u] for u in
/// [begin, end): values 0-3 and 4-7 of the nine as two vectors, the ninth alone, each summed over
/// the fine blocks in the same order as the baseline loop (no FMA): the same bits.
__attribute__((target("avx2"))) inline void galerkin_blocks_avx2(const int* upper, const int* g_begin,
                                                                 const int* g_block, const double* g_weight,
                                                                 const int* transposed, const double* fine,
                                                                 double* coarse, int begin, int end) {
  for (int u = begin; u < end; ++u) {
    __m256d s0 = _mm256_setzero_pd(), s1 = _mm256_setzero_pd();
    double s8 = 0;
    for (int e = g_begin[u]; e < g_begin[u + 1]; ++e) {
      const __m256d w = _mm256_broadcast_sd(g_weight + e);
      const double* f = fine + 9 * g_block[e];
      s0 = _mm256_add_pd(s0, _mm256_mul_pd(w, _mm256_loadu_pd(f)));
      s1 = _mm256_add_pd(s1, _mm256_mul_pd(w, _mm256_loadu_pd(f + 4)));
      s8 += g_weight[e] * f[8];
    }
    alignas(32) double s[9];
    _mm256_store_pd(s, s0);
    _mm256_storeu_pd(s + 4, s1);
    s[8] = s8;
    store_coarse_block(s, upper[u], transposed, coarse);
  }
}
}  // namespace detail
#endif

template <class Scalar = double>
class MultigridHierarchy {
 public:
  /// Builds the levels for matrices with `fine`'s pattern whose block rows sit on `layout`; level 0
  /// is `fine` itself (not copied). \throws InvalidParameter if the layout does not describe
  /// `fine`'s rows or `max_direct_rows` is out of range.
  void analyze(const GridLayout& layout, const BlockSparseMatrix<Scalar>& fine, int max_direct_rows);

  bool analyzed() const { return !m_levels.empty(); }
  int level_count() const { return static_cast<int>(m_levels.size()); }
  /// Block rows of level l.
  int rows(int l) const { return m_levels[static_cast<std::size_t>(l)].rows; }
  /// Operator of level l >= 1 (after galerkin(l)).
  const BlockSparseMatrix<Scalar>& matrix(int l) const { return m_levels[static_cast<std::size_t>(l)].a; }
  /// Scalar prolongation from level l >= 1 to level l - 1, `3 rows(l-1) x 3 rows(l)` (allocates:
  /// tests and diagnostics).
  Eigen::SparseMatrix<Scalar> prolongation(int l) const;

  /// Level l's operator (l >= 1) from `finer`, the operator of level l - 1. Shared by the team if
  /// `shared` (see team_for_if()).
  void galerkin(int l, const BlockSparseMatrix<Scalar>& finer, bool shared);
  /// `coarse = R fine` from level l - 1 to level l (l >= 1).
  void restrict_to(int l, const Scalar* fine, Scalar* coarse, bool shared) const;
  /// `fine += P coarse` from level l to level l - 1 (l >= 1).
  void prolong_add(int l, const Scalar* coarse, Scalar* fine, bool shared) const;

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
    int rows = 0;
  };

  std::vector<Level> m_levels;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Eigen::SparseMatrix<Scalar> MultigridHierarchy<Scalar>::prolongation(int l) const {
  const Level& coarse = m_levels[static_cast<std::size_t>(l)];
  const int fine_rows = m_levels[static_cast<std::size_t>(l) - 1].rows;
  std::vector<Eigen::Triplet<Scalar>> t;
  for (int rf = 0; rf < fine_rows; ++rf)
    for (int e = coarse.p_begin[static_cast<std::size_t>(rf)]; e < coarse.p_begin[static_cast<std::size_t>(rf) + 1];
         ++e)
      for (int k = 0; k < 3; ++k)
        t.emplace_back(3 * rf + k, 3 * coarse.p_row[static_cast<std::size_t>(e)] + k,
                       coarse.p_weight[static_cast<std::size_t>(e)]);
  Eigen::SparseMatrix<Scalar> p(3 * fine_rows, 3 * coarse.rows);
  p.setFromTriplets(t.begin(), t.end());
  return p;
}

template <class Scalar>
void MultigridHierarchy<Scalar>::analyze(const GridLayout& layout, const BlockSparseMatrix<Scalar>& a,
                                         int max_direct_rows) {
  if (layout.nx < 1 || layout.ny < 1 ||
      layout.row_of_node.size() != static_cast<std::size_t>(layout.nx) * static_cast<std::size_t>(layout.ny))
    detail::fail_argument("grid layout", detail::to_text(layout.row_of_node.size()) + " nodes",
                          "nx * ny nodes, one row index (or -1) each");
  int rows = 0;
  for (int r : layout.row_of_node) rows = std::max(rows, r + 1);
  if (rows != a.block_rows())
    detail::fail_argument("grid layout", detail::to_text(rows) + " rows",
                          detail::to_text(a.block_rows()) + " rows (the matrix's)");

  m_levels.clear();
  m_levels.reserve(32);  // levels hold the matrices the next level's set-up points at
  m_levels.emplace_back();
  m_levels[0].rows = a.block_rows();
  GridLayout fine = layout;
  const BlockSparseMatrix<Scalar>* fine_matrix = &a;
  while (m_levels.back().rows > max_direct_rows) {
    const detail::CoarseAxis ax = detail::coarsen_axis(fine.nx), ay = detail::coarsen_axis(fine.ny);
    if (!ax.halves() && !ay.halves()) break;
    GridLayout coarse;
    coarse.nx = ax.coarse;
    coarse.ny = ay.coarse;
    coarse.row_of_node.assign(static_cast<std::size_t>(coarse.nx) * static_cast<std::size_t>(coarse.ny), -1);
    int coarse_rows = 0;
    for (int cj = 0; cj < coarse.ny; ++cj)
      for (int ci = 0; ci < coarse.nx; ++ci)
        if (fine.row_of_node[static_cast<std::size_t>(ay.position[cj]) * fine.nx + ax.position[ci]] >= 0)
          coarse.row_of_node[static_cast<std::size_t>(cj) * coarse.nx + ci] = coarse_rows++;
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
        for (int cj : pj) {
          if (cj < 0) continue;
          for (int ci : pi) {
            if (ci < 0) continue;
            const int rc = coarse.row_of_node[static_cast<std::size_t>(cj) * coarse.nx + ci];
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
    // Coarse pattern: (ci, cj) for every fine block (i, j) and coarse parents ci of i, cj of j.
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
          for (const auto& [ci, wi] : p[static_cast<std::size_t>(i)])
            for (const auto& [cj, wj] : p[static_cast<std::size_t>(fcol[static_cast<std::size_t>(k)])])
              if (ci <= cj) term(level.a.find(ci, cj), k, wi * wj);
    };
    for_each_term([&](int cb, int, Scalar) { ++first[static_cast<std::size_t>(cb) + 1]; });
    for (std::size_t cb = 0; cb + 1 < first.size(); ++cb) first[cb + 1] += first[cb];
    std::vector<int> fill(first.begin(), first.end() - 1);
    std::vector<int> term_block(static_cast<std::size_t>(first.back()));
    std::vector<Scalar> term_weight(static_cast<std::size_t>(first.back()));
    for_each_term([&](int cb, int k, Scalar w) {
      const int at = fill[static_cast<std::size_t>(cb)]++;
      term_block[static_cast<std::size_t>(at)] = k;
      term_weight[static_cast<std::size_t>(at)] = w;
    });
    level.g_begin.push_back(0);
    for (int cb = 0; cb < level.a.block_count(); ++cb) {
      if (first[static_cast<std::size_t>(cb)] == first[static_cast<std::size_t>(cb) + 1]) continue;
      level.upper.push_back(cb);
      level.g_block.insert(level.g_block.end(), term_block.begin() + first[static_cast<std::size_t>(cb)],
                           term_block.begin() + first[static_cast<std::size_t>(cb) + 1]);
      level.g_weight.insert(level.g_weight.end(), term_weight.begin() + first[static_cast<std::size_t>(cb)],
                            term_weight.begin() + first[static_cast<std::size_t>(cb) + 1]);
      level.g_begin.push_back(static_cast<int>(level.g_block.size()));
    }
    m_levels.push_back(std::move(level));
    fine_matrix = &m_levels.back().a;
    fine = std::move(coarse);
  }
}

template <class Scalar>
void MultigridHierarchy<Scalar>::galerkin(int l, const BlockSparseMatrix<Scalar>& finer, bool shared) {
  Level& level = m_levels[static_cast<std::size_t>(l)];
  const Scalar* fine = finer.values();
  Scalar* coarse = level.a.values();
  const int* transposed = level.a.transposed().data();
  const int count = static_cast<int>(level.upper.size());
#if DRAPE_AVX2_DISPATCH
  if constexpr (std::is_same_v<Scalar, double>) {
    if (instruction_set() == InstructionSet::Avx2) {
      const auto share =
          shared ? even_share(count, team_rank(), team_size()) : std::pair<long long, long long>{0, count};
      detail::galerkin_blocks_avx2(level.upper.data(), level.g_begin.data(), level.g_block.data(),
                                   level.g_weight.data(), transposed, fine, coarse, int(share.first),
                                   int(share.second));
      if (shared) team_barrier();
      return;
    }
  }
#endif
  team_for_if(shared, count, [&](int u) {
    Scalar s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int e = level.g_begin[static_cast<std::size_t>(u)]; e < level.g_begin[static_cast<std::size_t>(u) + 1]; ++e) {
      const Scalar w = level.g_weight[static_cast<std::size_t>(e)];
      const Scalar* f = fine + 9 * level.g_block[static_cast<std::size_t>(e)];
      for (int q = 0; q < 9; ++q) s[q] += w * f[q];
    }
    detail::store_coarse_block(s, level.upper[static_cast<std::size_t>(u)], transposed, coarse);
  });
}

template <class Scalar>
void MultigridHierarchy<Scalar>::restrict_to(int l, const Scalar* fine, Scalar* coarse, bool shared) const {
  const Level& level = m_levels[static_cast<std::size_t>(l)];
  team_for_if(shared, level.rows, [&](int rc) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = level.r_begin[static_cast<std::size_t>(rc)]; e < level.r_begin[static_cast<std::size_t>(rc) + 1];
         ++e) {
      const Scalar w = level.r_weight[static_cast<std::size_t>(e)];
      const Scalar* tf = fine + 3 * level.r_row[static_cast<std::size_t>(e)];
      // One line per 3-vector:
      // clang-format off
      s0 += w * tf[0]; s1 += w * tf[1]; s2 += w * tf[2];
    }
    coarse[3 * rc] = s0; coarse[3 * rc + 1] = s1; coarse[3 * rc + 2] = s2;
    // clang-format on
  });
}

template <class Scalar>
void MultigridHierarchy<Scalar>::prolong_add(int l, const Scalar* coarse, Scalar* fine, bool shared) const {
  const Level& level = m_levels[static_cast<std::size_t>(l)];
  team_for_if(shared, m_levels[static_cast<std::size_t>(l) - 1].rows, [&](int rf) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = level.p_begin[static_cast<std::size_t>(rf)]; e < level.p_begin[static_cast<std::size_t>(rf) + 1];
         ++e) {
      const Scalar w = level.p_weight[static_cast<std::size_t>(e)];
      const Scalar* c = coarse + 3 * level.p_row[static_cast<std::size_t>(e)];
      // One line per 3-vector:
      // clang-format off
      s0 += w * c[0]; s1 += w * c[1]; s2 += w * c[2];
    }
    fine[3 * rf] += s0; fine[3 * rf + 1] += s1; fine[3 * rf + 2] += s2;
    // clang-format on
  });
}

}  // namespace drape
