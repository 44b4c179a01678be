#pragma once
/// \file block_jacobi.hpp
/// Block-Jacobi preconditioning: \f$ B = D^{-1} \f$, the inverses of the 3x3 diagonal blocks of A.
/// The one place they are computed: the preconditioner of CG, the preconditioner of BiCGSTAB and
/// the smoother on every multigrid level use this class.
///
/// Rows fixed by the system's constraints get a zero block (their unknowns do not move). A singular
/// diagonal block is reported (update returns false); what that means is the caller's to say: for
/// CG it proves A is not positive definite.

#include <array>
#include <atomic>
#include <type_traits>
#include <vector>

#include "drape/linalg/block3.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/detail/block_jacobi_avx2.hpp"
#include "drape/solvers/preconditioner.hpp"

namespace drape {

template <class Scalar = double>
class BlockJacobi final : public Preconditioner<Scalar> {
 public:
  void analyze(const LinearSystem<Scalar>& system) override { resize(system.block_rows()); }
  bool update_in_team(const LinearSystem<Scalar>& system) override;
  void apply_in_team(const Scalar* r, Scalar* z) override;

  /// Room for `rows` inverse blocks (allocates; once).
  void resize(int rows) { m_inverse.assign(9 * static_cast<std::size_t>(rows), Scalar(0)); }
  int rows() const { return static_cast<int>(m_inverse.size() / 9); }
  /// Inverts the diagonal blocks of `a` (zero blocks for rows that `constraints`, if given, fixes).
  /// Shared by the team if `shared` (the team waits at the end), else every row on the calling
  /// thread. Returns true if every block this thread inverted is regular.
  bool invert_rows(const BlockSparseMatrix<Scalar>& a, const ConstraintFilter<Scalar>* constraints, bool shared);
  /// The inverse block of a row, column-major.
  const Scalar* inverse(int row) const { return m_inverse.data() + 9 * static_cast<std::size_t>(row); }
  /// \f$ D_r^{-1} v \f$ for the 3 values at `v`.
  std::array<Scalar, 3> times(int row, const Scalar* v) const { return block_times(inverse(row), v); }
  /// One damped Jacobi step on rows [begin, end): \f$ x_r = \omega D_r^{-1} t_r \f$ (`first`) or
  /// \f$ x_r \mathrel{+}= \omega D_r^{-1} t_r \f$.
  void smooth_rows(const Scalar* t, Scalar omega, bool first, Scalar* x, int begin, int end) const;

 private:
  std::vector<Scalar> m_inverse;
  std::atomic<int> m_failed{0};
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
bool BlockJacobi<Scalar>::invert_rows(const BlockSparseMatrix<Scalar>& a, const ConstraintFilter<Scalar>* constraints,
                                      bool shared) {
  const bool any_fixed = constraints && !constraints->empty();
  const int* diagonal = a.diagonal().data();
  const Scalar* values = a.values();
  bool regular = true;
  team_for_if(shared, a.block_rows(), [&](int row) {
    Scalar* inverse = m_inverse.data() + 9 * static_cast<std::size_t>(row);
    if (any_fixed && constraints->kind(row) == ConstraintKind::Fixed) {
      for (int q = 0; q < 9; ++q) inverse[q] = Scalar(0);
      return;
    }
    if (!invert_block(values + 9 * diagonal[row], inverse)) regular = false;
  });
  return regular;
}

template <class Scalar>
void BlockJacobi<Scalar>::smooth_rows(const Scalar* t, Scalar omega, bool first, Scalar* x, int begin, int end) const {
#if DRAPE_AVX2_DISPATCH
  if constexpr (std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>) {
    if (instruction_set() == InstructionSet::Avx2) {
      detail::jacobi_smooth_rows_avx2(m_inverse.data(), t, omega, first, x, begin, end);
      return;
    }
  }
#endif
  for (int row = begin; row < end; ++row) {
    const std::array<Scalar, 3> d = times(row, t + 3 * row);
    const Scalar u0 = omega * d[0], u1 = omega * d[1], u2 = omega * d[2];
    Scalar* xr = x + 3 * row;
    if (first) {
      xr[0] = u0;
      xr[1] = u1;
      xr[2] = u2;
    } else {
      xr[0] += u0;
      xr[1] += u1;
      xr[2] += u2;
    }
  }
}

template <class Scalar>
bool BlockJacobi<Scalar>::update_in_team(const LinearSystem<Scalar>& system) {
  team_single([&] { m_failed.store(0, std::memory_order_relaxed); });
  if (!invert_rows(system.matrix, &system.constraints, true)) m_failed.store(1, std::memory_order_relaxed);
  team_barrier();
  return m_failed.load(std::memory_order_relaxed) == 0;
}

template <class Scalar>
void BlockJacobi<Scalar>::apply_in_team(const Scalar* r, Scalar* z) {
  team_for(rows(), [&](int row) {
    const std::array<Scalar, 3> t = times(row, r + 3 * row);
    z[3 * row] = t[0];
    z[3 * row + 1] = t[1];
    z[3 * row + 2] = t[2];
  });
}

}  // namespace drape
