#pragma once
/// \file pcg.hpp
/// Preconditioned conjugate gradients on the filtered system (Baraff & Witkin 1998, section 5.3),
/// warm-started from the caller's `x` (the previous step's dv). The preconditioner
/// (IterativeSettings::preconditioner) is block Jacobi, the geometric multigrid V-cycle or the
/// algebraic one (each in the solve's precision or in float), behind one interface (preconditioner.hpp,
/// made by make_preconditioner.hpp), so there is one CG loop:
/// \f[ x \leftarrow S x + z,\quad r = S(b - A x),\quad p = S B r; \qquad
///     q = S A p,\; \alpha = \frac{r \cdot B r}{p \cdot q},\; x \mathrel{+}= \alpha p,\; r \mathrel{-}= \alpha q,\;
///     p \leftarrow S B r + \beta p. \f]
/// S and z are the system's constraints (linalg/constraint_filter.hpp): pinned rows in
/// PinTreatment::Filter, contacts later. Stops when \f$ |r| \le \mathrm{tol}\, |S b| \f$.
/// Requires a symmetric positive definite matrix; reports `NotPositiveDefinite` when it meets a
/// direction with \f$ p^T A p \le 0 \f$ or the preconditioner cannot be built (a singular diagonal
/// block, or a multigrid level that is not positive definite).
///
/// Threads: the whole solve runs in one team; rows are split statically and every dot product is
/// summed per thread over a fixed row range, then the per-thread partials are added in thread
/// order. Results therefore depend on the thread count but never on scheduling. The product with A
/// uses the edge form when it is valid: half the 3x3 products of block rows, worth its barrier per
/// edge colour on a team (drape's implicit.md).

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "drape/linalg/block3.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/make_preconditioner.hpp"
#include "drape/solvers/solver_kind.hpp"

namespace drape {

template <class Scalar = double>
class PcgSolver final : public detail::BuiltInSolver<Scalar, LinearSolverKind::Cg> {
 public:
  /// Block rows per thread below which a second thread is not woken.
  static constexpr long long min_rows_per_thread = 3000;

  /// `multigrid`: the V-cycle's settings if settings.preconditioner is a geometric multigrid; `amg`
  /// the algebraic V-cycle's if it is amg or amg-float, or a geometric one on a system without a
  /// lattice.
  explicit PcgSolver(const IterativeSettings& settings = {}, const MultigridSettings& multigrid = {},
                     const AlgebraicMultigridSettings& amg = {});

  /// A system without a lattice layout (a cloth that is not a grid) takes the algebraic multigrid
  /// where a geometric multigrid was chosen, in the same precision: `multigrid` gives `amg`
  /// (algebraic_multigrid.hpp), `multigrid-float` `amg-float`
  /// (single_precision_algebraic_multigrid.hpp).
  /// \throws InvalidParameter if the layout does not match the system's matrix.
  void analyze(const LinearSystem<Scalar>& system) override;
  SolveStatus solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) override;

  const IterativeSettings& settings() const { return m_settings; }
  const Preconditioner<Scalar>& preconditioner() const { return *m_preconditioner; }

 private:
  static constexpr int max_team = 64;
  struct alignas(64) Partial {
    double value[4];
  };

  IterativeSettings m_settings;
  AlgebraicMultigridSettings m_amg;  // for a system without a lattice where a geometric multigrid was chosen
  std::unique_ptr<Preconditioner<Scalar>> m_preconditioner;
  VectorX<Scalar> m_r, m_z, m_p, m_q;
  Index m_analyzed = -1;
  std::array<Partial, max_team> m_partial{};
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
PcgSolver<Scalar>::PcgSolver(const IterativeSettings& settings, const MultigridSettings& multigrid,
                             const AlgebraicMultigridSettings& amg)
    : m_settings(settings),
      m_amg(amg),
      m_preconditioner(make_preconditioner<Scalar>(settings.preconditioner, multigrid, amg)) {}

template <class Scalar>
void PcgSolver<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  const Index n = system.size();
  for (VectorX<Scalar>* v : {&m_r, &m_z, &m_p, &m_q}) v->setZero(n);
  const PreconditionerKind chosen = m_settings.preconditioner;
  if (needs_grid_layout(chosen) && system.layout.empty())
    m_preconditioner = make_preconditioner<Scalar>(chosen == PreconditionerKind::MultigridFloat
                                                       ? PreconditionerKind::AlgebraicMultigridFloat
                                                       : PreconditionerKind::AlgebraicMultigrid,
                                                   {}, m_amg);
  m_preconditioner->analyze(system);
  m_analyzed = n;
}

template <class Scalar>
SolveStatus PcgSolver<Scalar>::solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) {
  if (m_analyzed != system.size()) analyze(system);
  const int rows = system.block_rows();
  const int team = std::min(max_team, effective_threads(m_settings.threads, rows, min_rows_per_thread));
  const ConstraintFilter<Scalar>& constraints = system.constraints;
  const bool constrained = !constraints.empty();
  const int* rb = system.matrix.row_begin().data();
  const int* col = system.matrix.column().data();
  const Scalar* val = system.matrix.values();
  Scalar* r = m_r.data();
  Scalar* z = m_z.data();
  Scalar* p = m_p.data();
  Scalar* q = m_q.data();
  Scalar* xs = x.data();
  const Scalar* bs = system.rhs.data();
  const double tol = m_settings.tolerance;
  const int max_it = m_settings.max_iterations;
  const bool edges = system.edges.valid();  // the cheaper product, on any team (edge_operator.hpp)
  Preconditioner<Scalar>& preconditioner = *m_preconditioner;
  std::array<Partial, max_team>& partial = m_partial;
  SolveStatus status;

  // (A s)_r for one block row.
  const auto row_product = [&](int row, const Scalar* s) {
    std::array<Scalar, 3> y{0, 0, 0};
    for (int k = rb[row]; k < rb[row + 1]; ++k) {
      const std::array<Scalar, 3> t = block_times(val + 9 * k, s + 3 * col[k]);
      y[0] += t[0];
      y[1] += t[1];
      y[2] += t[2];
    }
    return y;
  };
  // `body(row, s0, s1)` over this thread's static share of the rows, accumulating two sums in
  // registers (partials in shared memory would be reloaded at every row, since vectors may alias
  // them); then stores them as this thread's partials `slot0`, `slot1` (-1: none) and waits for
  // the team.
  const auto for_rows_summing = [&](Partial& mine, int slot0, int slot1, auto&& row_body) {
    double s0 = 0, s1 = 0;
    team_for_nowait(rows, [&](int row) { row_body(row, s0, s1); });
    if (slot0 >= 0) mine.value[slot0] = s0;
    if (slot1 >= 0) mine.value[slot1] = s1;
    team_barrier();
  };
  // z = S B r, and this thread's rows of r . z into partial `slot`.
  const auto precondition = [&](Partial& mine, int slot) {
    preconditioner.apply_in_team(r, z);
    for_rows_summing(mine, slot, -1, [&](int row, double& rz_sum, double&) {
      if (constrained) constraints.project_row(row, z + 3 * row);
      // A row's three terms first: a third of the additions in the chain through rz_sum.
      rz_sum += double(r[3 * row]) * double(z[3 * row]) + double(r[3 * row + 1]) * double(z[3 * row + 1]) +
                double(r[3 * row + 2]) * double(z[3 * row + 2]);
    });
  };
  // Every thread adds the team's partials in thread order, so all agree on the same value.
  const auto reduce = [&](int slot, int threads_in_team) {
    double s = 0;
    for (int t = 0; t < threads_in_team; ++t) s += partial[static_cast<std::size_t>(t)].value[slot];
    return s;
  };

  run_in_team(team, [&] {
    const int nt = team_size();
    Partial& mine = partial[static_cast<std::size_t>(team_rank())];
    mine.value[0] = mine.value[1] = mine.value[2] = mine.value[3] = 0;
    // Set-up: x = S x + z, the preconditioner for these values, r = S(b - A x), z = S B r, p = z.
    if (constrained) team_for(rows, [&](int row) { constraints.impose_row(row, xs + 3 * row); });
    const bool ready = preconditioner.update_in_team(system);
    if (edges) system.edges.multiply_in_team(xs, r);  // A x into r (ends with a barrier)
    team_for(rows, [&](int row) {
      Scalar* rr = r + 3 * row;
      const std::array<Scalar, 3> y = edges ? std::array<Scalar, 3>{rr[0], rr[1], rr[2]} : row_product(row, xs);
      rr[0] = bs[3 * row] - y[0];
      rr[1] = bs[3 * row + 1] - y[1];
      rr[2] = bs[3 * row + 2] - y[2];
      const ConstraintKind kind = constrained ? constraints.kind(row) : ConstraintKind::Free;
      if (kind == ConstraintKind::Free) {
        for (int k = 0; k < 3; ++k) {
          mine.value[0] += double(bs[3 * row + k]) * double(bs[3 * row + k]);
          mine.value[1] += double(rr[k]) * double(rr[k]);
        }
      } else {
        constraints.project_row(row, rr);
        Scalar sb[3] = {bs[3 * row], bs[3 * row + 1], bs[3 * row + 2]};
        constraints.project_row(row, sb);
        for (int k = 0; k < 3; ++k) {
          if (kind != ConstraintKind::Fixed) mine.value[0] += double(sb[k]) * double(sb[k]);
          mine.value[1] += double(rr[k]) * double(rr[k]);
        }
      }
    });
    if (!ready) {
      mine.value[3] = 1;
    } else {
      precondition(mine, 2);
      team_for(3 * rows, [&](int i) { p[i] = z[i]; });
    }
    team_barrier();
    const double bb = reduce(0, nt);
    double rr_norm2 = reduce(1, nt);
    double rz = reduce(2, nt);
    const bool preconditioner_failed = reduce(3, nt) != 0;
    team_barrier();
    const double b_norm = std::sqrt(bb);
    if (bb == 0) {  // S b = 0: the solution is S 0 + z, whatever the warm start
      team_for(rows, [&](int row) {
        xs[3 * row] = xs[3 * row + 1] = xs[3 * row + 2] = 0;
        if (constrained) constraints.impose_row(row, xs + 3 * row);
      });
      rr_norm2 = 0;
    }
    int it = 0;
    SolveError error = preconditioner_failed ? SolveError::NotPositiveDefinite : SolveError::None;
    while (error == SolveError::None && !(std::sqrt(rr_norm2) <= tol * b_norm)) {
      if (it >= max_it) {
        error = SolveError::NoConvergence;
        break;
      }
      ++it;
      // q = S A p, pq = p . q
      if (edges) {
        system.edges.multiply_in_team(p, q);  // ends with a barrier
        for_rows_summing(mine, 0, -1, [&](int row, double& pq_sum, double&) {
          if (constrained) constraints.project_row(row, q + 3 * row);
          pq_sum += double(p[3 * row]) * double(q[3 * row]) + double(p[3 * row + 1]) * double(q[3 * row + 1]) +
                    double(p[3 * row + 2]) * double(q[3 * row + 2]);
        });
      } else {
        for_rows_summing(mine, 0, -1, [&](int row, double& pq_sum, double&) {
          std::array<Scalar, 3> y = row_product(row, p);
          if (constrained) constraints.project_row(row, y.data());
          q[3 * row] = y[0];
          q[3 * row + 1] = y[1];
          q[3 * row + 2] = y[2];
          pq_sum += double(p[3 * row]) * y[0] + double(p[3 * row + 1]) * y[1] + double(p[3 * row + 2]) * y[2];
        });
      }
      const double pq = reduce(0, nt);
      if (!(pq > 0) || !std::isfinite(pq)) {
        error = std::isfinite(pq) ? SolveError::NotPositiveDefinite : SolveError::NonFiniteResult;
        break;
      }
      const Scalar alpha = Scalar(rz / pq);
      for_rows_summing(mine, 1, -1, [&](int row, double& rr_sum, double&) {
        Scalar* rr = r + 3 * row;
        for (int k = 0; k < 3; ++k) {
          xs[3 * row + k] += alpha * p[3 * row + k];
          rr[k] -= alpha * q[3 * row + k];
        }
        rr_sum += double(rr[0]) * double(rr[0]) + double(rr[1]) * double(rr[1]) + double(rr[2]) * double(rr[2]);
      });
      precondition(mine, 2);  // r is complete after the barrier
      rr_norm2 = reduce(1, nt);
      const double rz_new = reduce(2, nt);
      const Scalar beta = Scalar(rz_new / rz);
      rz = rz_new;
      team_for(3 * rows, [&](int i) { p[i] = z[i] + beta * p[i]; });
    }
    if (team_rank() == 0) {
      status.error = error;
      status.iterations = it;
      status.residual = b_norm > 0 ? std::sqrt(rr_norm2) / b_norm : std::sqrt(rr_norm2);
    }
  });
  // Every reduction above is followed by the barrier of a later shared loop before its partial is
  // written again, which is what keeps a partial from being overwritten before every thread has
  // read it.
  return status;
}

}  // namespace drape
