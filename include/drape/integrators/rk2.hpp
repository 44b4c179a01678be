#pragma once
/// \file rk2.hpp
/// Explicit midpoint rule (RK2), the brief's equation (3):
/// \f[ q_{t+1} = q_t + \Delta t\, F\!\left(q_t + \tfrac{\Delta t}{2} F(q_t)\right), \quad
///     q = (x, v), \quad F(q) = (v,\; M^{-1} f(x, v)). \f]
/// Pinned nodes are reset to their position and zero velocity after each stage, so they never move.
/// Conditionally stable: see docs/parameters.md for the largest stable dt.

#include "drape/core/cloth.hpp"
#include "drape/core/validation.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/physics/force_assembler.hpp"

namespace drape {

template <class Scalar = double>
class Rk2 {
 public:
  /// \param threads 0 = all available.
  explicit Rk2(const Cloth<Scalar>& cloth, int threads = 0);

  /// Advances `state` by `dt`. On failure `state` is left unchanged.
  /// \throws std::invalid_argument if dt is not finite and > 0 or the state has the wrong size.
  StepStatus step(State<Scalar>& state, Scalar dt);

  const ForceAssembler<Scalar>& forces() const { return m_forces; }

 private:
  /// a = M^-1 f (pinned nodes are reset after each stage instead).
  void accelerations(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Matrix3X<Scalar>& acc);

  ForceAssembler<Scalar> m_forces;
  VectorX<Scalar> m_inverse_mass;
  Matrix3X<Scalar> m_acc, m_x_mid, m_v_mid, m_x_new, m_v_new;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Rk2<Scalar>::Rk2(const Cloth<Scalar>& cloth, int threads) : m_forces(cloth, threads) {
  const int n = cloth.node_count();
  m_inverse_mass = cloth.grid().masses().cwiseInverse();
  for (Matrix3X<Scalar>* m : {&m_acc, &m_x_mid, &m_v_mid, &m_x_new, &m_v_new}) m->resize(3, n);
}

template <class Scalar>
void Rk2<Scalar>::accelerations(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Matrix3X<Scalar>& acc) {
  m_forces.force(x, v, acc);
  acc.array().rowwise() *= m_inverse_mass.transpose().array();
}

template <class Scalar>
StepStatus Rk2<Scalar>::step(State<Scalar>& state, Scalar dt) {
  detail::require_positive_finite("dt", dt);
  if (state.positions.cols() != m_inverse_mass.size() || state.velocities.cols() != m_inverse_mass.size())
    detail::fail_argument("state", detail::to_text(state.positions.cols()) + " nodes",
                          detail::to_text(m_inverse_mass.size()) + " nodes (the cloth's)");
  const Scalar half = Scalar(0.5) * dt;
  // Midpoint: q_mid = q + dt/2 F(q).
  accelerations(state.positions, state.velocities, m_acc);
  m_x_mid = state.positions + half * state.velocities;
  m_v_mid = state.velocities + half * m_acc;
  // Pinned nodes stay put whatever velocity the caller left on them.
  for (int p : m_forces.cloth().pins().nodes()) {
    m_x_mid.col(p) = state.positions.col(p);
    m_v_mid.col(p).setZero();
  }
  // Full step with the midpoint slope.
  accelerations(m_x_mid, m_v_mid, m_acc);
  m_x_new = state.positions + dt * m_v_mid;
  m_v_new = state.velocities + dt * m_acc;
  // Pinned nodes: v_mid = 0 already keeps x_new = x; the velocity must be zeroed explicitly.
  for (int p : m_forces.cloth().pins().nodes()) m_v_new.col(p).setZero();
  if (!(m_x_new.allFinite() && m_v_new.allFinite())) return {StepError::NonFiniteState, 0, 0.0};
  state.positions.swap(m_x_new);
  state.velocities.swap(m_v_new);
  state.time += dt;
  return {};
}

}  // namespace drape
