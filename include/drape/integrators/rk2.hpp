#pragma once
/// \file rk2.hpp
/// Explicit midpoint rule (RK2):
/// \f[ q_{t+1} = q_t + \Delta t\, F\!\left(q_t + \tfrac{\Delta t}{2} F(q_t)\right), \quad
///     q = (x, v), \quad F(q) = (v,\; M^{-1} f(x, v)). \f]
/// Pinned nodes are set on their paths after each stage (the midpoint's position at t + dt/2, the
/// end's at t + dt, the velocity (x(t + dt) - x) / dt): a holding pin never moves.
/// Contacts with colliders are resolved on the step's result (contact/contact_handler.hpp).
/// Conditionally stable: see drape's parameters.md for the largest stable dt.
///
/// One step is one parallel region with five barriers: q copied by component, spring pass at q,
/// node pass fused with the midpoint update, spring pass at the midpoint, node pass fused with the
/// final update and the finiteness check (force_assembler.hpp). Bitwise identical for any thread
/// count. Force terms are evaluated at t and at the midpoint t + dt/2, on one thread (a sixth
/// barrier, only with terms).

#include <algorithm>
#include <atomic>
#include <vector>

#include "drape/integrators/explicit_integrator.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/platform/team.hpp"

namespace drape {

template <class Scalar = double>
class Rk2 final : public ExplicitIntegrator<Scalar> {
 public:
  /// \throws InvalidParameter as IntegratorOptions::validate().
  explicit Rk2(const Cloth<Scalar>& cloth, const IntegratorOptions& options = {});
  /// The integrator keeps a reference to the cloth: a temporary would dangle.
  Rk2(const Cloth<Scalar>&& cloth, const IntegratorOptions& options = {}) = delete;

  StepStatus step(State<Scalar>& state) override;

 private:
  using ExplicitIntegrator<Scalar>::m_forces;
  using ExplicitIntegrator<Scalar>::m_inverse_mass;
  using ExplicitIntegrator<Scalar>::m_x_new;
  using ExplicitIntegrator<Scalar>::m_v_new;
  using ExplicitIntegrator<Scalar>::m_pin_end;

  /// Midpoint positions and velocities, one array per component (stride-1 input of the second
  /// spring pass).
  std::vector<Scalar> m_midpoint;
  /// The midpoint as 3 x n node data, for the force terms (empty without terms).
  Matrix3X<Scalar> m_x_mid, m_v_mid;
  /// The pins' positions at the midpoint (pins().nodes() order).
  Matrix3X<Scalar> m_pin_mid;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Rk2<Scalar>::Rk2(const Cloth<Scalar>& cloth, const IntegratorOptions& options)
    : ExplicitIntegrator<Scalar>(cloth, options), m_midpoint(6 * std::size_t(cloth.node_count())) {
  if (m_forces.has_terms()) {
    m_x_mid.resize(3, cloth.node_count());
    m_v_mid.resize(3, cloth.node_count());
  }
}

template <class Scalar>
StepStatus Rk2<Scalar>::step(State<Scalar>& state) {
  this->begin_step(state);
  const Scalar dt = this->dt();
  const Index n = m_inverse_mass.size();
  const Scalar half = Scalar(0.5) * dt;
  const Scalar* x = state.positions.data();
  // q by component (copy_input), read by the node passes too.
  const NodeView<Scalar> xs = m_forces.input_positions(), vs = m_forces.input_velocities();
  Scalar* x_new = m_x_new.data();
  Scalar* v_new = m_v_new.data();
  Scalar* const x_mid[3] = {&m_midpoint[0], &m_midpoint[std::size_t(n)], &m_midpoint[2 * std::size_t(n)]};
  Scalar* const v_mid[3] = {&m_midpoint[3 * std::size_t(n)], &m_midpoint[4 * std::size_t(n)],
                            &m_midpoint[5 * std::size_t(n)]};
  const Scalar* inverse_mass = m_inverse_mass.data();
  const std::vector<int>& pins = this->pins().nodes();
  this->pins().positions(state.time + half, state.positions, m_pin_mid);
  // Pins inside [begin, end): pins are sorted.
  const auto pins_in = [&](Index begin, Index end) {
    return std::make_pair(std::lower_bound(pins.begin(), pins.end(), begin),
                          std::lower_bound(pins.begin(), pins.end(), end));
  };
  std::atomic<bool> finite{true};
  const bool terms = m_forces.has_terms();
  m_forces.evaluate_terms(state.positions, state.velocities, state.time);

  run_in_team(m_forces.threads(), [&] {
    // Midpoint: q_mid = q + dt/2 F(q).
    m_forces.copy_input(state.positions, state.velocities);
    team_barrier();
    m_forces.spring_pass(xs, vs);
    team_barrier();
    m_forces.node_pass([&](const ForceBlock<Scalar>& block) {
      const Index i0 = block.begin;
      for (int k = 0; k < 3; ++k) {
        const Scalar* f = block.f[k];
        const Scalar* xk = xs.p[k] + i0;
        const Scalar* vk = vs.p[k] + i0;
        const Scalar* w = inverse_mass + i0;
        Scalar* xm = x_mid[k] + i0;
        Scalar* vm = v_mid[k] + i0;
        DRAPE_OMP_SIMD
        for (int j = 0; j < block.count; ++j) {
          xm[j] = xk[j] + half * vk[j];
          vm[j] = vk[j] + half * (f[j] * w[j]);
        }
      }
      // Pinned nodes follow their paths whatever velocity the caller left on them.
      const auto pinned = pins_in(i0, i0 + block.count);
      for (auto p = pinned.first; p != pinned.second; ++p) {
        const Index pin = p - pins.begin();
        for (int k = 0; k < 3; ++k) {
          x_mid[k][*p] = m_pin_mid(k, pin);
          v_mid[k][*p] = (m_pin_end(k, pin) - x[3 * *p + k]) / dt;
        }
      }
    });
    team_barrier();
    if (terms) {
      team_single([&] {
        for (Index i = 0; i < n; ++i)
          for (int k = 0; k < 3; ++k) {
            m_x_mid(k, i) = x_mid[k][i];
            m_v_mid(k, i) = v_mid[k][i];
          }
      });
      m_forces.evaluate_terms_in_team(m_x_mid, m_v_mid, state.time + half);
    }
    // Full step with the midpoint slope.
    m_forces.spring_pass(NodeView<Scalar>{{x_mid[0], x_mid[1], x_mid[2]}},
                         NodeView<Scalar>{{v_mid[0], v_mid[1], v_mid[2]}});
    team_barrier();
    // NaN if any new value is not finite (0 * inf = NaN), else 0.
    Scalar probe = 0;
    m_forces.node_pass([&](const ForceBlock<Scalar>& block) {
      const Index i0 = block.begin;
      const Scalar *f0 = block.f[0], *f1 = block.f[1], *f2 = block.f[2];
      const Scalar *x0 = xs.p[0] + i0, *x1 = xs.p[1] + i0, *x2 = xs.p[2] + i0;
      const Scalar *v0 = vs.p[0] + i0, *v1 = vs.p[1] + i0, *v2 = vs.p[2] + i0;
      const Scalar *m0 = v_mid[0] + i0, *m1 = v_mid[1] + i0, *m2 = v_mid[2] + i0;
      const Scalar* w = inverse_mass + i0;
      Scalar* xn = x_new + 3 * i0;
      Scalar* vn = v_new + 3 * i0;
      Scalar block_probe = 0;
      // All three components in one loop: whole-vector stores of the interleaved results.
      DRAPE_OMP_SIMD_SUM(block_probe)
      for (int j = 0; j < block.count; ++j) {
        const Scalar y0 = x0[j] + dt * m0[j], y1 = x1[j] + dt * m1[j], y2 = x2[j] + dt * m2[j];
        const Scalar u0 = v0[j] + dt * (f0[j] * w[j]);
        const Scalar u1 = v1[j] + dt * (f1[j] * w[j]);
        const Scalar u2 = v2[j] + dt * (f2[j] * w[j]);
        xn[3 * j] = y0;
        xn[3 * j + 1] = y1;
        xn[3 * j + 2] = y2;
        vn[3 * j] = u0;
        vn[3 * j + 1] = u1;
        vn[3 * j + 2] = u2;
        block_probe += (y0 + y1 + y2) * 0 + (u0 + u1 + u2) * 0;
      }
      probe += this->finish_block(x, i0, block.count, dt, block_probe);
    });
    if (!(probe == 0)) finite.store(false, std::memory_order_relaxed);
  });

  return this->finish_step(state, finite.load(std::memory_order_relaxed));
}

}  // namespace drape
