#pragma once
/// \file ramped_gravity.hpp
/// Gravity that starts late and ramps in: node i feels \f$ f_i = -m_i\, g\, s(t)\, \hat y \f$ with
/// s = 0 before `start`, rising linearly to 1 over `ramp` seconds, 1 after. A garment's seams close
/// while its panels hang where the pattern placed them, then the sewn garment settles under its
/// weight (garment/garment.hpp); with ClothSpec::gravity at 0 this term is the cloth's whole gravity.
/// The force does not depend on the positions or velocities: no derivatives.

#include <string>
#include <utility>

#include "drape/core/force_term.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar = double>
class RampedGravity final : public ForceTerm<Scalar> {
 public:
  /// `masses` (kg, one per node), `gravity` g (m/s^2, along -y), `start` (s) and `ramp` (s, >= 0; 0
  /// switches gravity on at `start`).
  /// \throws InvalidParameter naming `ramped gravity masses` (each finite and >= 0), `ramped gravity g`
  /// (finite, >= 0), `ramped gravity start` (finite) or `ramped gravity ramp` (finite, >= 0).
  RampedGravity(VectorX<Scalar> masses, Scalar gravity, Scalar start, Scalar ramp)
      : m_masses(std::move(masses)), m_gravity(gravity), m_start(start), m_ramp(ramp) {
    for (Index i = 0; i < m_masses.size(); ++i)
      if (!(std::isfinite(m_masses[i]) && m_masses[i] >= 0))
        detail::fail_argument("ramped gravity masses[" + detail::to_text(i) + "]", detail::to_text(m_masses[i]),
                              "finite and >= 0 kg");
    detail::require_nonnegative_finite("ramped gravity g", gravity);
    detail::require_finite("ramped gravity start", start);
    detail::require_nonnegative_finite("ramped gravity ramp", ramp);
  }

  std::string name() const override { return "ramped gravity"; }

  /// s(t): 0 before the start, 1 from start + ramp on, linear in between.
  Scalar share(Scalar t) const {
    if (t < m_start) return Scalar(0);
    if (!(m_ramp > 0) || t >= m_start + m_ramp) return Scalar(1);
    return (t - m_start) / m_ramp;
  }

  void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>&, Scalar t, Ref3X<Scalar> f) const override {
    if (x.cols() != m_masses.size())
      detail::fail_argument("ramped gravity nodes", detail::to_text(x.cols()),
                            "the " + detail::to_text(m_masses.size()) + " nodes of its masses");
    const Scalar g = m_gravity * share(t);
    if (g == 0) return;
    f.row(1) -= g * m_masses.transpose();
  }

 private:
  VectorX<Scalar> m_masses;
  Scalar m_gravity, m_start, m_ramp;
};

}  // namespace drape
