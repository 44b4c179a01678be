#pragma once
/// \file bicgstab.hpp
/// BiCGSTAB (van der Vorst 1992) with the 3x3 block-Jacobi preconditioner, warm-started: the
/// iterative path for the non-symmetric Exact Jacobian (it also accepts symmetric systems).
/// Constraints are honoured like in PCG: the start is \f$ S x + z \f$ and every residual and
/// search direction is filtered with S. Products with A are threaded by rows; vector updates and
/// dot products are serial, so results do not depend on scheduling.

#include <cmath>

#include "drape/platform/team.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/solver_kind.hpp"

namespace drape {

template <class Scalar = double>
class BicgstabSolver final : public detail::BuiltInSolver<Scalar, LinearSolverKind::Bicgstab> {
 public:
  static constexpr long long min_rows_per_thread = 3000;

  explicit BicgstabSolver(const IterativeSettings& settings = {}) : m_settings(settings) {}

  void analyze(const LinearSystem<Scalar>& system) override;
  SolveStatus solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) override;

 private:
  /// out = D^-1 in, row by row (Eigen's vectorised 3x3 product with the stored inverse blocks).
  void precondition(const VectorX<Scalar>& in, VectorX<Scalar>& out) const;

  IterativeSettings m_settings;
  BlockJacobi<Scalar> m_jacobi;
  VectorX<Scalar> m_r, m_r0, m_p, m_v, m_s, m_t, m_y, m_z;
  Index m_analyzed = -1;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void BicgstabSolver<Scalar>::analyze(const LinearSystem<Scalar>& system) {
  for (VectorX<Scalar>* v : {&m_r, &m_r0, &m_p, &m_v, &m_s, &m_t, &m_y, &m_z}) v->setZero(system.size());
  m_jacobi.resize(system.block_rows());
  m_analyzed = system.size();
}

template <class Scalar>
void BicgstabSolver<Scalar>::precondition(const VectorX<Scalar>& in, VectorX<Scalar>& out) const {
  const Index rows = in.size() / 3;
  for (Index r = 0; r < rows; ++r)
    out.template segment<3>(3 * r).noalias() =
        Eigen::Map<const Mat3<Scalar>>(m_jacobi.inverse(static_cast<int>(r))) * in.template segment<3>(3 * r);
}

template <class Scalar>
SolveStatus BicgstabSolver<Scalar>::solve(const LinearSystem<Scalar>& system, VectorX<Scalar>& x) {
  if (m_analyzed != system.size()) analyze(system);
  const int threads = effective_threads(m_settings.threads, system.block_rows(), min_rows_per_thread);
  const ConstraintFilter<Scalar>& constraints = system.constraints;
  if (!m_jacobi.invert_rows(system.matrix, &constraints, false)) return {SolveError::SolverFailure, 0, 0.0};
  constraints.impose(x.data());
  m_s = system.rhs;
  constraints.project(m_s.data());
  const double b_norm = double(m_s.norm());
  if (b_norm == 0) {
    x.setZero();
    constraints.impose(x.data());
    return {};
  }
  system.multiply(x.data(), m_t.data(), threads);
  m_r = system.rhs - m_t;
  constraints.project(m_r.data());
  m_r0 = m_r;
  Scalar rho = 1, alpha = 1, omega = 1;
  m_v.setZero();
  m_p.setZero();
  const double tol = m_settings.tolerance;
  double r_norm = double(m_r.norm());
  int it = 0;
  while (!(r_norm <= tol * b_norm)) {
    if (it >= m_settings.max_iterations) return {SolveError::NoConvergence, it, r_norm / b_norm};
    ++it;
    const Scalar rho_new = m_r0.dot(m_r);
    if (rho_new == Scalar(0) || !std::isfinite(double(rho_new))) {
      // Breakdown: restart with the current residual as shadow vector.
      m_r0 = m_r;
      rho = 1;
      alpha = 1;
      omega = 1;
      m_v.setZero();
      m_p.setZero();
      if (m_r0.squaredNorm() == Scalar(0)) break;
      continue;
    }
    const Scalar beta = (rho_new / rho) * (alpha / omega);
    rho = rho_new;
    m_p = m_r + beta * (m_p - omega * m_v);
    precondition(m_p, m_y);
    constraints.project(m_y.data());
    system.multiply(m_y.data(), m_v.data(), threads);
    constraints.project(m_v.data());
    alpha = rho / m_r0.dot(m_v);
    m_s = m_r - alpha * m_v;
    if (double(m_s.norm()) <= tol * b_norm) {
      x += alpha * m_y;
      m_r = m_s;
      r_norm = double(m_r.norm());
      break;
    }
    precondition(m_s, m_z);
    constraints.project(m_z.data());
    system.multiply(m_z.data(), m_t.data(), threads);
    constraints.project(m_t.data());
    const Scalar tt = m_t.squaredNorm();
    omega = tt > Scalar(0) ? m_t.dot(m_s) / tt : Scalar(0);
    x += alpha * m_y + omega * m_z;
    m_r = m_s - omega * m_t;
    r_norm = double(m_r.norm());
    if (!std::isfinite(r_norm)) return {SolveError::NonFiniteResult, it, r_norm};
    if (omega == Scalar(0)) return {SolveError::SolverFailure, it, r_norm / b_norm};
  }
  return {SolveError::None, it, r_norm / b_norm};
}

}  // namespace drape
