#pragma once
/// \file wind_field.hpp
/// The air's velocity in space and time: a constant mean wind plus gusts,
/// \f[ w(x, t) = \bar w + \sum_{k=1}^{K} \frac{a}{K}\, d_k \sin(\kappa_k \cdot x - \omega_k t + \varphi_k), \f]
/// a sum of K travelling waves whose directions \f$ d_k \f$ (unit, around the mean wind's
/// direction), wave vectors \f$ \kappa_k \f$, angular frequencies \f$ \omega_k \f$ and phases
/// \f$ \varphi_k \f$ are drawn once from a seed with a fixed generator (splitmix64), so the same
/// seed gives the same gusts on every platform. The gusts never exceed the amplitude a in
/// magnitude; they are smooth in x and t, and the gradient \f$ \partial w / \partial x \f$ is
/// exact (the air terms' implicit derivatives use it). The sines are drape's own (sine.hpp): the
/// waves of a point are evaluated together, vectorised, and give the same bits on every platform.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/platform/sine.hpp"

namespace drape {

/// The gusts of a WindField.
struct GustSettings {
  double amplitude = 0;    ///< m/s: largest gust speed added to the mean wind (0: no gusts)
  double period = 2.0;     ///< s: typical time between gusts (frequencies in [0.5, 1.5] / period)
  double wavelength = 8;   ///< m: typical gust size in space (wave numbers in [0.5, 1.5] 2 pi / wavelength)
  int waves = 4;           ///< K, number of travelling waves
  std::uint64_t seed = 1;  ///< the gusts' seed
  static constexpr int max_waves = 64;

  /// \throws InvalidParameter naming `gust amplitude` (finite, >= 0), `gust period`, `gust
  /// wavelength` (finite, > 0) or `gust waves` ([1, 64]).
  void validate() const {
    detail::require_nonnegative_finite("gust amplitude", amplitude);
    detail::require_positive_finite("gust period", period);
    detail::require_positive_finite("gust wavelength", wavelength);
    detail::require_in_range("gust waves", waves, 1, max_waves);
  }
};

template <class Scalar = double>
class WindField {
 public:
  /// Still air.
  WindField() = default;
  /// \throws InvalidParameter if `mean` is not finite or `gusts` do not validate.
  explicit WindField(const Vec3<Scalar>& mean, const GustSettings& gusts = {});

  /// w(x, t) (m/s).
  Vec3<Scalar> velocity(const Vec3<Scalar>& x, Scalar t) const;
  /// \f$ \partial w / \partial x \f$ at (x, t) (1/s), zero without gusts.
  Mat3<Scalar> gradient(const Vec3<Scalar>& x, Scalar t) const;
  /// True if the wind is the same everywhere and always (no gusts).
  bool uniform() const { return m_omega.empty(); }
  const Vec3<Scalar>& mean() const { return m_mean; }

 private:
  static constexpr int max_waves = GustSettings::max_waves;
  /// The phases kappa_k . x - omega_k t + phi_k of the waves at (x, t), in double.
  void phases(const Vec3<Scalar>& x, Scalar t, double* phase) const {
    const double x0 = double(x[0]), x1 = double(x[1]), x2 = double(x[2]), time = double(t);
    for (std::size_t k = 0; k < m_omega.size(); ++k)
      phase[k] = m_kx[k] * x0 + m_ky[k] * x1 + m_kz[k] * x2 - m_omega[k] * time + m_phase[k];
  }

  Vec3<Scalar> m_mean = Vec3<Scalar>::Zero();
  // The waves, one array per quantity so that the phases and their sines vectorise.
  std::vector<double> m_kx, m_ky, m_kz, m_omega, m_phase;
  std::vector<Vec3<Scalar>> m_amplitude;  // a / K times the unit direction
};

// ---------------------------------------------------------------------------------------------

namespace detail {
/// splitmix64 (Steele, Lea & Flood 2014): a fixed, portable generator for the gusts.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  /// A uniformly distributed unit vector.
  Vec3<double> direction() {
    const double z = 2 * uniform() - 1, phi = 2 * 3.14159265358979323846 * uniform();
    const double r = std::sqrt(std::max(0.0, 1 - z * z));
    return {r * cosine(phi), r * sine(phi), z};  // drape's own: the same bits everywhere
  }
};
}  // namespace detail

template <class Scalar>
WindField<Scalar>::WindField(const Vec3<Scalar>& mean, const GustSettings& gusts) : m_mean(mean) {
  if (!mean.allFinite()) detail::fail_argument("wind", "a non-finite vector", "finite (m/s)");
  gusts.validate();
  if (gusts.amplitude == 0) return;
  const double two_pi = 2 * 3.14159265358979323846;
  const double mean_speed = double(mean.norm());
  detail::SplitMix64 rng{gusts.seed};
  for (int k = 0; k < gusts.waves; ++k) {
    // Gusts blow mostly along the mean wind (any direction in still air).
    Vec3<double> d = rng.direction();
    if (mean_speed > 0) d = (mean.template cast<double>() / mean_speed + 0.5 * d).normalized();
    const Vec3<double> kappa = (two_pi / gusts.wavelength) * (0.5 + rng.uniform()) * rng.direction();
    const double omega = (two_pi / gusts.period) * (0.5 + rng.uniform());
    const double phase = two_pi * rng.uniform();
    m_amplitude.push_back((gusts.amplitude / gusts.waves * d).template cast<Scalar>());
    m_kx.push_back(kappa[0]);
    m_ky.push_back(kappa[1]);
    m_kz.push_back(kappa[2]);
    m_omega.push_back(omega);
    m_phase.push_back(phase);
  }
}

template <class Scalar>
Vec3<Scalar> WindField<Scalar>::velocity(const Vec3<Scalar>& x, Scalar t) const {
  Vec3<Scalar> w = m_mean;
  const std::size_t waves = m_omega.size();
  if (waves == 0) return w;
  double wave[max_waves];
  phases(x, t, wave);
  for (std::size_t k = 0; k < waves; ++k) wave[k] = detail::sine(wave[k]);
  for (std::size_t k = 0; k < waves; ++k) w += m_amplitude[k] * Scalar(wave[k]);
  return w;
}

template <class Scalar>
Mat3<Scalar> WindField<Scalar>::gradient(const Vec3<Scalar>& x, Scalar t) const {
  Mat3<Scalar> g = Mat3<Scalar>::Zero();
  const std::size_t waves = m_omega.size();
  if (waves == 0) return g;
  double wave[max_waves];
  phases(x, t, wave);
  for (std::size_t k = 0; k < waves; ++k) wave[k] = detail::cosine(wave[k]);
  for (std::size_t k = 0; k < waves; ++k)
    g += (m_amplitude[k] * Scalar(wave[k])) *
         Vec3<double>(m_kx[k], m_ky[k], m_kz[k]).template cast<Scalar>().transpose();
  return g;
}

}  // namespace drape
