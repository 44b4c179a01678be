#pragma once
/// \file aggregation_hierarchy.hpp
/// The levels of the algebraic multigrid preconditioner (algebraic_multigrid.hpp): smoothed
/// aggregation (Vanek, Mandel & Brezina 1996) on a matrix of 3x3 blocks, with every coarse space
/// filtered by the constraints (Tamstorf, Jones & McCormick 2015). It needs no lattice: only the
/// block pattern and the values.
///
/// Set-up (start(), then add_level() per level; once per pattern, from one set of values):
/// - Strength: block (i, j) is strong if \f$ \|A_{ij}\|_F^2 \ge \varepsilon_l^2 \|A_{ii}\|_F \|A_{jj}\|_F \f$
///   (\f$ \varepsilon_l = \varepsilon\, 2^{-l} \f$ on level l). On cloth this keeps the stretch springs
///   and drops the bending ones, so aggregates are compact patches.
/// - Aggregation, greedy in row order: a row whose strong neighbours are all unaggregated starts an
///   aggregate of itself and them; a row left over joins the aggregate it is most strongly tied to;
///   what remains forms aggregates with its unaggregated neighbours. A row with no strong neighbour
///   stays out of every aggregate (the smoother alone handles it).
/// - Tentative prolongator T: the three translations of each aggregate, i.e. block \f$ S_i \f$ (the
///   row's constraint filter, the identity for a free row) at (row, its aggregate).
/// - Smoothed prolongator \f$ P = (I - \omega D_F^{-1} A_F)\, T \f$, \f$ A_F \f$ the filtered matrix (weak
///   blocks dropped and added to the diagonal: row sums, hence the translations, are kept),
///   \f$ \omega = \tfrac43 / \rho(D^{-1} A) \f$ (the caller estimates \f$ \rho \f$). Row i of P reaches the
///   aggregates of i's strong neighbours.
/// - The patterns of \f$ A P \f$ and of the Galerkin operator \f$ A_c = P^T A P \f$, and for every block of
///   P, A P and \f$ A_c \f$ the list of block products it sums.
///
/// Every step (update(), values only, nothing allocated) recomputes P and \f$ A_c \f$ from the new
/// operator. Constraints (Tamstorf, Jones & McCormick 2015): the fine operator is the filtered
/// \f$ \hat A = S A S + I - S \f$ (the caller's), T's blocks are the filters \f$ S_i \f$ and P's rows are
/// filtered (\f$ S_i P_{iJ} \f$), so no coarse correction moves a constrained direction. Each coarse
/// row J gets the filter \f$ \Pi_J \f$, the projection on the directions its aggregate still has free
/// (the eigenvectors of \f$ \sum_{i \in J} S_i \f$ with eigenvalue above 1/100); P's columns are
/// projected on them and \f$ A_c = P^T \hat A P + I - \Pi \f$: the coarse level is a filtered operator
/// in turn, symmetric positive definite, and a fully fixed aggregate is an identity row. The strength
/// of a coarse level leaves \f$ I - \Pi \f$ out of its diagonal norms: whatever the units of A, the
/// identity of the constrained directions does not make a coarse row look weakly coupled.
///
/// Threads: every value is one thread's sum in a fixed order, whoever computes it, so the levels
/// are bitwise the same for any team size. A level's loops are shared by the team when `shared`.

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/linalg/block3.hpp"
#include "drape/linalg/block_sparse_matrix.hpp"
#include "drape/linalg/constraint_filter.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/detail/coarse_block.hpp"

namespace drape {

struct AlgebraicMultigridSettings {
  /// Strength threshold \f$ \varepsilon \f$ on the finest level (halved on each coarser one), in [0, 1).
  double strength = 0.08;
  /// P's smoothing weight w: \f$ P = (I - \tfrac{w}{\rho} D_F^{-1} A_F) T \f$ with \f$ \rho = \rho(D^{-1} A) \f$,
  /// in [0, 2); 0 gives plain (unsmoothed) aggregation.
  double prolongator_weight = 4.0 / 3.0;
  int sweeps = 1;  ///< block-Jacobi sweeps before and after the coarse correction
  /// Block-Jacobi weight, in (0, 1]; a level whose \f$ \rho(D^{-1} A) \f$ exceeds 4 / (3 omega) gets 4 / (3 rho).
  double omega = 0.8;
  /// The coarsest level: at most this many block rows, solved by dense Cholesky.
  int max_direct_rows = 32;
  int max_levels = 12;  ///< levels, the finest included
  /// Lanczos steps that estimate each level's \f$ \rho(D^{-1} A) \f$ (the weights of P and of the smoother).
  int spectral_steps = 6;
  /// Levels with fewer block rows run on one thread of the team (like MultigridSettings).
  int min_team_rows = 2048;

  /// \throws InvalidParameter naming the first setting out of range.
  void validate() const {
    if (!(strength >= 0 && strength < 1)) detail::fail_argument("amg strength", detail::to_text(strength), "[0, 1)");
    if (!(prolongator_weight >= 0 && prolongator_weight < 2))
      detail::fail_argument("amg prolongator_weight", detail::to_text(prolongator_weight), "[0, 2)");
    detail::require_at_least("amg sweeps", sweeps, 1);
    if (!(omega > 0 && omega <= 1)) detail::fail_argument("amg omega", detail::to_text(omega), "(0, 1]");
    if (!(max_direct_rows >= 1 && max_direct_rows <= 256))
      detail::fail_argument("amg max_direct_rows", detail::to_text(max_direct_rows),
                            "1 to 256 (the coarsest level is factorised densely)");
    detail::require_in_range("amg max_levels", max_levels, 1, 40);
    detail::require_in_range("amg spectral_steps", spectral_steps, 2, 40);
    detail::require_at_least("amg min_team_rows", min_team_rows, 1);
  }
};

namespace detail {

/// The strong off-diagonal blocks of each row of a matrix: block index, column and the strength
/// \f$ \|A_{ij}\|_F^2 / (\|A_{ii}\|_F \|A_{jj}\|_F) \f$.
struct StrongBlocks {
  std::vector<int> begin{0}, block, column;
  std::vector<double> strength;
};

template <class Scalar>
double frobenius_squared(const Scalar* block) {
  double s = 0;
  for (int q = 0; q < 9; ++q) s += double(block[q]) * double(block[q]);
  return s;
}

/// Blocks (i, j), j != i, with \f$ \|A_{ij}\|_F^2 \ge \varepsilon^2 \|A_{ii}\|_F \|A_{jj}\|_F \f$ (any
/// nonzero block if a diagonal block is zero). `identity` (9 values per row, or null): a part of each
/// diagonal block left out of its norm (a filtered operator's \f$ I - \Pi \f$, which couples nothing).
template <class Scalar>
StrongBlocks strong_blocks(const BlockSparseMatrix<Scalar>& a, double epsilon, const Scalar* identity = nullptr) {
  const int rows = a.block_rows();
  std::vector<double> diagonal(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    Scalar block[9];
    for (int q = 0; q < 9; ++q)
      block[q] = a.values()[9 * a.diagonal()[r] + q] - (identity ? identity[9 * static_cast<std::size_t>(r) + q] : 0);
    diagonal[static_cast<std::size_t>(r)] = std::sqrt(frobenius_squared(block));
  }
  StrongBlocks s;
  for (int r = 0; r < rows; ++r) {
    for (int k = a.row_begin()[r]; k < a.row_begin()[r + 1]; ++k) {
      const int c = a.column()[k];
      if (c == r) continue;
      const double v = frobenius_squared(a.values() + 9 * k);
      const double reference = diagonal[static_cast<std::size_t>(r)] * diagonal[static_cast<std::size_t>(c)];
      const bool strong = reference > 0 ? v >= epsilon * epsilon * reference : v > 0;
      if (!strong) continue;
      s.block.push_back(k);
      s.column.push_back(c);
      s.strength.push_back(reference > 0 ? v / reference : std::numeric_limits<double>::infinity());
    }
    s.begin.push_back(static_cast<int>(s.block.size()));
  }
  return s;
}

/// Greedy aggregation on the strong blocks (Vanek, Mandel & Brezina 1996, section 3): the
/// aggregate of each row (-1: none, a row with no strong neighbour); returns the aggregate count.
inline int aggregate(const StrongBlocks& s, int rows, std::vector<int>& of) {
  of.assign(static_cast<std::size_t>(rows), -1);
  const auto neighbours = [&](int r) {
    return std::pair<int, int>{s.begin[static_cast<std::size_t>(r)], s.begin[static_cast<std::size_t>(r) + 1]};
  };
  int count = 0;
  // 1: a row whose neighbours are all unaggregated starts an aggregate of itself and them.
  for (int r = 0; r < rows; ++r) {
    const auto [b, e] = neighbours(r);
    if (b == e || of[static_cast<std::size_t>(r)] >= 0) continue;
    bool free = true;
    for (int q = b; q < e && free; ++q) free = of[static_cast<std::size_t>(s.column[static_cast<std::size_t>(q)])] < 0;
    if (!free) continue;
    of[static_cast<std::size_t>(r)] = count;
    for (int q = b; q < e; ++q) of[static_cast<std::size_t>(s.column[static_cast<std::size_t>(q)])] = count;
    ++count;
  }
  // 2: a row left over joins the first-pass aggregate it is most strongly tied to.
  const std::vector<int> first = of;
  for (int r = 0; r < rows; ++r) {
    if (first[static_cast<std::size_t>(r)] >= 0) continue;
    const auto [b, e] = neighbours(r);
    double best = -1;
    for (int q = b; q < e; ++q) {
      const int joined = first[static_cast<std::size_t>(s.column[static_cast<std::size_t>(q)])];
      if (joined >= 0 && s.strength[static_cast<std::size_t>(q)] > best) {
        best = s.strength[static_cast<std::size_t>(q)];
        of[static_cast<std::size_t>(r)] = joined;
      }
    }
  }
  // 3: the rest, with their unaggregated neighbours.
  for (int r = 0; r < rows; ++r) {
    const auto [b, e] = neighbours(r);
    if (b == e || of[static_cast<std::size_t>(r)] >= 0) continue;
    of[static_cast<std::size_t>(r)] = count;
    for (int q = b; q < e; ++q) {
      int& other = of[static_cast<std::size_t>(s.column[static_cast<std::size_t>(q)])];
      if (other < 0) other = count;
    }
    ++count;
  }
  return count;
}

}  // namespace detail

template <class Scalar = double>
class AggregationHierarchy {
 public:
  /// Level 0 alone: `rows` block rows with the filters of `constraints`. Allocates.
  void start(int rows, const ConstraintFilter<Scalar>& constraints, const AlgebraicMultigridSettings& settings);
  /// A coarser level below the coarsest one: strength, aggregates and every pattern from `coarsest`,
  /// the values of the coarsest operator (level 0: A itself, unfiltered: the constraints change from
  /// step to step, the aggregates do not), with strength threshold `epsilon`. Its values come with
  /// update(). Returns false (and adds nothing) if the aggregates would not make fewer rows.
  bool add_level(const BlockSparseMatrix<Scalar>& coarsest, const AlgebraicMultigridSettings& settings,
                 double epsilon);

  bool built() const { return !m_levels.empty(); }
  /// Forgets the levels (built() is false until the next build()).
  void clear() { m_levels.clear(); }
  int level_count() const { return static_cast<int>(m_levels.size()); }
  int rows(int l) const { return m_levels[static_cast<std::size_t>(l)].rows; }
  /// Operator of level l >= 1 (after update()).
  const BlockSparseMatrix<Scalar>& matrix(int l) const { return m_levels[static_cast<std::size_t>(l)].a; }
  /// The aggregate (row of level l + 1) of each row of level l, -1 for none.
  const std::vector<int>& aggregates(int l) const { return m_levels[static_cast<std::size_t>(l) + 1].aggregate_of; }
  /// Level l's row filter (level 0: the constraints of the last update()).
  ConstraintKind kind(int l, int row) const {
    return m_levels[static_cast<std::size_t>(l)].kind[static_cast<std::size_t>(row)];
  }
  Mat3<Scalar> filter(int l, int row) const;
  /// The smoothing weight of the prolongator from level l in the last update().
  Scalar prolongator_omega(int l) const { return m_levels[static_cast<std::size_t>(l)].omega; }
  /// Scalar prolongation from level l >= 1 to level l - 1 (allocates: tests and diagnostics).
  Eigen::SparseMatrix<Scalar> prolongation(int l) const;
  /// Blocks of P, A P and P^T A P summed per update (a measure of the set-up's cost).
  long long block_count(int l) const;

  /// Level 0's row filters from `constraints` (empty: every row free). Rows shared if `shared`.
  void set_constraints(const ConstraintFilter<Scalar>& constraints, bool shared);
  /// Level l >= 1 from `finer`, the operator of level l - 1: P smoothed with weight `omega`, then
  /// \f$ P^T \hat A P + I - \Pi \f$. Shared by the team if `shared` (every thread calls it), else all
  /// on the calling thread. Returns false if a diagonal block of the filtered matrix and of `finer`
  /// are both singular.
  bool update(int l, const BlockSparseMatrix<Scalar>& finer, Scalar omega, bool shared);
  /// `coarse = P^T fine` from level l - 1 to level l (l >= 1).
  void restrict_to(int l, const Scalar* fine, Scalar* coarse, bool shared) const;
  /// `fine += P coarse` from level l to level l - 1 (l >= 1).
  void prolong_add(int l, const Scalar* coarse, Scalar* fine, bool shared) const;

 private:
  struct Level {
    int rows = 0;
    std::vector<ConstraintKind> kind;  // the rows' filters: Free, Fixed, or Projected with
    std::vector<Scalar> projection;    // 9 values per row (column-major); identity unless Projected
    bool constrained = false;          // a row that is not Free
    // Levels >= 1: the operator, and how it is made from the finer level.
    BlockSparseMatrix<Scalar> a;
    std::vector<int> aggregate_of;            // per finer row: this level's row, or -1
    std::vector<int> member_begin, member;    // per row: the finer rows of its aggregate
    std::vector<int> strong_begin, strong;    // per finer row: its strong off-diagonal blocks
    std::vector<int> weak_begin, weak;        // per finer row: its weak off-diagonal blocks
    std::vector<Scalar> lumped_inverse;       // per finer row: D_F^-1 (9 values)
    // P, by finer row: column (row of this level), values (9 each); each block sums the strong
    // blocks of the finer operator listed in [p_term_begin[e], p_term_begin[e+1]).
    std::vector<int> p_begin, p_column, p_term_begin, p_term_block;
    std::vector<char> p_tentative;  // the finer row belongs to this column's aggregate
    std::vector<Scalar> p_value;
    // P^T by row of this level: the finer row and P's block, transposed values.
    std::vector<int> r_begin, r_row, r_block;
    std::vector<Scalar> r_value;
    // A P, by finer row: column, values; terms (finer block, P block).
    std::vector<int> ap_begin, ap_column, ap_term_begin, ap_term_block, ap_term_p;
    std::vector<Scalar> ap_value;
    // Galerkin: per block on or above the diagonal, the pairs (P block, A P block) it sums.
    std::vector<int> g_upper, g_row, g_begin, g_p, g_ap;
    Scalar omega = 0;  // P's smoothing weight in the last update
  };

  std::vector<Level> m_levels;
  std::atomic<int> m_failed{0};
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Mat3<Scalar> AggregationHierarchy<Scalar>::filter(int l, int row) const {
  const Level& level = m_levels[static_cast<std::size_t>(l)];
  return Eigen::Map<const Mat3<Scalar>>(level.projection.data() + 9 * static_cast<std::size_t>(row));
}

template <class Scalar>
Eigen::SparseMatrix<Scalar> AggregationHierarchy<Scalar>::prolongation(int l) const {
  const Level& c = m_levels[static_cast<std::size_t>(l)];
  const int fine_rows = rows(l - 1);
  std::vector<Eigen::Triplet<Scalar>> t;
  for (int i = 0; i < fine_rows; ++i)
    for (int e = c.p_begin[static_cast<std::size_t>(i)]; e < c.p_begin[static_cast<std::size_t>(i) + 1]; ++e)
      for (int col = 0; col < 3; ++col)
        for (int row = 0; row < 3; ++row)
          t.emplace_back(3 * i + row, 3 * c.p_column[static_cast<std::size_t>(e)] + col,
                         c.p_value[9 * static_cast<std::size_t>(e) + 3 * static_cast<std::size_t>(col) +
                                   static_cast<std::size_t>(row)]);
  Eigen::SparseMatrix<Scalar> p(3 * fine_rows, 3 * c.rows);
  p.setFromTriplets(t.begin(), t.end());
  return p;
}

template <class Scalar>
long long AggregationHierarchy<Scalar>::block_count(int l) const {
  const Level& c = m_levels[static_cast<std::size_t>(l)];
  return static_cast<long long>(c.p_column.size() + c.ap_column.size() + c.g_upper.size());
}

template <class Scalar>
void AggregationHierarchy<Scalar>::start(int rows, const ConstraintFilter<Scalar>& constraints,
                                         const AlgebraicMultigridSettings& settings) {
  m_levels.clear();
  m_levels.reserve(static_cast<std::size_t>(settings.max_levels));  // levels hold matrices the next ones read
  m_levels.emplace_back();
  Level& finest = m_levels[0];
  finest.rows = rows;
  finest.kind.assign(static_cast<std::size_t>(rows), ConstraintKind::Free);
  finest.projection.assign(9 * static_cast<std::size_t>(rows), Scalar(0));
  for (int r = 0; r < rows; ++r)
    Eigen::Map<Mat3<Scalar>>(finest.projection.data() + 9 * static_cast<std::size_t>(r)).setIdentity();
  set_constraints(constraints, false);
}

template <class Scalar>
bool AggregationHierarchy<Scalar>::add_level(const BlockSparseMatrix<Scalar>& fine,
                                             const AlgebraicMultigridSettings& settings, double epsilon) {
  DRAPE_ASSERT(level_count() < static_cast<int>(m_levels.capacity()), "amg: more levels than max_levels");
  const int fine_rows = fine.block_rows();
  // A coarse operator's diagonal holds I - Pi for its constrained rows: not part of the strength.
  std::vector<Scalar> identity;
  const Level& coarsest = m_levels.back();
  if (level_count() > 1 && coarsest.constrained) {
    identity.assign(9 * static_cast<std::size_t>(fine_rows), Scalar(0));
    for (int r = 0; r < fine_rows; ++r)
      if (coarsest.kind[static_cast<std::size_t>(r)] != ConstraintKind::Free)
        Eigen::Map<Mat3<Scalar>>(identity.data() + 9 * static_cast<std::size_t>(r)) =
            Mat3<Scalar>::Identity() - filter(level_count() - 1, r);
  }
  const detail::StrongBlocks strong =
      detail::strong_blocks(fine, epsilon, identity.empty() ? nullptr : identity.data());
  Level c;
  c.rows = detail::aggregate(strong, fine_rows, c.aggregate_of);
  if (c.rows == 0 || c.rows >= fine_rows) return false;  // no coarser level: the finer one is the coarsest
  const auto at = [](const std::vector<int>& v, int i) { return v[static_cast<std::size_t>(i)]; };
  const int* col = fine.column().data();
  const int* rb = fine.row_begin().data();

  // Members of each aggregate, and each finer row's strong and weak blocks.
  c.member_begin.assign(static_cast<std::size_t>(c.rows) + 1, 0);
  for (int i = 0; i < fine_rows; ++i)
    if (at(c.aggregate_of, i) >= 0) ++c.member_begin[static_cast<std::size_t>(at(c.aggregate_of, i)) + 1];
  for (int cj = 0; cj < c.rows; ++cj) c.member_begin[static_cast<std::size_t>(cj) + 1] += at(c.member_begin, cj);
  c.member.resize(static_cast<std::size_t>(c.member_begin.back()));
  {
    std::vector<int> next(c.member_begin.begin(), c.member_begin.end() - 1);  // indexed by aggregate
    for (int i = 0; i < fine_rows; ++i)
      if (at(c.aggregate_of, i) >= 0) c.member[static_cast<std::size_t>(next[at(c.aggregate_of, i)]++)] = i;
  }
  c.strong_begin.assign(1, 0);
  c.weak_begin.assign(1, 0);
  for (int i = 0; i < fine_rows; ++i) {
    int q = strong.begin[static_cast<std::size_t>(i)];
    for (int k = rb[i]; k < rb[i + 1]; ++k) {
      if (col[k] == i) continue;
      if (q < strong.begin[static_cast<std::size_t>(i) + 1] && strong.block[static_cast<std::size_t>(q)] == k) {
        c.strong.push_back(k);
        ++q;
      } else {
        c.weak.push_back(k);
      }
    }
    c.strong_begin.push_back(static_cast<int>(c.strong.size()));
    c.weak_begin.push_back(static_cast<int>(c.weak.size()));
  }
  c.lumped_inverse.assign(9 * static_cast<std::size_t>(fine_rows), Scalar(0));

  // P: row i reaches its own aggregate and those of its strong neighbours (only its own if P is
  // not smoothed); the terms of block (i, J) are i's strong blocks to members of J.
  const bool smoothed = settings.prolongator_weight > 0;
  c.p_begin.assign(1, 0);
  c.p_term_begin.assign(1, 0);
  std::vector<std::pair<int, int>> row_terms;  // (aggregate, strong block position; -1: i itself)
  for (int i = 0; i < fine_rows; ++i) {
    row_terms.clear();
    if (at(c.aggregate_of, i) >= 0) row_terms.emplace_back(at(c.aggregate_of, i), -1);
    if (smoothed)
      for (int q = at(c.strong_begin, i); q < at(c.strong_begin, i + 1); ++q) {
        const int cj = at(c.aggregate_of, col[at(c.strong, q)]);
        if (cj >= 0) row_terms.emplace_back(cj, q);
      }
    std::stable_sort(row_terms.begin(), row_terms.end(),
                     [](const std::pair<int, int>& x, const std::pair<int, int>& y) { return x.first < y.first; });
    for (std::size_t t = 0; t < row_terms.size(); ++t) {
      const int cj = row_terms[t].first;
      if (t == 0 || row_terms[t - 1].first != cj) {
        if (t > 0) c.p_term_begin.push_back(static_cast<int>(c.p_term_block.size()));
        c.p_column.push_back(cj);
        c.p_tentative.push_back(0);
      }
      if (row_terms[t].second < 0) {
        c.p_tentative.back() = 1;
      } else {
        c.p_term_block.push_back(at(c.strong, row_terms[t].second));
      }
    }
    if (!row_terms.empty()) c.p_term_begin.push_back(static_cast<int>(c.p_term_block.size()));
    c.p_begin.push_back(static_cast<int>(c.p_column.size()));
  }
  c.p_value.assign(9 * c.p_column.size(), Scalar(0));

  // P^T by row of this level (finer rows in order).
  c.r_begin.assign(static_cast<std::size_t>(c.rows) + 1, 0);
  for (int cj : c.p_column) ++c.r_begin[static_cast<std::size_t>(cj) + 1];
  for (int cj = 0; cj < c.rows; ++cj) c.r_begin[static_cast<std::size_t>(cj) + 1] += at(c.r_begin, cj);
  c.r_row.resize(c.p_column.size());
  c.r_block.resize(c.p_column.size());
  {
    std::vector<int> next(c.r_begin.begin(), c.r_begin.end() - 1);
    for (int i = 0; i < fine_rows; ++i)
      for (int e = at(c.p_begin, i); e < at(c.p_begin, i + 1); ++e) {
        const int slot = next[static_cast<std::size_t>(at(c.p_column, e))]++;
        c.r_row[static_cast<std::size_t>(slot)] = i;
        c.r_block[static_cast<std::size_t>(slot)] = e;
      }
  }
  c.r_value.assign(9 * c.r_block.size(), Scalar(0));

  // A P by finer row: (A P)_iJ = sum over the blocks (i, j) of the finer operator and P's blocks (j, J).
  c.ap_begin.assign(1, 0);
  c.ap_term_begin.assign(1, 0);
  std::vector<std::array<int, 3>> products;  // (J, finer block, P block)
  for (int i = 0; i < fine_rows; ++i) {
    products.clear();
    for (int k = rb[i]; k < rb[i + 1]; ++k)
      for (int e = at(c.p_begin, col[k]); e < at(c.p_begin, col[k] + 1); ++e)
        products.push_back({at(c.p_column, e), k, e});
    std::stable_sort(products.begin(), products.end(),
                     [](const std::array<int, 3>& x, const std::array<int, 3>& y) { return x[0] < y[0]; });
    for (std::size_t t = 0; t < products.size(); ++t) {
      const bool first = t == 0 || products[t - 1][0] != products[t][0];
      if (first && t > 0) c.ap_term_begin.push_back(static_cast<int>(c.ap_term_block.size()));
      if (first) c.ap_column.push_back(products[t][0]);
      c.ap_term_block.push_back(products[t][1]);
      c.ap_term_p.push_back(products[t][2]);
    }
    if (!products.empty()) c.ap_term_begin.push_back(static_cast<int>(c.ap_term_block.size()));
    c.ap_begin.push_back(static_cast<int>(c.ap_column.size()));
  }
  c.ap_value.assign(9 * c.ap_column.size(), Scalar(0));

  // P^T (A P): block (I, J) sums P_iI^T (A P)_iJ over the finer rows i; pattern, then the pairs of
  // each block on or above the diagonal.
  std::vector<std::vector<std::array<int, 3>>> pairs(static_cast<std::size_t>(c.rows));  // (J, P block, AP block)
  std::vector<std::vector<int>> columns(static_cast<std::size_t>(c.rows));
  for (int ci = 0; ci < c.rows; ++ci) {
    for (int s = at(c.r_begin, ci); s < at(c.r_begin, ci + 1); ++s) {
      const int i = at(c.r_row, s);
      for (int f = at(c.ap_begin, i); f < at(c.ap_begin, i + 1); ++f) {
        const int cj = at(c.ap_column, f);
        if (cj < ci) continue;
        pairs[static_cast<std::size_t>(ci)].push_back({cj, at(c.r_block, s), f});
        columns[static_cast<std::size_t>(ci)].push_back(cj);
        columns[static_cast<std::size_t>(cj)].push_back(ci);
      }
    }
  }
  c.a = BlockSparseMatrix<Scalar>(std::move(columns));
  c.g_begin.assign(1, 0);
  for (int ci = 0; ci < c.rows; ++ci) {
    std::vector<std::array<int, 3>>& list = pairs[static_cast<std::size_t>(ci)];
    std::stable_sort(list.begin(), list.end(),
                     [](const std::array<int, 3>& x, const std::array<int, 3>& y) { return x[0] < y[0]; });
    for (std::size_t t = 0; t < list.size(); ++t) {
      if (t > 0 && list[t - 1][0] != list[t][0]) c.g_begin.push_back(static_cast<int>(c.g_p.size()));
      if (t == 0 || list[t - 1][0] != list[t][0]) {
        c.g_upper.push_back(c.a.find(ci, list[t][0]));
        c.g_row.push_back(ci);
      }
      c.g_p.push_back(list[t][1]);
      c.g_ap.push_back(list[t][2]);
    }
    if (!list.empty()) c.g_begin.push_back(static_cast<int>(c.g_p.size()));
  }
  c.kind.assign(static_cast<std::size_t>(c.rows), ConstraintKind::Free);
  c.projection.assign(9 * static_cast<std::size_t>(c.rows), Scalar(0));
  for (int cj = 0; cj < c.rows; ++cj)
    Eigen::Map<Mat3<Scalar>>(c.projection.data() + 9 * static_cast<std::size_t>(cj)).setIdentity();
  m_levels.push_back(std::move(c));
  return true;
}

template <class Scalar>
void AggregationHierarchy<Scalar>::set_constraints(const ConstraintFilter<Scalar>& constraints, bool shared) {
  Level& finest = m_levels[0];
  const bool any = !constraints.empty();
  if (!any && !finest.constrained) return;  // already every row free
  team_for_if(shared, finest.rows, [&](int r) {
    const ConstraintKind kind = any ? constraints.kind(r) : ConstraintKind::Free;
    const ConstraintKind before = finest.kind[static_cast<std::size_t>(r)];
    if (kind == ConstraintKind::Free && before == ConstraintKind::Free) return;
    finest.kind[static_cast<std::size_t>(r)] = kind;
    Eigen::Map<Mat3<Scalar>>(finest.projection.data() + 9 * static_cast<std::size_t>(r)) =
        kind == ConstraintKind::Free ? Mat3<Scalar>::Identity() : constraints.filter(r);
  });
  if (shared)
    team_single([&] { finest.constrained = any; });
  else
    finest.constrained = any;
}

template <class Scalar>
bool AggregationHierarchy<Scalar>::update(int l, const BlockSparseMatrix<Scalar>& finer, Scalar omega, bool shared) {
  using Block = Eigen::Map<const Mat3<Scalar>>;
  const Level& f = m_levels[static_cast<std::size_t>(l) - 1];
  Level& c = m_levels[static_cast<std::size_t>(l)];
  const int fine_rows = f.rows;
  const Scalar* values = finer.values();
  const int* diagonal = finer.diagonal().data();
  const auto at = [](const std::vector<int>& v, int i) { return v[static_cast<std::size_t>(i)]; };
  const auto fine_filter = [&](int i) { return Block(f.projection.data() + 9 * static_cast<std::size_t>(i)); };
  if (shared)
    team_single([&] { m_failed.store(0, std::memory_order_relaxed); });
  else
    m_failed.store(0, std::memory_order_relaxed);

  // D_F^-1: the diagonal with the weak blocks added (A_F's; singular: A's own).
  const bool smoothed = c.p_term_block.size() > 0;
  if (smoothed)
    team_for_if(shared, fine_rows, [&](int i) {
      Mat3<Scalar> lumped = Block(values + 9 * diagonal[i]);
      for (int q = at(c.weak_begin, i); q < at(c.weak_begin, i + 1); ++q) lumped += Block(values + 9 * at(c.weak, q));
      Scalar* inverse = c.lumped_inverse.data() + 9 * static_cast<std::size_t>(i);
      if (!invert_block(lumped.data(), inverse) && !invert_block(values + 9 * diagonal[i], inverse))
        m_failed.store(1, std::memory_order_relaxed);
    });
  // The coarse filters: the directions the members' filters leave, all three if every member is free.
  team_for_if(shared, c.rows, [&](int cj) {
    Mat3<Scalar> sum = Mat3<Scalar>::Zero();
    bool free = true;
    for (int m = at(c.member_begin, cj); m < at(c.member_begin, cj + 1); ++m) {
      const int i = at(c.member, m);
      if (f.kind[static_cast<std::size_t>(i)] != ConstraintKind::Free) free = false;
      sum += fine_filter(i);
    }
    Eigen::Map<Mat3<Scalar>> projection(c.projection.data() + 9 * static_cast<std::size_t>(cj));
    ConstraintKind& kind = c.kind[static_cast<std::size_t>(cj)];
    if (free) {
      if (kind != ConstraintKind::Free) projection.setIdentity();
      kind = ConstraintKind::Free;
      return;
    }
    Eigen::SelfAdjointEigenSolver<Mat3<Scalar>> eigen;
    eigen.computeDirect(sum);
    projection.setZero();
    int kept = 0;
    for (int k = 0; k < 3; ++k)
      if (eigen.eigenvalues()[k] > Scalar(0.01)) {
        projection.noalias() += eigen.eigenvectors().col(k) * eigen.eigenvectors().col(k).transpose();
        ++kept;
      }
    if (kept == 3) projection.setIdentity();
    kind = kept == 3 ? ConstraintKind::Free : kept == 0 ? ConstraintKind::Fixed : ConstraintKind::Projected;
  });
  if (shared) {
    team_single([&] {
      c.omega = omega;
      c.constrained = f.constrained;
    });
  } else {
    c.omega = omega;
    c.constrained = f.constrained;
  }

  // P_iJ = S_i ([i in J] (1 - omega) I - omega D_F,i^-1 sum_j A_ij) Pi_J over i's strong blocks to
  // members j of J: (I - omega D_F^-1 A_F) T with T_j = S_j, as the filtered A_ij = A_ij S_j.
  team_for_if(shared, fine_rows, [&](int i) {
    const bool row_free = f.kind[static_cast<std::size_t>(i)] == ConstraintKind::Free;
    const Block d_inverse(c.lumped_inverse.data() + 9 * static_cast<std::size_t>(i));
    for (int e = at(c.p_begin, i); e < at(c.p_begin, i + 1); ++e) {
      Mat3<Scalar> sum = Mat3<Scalar>::Zero();
      for (int t = at(c.p_term_begin, e); t < at(c.p_term_begin, e + 1); ++t)
        sum += Block(values + 9 * at(c.p_term_block, t));
      Mat3<Scalar> p = Mat3<Scalar>::Zero();
      if (c.p_term_begin[static_cast<std::size_t>(e)] < c.p_term_begin[static_cast<std::size_t>(e) + 1])
        p.noalias() = -omega * (d_inverse * sum);
      if (c.p_tentative[static_cast<std::size_t>(e)]) p.diagonal().array() += Scalar(1) - omega;
      if (!row_free) p = (fine_filter(i) * p).eval();
      const int cj = at(c.p_column, e);
      const ConstraintKind coarse = c.kind[static_cast<std::size_t>(cj)];
      if (coarse == ConstraintKind::Fixed) p.setZero();
      if (coarse == ConstraintKind::Projected)
        p = (p * Block(c.projection.data() + 9 * static_cast<std::size_t>(cj))).eval();
      Eigen::Map<Mat3<Scalar>>(c.p_value.data() + 9 * static_cast<std::size_t>(e)) = p;
    }
  });
  // P^T's blocks for the restriction, and A P.
  team_for_if(shared, c.rows, [&](int cj) {
    for (int s = at(c.r_begin, cj); s < at(c.r_begin, cj + 1); ++s)
      Eigen::Map<Mat3<Scalar>>(c.r_value.data() + 9 * static_cast<std::size_t>(s)) =
          Block(c.p_value.data() + 9 * static_cast<std::size_t>(at(c.r_block, s))).transpose();
  });
  team_for_if(shared, fine_rows, [&](int i) {
    for (int g = at(c.ap_begin, i); g < at(c.ap_begin, i + 1); ++g) {
      Mat3<Scalar> sum = Mat3<Scalar>::Zero();
      for (int t = at(c.ap_term_begin, g); t < at(c.ap_term_begin, g + 1); ++t)
        sum.noalias() += Block(values + 9 * at(c.ap_term_block, t)) *
                         Block(c.p_value.data() + 9 * static_cast<std::size_t>(at(c.ap_term_p, t)));
      Eigen::Map<Mat3<Scalar>>(c.ap_value.data() + 9 * static_cast<std::size_t>(g)) = sum;
    }
  });
  // A_c = P^T (A P) + I - Pi, the blocks on and above the diagonal summed, the others mirrored.
  Scalar* coarse = c.a.values();
  const int* transposed = c.a.transposed().data();
  team_for_if(shared, static_cast<int>(c.g_upper.size()), [&](int u) {
    Mat3<Scalar> sum = Mat3<Scalar>::Zero();
    for (int t = at(c.g_begin, u); t < at(c.g_begin, u + 1); ++t)
      sum.noalias() += Block(c.p_value.data() + 9 * static_cast<std::size_t>(at(c.g_p, t))).transpose() *
                       Block(c.ap_value.data() + 9 * static_cast<std::size_t>(at(c.g_ap, t)));
    const int ci = at(c.g_row, u), block = at(c.g_upper, u);
    if (block == c.a.diagonal()[static_cast<std::size_t>(ci)] &&
        c.kind[static_cast<std::size_t>(ci)] != ConstraintKind::Free)
      sum += Mat3<Scalar>::Identity() - Block(c.projection.data() + 9 * static_cast<std::size_t>(ci));
    detail::store_coarse_block(sum.data(), block, transposed, coarse);
  });
  return m_failed.load(std::memory_order_relaxed) == 0;
}

template <class Scalar>
void AggregationHierarchy<Scalar>::restrict_to(int l, const Scalar* fine, Scalar* coarse, bool shared) const {
  const Level& c = m_levels[static_cast<std::size_t>(l)];
  const int* begin = c.r_begin.data();
  const int* row = c.r_row.data();
  const Scalar* value = c.r_value.data();
  team_for_if(shared, c.rows, [&](int cj) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int s = begin[cj]; s < begin[cj + 1]; ++s) {
      const std::array<Scalar, 3> t = block_times(value + 9 * static_cast<std::size_t>(s), fine + 3 * row[s]);
      s0 += t[0];
      s1 += t[1];
      s2 += t[2];
    }
    coarse[3 * cj] = s0;
    coarse[3 * cj + 1] = s1;
    coarse[3 * cj + 2] = s2;
  });
}

template <class Scalar>
void AggregationHierarchy<Scalar>::prolong_add(int l, const Scalar* coarse, Scalar* fine, bool shared) const {
  const Level& c = m_levels[static_cast<std::size_t>(l)];
  const int* begin = c.p_begin.data();
  const int* column = c.p_column.data();
  const Scalar* value = c.p_value.data();
  team_for_if(shared, rows(l - 1), [&](int i) {
    Scalar s0 = 0, s1 = 0, s2 = 0;
    for (int e = begin[i]; e < begin[i + 1]; ++e) {
      const std::array<Scalar, 3> t = block_times(value + 9 * static_cast<std::size_t>(e), coarse + 3 * column[e]);
      s0 += t[0];
      s1 += t[1];
      s2 += t[2];
    }
    fine[3 * i] += s0;
    fine[3 * i + 1] += s1;
    fine[3 * i + 2] += s2;
  });
}

}  // namespace drape
