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
/// - Routing (`route_through_midpoints`, the default): level 1 is \f$ P^T A' P \f$ with \f$ A' \f$
///   the fine operator whose couplings of nodes two apart along a line (bending) go through the
///   node between them (detail::operator_terms()): the same energy for motion linear along the
///   line, couplings to the 8 neighbours only, so every coarse operator has at most 9 blocks per
///   row instead of up to 25, and CG needs the same iterations (docs/implicit.md).

#include <algorithm>
#include <array>
#include <cstdlib>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/core/validation.hpp"
#include "drape/linalg/block_sparse_matrix.hpp"
#include "drape/linalg/grid_layout.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/detail/coarse_block.hpp"
#include "drape/solvers/detail/multigrid_hierarchy_avx2.hpp"

namespace drape {

struct MultigridSettings {
  int sweeps = 1;            ///< block-Jacobi sweeps before and after the coarse correction
  double omega = 0.8;        ///< Jacobi weight, in (0, 1]
  int max_direct_rows = 16;  ///< coarsest level: at most this many block rows (dense Cholesky)
  /// Coarse operators from the fine one with every coupling of nodes two apart along a lattice
  /// line (bending) routed through the node between them (multigrid_hierarchy.hpp): 9 blocks per
  /// coarse row instead of up to 25, the same CG iterations.
  bool route_through_midpoints = true;
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

/// A weighted block of an operator's row: `weight` times block `block` of a matrix, at `column`.
template <class Scalar>
struct BlockTerm {
  int column, block;
  Scalar weight;
};

/// The rows of `a` (block rows on `layout`) as weighted blocks of a. Block k of row i stays at its
/// column, unless `route` and it couples i to a node c two apart along a lattice line whose node m
/// between them is in the system: then, with \f$ B = a_{ic} \f$, the coupling goes through m,
/// like two springs of half the length and twice the stiffness in series: \f$ 2B \f$ at (i, m)
/// and (m, c), \f$ -\tfrac12 (B + B^T) \f$ at (i, i) and \f$ -(B + B^T) \f$ at (m, m) (block
/// (c, i) adds the mirror terms). For a spring coupling \f$ B = -C \f$ this is exactly the two
/// springs of 2C: the operator stays symmetric and positive definite, keeps its row sums, and has
/// the same energy for displacements linear along the line; its couplings reach one node only.
template <class Scalar>
std::vector<std::vector<BlockTerm<Scalar>>> operator_terms(const GridLayout& layout, const BlockSparseMatrix<Scalar>& a,
                                                           bool route) {
  const int rows = a.block_rows();
  std::vector<std::vector<BlockTerm<Scalar>>> terms(static_cast<std::size_t>(rows));
  std::vector<int> node_of_row(route ? static_cast<std::size_t>(rows) : 0, -1);
  for (std::size_t n = 0; route && n < layout.row_of_node.size(); ++n)
    if (layout.row_of_node[n] >= 0) node_of_row[static_cast<std::size_t>(layout.row_of_node[n])] = static_cast<int>(n);
  const auto midpoint = [&](int i, int c) {
    const int ni = node_of_row[static_cast<std::size_t>(i)], nc = node_of_row[static_cast<std::size_t>(c)];
    const int di = nc % layout.nx - ni % layout.nx, dj = nc / layout.nx - ni / layout.nx;
    if (!((std::abs(di) == 2 && dj == 0) || (di == 0 && std::abs(dj) == 2))) return -1;
    return layout.row_of_node[static_cast<std::size_t>(ni + di / 2 + (dj / 2) * layout.nx)];
  };
  const int* rb = a.row_begin().data();
  const int* col = a.column().data();
  const int* transposed = a.transposed().data();
  for (int i = 0; i < rows; ++i)
    for (int k = rb[i]; k < rb[i + 1]; ++k) {
      const int c = col[k];
      const int m = route && c != i ? midpoint(i, c) : -1;
      std::vector<BlockTerm<Scalar>>& row = terms[static_cast<std::size_t>(i)];
      if (m < 0) {
        row.push_back({c, k, Scalar(1)});
        continue;
      }
      const int kt = transposed[k];  // block (c, i) = B^T
      row.push_back({i, k, Scalar(-0.5)});
      row.push_back({i, kt, Scalar(-0.5)});
      row.push_back({m, k, Scalar(2)});
      std::vector<BlockTerm<Scalar>>& middle = terms[static_cast<std::size_t>(m)];
      middle.push_back({c, k, Scalar(2)});
      middle.push_back({m, k, Scalar(-1)});
      middle.push_back({m, kt, Scalar(-1)});
    }
  return terms;
}

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
/// Blocks of one matrix as fixed weighted sums of another's: block upper[u] (on or above the
/// diagonal; its transpose is stored with it) = sum over e in [begin[u], begin[u+1]) of
/// weight[e] * (source block block[e]).
template <class Scalar>
struct BlockSums {
  std::vector<int> upper, begin, block;
  std::vector<Scalar> weight;
};

/// The pattern of `target` rows and the sums giving its blocks from the source's: target block
/// (ci, cj) sums `t.weight wi wj` times source block t.block for every term t of source row i at
/// column j, (ci, wi) in parent[i], (cj, wj) in parent[j]. A source block in several terms of one
/// target block gets one weight (their sum).
template <class Scalar>
std::pair<BlockSparseMatrix<Scalar>, BlockSums<Scalar>> block_sums(
    const std::vector<std::vector<BlockTerm<Scalar>>>& terms,
    const std::vector<std::vector<std::pair<int, Scalar>>>& parent, int target_rows) {
  const int source_rows = static_cast<int>(terms.size());
  std::vector<std::vector<int>> columns(static_cast<std::size_t>(target_rows));
  for (int i = 0; i < source_rows; ++i)
    for (const BlockTerm<Scalar>& t : terms[static_cast<std::size_t>(i)])
      for (const auto& pi : parent[static_cast<std::size_t>(i)])
        for (const auto& pj : parent[static_cast<std::size_t>(t.column)])
          columns[static_cast<std::size_t>(pi.first)].push_back(pj.first);
  BlockSparseMatrix<Scalar> target(std::move(columns));
  // Terms of every target block on or above the diagonal, grouped by target block (counting sort:
  // count, then fill).
  std::vector<int> first(static_cast<std::size_t>(target.block_count()) + 1, 0);
  const auto for_each_term = [&](auto&& term) {
    for (int i = 0; i < source_rows; ++i)
      for (const BlockTerm<Scalar>& t : terms[static_cast<std::size_t>(i)])
        for (const auto& [ci, wi] : parent[static_cast<std::size_t>(i)])
          for (const auto& [cj, wj] : parent[static_cast<std::size_t>(t.column)])
            if (ci <= cj) term(target.find(ci, cj), t.block, t.weight * wi * wj);
  };
  for_each_term([&](int cb, int, Scalar) { ++first[static_cast<std::size_t>(cb) + 1]; });
  for (std::size_t cb = 0; cb + 1 < first.size(); ++cb) first[cb + 1] += first[cb];
  std::vector<int> fill(first.begin(), first.end() - 1);
  std::vector<std::pair<int, Scalar>> term(static_cast<std::size_t>(first.back()));  // (source block, weight)
  for_each_term([&](int cb, int k, Scalar w) {
    term[static_cast<std::size_t>(fill[static_cast<std::size_t>(cb)]++)] = {k, w};
  });
  BlockSums<Scalar> sums;
  sums.begin.push_back(0);
  for (int cb = 0; cb < target.block_count(); ++cb) {
    const auto begin = term.begin() + first[static_cast<std::size_t>(cb)];
    const auto end = term.begin() + first[static_cast<std::size_t>(cb) + 1];
    if (begin == end) continue;
    std::stable_sort(begin, end, [](const auto& x, const auto& y) { return x.first < y.first; });
    sums.upper.push_back(cb);
    for (auto t = begin; t != end; ++t) {
      if (t != begin && t->first == sums.block.back()) {
        sums.weight.back() += t->second;
        continue;
      }
      sums.block.push_back(t->first);
      sums.weight.push_back(t->second);
    }
    sums.begin.push_back(static_cast<int>(sums.block.size()));
  }
  return {std::move(target), std::move(sums)};
}
}  // namespace detail

template <class Scalar = double>
class MultigridHierarchy {
 public:
  /// Builds the levels for matrices with `fine`'s pattern whose block rows sit on `layout`; level 0
  /// is `fine` itself (not copied). With `route_through_midpoints` (MultigridSettings), level 1 is
  /// summed from the routed operator (routed_matrix()) instead of `fine`. \throws InvalidParameter if
  /// the layout does not describe `fine`'s rows.
  void analyze(const GridLayout& layout, const BlockSparseMatrix<Scalar>& fine, int max_direct_rows,
               bool route_through_midpoints = true);

  bool analyzed() const { return !m_levels.empty(); }
  int level_count() const { return static_cast<int>(m_levels.size()); }
  /// Block rows of level l.
  int rows(int l) const { return m_levels[static_cast<std::size_t>(l)].rows; }
  /// Operator of level l >= 1 (after galerkin(l)).
  const BlockSparseMatrix<Scalar>& matrix(int l) const { return m_levels[static_cast<std::size_t>(l)].a; }
  /// Scalar prolongation from level l >= 1 to level l - 1, `3 rows(l-1) x 3 rows(l)` (allocates:
  /// tests and diagnostics).
  Eigen::SparseMatrix<Scalar> prolongation(int l) const;

  /// True if level 1 is summed from the routed operator (there are coarse levels and analyze() was
  /// asked to route).
  bool routed() const { return !m_route.upper.empty(); }
  /// The fine operator with its couplings two apart routed through midpoints
  /// (detail::operator_terms()), after route(); the caller may filter it in place.
  const BlockSparseMatrix<Scalar>& routed_matrix() const { return m_routed; }
  BlockSparseMatrix<Scalar>& routed_matrix() { return m_routed; }
  /// routed_matrix() from the values of `fine` (level 0's pattern). Shared by the team if `shared`.
  void route(const BlockSparseMatrix<Scalar>& fine, bool shared);
  /// If routed(): level 1's operator straight from level 0's values `fine`, the routing folded into
  /// the Galerkin weights (the same operator as route() then galerkin(1), without the pass over the
  /// routed matrix; for a fine operator that needs no filtering in between).
  /// `fine` may hold the values in double for a float hierarchy (summed in double, rounded once).
  template <class Source>
  void galerkin_through_routing(const BlockSparseMatrix<Source>& fine, bool shared) {
    sum_blocks(m_levels[1].galerkin_through_routing, fine, m_levels[1].a, shared);
  }
  /// Level l's operator (l >= 1) from `finer`: the operator of level l - 1, or for l = 1 the routed
  /// one if routed(). Shared by the team if `shared` (see team_for_if()). `finer` may be double for
  /// a float hierarchy, like galerkin_through_routing().
  template <class Source>
  void galerkin(int l, const BlockSparseMatrix<Source>& finer, bool shared);
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
    detail::BlockSums<Scalar> galerkin;                  // this level's blocks from the finer level's
    detail::BlockSums<Scalar> galerkin_through_routing;  // level 1 if routed(): from level 0's blocks
    int rows = 0;
  };
  /// Rows [0, rows) of `to` = (`add`: plus) the weighted sums of `from`'s rows listed per row
  /// (restriction and prolongation). Shared by the team if `shared`.
  static void transfer(const std::vector<int>& index_begin, const std::vector<int>& index_row,
                       const std::vector<Scalar>& index_weight, const Scalar* from, Scalar* to, bool add, int rows,
                       bool shared);
  /// `target`'s blocks from `source` by `sums`, summed in the wider of the two precisions.
  template <class Source>
  static void sum_blocks(const detail::BlockSums<Scalar>& sums, const BlockSparseMatrix<Source>& source,
                         BlockSparseMatrix<Scalar>& target, bool shared);

  std::vector<Level> m_levels;
  BlockSparseMatrix<Scalar> m_routed;  // level 0 routed (empty unless routed())
  detail::BlockSums<Scalar> m_route;   // m_routed's blocks from level 0's
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
                                         int max_direct_rows, bool route_through_midpoints) {
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
  m_routed = BlockSparseMatrix<Scalar>();
  m_route = {};
  if (route_through_midpoints && rows > max_direct_rows) {
    const std::vector<std::vector<std::pair<int, Scalar>>> itself = [&] {
      std::vector<std::vector<std::pair<int, Scalar>>> parent(static_cast<std::size_t>(rows));
      for (int r = 0; r < rows; ++r) parent[static_cast<std::size_t>(r)] = {{r, Scalar(1)}};
      return parent;
    }();
    auto [matrix, sums] = detail::block_sums(detail::operator_terms(layout, a, true), itself, rows);
    m_routed = std::move(matrix);
    m_route = std::move(sums);
    fine_matrix = &m_routed;
  }
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
    // Level l's operator is P^T A P of the finer one (of the routed operator for level 1).
    auto [matrix, sums] = detail::block_sums(detail::operator_terms(fine, *fine_matrix, false), p, coarse_rows);
    level.a = std::move(matrix);
    level.galerkin = std::move(sums);
    if (fine_matrix == &m_routed)  // the same pattern: the routed operator's couplings
      level.galerkin_through_routing =
          detail::block_sums(detail::operator_terms(layout, a, true), p, coarse_rows).second;
    m_levels.push_back(std::move(level));
    fine_matrix = &m_levels.back().a;
    fine = std::move(coarse);
  }
  if (m_levels.size() == 1) {  // no coarse level to sum from the routed operator
    m_routed = BlockSparseMatrix<Scalar>();
    m_route = {};
  }
}

template <class Scalar>
template <class Source>
void MultigridHierarchy<Scalar>::galerkin(int l, const BlockSparseMatrix<Source>& finer, bool shared) {
  Level& level = m_levels[static_cast<std::size_t>(l)];
  sum_blocks(level.galerkin, finer, level.a, shared);
}

template <class Scalar>
void MultigridHierarchy<Scalar>::route(const BlockSparseMatrix<Scalar>& fine, bool shared) {
  sum_blocks(m_route, fine, m_routed, shared);
}

template <class Scalar>
template <class Source>
void MultigridHierarchy<Scalar>::sum_blocks(const detail::BlockSums<Scalar>& sums,
                                            const BlockSparseMatrix<Source>& source, BlockSparseMatrix<Scalar>& target,
                                            bool shared) {
  using Sum = std::common_type_t<Scalar, Source>;
  static_assert(std::is_same_v<Sum, Source>, "sum_blocks: the source is at least as precise as the target");
  const Source* fine = source.values();
  Scalar* coarse = target.values();
  const int* transposed = target.transposed().data();
  const int count = static_cast<int>(sums.upper.size());
#if DRAPE_AVX2_DISPATCH
  if constexpr ((std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>) &&
                (std::is_same_v<Source, double> || std::is_same_v<Source, float>)) {
    if (instruction_set() == InstructionSet::Avx2) {
      const auto share =
          shared ? even_share(count, team_rank(), team_size()) : std::pair<long long, long long>{0, count};
      detail::galerkin_blocks_avx2(sums.upper.data(), sums.begin.data(), sums.block.data(), sums.weight.data(),
                                   transposed, fine, coarse, int(share.first), int(share.second));
      if (shared) team_barrier();
      return;
    }
  }
#endif
  team_for_if(shared, count, [&](int u) {
    Sum s[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int e = sums.begin[static_cast<std::size_t>(u)]; e < sums.begin[static_cast<std::size_t>(u) + 1]; ++e) {
      const Sum w = sums.weight[static_cast<std::size_t>(e)];
      const Source* f = fine + 9 * sums.block[static_cast<std::size_t>(e)];
      for (int q = 0; q < 9; ++q) s[q] += w * f[q];
    }
    Scalar rounded[9];
    for (int q = 0; q < 9; ++q) rounded[q] = static_cast<Scalar>(s[q]);
    detail::store_coarse_block(rounded, sums.upper[static_cast<std::size_t>(u)], transposed, coarse);
  });
}

template <class Scalar>
void MultigridHierarchy<Scalar>::restrict_to(int l, const Scalar* fine, Scalar* coarse, bool shared) const {
  const Level& level = m_levels[static_cast<std::size_t>(l)];
  transfer(level.r_begin, level.r_row, level.r_weight, fine, coarse, false, level.rows, shared);
}

template <class Scalar>
void MultigridHierarchy<Scalar>::prolong_add(int l, const Scalar* coarse, Scalar* fine, bool shared) const {
  const Level& level = m_levels[static_cast<std::size_t>(l)];
  transfer(level.p_begin, level.p_row, level.p_weight, coarse, fine, true,
           m_levels[static_cast<std::size_t>(l) - 1].rows, shared);
}

template <class Scalar>
void MultigridHierarchy<Scalar>::transfer(const std::vector<int>& index_begin, const std::vector<int>& index_row,
                                          const std::vector<Scalar>& index_weight, const Scalar* from, Scalar* to,
                                          bool add, int rows, bool shared) {
  const auto share = shared ? even_share(rows, team_rank(), team_size()) : std::pair<long long, long long>{0, rows};
  const int begin = int(share.first), end = int(share.second);
#if DRAPE_AVX2_DISPATCH
  if constexpr (std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>) {
    if (instruction_set() == InstructionSet::Avx2) {
      detail::transfer_rows_avx2(index_begin.data(), index_row.data(), index_weight.data(), from, to, add, begin, end);
      if (shared) team_barrier();
      return;
    }
  }
#endif
  for (int r = begin; r < end; ++r) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = index_begin[static_cast<std::size_t>(r)]; e < index_begin[static_cast<std::size_t>(r) + 1]; ++e) {
      const Scalar w = index_weight[static_cast<std::size_t>(e)];
      const Scalar* f = from + 3 * index_row[static_cast<std::size_t>(e)];
      // One line per 3-vector:
      // clang-format off
      s0 += w * f[0]; s1 += w * f[1]; s2 += w * f[2];
    }
    Scalar* t = to + 3 * r;
    if (add) { t[0] += s0; t[1] += s1; t[2] += s2; } else { t[0] = s0; t[1] = s1; t[2] = s2; }
    // clang-format on
  }
  if (shared) team_barrier();
}

}  // namespace drape
