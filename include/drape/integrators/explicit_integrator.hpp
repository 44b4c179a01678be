#pragma once
/// \file explicit_integrator.hpp
/// What the explicit integrators (Rk2, SymplecticEuler) share: the force pass (force_assembler.hpp)
/// and the inverse masses their node passes read, the step's result before it is committed, the
/// pins' positions at the end of the step, the end of each node block (pinned nodes put on their
/// paths, the finiteness probe) and the end of the step (contacts, then the result swapped in).
/// A step that computes a non-finite value fails and leaves the state unchanged.

#include <algorithm>
#include <vector>

#include "drape/core/state.hpp"
#include "drape/core/types.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"

namespace drape {

template <class Scalar = double>
class ExplicitIntegrator : public Integrator<Scalar> {
 public:
  const ForceAssembler<Scalar>& forces() const { return m_forces; }

 protected:
  /// \throws InvalidParameter as IntegratorOptions::validate().
  ExplicitIntegrator(const Cloth<Scalar>& cloth, const IntegratorOptions& options)
      : Integrator<Scalar>(cloth, options),
        m_forces(cloth, options.threads),
        m_inverse_mass(cloth.masses().cwiseInverse()),
        m_x_new(3, cloth.node_count()),
        m_v_new(3, cloth.node_count()) {}

  /// The start of a step from `state`: checks that it fits the cloth and puts the pins' positions
  /// at the end of the step, t + dt, into m_pin_end.
  /// \throws InvalidParameter as Integrator::require_state_fits().
  void begin_step(const State<Scalar>& state) {
    this->require_state_fits(state);
    this->pins().positions(state.time + this->dt(), state.positions, m_pin_end);
  }

  /// The end of the node pass for the nodes [begin, begin + count) (3 scalars each, `x` the
  /// positions at the start): the pinned ones among them end on their paths with velocity
  /// (x(t + dt) - x) / dt in m_x_new and m_v_new, whatever velocity the caller left on them.
  /// `computed_probe` is the caller's NaN probe of the block's computed values, pinned nodes
  /// included (0 if all are finite, NaN if not: 0 * inf = NaN); returns it plus the probe of the
  /// pins' values. A non-finite value computed for a pinned node fails the step too: it comes from
  /// non-finite forces or velocities, which never stay on one node.
  Scalar finish_block(const Scalar* x, Index begin, int count, Scalar dt, Scalar computed_probe) {
    const std::vector<int>& pins = this->pins().nodes();
    const Matrix3X<Scalar>& pin_end = m_pin_end;
    Scalar* x_new = m_x_new.data();
    Scalar* v_new = m_v_new.data();
    const auto first = std::lower_bound(pins.begin(), pins.end(), begin);
    const auto last = std::lower_bound(first, pins.end(), begin + count);
    Scalar probe = computed_probe;
    for (auto p = first; p != last; ++p) {
      const Index pin = p - pins.begin();
      for (int k = 0; k < 3; ++k) {
        x_new[3 * *p + k] = pin_end(k, pin);
        v_new[3 * *p + k] = (pin_end(k, pin) - x[3 * *p + k]) / dt;
        probe += x_new[3 * *p + k] * 0 + v_new[3 * *p + k] * 0;
      }
    }
    return probe;
  }

  /// The end of the step from `state` by dt(), whose node passes left the result in m_x_new and
  /// m_v_new and found every value finite or not: contacts with the colliders (an impulse to each
  /// node that reaches one, friction, the end-of-step check) and the cloth against itself, then
  /// the result is the new state. A non-finite result fails the step and leaves `state` unchanged.
  StepStatus finish_step(State<Scalar>& state, bool finite) {
    if (!finite) return {StepError::NonFiniteState, 0, 0.0};
    const Scalar dt = this->dt();
    this->respond_to_contacts(state, dt, m_x_new, m_v_new);
    state.positions.swap(m_x_new);
    state.velocities.swap(m_v_new);
    state.time += dt;
    return {};
  }

  ForceAssembler<Scalar> m_forces;
  VectorX<Scalar> m_inverse_mass;
  Matrix3X<Scalar> m_x_new, m_v_new;  // the step's result, swapped into the state at its end
  Matrix3X<Scalar> m_pin_end;         // the pins' positions at the end of the step (pins().nodes() order)
};

}  // namespace drape
