#pragma once
/// \file air_drag.hpp
/// Linear air drag on every node, relative to the wind:
/// \f[ f_i = -c\, (v_i - w(x_i, t)), \qquad \frac{\partial f_i}{\partial v_i} = -c I, \qquad
///     \frac{\partial f_i}{\partial x_i} = c\, \frac{\partial w}{\partial x}(x_i, t), \f]
/// with c in N s/m per node. A falling cloth under gravity and this drag reaches the terminal
/// velocity \f$ m g / c \f$. The velocity derivative (symmetric, damping) always enters the implicit
/// system; the position derivative (from gusts that vary in space, not symmetric) only with the
/// Exact Jacobian.

#include <string>

#include "drape/core/force_term.hpp"
#include "drape/core/validation.hpp"
#include "drape/physics/wind_field.hpp"
#include "drape/platform/team.hpp"

namespace drape {

template <class Scalar = double>
class AirDrag final : public ForceTerm<Scalar> {
 public:
  /// \throws InvalidParameter naming `air drag` unless `coefficient` is finite and >= 0 (N s/m).
  AirDrag(Scalar coefficient, WindField<Scalar> wind = {}) : m_c(coefficient), m_wind(std::move(wind)) {
    detail::require_nonnegative_finite("air drag", coefficient);
  }

  std::string name() const override { return "air drag"; }
  Scalar coefficient() const { return m_c; }
  const WindField<Scalar>& wind() const { return m_wind; }

  void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f) const override {
    team_for(static_cast<int>(x.cols()), [&](int i) { f.col(i) -= m_c * (v.col(i) - m_wind.velocity(x.col(i), t)); });
  }

  bool has_derivatives() const override { return m_c > 0; }
  /// Each node's force is its own: a team splits the nodes.
  bool shares_work() const override { return true; }
  void add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>&, Scalar t,
                       ForceDerivatives<Scalar>& out) const override {
    const Mat3<Scalar> dfdv = -m_c * Mat3<Scalar>::Identity();
    const bool gradient = !out.symmetric() && !m_wind.uniform();
    team_for(static_cast<int>(x.cols()), [&](int i) {
      if (gradient)
        out.add(i, i, m_c * m_wind.gradient(x.col(i), t), dfdv);
      else
        out.add_velocity(i, i, dfdv);
    });
  }

 private:
  Scalar m_c;
  WindField<Scalar> m_wind;
};

}  // namespace drape
