#pragma once
/// \file drape_measures.hpp
/// The measures of the Cusick drape test (BS 5058, ISO 9073-9; drape's cusick.md): a circular
/// specimen of radius R_s lies centred on a horizontal support disk of radius R_d and hangs over
/// its edge; light from above casts its shadow on the horizontal plane (y up).
///
/// - The drape coefficient DC = (A_shadow - A_disk) / (A_specimen - A_disk), with A_disk = pi R_d^2
///   and A_specimen = pi R_s^2 (the flat specimen): 1 for a specimen that stays flat, 0 for one
///   whose overhang hangs straight down.
/// - The shadow is the union of the cloth's triangles projected onto the plane (folds lying over
///   one another count once), measured along `ray_count` rays from the disk's centre: each ray
///   meets every projected triangle in an exact interval, the intervals of a ray are merged, and
///   the area is the sum over rays of the integral of s ds over the merged intervals, times the
///   angle between rays (the midpoint rule in the angle). The only error is that of the angular
///   rule: second order in the angle between rays, below 1e-6 of the area at the default 3600
///   rays for a draped disk (checked in tests/physics/test_drape_measures.cpp). Holes in the shadow
///   are left out, so the shadow need not be star-shaped.
/// - The outline r(phi): the outer end of the shadow along each ray, for plots and folds.
/// - The fold count: the number of maxima of r(phi) around the circle after a light smoothing (a
///   circular moving average `smoothing_degrees` wide) that rise and fall by at least
///   `fold_prominence` of the overhang R_s - R_d (count_outline_folds()).

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

/// How finely the shadow is measured and what counts as a fold.
struct DrapeMeasureOptions {
  /// Rays from the disk's centre, equally spaced in angle: the outline's samples.
  int ray_count = 3600;
  /// Width (degrees) of the circular moving average over r(phi) before folds are counted.
  double smoothing_degrees = 5.0;
  /// A fold rises above the troughs on both sides of it by at least this fraction of R_s - R_d.
  double fold_prominence = 0.02;

  /// \throws InvalidParameter unless ray_count is in [8, 10^7], smoothing_degrees in [0, 90] and
  /// fold_prominence in [0, 1].
  void validate() const;
};

template <class Scalar = double>
struct DrapeMeasures {
  /// (A_shadow - A_disk) / (A_specimen - A_disk).
  Scalar drape_coefficient = Scalar(0);
  /// m^2: the area of the union of the projected triangles.
  Scalar shadow_area = Scalar(0);
  int fold_count = 0;
  /// m: r(phi_k), the distance from the disk's centre to the outer end of the shadow along ray k
  /// (0 where the ray misses it), at the angles of outline_angle().
  VectorX<Scalar> outline_radius;

  /// The angle of ray k: (k + 1/2) 2 pi / ray_count, from +x towards +z (phi = atan2(z, x) about
  /// the disk's centre).
  Scalar outline_angle(int k) const;
};

/// The Cusick measures of the cloth with vertex `positions` (3 x n) and `triangles`, draped over a
/// disk of `disk_radius` centred at `disk_centre` (its x and z are the centre of the rays; its
/// height plays no part). \throws InvalidParameter for a radius that is not finite and > 0, a
/// specimen not larger than the disk, a non-finite centre or position, a vertex id out of range, or
/// bad options.
template <class Scalar>
DrapeMeasures<Scalar> measure_drape(const detail::NonDeducedT<ConstRef3X<Scalar>>& positions,
                                    const std::vector<std::array<int, 3>>& triangles,
                                    const detail::NonDeducedT<Vec3<Scalar>>& disk_centre, Scalar disk_radius,
                                    Scalar specimen_radius, const DrapeMeasureOptions& options = DrapeMeasureOptions{});

/// measure_drape()'s drape coefficient.
template <class Scalar>
Scalar drape_coefficient(const detail::NonDeducedT<ConstRef3X<Scalar>>& positions,
                         const std::vector<std::array<int, 3>>& triangles,
                         const detail::NonDeducedT<Vec3<Scalar>>& disk_centre, Scalar disk_radius,
                         Scalar specimen_radius, const DrapeMeasureOptions& options = DrapeMeasureOptions{}) {
  return measure_drape<Scalar>(positions, triangles, disk_centre, disk_radius, specimen_radius, options)
      .drape_coefficient;
}

/// measure_drape()'s fold count.
template <class Scalar>
int fold_count(const detail::NonDeducedT<ConstRef3X<Scalar>>& positions,
               const std::vector<std::array<int, 3>>& triangles, const detail::NonDeducedT<Vec3<Scalar>>& disk_centre,
               Scalar disk_radius, Scalar specimen_radius, const DrapeMeasureOptions& options = DrapeMeasureOptions{}) {
  return measure_drape<Scalar>(positions, triangles, disk_centre, disk_radius, specimen_radius, options).fold_count;
}

/// The folds of an outline r(phi) sampled at equal angles around the circle: smoothed by a
/// circular moving average `smoothing_degrees` wide (rounded to an odd number of samples), then
/// the maxima that rise by `prominence` (m) or more above the trough before them and fall by as
/// much before the next one rises (hysteresis; the walk starts at the lowest sample, so the circle
/// closes on a trough). A flat outline has 0 folds, r0 + a cos(n phi) has n while its smoothed
/// swing 2a exceeds the prominence.
template <class Scalar>
int count_outline_folds(const VectorX<Scalar>& outline_radius, Scalar prominence, double smoothing_degrees);

// ---------------------------------------------------------------------------------------------

inline void DrapeMeasureOptions::validate() const {
  detail::require_in_range("ray_count", ray_count, 8, 10'000'000);
  if (!(smoothing_degrees >= 0 && smoothing_degrees <= 90))
    detail::fail_argument("smoothing_degrees", detail::to_text(smoothing_degrees), "[0, 90]");
  if (!(fold_prominence >= 0 && fold_prominence <= 1))
    detail::fail_argument("fold_prominence", detail::to_text(fold_prominence), "[0, 1] (a fraction of R_s - R_d)");
}

template <class Scalar>
Scalar DrapeMeasures<Scalar>::outline_angle(int k) const {
  const double two_pi = 2 * 3.14159265358979323846;
  return static_cast<Scalar>((k + 0.5) * two_pi / static_cast<double>(outline_radius.size()));
}

namespace detail {

/// The shadow along `ray_count` rays from the origin of the (x, z) plane: its area and outline.
struct RayShadow {
  double area = 0;
  std::vector<double> outline;
};

/// The interval [s0, s1] of the ray s (cos phi, sin phi), s >= 0, inside the counter-clockwise
/// triangle (a, b, c); s1 < s0 when the ray misses it.
inline std::pair<double, double> ray_through_triangle(const std::array<Eigen::Vector2d, 3>& corner,
                                                      const Eigen::Vector2d& direction) {
  double s0 = 0, s1 = HUGE_VAL;
  for (int k = 0; k < 3; ++k) {
    // Inside edge k: cross(e, s d - a) >= 0, i.e. s cross(e, d) >= cross(e, a).
    const Eigen::Vector2d& a = corner[static_cast<std::size_t>(k)];
    const Eigen::Vector2d e = corner[static_cast<std::size_t>((k + 1) % 3)] - a;
    const double along = e.x() * direction.y() - e.y() * direction.x(), offset = e.x() * a.y() - e.y() * a.x();
    if (along > 0) {
      s0 = std::max(s0, offset / along);
    } else if (along < 0) {
      s1 = std::min(s1, offset / along);
    } else if (offset > 0) {
      return {1, 0};  // parallel to the edge and outside it
    }
  }
  return {s0, s1};
}

inline RayShadow ray_shadow(const std::vector<std::array<Eigen::Vector2d, 3>>& projected, int ray_count) {
  const double two_pi = 2 * 3.14159265358979323846, step = two_pi / ray_count;
  std::vector<std::vector<std::pair<double, double>>> hits(static_cast<std::size_t>(ray_count));
  std::vector<Eigen::Vector2d> direction(static_cast<std::size_t>(ray_count));
  for (int k = 0; k < ray_count; ++k)
    direction[static_cast<std::size_t>(k)] = {std::cos((k + 0.5) * step), std::sin((k + 0.5) * step)};

  for (std::array<Eigen::Vector2d, 3> corner : projected) {
    const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double twice_area = cross(corner[1] - corner[0], corner[2] - corner[0]);
    const double longest = std::max({(corner[1] - corner[0]).squaredNorm(), (corner[2] - corner[1]).squaredNorm(),
                                     (corner[0] - corner[2]).squaredNorm()});
    if (!(std::abs(twice_area) > 1e-14 * longest)) continue;  // seen edge-on: no shadow of its own
    if (twice_area < 0) std::swap(corner[1], corner[2]);      // a fold turned over casts the same shadow
    // The rays the triangle can meet: all of them if it holds the centre, else those within its
    // angular span (below pi, as the triangle is convex and leaves the centre out).
    int first = 0, last = ray_count - 1;
    const bool holds_centre = cross(corner[1] - corner[0], -corner[0]) >= 0 &&
                              cross(corner[2] - corner[1], -corner[1]) >= 0 &&
                              cross(corner[0] - corner[2], -corner[2]) >= 0;
    if (!holds_centre) {
      const double a0 = std::atan2(corner[0].y(), corner[0].x());
      double low = 0, high = 0;
      for (int c = 1; c < 3; ++c) {
        const double d = std::remainder(
            std::atan2(corner[static_cast<std::size_t>(c)].y(), corner[static_cast<std::size_t>(c)].x()) - a0, two_pi);
        low = std::min(low, d);
        high = std::max(high, d);
      }
      first = static_cast<int>(std::ceil((a0 + low) / step - 0.5));
      last = static_cast<int>(std::floor((a0 + high) / step - 0.5));
    }
    for (int k = first; k <= last; ++k) {
      const int ray = ((k % ray_count) + ray_count) % ray_count;
      const std::pair<double, double> s = ray_through_triangle(corner, direction[static_cast<std::size_t>(ray)]);
      if (s.second > s.first) hits[static_cast<std::size_t>(ray)].push_back(s);
    }
  }

  RayShadow shadow;
  shadow.outline.assign(static_cast<std::size_t>(ray_count), 0.0);
  for (int k = 0; k < ray_count; ++k) {
    std::vector<std::pair<double, double>>& ray = hits[static_cast<std::size_t>(k)];
    std::sort(ray.begin(), ray.end());
    // Merge overlapping intervals: a place under two layers of cloth is shadow once.
    double covered = 0, begin = 0, end = -1;
    for (const std::pair<double, double>& s : ray) {
      if (s.first > end) {
        if (end > begin) covered += 0.5 * (end * end - begin * begin);
        begin = s.first;
        end = s.second;
      } else {
        end = std::max(end, s.second);
      }
    }
    if (end > begin) covered += 0.5 * (end * end - begin * begin);
    shadow.area += covered * step;
    shadow.outline[static_cast<std::size_t>(k)] = std::max(0.0, end);
  }
  return shadow;
}

}  // namespace detail

template <class Scalar>
int count_outline_folds(const VectorX<Scalar>& outline_radius, Scalar prominence, double smoothing_degrees) {
  const Index n = outline_radius.size();
  if (n < 3) detail::fail_argument("outline_radius", detail::to_text(n) + " samples", "3 or more");
  if (!outline_radius.allFinite()) detail::fail_argument("outline_radius", "a non-finite sample", "finite radii (m)");
  detail::require_nonnegative_finite("prominence", prominence);
  if (!(smoothing_degrees >= 0 && smoothing_degrees <= 90))
    detail::fail_argument("smoothing_degrees", detail::to_text(smoothing_degrees), "[0, 90]");
  // Circular moving average over `half` samples either side.
  const Index half = static_cast<Index>(std::lround(smoothing_degrees / 360.0 * static_cast<double>(n) / 2));
  std::vector<double> smooth(static_cast<std::size_t>(n));
  double window = 0;
  for (Index k = -half; k <= half; ++k) window += double(outline_radius[((k % n) + n) % n]);
  for (Index k = 0; k < n; ++k) {
    smooth[static_cast<std::size_t>(k)] = window / static_cast<double>(2 * half + 1);
    window += double(outline_radius[(k + half + 1) % n]) - double(outline_radius[((k - half) % n + n) % n]);
  }
  // Walk once around from the lowest sample, counting each rise and fall of at least `prominence`.
  const double step = double(prominence);
  const Index start = static_cast<Index>(std::min_element(smooth.begin(), smooth.end()) - smooth.begin());
  double trough = smooth[static_cast<std::size_t>(start)], peak = trough;
  bool rising = true;  // looking for a rise above the trough, else for a fall below the peak
  int folds = 0;
  for (Index i = 1; i <= n; ++i) {
    const double r = smooth[static_cast<std::size_t>((start + i) % n)];
    if (rising) {
      trough = std::min(trough, r);
      if (r >= trough + step && r > trough) {
        rising = false;
        peak = r;
      }
    } else {
      peak = std::max(peak, r);
      if (r <= peak - step && r < peak) {
        ++folds;
        rising = true;
        trough = r;
      }
    }
  }
  return folds;
}

template <class Scalar>
DrapeMeasures<Scalar> measure_drape(const detail::NonDeducedT<ConstRef3X<Scalar>>& positions,
                                    const std::vector<std::array<int, 3>>& triangles,
                                    const detail::NonDeducedT<Vec3<Scalar>>& disk_centre, Scalar disk_radius,
                                    Scalar specimen_radius, const DrapeMeasureOptions& options) {
  detail::require_positive_finite("disk_radius", disk_radius);
  detail::require_positive_finite("specimen_radius", specimen_radius);
  if (!(specimen_radius > disk_radius))
    detail::fail_argument("specimen_radius", detail::to_text(specimen_radius),
                          "> disk_radius (" + detail::to_text(disk_radius) + "): a specimen that overhangs the disk");
  if (!disk_centre.allFinite())
    detail::fail_argument("disk_centre", "a non-finite coordinate", "finite coordinates (m)");
  options.validate();
  const Index n = positions.cols();
  for (Index v = 0; v < n; ++v)
    if (!positions.col(v).allFinite())
      detail::fail_argument("positions[" + detail::to_text(v) + "]", "a non-finite coordinate",
                            "finite coordinates (m)");

  std::vector<std::array<Eigen::Vector2d, 3>> projected;
  projected.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::array<Eigen::Vector2d, 3> corner;
    for (int c = 0; c < 3; ++c) {
      const int v = triangles[t][static_cast<std::size_t>(c)];
      if (v < 0 || v >= n)
        detail::fail_argument("triangles[" + detail::to_text(t) + "]", "vertex id " + detail::to_text(v),
                              "vertex ids in [0, " + detail::to_text(n - 1) + "]");
      corner[static_cast<std::size_t>(c)] = {double(positions(0, v)) - double(disk_centre.x()),
                                             double(positions(2, v)) - double(disk_centre.z())};
    }
    projected.push_back(corner);
  }
  const detail::RayShadow shadow = detail::ray_shadow(projected, options.ray_count);

  const double pi = 3.14159265358979323846;
  const double disk_area = pi * double(disk_radius) * double(disk_radius),
               specimen_area = pi * double(specimen_radius) * double(specimen_radius);
  DrapeMeasures<Scalar> out;
  out.shadow_area = static_cast<Scalar>(shadow.area);
  out.drape_coefficient = static_cast<Scalar>((shadow.area - disk_area) / (specimen_area - disk_area));
  out.outline_radius.resize(options.ray_count);
  for (int k = 0; k < options.ray_count; ++k)
    out.outline_radius[k] = static_cast<Scalar>(shadow.outline[static_cast<std::size_t>(k)]);
  out.fold_count = count_outline_folds<Scalar>(
      out.outline_radius,
      static_cast<Scalar>(options.fold_prominence * (double(specimen_radius) - double(disk_radius))),
      options.smoothing_degrees);
  return out;
}

}  // namespace drape
