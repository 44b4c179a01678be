#pragma once
/// \file cloth_scene.hpp
/// Several cloths in one scene, stepped together. Each cloth keeps its own model (grid, springs,
/// pins, colliders, placement: model/cloth.hpp) and its own integrator; one step advances every
/// cloth by the same dt, then one collision handler (contact/self_collision.hpp) treats all the
/// cloths as one mesh: contacts within a cloth and between cloths are the same pairs, found by
/// one hierarchy, resolved by the same three stages. The handler runs after each cloth's step
/// and its colliders, as it does inside a single cloth's step, so a scene of one cloth with
/// collisions on gives the bits of that cloth stepped alone with self-collision on.

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "drape/contact/self_collision.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/model/cloth.hpp"

namespace drape {

template <class Scalar = double>
class ClothScene {
 public:
  /// Builds a cloth and an integrator of `kind` per spec. With `collisions.enabled`, the scene's
  /// handler takes every cloth-cloth contact (the cloths' own self_collision settings are then
  /// not used but for their joined nodes, which it joins too; layers keep twice the largest
  /// contact thickness apart; `collisions.joined_nodes` are ids of the scene's numbering,
  /// node_offset()); without, each cloth collides with itself as its spec says and never with the
  /// others.
  /// \throws InvalidParameter naming `cloths[k]` and the parameter, `cloths` if empty, or the
  /// parameter of `collisions` (`self joined nodes[k]` for ids outside the scene's nodes).
  ClothScene(const std::vector<ClothSpec<Scalar>>& cloths, IntegratorKind kind, const ImplicitOptions& options,
             const SelfCollisionSettings<Scalar>& collisions);

  int cloth_count() const { return static_cast<int>(m_cloths.size()); }
  const Cloth<Scalar>& cloth(int k) const { return *m_cloths[std::size_t(k)]; }
  Integrator<Scalar>& integrator(int k) { return *m_integrators[std::size_t(k)]; }
  const Integrator<Scalar>& integrator(int k) const { return *m_integrators[std::size_t(k)]; }
  const State<Scalar>& state(int k) const { return m_states[std::size_t(k)]; }
  State<Scalar>& state(int k) { return m_states[std::size_t(k)]; }
  /// The first node of cloth k in the scene's numbering (the handler's mesh).
  int node_offset(int k) const { return m_offset[std::size_t(k)]; }
  int node_count() const { return m_offset.back(); }

  /// Advances every cloth by dt: each cloth's integrator, then the collisions between all of
  /// them. On failure no state changes and the status is the failing cloth's (or NonFiniteState).
  StepStatus step();

  /// What the scene's collision handler did in the last step (empty when collisions are off).
  const SelfCollisionReport& collision_report() const { return m_collisions.report(); }
  /// N: the mean force the cloth-cloth contacts put on cloth k over the last step (the other
  /// cloths' push; contacts within cloth k cancel). Zero when collisions are off.
  Vec3<Scalar> contact_force_on(int k) const;

 private:
  static std::vector<ClothSpec<Scalar>> specs_for_scene(std::vector<ClothSpec<Scalar>> cloths,
                                                        const SelfCollisionSettings<Scalar>& collisions);
  static SelfCollisionHandler<Scalar> make_handler(const std::vector<std::unique_ptr<Cloth<Scalar>>>& cloths,
                                                   const SelfCollisionSettings<Scalar>& collisions);

  std::vector<std::unique_ptr<Cloth<Scalar>>> m_cloths;
  std::vector<std::unique_ptr<Integrator<Scalar>>> m_integrators;
  std::vector<State<Scalar>> m_states;
  std::vector<State<Scalar>> m_starts;  // the states at the start of the step being taken
  std::vector<int> m_offset;            // cloth k's nodes are [m_offset[k], m_offset[k + 1])
  SelfCollisionHandler<Scalar> m_collisions;
  Matrix3X<Scalar> m_x0, m_x1, m_v1;  // every cloth's start, end positions and end velocities
  std::vector<std::uint8_t> m_pinned;
  std::vector<int> m_cloth_of_node;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
std::vector<ClothSpec<Scalar>> ClothScene<Scalar>::specs_for_scene(std::vector<ClothSpec<Scalar>> cloths,
                                                                   const SelfCollisionSettings<Scalar>& collisions) {
  if (cloths.empty()) detail::fail_argument("cloths", "none", "at least one cloth");
  collisions.validate();
  for (std::size_t k = 0; k < cloths.size(); ++k) {
    try {
      cloths[k].validate();
    } catch (const InvalidParameter& e) {
      throw InvalidParameter("cloths[" + detail::to_text(k) + "]." + e.parameter(), e.value(), e.allowed());
    }
    if (collisions.enabled) cloths[k].self_collision.enabled = false;  // the scene's handler does it
  }
  return cloths;
}

template <class Scalar>
SelfCollisionHandler<Scalar> ClothScene<Scalar>::make_handler(const std::vector<std::unique_ptr<Cloth<Scalar>>>& cloths,
                                                              const SelfCollisionSettings<Scalar>& collisions) {
  Scalar thickness = 0;
  Index nodes = 0;
  for (const auto& c : cloths) {
    thickness = std::max(thickness, c->contact_thickness());
    nodes += c->node_count();
  }
  if (!collisions.enabled) return SelfCollisionHandler<Scalar>(collisions, thickness, {}, VectorX<Scalar>(), {});
  std::vector<std::array<int, 3>> triangles;
  VectorX<Scalar> masses(nodes);
  Matrix3X<Scalar> positions(3, nodes);
  SelfCollisionSettings<Scalar> settings = collisions;  // with each cloth's joined nodes
  int offset = 0;
  for (const auto& c : cloths) {
    for (std::array<int, 3> t : c->triangles())
      triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    for (std::array<int, 2> p : c->self_collision().joined_nodes)
      settings.joined_nodes.push_back({p[0] + offset, p[1] + offset});
    masses.segment(offset, c->node_count()) = c->masses();
    positions.middleCols(offset, c->node_count()) = c->start_positions();
    offset += c->node_count();
  }
  return SelfCollisionHandler<Scalar>(settings, thickness, triangles, masses, positions);
}

template <class Scalar>
ClothScene<Scalar>::ClothScene(const std::vector<ClothSpec<Scalar>>& cloths, IntegratorKind kind,
                               const ImplicitOptions& options, const SelfCollisionSettings<Scalar>& collisions)
    : m_cloths([&] {
        std::vector<std::unique_ptr<Cloth<Scalar>>> built;
        for (const ClothSpec<Scalar>& spec : specs_for_scene(cloths, collisions))
          built.push_back(std::make_unique<Cloth<Scalar>>(spec));
        return built;
      }()),
      m_collisions(make_handler(m_cloths, collisions)) {
  m_offset.push_back(0);
  for (const auto& c : m_cloths) {
    m_integrators.push_back(make_integrator(*c, kind, options));
    m_states.push_back(c->initial_state());
    m_offset.push_back(m_offset.back() + c->node_count());
  }
  m_starts = m_states;
  for (int k = 0; k < cloth_count(); ++k)
    m_cloth_of_node.insert(m_cloth_of_node.end(), std::size_t(m_cloths[std::size_t(k)]->node_count()), k);
}

template <class Scalar>
StepStatus ClothScene<Scalar>::step() {
  for (std::size_t k = 0; k < m_states.size(); ++k) {
    m_starts[k].positions = m_states[k].positions;
    m_starts[k].velocities = m_states[k].velocities;
    m_starts[k].time = m_states[k].time;
  }
  StepStatus status;
  for (std::size_t k = 0; k < m_states.size() && status.ok(); ++k) status = m_integrators[k]->step(m_states[k]);
  if (status.ok() && m_collisions.active()) {
    const Index n = node_count();
    m_x0.resize(3, n);
    m_x1.resize(3, n);
    m_v1.resize(3, n);
    m_pinned.resize(std::size_t(n));
    for (std::size_t k = 0; k < m_states.size(); ++k) {
      const Index begin = m_offset[k], count = m_cloths[k]->node_count();
      m_x0.middleCols(begin, count) = m_starts[k].positions;
      m_x1.middleCols(begin, count) = m_states[k].positions;
      m_v1.middleCols(begin, count) = m_states[k].velocities;
      const std::vector<std::uint8_t>& mask = m_integrators[k]->pins().mask();
      std::copy(mask.begin(), mask.end(), m_pinned.begin() + begin);
    }
    // The pushes between the cloths come after each cloth's own end-of-step check: check again.
    m_collisions.respond_and_keep_clear(
        m_x0, m_integrators.front()->dt(), m_x1, m_v1, m_pinned,
        [this](int i) {
          const int k = m_cloth_of_node[std::size_t(i)];
          return m_integrators[std::size_t(k)]->contact_handler().hold(i - m_offset[std::size_t(k)]);
        },
        [this](Ref3X<Scalar> x1, Ref3X<Scalar> v1) {
          int pushed = 0;
          for (std::size_t k = 0; k < m_states.size(); ++k) {
            const Index begin = m_offset[k], count = m_cloths[k]->node_count();
            pushed += m_integrators[k]->keep_clear(x1.middleCols(begin, count), v1.middleCols(begin, count));
          }
          return pushed;
        });
    if (!(m_x1.allFinite() && m_v1.allFinite())) status.error = StepError::NonFiniteState;
    for (std::size_t k = 0; k < m_states.size() && status.ok(); ++k) {
      const Index begin = m_offset[k], count = m_cloths[k]->node_count();
      m_states[k].positions = m_x1.middleCols(begin, count);
      m_states[k].velocities = m_v1.middleCols(begin, count);
    }
  }
  if (!status.ok())
    for (std::size_t k = 0; k < m_states.size(); ++k) {
      m_states[k].positions = m_starts[k].positions;
      m_states[k].velocities = m_starts[k].velocities;
      m_states[k].time = m_starts[k].time;
    }
  return status;
}

template <class Scalar>
Vec3<Scalar> ClothScene<Scalar>::contact_force_on(int k) const {
  if (!m_collisions.active()) return Vec3<Scalar>::Zero();
  return m_collisions.received_momentum().middleCols(m_offset[std::size_t(k)], cloth(k).node_count()).rowwise().sum() /
         m_integrators.front()->dt();
}

}  // namespace drape
