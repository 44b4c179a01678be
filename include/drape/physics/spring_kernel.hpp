#pragma once
/// \file spring_kernel.hpp
/// Per-spring kernels (no assembly): the damped spring of the mass-spring cloth model (structural,
/// shear and bend springs, Provot 1995, "Deformation constraints in a mass-spring model").
///
/// With \f$ d = x_b - x_a \f$, \f$ L = |d| \f$, \f$ u = d / L \f$, \f$ w = v_b - v_a \f$, rest length
/// \f$ l \f$, stiffness \f$ k_s \f$ and damping \f$ k_d \f$:
/// \f[ f = k_s (L - l) + k_d (w \cdot u), \qquad f_a = f\,u, \qquad f_b = -f_a. \f]
/// The elastic part derives from \f$ E = \tfrac12 k_s (L - l)^2 \f$ with \f$ f_a = -\partial E/\partial x_a \f$.
/// A zero-length spring has no direction; the kernels then return non-finite values, which the
/// integrators detect and report (they never commit a non-finite state).

#include "drape/core/types.hpp"

namespace drape {

/// Elastic energy \f$ \tfrac12 k_s (|x_b - x_a| - l)^2 \f$ (J).
template <class Scalar>
Scalar spring_energy(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, Scalar rest_length, Scalar stiffness) {
  const Scalar stretch = (xb - xa).norm() - rest_length;
  return Scalar(0.5) * stiffness * stretch * stretch;
}

/// The factor c of \f$ f_a = c\, d \f$, from the length \f$ L = |d| \f$ and \f$ w \cdot d \f$:
/// \f$ c = (k_s (L - l) + k_d\, (w \cdot d) / L) / L \f$, with one reciprocal instead of three
/// divisions. Every force pass (spring_force and the vectorised ForceAssembler) goes through it.
template <class Scalar>
inline Scalar spring_force_factor(Scalar length, Scalar w_dot_d, Scalar rest_length, Scalar stiffness, Scalar damping) {
  const Scalar inverse_length = Scalar(1) / length;
  const Scalar magnitude = stiffness * (length - rest_length) + damping * (w_dot_d * inverse_length);
  return magnitude * inverse_length;
}

/// Force on node a (N); the force on node b is its negative.
template <class Scalar>
Vec3<Scalar> spring_force(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& va,
                          const Vec3<Scalar>& vb, Scalar rest_length, Scalar stiffness, Scalar damping) {
  const Vec3<Scalar> d = xb - xa;
  return spring_force_factor(d.norm(), (vb - va).dot(d), rest_length, stiffness, damping) * d;
}

}  // namespace drape
