#pragma once
/// \file cloth.hpp
/// `ClothSpec`: the scene description, with documented defaults. `Cloth`: the model built from it
/// (its mesh, which is a grid by default, springs, masses, pins, gravity and any further force
/// terms), shared read-only by the assemblers and integrators. The time step belongs to the
/// integrator (integrators/integrator.hpp).

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "drape/contact/collider.hpp"
#include "drape/contact/self_collision_settings.hpp"
#include "drape/core/cloth_mesh.hpp"
#include "drape/core/force_term.hpp"
#include "drape/core/grid.hpp"
#include "drape/core/mesh_generators.hpp"
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
  /// If set, the cloth is this mesh (core/cloth_mesh.hpp) instead of the nx x ny grid, and nx, ny
  /// and spacing are unused. The boundary presets name grid corners: a mesh cloth that is not a
  /// lattice (grid_mesh()) has only the `pinned_nodes` pinned.
  std::optional<ClothMesh<Scalar>> mesh;
  /// kg/m^2: if set, every node weighs its share of the rest area (a third of each triangle
  /// around it) times this, instead of `node_mass`.
  std::optional<Scalar> areal_density;
  /// Forces besides springs and gravity (core/force_term.hpp); none by default.
  std::vector<std::shared_ptr<const ForceTerm<Scalar>>> force_terms;
  /// Rigid bodies the cloth collides with (contact/collider.hpp); none by default.
  std::vector<Collider<Scalar>> colliders;
  /// m: the cloth's half-thickness; nodes rest this far from a collider's surface.
  Scalar contact_thickness = Scalar(0.005);
  /// The cloth against itself (contact/self_collision_settings.hpp); off by default. Its joined
  /// nodes are this cloth's node ids.
  SelfCollisionSettings<Scalar> self_collision;
  /// Where the flat grid starts (core/placement.hpp); by default node 0 at the origin, in the x-z plane.
  Placement<Scalar> placement;

  static constexpr SpringCoefficients<Scalar> default_springs() {
    return {{Scalar(20000), Scalar(10)}, {Scalar(5000), Scalar(5)}, {Scalar(500), Scalar(1)}};
  }

  /// \throws InvalidParameter naming the first invalid parameter.
  void validate() const {
    if (mesh) {
      mesh->validate("mesh");
      detail::require_positive_finite("node_mass", node_mass);
    } else {
      Grid<Scalar>::validate(nx, ny, spacing, node_mass);
    }
    if (areal_density) detail::require_positive_finite("areal_density", *areal_density);
    detail::require_nonnegative_finite("gravity", gravity);
    springs.validate();
    if (pinned_nodes)
      Pins::validate(*pinned_nodes, mesh ? mesh->vertex_count() : nx * ny);
    else
      Pins::validate(boundary);
    for (const auto& term : force_terms)
      if (!term) detail::fail_argument("force_terms", "a null pointer", "force terms that exist");
    detail::require_nonnegative_finite("contact thickness", contact_thickness);
    self_collision.validate(mesh ? mesh->vertex_count() : nx * ny);
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

  /// True if the cloth is a grid (a grid spec, or a lattice mesh): grid() is then valid, and the
  /// force pass and multigrid use the lattice.
  bool is_grid() const { return m_grid.has_value(); }
  /// The grid of a grid cloth. \throws std::logic_error for a cloth that is not a grid.
  const Grid<Scalar>& grid() const {
    if (!m_grid) throw std::logic_error("drape: Cloth::grid() of a cloth that is not a grid (use mesh())");
    return *m_grid;
  }
  /// The cloth's mesh: the grid's as grid_mesh() makes it, or the spec's.
  const ClothMesh<Scalar>& mesh() const { return m_mesh; }
  /// Triangles of the mesh (a quad counts as two), counter-clockwise seen from the front.
  const std::vector<std::array<int, 3>>& triangles() const { return m_triangles; }
  /// kg, one per node; the mass matrix is `diag(m_0, m_0, m_0, m_1, ...)`.
  const VectorX<Scalar>& masses() const { return m_masses; }
  /// What ClothMesh::validate() found harmless but odd (e.g. nodes in no face, which stay pinned).
  const std::vector<std::string>& warnings() const { return m_warnings; }
  const SpringSet<Scalar>& springs() const { return m_springs; }
  const Pins& pins() const { return m_pins; }
  /// Gravitational acceleration vector (m/s^2).
  const Vec3<Scalar>& gravity() const { return m_gravity; }
  /// Forces besides springs and gravity, in the order they are added.
  const std::vector<std::shared_ptr<const ForceTerm<Scalar>>>& force_terms() const { return m_force_terms; }
  int node_count() const { return static_cast<int>(m_masses.size()); }
  const std::vector<Collider<Scalar>>& colliders() const { return m_colliders; }
  /// m: nodes rest this far from a collider's surface.
  Scalar contact_thickness() const { return m_contact_thickness; }
  /// How the cloth collides with itself.
  const SelfCollisionSettings<Scalar>& self_collision() const { return m_self_collision; }
  /// m: how much deeper than the thickness a node may end a step before the end-of-step check
  /// pushes it out (contact/contact_handler.hpp): 1% of the thickness, or rounding.
  Scalar contact_tolerance() const { return detail::contact_tolerance(m_contact_thickness); }

  /// Node positions at the start: the flat grid or the mesh's positions, placed.
  const Matrix3X<Scalar>& start_positions() const { return m_start_positions; }

  /// The model's start: undeformed and flat where its placement puts it (by default horizontal at
  /// height 0), at rest, t = 0.
  State<Scalar> initial_state() const {
    State<Scalar> s;
    s.positions = m_start_positions;
    s.velocities = Matrix3X<Scalar>::Zero(3, node_count());
    return s;
  }

 private:
  std::optional<Grid<Scalar>> m_grid;
  ClothMesh<Scalar> m_mesh;
  std::vector<std::array<int, 3>> m_triangles;
  VectorX<Scalar> m_masses;
  std::vector<std::string> m_warnings;
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

namespace detail {
/// The spec's grid: that of a grid spec or of a lattice mesh, none for another mesh.
template <class Scalar>
std::optional<Grid<Scalar>> grid_of(const ClothSpec<Scalar>& spec) {
  spec.validate();
  if (!spec.mesh) return Grid<Scalar>(spec.nx, spec.ny, spec.spacing, spec.node_mass);
  if (const auto& l = spec.mesh->lattice) return Grid<Scalar>(l->nx, l->ny, l->spacing, spec.node_mass);
  return std::nullopt;
}

/// The nodes of `mask` (nonzero entries) together with `nodes`, for Pins.
inline std::vector<int> with_nodes(std::vector<int> nodes, const std::vector<char>& mask) {
  for (std::size_t v = 0; v < mask.size(); ++v)
    if (mask[v]) nodes.push_back(static_cast<int>(v));
  return nodes;
}
}  // namespace detail

template <class Scalar>
Cloth<Scalar>::Cloth(const ClothSpec<Scalar>& spec)
    : m_grid(detail::grid_of(spec)),
      m_mesh(spec.mesh ? *spec.mesh : grid_mesh(spec.nx, spec.ny, spec.spacing)),
      m_triangles(m_mesh.all_triangles()),
      m_masses(m_grid && !spec.areal_density ? m_grid->masses()
                                              : VectorX<Scalar>::Constant(m_mesh.vertex_count(), spec.node_mass)),
      m_warnings(spec.mesh ? spec.mesh->validate("mesh") : std::vector<std::string>{}),
      m_springs(m_mesh, spec.springs),
      m_gravity(Scalar(0), -spec.gravity, Scalar(0)),
      m_force_terms(spec.force_terms),
      m_colliders(spec.colliders),
      m_contact_thickness(spec.contact_thickness),
      m_self_collision(spec.self_collision),
      m_start_positions(spec.placement.apply(m_mesh.positions)) {
  if (spec.areal_density) {
    const VectorX<Scalar> area = m_mesh.vertex_areas();
    for (Index v = 0; v < area.size(); ++v)
      if (area[v] > 0) m_masses[v] = area[v] * *spec.areal_density;
  }
  // Nodes in no face have no springs: held where they are.
  std::vector<char> unused(static_cast<std::size_t>(node_count()), 1);
  for (const std::array<int, 3>& t : m_triangles)
    for (int v : t) unused[static_cast<std::size_t>(v)] = 0;
  std::vector<int> pinned;
  if (spec.pinned_nodes)
    pinned = *spec.pinned_nodes;
  else if (m_grid)
    pinned = Pins::preset(spec.boundary, *m_grid).nodes();
  m_pins = Pins(detail::with_nodes(std::move(pinned), unused), node_count());
  require_pins_clear_of_colliders();
}

template <class Scalar>
Cloth<Scalar>::Cloth(Grid<Scalar> grid, SpringSet<Scalar> springs, Pins pins, const Vec3<Scalar>& gravity,
                     std::vector<std::shared_ptr<const ForceTerm<Scalar>>> force_terms,
                     std::vector<Collider<Scalar>> colliders, Scalar contact_thickness,
                     SelfCollisionSettings<Scalar> self_collision, const Placement<Scalar>& placement)
    : m_grid(std::move(grid)),
      m_mesh(grid_mesh(m_grid->nx(), m_grid->ny(), m_grid->spacing())),
      m_triangles(m_mesh.all_triangles()),
      m_masses(m_grid->masses()),
      m_springs(std::move(springs)),
      m_pins(std::move(pins)),
      m_gravity(gravity),
      m_force_terms(std::move(force_terms)),
      m_colliders(std::move(colliders)),
      m_contact_thickness(contact_thickness),
      m_self_collision(self_collision) {
  placement.validate();
  m_start_positions = placement.apply(m_mesh.positions);
  if (m_pins.mask().size() != static_cast<std::size_t>(node_count()))
    detail::fail_argument("pins", "a pin set for " + detail::to_text(m_pins.mask().size()) + " nodes",
                          "a pin set built for this grid's " + detail::to_text(node_count()) + " nodes");
  if (!m_gravity.allFinite()) detail::fail_argument("gravity", "non-finite vector", "finite");
  for (const auto& term : m_force_terms)
    if (!term) detail::fail_argument("force_terms", "a null pointer", "force terms that exist");
  detail::require_nonnegative_finite("contact thickness", m_contact_thickness);
  m_self_collision.validate(node_count());
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
