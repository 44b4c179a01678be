#pragma once
/// \file cloth.hpp
/// `ClothSpec`: the scene description with the brief's defaults. `Cloth`: the model built from it
/// (grid, springs, pins, gravity), shared read-only by assemblers and integrators.

#include <optional>
#include <vector>

#include "drape/core/grid.hpp"
#include "drape/core/pins.hpp"
#include "drape/core/spring_set.hpp"
#include "drape/core/state.hpp"

namespace drape {

/// Everything that defines a scene. Defaults are the brief's cloth (33 x 33 nodes, 0.1 m apart,
/// 0.03 kg each, g = 10 m/s^2) with the spring constants and time step chosen in
/// docs/parameters.md.
template <class Scalar = double>
struct ClothSpec {
  int nx = 33;
  int ny = 33;
  Scalar spacing = Scalar(0.1);    ///< m
  Scalar node_mass = Scalar(0.03); ///< kg
  Scalar gravity = Scalar(10);     ///< m/s^2, acting along -y
  SpringCoefficients<Scalar> springs = default_springs();
  BoundaryCondition boundary = BoundaryCondition::TwoCorners;
  /// If set, these node ids are pinned instead of the `boundary` preset.
  std::optional<std::vector<int>> pinned_nodes;
  Scalar dt = default_dt();  ///< s

  static constexpr SpringCoefficients<Scalar> default_springs() {
    return {{Scalar(20000), Scalar(10)}, {Scalar(5000), Scalar(5)}, {Scalar(500), Scalar(1)}};
  }
  static constexpr Scalar default_dt() { return Scalar(0.0005); }

  /// \throws std::invalid_argument naming the first invalid parameter.
  void validate() const {
    detail::require_at_least("nx", nx, 2);
    detail::require_at_least("ny", ny, 2);
    detail::require_positive_finite("spacing", spacing);
    detail::require_positive_finite("node_mass", node_mass);
    detail::require_nonnegative_finite("gravity", gravity);
    detail::require_positive_finite("dt", dt);
    springs.validate();
  }
};

template <class Scalar = double>
class Cloth {
 public:
  /// \throws std::invalid_argument naming the first invalid parameter of `spec`.
  explicit Cloth(const ClothSpec<Scalar>& spec)
      : m_grid((spec.validate(), Grid<Scalar>(spec.nx, spec.ny, spec.spacing, spec.node_mass))),
        m_springs(m_grid, spec.springs),
        m_pins(spec.pinned_nodes ? Pins(*spec.pinned_nodes, m_grid.node_count()) : Pins::preset(spec.boundary, m_grid)),
        m_gravity(Scalar(0), -spec.gravity, Scalar(0)) {}

  Cloth(Grid<Scalar> grid, SpringSet<Scalar> springs, Pins pins, const Vec3<Scalar>& gravity)
      : m_grid(std::move(grid)), m_springs(std::move(springs)), m_pins(std::move(pins)), m_gravity(gravity) {
    if (m_pins.mask().size() != static_cast<std::size_t>(m_grid.node_count()))
      detail::fail_argument("pins", "a pin set for " + detail::to_text(m_pins.mask().size()) + " nodes",
                            "a pin set built for this grid's " + detail::to_text(m_grid.node_count()) + " nodes");
    if (!m_gravity.allFinite()) detail::fail_argument("gravity", "non-finite vector", "finite");
  }

  const Grid<Scalar>& grid() const { return m_grid; }
  const SpringSet<Scalar>& springs() const { return m_springs; }
  const Pins& pins() const { return m_pins; }
  /// Gravitational acceleration vector (m/s^2).
  const Vec3<Scalar>& gravity() const { return m_gravity; }
  int node_count() const { return m_grid.node_count(); }

  /// The brief's start: undeformed, flat, horizontal, at rest, t = 0.
  State<Scalar> initial_state() const {
    State<Scalar> s;
    s.positions = m_grid.rest_positions();
    s.velocities = Matrix3X<Scalar>::Zero(3, m_grid.node_count());
    return s;
  }

 private:
  Grid<Scalar> m_grid;
  SpringSet<Scalar> m_springs;
  Pins m_pins;
  Vec3<Scalar> m_gravity;
};

}  // namespace drape
