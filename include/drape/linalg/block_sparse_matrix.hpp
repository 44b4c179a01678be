#pragma once
/// \file block_sparse_matrix.hpp
/// Square sparse matrix of 3x3 blocks in block-CSR form with a fixed, structurally symmetric
/// pattern: the storage of the implicit system (one block row per simulated node).
///
/// Block k is stored as 9 contiguous scalars, column-major (an `Eigen::Map<Mat3>`, block3.hpp).
/// The pattern is built once; values are overwritten in place every step. Compared with scalar CSR
/// this stores one column index per 9 values, so a mat-vec reads about 2.5x fewer bytes
/// (drape's implicit.md).

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <Eigen/SparseCore>

#include "drape/config.hpp"
#include "drape/core/types.hpp"
#include "drape/linalg/block3.hpp"
#include "drape/linalg/detail/block_sparse_matrix_avx2.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"

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
  void set_zero() { std::fill(m_values.begin(), m_values.end(), Scalar(0)); }

  /// `y = A x` over `threads` threads (rows split statically; each row summed in pattern order, so
  /// the result does not depend on the thread count). `x`, `y`: size() scalars, not aliased.
  void multiply(const Scalar* x, Scalar* y, int threads = 1) const;
  /// multiply() for the calling thread's share of the rows of a team already running (or all rows,
  /// serially); the team waits at the end.
  void multiply_rows_in_team(const Scalar* x, Scalar* y) const;
  /// `r = b - A x` on the block rows [begin, end), each row summed in pattern order: an AVX2
  /// version when the CPU has it, with the same bits (instruction_set.hpp).
  void residual_rows(const Scalar* b, const Scalar* x, Scalar* r, int begin, int end) const;

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
};

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
void BlockSparseMatrix<Scalar>::multiply_rows_in_team(const Scalar* x, Scalar* y) const {
  const int* rb = m_row_begin.data();
  const int* col = m_column.data();
  const Scalar* val = m_values.data();
  team_for(block_rows(), [&](int r) {
    Scalar y0 = 0, y1 = 0, y2 = 0;
    for (int k = rb[r]; k < rb[r + 1]; ++k) {
      const std::array<Scalar, 3> t = block_times(val + 9 * k, x + 3 * col[k]);
      y0 += t[0];
      y1 += t[1];
      y2 += t[2];
    }
    y[3 * r] = y0;
    y[3 * r + 1] = y1;
    y[3 * r + 2] = y2;
  });
}

template <class Scalar>
void BlockSparseMatrix<Scalar>::residual_rows(const Scalar* b, const Scalar* x, Scalar* r, int begin, int end) const {
  const int* rb = m_row_begin.data();
  const int* col = m_column.data();
  const Scalar* val = m_values.data();
#if DRAPE_AVX2_DISPATCH
  if constexpr (std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>) {
    if (instruction_set() == InstructionSet::Avx2) {
      detail::block_residual_rows_avx2(rb, col, val, b, x, r, begin, end);
      return;
    }
  }
#endif
  for (int row = begin; row < end; ++row) {
    Scalar y0 = b[3 * row], y1 = b[3 * row + 1], y2 = b[3 * row + 2];
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const std::array<Scalar, 3> t = block_times(val + 9 * k, x + 3 * col[k]);
      y0 -= t[0];
      y1 -= t[1];
      y2 -= t[2];
    }
    r[3 * row] = y0;
    r[3 * row + 1] = y1;
    r[3 * row + 2] = y2;
  }
}

template <class Scalar>
void BlockSparseMatrix<Scalar>::multiply(const Scalar* x, Scalar* y, int threads) const {
  run_in_team(threads, [&] { multiply_rows_in_team(x, y); });
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
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> d =
      Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>::Zero(size(), size());
  for (int r = 0; r < block_rows(); ++r)
    for (int k = m_row_begin[r]; k < m_row_begin[r + 1]; ++k) d.template block<3, 3>(3 * r, 3 * m_column[k]) = block(k);
  return d;
}

}  // namespace drape
