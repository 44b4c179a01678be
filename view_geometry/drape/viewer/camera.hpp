#pragma once
/// \file camera.hpp
/// Cameras that frame the cloth whatever its size: frame_bounds() fits a box that holds the
/// flat starting cloth and the cloth hanging from its pins (`--camera fixed`), seen from a chosen
/// azimuth and elevation; FollowCamera re-frames the moving cloth every frame (`--camera follow`).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "drape/model/cloth.hpp"
#include "drape/viewer/cloth_shape.hpp"

namespace drape::viewer {

struct Bounds {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f max = Eigen::Vector3f::Constant(-std::numeric_limits<float>::max());

  void extend(const Eigen::Vector3f& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  Eigen::Vector3f centre() const { return 0.5f * (min + max); }
  Eigen::Vector3f size() const { return max - min; }
};

struct Camera {
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();
  Eigen::Vector3f eye = Eigen::Vector3f::Zero();
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  float floor_height = 0;  ///< y of the floor plane, just below the framed box
  float scene_radius = 1;  ///< radius of the framed box's bounding sphere
};

/// The box a cloth stays in while it falls and hangs from the nodes `pins`: the bounding box of
/// `start`, extended down to where each node would hang straight below its nearest pin (5% stretch
/// allowed), and sideways by what the cloth's longer side exceeds the pins' horizontal spread
/// (a cloth hanging from one corner spreads either side of it). Without pins: `start`'s box.
template <class Scalar>
Bounds hanging_bounds(const Cloth<Scalar>& cloth, const Matrix3X<Scalar>& start, const std::vector<int>& pins) {
  Bounds b;
  for (Index i = 0; i < start.cols(); ++i) b.extend(start.col(i).template cast<float>());
  if (pins.empty()) return b;
  Bounds pin_box;
  for (int p : pins) pin_box.extend(start.col(p).template cast<float>());
  float lowest = std::numeric_limits<float>::max();
  for (Index i = 0; i < start.cols(); ++i) {
    float nearest = std::numeric_limits<float>::max();
    float pin_y = 0;
    for (int p : pins) {
      const float d = float((start.col(i) - start.col(p)).norm());
      if (d < nearest) {
        nearest = d;
        pin_y = float(start(1, p));
      }
    }
    lowest = std::min(lowest, pin_y - 1.05f * nearest);
  }
  const float spread = std::max(pin_box.size().x(), pin_box.size().z());
  const float longest = cloth.is_grid() ? float(std::max(cloth.grid().nx() - 1, cloth.grid().ny() - 1)) *
                                              float(cloth.grid().spacing())
                                        : float(longest_side(cloth));
  const float side = 0.5f * std::max(0.0f, longest - spread);
  b.extend(Eigen::Vector3f(pin_box.min.x() - side, lowest, pin_box.min.z() - side));
  b.extend(Eigen::Vector3f(pin_box.max.x() + side, pin_box.max.y(), pin_box.max.z() + side));
  return b;
}

/// hanging_bounds() for the cloth's own pins.
template <class Scalar>
Bounds hanging_bounds(const Cloth<Scalar>& cloth, const Matrix3X<Scalar>& start) {
  return hanging_bounds(cloth, start, cloth.pins().nodes());
}

/// Where a camera looks from: the unit vector from the target to the eye for `azimuth_deg`
/// (0 = from +z, 90 = from +x) and `elevation_deg` (> 0 from above, < 0 from below), and the
/// image's right and up vectors.
struct ViewDirection {
  Eigen::Vector3f back, right, up;
  ViewDirection(float azimuth_deg, float elevation_deg) {
    constexpr float deg = 3.14159265358979f / 180.0f;
    const float az = azimuth_deg * deg, el = elevation_deg * deg;
    back = Eigen::Vector3f(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    right = Eigen::Vector3f::UnitY().cross(back).normalized();
    up = back.cross(right);
  }
};

/// Smallest eye distance from `target` at which point `p` is inside the image: its depth in
/// front of the eye, dist - q.back, must cover |q.right| / tan(fov_x/2) and |q.up| / tan(fov_y/2).
inline float fit_distance(const Eigen::Vector3f& p, const Eigen::Vector3f& target, const ViewDirection& v, float tx,
                          float ty) {
  const Eigen::Vector3f q = p - target;
  return std::max(std::abs(q.dot(v.right)) / tx, std::abs(q.dot(v.up)) / ty) + q.dot(v.back);
}

/// A perspective camera at `dist` from `target` along `v`.
inline Camera look_at(const Eigen::Vector3f& target, float dist, float scene_radius, const ViewDirection& v,
                      float aspect, float fov_y_deg) {
  constexpr float deg = 3.14159265358979f / 180.0f;
  Camera cam;
  cam.target = target;
  cam.scene_radius = scene_radius;
  dist = std::max(dist, 1e-3f);
  cam.eye = target + dist * v.back;
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
  view.block<1, 3>(0, 0) = v.right.transpose();
  view.block<1, 3>(1, 0) = v.up.transpose();
  view.block<1, 3>(2, 0) = v.back.transpose();
  view(0, 3) = -v.right.dot(cam.eye);
  view(1, 3) = -v.up.dot(cam.eye);
  view(2, 3) = -v.back.dot(cam.eye);
  cam.view = view;
  const float ty = std::tan(0.5f * fov_y_deg * deg), tx = ty * aspect;
  const float near_plane = std::max(1e-3f, 0.05f * dist);
  const float far_plane = dist + 12.0f * scene_radius;  // the floor reaches well behind the cloth
  Eigen::Matrix4f proj = Eigen::Matrix4f::Zero();
  proj(0, 0) = 1.0f / tx;
  proj(1, 1) = 1.0f / ty;
  proj(2, 2) = -(far_plane + near_plane) / (far_plane - near_plane);
  proj(2, 3) = -2.0f * far_plane * near_plane / (far_plane - near_plane);
  proj(3, 2) = -1.0f;
  cam.projection = proj;
  return cam;
}

/// A camera looking at the centre of `box` from `azimuth_deg`, `elevation_deg` (see
/// ViewDirection), at the smallest distance at which all 8 corners of the box (grown by `margin`
/// of its largest side) fit the image. The floor goes just below the box.
inline Camera frame_bounds(const Bounds& box, float aspect, float azimuth_deg, float elevation_deg,
                           float fov_y_deg = 35.0f, float margin = 0.06f) {
  constexpr float deg = 3.14159265358979f / 180.0f;
  const Eigen::Vector3f grow = Eigen::Vector3f::Constant(margin * std::max(box.size().maxCoeff(), 1e-6f));
  const Eigen::Vector3f lo = box.min - grow, hi = box.max + grow;
  const Eigen::Vector3f target = 0.5f * (lo + hi);
  const ViewDirection v(azimuth_deg, elevation_deg);
  const float ty = std::tan(0.5f * fov_y_deg * deg), tx = ty * aspect;
  float dist = 0;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3f p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    dist = std::max(dist, fit_distance(p, target, v, tx, ty));
  }
  Camera cam = look_at(target, dist, 0.5f * (hi - lo).norm(), v, aspect, fov_y_deg);
  cam.floor_height = lo.y();
  return cam;
}

/// A camera that follows the cloth: each frame it aims at the centre of the bounding box of the
/// current positions (smoothed with time constant `smoothing`, s of simulated time, so the view
/// glides) and backs off until every node is in the image with a margin (at once when it must
/// back off, smoothed when it can come closer), so the cloth is never cut off. The floor stays at a fixed height (below
/// the lowest point the cloth can hang to), so the cloth's motion still reads against it.
class FollowCamera {
 public:
  FollowCamera(float aspect, float azimuth_deg, float elevation_deg, float floor_height, float smoothing = 0.3f,
               float fov_y_deg = 35.0f, float margin = 0.08f)
      : m_aspect(aspect),
        m_fov(fov_y_deg),
        m_margin(margin),
        m_floor(floor_height),
        m_smoothing(smoothing),
        m_view(azimuth_deg, elevation_deg) {}

  /// The camera for `positions` (`3 x n`), `elapsed` s of simulated time after the previous call.
  template <class Scalar>
  Camera update(const Matrix3X<Scalar>& positions, double elapsed) {
    constexpr float deg = 3.14159265358979f / 180.0f;
    Bounds b;
    for (Index i = 0; i < positions.cols(); ++i) b.extend(positions.col(i).template cast<float>());
    const float a =
        (!m_started || m_smoothing <= 0) ? 1.0f : 1.0f - std::exp(-float(std::max(elapsed, 0.0)) / m_smoothing);
    m_target = m_started ? Eigen::Vector3f(m_target + a * (b.centre() - m_target)) : b.centre();
    // The distance that fits every node around the (smoothed) aim: backing off is immediate so
    // the cloth never leaves the image; moving in is smoothed.
    const float ty = std::tan(0.5f * m_fov * deg) / (1.0f + m_margin), tx = ty * m_aspect;
    float need = 0;
    for (Index i = 0; i < positions.cols(); ++i)
      need = std::max(need, fit_distance(positions.col(i).template cast<float>(), m_target, m_view, tx, ty));
    // A cloth seen exactly edge-on has no extent on screen; keep a sensible minimum distance.
    need = std::max(need, 0.3f * b.size().norm() / std::tan(0.5f * m_fov * deg));
    m_dist = (!m_started || need > m_dist) ? need : m_dist + a * (need - m_dist);
    m_started = true;
    Camera cam = look_at(m_target, m_dist, 0.5f * b.size().norm(), m_view, m_aspect, m_fov);
    cam.floor_height = m_floor;
    return cam;
  }

 private:
  float m_aspect, m_fov, m_margin, m_floor, m_smoothing;
  ViewDirection m_view;
  Eigen::Vector3f m_target = Eigen::Vector3f::Zero();
  float m_dist = 1;
  bool m_started = false;
};

/// What the following camera frames: the nodes, and the 8 corners of the solids' box `solids` when
/// there are solids (`has_solids`). `out` is resized to fit.
inline void framed_points(const Matrix3X<double>& positions, const Bounds& solids, bool has_solids,
                          Matrix3X<double>& out) {
  out.resize(3, positions.cols() + (has_solids ? 8 : 0));
  out.leftCols(positions.cols()) = positions;
  for (int c = 0; c < 8 && has_solids; ++c)
    out.col(positions.cols() + c) =
        Eigen::Vector3f((c & 1) ? solids.max.x() : solids.min.x(), (c & 2) ? solids.max.y() : solids.min.y(),
                        (c & 4) ? solids.max.z() : solids.min.z())
            .cast<double>();
}

}  // namespace drape::viewer
