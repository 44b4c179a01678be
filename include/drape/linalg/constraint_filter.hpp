#pragma once
/// \file constraint_filter.hpp
/// Velocity constraints on the unknowns of a linear system, per block row (Baraff & Witkin 1998,
/// section 5.3): the solution \f$ x_r \f$ of a constrained row may only move in the directions
/// \f$ S_r \f$ lets through and takes the prescribed value \f$ z_r \f$ in the others,
/// \f[ x_r = S_r\, y_r + z_r, \qquad S_r z_r = 0, \f]
/// with \f$ S_r \f$ a symmetric projection: \f$ 0 \f$ for a fixed row (a pinned node),
/// \f$ I - n n^T \f$ for a node held on a surface with normal \f$ n \f$, \f$ I - n_1 n_1^T - n_2 n_2^T \f$
/// for two surfaces. An iterative solver filters its residual and search directions with
/// \f$ S \f$ and starts from \f$ S x + z \f$ (pcg.hpp); a row that is not constrained is free
/// (\f$ S_r = I, z_r = 0 \f$). A filter with no constrained row costs the solvers nothing.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/linalg/block3.hpp"

namespace drape {

enum class ConstraintKind : std::uint8_t {
  Free = 0,       ///< S = I, z = 0
  Fixed = 1,      ///< S = 0: the row's unknowns are z
  Projected = 2,  ///< a general projection S and value z
};

template <class Scalar = double>
class ConstraintFilter {
 public:
  ConstraintFilter() = default;
  /// `rows` block rows, all free.
  explicit ConstraintFilter(int rows)
      : m_kind(static_cast<std::size_t>(rows), ConstraintKind::Free),
        m_filter(9 * static_cast<std::size_t>(rows), Scalar(0)),
        m_value(3 * static_cast<std::size_t>(rows), Scalar(0)) {}

  int rows() const { return static_cast<int>(m_kind.size()); }
  /// True if no row is constrained.
  bool empty() const { return m_constrained == 0; }
  int constrained_rows() const { return m_constrained; }
  ConstraintKind kind(int row) const { return m_kind[static_cast<std::size_t>(row)]; }
  const ConstraintKind* kinds() const { return m_kind.data(); }

  /// Row `row`'s unknowns are `value` (a pinned node: 0).
  void fix(int row, const Vec3<Scalar>& value = Vec3<Scalar>::Zero()) {
    set(row, ConstraintKind::Fixed, Mat3<Scalar>::Zero(), value);
  }
  /// Row `row`'s unknowns move only along the symmetric projection `filter` and equal `value` in
  /// the directions it removes. \throws InvalidParameter unless `filter` is a symmetric projection
  /// (S = S^T = S^2 to 1e-6) and S value = 0.
  void constrain(int row, const Mat3<Scalar>& filter, const Vec3<Scalar>& value) {
    const Scalar scale = Scalar(1e-6);
    if (!((filter - filter.transpose()).cwiseAbs().maxCoeff() <= scale &&
          (filter * filter - filter).cwiseAbs().maxCoeff() <= scale))
      detail::fail_argument("constraint filter", "a matrix that is not a symmetric projection",
                            "S = S^T = S^2 (e.g. I - n n^T with |n| = 1)");
    if (!((filter * value).cwiseAbs().maxCoeff() <= scale * std::max(Scalar(1), value.cwiseAbs().maxCoeff())))
      detail::fail_argument("constraint value", "a value with a free component", "S value = 0");
    set(row, ConstraintKind::Projected, filter, value);
  }
  /// Row `row` becomes free.
  void release(int row) { set(row, ConstraintKind::Free, Mat3<Scalar>::Identity(), Vec3<Scalar>::Zero()); }
  /// Every prescribed value becomes 0, the filters stay (Newton corrections of a solution that
  /// already meets the constraints).
  void zero_values() { std::fill(m_value.begin(), m_value.end(), Scalar(0)); }
  /// Every row becomes free.
  void clear() {
    for (int r = 0; r < rows(); ++r)
      if (kind(r) != ConstraintKind::Free) release(r);
  }

  /// \f$ v_r \leftarrow S_r v_r \f$ for one row (`v` points at its 3 values).
  void project_row(int row, Scalar* v) const {
    switch (kind(row)) {
      case ConstraintKind::Free: return;
      case ConstraintKind::Fixed: v[0] = v[1] = v[2] = Scalar(0); return;
      case ConstraintKind::Projected: {
        const std::array<Scalar, 3> t = block_times(m_filter.data() + 9 * static_cast<std::size_t>(row), v);
        v[0] = t[0];
        v[1] = t[1];
        v[2] = t[2];
        return;
      }
    }
  }
  /// \f$ x_r \leftarrow S_r x_r + z_r \f$ for one row: the closest start that meets the constraint.
  void impose_row(int row, Scalar* x) const {
    if (kind(row) == ConstraintKind::Free) return;
    project_row(row, x);
    const Scalar* z = m_value.data() + 3 * static_cast<std::size_t>(row);
    x[0] += z[0];
    x[1] += z[1];
    x[2] += z[2];
  }
  /// project_row() on every row of `v` (3 * rows() scalars).
  void project(Scalar* v) const {
    if (empty()) return;
    for (int r = 0; r < rows(); ++r) project_row(r, v + 3 * r);
  }
  /// impose_row() on every row of `x`.
  void impose(Scalar* x) const {
    if (empty()) return;
    for (int r = 0; r < rows(); ++r) impose_row(r, x + 3 * r);
  }
  /// This filter becomes `other`, its values rounded to Scalar (the single-precision copy a
  /// mixed-precision preconditioner works with). Only rows constrained in either are copied; no
  /// allocation once the row counts match.
  template <class Other>
  void assign(const ConstraintFilter<Other>& other) {
    if (rows() != other.rows()) *this = ConstraintFilter(other.rows());
    for (int r = 0; r < rows(); ++r) {
      const std::size_t i = static_cast<std::size_t>(r);
      if (m_kind[i] == ConstraintKind::Free && other.m_kind[i] == ConstraintKind::Free) continue;
      m_kind[i] = other.m_kind[i];
      for (std::size_t q = 0; q < 9; ++q) m_filter[9 * i + q] = Scalar(other.m_filter[9 * i + q]);
      for (std::size_t q = 0; q < 3; ++q) m_value[3 * i + q] = Scalar(other.m_value[3 * i + q]);
    }
    m_constrained = other.m_constrained;
  }

  /// \f$ S_r \f$ (column-major) and \f$ z_r \f$ of a row.
  Mat3<Scalar> filter(int row) const {
    if (kind(row) == ConstraintKind::Free) return Mat3<Scalar>::Identity();
    return Eigen::Map<const Mat3<Scalar>>(m_filter.data() + 9 * static_cast<std::size_t>(row));
  }
  Vec3<Scalar> value(int row) const {
    return Eigen::Map<const Vec3<Scalar>>(m_value.data() + 3 * static_cast<std::size_t>(row));
  }

 private:
  void set(int row, ConstraintKind kind, const Mat3<Scalar>& filter, const Vec3<Scalar>& value) {
    if (row < 0 || row >= rows())
      detail::fail_argument("constrained row", detail::to_text(row), "[0, " + detail::to_text(rows() - 1) + "]");
    ConstraintKind& k = m_kind[static_cast<std::size_t>(row)];
    m_constrained += (kind != ConstraintKind::Free) - (k != ConstraintKind::Free);
    k = kind;
    Eigen::Map<Mat3<Scalar>>(m_filter.data() + 9 * static_cast<std::size_t>(row)) = filter;
    Eigen::Map<Vec3<Scalar>>(m_value.data() + 3 * static_cast<std::size_t>(row)) = value;
  }

  template <class>
  friend class ConstraintFilter;

  std::vector<ConstraintKind> m_kind;
  std::vector<Scalar> m_filter;  // 9 per row, column-major
  std::vector<Scalar> m_value;   // 3 per row
  int m_constrained = 0;
};

}  // namespace drape
