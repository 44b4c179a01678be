#pragma once
/// \file pcg.hpp
/// Preconditioned conjugate gradients, warm-started from the caller's `x` (the previous step's dv),
/// on the block-CSR system. Preconditioner (IterativeSettings::preconditioner): 3x3 block Jacobi,
/// or a geometric multigrid V-cycle on the cloth's lattice (multigrid.hpp; needs set_grid_layout()).
/// Requires a symmetric positive definite matrix; reports `NotPositiveDefinite` when it meets a
/// direction with p^T A p <= 0 (or the multigrid hierarchy finds a coarse operator that is not).
///
/// Threads: the whole solve runs in one parallel region; rows are split statically and every dot
/// product is summed per thread over a fixed row range, then the per-thread partials are added in
/// thread order. Results therefore depend on the thread count but never on scheduling.
/// Pinned rows (the optional filter) are projected out: r, z, p and A p are zero on them
/// (Baraff & Witkin's filter S).

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "drape/core/parallel.hpp"
#include <Eigen/LU>  // 3x3 inverse

#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/multigrid.hpp"

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace drape {

template <class Scalar = double>
class PcgSolver final : public LinearSolver<Scalar> {
 public:
  /// Block rows per thread below which a second thread is not woken.
  static constexpr long long min_rows_per_thread = 3000;

  explicit PcgSolver(const IterativeSettings& settings = {}) : m_settings(settings) {}

  const char* name() const override { return "cg"; }
  bool requires_symmetric() const override { return true; }
  bool supports_filter() const override { return true; }
  void set_grid_layout(const GridLayout& layout) override { m_layout = layout; }
  /// \throws std::invalid_argument if the multigrid preconditioner is chosen without a grid layout
  /// (or with one that does not match `a`).
  void analyze(const BlockSparseMatrix<Scalar>& a) override;
  StepStatus solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                   const std::uint8_t* filter = nullptr) override;

  const IterativeSettings& settings() const { return m_settings; }
  const MultigridPreconditioner<Scalar>& multigrid() const { return m_multigrid; }

 private:
  static constexpr int max_team = 64;
  struct alignas(64) Partial {
    double value[4];
  };

  bool use_multigrid() const { return m_settings.preconditioner == Preconditioner::Multigrid; }

  IterativeSettings m_settings;
  GridLayout m_layout;
  MultigridPreconditioner<Scalar> m_multigrid;
  VectorX<Scalar> m_r, m_z, m_p, m_q, m_inv_diag;
  std::array<Partial, max_team> m_partial{};
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void PcgSolver<Scalar>::analyze(const BlockSparseMatrix<Scalar>& a) {
  const Index n = a.size();
  for (VectorX<Scalar>* v : {&m_r, &m_z, &m_p, &m_q}) v->setZero(n);
  m_inv_diag.setZero(3 * n);
  if (use_multigrid()) {
    if (m_layout.empty())
      detail::fail_argument("preconditioner", "multigrid without a grid layout",
                            "block-jacobi, or multigrid after set_grid_layout() (ImplicitEuler does this)");
    m_multigrid.analyze(m_layout, a);
  }
}

template <class Scalar>
StepStatus PcgSolver<Scalar>::solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                                    const std::uint8_t* filter) {
  if (m_r.size() != a.size() || (use_multigrid() && !m_multigrid.analyzed())) analyze(a);
  const bool multigrid = use_multigrid();
  const int rows = a.block_rows();
  const int team = std::min(max_team, effective_threads(m_settings.threads, rows, min_rows_per_thread));
  const int* rb = a.row_begin().data();
  const int* col = a.column().data();
  const int* diag = a.diagonal().data();
  const Scalar* val = a.values();
  Scalar* r = m_r.data();
  Scalar* z = m_z.data();
  Scalar* p = m_p.data();
  Scalar* q = m_q.data();
  Scalar* inv = m_inv_diag.data();
  Scalar* xs = x.data();
  const Scalar* bs = b.data();
  const double tol = m_settings.tolerance;
  const int max_it = m_settings.max_iterations;
  // Per-spring mat-vec (fewer flops and bytes) on one thread; with a team, the row-parallel block
  // CSR mat-vec needs one barrier instead of one per spring colour (docs/implicit.md).
  const bool edges = a.edge_form_valid() && team == 1;
  std::array<Partial, max_team>& partial = m_partial;
  StepStatus status;

  // y_r = (A s)_r for one block row.
  const auto row_product = [&](int row, const Scalar* s, Scalar& y0, Scalar& y1, Scalar& y2) {
    y0 = y1 = y2 = 0;
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const Scalar* m = val + 9 * k;
      const Scalar* sc = s + 3 * col[k];
      y0 += m[0] * sc[0] + m[3] * sc[1] + m[6] * sc[2];
      y1 += m[1] * sc[0] + m[4] * sc[1] + m[7] * sc[2];
      y2 += m[2] * sc[0] + m[5] * sc[1] + m[8] * sc[2];
    }
  };
  // z_r = P^-1 r_r with the stored 3x3 inverse.
  const auto precondition = [&](int row) {
    const Scalar* m = inv + 9 * row;
    const Scalar* rr = r + 3 * row;
    z[3 * row] = m[0] * rr[0] + m[3] * rr[1] + m[6] * rr[2];
    z[3 * row + 1] = m[1] * rr[0] + m[4] * rr[1] + m[7] * rr[2];
    z[3 * row + 2] = m[2] * rr[0] + m[5] * rr[1] + m[8] * rr[2];
  };
  // `body(row, s0, s1)` over this thread's static share of the rows, accumulating two sums in
  // registers (partials in shared memory would be reloaded at every row, since vectors may alias
  // them); then stores them as this thread's partials `slot0`, `slot1` (-1: none) and waits for
  // the team.
  const auto for_rows_summing = [&](Partial& mine, int slot0, int slot1, auto&& row_body) {
    double s0 = 0, s1 = 0;
#if defined(_OPENMP)
#pragma omp for schedule(static) nowait
#endif
    for (int row = 0; row < rows; ++row) row_body(row, s0, s1);
    if (slot0 >= 0) mine.value[slot0] = s0;
    if (slot1 >= 0) mine.value[slot1] = s1;
#if defined(_OPENMP)
#pragma omp barrier
#endif
  };
  // Multigrid only: zero z on filtered rows and sum this thread's rows of r . z into `slot`.
  const auto filtered_dot = [&](Partial& mine, int slot) {
    for_rows_summing(mine, slot, -1, [&](int row, double& rz_sum, double&) {
      if (filter && filter[row]) z[3 * row] = z[3 * row + 1] = z[3 * row + 2] = 0;
      for (int k = 0; k < 3; ++k) rz_sum += double(r[3 * row + k]) * double(z[3 * row + k]);
    });
  };
  // Every thread adds the team's partials in thread order, so all agree on the same value.
  const auto reduce = [&](int slot, int threads_in_team) {
    double s = 0;
    for (int t = 0; t < threads_in_team; ++t) s += partial[static_cast<std::size_t>(t)].value[slot];
    return s;
  };

  const auto body = [&]() {
#if defined(_OPENMP)
    const int tid = omp_get_thread_num();
    const int nt = omp_get_num_threads();
#else
    const int tid = 0, nt = 1;
#endif
    Partial& mine = partial[static_cast<std::size_t>(tid)];
    mine.value[0] = mine.value[1] = mine.value[2] = mine.value[3] = 0;
    bool bad_diagonal = false;
    // Set-up: preconditioner, r = S(b - A x), z = P^-1 r, p = z.
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int row = 0; row < rows; ++row) {
      const bool fixed = filter && filter[row];
      Eigen::Map<Mat3<Scalar>> m(inv + 9 * row);
      if (fixed) {
        m.setZero();
        xs[3 * row] = xs[3 * row + 1] = xs[3 * row + 2] = 0;
      } else if (!multigrid) {
        m = Eigen::Map<const Mat3<Scalar>>(val + 9 * diag[row]).inverse();
        if (!m.allFinite()) bad_diagonal = true;
      }
    }
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int row = 0; row < rows; ++row) {
      Scalar y0, y1, y2;
      row_product(row, xs, y0, y1, y2);
      const bool fixed = filter && filter[row];
      Scalar* rr = r + 3 * row;
      rr[0] = fixed ? Scalar(0) : bs[3 * row] - y0;
      rr[1] = fixed ? Scalar(0) : bs[3 * row + 1] - y1;
      rr[2] = fixed ? Scalar(0) : bs[3 * row + 2] - y2;
      for (int k = 0; k < 3; ++k) {
        if (!fixed) mine.value[0] += double(bs[3 * row + k]) * double(bs[3 * row + k]);
        mine.value[1] += double(rr[k]) * double(rr[k]);
      }
      if (!multigrid) {
        precondition(row);
        for (int k = 0; k < 3; ++k) {
          p[3 * row + k] = z[3 * row + k];
          mine.value[2] += double(rr[k]) * double(z[3 * row + k]);
        }
      }
      if (bad_diagonal) mine.value[3] = 1;
    }
    if (multigrid) {
      // Coarse operators for this matrix (ends with a barrier, so r is complete), then z = B r.
      if (!m_multigrid.update_in_team(a)) {
        mine.value[3] = 1;
      } else {
        m_multigrid.apply_in_team(r, z);
        filtered_dot(mine, 2);
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
        for (int i = 0; i < 3 * rows; ++i) p[i] = z[i];
      }
    }
#if defined(_OPENMP)
#pragma omp barrier
#endif
    const double bb = reduce(0, nt);
    double rr_norm2 = reduce(1, nt);
    double rz = reduce(2, nt);
    const bool diagonal_failed = reduce(3, nt) != 0;
#if defined(_OPENMP)
#pragma omp barrier
#endif
    const double b_norm = std::sqrt(bb);
    if (bb == 0) {  // b = 0: the solution is 0, whatever the warm start
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
      for (int i = 0; i < 3 * rows; ++i) xs[i] = 0;
      rr_norm2 = 0;
    }
    int it = 0;
    StepError error = StepError::None;
    if (diagonal_failed) error = StepError::NotPositiveDefinite;
    while (error == StepError::None && !(std::sqrt(rr_norm2) <= tol * b_norm)) {
      if (it >= max_it) {
        error = StepError::NoConvergence;
        break;
      }
      ++it;
      // q = S A p, pq = p . q
      if (edges) {
        detail::edge_multiply_in_team(a, p, q);  // ends with a barrier
        for_rows_summing(mine, 0, -1, [&](int row, double& pq_sum, double&) {
          if (filter && filter[row]) q[3 * row] = q[3 * row + 1] = q[3 * row + 2] = 0;
          pq_sum += double(p[3 * row]) * double(q[3 * row]) + double(p[3 * row + 1]) * double(q[3 * row + 1]) +
                    double(p[3 * row + 2]) * double(q[3 * row + 2]);
        });
      } else {
        for_rows_summing(mine, 0, -1, [&](int row, double& pq_sum, double&) {
          Scalar y0, y1, y2;
          row_product(row, p, y0, y1, y2);
          if (filter && filter[row]) y0 = y1 = y2 = 0;
          q[3 * row] = y0;
          q[3 * row + 1] = y1;
          q[3 * row + 2] = y2;
          pq_sum += double(p[3 * row]) * y0 + double(p[3 * row + 1]) * y1 + double(p[3 * row + 2]) * y2;
        });
      }
      const double pq = reduce(0, nt);
      if (!(pq > 0) || !std::isfinite(pq)) {
        error = std::isfinite(pq) ? StepError::NotPositiveDefinite : StepError::NonFiniteState;
        break;
      }
      const Scalar alpha = Scalar(rz / pq);
      for_rows_summing(mine, 1, multigrid ? -1 : 2, [&](int row, double& rr_sum, double& rz_sum) {
        for (int k = 0; k < 3; ++k) {
          xs[3 * row + k] += alpha * p[3 * row + k];
          r[3 * row + k] -= alpha * q[3 * row + k];
          rr_sum += double(r[3 * row + k]) * double(r[3 * row + k]);
        }
        if (!multigrid) {
          precondition(row);
          for (int k = 0; k < 3; ++k) rz_sum += double(r[3 * row + k]) * double(z[3 * row + k]);
        }
      });
      if (multigrid) {  // r is complete after the barrier
        m_multigrid.apply_in_team(r, z);
        filtered_dot(mine, 2);
      }
      rr_norm2 = reduce(1, nt);
      const double rz_new = reduce(2, nt);
      const Scalar beta = Scalar(rz_new / rz);
      rz = rz_new;
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
      for (int i = 0; i < 3 * rows; ++i) p[i] = z[i] + beta * p[i];
    }
    if (tid == 0) {
      status.error = error;
      status.iterations = it;
      status.residual = b_norm > 0 ? std::sqrt(rr_norm2) / b_norm : std::sqrt(rr_norm2);
    }
  };
  // The loop's reductions are followed by implicit barriers of the next `omp for`, which is what
  // keeps a partial from being overwritten before every thread has read it.
#if defined(_OPENMP)
  if (team > 1) {
#pragma omp parallel num_threads(team)
    body();
    return status;
  }
#endif
  body();
  return status;
}

}  // namespace drape
