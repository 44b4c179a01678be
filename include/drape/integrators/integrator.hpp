#pragma once
/// \file integrator.hpp
/// What every time integrator shares: the cloth it advances, its time step (the integrator is the
/// step's one owner: set at construction, changed with set_dt(), checked in one place) and
/// `step(state)`. `IntegratorOptions` are the settings every integrator takes; the implicit one
/// adds its own (implicit_euler.hpp). make_integrator.hpp builds one by kind.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "drape/contact/contact_handler.hpp"
#include "drape/contact/self_collision.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/core/pin_set.hpp"
#include "drape/core/state.hpp"
#include "drape/core/validation.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/model/cloth.hpp"
#include "drape/platform/team.hpp"

namespace drape {

enum class IntegratorKind : std::uint8_t {
  Rk2 = 0,         ///< explicit midpoint rule (rk2.hpp)
  Implicit = 1,    ///< linearised implicit Euler (implicit_euler.hpp)
  Symplectic = 2,  ///< symplectic (semi-implicit) Euler (symplectic_euler.hpp)
};

template <>
struct EnumNames<IntegratorKind> {
  static constexpr const char* parameter = "integrator";
  static constexpr std::array<EnumName<IntegratorKind>, 3> values{{{IntegratorKind::Rk2, "rk2"},
                                                                   {IntegratorKind::Implicit, "implicit"},
                                                                   {IntegratorKind::Symplectic, "symplectic"}}};
};

struct IntegratorOptions {
  /// Time step (s). The default suits the explicit integrators with the default springs (drape's
  /// parameters.md); the implicit step is stable far beyond it.
  double dt = 0.0005;
  int threads = 0;  ///< 0 = all available

  /// \throws InvalidParameter naming `dt` (finite and > 0) or `threads` (>= 0).
  void validate() const {
    detail::require_time_step(dt);
    detail::require_at_least("threads", threads, 0);
  }
};

template <class Scalar = double>
class Integrator {
 public:
  virtual ~Integrator() = default;
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  /// Advances `state` by dt(). On failure `state` is unchanged and the status says why.
  /// \throws InvalidParameter if the state does not have one column per node of the cloth.
  virtual StepStatus step(State<Scalar>& state) = 0;

  /// The time step (s).
  Scalar dt() const { return m_dt; }
  /// \throws InvalidParameter naming `dt` unless it is finite and > 0.
  void set_dt(Scalar dt) {
    detail::require_time_step(dt);
    m_dt = dt;
  }
  const Cloth<Scalar>& cloth() const { return *m_cloth; }
  /// The pins of this run: the cloth's at the start, holding still; pin, move and release nodes
  /// between steps (core/pin_set.hpp). A pinned node ends each step on its path.
  PinSet<Scalar>& pins() { return m_pins; }
  const PinSet<Scalar>& pins() const { return m_pins; }
  /// The contacts with the cloth's colliders (which nodes they held in the last step).
  const ContactHandler<Scalar>& contact_handler() const { return m_contacts; }
  /// The colliders' end-of-step check (ContactHandler::keep_clear) again, on a result moved after
  /// the step (a ClothScene's pushes between its cloths).
  /// Returns the nodes it pushed out.
  int keep_clear(Ref3X<Scalar> x_new, Ref3X<Scalar> v_new) { return m_contacts.keep_clear(x_new, v_new, m_pins.mask()); }
  /// What the cloth's contacts did in the last step (empty without colliders).
  const ContactReport<Scalar>& contact_report() const { return m_contacts.report(); }
  /// What the cloth's self-collision did in the last step (empty when it is off).
  const SelfCollisionReport& self_collision_report() const { return m_self_collisions.report(); }

 protected:
  /// \throws InvalidParameter as IntegratorOptions::validate().
  Integrator(const Cloth<Scalar>& cloth, const IntegratorOptions& options)
      : m_cloth(&cloth),
        m_dt((options.validate(), Scalar(options.dt))),
        m_pins(cloth.pins()),
        m_contacts(cloth.colliders(), cloth.contact_thickness(), cloth.masses()),
        m_self_collisions(cloth.self_collision(), cloth.contact_thickness(), cloth.triangles(),
                          cloth.masses(), cloth.start_positions()) {
    set_dt(m_dt);  // the conversion to Scalar must not make it 0 or infinite
  }

  /// \throws InvalidParameter naming `state` unless it has one column per node.
  void require_state_fits(const State<Scalar>& state) const {
    const Index n = m_cloth->node_count();
    if (state.positions.cols() != n || state.velocities.cols() != n)
      detail::fail_argument("state", detail::to_text(state.positions.cols()) + " nodes",
                            detail::to_text(n) + " nodes (the cloth's)");
  }

  /// The contacts with the cloth's colliders: constraints and responses, the same for every integrator.
  ContactHandler<Scalar>& contacts() { return m_contacts; }

  /// The end of every integrator's step, on its result `x_new`, `v_new` from `state`: contacts
  /// with the colliders, then the cloth against itself, then the colliders' end-of-step check.
  void respond_to_contacts(const State<Scalar>& state, Scalar dt, Matrix3X<Scalar>& x_new, Matrix3X<Scalar>& v_new) {
    m_contacts.respond(state.positions, state.velocities, state.time, dt, x_new, v_new, m_pins.mask());
#ifndef DRAPE_BUILD_WITHOUT_SELF_COLLISION  // defined only by the test that off changes nothing
    if (m_self_collisions.active()) {
      m_self_collisions.respond_and_keep_clear(
          state.positions, dt, x_new, v_new, m_pins.mask(), [this](int i) { return m_contacts.hold(i); },
          [this](Ref3X<Scalar> x1, Ref3X<Scalar> v1) { return m_contacts.keep_clear(x1, v1, m_pins.mask()); });
      return;
    }
#endif
    m_contacts.keep_clear(x_new, v_new, m_pins.mask());
  }

 private:
  const Cloth<Scalar>* m_cloth;
  Scalar m_dt;
  PinSet<Scalar> m_pins;
  ContactHandler<Scalar> m_contacts;
  SelfCollisionHandler<Scalar> m_self_collisions;
};

}  // namespace drape
