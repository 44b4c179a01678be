#pragma once
/// \file cloth.hpp
/// `ClothSpec`: the scene description, with documented defaults. `Cloth`: the model built from it
/// (grid, springs, pins, gravity and any further force terms), shared read-only by the assemblers
/// and integrators. The time step belongs to the integrator (integrators/integrator.hpp).

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "drape/contact/collider.hpp"
#include "drape/contact/self_collision_settings.hpp"
#include "drape/core/force_term.hpp"
#include "drape/core/grid.hpp"
#include "drape/core/pins.hpp"
#include "drape/core/placement.hpp"
#include "drape/core/spring_set.hpp"
#include "drape/core/state.hpp"

namespace drape {

/// Everything that defines a scene. Defaults: the course model's cloth (33 x 33 nodes, 0.1 m apart,
/// 0.03 kg each, g = 10 m/s^2, two corners pinned) with the spring constants chosen in
/// drape's parameters.md.
template <class Scalar = double>
struct ClothSpec {
  int nx = 33;
  int ny = 33;
  Scalar spacing = Scalar(0.1);     ///< m
  Scalar node_mass = Scalar(0.03);  ///< kg
  Scalar gravity = Scalar(10);      ///< m/s^2, acting along -y
  SpringCoefficients<Scalar> springs = default_springs();
  BoundaryCondition boundary = BoundaryCondition::TwoCorners;
  /// If set, these node ids are pinned instead of the `boundary` preset.
  std::optional<std::vector<int>> pinned_nodes;
  /// Forces besides springs and gravity (core/force_term.hpp); none by default.
  std::vector<std::shared_ptr<const ForceTerm<Scalar>>> force_terms;
  /// Rigid bodies the cloth collides with (contact/collider.hpp); none by default.
  std::vector<Collider<Scalar>> colliders;
  /// m: the cloth's half-thickness; nodes rest this far from a collider's surface.
  Scalar contact_thickness = Scalar(0.005);
  /// The cloth against itself (contact/self_collision_settings.hpp); off by default.
  SelfCollisionSettings<Scalar> self_collision;
  /// Where the flat grid starts (core/placement.hpp); by default node 0 at the origin, in the x-z plane.
  Placement<Scalar> placement;

  static constexpr SpringCoefficients<Scalar> default_springs() {
    return {{Scalar(20000), Scalar(10)}, {Scalar(5000), Scalar(5)}, {Scalar(500), Scalar(1)}};
  }

  /// \throws InvalidParameter naming the first invalid parameter.
  void validate() const {
    Grid<Scalar>::validate(nx, ny, spacing, node_mass);
    detail::require_nonnegative_finite("gravity", gravity);
    springs.validate();
    if (pinned_nodes)
      Pins::validate(*pinned_nodes, nx * ny);
    else
      Pins::validate(boundary);
    for (const auto& term : force_terms)
      if (!term) detail::fail_argument("force_terms", "a null pointer", "force terms that exist");
    detail::require_nonnegative_finite("contact thickness", contact_thickness);
    self_collision.validate();
    if (self_collision.enabled && !(contact_thickness > 0))
      detail::fail_argument("contact thickness", "0 with self-collision on", "> 0 (layers keep twice it apart)");
    placement.validate();
  }
};

template <class Scalar = double>
class Cloth {
 public:
  /// \throws InvalidParameter naming the first invalid parameter of `spec`.
  explicit Cloth(const ClothSpec<Scalar>& spec);

  Cloth(Grid<Scalar> grid, SpringSet<Scalar> springs, Pins pins, const Vec3<Scalar>& gravity,
        std::vector<std::shared_ptr<const ForceTerm<Scalar>>> force_terms = {},
        std::vector<Collider<Scalar>> colliders = {}, Scalar contact_thickness = Scalar(0.005),
        SelfCollisionSettings<Scalar> self_collision = {}, const Placement<Scalar>& placement = {});

  const Grid<Scalar>& grid() const { return m_grid; }
  const SpringSet<Scalar>& springs() const { return m_springs; }
  const Pins& pins() const { return m_pins; }
  /// Gravitational acceleration vector (m/s^2).
  const Vec3<Scalar>& gravity() const { return m_gravity; }
  /// Forces besides springs and gravity, in the order they are added.
  const std::vector<std::shared_ptr<const ForceTerm<Scalar>>>& force_terms() const { return m_force_terms; }
  int node_count() const { return m_grid.node_count(); }
  const std::vector<Collider<Scalar>>& colliders() const { return m_colliders; }
  /// m: nodes rest this far from a collider's surface.
  Scalar contact_thickness() const { return m_contact_thickness; }
  /// How the cloth collides with itself.
  const SelfCollisionSettings<Scalar>& self_collision() const { return m_self_collision; }
  /// m: how much deeper than the thickness a node may end a step before the end-of-step check
  /// pushes it out (contact/contact_handler.hpp): 1% of the thickness, or rounding.
  Scalar contact_tolerance() const { return detail::contact_tolerance(m_contact_thickness); }

  /// Node positions at the start: the flat grid, placed.
  const Matrix3X<Scalar>& start_positions() const { return m_start_positions; }

  /// The model's start: undeformed and flat where its placement puts it (by default horizontal at
  /// height 0), at rest, t = 0.
  State<Scalar> initial_state() const {
    State<Scalar> s;
    s.positions = m_start_positions;
    s.velocities = Matrix3X<Scalar>::Zero(3, m_grid.node_count());
    return s;
  }

 private:
  Grid<Scalar> m_grid;
  SpringSet<Scalar> m_springs;
  Pins m_pins;
  Vec3<Scalar> m_gravity;
  std::vector<std::shared_ptr<const ForceTerm<Scalar>>> m_force_terms;
  std::vector<Collider<Scalar>> m_colliders;
  Scalar m_contact_thickness;
  SelfCollisionSettings<Scalar> m_self_collision;
  Matrix3X<Scalar> m_start_positions;

  /// \throws InvalidParameter naming `colliders[k]` if a pinned node starts closer than the
  /// contact thickness to collider k (it could never be pushed out).
  void require_pins_clear_of_colliders() const;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Cloth<Scalar>::Cloth(const ClothSpec<Scalar>& spec)
    : m_grid((spec.validate(), Grid<Scalar>(spec.nx, spec.ny, spec.spacing, spec.node_mass))),
      m_springs(m_grid, spec.springs),
      m_pins(spec.pinned_nodes ? Pins(*spec.pinned_nodes, m_grid.node_count()) : Pins::preset(spec.boundary, m_grid)),
      m_gravity(Scalar(0), -spec.gravity, Scalar(0)),
      m_force_terms(spec.force_terms),
      m_colliders(spec.colliders),
      m_contact_thickness(spec.contact_thickness),
      m_self_collision(spec.self_collision),
      m_start_positions(spec.placement.apply(m_grid.rest_positions())) {
  require_pins_clear_of_colliders();
}

template <class Scalar>
Cloth<Scalar>::Cloth(Grid<Scalar> grid, SpringSet<Scalar> springs, Pins pins, const Vec3<Scalar>& gravity,
                     std::vector<std::shared_ptr<const ForceTerm<Scalar>>> force_terms,
                     std::vector<Collider<Scalar>> colliders, Scalar contact_thickness,
                     SelfCollisionSettings<Scalar> self_collision, const Placement<Scalar>& placement)
    : m_grid(std::move(grid)),
      m_springs(std::move(springs)),
      m_pins(std::move(pins)),
      m_gravity(gravity),
      m_force_terms(std::move(force_terms)),
      m_colliders(std::move(colliders)),
      m_contact_thickness(contact_thickness),
      m_self_collision(self_collision) {
  placement.validate();
  m_start_positions = placement.apply(m_grid.rest_positions());
  if (m_pins.mask().size() != static_cast<std::size_t>(m_grid.node_count()))
    detail::fail_argument("pins", "a pin set for " + detail::to_text(m_pins.mask().size()) + " nodes",
                          "a pin set built for this grid's " + detail::to_text(m_grid.node_count()) + " nodes");
  if (!m_gravity.allFinite()) detail::fail_argument("gravity", "non-finite vector", "finite");
  for (const auto& term : m_force_terms)
    if (!term) detail::fail_argument("force_terms", "a null pointer", "force terms that exist");
  detail::require_nonnegative_finite("contact thickness", m_contact_thickness);
  m_self_collision.validate();
  if (m_self_collision.enabled && !(m_contact_thickness > 0))
    detail::fail_argument("contact thickness", "0 with self-collision on", "> 0 (layers keep twice it apart)");
  require_pins_clear_of_colliders();
}

template <class Scalar>
void Cloth<Scalar>::require_pins_clear_of_colliders() const {
  const Matrix3X<Scalar>& x = m_start_positions;
  for (std::size_t k = 0; k < m_colliders.size(); ++k)
    for (int p : m_pins.nodes())
      if (m_colliders[k].query(x.col(p), Scalar(0)).distance < m_contact_thickness)
        detail::fail_argument("colliders[" + detail::to_text(k) + "]",
                              "a collider touching pinned node " + detail::to_text(p) + " at the start",
                              "colliders clear of every pinned node by the contact thickness");
}

}  // namespace drape
