#pragma once
/// \file contact_handler.hpp
/// Cloth nodes against the scene's colliders: detection, the implicit step's velocity constraints,
/// Coulomb friction and the end-of-step guarantee, in one place for both integrators (drape's
/// contact.md has the derivation and the limits).
///
/// A node touches a collider when its signed distance d is at most the contact thickness h (the
/// cloth's half-thickness). For a node that touches, or whose straight path during the step
/// reaches the surface (a swept test in the collider's moving frame), the normal velocity at the
/// end of the step is prescribed,
/// \f[ n \cdot v^{+} = n \cdot v_c + (h - d) / \Delta t , \f]
/// with n, d and the collider's surface velocity \f$ v_c \f$ taken at the start of the step: the
/// node ends on the plane tangent to the collider (inflated by h) at its closest point, which for a
/// convex collider keeps the whole path outside, however fast it moves.
///  - Implicit step: the constraint enters the linear solve through the constraint filter
///    (Baraff & Witkin 1998, section 5), \f$ S = I - n n^T \f$, \f$ z = n (n \cdot v^{+} - n \cdot v) \f$.
///    After each solve the contact impulse is \f$ \lambda = (A \Delta v - b)_r \f$; contacts that
///    pull (\f$ n \cdot \lambda < 0 \f$) are released and nodes whose new path enters a collider
///    are added, and the system is solved again while the set changes (at most `rounds` solves).
///  - RK2: the same target applied to the step's result as an inelastic impulse.
/// Friction (both): with the normal impulse \f$ j_n \f$ of the step, a node whose tangential
/// relative velocity \f$ u_t \f$ can be stopped by \f$ m |u_t| \le \mu_s j_n \f$ sticks
/// (\f$ u_t = 0 \f$); otherwise it slides and \f$ |u_t| \f$ drops by \f$ \mu_k j_n / m \f$
/// (Bridson, Fedkiw & Anderson 2002). A node in contact then moves by \f$ \Delta t\, v^{+} \f$.
/// Last of the step, after the cloth against itself (keep_clear()), every node is checked at its
/// end position against every collider and pushed out to the distance h if it is deeper than h by
/// more than the tolerance: the guarantee, counted in `ContactReport::corrected`.
/// Mesh colliders keep, per node, a lower bound on its distance to the surface (conservative
/// advancement): the distance measured at the node's last exact query, at the end of a step, less
/// how far the node has moved since in the collider's frame and how far the surface has moved (a
/// deforming mesh: the largest vertex displacement of each step, summed). The distance is
/// 1-Lipschitz, so a node whose bound exceeds the offset cannot touch the mesh this step and skips
/// the tree: the answers are the same, only far nodes cost less.
/// A key-framed (deforming) mesh collider is held per step as its surface at t and at t + dt with
/// the swept boxes between (collision/mesh_sweep.hpp, made at its first step, refitted after): its
/// queries take the surface of their end of the step, its surface velocity the vertices' motion
/// across the step, its swept test the continuous vertex-triangle test on the moving triangles.

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "drape/contact/collider.hpp"
#include "drape/core/types.hpp"
#include "drape/linalg/linear_system.hpp"

namespace drape {

/// What the contacts did in the last step.
template <class Scalar>
struct ContactReport {
  int contacts = 0;   ///< nodes in contact (normal impulse > 0 or held by a constraint)
  int sticking = 0;   ///< of which friction held still
  int sliding = 0;    ///< of which slid
  int corrected = 0;  ///< nodes the end-of-step check had to push out
  /// Contacts resolved by an impulse after the solve instead of as constraints of it: all of them
  /// in RK2; in the implicit step those its last solve brought to a collider.
  int after_solve = 0;
  int rounds = 0;      ///< implicit step: linear solves (1 without contact changes); RK2: 0
  Scalar deepest = 0;  ///< deepest penetration h - d at the end of the step, before the check (m, >= 0)
  Vec3<Scalar> normal_force = Vec3<Scalar>::Zero();    ///< total normal force on the cloth (N)
  Vec3<Scalar> friction_force = Vec3<Scalar>::Zero();  ///< total friction force on the cloth (N)
};

template <class Scalar = double>
class ContactHandler {
 public:
  /// The nodes of `masses` (a mass per node) against `colliders`, resting `contact_thickness` from
  /// their surfaces: a cloth's `colliders()`, `contact_thickness()` and `masses()`. Keeps
  /// references to the colliders and the masses; temporaries would dangle.
  ContactHandler(const std::vector<Collider<Scalar>>& colliders, Scalar contact_thickness,
                 const VectorX<Scalar>& masses)
      : m_colliders(&colliders),
        m_masses(&masses),
        m_thickness(contact_thickness),
        m_tolerance(detail::contact_tolerance(contact_thickness)),
        m_slot(static_cast<std::size_t>(masses.size()), -1),
        m_let_go(static_cast<std::size_t>(masses.size()), -1),
        m_set_back_collider(static_cast<std::size_t>(masses.size()), -1),
        m_set_back_normal(3, masses.size()) {}
  ContactHandler(const std::vector<Collider<Scalar>>&& colliders, Scalar contact_thickness,
                 const VectorX<Scalar>& masses) = delete;
  ContactHandler(const std::vector<Collider<Scalar>>& colliders, Scalar contact_thickness,
                 const VectorX<Scalar>&& masses) = delete;

  /// True if the scene has colliders (everything below is then a no-op otherwise).
  bool active() const { return !m_colliders->empty(); }
  const ContactReport<Scalar>& report() const { return m_report; }
  /// After respond(): how the collider node `i` touches this step holds it (not held: zero normal).
  /// A node keep_clear() set back onto a collider this step is held by it too.
  ColliderHold<Scalar> hold(int i) const {
    const int slot = m_slot[static_cast<std::size_t>(i)];
    if (slot >= 0) {
      const Contact& contact = m_contacts[static_cast<std::size_t>(slot)];
      return {contact.normal, (*m_colliders)[static_cast<std::size_t>(contact.collider)].static_friction()};
    }
    const int collider = m_set_back_collider[static_cast<std::size_t>(i)];
    if (collider < 0) return {};
    return {m_set_back_normal.col(i), (*m_colliders)[static_cast<std::size_t>(collider)].static_friction()};
  }

  /// Implicit step, before the first solve: the nodes that touch a collider, or would reach one
  /// moving at their velocity v, become constraints of `c` (rows from `row_of_node`, -1 = not in
  /// the system). Releases the previous step's contact rows first.
  void constrain(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Scalar dt,
                 const std::vector<int>& row_of_node, ConstraintFilter<Scalar>& c);

  /// Implicit step, after a solve with `dv` (3 per row): contact impulses from the residual;
  /// releases pulling contacts and adds nodes whose new path enters a collider. Returns true if
  /// the constraints changed (solve again).
  bool revise(const LinearSystem<Scalar>& system, const VectorX<Scalar>& dv, const ConstRef3X<Scalar>& x,
              const ConstRef3X<Scalar>& v, Scalar dt, const std::vector<int>& row_of_node, ConstraintFilter<Scalar>& c);

  /// Both integrators, on the step's result `x_new`, `v_new` from (x, v) at t: the RK2 contact
  /// impulses (nodes not already constrained) and friction. Nodes with `pinned[i] != 0` follow
  /// their pins and are left alone.
  void respond(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Scalar dt, Ref3X<Scalar> x_new,
               Ref3X<Scalar> v_new, const std::vector<std::uint8_t>& pinned);

  /// The end-of-step check, after respond() and after the cloth against itself (whose pushes may
  /// move a node that no contact holds towards a collider): every free node at its end position
  /// against every collider at the step's end; one deeper than h by more than the tolerance is
  /// pushed out to h and loses its approaching velocity (`ContactReport::corrected`), and hold()
  /// counts it as held for the rest of the step. Returns the nodes pushed out by this call.
  int keep_clear(Ref3X<Scalar> x_new, Ref3X<Scalar> v_new, const std::vector<std::uint8_t>& pinned);

 private:
  struct Contact {
    int node;
    int collider;
    int row;  // system row under the implicit step's constraints, -1 otherwise
    Vec3<Scalar> normal;
    Vec3<Scalar> surface_velocity;
    Scalar target;        // n . v+ at the end of the step
    Scalar impulse;       // normal impulse of the step (N s)
    bool solved = false;  // a constraint of the step's last solve (else resolved by an impulse after it)
  };

  /// What the broad phase knows of a collider during the step, and its poses.
  struct Bounds {
    RigidPose<Scalar> start, end;           // the collider's poses at t and t + dt
    bool plane;                             // a plane: the half-space test below; otherwise the ball
    Vec3<Scalar> normal_start, normal_end;  // plane: its normal at t and t + dt
    Scalar level_start, level_end;          // plane: n . x on its surface at t and t + dt
    Vec3<Scalar> middle;                    // ball: its centre halfway through the step
    Scalar reach;                           // ball: the shape's bounding radius plus half the centre's displacement
  };
  /// The colliders' bounds for the step from t to t + dt (once per step).
  void bound(Scalar t, Scalar dt);
  /// False if the path x0 -> x1 (midpoint `middle`, half length `half_travel`) cannot come within
  /// `offset` of collider k. Both move linearly: for a ball their distance is at least the
  /// midpoints' distance minus half of both displacements; for a plane the distance is linear
  /// along the path, so the nearer end decides.
  bool may_reach(std::size_t k, const Vec3<Scalar>& x0, const Vec3<Scalar>& x1, const Vec3<Scalar>& middle,
                 Scalar half_travel, Scalar offset) const {
    const Bounds& b = m_bounds[k];
    if (b.plane) return std::min(b.normal_start.dot(x0) - b.level_start, b.normal_end.dot(x1) - b.level_end) <= offset;
    const Scalar reach = b.reach + offset + half_travel;
    return (middle - b.middle).squaredNorm() <= reach * reach;
  }
  /// Collider k at world point x at the start (or the end) of the step.
  ColliderContact<Scalar> query(std::size_t k, const Vec3<Scalar>& x, bool at_end) const;
  /// The first s at which the path x0 (t) -> x1 (t + dt) comes within `offset` of collider k, -1 if never.
  Scalar first_contact(std::size_t k, const Vec3<Scalar>& x0, const Vec3<Scalar>& x1, Scalar offset) const;
  /// A lower bound on how near node i's path p0 (t) -> p1 (t + dt), in mesh collider k's frame,
  /// comes to the surface during the step (-infinity when nothing is known).
  Scalar clearance(std::size_t k, int i, const Vec3<Scalar>& p0, const Vec3<Scalar>& p1) const {
    const Clearance& c = m_clearance[k];
    const Scalar measured = c.distance[i];
    if (!(measured > 0)) return -std::numeric_limits<Scalar>::infinity();
    const Scalar moved = std::max((p0 - c.at.col(i)).norm(), (p1 - c.at.col(i)).norm());
    return measured - moved - (m_travel[k] - c.travel_at[i]);
  }
  /// The first collider the path x0 (t) -> x1 (t + dt) reaches within `offset`, as a contact
  /// taken at the start; false if none.
  bool sweep(int node, const Vec3<Scalar>& x0, const Vec3<Scalar>& x1, Scalar dt, Scalar offset, Contact& out) const;
  void add(const Contact& contact, ConstraintFilter<Scalar>* c, const ConstRef3X<Scalar>& v);
  void release_rows(ConstraintFilter<Scalar>& c);
  void forget_set_back();
  /// Coulomb friction on a node in contact (its velocity, in place), and the report's totals.
  void apply_friction(const Contact& contact, Vec3<Scalar>& velocity, Scalar mass, Scalar dt);

  const std::vector<Collider<Scalar>>* m_colliders;
  const VectorX<Scalar>* m_masses;  // per node
  Scalar m_thickness;               // h: nodes rest this far from a collider's surface
  Scalar m_tolerance;               // how much deeper than h a node may end a step
  std::vector<Contact> m_contacts;  // this step's
  std::vector<Contact> m_kept;      // scratch of revise()
  std::vector<int> m_slot;          // per node: index into m_contacts, -1 if none
  // Per node: the step (m_step) in which revise() let its contact go because it pulled.
  std::vector<long long> m_let_go;
  // Per node: the collider keep_clear() set it back onto this step (-1: none) and that collider's
  // normal there; the nodes set back, to forget them at the next step.
  std::vector<int> m_set_back_collider;
  Matrix3X<Scalar> m_set_back_normal;
  std::vector<int> m_set_back;
  long long m_step = 0;          // constrain() calls
  std::vector<Bounds> m_bounds;  // per collider, this step's
  // Per collider: a deforming mesh over this step (null for the others), made at its first step.
  std::vector<std::unique_ptr<MeshSweep<Scalar>>> m_sweeps;
  Matrix3X<Scalar> m_frame_start, m_frame_end;  // scratch: a deforming mesh's vertices at t and t + dt
  // Per mesh collider (empty for the others): each node's position in the collider's frame at its
  // last exact query, the distance measured there (-infinity: none) and the surface's travel then.
  struct Clearance {
    Matrix3X<Scalar> at;
    VectorX<Scalar> distance;
    VectorX<Scalar> travel_at;
  };
  std::vector<Clearance> m_clearance;
  std::vector<Scalar> m_travel;  // per collider: how far its surface has moved, summed to this step's end
  Scalar m_last_end = std::numeric_limits<Scalar>::quiet_NaN();  // when the last step ended
  Scalar m_dt = 0;                              // this step's
  ContactReport<Scalar> m_report;
  bool m_constrained = false;  // constrain() began this step
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void ContactHandler<Scalar>::bound(Scalar t, Scalar dt) {
  const std::vector<Collider<Scalar>>& colliders = *m_colliders;
  m_bounds.resize(colliders.size());
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    const RigidMotion<Scalar>& motion = colliders[k].motion();
    Bounds& b = m_bounds[k];
    b.start = motion.pose(t);
    b.end = motion.pose(t + dt);
    b.plane = colliders[k].kind() == ShapeKind::Plane;
    b.normal_start = b.start.rotation.col(1);  // a plane's local +y
    b.normal_end = b.end.rotation.col(1);
    b.level_start = b.normal_start.dot(b.start.translation);
    b.level_end = b.normal_end.dot(b.end.translation);
    b.middle = Scalar(0.5) * (b.start.translation + b.end.translation);
    b.reach = colliders[k].bounding_radius() + Scalar(0.5) * (b.end.translation - b.start.translation).norm();
  }
  m_dt = dt;
  m_sweeps.resize(colliders.size());
  m_clearance.resize(colliders.size());
  m_travel.resize(colliders.size(), Scalar(0));
  const Index nodes = m_masses->size();
  // A deforming mesh's bounds hold from one step to the next only; after a jump in time they go.
  const bool continues = t == m_last_end;
  m_last_end = t + dt;
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    if (colliders[k].kind() != ShapeKind::Mesh) continue;
    Clearance& c = m_clearance[k];
    if (c.distance.size() != nodes) {
      c.at = Matrix3X<Scalar>::Zero(3, nodes);
      c.distance = VectorX<Scalar>::Constant(nodes, -std::numeric_limits<Scalar>::infinity());
      c.travel_at = VectorX<Scalar>::Zero(nodes);
    }
    if (!colliders[k].deforms()) continue;  // the surface is fixed in its own frame
    if (!continues) c.distance.fill(-std::numeric_limits<Scalar>::infinity());
    colliders[k].mesh_positions(t, m_frame_start);
    colliders[k].mesh_positions(t + dt, m_frame_end);
    if (!m_sweeps[k]) m_sweeps[k] = std::make_unique<MeshSweep<Scalar>>(colliders[k].mesh()->triangles(), m_frame_start);
    m_sweeps[k]->update(m_frame_start, m_frame_end);
    m_travel[k] += (m_frame_end - m_frame_start).colwise().norm().maxCoeff();
  }
}

template <class Scalar>
ColliderContact<Scalar> ContactHandler<Scalar>::query(std::size_t k, const Vec3<Scalar>& x, bool at_end) const {
  const Collider<Scalar>& collider = (*m_colliders)[k];
  const RigidPose<Scalar>& pose = at_end ? m_bounds[k].end : m_bounds[k].start;
  if (!collider.deforms()) return collider.query(x, pose);
  const MeshSweep<Scalar>& sweep = *m_sweeps[k];
  const typename MeshDistance<Scalar>::Closest c = (at_end ? sweep.end() : sweep.start()).closest(pose.to_local(x));
  return {c.distance, pose.rotation * c.normal,
          pose.point_velocity(x) + pose.rotation * sweep.surface_velocity(c.triangle, c.weights, m_dt)};
}

template <class Scalar>
Scalar ContactHandler<Scalar>::first_contact(std::size_t k, const Vec3<Scalar>& x0, const Vec3<Scalar>& x1,
                                             Scalar offset) const {
  const Collider<Scalar>& collider = (*m_colliders)[k];
  const Bounds& b = m_bounds[k];
  if (!collider.deforms()) return collider.first_contact(x0, b.start, x1, b.end, offset);
  return m_sweeps[k]->first_contact(b.start.to_local(x0), b.end.to_local(x1), offset, detail::swept_tolerance(offset));
}

template <class Scalar>
bool ContactHandler<Scalar>::sweep(int node, const Vec3<Scalar>& x0, const Vec3<Scalar>& x1, Scalar dt, Scalar offset,
                                   Contact& out) const {
  Scalar first = 2;
  int hit = -1;
  const std::vector<Collider<Scalar>>& colliders = *m_colliders;
  const Vec3<Scalar> middle = Scalar(0.5) * (x0 + x1);
  const Scalar half_travel = Scalar(0.5) * (x1 - x0).norm();
  for (std::size_t k = 0; k < colliders.size(); ++k) {
    if (!may_reach(k, x0, x1, middle, half_travel, offset)) continue;
    if (colliders[k].kind() == ShapeKind::Mesh &&
        clearance(k, node, m_bounds[k].start.to_local(x0), m_bounds[k].end.to_local(x1)) >
            offset + detail::swept_tolerance(offset))
      continue;
    const Scalar s = first_contact(k, x0, x1, offset);
    if (s >= 0 && s < first) {
      first = s;
      hit = static_cast<int>(k);
    }
  }
  if (hit < 0) return false;
  const ColliderContact<Scalar> q = query(static_cast<std::size_t>(hit), x0, false);
  out = {node,     hit,        -1,
         q.normal, q.velocity, q.normal.dot(q.velocity) + (m_thickness - q.distance) / dt,
         Scalar(0)};
  return true;
}

template <class Scalar>
void ContactHandler<Scalar>::add(const Contact& contact, ConstraintFilter<Scalar>* c, const ConstRef3X<Scalar>& v) {
  m_slot[static_cast<std::size_t>(contact.node)] = static_cast<int>(m_contacts.size());
  m_contacts.push_back(contact);
  if (c == nullptr || contact.row < 0) return;
  const Vec3<Scalar>& n = contact.normal;
  const Scalar dv_normal = contact.target - n.dot(v.col(contact.node));
  c->constrain(contact.row, Mat3<Scalar>::Identity() - n * n.transpose(), dv_normal * n);
}

template <class Scalar>
void ContactHandler<Scalar>::release_rows(ConstraintFilter<Scalar>& c) {
  for (const Contact& contact : m_contacts) {
    if (contact.row >= 0 && c.kind(contact.row) == ConstraintKind::Projected) c.release(contact.row);
    m_slot[static_cast<std::size_t>(contact.node)] = -1;
  }
  m_contacts.clear();
}

template <class Scalar>
void ContactHandler<Scalar>::constrain(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Scalar dt,
                                       const std::vector<int>& row_of_node, ConstraintFilter<Scalar>& c) {
  release_rows(c);
  forget_set_back();
  m_report = {};
  m_constrained = true;
  ++m_step;
  if (!active()) return;
  bound(t, dt);
  // A node resting on a surface sits at d = h up to rounding: a small margin keeps it constrained
  // instead of letting it fall in and be caught by a second solve.
  const Scalar h = m_thickness;
  const Scalar margin = Scalar(0.05) * h + Scalar(16) * std::numeric_limits<Scalar>::epsilon();
  for (Index i = 0; i < x.cols(); ++i) {
    const int node = static_cast<int>(i);
    const int row = row_of_node[static_cast<std::size_t>(node)];
    if (row < 0 || c.kind(row) == ConstraintKind::Fixed) continue;  // pinned
    Contact contact;
    if (!sweep(node, x.col(i), x.col(i) + dt * v.col(i), dt, h + margin, contact)) continue;
    // How far its velocity would take it past the surface target in the step (> 0: in, < 0: out).
    const Scalar approach = contact.target * dt - contact.normal.dot(v.col(i)) * dt;
    if (approach <= -margin) continue;  // clearly leaving
    // Let go last step because the surface had to pull it: free unless it moves in. Constraining
    // it again would only let it go again after a second solve (Baraff & Witkin 1998 release
    // contacts on the last step's constraint force the same way). If its new path enters the
    // collider, revise() takes it back.
    if (m_let_go[static_cast<std::size_t>(node)] == m_step - 1 && approach <= margin) continue;
    contact.row = row;
    add(contact, &c, v);
  }
}

template <class Scalar>
bool ContactHandler<Scalar>::revise(const LinearSystem<Scalar>& system, const VectorX<Scalar>& dv,
                                    const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar dt,
                                    const std::vector<int>& row_of_node, ConstraintFilter<Scalar>& c) {
  if (!active()) return false;
  ++m_report.rounds;
  const BlockSparseMatrix<Scalar>& a = system.matrix;
  bool changed = false;
  // Impulses lambda = (A dv - b)_r of the constrained rows; pulling contacts let go.
  std::vector<Contact>& kept = m_kept;
  kept.clear();
  for (Contact& contact : m_contacts) {
    contact.solved = true;
    const int r = contact.row;
    Vec3<Scalar> lambda = -system.rhs.template segment<3>(3 * r);
    for (int k = a.row_begin()[r]; k < a.row_begin()[r + 1]; ++k)
      lambda += a.block(k) * dv.template segment<3>(3 * a.column()[k]);
    contact.impulse = contact.normal.dot(lambda);
    m_slot[static_cast<std::size_t>(contact.node)] = -1;
    if (contact.impulse < 0) {
      c.release(r);
      m_let_go[static_cast<std::size_t>(contact.node)] = m_step;
      changed = true;
    } else {
      kept.push_back(contact);
    }
  }
  m_contacts.swap(kept);
  for (std::size_t k = 0; k < m_contacts.size(); ++k) m_slot[static_cast<std::size_t>(m_contacts[k].node)] = int(k);
  // Nodes whose new path reaches a collider.
  const Scalar h = m_thickness;
  for (Index i = 0; i < x.cols(); ++i) {
    const int node = static_cast<int>(i);
    const int row = row_of_node[static_cast<std::size_t>(node)];
    if (row < 0 || c.kind(row) != ConstraintKind::Free) continue;
    const Vec3<Scalar> v_new = v.col(i) + dv.template segment<3>(3 * row);
    Contact contact;
    if (!sweep(node, x.col(i), x.col(i) + dt * v_new, dt, h, contact)) continue;
    if (contact.normal.dot(v_new) >= contact.target) continue;  // touches but leaves by itself
    contact.row = row;
    add(contact, &c, v);
    m_let_go[static_cast<std::size_t>(node)] = -1;  // it moves in after all
    changed = true;
  }
  return changed;
}

template <class Scalar>
void ContactHandler<Scalar>::apply_friction(const Contact& contact, Vec3<Scalar>& velocity, Scalar mass, Scalar dt) {
  const Vec3<Scalar>& n = contact.normal;
  ++m_report.contacts;
  m_report.normal_force += (contact.impulse / dt) * n;
  const Collider<Scalar>& collider = (*m_colliders)[static_cast<std::size_t>(contact.collider)];
  const Vec3<Scalar> relative = velocity - contact.surface_velocity;
  const Vec3<Scalar> tangential = relative - n.dot(relative) * n;
  const Scalar speed = tangential.norm();
  if (!(contact.impulse > 0) || !(speed > 0)) return;
  Vec3<Scalar> change;
  if (mass * speed <= collider.static_friction() * contact.impulse) {
    change = -tangential;  // the impulse that stops it is inside the cone: it sticks
    ++m_report.sticking;
  } else {
    change = -std::min(Scalar(1), collider.kinetic_friction() * contact.impulse / (mass * speed)) * tangential;
    ++m_report.sliding;
  }
  velocity += change;
  m_report.friction_force += (mass / dt) * change;
}

template <class Scalar>
void ContactHandler<Scalar>::respond(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Scalar dt,
                                     Ref3X<Scalar> x_new, Ref3X<Scalar> v_new,
                                     const std::vector<std::uint8_t>& pinned) {
  if (!active()) return;
  if (!m_constrained) {  // a step without constrain() (RK2): start afresh
    for (const Contact& contact : m_contacts) m_slot[static_cast<std::size_t>(contact.node)] = -1;
    m_contacts.clear();
    forget_set_back();
    m_report = {};
    bound(t, dt);
  }
  m_constrained = false;
  const VectorX<Scalar>& masses = *m_masses;
  const Scalar h = m_thickness;
  for (Index i = 0; i < x.cols(); ++i) {
    const int node = static_cast<int>(i);
    if (pinned[static_cast<std::size_t>(node)] != 0) continue;
    const Scalar mass = masses[i];
    int slot = m_slot[static_cast<std::size_t>(node)];
    if (slot < 0) {
      // Not constrained in a solve (RK2, or a node the rounds left over): an impulse to the target.
      Contact contact;
      if (!sweep(node, x.col(i), x_new.col(i), dt, h, contact)) continue;
      if (contact.normal.dot(v_new.col(i)) >= contact.target) continue;  // leaves the surface by itself
      add(contact, nullptr, v);
      slot = m_slot[static_cast<std::size_t>(node)];
    }
    Contact& contact = m_contacts[static_cast<std::size_t>(slot)];
    if (!contact.solved) ++m_report.after_solve;
    Vec3<Scalar> velocity = v_new.col(i);
    const Scalar normal_speed = contact.normal.dot(velocity);
    if (normal_speed < contact.target) {
      contact.impulse += mass * (contact.target - normal_speed);
      velocity += (contact.target - normal_speed) * contact.normal;
    }
    apply_friction(contact, velocity, mass, dt);
    v_new.col(i) = velocity;
    x_new.col(i) = x.col(i) + dt * velocity;
  }
}

template <class Scalar>
void ContactHandler<Scalar>::forget_set_back() {
  for (int i : m_set_back) m_set_back_collider[static_cast<std::size_t>(i)] = -1;
  m_set_back.clear();
}

template <class Scalar>
int ContactHandler<Scalar>::keep_clear(Ref3X<Scalar> x_new, Ref3X<Scalar> v_new,
                                       const std::vector<std::uint8_t>& pinned) {
  if (!active()) return 0;
  int pushed = 0;
  const std::vector<Collider<Scalar>>& colliders = *m_colliders;
  const Scalar h = m_thickness;
  // The guarantee: no node ends deeper than the tolerance.
  const Scalar tolerance = m_tolerance;
  for (Index i = 0; i < x_new.cols(); ++i) {
    if (pinned[static_cast<std::size_t>(i)] != 0) continue;
    for (std::size_t k = 0; k < colliders.size(); ++k) {
      if (!may_reach(k, x_new.col(i), x_new.col(i), x_new.col(i), 0, h)) continue;
      const bool mesh = colliders[k].kind() == ShapeKind::Mesh;
      const Vec3<Scalar> local = mesh ? m_bounds[k].end.to_local(x_new.col(i)) : Vec3<Scalar>::Zero();
      if (mesh && clearance(k, static_cast<int>(i), local, local) >= h) continue;
      const ColliderContact<Scalar> q = query(k, x_new.col(i), true);
      if (mesh) {
        Clearance& c = m_clearance[k];
        c.at.col(i) = local;
        c.distance[i] = q.distance;
        c.travel_at[i] = m_travel[k];
      }
      if (q.distance >= h) continue;
      m_report.deepest = std::max(m_report.deepest, h - q.distance);
      if (q.distance >= h - tolerance) continue;
      x_new.col(i) += (h - q.distance) * q.normal;
      const Scalar approach = q.normal.dot(v_new.col(i) - q.velocity);
      if (approach < 0) v_new.col(i) -= approach * q.normal;
      ++m_report.corrected;
      ++pushed;
      if (m_set_back_collider[static_cast<std::size_t>(i)] < 0) m_set_back.push_back(static_cast<int>(i));
      m_set_back_collider[static_cast<std::size_t>(i)] = static_cast<int>(k);
      m_set_back_normal.col(i) = q.normal;
    }
  }
  return pushed;
}

}  // namespace drape
