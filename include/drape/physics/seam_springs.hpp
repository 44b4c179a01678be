#pragma once
/// \file seam_springs.hpp
/// Seams: springs between pairs of nodes that are sewn together (a vertex on one panel's edge and
/// its partner on the other's), pulling the pairs closed while a garment settles and holding them
/// closed after.
///
/// Each pair (a, b) pulls with \f$ f_a = -k \max(0, |d| - L(t))\, \hat d - c\,(v_a - v_b) \f$,
/// \f$ f_b = -f_a \f$, \f$ d = x_a - x_b \f$: a spring that only pulls, whose rest length L shrinks
/// from the pair's gap at the start, \f$ L_0 \f$, linearly to zero at the closing time T, and is
/// zero after (a zero-rest-length spring, linear in x). The gaps so close together and at a speed
/// the stepper can follow, not in one snap; a pair already closer than L(t) feels nothing (the
/// cloth or a collider may close it sooner). Damping acts on the pair's relative velocity, in every
/// direction. Forces come in equal and opposite pairs along d and relative velocities: momentum
/// and angular momentum are kept.
///
/// Derivatives (exact, every variant: the matrix is symmetric and negative semi-definite, so an SPD
/// system stays SPD): \f$ \partial f_a / \partial x_a = -k\,[(1 - L/|d|)(I - \hat d \hat d^T) +
/// \hat d \hat d^T] \f$ where the pair pulls (\f$ -k I \f$ once L = 0), zero where it does not;
/// \f$ \partial f_a / \partial v_a = -c I \f$; the (a, b) blocks are their negatives.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "drape/core/force_term.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar = double>
class SeamSprings final : public ForceTerm<Scalar> {
 public:
  /// `pairs` of node ids sewn together, `start` the nodes' positions when the seams start closing
  /// at time `start_time` (each pair's L0 is its distance there), `stiffness` k (N/m) and `damping`
  /// c (N s/m) per pair, `closing_time` T (s; 0: zero rest length from the start).
  /// \throws InvalidParameter naming `seam pairs` (ids out of range or a node sewn to itself),
  /// `seam stiffness` (finite, > 0), `seam damping`, `seam closing time` (finite, >= 0).
  SeamSprings(std::vector<std::array<int, 2>> pairs, const Matrix3X<Scalar>& start, Scalar stiffness,
              Scalar damping, Scalar closing_time, Scalar start_time = Scalar(0))
      : m_pairs(std::move(pairs)),
        m_stiffness(stiffness),
        m_damping(damping),
        m_closing_time(closing_time),
        m_start_time(start_time) {
    detail::require_positive_finite("seam stiffness", stiffness);
    detail::require_nonnegative_finite("seam damping", damping);
    detail::require_nonnegative_finite("seam closing time", closing_time);
    detail::require_finite("seam start time", start_time);
    const Index n = start.cols();
    m_start_gap.reserve(m_pairs.size());
    for (std::size_t p = 0; p < m_pairs.size(); ++p) {
      const auto [a, b] = m_pairs[p];
      if (a < 0 || b < 0 || a >= n || b >= n || a == b)
        detail::fail_argument("seam pairs[" + detail::to_text(p) + "]",
                              "(" + detail::to_text(a) + ", " + detail::to_text(b) + ")",
                              "two different node ids in [0, " + detail::to_text(n) + ")");
      m_start_gap.push_back((start.col(a) - start.col(b)).norm());
    }
  }

  std::string name() const override { return "seams"; }
  const std::vector<std::array<int, 2>>& pairs() const { return m_pairs; }
  Scalar stiffness() const { return m_stiffness; }
  Scalar damping() const { return m_damping; }
  Scalar closing_time() const { return m_closing_time; }

  /// Pair p's rest length at time t: L0 (1 - (t - t0) / T), clamped to [0, L0].
  Scalar rest_length(std::size_t p, Scalar t) const {
    if (!(m_closing_time > 0)) return Scalar(0);
    const Scalar left = Scalar(1) - (t - m_start_time) / m_closing_time;
    return m_start_gap[p] * std::clamp(left, Scalar(0), Scalar(1));
  }

  /// The widest gap |x_a - x_b| over the pairs (m): how far the seams are from closed.
  Scalar widest_gap(const ConstRef3X<Scalar>& x) const {
    Scalar widest = 0;
    for (const auto& [a, b] : m_pairs) widest = std::max(widest, Scalar((x.col(a) - x.col(b)).norm()));
    return widest;
  }

  void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f) const override {
    for (std::size_t p = 0; p < m_pairs.size(); ++p) {
      const auto [a, b] = m_pairs[p];
      const Vec3<Scalar> pull = pair_force(p, x.col(a) - x.col(b), v.col(a) - v.col(b), t);
      f.col(a) += pull;
      f.col(b) -= pull;
    }
  }

  std::vector<std::array<int, 2>> coupled_nodes() const override { return m_pairs; }
  bool has_derivatives() const override { return true; }

  void add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& /*v*/, Scalar t,
                       ForceDerivatives<Scalar>& out) const override {
    const Mat3<Scalar> dv = -m_damping * Mat3<Scalar>::Identity();
    for (std::size_t p = 0; p < m_pairs.size(); ++p) {
      const auto [a, b] = m_pairs[p];
      const Mat3<Scalar> dx = position_derivative(p, x.col(a) - x.col(b), t);
      out.add(a, a, dx, dv);
      out.add(b, b, dx, dv);
      out.add(a, b, -dx, -dv);
      out.add(b, a, -dx, -dv);
    }
  }

 private:
  /// The force on a (b gets its negative) for d = x_a - x_b and w = v_a - v_b.
  Vec3<Scalar> pair_force(std::size_t p, const Vec3<Scalar>& d, const Vec3<Scalar>& w, Scalar t) const {
    const Scalar rest = rest_length(p, t);
    Vec3<Scalar> pull = -m_damping * w;
    if (rest == 0) return pull - m_stiffness * d;
    const Scalar length = d.norm();
    if (length > rest) pull -= m_stiffness * (length - rest) / length * d;
    return pull;
  }

  /// d f_a / d x_a.
  Mat3<Scalar> position_derivative(std::size_t p, const Vec3<Scalar>& d, Scalar t) const {
    const Scalar rest = rest_length(p, t);
    if (rest == 0) return -m_stiffness * Mat3<Scalar>::Identity();
    const Scalar length = d.norm();
    if (!(length > rest)) return Mat3<Scalar>::Zero();
    const Vec3<Scalar> u = d / length;
    const Mat3<Scalar> uu = u * u.transpose();
    return -m_stiffness * ((Scalar(1) - rest / length) * (Mat3<Scalar>::Identity() - uu) + uu);
  }

  std::vector<std::array<int, 2>> m_pairs;
  std::vector<Scalar> m_start_gap;
  Scalar m_stiffness, m_damping, m_closing_time, m_start_time;
};

}  // namespace drape
