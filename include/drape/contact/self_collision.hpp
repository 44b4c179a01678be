#pragma once
/// \file self_collision.hpp
/// The cloth against itself, after the step and its colliders, the same for every integrator
/// (Bridson, Fedkiw & Anderson 2002; drape's contact.md has the derivation and the limits).
///
/// The step moved every node on a straight path from x0 (start) to x1 (end). The handler changes
/// the ends x1 (and the velocities by the same amount over dt where momentum changes) in three stages,
/// each on vertex-triangle and edge-edge pairs that share no node (nodes joined by
/// `SelfCollisionSettings::joined_nodes`, the sides of a seam, count as one node), found by a
/// bounding volume hierarchy over the triangles (collision/bounding_volume_hierarchy.hpp):
///  1. **Proximity**: a pair closer than the layer distance 2h at the start (h = the cloth's
///     half-thickness) may not come closer during the step along its start normal n (an inelastic
///     impulse, with Coulomb friction on the relative tangential motion), and is pushed a fraction
///     of the way back to 2h (a position change only, so layers do not bounce apart).
///  2. **Collisions**: continuous tests of every pair's straight paths
///     (collision/continuous_collision.hpp); a pair that crosses gets an inelastic impulse along the
///     normal at the impact so that it ends a small gap apart on its starting side; repeated
///     while new crossings appear, at most `SelfCollisionSettings::impulse_rounds` times.
///  3. **Fail-safe** (impact zones, Provot 1997, Bridson et al. 2002): the nodes of pairs that still
///     cross are merged into zones that move rigidly over the step (their momentum and angular
///     momentum kept), merged further while crossings remain. A rigid motion of a zone that did not
///     intersect at the start cannot make it intersect (the straight paths between two poses are an
///     affine map that stays invertible for rotations under pi), so this ends without crossings;
///     pairs inside one zone that moved rigidly are therefore not tested again (two layers that
///     touch at the start, pressed together by colliders, would otherwise count as meeting).
/// A node's share of an impulse follows its inverse mass: pinned nodes take none. A node held by
/// a collider this step moves only away from it (a contact stops motion one way only), and along
/// its surface only if the collider's static friction is below the layers' friction: otherwise
/// the collider's friction carries the layer's tangential push, since the collider's normal
/// force on the node is at least the layer's (the layer presses it on) and its coefficient at
/// least as large.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/continuous_collision.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/collision/primitive_distance.hpp"
#include "drape/contact/collider.hpp"
#include "drape/contact/self_collision_settings.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// What self-collision did in the last step.
struct SelfCollisionReport {
  int proximity_pairs = 0;  ///< pairs closer than 2h at the start of the step
  int repulsions = 0;       ///< of which had to be stopped or pushed apart
  int impacts = 0;          ///< crossings found by the continuous test and resolved by impulses
  int impulse_rounds = 0;   ///< rounds of continuous tests with impulses
  int zones = 0;            ///< impact zones the fail-safe moved rigidly (0: not needed)
  int zone_nodes = 0;       ///< nodes in those zones
  int unresolved = 0;       ///< crossings left when the fail-safe gave up (0 in every tested scene)
  int clear_passes = 0;     ///< passes run again after the colliders' end-of-step check pushed nodes out
  bool failsafe() const { return zones > 0; }
};

namespace detail {

/// True if the box around points[0, split) and the box around points[split, Count) are more than
/// `margin` apart along some axis: the two sides of a pair cannot touch (the exact tests are far
/// dearer than this and most candidate pairs of the broad phase fail it).
template <class Scalar, std::size_t Count>
bool sides_apart(const std::array<Vec3<Scalar>, Count>& points, std::size_t split, Scalar margin) {
  for (int axis = 0; axis < 3; ++axis) {
    Scalar low_a = points[0][axis], high_a = low_a;
    for (std::size_t j = 1; j < split; ++j) {
      low_a = std::min(low_a, points[j][axis]);
      high_a = std::max(high_a, points[j][axis]);
    }
    Scalar low_b = points[split][axis], high_b = low_b;
    for (std::size_t j = split + 1; j < Count; ++j) {
      low_b = std::min(low_b, points[j][axis]);
      high_b = std::max(high_b, points[j][axis]);
    }
    if (low_b - high_a > margin || low_a - high_b > margin) return true;
  }
  return false;
}

}  // namespace detail

template <class Scalar = double>
class SelfCollisionHandler {
 public:
  /// For any triangle mesh: a cloth's (its self_collision(), contact_thickness(), triangles(),
  /// masses(), start_positions()) or several cloths as one (their node ids one after the other):
  /// `masses` and `positions` (any pose, to shape the hierarchy) have a column per node.
  /// The settings' joined nodes are ids of this numbering.
  /// \throws InvalidParameter as SelfCollisionSettings::validate(), and when active as
  /// validate(node count) (the joined nodes).
  SelfCollisionHandler(const SelfCollisionSettings<Scalar>& settings, Scalar contact_thickness,
                       const std::vector<std::array<int, 3>>& triangles, const VectorX<Scalar>& masses,
                       const Matrix3X<Scalar>& positions)
      : SelfCollisionHandler(settings, contact_thickness) {
    m_settings.validate();
    if (active()) {
      m_settings.validate(static_cast<int>(masses.size()));
      build(triangles, masses, positions);
    }
  }

  /// True if the cloth's self-collision is on (everything below is a no-op otherwise).
  bool active() const { return m_settings.enabled; }
  const SelfCollisionReport& report() const { return m_report; }
  /// N s: the momentum each node received from cloth-cloth contacts in the last step (a column
  /// per node; the colliders' and pins' share included). Each contact gives its nodes momenta that
  /// sum to zero, so the sum over one cloth's nodes is what the other cloths pushed it with.
  const Matrix3X<Scalar>& received_momentum() const { return m_received; }

  /// On the step's result (`x_new`, `v_new`) from positions `x`: the three stages above. Only
  /// when active(): callers skip the call when off, so off costs nothing.
  /// `pinned[i] != 0` marks pinned nodes; `held(i)` returns how a collider holds node i this
  /// step (ColliderHold: zero normal if none).
  template <class Held>
  void respond(const ConstRef3X<Scalar>& x, Scalar dt, Ref3X<Scalar> x_new, Ref3X<Scalar> v_new,
               const std::vector<std::uint8_t>& pinned, const Held& held) {
    respond_pass(x, dt, x_new, v_new, pinned, held, false);
  }

  /// respond(), then the colliders' end-of-step check `keep_clear(x_new, v_new)`, which returns the
  /// nodes it pushed out of a collider and holds them there for the rest of the step (`held`
  /// then says so). A node pushed out along the collider's normal may pass through a layer resting
  /// on it (a layer the handler had pushed the node towards the collider to clear), so while the
  /// check pushes any node out the handler runs again on the paths from `x` (the report sums the
  /// passes; `unresolved` is the last pass's), at most `clear_passes` times; the check is last.
  template <class Held, class KeepClear>
  void respond_and_keep_clear(const ConstRef3X<Scalar>& x, Scalar dt, Ref3X<Scalar> x_new, Ref3X<Scalar> v_new,
                              const std::vector<std::uint8_t>& pinned, const Held& held,
                              const KeepClear& keep_clear) {
    respond_pass(x, dt, x_new, v_new, pinned, held, false);
    for (int pass = 0; keep_clear(x_new, v_new) > 0 && pass < clear_passes; ++pass) {
      ++m_report.clear_passes;
      respond_pass(x, dt, x_new, v_new, pinned, held, true);
    }
  }
  /// How many times respond_and_keep_clear() runs the handler again after the end-of-step check.
  static constexpr int clear_passes = 4;

 private:
  /// A vertex-triangle pair (p; a, b, c) or an edge-edge pair (p0, p1; q0, q1): four nodes with
  /// weights alpha (the pair's gap is n . sum alpha_i x_i).
  struct Pair {
    std::array<int, 4> node;
    std::array<Scalar, 4> alpha;
  };

  SelfCollisionHandler(const SelfCollisionSettings<Scalar>& settings, Scalar contact_thickness);
  void build(const std::vector<std::array<int, 3>>& triangles, const VectorX<Scalar>& masses,
             const Matrix3X<Scalar>& positions);
  template <class Visit>
  void for_each_candidate(const Visit& visit);
  /// Moves the pair's ends so its gap along n grows by `gap` (> 0); returns the impulse size
  /// (the gap change per unit of inverse mass), 0 if no node of the pair can move.
  Scalar separate(const Pair& pair, const Vec3<Scalar>& n, Scalar gap, Scalar dt, bool change_velocity);
  void apply_friction(const Pair& pair, const Vec3<Scalar>& n, Scalar normal_impulse, const ConstRef3X<Scalar>& x,
                      Scalar dt);
  void proximity(const ConstRef3X<Scalar>& x, Scalar dt);
  /// One round of continuous tests; with `resolve`, an impulse per crossing, else the crossing
  /// pairs' nodes merged into zones. Returns the crossings found.
  int collisions(const ConstRef3X<Scalar>& x, Scalar dt, bool resolve);
  void merge_zone(const Pair& pair);
  bool in_one_rigid_zone(const Pair& pair);
  /// respond()'s three stages; `again`: a further pass of the same step, added to its report and
  /// received momentum.
  template <class Held>
  void respond_pass(const ConstRef3X<Scalar>& x, Scalar dt, Ref3X<Scalar> x_new, Ref3X<Scalar> v_new,
                    const std::vector<std::uint8_t>& pinned, const Held& held, bool again);
  void move_zones_rigidly(const ConstRef3X<Scalar>& x, Scalar dt);
  int zone_root(int node);
  /// How node i moves when pushed along the unit vector d: freely unless a collider holds it;
  /// held, only the part of d away from the collider, plus the part along its surface if the
  /// collider's friction cannot carry it (see the file comment). (Letting a layer's pushes slide
  /// held nodes along a rough collider crept a cloth on a box's rounded edges out from under the
  /// layer resting on it and dragged it down the box's sides, step by step, in the implicit step.)
  Vec3<Scalar> allowed_push(int i, const Vec3<Scalar>& d) const {
    const Vec3<Scalar> c = m_held_normal.col(i);
    if (c.squaredNorm() == 0) return d;
    const Scalar away = c.dot(d);
    Vec3<Scalar> push = away > 0 ? Vec3<Scalar>(away * c) : Vec3<Scalar>(Vec3<Scalar>::Zero());
    if (m_held_slides[std::size_t(i)] != 0) push += d - away * c;
    return push;
  }
  /// sum alpha_i^2 / m_i along n, 0 if colliders hold the pair along n.
  Scalar effective_inverse_mass(const Pair& pair, const Vec3<Scalar>& n) const;

  SelfCollisionSettings<Scalar> m_settings;
  Scalar m_layer_distance;    // 2h
  Scalar m_impact_gap;        // the gap a crossing pair ends at
  Scalar m_impact_tolerance;  // distance the continuous test counts as touching
  std::optional<MeshTopology> m_topology;
  std::optional<TriangleBvh<Scalar>> m_bvh;
  VectorX<Scalar> m_mass;
  VectorX<Scalar> m_inverse_mass;           // per node this step: 0 for pinned ones
  Matrix3X<Scalar> m_held_normal;           // per node this step: the holding collider's normal, or 0
  std::vector<std::uint8_t> m_held_slides;  // per held node: its collider's friction is below the layers'
  Matrix3X<Scalar> m_x1;                    // ends of the paths being corrected
  Matrix3X<Scalar> m_dv;                    // velocity changes
  Matrix3X<Scalar> m_received;              // momentum from contacts
  std::vector<std::array<int, 2>> m_triangle_pairs;
  std::vector<int> m_zone_parent;  // union-find over nodes, -1 = not in a zone
  std::vector<std::uint8_t> m_zone_rigid;  // by root: the zone moved rigidly and nothing joined it since
  std::vector<int> m_zone_members;
  std::vector<int> m_zone_begin;  // zone of root r: members [begin[r], begin[r + 1])
  std::vector<int> m_zone_fill;
  SelfCollisionReport m_report;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
SelfCollisionHandler<Scalar>::SelfCollisionHandler(const SelfCollisionSettings<Scalar>& settings,
                                                   Scalar contact_thickness)
    : m_settings(settings),
      m_layer_distance(Scalar(2) * contact_thickness),
      m_impact_gap(Scalar(0.1) * m_layer_distance),
      m_impact_tolerance(
          std::max(Scalar(1e-3) * m_layer_distance, Scalar(64) * std::numeric_limits<Scalar>::epsilon())) {
  if (active() && !(contact_thickness > 0 && std::isfinite(contact_thickness)))
    detail::fail_argument("contact thickness", detail::to_text(contact_thickness),
                          "finite and > 0 with self-collision on (layers keep twice it apart)");
}

template <class Scalar>
void SelfCollisionHandler<Scalar>::build(const std::vector<std::array<int, 3>>& triangles,
                                         const VectorX<Scalar>& masses, const Matrix3X<Scalar>& positions) {
  const Index n = masses.size();
  if (positions.cols() != n)
    detail::fail_argument("positions", detail::to_text(positions.cols()) + " nodes",
                          detail::to_text(n) + " (one per mass)");
  m_topology.emplace(static_cast<int>(n), triangles, m_settings.joined_nodes);
  m_bvh.emplace(*m_topology, positions);
  m_mass = masses;
  m_inverse_mass.resize(n);
  m_held_normal.resize(3, n);
  m_held_slides.assign(std::size_t(n), 0);
  m_x1.resize(3, n);
  m_dv.resize(3, n);
  m_received.resize(3, n);
  m_zone_parent.assign(static_cast<std::size_t>(n), -1);
  m_zone_rigid.assign(static_cast<std::size_t>(n), 0);
}

template <class Scalar>
template <class Visit>
void SelfCollisionHandler<Scalar>::for_each_candidate(const Visit& visit) {
  const MeshTopology& mesh = *m_topology;
  m_bvh->overlapping_pairs(m_triangle_pairs);
  for (const std::array<int, 2>& tp : m_triangle_pairs) {
    for (int side = 0; side < 2; ++side) {
      const int owner = tp[static_cast<std::size_t>(side)], other = tp[static_cast<std::size_t>(1 - side)];
      const std::array<int, 3>& tri = mesh.triangle(other);
      for (int p : mesh.owned_nodes(owner))
        if (!mesh.triangle_has_node(other, p)) visit(Pair{{p, tri[0], tri[1], tri[2]}, {}}, true);
    }
    for (int e : mesh.owned_edges(tp[0]))
      for (int f : mesh.owned_edges(tp[1])) {
        if (mesh.edges_share_node(e, f)) continue;
        const std::array<int, 2>& a = mesh.edge(e);
        const std::array<int, 2>& b = mesh.edge(f);
        visit(Pair{{a[0], a[1], b[0], b[1]}, {}}, false);
      }
  }
}

template <class Scalar>
Scalar SelfCollisionHandler<Scalar>::effective_inverse_mass(const Pair& pair, const Vec3<Scalar>& n) const {
  Scalar k = 0, free = 0;
  for (std::size_t j = 0; j < 4; ++j) {
    const Scalar a2 = pair.alpha[j] * pair.alpha[j];
    const Vec3<Scalar> d = pair.alpha[j] < 0 ? Vec3<Scalar>(-n) : n;
    k += a2 * m_inverse_mass[pair.node[j]] * allowed_push(pair.node[j], d).dot(d);
    free += a2 * m_inverse_mass[pair.node[j]];
  }
  // Colliders hold the pair (nearly) along n: it cannot separate that way. Below 5% of its free
  // mobility a push would be a slide of more than 4.5 times the gap along the colliders' surfaces.
  return k > Scalar(0.05) * free ? k : Scalar(0);
}

template <class Scalar>
Scalar SelfCollisionHandler<Scalar>::separate(const Pair& pair, const Vec3<Scalar>& n, Scalar gap, Scalar dt,
                                              bool change_velocity) {
  const Scalar k = effective_inverse_mass(pair, n);
  if (!(k > 0)) return 0;
  const Scalar impulse = gap / k;
  if (change_velocity)
    for (std::size_t j = 0; j < 4; ++j) m_received.col(pair.node[j]) += (pair.alpha[j] * impulse / dt) * n;
  for (std::size_t j = 0; j < 4; ++j) {
    const int i = pair.node[j];
    const Scalar w = m_inverse_mass[i];
    if (w == 0) continue;
    const Vec3<Scalar> d = pair.alpha[j] < 0 ? Vec3<Scalar>(-n) : n;
    const Vec3<Scalar> move = (std::abs(pair.alpha[j]) * impulse * w) * allowed_push(i, d);
    m_x1.col(i) += move;
    if (change_velocity) m_dv.col(i) += move / dt;
  }
  return impulse;
}

template <class Scalar>
void SelfCollisionHandler<Scalar>::apply_friction(const Pair& pair, const Vec3<Scalar>& n, Scalar normal_impulse,
                                                  const ConstRef3X<Scalar>& x, Scalar dt) {
  if (!(normal_impulse > 0) || m_settings.friction == 0) return;
  Vec3<Scalar> relative = Vec3<Scalar>::Zero();  // the pair's relative motion over the step
  for (int j = 0; j < 4; ++j) {
    const int i = pair.node[std::size_t(j)];
    relative += pair.alpha[std::size_t(j)] * (m_x1.col(i) - x.col(i));
  }
  const Vec3<Scalar> tangential = relative - n.dot(relative) * n;
  const Scalar slide = tangential.norm();
  if (!(slide > 0)) return;
  const Vec3<Scalar> direction = -tangential / slide;
  const Scalar k = effective_inverse_mass(pair, direction);
  if (!(k > 0)) return;
  // The impulse that stops the slide, or the most the cone allows (Coulomb: sticking or sliding).
  const Scalar impulse = std::min(slide / k, m_settings.friction * normal_impulse);
  separate(pair, direction, impulse * k, dt, true);
}

template <class Scalar>
void SelfCollisionHandler<Scalar>::proximity(const ConstRef3X<Scalar>& x, Scalar dt) {
  const Scalar layer = m_layer_distance;
  // Boxes of the paths, each reaching half the layer distance (and a little more: a layer resting
  // at 2h must count as close).
  const Scalar reach = Scalar(1.05) * layer;
  m_bvh->refit(x, m_x1, Scalar(0.5) * reach);
  const Scalar tiny = Scalar(1e-6) * layer;
  for_each_candidate([&](Pair pair, bool vertex_triangle) {
    // Closest points where the pair ends (the ends move as earlier pairs are corrected).
    const Vec3<Scalar> e0 = m_x1.col(pair.node[0]), e1 = m_x1.col(pair.node[1]), e2 = m_x1.col(pair.node[2]),
                       e3 = m_x1.col(pair.node[3]);
    if (detail::sides_apart(std::array<Vec3<Scalar>, 4>{e0, e1, e2, e3}, vertex_triangle ? 1 : 2, reach)) return;
    if (vertex_triangle) {
      const PointTriangleClosest<Scalar> c = closest_point_on_triangle(e0, e1, e2, e3);
      if (c.distance_squared >= reach * reach) return;
      pair.alpha = {Scalar(1), -c.weights[0], -c.weights[1], -c.weights[2]};
    } else {
      const SegmentClosest<Scalar> c = closest_points_on_segments(e0, e1, e2, e3);
      if (c.distance_squared >= reach * reach) return;
      pair.alpha = {1 - c.s, c.s, c.t - 1, -c.t};
    }
    Vec3<Scalar> start_gap = Vec3<Scalar>::Zero(), end_gap = Vec3<Scalar>::Zero();
    for (std::size_t j = 0; j < 4; ++j) {
      start_gap += pair.alpha[j] * x.col(pair.node[j]);
      end_gap += pair.alpha[j] * m_x1.col(pair.node[j]);
    }
    const Scalar end_distance = end_gap.norm();
    if (end_distance < layer) ++m_report.proximity_pairs;
    Vec3<Scalar> n;
    if (end_distance > tiny) {
      n = end_gap / end_distance;
    } else if (start_gap.norm() > tiny) {
      n = start_gap.normalized();
    } else {
      return;  // touching at both ends: the continuous test decides
    }
    const Scalar start = n.dot(start_gap);
    if (start <= 0) return;  // on the other side at the start: it crossed, the continuous test resolves it
    Scalar end = n.dot(end_gap);
    bool acted = false;
    const Scalar stop = std::min(start, layer);
    if (end < stop) {  // approaching: stopped (inelastic) at its start distance or 2h, with friction
      const Scalar impulse = separate(pair, n, stop - end, dt, true);
      apply_friction(pair, n, impulse, x, dt);
      end = stop;
      acted = true;
    }
    const Scalar target = start + m_settings.separation_rate * (layer - start);
    if (start < layer && end < target) {
      separate(pair, n, target - end, dt, false);
      acted = true;
    }
    if (acted) ++m_report.repulsions;
  });
}

template <class Scalar>
int SelfCollisionHandler<Scalar>::collisions(const ConstRef3X<Scalar>& x, Scalar dt, bool resolve) {
  m_bvh->refit(x, m_x1, m_impact_tolerance);
  int found = 0;
  for_each_candidate([&](Pair pair, bool vertex_triangle) {
    std::array<Vec3<Scalar>, 4> start, end;
    for (std::size_t j = 0; j < 4; ++j) {
      start[j] = x.col(pair.node[j]);
      end[j] = m_x1.col(pair.node[j]);
    }
    // The boxes swept by the pair's two sides over the step.
    std::array<Vec3<Scalar>, 8> swept;
    for (std::size_t j = 0; j < 4; ++j) {
      swept[2 * j] = start[j];
      swept[2 * j + 1] = end[j];
    }
    if (detail::sides_apart(swept, vertex_triangle ? 2 : 4, m_impact_tolerance)) return;
    // Inside one zone that moved rigidly the pair's shape is its start's: it cannot cross (a pair
    // touching at the start, within the tolerance, would otherwise count at every pass).
    if (!resolve && in_one_rigid_zone(pair)) return;
    const std::optional<Scalar> hit = vertex_triangle ? vertex_triangle_impact(start, end, m_impact_tolerance)
                                                      : edge_edge_impact(start, end, m_impact_tolerance);
    if (!hit) return;
    ++found;
    if (!resolve) {
      merge_zone(pair);
      return;
    }
    // Weights and normal where they meet.
    std::array<Vec3<Scalar>, 4> at;
    for (std::size_t j = 0; j < 4; ++j) at[j] = start[j] + *hit * (end[j] - start[j]);
    Vec3<Scalar> n;
    if (vertex_triangle) {
      const PointTriangleClosest<Scalar> c = closest_point_on_triangle(at[0], at[1], at[2], at[3]);
      pair.alpha = {Scalar(1), -c.weights[0], -c.weights[1], -c.weights[2]};
      n = (at[2] - at[1]).cross(at[3] - at[1]);
    } else {
      const SegmentClosest<Scalar> c = closest_points_on_segments(at[0], at[1], at[2], at[3]);
      pair.alpha = {1 - c.s, c.s, c.t - 1, -c.t};
      n = (at[1] - at[0]).cross(at[3] - at[2]);
    }
    Vec3<Scalar> gap_start = Vec3<Scalar>::Zero(), gap_end = Vec3<Scalar>::Zero();
    for (std::size_t j = 0; j < 4; ++j) {
      gap_start += pair.alpha[j] * start[j];
      gap_end += pair.alpha[j] * end[j];
    }
    if (!(n.norm() > 0)) n = gap_start;  // degenerate triangle or parallel edges: the start's direction
    if (!(n.norm() > 0)) return;         // left to the fail-safe
    n.normalize();
    // The side the pair starts on; touching at the start, the side it comes from.
    const Scalar side = n.dot(gap_start);
    if (side < 0 || (side == 0 && n.dot(gap_end - gap_start) > 0)) n = -n;
    const Scalar end_gap = n.dot(gap_end);
    if (end_gap < m_impact_gap) separate(pair, n, m_impact_gap - end_gap, dt, true);
  });
  return found;
}

template <class Scalar>
int SelfCollisionHandler<Scalar>::zone_root(int node) {
  int root = node;
  while (m_zone_parent[std::size_t(root)] != root) root = m_zone_parent[std::size_t(root)];
  while (m_zone_parent[std::size_t(node)] != root) {  // path compression
    const int next = m_zone_parent[std::size_t(node)];
    m_zone_parent[std::size_t(node)] = root;
    node = next;
  }
  return root;
}

template <class Scalar>
void SelfCollisionHandler<Scalar>::merge_zone(const Pair& pair) {
  int root = -1;
  for (int node : pair.node) {
    if (m_zone_parent[std::size_t(node)] < 0) {
      m_zone_parent[std::size_t(node)] = node;
      m_zone_rigid[std::size_t(node)] = 0;
    }
    const int r = zone_root(node);
    if (root < 0) {
      root = r;
    } else if (r != root) {  // the smaller id becomes the root: the same zones for the same input
      const int low = std::min(r, root), high = std::max(r, root);
      m_zone_parent[std::size_t(high)] = low;
      m_zone_rigid[std::size_t(low)] = 0;  // its parts moved apart: not one rigid motion
      root = low;
    }
  }
}

template <class Scalar>
bool SelfCollisionHandler<Scalar>::in_one_rigid_zone(const Pair& pair) {
  if (m_zone_parent[std::size_t(pair.node[0])] < 0) return false;
  const int root = zone_root(pair.node[0]);
  if (m_zone_rigid[std::size_t(root)] == 0) return false;
  for (std::size_t j = 1; j < 4; ++j)
    if (m_zone_parent[std::size_t(pair.node[j])] < 0 || zone_root(pair.node[j]) != root) return false;
  return true;
}

template <class Scalar>
void SelfCollisionHandler<Scalar>::move_zones_rigidly(const ConstRef3X<Scalar>& x, Scalar dt) {
  const int n = static_cast<int>(x.cols());
  // Members of each zone, by root, in ascending node order (a counting sort).
  m_zone_begin.assign(std::size_t(n) + 1, 0);
  for (int i = 0; i < n; ++i)
    if (m_zone_parent[std::size_t(i)] >= 0) ++m_zone_begin[std::size_t(zone_root(i)) + 1];
  for (int i = 0; i < n; ++i) m_zone_begin[std::size_t(i) + 1] += m_zone_begin[std::size_t(i)];
  m_zone_members.resize(std::size_t(m_zone_begin[std::size_t(n)]));
  m_zone_fill.assign(m_zone_begin.begin(), m_zone_begin.end() - 1);
  for (int i = 0; i < n; ++i)
    if (m_zone_parent[std::size_t(i)] >= 0) m_zone_members[std::size_t(m_zone_fill[std::size_t(zone_root(i))]++)] = i;
  m_report.zones = 0;
  m_report.zone_nodes = 0;
  for (int root = 0; root < n; ++root) {
    const int begin = m_zone_begin[std::size_t(root)], end = m_zone_begin[std::size_t(root) + 1];
    if (begin == end) continue;
    ++m_report.zones;
    m_report.zone_nodes += end - begin;
    // A zone with a pinned or held node moves with them (their mean displacement); any other
    // zone rigidly, with its momentum and angular momentum over the step.
    Vec3<Scalar> anchored = Vec3<Scalar>::Zero();
    int anchors = 0;
    Scalar mass = 0;
    Vec3<Scalar> centre = Vec3<Scalar>::Zero(), shift = Vec3<Scalar>::Zero();
    for (int k = begin; k < end; ++k) {
      const int i = m_zone_members[std::size_t(k)];
      const Vec3<Scalar> d = m_x1.col(i) - x.col(i);
      if (m_inverse_mass[i] == 0 || m_held_normal.col(i).squaredNorm() > 0) {
        anchored += d;
        ++anchors;
      }
      mass += m_mass[i];
      centre += m_mass[i] * x.col(i);
      shift += m_mass[i] * d;
    }
    centre /= mass;
    shift /= mass;
    Mat3<Scalar> rotation = Mat3<Scalar>::Identity();
    if (anchors > 0) {
      shift = anchored / Scalar(anchors);
    } else {
      Vec3<Scalar> spin = Vec3<Scalar>::Zero();  // angular momentum times dt
      Mat3<Scalar> inertia = Mat3<Scalar>::Zero();
      for (int k = begin; k < end; ++k) {
        const int i = m_zone_members[std::size_t(k)];
        const Vec3<Scalar> r = x.col(i) - centre;
        spin += m_mass[i] * r.cross(m_x1.col(i) - x.col(i) - shift);
        inertia += m_mass[i] * (r.squaredNorm() * Mat3<Scalar>::Identity() - r * r.transpose());
      }
      // A zone on a line has no inertia about it: a small multiple of the trace keeps the solve sound.
      inertia += Scalar(1e-6) * inertia.trace() * Mat3<Scalar>::Identity();
      Vec3<Scalar> angle = inertia.ldlt().solve(spin);
      const Scalar turn = angle.norm();
      const Scalar limit = Scalar(0.9) * Scalar(3.14159265358979323846);  // the paths stay invertible below pi
      if (turn > limit) angle *= limit / turn;
      if (turn > 0 && std::isfinite(turn))
        rotation = Eigen::AngleAxis<Scalar>(angle.norm(), angle.normalized()).toRotationMatrix();
    }
    // Rigid unless a pinned node, which keeps its own path, ends off the zone's motion.
    const Scalar slack = Scalar(0.01) * m_impact_tolerance;
    bool rigid = true;
    for (int k = begin; k < end; ++k) {
      const int i = m_zone_members[std::size_t(k)];
      const Vec3<Scalar> moved = centre + shift + rotation * (x.col(i) - centre);
      if (m_inverse_mass[i] == 0 && (moved - m_x1.col(i)).norm() > slack) rigid = false;
      const Vec3<Scalar> change = (m_inverse_mass[i] == 0) ? Vec3<Scalar>::Zero() : Vec3<Scalar>(moved - m_x1.col(i));
      m_x1.col(i) += change;
      m_dv.col(i) += change / dt;
      m_received.col(i) += (m_mass[i] / dt) * change;
    }
    m_zone_rigid[std::size_t(root)] = rigid ? 1 : 0;
  }
}

template <class Scalar>
template <class Held>
void SelfCollisionHandler<Scalar>::respond_pass(const ConstRef3X<Scalar>& x, Scalar dt, Ref3X<Scalar> x_new,
                                                Ref3X<Scalar> v_new, const std::vector<std::uint8_t>& pinned,
                                                const Held& held, bool again) {
  if (!again) {
    m_report = {};
    m_received.setZero();
  }
  m_report.unresolved = 0;
  const Index n = x.cols();
  for (Index i = 0; i < n; ++i) {
    m_inverse_mass[i] = pinned[std::size_t(i)] != 0 ? Scalar(0) : Scalar(1) / m_mass[i];
    const ColliderHold<Scalar> hold = held(static_cast<int>(i));
    m_held_normal.col(i) = hold.normal;
    m_held_slides[std::size_t(i)] = hold.held() && hold.static_friction < m_settings.friction;
  }
  m_x1 = x_new;
  m_dv.setZero();
  // Proximity, then rounds of continuous tests, each followed by proximity again: the impulses of
  // a crossing leave its pair closer than 2h, which proximity restores before the next check.
  int found = 1;
  for (int round = 0; round < m_settings.impulse_rounds && found > 0; ++round) {
    proximity(x, dt);
    ++m_report.impulse_rounds;
    found = collisions(x, dt, true);
    m_report.impacts += found;
  }
  if (m_settings.impulse_rounds == 0) proximity(x, dt);
  if (found > 0) {  // the fail-safe: impact zones until no pair crosses
    std::fill(m_zone_parent.begin(), m_zone_parent.end(), -1);
    constexpr int max_zone_passes = 200;
    for (int pass = 0; pass < max_zone_passes && found > 0; ++pass) {
      found = collisions(x, dt, false);
      if (found > 0) move_zones_rigidly(x, dt);
    }
    if (found > 0) m_report.unresolved = collisions(x, dt, false);
  }
  x_new = m_x1;
  v_new += m_dv;
}

}  // namespace drape
