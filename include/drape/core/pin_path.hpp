#pragma once
/// \file pin_path.hpp
/// Where a pinned node is at time t: held where it is, along key frames (linear, or smooth: a
/// cubic Hermite curve through the key positions with Catmull-Rom tangents, at rest at the first
/// and last key so a pin starts and stops without a jolt), or given by a user's function. Before
/// the first key the path is at the first position, after the last at the last.

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "drape/core/enum_names.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

enum class Interpolation : std::uint8_t {
  Linear = 0,  ///< straight between key frames (velocity jumps at each key)
  Smooth = 1,  ///< cubic Hermite, Catmull-Rom tangents, zero velocity at the ends (C1)
};

template <>
struct EnumNames<Interpolation> {
  static constexpr const char* parameter = "interpolation";
  static constexpr std::array<EnumName<Interpolation>, 2> values{
      {{Interpolation::Linear, "linear"}, {Interpolation::Smooth, "smooth"}}};
};

template <class Scalar = double>
class PinPath {
 public:
  /// Holds the node where it is.
  PinPath() = default;

  /// Through `positions` (m) at `times` (s). \throws InvalidParameter naming `pin path times`
  /// (at least one, finite, strictly increasing) or `pin path positions` (one per time, finite).
  static PinPath keyframes(std::vector<Scalar> times, std::vector<Vec3<Scalar>> positions,
                           Interpolation interpolation = Interpolation::Smooth);
  /// `position(t)` from the caller (it must be defined for every t the run reaches and return
  /// finite values; a non-finite one fails the step). \throws InvalidParameter if empty.
  static PinPath callback(std::function<Vec3<Scalar>(Scalar)> position);

  /// True for a pin that stays where it is.
  bool holds() const { return m_kind == Kind::Hold; }
  /// The position at `t`; `current` for a pin that holds.
  Vec3<Scalar> position(Scalar t, const Vec3<Scalar>& current) const;

 private:
  enum class Kind : std::uint8_t { Hold, Keyframes, Callback };
  Kind m_kind = Kind::Hold;
  Interpolation m_interpolation = Interpolation::Smooth;
  std::vector<Scalar> m_times;
  std::vector<Vec3<Scalar>> m_positions;
  std::function<Vec3<Scalar>(Scalar)> m_callback;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
PinPath<Scalar> PinPath<Scalar>::keyframes(std::vector<Scalar> times, std::vector<Vec3<Scalar>> positions,
                                           Interpolation interpolation) {
  if (times.empty()) detail::fail_argument("pin path times", "none", "at least one key frame");
  for (std::size_t k = 0; k < times.size(); ++k)
    if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1])))
      detail::fail_argument("pin path times", detail::to_text(times[k]), "finite and strictly increasing");
  if (positions.size() != times.size())
    detail::fail_argument("pin path positions", detail::to_text(positions.size()) + " positions",
                          "one per key time (" + detail::to_text(times.size()) + ")");
  for (const Vec3<Scalar>& p : positions)
    if (!p.allFinite()) detail::fail_argument("pin path positions", "a non-finite position", "finite (m)");
  if (interpolation != Interpolation::Linear && interpolation != Interpolation::Smooth)
    detail::fail_argument("interpolation", detail::to_text(int(interpolation)), "linear or smooth");
  PinPath path;
  path.m_kind = Kind::Keyframes;
  path.m_interpolation = interpolation;
  path.m_times = std::move(times);
  path.m_positions = std::move(positions);
  return path;
}

template <class Scalar>
PinPath<Scalar> PinPath<Scalar>::callback(std::function<Vec3<Scalar>(Scalar)> position) {
  if (!position) detail::fail_argument("pin path", "an empty function", "a function of time");
  PinPath path;
  path.m_kind = Kind::Callback;
  path.m_callback = std::move(position);
  return path;
}

template <class Scalar>
Vec3<Scalar> PinPath<Scalar>::position(Scalar t, const Vec3<Scalar>& current) const {
  switch (m_kind) {
    case Kind::Hold: return current;
    case Kind::Callback: return m_callback(t);
    case Kind::Keyframes: break;
  }
  const std::vector<Scalar>& ts = m_times;
  if (!(t > ts.front())) return m_positions.front();
  if (!(t < ts.back())) return m_positions.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin()) - 1;
  const Scalar span = ts[k + 1] - ts[k];
  const Scalar s = (t - ts[k]) / span;
  const Vec3<Scalar>& p0 = m_positions[k];
  const Vec3<Scalar>& p1 = m_positions[k + 1];
  if (m_interpolation == Interpolation::Linear) return p0 + s * (p1 - p0);
  // Catmull-Rom tangents (m/s), zero at the first and last key.
  const auto tangent = [&](std::size_t i) -> Vec3<Scalar> {
    if (i == 0 || i + 1 == ts.size()) return Vec3<Scalar>::Zero();
    return (m_positions[i + 1] - m_positions[i - 1]) / (ts[i + 1] - ts[i - 1]);
  };
  const Scalar s2 = s * s, s3 = s2 * s;
  const Scalar h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * p0 + (h10 * span) * tangent(k) + h01 * p1 + (h11 * span) * tangent(k + 1);
}

}  // namespace drape
