#pragma once
/// \file collider.hpp
/// Rigid colliders for cloth contact: a plane, a sphere, a capsule, a box with rounded edges and a
/// cylinder with rounded rims, each an exact Euclidean signed distance in its own frame, and a
/// closed triangle mesh (a body, an object read from OBJ), its signed distance from the nearest
/// triangle (collision/mesh_distance.hpp); each placed and moved by a rigid motion. A mesh may also
/// deform: key frames of its vertices (an animated body), linear in time between them. A query returns the signed distance, the outward
/// normal (its analytic gradient) and the velocity of the collider's surface at a point; a swept
/// test finds the first time a point's straight path comes within a given offset of the surface,
/// without sampling, so a fast point cannot tunnel through a thin box or a thin part of a mesh.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "drape/collision/mesh_distance.hpp"
#include "drape/collision/mesh_sweep.hpp"
#include "drape/config.hpp"
#include "drape/core/cloth_mesh.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// A rigid pose at one instant and its rate: world = rotation * local + translation.
template <class Scalar>
struct RigidPose {
  Mat3<Scalar> rotation = Mat3<Scalar>::Identity();
  Vec3<Scalar> translation = Vec3<Scalar>::Zero();
  Vec3<Scalar> velocity = Vec3<Scalar>::Zero();          ///< of the local origin, world frame (m/s)
  Vec3<Scalar> angular_velocity = Vec3<Scalar>::Zero();  ///< world frame (rad/s)

  Vec3<Scalar> to_local(const Vec3<Scalar>& x) const { return rotation.transpose() * (x - translation); }
  Vec3<Scalar> to_world(const Vec3<Scalar>& p) const { return rotation * p + translation; }
  /// Velocity of the body's material point that is at world point x now.
  Vec3<Scalar> point_velocity(const Vec3<Scalar>& x) const {
    return velocity + angular_velocity.cross(x - translation);
  }
};

/// How a collider moves: fixed, with constant linear and angular velocity, or along a user's
/// callback (animation, a driven body).
template <class Scalar>
class RigidMotion {
 public:
  /// Static at the identity.
  RigidMotion() = default;
  /// \throws InvalidParameter naming `collider position` or `collider rotation` (orthonormal, det +1).
  static RigidMotion fixed(const Vec3<Scalar>& translation, const Mat3<Scalar>& rotation = Mat3<Scalar>::Identity());
  /// pose(t): translation p0 + v t, rotation exp([w]x t) R0, so the frame spins about its origin.
  /// \throws InvalidParameter as fixed(), or naming `collider velocity` / `collider angular velocity`.
  static RigidMotion constant(const Vec3<Scalar>& translation, const Mat3<Scalar>& rotation,
                              const Vec3<Scalar>& velocity, const Vec3<Scalar>& angular_velocity);
  /// pose(t) is the callback's value, trusted to be a rigid pose with its rates (not checked per call).
  /// \throws InvalidParameter naming `collider motion` if `pose` is empty.
  static RigidMotion callback(std::function<RigidPose<Scalar>(Scalar)> pose);

  RigidPose<Scalar> pose(Scalar t) const;
  /// True if the pose never changes (fixed, or constant with zero rates); a callback never is.
  bool is_static() const { return !m_callback && m_start.velocity.isZero(0) && m_start.angular_velocity.isZero(0); }

 private:
  RigidPose<Scalar> m_start;  // the pose at t = 0 with its constant rates
  std::function<RigidPose<Scalar>(Scalar)> m_callback;
};

enum class ShapeKind : std::uint8_t { Plane, Sphere, Capsule, Box, Cylinder, Mesh };

template <>
struct EnumNames<ShapeKind> {
  static constexpr const char* parameter = "collider shape";
  static constexpr std::array<EnumName<ShapeKind>, 6> values{{{ShapeKind::Plane, "plane"},
                                                              {ShapeKind::Sphere, "sphere"},
                                                              {ShapeKind::Capsule, "capsule"},
                                                              {ShapeKind::Box, "box"},
                                                              {ShapeKind::Cylinder, "cylinder"},
                                                              {ShapeKind::Mesh, "mesh"}}};
};

/// What a collider query returns at one point and time.
template <class Scalar>
struct ColliderContact {
  Scalar distance;        ///< signed distance to the surface (m), negative inside
  Vec3<Scalar> normal;    ///< outward unit normal, the gradient of the distance (world frame)
  Vec3<Scalar> velocity;  ///< velocity of the collider's material point at the query point (m/s)
};

/// How a collider holds a node in contact this step (what a layer pressing on the node meets).
template <class Scalar>
struct ColliderHold {
  Vec3<Scalar> normal = Vec3<Scalar>::Zero();  ///< the collider's outward unit normal; zero: not held
  Scalar static_friction = 0;                  ///< the collider's static friction coefficient
  bool held() const { return normal.squaredNorm() > 0; }
};

namespace detail {
/// m: how much deeper than the contact thickness h a node may end a step before the end-of-step
/// check pushes it out (contact_handler.hpp): 1% of h, or rounding.
template <class Scalar>
Scalar contact_tolerance(Scalar contact_thickness) {
  return std::max(Scalar(0.01) * contact_thickness, Scalar(64) * std::numeric_limits<Scalar>::epsilon());
}
}  // namespace detail

/// A rigid shape the cloth cannot enter. Each shape is defined in its local frame, which the
/// motion's pose places in the world:
///  - plane: the half-space y <= 0 (outward normal +y);
///  - sphere: radius r about the origin;
///  - capsule: the segment from (-half_length, 0, 0) to (half_length, 0, 0) inflated by r;
///  - box: half extents h about the origin, edges and corners rounded with radius `rounding`
///    inside the same outer size;
///  - cylinder: radius r about the y axis from y = -half_height to half_height, its two rims
///    rounded with radius `rounding` inside the same outer size;
///  - mesh: the solid a closed triangle mesh bounds, its vertices in the local frame. An open mesh
///    (a sheet) is allowed: its front side (faces counter-clockwise) is outside.
template <class Scalar = double>
class Collider {
 public:
  /// The half-space below the plane through `point` with outward `normal` (any length).
  /// \throws InvalidParameter naming `collider position` or `collider normal` (finite, non-zero).
  static Collider plane(const Vec3<Scalar>& point, const Vec3<Scalar>& normal);
  /// \throws InvalidParameter naming `collider position` or `collider radius` (finite, > 0).
  static Collider sphere(const Vec3<Scalar>& center, Scalar radius);
  /// The segment a-b (world) inflated by `radius`.
  /// \throws InvalidParameter naming `collider position`, `capsule axis` (a != b) or `collider radius`.
  static Collider capsule(const Vec3<Scalar>& a, const Vec3<Scalar>& b, Scalar radius);
  /// \throws InvalidParameter naming `collider position`, `collider half extents` (finite, > 0
  /// each), `collider rotation` or `collider rounding` ([0, smallest half extent]).
  static Collider box(const Vec3<Scalar>& center, const Vec3<Scalar>& half_extents,
                      const Mat3<Scalar>& rotation = Mat3<Scalar>::Identity(), Scalar rounding = 0);
  /// A cylinder about its local y axis (turned by `rotation`), centred at `center`.
  /// \throws InvalidParameter naming `collider position`, `collider radius` or `collider half height`
  /// (finite, > 0), `collider rotation` or `collider rounding` ([0, min(radius, half height)]).
  static Collider cylinder(const Vec3<Scalar>& center, Scalar radius, Scalar half_height,
                           const Mat3<Scalar>& rotation = Mat3<Scalar>::Identity(), Scalar rounding = 0);

  /// The solid bounded by `triangles` over `vertices` (3 x n, the local frame), placed at
  /// `position` turned by `rotation`. Quads count as two triangles (0, 1, 2), (0, 2, 3).
  /// \throws InvalidParameter naming `collider mesh` and the element (ClothMesh::validate(): an
  /// empty mesh, an id out of range, a non-finite coordinate, a zero-area face, an edge of more
  /// than two faces, faces that disagree on orientation), or `collider mesh` if a closed mesh's
  /// faces wind inward (negative volume); then `collider position` or `collider rotation`.
  static Collider mesh(const ClothMesh<Scalar>& mesh, const Vec3<Scalar>& position = Vec3<Scalar>::Zero(),
                       const Mat3<Scalar>& rotation = Mat3<Scalar>::Identity());

  /// A mesh whose vertices move: `frames[k]` (3 x n, the local frame, n = mesh.positions.cols())
  /// at `times[k]` (s), linear in between, held before the first and after the last. The faces are
  /// mesh's and every frame must suit them (as mesh.positions must); mesh.positions itself is not
  /// used. \throws InvalidParameter as mesh(), naming `collider frames[k]` (its column count, a
  /// non-finite coordinate, a zero-area face, faces that wind inward), or `collider frame times`
  /// (one per frame, finite, strictly increasing).
  static Collider animated_mesh(const ClothMesh<Scalar>& mesh, const std::vector<Matrix3X<Scalar>>& frames,
                                const std::vector<Scalar>& times, const Vec3<Scalar>& position = Vec3<Scalar>::Zero(),
                                const Mat3<Scalar>& rotation = Mat3<Scalar>::Identity());

  /// The motion of the shape's local frame; it replaces the factory's placement.
  Collider& set_motion(RigidMotion<Scalar> motion);
  /// Constant velocities from the current placement at t = 0, spinning about the shape's centre
  /// (the plane's point). \throws InvalidParameter as RigidMotion::constant.
  Collider& moving(const Vec3<Scalar>& velocity, const Vec3<Scalar>& angular_velocity = Vec3<Scalar>::Zero());
  /// Coulomb coefficients; kinetic may exceed static (the contact code decides what to make of it).
  /// \throws InvalidParameter naming `static friction` or `kinetic friction` (finite, >= 0).
  Collider& set_friction(Scalar static_coefficient, Scalar kinetic_coefficient);

  ShapeKind kind() const { return m_kind; }
  /// Sphere, capsule and cylinder radius (0 for the other shapes).
  Scalar radius() const { return m_radius; }
  /// Capsule half length (0 for the other shapes).
  Scalar half_length() const { return m_half_length; }
  /// Box half extents (zero for the other shapes).
  const Vec3<Scalar>& half_extents() const { return m_half_extents; }
  /// Cylinder half height along its local y axis (0 for the other shapes).
  Scalar half_height() const { return m_half_height; }
  /// Box edge and cylinder rim rounding (0 for the other shapes).
  Scalar rounding() const { return m_rounding; }
  Scalar static_friction() const { return m_static_friction; }
  Scalar kinetic_friction() const { return m_kinetic_friction; }
  const RigidMotion<Scalar>& motion() const { return m_motion; }
  /// A mesh collider's geometry in its local frame (null for the other shapes); for a deforming
  /// mesh, its first frame.
  const MeshDistance<Scalar>* mesh() const { return m_mesh.get(); }
  /// True for a mesh with key frames (animated_mesh()).
  bool deforms() const { return m_frames != nullptr; }
  /// A mesh collider's vertices at time t in its local frame (the key frames interpolated).
  void mesh_positions(Scalar t, Matrix3X<Scalar>& out) const;
  /// Radius of a ball about the local origin that holds the shape (infinite for a plane): the
  /// contact search skips points farther than this from the collider (broad phase).
  Scalar bounding_radius() const {
    switch (m_kind) {
      case ShapeKind::Plane: return std::numeric_limits<Scalar>::infinity();
      case ShapeKind::Sphere: return m_radius;
      case ShapeKind::Capsule: return m_half_length + m_radius;
      case ShapeKind::Box: return m_half_extents.norm();
      case ShapeKind::Cylinder: {  // the inner cylinder's rim, inflated by the rounding
        const Scalar r = m_radius - m_rounding, h = m_half_height - m_rounding;
        return std::sqrt(r * r + h * h) + m_rounding;
      }
      case ShapeKind::Mesh: return m_mesh_radius;
    }
    return std::numeric_limits<Scalar>::infinity();
  }

  /// Signed distance, outward normal and surface velocity at world point x at time t. A deforming
  /// mesh is interpolated and its tree built for the call (O(n log n)): ContactHandler keeps its
  /// own per step (collision/mesh_sweep.hpp).
  ColliderContact<Scalar> query(const Vec3<Scalar>& x, Scalar t) const;
  /// query() with the collider's pose at that time given (a caller that queries many points); not
  /// for a deforming mesh, whose shape depends on the time.
  ColliderContact<Scalar> query(const Vec3<Scalar>& x, const RigidPose<Scalar>& pose) const;
  /// Swept test of a point going from x0 at t0 to x1 at t1 along a straight line in the collider's
  /// frame (between pose(t0).to_local(x0) and pose(t1).to_local(x1)) against the surface moved out
  /// by `offset` >= 0: the first s in [0, 1] with distance <= offset (0 if the path starts there),
  /// or -1 if it never comes that close. Every shape is convex, so the distance along a line is a
  /// convex function of s: Newton steps from the start never pass its first root (conservative
  /// advancement, with steps at least the 1-Lipschitz bound's; exact in one step for the plane) and
  /// a tangent that misses proves a miss. A mesh is not convex, but each of its triangles is: the
  /// same steps per triangle near the path, the least root wins (MeshDistance::first_contact()).
  /// Tolerance max(1e-6, 16 eps) (1 + offset) m.
  /// No sampling: a fast point cannot skip a thin box. After 100 steps (a pathological path) the s
  /// reached, before which the path stays outside the offset surface, is returned.
  Scalar first_contact(const Vec3<Scalar>& x0, Scalar t0, const Vec3<Scalar>& x1, Scalar t1, Scalar offset) const;
  /// first_contact() with the collider's poses at t0 and t1 given (not for a deforming mesh).
  Scalar first_contact(const Vec3<Scalar>& x0, const RigidPose<Scalar>& pose0, const Vec3<Scalar>& x1,
                       const RigidPose<Scalar>& pose1, Scalar offset) const;

 private:
  struct LocalDistance {
    Scalar distance;
    Vec3<Scalar> normal;
  };

  Collider(ShapeKind kind, RigidMotion<Scalar> motion) : m_kind(kind), m_motion(std::move(motion)) {}
  /// The shape's signed distance and its gradient at local point p.
  LocalDistance local_distance(const Vec3<Scalar>& p) const;
  LocalDistance cylinder_distance(const Vec3<Scalar>& p) const;

  ShapeKind m_kind;
  RigidMotion<Scalar> m_motion;
  Scalar m_radius = 0, m_half_length = 0, m_half_height = 0, m_rounding = 0;
  Vec3<Scalar> m_half_extents = Vec3<Scalar>::Zero();
  Scalar m_static_friction = 0, m_kinetic_friction = 0;
  std::shared_ptr<const MeshDistance<Scalar>> m_mesh;  // shared by copies: the geometry never changes
  /// A deforming mesh's key frames.
  struct KeyFrames {
    std::vector<Matrix3X<Scalar>> positions;
    std::vector<Scalar> times;
  };
  std::shared_ptr<const KeyFrames> m_frames;
  Scalar m_mesh_radius = 0;  // the largest vertex distance from the local origin over all frames
};

namespace detail {
/// The swept tests' tolerance on a distance (m): max(1e-6, 16 eps) (1 + offset).
template <class Scalar>
Scalar swept_tolerance(Scalar offset) {
  return std::max(Scalar(1e-6), 16 * std::numeric_limits<Scalar>::epsilon()) * (1 + offset);
}
}  // namespace detail

// ---------------------------------------------------------------------------------------------

namespace detail {
template <class S>
std::string vec3_text(const Vec3<S>& v) {
  return "(" + to_text(v.x()) + ", " + to_text(v.y()) + ", " + to_text(v.z()) + ")";
}

template <class S>
void require_finite_vector(const char* name, const Vec3<S>& v) {
  if (!v.allFinite()) fail_argument(name, vec3_text(v), "finite");
}

/// Orthonormal to within 1e-4 (room for a rotation typed with a few digits), determinant +1.
template <class S>
void require_rotation(const char* name, const Mat3<S>& r) {
  const bool ok = r.allFinite() && (r.transpose() * r - Mat3<S>::Identity()).cwiseAbs().maxCoeff() <= S(1e-4) &&
                  r.determinant() > 0;
  if (!ok) fail_argument(name, "a 3x3 matrix that is not a rotation", "orthonormal with determinant +1");
}
}  // namespace detail

template <class Scalar>
RigidMotion<Scalar> RigidMotion<Scalar>::fixed(const Vec3<Scalar>& translation, const Mat3<Scalar>& rotation) {
  return constant(translation, rotation, Vec3<Scalar>::Zero(), Vec3<Scalar>::Zero());
}

template <class Scalar>
RigidMotion<Scalar> RigidMotion<Scalar>::constant(const Vec3<Scalar>& translation, const Mat3<Scalar>& rotation,
                                                  const Vec3<Scalar>& velocity, const Vec3<Scalar>& angular_velocity) {
  detail::require_finite_vector("collider position", translation);
  detail::require_rotation("collider rotation", rotation);
  detail::require_finite_vector("collider velocity", velocity);
  detail::require_finite_vector("collider angular velocity", angular_velocity);
  RigidMotion motion;
  motion.m_start = {rotation, translation, velocity, angular_velocity};
  return motion;
}

template <class Scalar>
RigidMotion<Scalar> RigidMotion<Scalar>::callback(std::function<RigidPose<Scalar>(Scalar)> pose) {
  if (!pose) detail::fail_argument("collider motion", "an empty function", "a callable t -> RigidPose");
  RigidMotion motion;
  motion.m_callback = std::move(pose);
  return motion;
}

template <class Scalar>
RigidPose<Scalar> RigidMotion<Scalar>::pose(Scalar t) const {
  if (m_callback) return m_callback(t);
  RigidPose<Scalar> p = m_start;
  p.translation += t * m_start.velocity;
  const Scalar rate = m_start.angular_velocity.norm();
  if (rate > 0)
    p.rotation =
        Eigen::AngleAxis<Scalar>(rate * t, m_start.angular_velocity / rate).toRotationMatrix() * m_start.rotation;
  return p;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::plane(const Vec3<Scalar>& point, const Vec3<Scalar>& normal) {
  if (!(normal.allFinite() && normal.norm() > 0))
    detail::fail_argument("collider normal", detail::vec3_text(normal), "finite and non-zero");
  const Mat3<Scalar> rotation =
      Eigen::Quaternion<Scalar>::FromTwoVectors(Vec3<Scalar>::UnitY(), normal.normalized()).toRotationMatrix();
  return Collider(ShapeKind::Plane, RigidMotion<Scalar>::fixed(point, rotation));
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::sphere(const Vec3<Scalar>& center, Scalar radius) {
  detail::require_positive_finite("collider radius", radius);
  Collider c(ShapeKind::Sphere, RigidMotion<Scalar>::fixed(center));
  c.m_radius = radius;
  return c;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::capsule(const Vec3<Scalar>& a, const Vec3<Scalar>& b, Scalar radius) {
  detail::require_finite_vector("collider position", a);
  detail::require_finite_vector("collider position", b);
  const Vec3<Scalar> axis = b - a;
  if (!(axis.norm() > 0)) detail::fail_argument("capsule axis", "a == b", "a != b");
  detail::require_positive_finite("collider radius", radius);
  const Mat3<Scalar> rotation =
      Eigen::Quaternion<Scalar>::FromTwoVectors(Vec3<Scalar>::UnitX(), axis.normalized()).toRotationMatrix();
  Collider c(ShapeKind::Capsule, RigidMotion<Scalar>::fixed(Scalar(0.5) * (a + b), rotation));
  c.m_radius = radius;
  c.m_half_length = Scalar(0.5) * axis.norm();
  return c;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::box(const Vec3<Scalar>& center, const Vec3<Scalar>& half_extents,
                                       const Mat3<Scalar>& rotation, Scalar rounding) {
  for (int k = 0; k < 3; ++k) detail::require_positive_finite("collider half extents", half_extents[k]);
  const Scalar smallest = half_extents.minCoeff();
  if (!(rounding >= 0 && rounding <= smallest))
    detail::fail_argument("collider rounding", detail::to_text(rounding), "[0, " + detail::to_text(smallest) + "]");
  Collider c(ShapeKind::Box, RigidMotion<Scalar>::fixed(center, rotation));
  c.m_half_extents = half_extents;
  c.m_rounding = rounding;
  return c;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::cylinder(const Vec3<Scalar>& center, Scalar radius, Scalar half_height,
                                            const Mat3<Scalar>& rotation, Scalar rounding) {
  detail::require_positive_finite("collider radius", radius);
  detail::require_positive_finite("collider half height", half_height);
  const Scalar smallest = std::min(radius, half_height);
  if (!(rounding >= 0 && rounding <= smallest))
    detail::fail_argument("collider rounding", detail::to_text(rounding), "[0, " + detail::to_text(smallest) + "]");
  Collider c(ShapeKind::Cylinder, RigidMotion<Scalar>::fixed(center, rotation));
  c.m_radius = radius;
  c.m_half_height = half_height;
  c.m_rounding = rounding;
  return c;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::mesh(const ClothMesh<Scalar>& mesh, const Vec3<Scalar>& position,
                                        const Mat3<Scalar>& rotation) {
  mesh.validate("collider mesh");
  std::vector<std::array<int, 3>> triangles = mesh.all_triangles();
  // Closed: every edge in two faces (validate() allows at most two). Counted by its directed half-edges.
  std::vector<long long> half_edges;
  half_edges.reserve(3 * triangles.size());
  for (const std::array<int, 3>& t : triangles)
    for (int k = 0; k < 3; ++k) half_edges.push_back(detail::edge_key(t[std::size_t(k)], t[std::size_t((k + 1) % 3)]));
  std::sort(half_edges.begin(), half_edges.end());
  bool closed = true;
  for (std::size_t k = 0; k < half_edges.size() && closed; k += 2)
    closed = k + 1 < half_edges.size() && half_edges[k] == half_edges[k + 1];
  Collider c(ShapeKind::Mesh, RigidMotion<Scalar>::fixed(position, rotation));
  c.m_mesh = std::make_shared<const MeshDistance<Scalar>>(std::move(triangles), mesh.positions);
  c.m_mesh_radius = c.m_mesh->bounding_radius();
  const Scalar volume = c.m_mesh->signed_volume();
  if (closed && !(volume > 0))
    detail::fail_argument("collider mesh", "faces that wind inward (volume " + detail::to_text(volume) + " m^3)",
                          "faces counter-clockwise seen from outside (positive volume)");
  return c;
}

template <class Scalar>
Collider<Scalar> Collider<Scalar>::animated_mesh(const ClothMesh<Scalar>& mesh, const std::vector<Matrix3X<Scalar>>& frames,
                                                 const std::vector<Scalar>& times, const Vec3<Scalar>& position,
                                                 const Mat3<Scalar>& rotation) {
  if (frames.empty()) detail::fail_argument("collider frames", "none", "at least one key frame");
  if (times.size() != frames.size())
    detail::fail_argument("collider frame times", detail::to_text(times.size()) + " times",
                          "one per frame (" + detail::to_text(frames.size()) + ")");
  for (std::size_t k = 0; k < times.size(); ++k)
    if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
      detail::fail_argument("collider frame times", "times[" + detail::to_text(k) + "] = " + detail::to_text(times[k]),
                            "finite and strictly increasing");
  // Each frame checked as a static mesh would be; the first one is the collider's shape at rest.
  const auto frame_collider = [&](std::size_t k) {
    const std::string name = "collider frames[" + detail::to_text(k) + "]";
    if (frames[k].cols() != mesh.positions.cols())
      detail::fail_argument(name, detail::to_text(frames[k].cols()) + " vertices",
                            detail::to_text(mesh.positions.cols()) + " (the mesh's)");
    ClothMesh<Scalar> frame = mesh;
    frame.positions = frames[k];
    try {
      return Collider::mesh(frame, position, rotation);
    } catch (const InvalidParameter& e) {
      // "collider mesh.triangles[3]" -> "collider frames[2].triangles[3]"
      if (e.parameter().rfind("collider mesh", 0) != 0) throw;
      detail::fail_argument(name + e.parameter().substr(13), e.value(), e.allowed());
    }
  };
  Collider c = frame_collider(0);
  for (std::size_t k = 1; k < frames.size(); ++k) c.m_mesh_radius = std::max(c.m_mesh_radius, frame_collider(k).m_mesh_radius);
  c.m_frames = std::make_shared<const KeyFrames>(KeyFrames{frames, times});
  return c;
}

template <class Scalar>
void Collider<Scalar>::mesh_positions(Scalar t, Matrix3X<Scalar>& out) const {
  DRAPE_ASSERT(m_kind == ShapeKind::Mesh, "mesh_positions: not a mesh collider");
  if (!m_frames) {
    out = m_mesh->positions();
    return;
  }
  const std::vector<Scalar>& times = m_frames->times;
  const std::vector<Matrix3X<Scalar>>& x = m_frames->positions;
  if (!(t > times.front())) {
    out = x.front();
    return;
  }
  if (!(t < times.back())) {
    out = x.back();
    return;
  }
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
  const Scalar w = (t - times[k - 1]) / (times[k] - times[k - 1]);
  out = (1 - w) * x[k - 1] + w * x[k];
}

template <class Scalar>
Collider<Scalar>& Collider<Scalar>::set_motion(RigidMotion<Scalar> motion) {
  m_motion = std::move(motion);
  return *this;
}

template <class Scalar>
Collider<Scalar>& Collider<Scalar>::moving(const Vec3<Scalar>& velocity, const Vec3<Scalar>& angular_velocity) {
  const RigidPose<Scalar> start = m_motion.pose(0);
  m_motion = RigidMotion<Scalar>::constant(start.translation, start.rotation, velocity, angular_velocity);
  return *this;
}

template <class Scalar>
Collider<Scalar>& Collider<Scalar>::set_friction(Scalar static_coefficient, Scalar kinetic_coefficient) {
  detail::require_nonnegative_finite("static friction", static_coefficient);
  detail::require_nonnegative_finite("kinetic friction", kinetic_coefficient);
  m_static_friction = static_coefficient;
  m_kinetic_friction = kinetic_coefficient;
  return *this;
}

template <class Scalar>
typename Collider<Scalar>::LocalDistance Collider<Scalar>::local_distance(const Vec3<Scalar>& p) const {
  // Where the gradient is undefined (a sphere's centre, a capsule's axis) any unit vector is a
  // valid subgradient; +y is perpendicular to the capsule's axis.
  const auto away = [](const Vec3<Scalar>& e, Scalar length) -> Vec3<Scalar> {
    return length > 0 ? Vec3<Scalar>(e / length) : Vec3<Scalar>::UnitY();
  };
  switch (m_kind) {
    case ShapeKind::Plane: return {p.y(), Vec3<Scalar>::UnitY()};
    case ShapeKind::Sphere: {
      const Scalar r = p.norm();
      return {r - m_radius, away(p, r)};
    }
    case ShapeKind::Capsule: {
      const Vec3<Scalar> e(p.x() - std::clamp(p.x(), -m_half_length, m_half_length), p.y(), p.z());
      const Scalar r = e.norm();
      return {r - m_radius, away(e, r)};
    }
    case ShapeKind::Box: break;
    case ShapeKind::Cylinder: return cylinder_distance(p);
    case ShapeKind::Mesh: {
      const typename MeshDistance<Scalar>::Closest c = m_mesh->closest(p);
      return {c.distance, c.normal};
    }
  }
  // The rounded box: the inner box h - rounding inflated by the rounding.
  const Vec3<Scalar> q = p.cwiseAbs() - (m_half_extents.array() - m_rounding).matrix();
  const Vec3<Scalar> sign = p.unaryExpr([](Scalar v) { return v < 0 ? Scalar(-1) : Scalar(1); });
  const Vec3<Scalar> outside = q.cwiseMax(Scalar(0));
  const Scalar out = outside.norm();
  if (out > 0) return {out - m_rounding, sign.cwiseProduct(outside) / out};
  // Inside the inner box: the nearest face is the flat part of the face with the largest q.
  Index face = 0;
  const Scalar deepest = q.maxCoeff(&face);
  Vec3<Scalar> normal = Vec3<Scalar>::Zero();
  normal[face] = sign[face];
  return {deepest - m_rounding, normal};
}

template <class Scalar>
typename Collider<Scalar>::LocalDistance Collider<Scalar>::cylinder_distance(const Vec3<Scalar>& p) const {
  // A solid of revolution: the nearest surface point lies in p's half-plane through the axis, so the
  // distance is the 2D rounded box's in (distance from the axis, y), the inner rectangle
  // (r - rounding, half_height - rounding) inflated by the rounding.
  const Scalar axial = std::sqrt(p.x() * p.x() + p.z() * p.z());
  // The way out from the axis; on the axis any horizontal unit vector is a subgradient.
  const Vec3<Scalar> radial = axial > 0 ? Vec3<Scalar>(p.x() / axial, 0, p.z() / axial) : Vec3<Scalar>::UnitX();
  const Scalar up = p.y() < 0 ? Scalar(-1) : Scalar(1);
  const Scalar qr = axial - (m_radius - m_rounding), qy = std::abs(p.y()) - (m_half_height - m_rounding);
  const Scalar outr = std::max(qr, Scalar(0)), outy = std::max(qy, Scalar(0));
  const Scalar out = std::sqrt(outr * outr + outy * outy);
  if (out > 0) return {out - m_rounding, (outr * radial + Vec3<Scalar>(0, up * outy, 0)) / out};
  // Inside the inner cylinder: the nearer of the side and the cap.
  if (qr >= qy) return {qr - m_rounding, radial};
  return {qy - m_rounding, Vec3<Scalar>(0, up, 0)};
}

template <class Scalar>
ColliderContact<Scalar> Collider<Scalar>::query(const Vec3<Scalar>& x, Scalar t) const {
  const RigidPose<Scalar> pose = m_motion.pose(t);
  if (!deforms()) return query(x, pose);
  // The mesh now, and its vertices' velocity: the slope of the key frames' segment holding t
  // (zero before the first and after the last).
  Matrix3X<Scalar> now;
  mesh_positions(t, now);
  const MeshDistance<Scalar> surface(m_mesh->triangles(), now);
  const typename MeshDistance<Scalar>::Closest c = surface.closest(pose.to_local(x));
  const std::vector<Scalar>& times = m_frames->times;
  Vec3<Scalar> moving = Vec3<Scalar>::Zero();
  if (t >= times.front() && t < times.back()) {
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
    const std::array<int, 3>& corner = m_mesh->triangles()[static_cast<std::size_t>(c.triangle)];
    for (int q = 0; q < 3; ++q) {
      const Index v = corner[std::size_t(q)];
      moving += c.weights[q] * (m_frames->positions[k].col(v) - m_frames->positions[k - 1].col(v));
    }
    moving /= times[k] - times[k - 1];
  }
  return {c.distance, pose.rotation * c.normal, pose.point_velocity(x) + pose.rotation * moving};
}

template <class Scalar>
Scalar Collider<Scalar>::first_contact(const Vec3<Scalar>& x0, Scalar t0, const Vec3<Scalar>& x1, Scalar t1,
                                       Scalar offset) const {
  if (!deforms()) return first_contact(x0, m_motion.pose(t0), x1, m_motion.pose(t1), offset);
  Matrix3X<Scalar> start, end;
  mesh_positions(t0, start);
  mesh_positions(t1, end);
  MeshSweep<Scalar> sweep(m_mesh->triangles(), start);
  sweep.update(start, end);
  return sweep.first_contact(m_motion.pose(t0).to_local(x0), m_motion.pose(t1).to_local(x1), offset,
                             detail::swept_tolerance(offset));
}

template <class Scalar>
ColliderContact<Scalar> Collider<Scalar>::query(const Vec3<Scalar>& x, const RigidPose<Scalar>& pose) const {
  DRAPE_ASSERT(!deforms(), "query(x, pose): a deforming mesh needs the time");
  const LocalDistance local = local_distance(pose.to_local(x));
  return {local.distance, pose.rotation * local.normal, pose.point_velocity(x)};
}

template <class Scalar>
Scalar Collider<Scalar>::first_contact(const Vec3<Scalar>& x0, const RigidPose<Scalar>& pose0, const Vec3<Scalar>& x1,
                                       const RigidPose<Scalar>& pose1, Scalar offset) const {
  DRAPE_ASSERT(offset >= 0, "first_contact: offset must be >= 0");
  DRAPE_ASSERT(!deforms(), "first_contact(x0, pose0, ...): a deforming mesh needs the times");
  const Vec3<Scalar> p0 = pose0.to_local(x0);
  const Vec3<Scalar> path = pose1.to_local(x1) - p0;
  const Scalar tolerance = detail::swept_tolerance(offset);
  Scalar s = 0;
  if (m_kind == ShapeKind::Mesh) return m_mesh->first_contact(p0, path, offset, tolerance);
  for (int step = 0; step < 100; ++step) {
    const LocalDistance here = local_distance(p0 + s * path);
    const Scalar gap = here.distance - offset;
    if (gap <= tolerance) return s;
    // The gap is convex along the path, so it stays above its tangent: the tangent's root is the
    // next safe s, and a tangent that does not reach 0 before s = 1 proves a miss.
    const Scalar closing = -here.normal.dot(path);
    if (!(gap < closing * (1 - s))) return -1;
    s = std::min(s + gap / closing, Scalar(1));
  }
  return s;
}

}  // namespace drape
