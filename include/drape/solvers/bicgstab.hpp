#pragma once
/// \file bicgstab.hpp
/// BiCGSTAB (van der Vorst 1992) with the 3x3 block-Jacobi preconditioner, warm-started: the
/// iterative path for the non-symmetric Exact Jacobian (it also accepts symmetric systems).
/// Mat-vecs are threaded by rows; vector updates and dot products are serial, so results do not
/// depend on scheduling.

#include <cmath>
#include <vector>

#include "drape/core/parallel.hpp"
#include <Eigen/LU>  // 3x3 inverse

#include "drape/solvers/linear_solver.hpp"

namespace drape {

template <class Scalar = double>
class BicgstabSolver final : public LinearSolver<Scalar> {
 public:
  static constexpr long long min_rows_per_thread = 3000;

  explicit BicgstabSolver(const IterativeSettings& settings = {}) : m_settings(settings) {}

  const char* name() const override { return "bicgstab"; }
  bool requires_symmetric() const override { return false; }
  bool supports_filter() const override { return true; }
  void analyze(const BlockSparseMatrix<Scalar>& a) override;
  StepStatus solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b, VectorX<Scalar>& x,
                   const std::uint8_t* filter = nullptr) override;

 private:
  void precondition(const VectorX<Scalar>& in, VectorX<Scalar>& out) const;
  void mask(VectorX<Scalar>& v, const std::uint8_t* filter) const;

  IterativeSettings m_settings;
  VectorX<Scalar> m_r, m_r0, m_p, m_v, m_s, m_t, m_y, m_z, m_inv_diag;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void BicgstabSolver<Scalar>::analyze(const BlockSparseMatrix<Scalar>& a) {
  for (VectorX<Scalar>* v : {&m_r, &m_r0, &m_p, &m_v, &m_s, &m_t, &m_y, &m_z}) v->setZero(a.size());
  m_inv_diag.setZero(3 * a.size());
}

template <class Scalar>
void BicgstabSolver<Scalar>::precondition(const VectorX<Scalar>& in, VectorX<Scalar>& out) const {
  const Index rows = in.size() / 3;
  for (Index r = 0; r < rows; ++r)
    out.template segment<3>(3 * r).noalias() =
        Eigen::Map<const Mat3<Scalar>>(m_inv_diag.data() + 9 * r) * in.template segment<3>(3 * r);
}

template <class Scalar>
void BicgstabSolver<Scalar>::mask(VectorX<Scalar>& v, const std::uint8_t* filter) const {
  if (!filter) return;
  for (Index r = 0; r < v.size() / 3; ++r)
    if (filter[r]) v.template segment<3>(3 * r).setZero();
}

template <class Scalar>
StepStatus BicgstabSolver<Scalar>::solve(const BlockSparseMatrix<Scalar>& a, const VectorX<Scalar>& b,
                                         VectorX<Scalar>& x, const std::uint8_t* filter) {
  if (m_r.size() != a.size()) analyze(a);
  const int threads = effective_threads(m_settings.threads, a.block_rows(), min_rows_per_thread);
  for (int r = 0; r < a.block_rows(); ++r) {
    Eigen::Map<Mat3<Scalar>> m(m_inv_diag.data() + 9 * r);
    if (filter && filter[r]) {
      m.setZero();
      continue;
    }
    m = a.block(a.diagonal()[static_cast<std::size_t>(r)]).inverse();
    if (!m.allFinite()) return {StepError::SolverFailure, 0, 0.0};
  }
  mask(x, filter);
  m_s = b;
  mask(m_s, filter);
  const double b_norm = double(m_s.norm());
  if (b_norm == 0) {
    x.setZero();
    return {};
  }
  a.multiply(x.data(), m_t.data(), threads);
  m_r = b - m_t;
  mask(m_r, filter);
  m_r0 = m_r;
  Scalar rho = 1, alpha = 1, omega = 1;
  m_v.setZero();
  m_p.setZero();
  const double tol = m_settings.tolerance;
  double r_norm = double(m_r.norm());
  int it = 0;
  while (!(r_norm <= tol * b_norm)) {
    if (it >= m_settings.max_iterations) return {StepError::NoConvergence, it, r_norm / b_norm};
    ++it;
    const Scalar rho_new = m_r0.dot(m_r);
    if (rho_new == Scalar(0) || !std::isfinite(double(rho_new))) {
      // Breakdown: restart with the current residual as shadow vector.
      m_r0 = m_r;
      rho = 1; alpha = 1; omega = 1;
      m_v.setZero();
      m_p.setZero();
      if (m_r0.squaredNorm() == Scalar(0)) break;
      continue;
    }
    const Scalar beta = (rho_new / rho) * (alpha / omega);
    rho = rho_new;
    m_p = m_r + beta * (m_p - omega * m_v);
    precondition(m_p, m_y);
    a.multiply(m_y.data(), m_v.data(), threads);
    mask(m_v, filter);
    alpha = rho / m_r0.dot(m_v);
    m_s = m_r - alpha * m_v;
    if (double(m_s.norm()) <= tol * b_norm) {
      x += alpha * m_y;
      m_r = m_s;
      r_norm = double(m_r.norm());
      break;
    }
    precondition(m_s, m_z);
    a.multiply(m_z.data(), m_t.data(), threads);
    mask(m_t, filter);
    const Scalar tt = m_t.squaredNorm();
    omega = tt > Scalar(0) ? m_t.dot(m_s) / tt : Scalar(0);
    x += alpha * m_y + omega * m_z;
    m_r = m_s - omega * m_t;
    r_norm = double(m_r.norm());
    if (!std::isfinite(r_norm)) return {StepError::NonFiniteState, it, r_norm};
    if (omega == Scalar(0)) return {StepError::SolverFailure, it, r_norm / b_norm};
  }
  return {StepError::None, it, r_norm / b_norm};
}

}  // namespace drape
