#pragma once
/// \file symplectic_euler.hpp
/// Symplectic (semi-implicit) Euler:
/// \f[ v_{t+1} = v_t + \Delta t\, M^{-1} f(x_t, v_t), \qquad x_{t+1} = x_t + \Delta t\, v_{t+1}. \f]
/// The explicit scheme most cloth simulators use: one force pass per step (RK2 takes two), first
/// order, and symplectic for the conservative part of the force, so an undamped cloth's energy
/// oscillates around its true value instead of drifting (its stable dt is also larger than the
/// midpoint rule's for springs with little damping: docs/parameters.md). RK2 stays the default.
/// Pinned nodes end the step on their path with velocity (x(t + dt) - x) / dt, as in RK2; contacts
/// with colliders are resolved on the step's result (contact/contact_handler.hpp).
///
/// One step is one parallel region with two barriers: x and v copied by component, the spring pass,
/// then the node pass fused with the update and the finiteness check (force_assembler.hpp).
/// Bitwise identical for any thread count. Force terms are evaluated at (x_t, v_t, t) before it.

#include <atomic>

#include "drape/integrators/explicit_integrator.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/platform/team.hpp"

namespace drape {

template <class Scalar = double>
class SymplecticEuler final : public ExplicitIntegrator<Scalar> {
 public:
  /// \throws InvalidParameter as IntegratorOptions::validate().
  explicit SymplecticEuler(const Cloth<Scalar>& cloth, const IntegratorOptions& options = {})
      : ExplicitIntegrator<Scalar>(cloth, options) {}
  /// The integrator keeps a reference to the cloth: a temporary would dangle.
  SymplecticEuler(const Cloth<Scalar>&& cloth, const IntegratorOptions& options = {}) = delete;

  StepStatus step(State<Scalar>& state) override;

 private:
  using ExplicitIntegrator<Scalar>::m_forces;
  using ExplicitIntegrator<Scalar>::m_inverse_mass;
  using ExplicitIntegrator<Scalar>::m_x_new;
  using ExplicitIntegrator<Scalar>::m_v_new;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
StepStatus SymplecticEuler<Scalar>::step(State<Scalar>& state) {
  this->begin_step(state);
  const Scalar dt = this->dt();
  const Scalar* x = state.positions.data();
  // x and v by component (copy_input), read by the node pass too.
  const NodeView<Scalar> xs = m_forces.input_positions(), vs = m_forces.input_velocities();
  Scalar* x_new = m_x_new.data();
  Scalar* v_new = m_v_new.data();
  const Scalar* inverse_mass = m_inverse_mass.data();
  std::atomic<bool> finite{true};
  m_forces.evaluate_terms(state.positions, state.velocities, state.time);

  run_in_team(m_forces.threads(), [&] {
    m_forces.copy_input(state.positions, state.velocities);
    team_barrier();
    m_forces.spring_pass(xs, vs);
    team_barrier();
    Scalar probe = 0;  // NaN if any new value is not finite (0 * inf = NaN), else 0
    m_forces.node_pass([&](const ForceBlock<Scalar>& block) {
      const Index i0 = block.begin;
      const Scalar *f0 = block.f[0], *f1 = block.f[1], *f2 = block.f[2];
      const Scalar *x0 = xs.p[0] + i0, *x1 = xs.p[1] + i0, *x2 = xs.p[2] + i0;
      const Scalar *v0 = vs.p[0] + i0, *v1 = vs.p[1] + i0, *v2 = vs.p[2] + i0;
      const Scalar* w = inverse_mass + i0;
      Scalar* xn = x_new + 3 * i0;
      Scalar* vn = v_new + 3 * i0;
      Scalar block_probe = 0;
      // All three components in one loop: whole-vector stores of the interleaved results. The
      // position moves with the new velocity: symplectic.
      DRAPE_OMP_SIMD_SUM(block_probe)
      for (int j = 0; j < block.count; ++j) {
        const Scalar u0 = v0[j] + dt * (f0[j] * w[j]);
        const Scalar u1 = v1[j] + dt * (f1[j] * w[j]);
        const Scalar u2 = v2[j] + dt * (f2[j] * w[j]);
        vn[3 * j] = u0;
        vn[3 * j + 1] = u1;
        vn[3 * j + 2] = u2;
        const Scalar y0 = x0[j] + dt * u0, y1 = x1[j] + dt * u1, y2 = x2[j] + dt * u2;
        xn[3 * j] = y0;
        xn[3 * j + 1] = y1;
        xn[3 * j + 2] = y2;
        block_probe += (y0 + y1 + y2) * 0 + (u0 + u1 + u2) * 0;
      }
      probe += this->finish_block(x, i0, block.count, dt, block_probe);
    });
    if (!(probe == 0)) finite.store(false, std::memory_order_relaxed);
  });

  return this->finish_step(state, finite.load(std::memory_order_relaxed));
}

}  // namespace drape
