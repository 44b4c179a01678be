#pragma once
/// \file spring_jacobian.hpp
/// Per-spring 3x3 derivative blocks of the damped spring force (drape's implicit.md derives them).
///
/// With \f$ d = x_b - x_a \f$, \f$ L = |d| \f$, \f$ u = d/L \f$, \f$ P = I - u u^T \f$,
/// \f$ w = v_b - v_a \f$ and \f$ f_a = \varphi u \f$, \f$ \varphi = k_s (L - l) + k_d\, w \cdot u \f$:
/// \f[ K = \frac{\partial f_a}{\partial x_b}
///       = k_s u u^T + k_s \Bigl(1 - \frac{l}{L}\Bigr) P
///       + \frac{k_d}{L}\bigl(u\, (P w)^T + (w \cdot u) P\bigr), \qquad
///     D = \frac{\partial f_a}{\partial v_b} = k_d\, u u^T. \f]
/// Because \f$ f_a \f$ depends on \f$ x_b - x_a \f$ and \f$ f_b = -f_a \f$, the four global blocks are
/// \f$ \partial f_a/\partial x_a = \partial f_b/\partial x_b = -K \f$ and
/// \f$ \partial f_a/\partial x_b = \partial f_b/\partial x_a = +K \f$ (same for D).
/// Variants of K: `Exact` keeps every term (non-symmetric because of \f$ u (P w)^T \f$);
/// `Symmetric` drops the damping term (Baraff & Witkin); `Spd` also clamps the transverse factor
/// to \f$ \max(0, 1 - l/L) \f$, so K is positive semi-definite and the implicit system matrix
/// \f$ M - \Delta t\, \partial f/\partial v - \Delta t^2 \partial f/\partial x \f$ is symmetric positive definite.

#include <algorithm>
#include <array>
#include <cstdint>

#include "drape/core/enum_names.hpp"
#include "drape/core/types.hpp"

namespace drape {

/// Which \f$ \partial f / \partial x \f$ the implicit integrator uses.
enum class JacobianVariant : std::uint8_t {
  Exact = 0,      ///< full derivative incl. the damping term's x-derivative (non-symmetric)
  Symmetric = 1,  ///< Baraff-Witkin: damping term's x-derivative dropped (symmetric, may be indefinite)
  Spd = 2,        ///< Symmetric with compressed springs' transverse stiffness clamped to >= 0
};

template <>
struct EnumNames<JacobianVariant> {
  static constexpr const char* parameter = "jacobian";
  static constexpr std::array<EnumName<JacobianVariant>, 3> values{
      {{JacobianVariant::Exact, "exact"}, {JacobianVariant::Symmetric, "symmetric"}, {JacobianVariant::Spd, "spd"}}};
};

/// The scalars every derivative block of one spring is made of (see the file comment):
/// \f$ f_a = \varphi u \f$, \f$ K = k_{uu}\, u u^T + k_I\, I + k_{uw}\, u w^T \f$ and
/// \f$ D = k_d\, u u^T \f$. The system assembly forms \f$ C = \Delta t D + \Delta t^2 K \f$ and
/// \f$ K w \f$ from them directly, without any 3x3 temporary (jacobian_assembler.hpp).
template <class Scalar>
struct SpringLinearisation {
  Vec3<Scalar> u;  ///< unit direction from a to b
  Vec3<Scalar> w;  ///< relative velocity v_b - v_a
  Scalar wu;       ///< w . u
  Scalar phi;      ///< force magnitude: f_a = phi u (N)
  Scalar k_uu;     ///< K's u u^T coefficient (N/m)
  Scalar k_i;      ///< K's identity coefficient (N/m)
  Scalar k_uw;     ///< K's u w^T coefficient (N s/m^2); 0 unless the variant is Exact
};

template <class Scalar>
SpringLinearisation<Scalar> linearise_spring(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& va,
                                             const Vec3<Scalar>& vb, Scalar rest_length, Scalar stiffness,
                                             Scalar damping, JacobianVariant variant) {
  SpringLinearisation<Scalar> s;
  const Vec3<Scalar> d = xb - xa;
  const Scalar length = d.norm();
  const Scalar inv_length = Scalar(1) / length;
  s.u = d * inv_length;
  s.w = vb - va;
  s.wu = s.w.dot(s.u);
  s.phi = stiffness * (length - rest_length) + damping * s.wu;
  // ks u u^T + ks t P = ks t I + ks (1 - t) u u^T with transverse factor t = 1 - l/L.
  Scalar t = Scalar(1) - rest_length * inv_length;
  if (variant == JacobianVariant::Spd) t = std::max(t, Scalar(0));
  s.k_uu = stiffness * (Scalar(1) - t);
  s.k_i = stiffness * t;
  s.k_uw = 0;
  if (variant == JacobianVariant::Exact) {
    // (kd/L) (u (Pw)^T + (w.u) P) = (kd/L) (u w^T + (w.u) I - 2 (w.u) u u^T)
    const Scalar c = damping * inv_length;
    s.k_uw = c;
    s.k_i += c * s.wu;
    s.k_uu -= Scalar(2) * c * s.wu;
  }
  return s;
}

/// Force on node a and the blocks \f$ K = \partial f_a / \partial x_b \f$,
/// \f$ D = \partial f_a / \partial v_b \f$ of one spring (see the file comment).
template <class Scalar>
struct SpringDerivatives {
  Vec3<Scalar> force;  ///< f_a (N)
  Mat3<Scalar> dfdx;   ///< K (N/m)
  Mat3<Scalar> dfdv;   ///< D (N s/m)
};

/// The full 3x3 blocks (assemble_jacobians(), tests); the implicit step uses linearise_spring().
template <class Scalar>
SpringDerivatives<Scalar> spring_derivatives(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& va,
                                             const Vec3<Scalar>& vb, Scalar rest_length, Scalar stiffness,
                                             Scalar damping, JacobianVariant variant) {
  const SpringLinearisation<Scalar> s =
      linearise_spring<Scalar>(xa, xb, va, vb, rest_length, stiffness, damping, variant);
  const Mat3<Scalar> uu = s.u * s.u.transpose();
  SpringDerivatives<Scalar> out;
  out.force = s.phi * s.u;
  out.dfdx = s.k_uu * uu + s.k_uw * (s.u * s.w.transpose());
  out.dfdx.diagonal().array() += s.k_i;
  out.dfdv = damping * uu;
  return out;
}

}  // namespace drape
