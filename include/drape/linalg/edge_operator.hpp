#pragma once
/// \file edge_operator.hpp
/// A second form of a system matrix whose off-diagonal coupling comes in pairs of rows ("edges",
/// e.g. the springs of a cloth):
/// \f[ A = \mathrm{diag}(m_r) \otimes I_3 + \mathrm{blockdiag}(B_r)
///        + \sum_e \begin{bmatrix} C_e & -C_e \\ -C_e & C_e \end{bmatrix}_{(a_e, b_e)}, \f]
/// so that \f$ A p = m \circ p + B p + \sum_e \pm C_e (p_{a_e} - p_{b_e}) \f$: one 3x3 product per edge
/// instead of two per edge in block CSR, and about a third of the bytes. Solvers use it for the
/// product when it is valid; on a team it costs a barrier per colour, which the halved work pays
/// for (measured).
///
/// - Structure (set once): the two block rows of every edge (-1 for an end that is not in the
///   system: its unknowns are zero), the edges grouped in colours in which no two edges share a row
///   (so threads scatter without races and in a fixed order), the diagonal `m_r` of every row.
///   Each group of four edges has a shape (GroupShape, group_count()) that tells the AVX2 product
///   how to reach its rows: `Consecutive` (first rows consecutive, and so are the second rows: a
///   cloth's springs along j, core/spring_set.hpp), `AdjacentPairs` (the four edges join rows
///   a, a+1; a+2, a+3; ... of one window of eight: structural springs along i) and `TwoApartPairs`
///   (rows a, a+2; a+1, a+3; a+4, a+6; a+5, a+7: bend springs along i) load and store whole vectors
///   of the window; `Gathered` groups are read and written row by row. The AVX2 product (symmetric
///   blocks) holds the four edges in 256-bit vectors for double and 128-bit ones for float: the
///   same steps on half the bytes.
/// - Values (written by whoever assembles the system, e.g. JacobianAssembler): each edge's \f$ C_e \f$
///   takes stride() scalars: 9 (column-major) in general, 6 when every \f$ C_e \f$ is symmetric
///   (lower triangle row by row, block3.hpp), a third fewer bytes. values() keeps the edges in
///   groups of `group` = 4, value k of the group's edges side by side (value_index()), so a vector
///   instruction loads one value of four edges at once. Optionally a 3x3 block
///   \f$ B_r \f$ per row (9 values, column-major; room made by enable_row_blocks()), for terms whose
///   blocks lie on the diagonal (air drag). The writer then calls set_valid(); anything that
///   changes the matrix otherwise must invalidate() it. When every \f$ B_r \f$ is a multiple
///   \f$ s_r I \f$ of the identity (linear drag), set_valid() folds them into the diagonal,
///   \f$ (m_r + s_r) \f$, and the product is as cheap as without them.

#include <algorithm>
#include <array>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "drape/core/types.hpp"
#include "drape/linalg/block3.hpp"
#include "drape/linalg/detail/edge_operator_avx2.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"

namespace drape {

/// How the rows of a group of four edges lie (see the file comment).
enum class GroupShape : char { Gathered = 0, Consecutive = 1, AdjacentPairs = 2, TwoApartPairs = 3 };

template <class Scalar = double>
class EdgeOperator {
 public:
  EdgeOperator() = default;
  /// `edge_rows`: rows a_e, b_e of edge e at [2e], [2e + 1]; `colour_begin`: colour c holds edges
  /// [colour_begin[c], colour_begin[c + 1]); `row_mass`: m_r of every row.
  EdgeOperator(std::vector<int> edge_rows, std::vector<int> colour_begin, std::vector<Scalar> row_mass)
      : m_edge_rows(std::move(edge_rows)),
        m_colour_begin(std::move(colour_begin)),
        m_row_mass(std::move(row_mass)),
        m_component_mass(per_component(m_row_mass)),
        m_values(9 * padded(m_edge_rows.size() / 2), Scalar(0)),
        m_group_shape(find_group_shapes(m_edge_rows)) {}

  /// Edges per group of values() (see value_index()).
  static constexpr int group = 4;
  /// Where value k (< stride) of edge e lies in values(), for `stride` values per edge.
  static std::size_t value_index(int e, int k, int stride) {
    return std::size_t(e / group) * std::size_t(group * stride) + std::size_t(group * k + e % group);
  }

  int rows() const { return static_cast<int>(m_row_mass.size()); }
  int edge_count() const { return static_cast<int>(m_edge_rows.size() / 2); }
  const std::vector<int>& edge_rows() const { return m_edge_rows; }
  const std::vector<int>& colour_begin() const { return m_colour_begin; }
  const std::vector<Scalar>& row_mass() const { return m_row_mass; }
  /// Groups of four edges (edges [4g, 4g + 4)) of the given shape (see the file comment).
  int group_count(GroupShape shape) const {
    return static_cast<int>(std::count(m_group_shape.begin(), m_group_shape.end(), shape));
  }

  /// True if the values describe the current matrix (see the file comment).
  bool valid() const { return m_valid; }
  /// True if every C_e is stored as 6 values (symmetric).
  bool symmetric() const { return m_symmetric; }
  /// Scalars per edge in values(): 6 or 9.
  int stride() const { return m_symmetric ? 6 : 9; }
  /// Room for 9 scalars per edge, grouped (value_index()); see stride().
  Scalar* values() { return m_values.data(); }
  const Scalar* values() const { return m_values.data(); }
  /// Scalars in values().
  std::size_t value_count() const { return m_values.size(); }
  /// Makes room for the row blocks B_r (zero); they count once set_valid() says so.
  void enable_row_blocks() {
    m_row_blocks.assign(9 * m_row_mass.size(), Scalar(0));
    m_row_diagonal = m_row_mass;
  }
  /// B_r of every row (9 values each), empty unless enable_row_blocks() was called.
  Scalar* row_blocks() { return m_row_blocks.data(); }
  const Scalar* row_blocks() const { return m_row_blocks.data(); }
  /// True if enable_row_blocks() made room for the row blocks.
  bool has_row_blocks() const { return !m_row_blocks.empty(); }
  /// True if the product includes the row blocks as 3x3 blocks.
  bool uses_row_blocks() const { return m_use_row_blocks; }
  /// True if the row blocks, all multiples of I, are folded into the diagonal m_r + s_r.
  bool uses_row_diagonal() const { return m_use_row_diagonal; }

  /// Declares the values current; `symmetric`: they are stored as 6 per edge; `row_blocks`: the
  /// row blocks are part of A (they must have been enabled). An operator without structure never
  /// becomes valid.
  void set_valid(bool symmetric, bool row_blocks = false) {
    m_valid = !m_edge_rows.empty() || !m_row_mass.empty();
    m_symmetric = symmetric;
    m_use_row_blocks = row_blocks && !m_row_blocks.empty();
    m_use_row_diagonal = m_use_row_blocks && fold_isotropic_row_blocks();
    if (m_use_row_diagonal) m_use_row_blocks = false;
  }
  void invalidate() { m_valid = false; }

  /// `y = A x` over `threads` threads; the result does not depend on the thread count.
  void multiply(const Scalar* x, Scalar* y, int threads = 1) const {
    run_in_team(threads, [&] { multiply_in_team(x, y); });
  }
  /// multiply() for the calling thread's share of a team already running (or serially); the team
  /// waits at the end.
  void multiply_in_team(const Scalar* x, Scalar* y) const;

 private:
  static std::size_t padded(std::size_t edges) { return (edges + group - 1) / group * group; }
  /// Every row's value three times, once per component: the diagonal pass then runs over 3n
  /// values in one vectorised loop instead of row by row.
  static std::vector<Scalar> per_component(const std::vector<Scalar>& row_values) {
    std::vector<Scalar> out(3 * row_values.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = row_values[i / 3];
    return out;
  }
  /// The shape of every whole group of four edges.
  static std::vector<GroupShape> find_group_shapes(const std::vector<int>& edge_rows);
  /// `y += sum_e +-C_e (x_a - x_b)` over the edges in colour order.
  template <bool Symmetric>
  void add_edge_products(const Scalar* x, Scalar* y) const;
  /// `y += +-C_e (x_a - x_b)` for the edges [begin, end) one by one.
  template <bool Symmetric>
  DRAPE_INLINE_LOOP void add_edge_range(const Scalar* x, Scalar* y, int begin, int end) const;
#if DRAPE_AVX2_DISPATCH
  /// add_edge_products for symmetric blocks with AVX2, Scalar double (four edges of a colour per
  /// step in 256-bit vectors) or float (in 128-bit ones, the same steps).
  __attribute__((target("avx2"))) void add_symmetric_edge_products_avx2(const Scalar* x, Scalar* y) const;
#endif
  /// If every B_r is s_r I, writes m_r + s_r to m_row_diagonal and returns true.
  bool fold_isotropic_row_blocks();

  std::vector<int> m_edge_rows, m_colour_begin;
  std::vector<Scalar> m_row_mass, m_component_mass, m_values, m_row_blocks, m_row_diagonal, m_component_diagonal;
  std::vector<GroupShape> m_group_shape;
  bool m_valid = false;
  bool m_symmetric = false;
  bool m_use_row_blocks = false;
  bool m_use_row_diagonal = false;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
std::vector<GroupShape> EdgeOperator<Scalar>::find_group_shapes(const std::vector<int>& edge_rows) {
  const int edges = static_cast<int>(edge_rows.size() / 2);
  std::vector<GroupShape> shapes(static_cast<std::size_t>(edges / group), GroupShape::Gathered);
  constexpr int two_apart_offset[group] = {0, 1, 4, 5};
  for (int g = 0; g < edges / group; ++g) {
    const int* rows = edge_rows.data() + 2 * group * g;
    const int a = rows[0];
    bool consecutive = a >= 0 && rows[1] >= 0, adjacent = a >= 0, two_apart = a >= 0;
    for (int k = 0; k < group; ++k) {
      consecutive = consecutive && rows[2 * k] == a + k && rows[2 * k + 1] == rows[1] + k;
      adjacent = adjacent && rows[2 * k] == a + 2 * k && rows[2 * k + 1] == a + 2 * k + 1;
      two_apart = two_apart && rows[2 * k] == a + two_apart_offset[k] && rows[2 * k + 1] == a + two_apart_offset[k] + 2;
    }
    shapes[static_cast<std::size_t>(g)] = consecutive  ? GroupShape::Consecutive
                                          : adjacent   ? GroupShape::AdjacentPairs
                                          : two_apart  ? GroupShape::TwoApartPairs
                                                       : GroupShape::Gathered;
  }
  return shapes;
}

template <class Scalar>
bool EdgeOperator<Scalar>::fold_isotropic_row_blocks() {
  const Scalar* b = m_row_blocks.data();
  for (int r = 0; r < rows(); ++r, b += 9)
    if (b[1] != 0 || b[2] != 0 || b[3] != 0 || b[5] != 0 || b[6] != 0 || b[7] != 0 || b[4] != b[0] || b[8] != b[0])
      return false;
  for (std::size_t r = 0; r < m_row_mass.size(); ++r) m_row_diagonal[r] = m_row_mass[r] + m_row_blocks[9 * r];
  m_component_diagonal.resize(3 * m_row_diagonal.size());
  for (std::size_t i = 0; i < m_component_diagonal.size(); ++i) m_component_diagonal[i] = m_row_diagonal[i / 3];
  return true;
}

template <class Scalar>
void EdgeOperator<Scalar>::multiply_in_team(const Scalar* x, Scalar* y) const {
  const Scalar* mass = m_use_row_diagonal ? m_row_diagonal.data() : m_row_mass.data();
  if (m_use_row_blocks) {
    const Scalar* b = m_row_blocks.data();
    team_for(rows(), [&](int r) {
      const std::array<Scalar, 3> t = block_times(b + 9 * r, x + 3 * r);
      y[3 * r] = mass[r] * x[3 * r] + t[0];
      y[3 * r + 1] = mass[r] * x[3 * r + 1] + t[1];
      y[3 * r + 2] = mass[r] * x[3 * r + 2] + t[2];
    });
  } else {
    const Scalar* diagonal = m_use_row_diagonal ? m_component_diagonal.data() : m_component_mass.data();
    const auto share = even_share(3LL * rows(), team_rank(), team_size());
    DRAPE_OMP_SIMD
    for (long long i = share.first; i < share.second; ++i) y[i] = diagonal[i] * x[i];
    team_barrier();
  }
  if (m_symmetric)
    add_edge_products<true>(x, y);
  else
    add_edge_products<false>(x, y);
}

template <class Scalar>
template <bool Symmetric>
void EdgeOperator<Scalar>::add_edge_products(const Scalar* x, Scalar* y) const {
#if DRAPE_AVX2_DISPATCH
  if constexpr (Symmetric && (std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>)) {
    if (instruction_set() == InstructionSet::Avx2) {
      add_symmetric_edge_products_avx2(x, y);
      return;
    }
  }
#endif
  const int colours = static_cast<int>(m_colour_begin.size()) - 1;
  for (int k = 0; k < colours; ++k) {
    const auto share = even_share(m_colour_begin[k + 1] - m_colour_begin[k], team_rank(), team_size());
    add_edge_range<Symmetric>(x, y, m_colour_begin[k] + int(share.first), m_colour_begin[k] + int(share.second));
    team_barrier();
  }
}

// One line per row of each 3x3 update: it reads as the math.
// clang-format off
template <class Scalar>
template <bool Symmetric>
DRAPE_INLINE_LOOP void EdgeOperator<Scalar>::add_edge_range(const Scalar* x, Scalar* y, int begin, int end) const {
  // Symmetric C is stored row by row (c00 c10 c11 c20 c21 c22), so the first two rows of C d are
  // three 2-vector products (SSE2 for double) and the third a 2-vector dot plus one term; each row
  // sums (c_i0 d0 + c_i1 d1) + c_i2 d2, like block3.hpp and the AVX2 version.
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec2Map = Eigen::Map<Vec2>;
  using ConstVec2Map = Eigen::Map<const Vec2>;
  constexpr int stride = Symmetric ? 6 : 9;
  const int* er = m_edge_rows.data();
  for (int e = begin; e < end; ++e) {
    const int ra = er[2 * e], rb = er[2 * e + 1];
    const Scalar* c = m_values.data() + value_index(e, 0, stride);  // value k at c[group * k]
    if constexpr (Symmetric) {
      Vec2 d01 = Vec2::Zero();
      Scalar d2 = 0;
      if (ra >= 0) { d01 = ConstVec2Map(x + 3 * ra); d2 = x[3 * ra + 2]; }
      if (rb >= 0) { d01 -= ConstVec2Map(x + 3 * rb); d2 -= x[3 * rb + 2]; }
      // Built from scalars, not mapped from a local copy: an unaligned load across two stores
      // stalls on store forwarding (measured: 2x slower).
      const Vec2 col0(c[0], c[group]), col1(c[group], c[2 * group]);
      const Vec2 row2(c[3 * group], c[4 * group]);  // (c20, c21) = (c02, c12)
      const Vec2 t01 = col0 * d01[0] + col1 * d01[1] + row2 * d2;
      const Scalar t2 = row2.dot(d01) + c[5 * group] * d2;
      if (ra >= 0) { Vec2Map(y + 3 * ra) += t01; y[3 * ra + 2] += t2; }
      if (rb >= 0) { Vec2Map(y + 3 * rb) -= t01; y[3 * rb + 2] -= t2; }
    } else {
      Scalar d[3] = {0, 0, 0};
      if (ra >= 0) { d[0] = x[3 * ra]; d[1] = x[3 * ra + 1]; d[2] = x[3 * ra + 2]; }
      if (rb >= 0) { d[0] -= x[3 * rb]; d[1] -= x[3 * rb + 1]; d[2] -= x[3 * rb + 2]; }
      Scalar m[9];
      for (int k = 0; k < 9; ++k) m[k] = c[group * k];
      const std::array<Scalar, 3> t = block_times(m, d);
      if (ra >= 0) { y[3 * ra] += t[0]; y[3 * ra + 1] += t[1]; y[3 * ra + 2] += t[2]; }
      if (rb >= 0) { y[3 * rb] -= t[0]; y[3 * rb + 1] -= t[1]; y[3 * rb + 2] -= t[2]; }
    }
  }
}
// clang-format on

#if DRAPE_AVX2_DISPATCH
// The vector version does the scalar one's operations in the same order (no fused multiply-add),
// so both give the same bits. The loads and stores of each group shape are edge_operator_avx2.hpp's,
// for the lanes of each scalar type; the arithmetic is row_avx2.hpp's.
template <class Scalar>
__attribute__((target("avx2"))) void EdgeOperator<Scalar>::add_symmetric_edge_products_avx2(const Scalar* x,
                                                                                            Scalar* y) const {
  using Lanes = typename detail::Lanes4Avx2<Scalar>::type;  // the four edges of a group
  using detail::add_avx2;
  using detail::load4_avx2;
  using detail::mul_avx2;
  const int* er = m_edge_rows.data();
  const GroupShape* shapes = m_group_shape.data();
  const int colours = static_cast<int>(m_colour_begin.size()) - 1;
  for (int k = 0; k < colours; ++k) {
    const auto share = even_share(m_colour_begin[k + 1] - m_colour_begin[k], team_rank(), team_size());
    const int begin = m_colour_begin[k] + int(share.first), end = m_colour_begin[k] + int(share.second);
    // Whole groups [first_group, end_group), the edges before and after them one by one.
    const int first_group = (begin + group - 1) / group, end_group = end / group;
    const int head_end = std::min(end, first_group * group), tail_begin = std::max(head_end, end_group * group);
    add_edge_range<true>(x, y, begin, head_end);
    for (int g = first_group; g < end_group; ++g) {
      const int* rows = er + 2 * group * g;
      const GroupShape shape = shapes[g];
      // d = x_a - x_b of the four edges, one vector per component.
      Lanes dx, dy, dz;
      if (shape == GroupShape::Consecutive) {
        detail::load_consecutive_differences_avx2(x, rows[0], rows[1], dx, dy, dz);
      } else if (shape == GroupShape::AdjacentPairs) {
        detail::load_adjacent_pair_differences_avx2(x, rows[0], dx, dy, dz);
      } else if (shape == GroupShape::TwoApartPairs) {
        detail::load_two_apart_differences_avx2(x, rows[0], dx, dy, dz);
      } else {
        detail::load_gathered_differences_avx2(x, rows, dx, dy, dz);
      }
      // The group's 24 values, value k of the four edges in the k-th vector (value_index(4 g, k, 6)).
      // Unaligned loads: a std::vector is only 16-byte aligned (an aligned load would fault).
      const Scalar* c = m_values.data() + std::size_t(6 * group) * std::size_t(g);
      const Lanes c0 = load4_avx2(c), c1 = load4_avx2(c + 4), c2 = load4_avx2(c + 8);
      const Lanes c3 = load4_avx2(c + 12), c4 = load4_avx2(c + 16), c5 = load4_avx2(c + 20);
      const Lanes tx = add_avx2(add_avx2(mul_avx2(c0, dx), mul_avx2(c1, dy)), mul_avx2(c3, dz));
      const Lanes ty = add_avx2(add_avx2(mul_avx2(c1, dx), mul_avx2(c2, dy)), mul_avx2(c4, dz));
      const Lanes tz = add_avx2(add_avx2(mul_avx2(c3, dx), mul_avx2(c4, dy)), mul_avx2(c5, dz));
      if (shape == GroupShape::Consecutive) {
        detail::update_consecutive_rows_avx2(y, rows[0], rows[1], tx, ty, tz);
      } else if (shape == GroupShape::AdjacentPairs) {
        detail::update_adjacent_pairs_avx2(y, rows[0], tx, ty, tz);
      } else if (shape == GroupShape::TwoApartPairs) {
        detail::update_two_apart_pairs_avx2(y, rows[0], tx, ty, tz);
      } else {
        detail::update_gathered_rows_avx2(y, rows, tx, ty, tz);
      }
    }
    add_edge_range<true>(x, y, tail_begin, end);
    team_barrier();
  }
}
#endif

}  // namespace drape
