#pragma once
/// \file block_sparse_matrix.hpp
/// Square sparse matrix of 3x3 blocks in block-CSR form with a fixed, structurally symmetric
/// pattern: the storage of the implicit system (one block row per simulated node).
///
/// Block k is stored as 9 contiguous scalars, column-major (an `Eigen::Map<Mat3>`). The pattern is
/// built once; values are overwritten in place every step. Compared with scalar CSR this stores one
/// column index per 9 values, so a mat-vec reads about 2.5x fewer bytes (docs/implicit.md).

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/config.hpp"
#include "drape/core/parallel.hpp"
#include "drape/core/types.hpp"

namespace drape {

template <class Scalar = double>
class BlockSparseMatrix {
 public:
  BlockSparseMatrix() = default;
  /// `columns[r]` lists the block columns of block row r; the pattern must be structurally
  /// symmetric and contain every diagonal block. Columns are sorted and deduplicated here.
  explicit BlockSparseMatrix(std::vector<std::vector<int>> columns);

  int block_rows() const { return static_cast<int>(m_row_begin.size()) - 1; }
  int size() const { return 3 * block_rows(); }
  int block_count() const { return static_cast<int>(m_column.size()); }
  const std::vector<int>& row_begin() const { return m_row_begin; }
  const std::vector<int>& column() const { return m_column; }
  /// Index of the diagonal block of each row.
  const std::vector<int>& diagonal() const { return m_diagonal; }
  /// Index of block (c, r) for block k = (r, c).
  const std::vector<int>& transposed() const { return m_transposed; }
  /// Block index of (r, c), or -1 if not in the pattern.
  int find(int r, int c) const;

  Scalar* values() { return m_values.data(); }
  const Scalar* values() const { return m_values.data(); }
  Eigen::Map<Mat3<Scalar>> block(int k) { return Eigen::Map<Mat3<Scalar>>(m_values.data() + 9 * k); }
  Eigen::Map<const Mat3<Scalar>> block(int k) const { return Eigen::Map<const Mat3<Scalar>>(m_values.data() + 9 * k); }
  /// Zeroes the blocks and invalidates the edge form.
  void set_zero() {
    std::fill(m_values.begin(), m_values.end(), Scalar(0));
    m_edge_valid = false;
  }

  /// Optional second representation of the same matrix, per spring ("edge"):
  /// \f[ A = \mathrm{diag}(m_r) \otimes I_3 + \sum_e \begin{bmatrix} C_e & -C_e \\ -C_e & C_e \end{bmatrix}_{(a_e, b_e)}, \f]
  /// so that \f$ A p = m \circ p + \sum_e \pm C_e (p_{a_e} - p_{b_e}) \f$: one 3x3 product per
  /// spring instead of two per spring in block CSR, and about a third of the bytes. Edge rows are
  /// -1 for eliminated nodes (their p is 0); edges are grouped in colours in which no two share a
  /// row, so threads scatter without races and in a fixed order. Set up once (set_edge_form); the
  /// values are written by JacobianAssembler::assemble_system, which then calls
  /// mark_edge_form_valid(). Each edge's C takes edge_stride() scalars of edge_values(): 9
  /// (column-major) in general, 6 when every C is symmetric (lower triangle row by row:
  /// (0,0) (1,0) (1,1) (2,0) (2,1) (2,2)), a third fewer bytes. Direct solvers use the blocks;
  /// multiply() and PCG use the edge form when it is valid.
  void set_edge_form(std::vector<int> edge_rows, std::vector<int> colour_begin, std::vector<Scalar> row_mass) {
    m_edge_rows = std::move(edge_rows);
    m_edge_colour_begin = std::move(colour_begin);
    m_row_mass = std::move(row_mass);
    m_edge_values.assign(9 * (m_edge_rows.size() / 2), Scalar(0));
    m_edge_valid = false;
  }
  bool edge_form_valid() const { return m_edge_valid; }
  /// Declares the edge values current; `symmetric`: they are stored as 6 per edge.
  void mark_edge_form_valid(bool symmetric) {
    m_edge_valid = !m_edge_rows.empty() || !m_row_mass.empty();
    m_edge_symmetric = symmetric;
  }
  bool edge_form_symmetric() const { return m_edge_symmetric; }
  int edge_stride() const { return m_edge_symmetric ? 6 : 9; }
  int edge_count() const { return static_cast<int>(m_edge_rows.size() / 2); }
  const std::vector<int>& edge_rows() const { return m_edge_rows; }
  const std::vector<int>& edge_colour_begin() const { return m_edge_colour_begin; }
  const std::vector<Scalar>& row_mass() const { return m_row_mass; }
  /// Room for 9 scalars per edge; see edge_stride().
  Scalar* edge_values() { return m_edge_values.data(); }
  const Scalar* edge_values() const { return m_edge_values.data(); }

  /// `y = A x` over `threads` threads (rows split statically; each row summed in pattern order, so
  /// the result does not depend on the thread count). `x`, `y`: size() scalars, not aliased.
  void multiply(const Scalar* x, Scalar* y, int threads = 1) const;

  /// Scalar compressed-column copy of the pattern (allocates; call once), and the map that fills
  /// its values from the blocks: `csc.valuePtr()[e] = values()[map[e]]`.
  template <class Real>
  Eigen::SparseMatrix<Real> scalar_pattern(std::vector<int>& map) const;
  /// Writes the current values into a matrix made by scalar_pattern() (no allocation).
  template <class Real>
  void copy_values(Eigen::SparseMatrix<Real>& csc, const std::vector<int>& map) const;
  /// Dense copy (tests and small diagnostics only).
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> to_dense() const;

 private:
  std::vector<int> m_row_begin{0};
  std::vector<int> m_column;
  std::vector<int> m_diagonal;
  std::vector<int> m_transposed;
  std::vector<Scalar> m_values;
  std::vector<int> m_edge_rows, m_edge_colour_begin;
  std::vector<Scalar> m_row_mass, m_edge_values;
  bool m_edge_valid = false;
  bool m_edge_symmetric = false;
};

namespace detail {
/// `y += sum_e +-C_e (x_a - x_b)` over the edges in colour order (the scatter of the edge form).
/// Symmetric C is stored row by row (c00 c10 c11 c20 c21 c22) so that the first two rows of
/// C d are three 2-vector products (SSE2 for double) and the third a 2-vector dot plus one term.
template <bool Symmetric, class Scalar>
void add_edge_products(const BlockSparseMatrix<Scalar>& a, const Scalar* x, Scalar* y) {
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec2Map = Eigen::Map<Vec2>;
  using ConstVec2Map = Eigen::Map<const Vec2>;
  const int* er = a.edge_rows().data();
  const Scalar* c = a.edge_values();
  const std::vector<int>& colour = a.edge_colour_begin();
  const int colours = static_cast<int>(colour.size()) - 1;
  for (int k = 0; k < colours; ++k) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int e = colour[k]; e < colour[k + 1]; ++e) {
      const int ra = er[2 * e], rb = er[2 * e + 1];
      if constexpr (Symmetric) {
        Vec2 d01 = Vec2::Zero();
        Scalar d2 = 0;
        if (ra >= 0) { d01 = ConstVec2Map(x + 3 * ra); d2 = x[3 * ra + 2]; }
        if (rb >= 0) { d01 -= ConstVec2Map(x + 3 * rb); d2 -= x[3 * rb + 2]; }
        const Scalar* m = c + 6 * e;
        const ConstVec2Map row2(m + 3);  // (c20, c21) = (c02, c12)
        const Vec2 t01 = ConstVec2Map(m) * d01[0] + ConstVec2Map(m + 1) * d01[1] + row2 * d2;
        const Scalar t2 = row2.dot(d01) + m[5] * d2;
        if (ra >= 0) { Vec2Map(y + 3 * ra) += t01; y[3 * ra + 2] += t2; }
        if (rb >= 0) { Vec2Map(y + 3 * rb) -= t01; y[3 * rb + 2] -= t2; }
      } else {
        Scalar d0 = 0, d1 = 0, d2 = 0;
        if (ra >= 0) { d0 = x[3 * ra]; d1 = x[3 * ra + 1]; d2 = x[3 * ra + 2]; }
        if (rb >= 0) { d0 -= x[3 * rb]; d1 -= x[3 * rb + 1]; d2 -= x[3 * rb + 2]; }
        const Scalar* m = c + 9 * e;
        const Scalar t0 = m[0] * d0 + m[3] * d1 + m[6] * d2;
        const Scalar t1 = m[1] * d0 + m[4] * d1 + m[7] * d2;
        const Scalar t2 = m[2] * d0 + m[5] * d1 + m[8] * d2;
        if (ra >= 0) { y[3 * ra] += t0; y[3 * ra + 1] += t1; y[3 * ra + 2] += t2; }
        if (rb >= 0) { y[3 * rb] -= t0; y[3 * rb + 1] -= t1; y[3 * rb + 2] -= t2; }
      }
    }
  }
}

/// `y = A x` through the edge form, for the calling thread's share of a team already running
/// (inside an OpenMP parallel region) or serially. Ends with a barrier (the last `omp for`).
template <class Scalar>
void edge_multiply_in_team(const BlockSparseMatrix<Scalar>& a, const Scalar* x, Scalar* y) {
  const int rows = a.block_rows();
  const Scalar* mass = a.row_mass().data();
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
  for (int r = 0; r < rows; ++r) {
    y[3 * r] = mass[r] * x[3 * r];
    y[3 * r + 1] = mass[r] * x[3 * r + 1];
    y[3 * r + 2] = mass[r] * x[3 * r + 2];
  }
  if (a.edge_form_symmetric())
    add_edge_products<true>(a, x, y);
  else
    add_edge_products<false>(a, x, y);
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------

template <class Scalar>
BlockSparseMatrix<Scalar>::BlockSparseMatrix(std::vector<std::vector<int>> columns) {
  const int rows = static_cast<int>(columns.size());
  m_row_begin.assign(1, 0);
  m_row_begin.reserve(static_cast<std::size_t>(rows) + 1);
  for (int r = 0; r < rows; ++r) {
    std::vector<int>& c = columns[static_cast<std::size_t>(r)];
    c.push_back(r);
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    m_column.insert(m_column.end(), c.begin(), c.end());
    m_row_begin.push_back(static_cast<int>(m_column.size()));
  }
  m_diagonal.resize(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) m_diagonal[static_cast<std::size_t>(r)] = find(r, r);
  m_transposed.resize(m_column.size());
  for (int r = 0; r < rows; ++r)
    for (int k = m_row_begin[r]; k < m_row_begin[r + 1]; ++k) {
      const int t = find(m_column[k], r);
      DRAPE_ASSERT(t >= 0, "BlockSparseMatrix: pattern must be structurally symmetric");
      m_transposed[static_cast<std::size_t>(k)] = t;
    }
  m_values.assign(9 * m_column.size(), Scalar(0));
}

template <class Scalar>
int BlockSparseMatrix<Scalar>::find(int r, int c) const {
  const auto first = m_column.begin() + m_row_begin[r];
  const auto last = m_column.begin() + m_row_begin[r + 1];
  const auto it = std::lower_bound(first, last, c);
  return it != last && *it == c ? static_cast<int>(it - m_column.begin()) : -1;
}

template <class Scalar>
void BlockSparseMatrix<Scalar>::multiply(const Scalar* x, Scalar* y, int threads) const {
  if (m_edge_valid) {
#if defined(_OPENMP)
    if (threads > 1) {
#pragma omp parallel num_threads(threads)
      detail::edge_multiply_in_team(*this, x, y);
      return;
    }
#endif
    detail::edge_multiply_in_team(*this, x, y);
    return;
  }
  const int rows = block_rows();
  const int* rb = m_row_begin.data();
  const int* col = m_column.data();
  const Scalar* val = m_values.data();
  const auto row = [&](int r) {
    Scalar y0 = 0, y1 = 0, y2 = 0;
    for (int k = rb[r]; k < rb[r + 1]; ++k) {
      const Scalar* b = val + 9 * k;
      const Scalar* xc = x + 3 * col[k];
      y0 += b[0] * xc[0] + b[3] * xc[1] + b[6] * xc[2];
      y1 += b[1] * xc[0] + b[4] * xc[1] + b[7] * xc[2];
      y2 += b[2] * xc[0] + b[5] * xc[1] + b[8] * xc[2];
    }
    y[3 * r] = y0;
    y[3 * r + 1] = y1;
    y[3 * r + 2] = y2;
  };
#if defined(_OPENMP)
  if (threads > 1) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int r = 0; r < rows; ++r) row(r);
    return;
  }
#endif
  (void)threads;
  for (int r = 0; r < rows; ++r) row(r);
}

template <class Scalar>
template <class Real>
Eigen::SparseMatrix<Real> BlockSparseMatrix<Scalar>::scalar_pattern(std::vector<int>& map) const {
  const int rows = block_rows();
  std::vector<int> outer(static_cast<std::size_t>(size()) + 1, 0);
  std::vector<int> inner;
  map.clear();
  inner.reserve(9 * m_column.size());
  map.reserve(9 * m_column.size());
  // Column 3c+j holds the blocks (r, c) for r in the columns of row c (symmetric pattern), sorted.
  for (int c = 0; c < rows; ++c)
    for (int j = 0; j < 3; ++j) {
      for (int k = m_row_begin[c]; k < m_row_begin[c + 1]; ++k) {
        const int r = m_column[k];
        const int kt = m_transposed[static_cast<std::size_t>(k)];  // block (r, c)
        for (int i = 0; i < 3; ++i) {
          inner.push_back(3 * r + i);
          map.push_back(9 * kt + i + 3 * j);
        }
      }
      outer[static_cast<std::size_t>(3 * c + j + 1)] = static_cast<int>(inner.size());
    }
  const std::vector<Real> zeros(inner.size(), Real(0));
  const Eigen::Map<const Eigen::SparseMatrix<Real>> view(size(), size(), static_cast<Index>(inner.size()), outer.data(),
                                                         inner.data(), zeros.data());
  Eigen::SparseMatrix<Real> csc = view;
  csc.makeCompressed();
  return csc;
}

template <class Scalar>
template <class Real>
void BlockSparseMatrix<Scalar>::copy_values(Eigen::SparseMatrix<Real>& csc, const std::vector<int>& map) const {
  Real* out = csc.valuePtr();
  const Scalar* in = m_values.data();
  const std::size_t n = map.size();
  for (std::size_t e = 0; e < n; ++e) out[e] = static_cast<Real>(in[map[e]]);
}

template <class Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> BlockSparseMatrix<Scalar>::to_dense() const {
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> d = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>::Zero(size(), size());
  for (int r = 0; r < block_rows(); ++r)
    for (int k = m_row_begin[r]; k < m_row_begin[r + 1]; ++k) d.template block<3, 3>(3 * r, 3 * m_column[k]) = block(k);
  return d;
}

}  // namespace drape
