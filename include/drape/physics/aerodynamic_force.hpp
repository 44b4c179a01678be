#pragma once
/// \file aerodynamic_force.hpp
/// Aerodynamic drag and lift on every triangle of the cloth, from the relative wind.
///
/// For a triangle with corners a, b, c let \f$ N = \tfrac12 (x_b - x_a) \times (x_c - x_a) \f$ (its
/// area A times its unit normal n), \f$ v = \tfrac13 (v_a + v_b + v_c) - w(\bar x, t) \f$ its
/// velocity relative to the air at its centroid \f$ \bar x \f$, \f$ s = v \cdot N = A\, (v \cdot n) \f$
/// and \f$ q = |v| \f$. With \f$ k_d = \tfrac12 \rho C_d \f$ and \f$ k_l = \tfrac12 \rho C_l \f$:
/// \f[ f_d = -k_d A\, |v \cdot n|\, (v \cdot n)\, n = -k_d \frac{|s|\, s}{N \cdot N} N, \f]
/// drag along the normal, quadratic in the normal relative velocity (a plate moving along its
/// normal at speed u feels \f$ \tfrac12 \rho C_d A u^2 \f$);
/// \f[ f_l = -k_l A\, q\, (v \cdot n)\, (n - (n \cdot \hat v)\, \hat v)
///        = -\frac{k_l}{|N|} \Bigl(s q N - \frac{s^2}{q} v\Bigr), \f]
/// lift perpendicular to the relative wind, in the plane of n and v, of magnitude
/// \f$ \tfrac12 \rho C_l A q^2 \sin\alpha \cos\alpha \f$ at angle of attack \f$ \alpha \f$ (largest at
/// 45 degrees, zero for a plate along or across the flow). Each corner receives a third of
/// \f$ f_d + f_l \f$. Both are independent of the triangle's orientation (N and -N give the same
/// force).
///
/// Derivatives (exact, tested against finite differences): with \f$ J_v = \partial f/\partial v \f$,
/// \f$ J_N = \partial f / \partial N \f$, \f$ \partial N/\partial x_a = \tfrac12 [x_c - x_b]_\times \f$
/// (cyclic) and \f$ G = \partial w / \partial x \f$ at the centroid,
/// \f$ \partial f_i / \partial v_j = J_v / 9 \f$ and
/// \f$ \partial f_i / \partial x_j = \tfrac13 (J_N\, \partial N/\partial x_j - \tfrac13 J_v G) \f$.
/// A symmetric system (Symmetric and Spd Jacobians) receives only the drag's velocity derivative
/// \f$ -2 k_d |s|\, N N^T / (9\, N \cdot N) \f$, lumped: each corner's diagonal block gets the sum
/// of its row, \f$ -2 k_d |s|\, N N^T / (3\, N \cdot N) \f$ (a triangle moving as one is damped
/// alike; a third of the blocks and no off-diagonal ones); symmetric and damping (negative
/// semi-definite). The rest stays explicit. The Exact Jacobian receives every block.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "drape/core/force_term.hpp"
#include "drape/core/validation.hpp"
#include "drape/physics/wind_field.hpp"
#include "drape/platform/team.hpp"

namespace drape {

struct AerodynamicSettings {
  double density = 1.2;           ///< kg/m^3, air
  double drag_coefficient = 1.0;  ///< C_d (a flat plate across the flow: about 1.2)
  double lift_coefficient = 0.0;  ///< C_l

  /// \throws InvalidParameter naming `air density`, `drag coefficient` or `lift coefficient`
  /// unless each is finite and >= 0.
  void validate() const {
    detail::require_nonnegative_finite("air density", density);
    detail::require_nonnegative_finite("drag coefficient", drag_coefficient);
    detail::require_nonnegative_finite("lift coefficient", lift_coefficient);
  }
};

template <class Scalar = double>
class AerodynamicForce final : public ForceTerm<Scalar> {
 public:
  /// `triangles`: node ids of the cloth's triangles (Grid::triangles()).
  /// \throws InvalidParameter as AerodynamicSettings::validate().
  AerodynamicForce(std::vector<std::array<int, 3>> triangles, WindField<Scalar> wind,
                   const AerodynamicSettings& settings)
      : m_triangles(std::move(triangles)), m_wind(std::move(wind)) {
    settings.validate();
    m_kd = Scalar(0.5 * settings.density * settings.drag_coefficient);
    m_kl = Scalar(0.5 * settings.density * settings.lift_coefficient);
    colour_triangles();
  }

  std::string name() const override { return "aerodynamic force"; }
  const WindField<Scalar>& wind() const { return m_wind; }

  /// The aerodynamic force on one triangle (before it is split between the corners) for corner
  /// positions and its velocity relative to the air, and (when the pointers are given) its
  /// derivatives J_v and J_N; `drag_velocity_only`: J_v of the drag alone (the symmetric block),
  /// J_N not computed.
  Vec3<Scalar> triangle_force(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc,
                              const Vec3<Scalar>& v, Mat3<Scalar>* jv = nullptr, Mat3<Scalar>* jn = nullptr,
                              bool drag_velocity_only = false) const;

  void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f) const override {
    for_each_triangle([&](int a, int b, int c) {
      const Vec3<Scalar> third = triangle_force(x.col(a), x.col(b), x.col(c), relative_velocity(x, v, a, b, c, t)) / 3;
      f.col(a) += third;
      f.col(b) += third;
      f.col(c) += third;
    });
  }

  std::vector<std::array<int, 2>> coupled_nodes() const override {
    std::vector<std::array<int, 2>> pairs;
    pairs.reserve(3 * m_triangles.size());
    for (const auto& [a, b, c] : m_triangles) {
      pairs.push_back({a, b});
      pairs.push_back({b, c});
      pairs.push_back({a, c});
    }
    return pairs;
  }

  bool has_derivatives() const override { return m_kd > 0 || m_kl > 0; }
  /// One pass over the triangles for both: the wind at each centroid is evaluated once.
  void add_force_and_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f,
                                 ForceDerivatives<Scalar>& out) const override {
    add_derivatives(x, v, t, out, &f);
  }
  /// Triangles in colours that share no node: a team takes a colour at a time.
  bool shares_work() const override { return true; }
  /// The triangles, sorted by colour: colour c is [colour_begin()[c], colour_begin()[c + 1]).
  const std::vector<std::array<int, 3>>& triangles() const { return m_triangles; }
  const std::vector<int>& colour_begin() const { return m_colour_begin; }
  void add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t,
                       ForceDerivatives<Scalar>& out) const override {
    add_derivatives(x, v, t, out, nullptr);
  }

 private:
  /// Sorts the triangles into colours, greedily in their order: each takes the first colour none
  /// of its corners has yet. Every node then receives its triangles' shares in colour order, one
  /// per colour, whatever the thread count.
  void colour_triangles() {
    std::vector<std::vector<int>> node_colours;  // the colours each node's triangles have taken
    std::vector<int> colour(m_triangles.size());
    int colours = 0;
    for (std::size_t k = 0; k < m_triangles.size(); ++k) {
      for (int node : m_triangles[k]) {
        if (node < 0) detail::fail_argument("triangle corner", detail::to_text(node), ">= 0");
        if (static_cast<std::size_t>(node) >= node_colours.size()) node_colours.resize(std::size_t(node) + 1);
      }
      const auto taken = [&](int c) {
        for (int node : m_triangles[k]) {
          const std::vector<int>& used = node_colours[static_cast<std::size_t>(node)];
          if (std::find(used.begin(), used.end(), c) != used.end()) return true;
        }
        return false;
      };
      int c = 0;
      while (taken(c)) ++c;
      for (int node : m_triangles[k]) node_colours[static_cast<std::size_t>(node)].push_back(c);
      colour[k] = c;
      colours = std::max(colours, c + 1);
    }
    std::vector<std::array<int, 3>> sorted;
    sorted.reserve(m_triangles.size());
    m_colour_begin.assign(1, 0);
    for (int c = 0; c < colours; ++c) {
      for (std::size_t k = 0; k < m_triangles.size(); ++k)
        if (colour[k] == c) sorted.push_back(m_triangles[k]);
      m_colour_begin.push_back(static_cast<int>(sorted.size()));
    }
    m_triangles = std::move(sorted);
  }
  /// add_derivatives(), and the force into `*f` when it is given.
  void add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t,
                       ForceDerivatives<Scalar>& out, Ref3X<Scalar>* f) const;
  /// `body(a, b, c)` for every triangle, a colour at a time, shared by the calling team.
  template <class Body>
  void for_each_triangle(Body&& body) const {
    for (std::size_t c = 0; c + 1 < m_colour_begin.size(); ++c)
      team_for(m_colour_begin[c], m_colour_begin[c + 1], [&](int k) {
        const std::array<int, 3>& corners = m_triangles[static_cast<std::size_t>(k)];
        body(corners[0], corners[1], corners[2]);
      });
  }

  Vec3<Scalar> relative_velocity(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, int a, int b, int c,
                                 Scalar t) const {
    const Vec3<Scalar> centroid = (x.col(a) + x.col(b) + x.col(c)) / 3;
    return (v.col(a) + v.col(b) + v.col(c)) / 3 - m_wind.velocity(centroid, t);
  }
  /// \f$ [u]_\times \f$: the matrix of y -> u x y.
  static Mat3<Scalar> cross_matrix(const Vec3<Scalar>& u) {
    Mat3<Scalar> m;
    m << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
    return m;
  }

  std::vector<std::array<int, 3>> m_triangles;  // sorted by colour
  std::vector<int> m_colour_begin;              // colour c: triangles [begin[c], begin[c + 1])
  WindField<Scalar> m_wind;
  Scalar m_kd = 0, m_kl = 0;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
Vec3<Scalar> AerodynamicForce<Scalar>::triangle_force(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb,
                                                      const Vec3<Scalar>& xc, const Vec3<Scalar>& v, Mat3<Scalar>* jv,
                                                      Mat3<Scalar>* jn, bool drag_velocity_only) const {
  const Vec3<Scalar> n = Scalar(0.5) * (xb - xa).cross(xc - xa);
  const Scalar nn = n.squaredNorm();
  if (jv) jv->setZero();
  if (jn) jn->setZero();
  if (!(nn > 0)) return Vec3<Scalar>::Zero();  // a degenerate triangle has no area
  const Scalar s = v.dot(n), abs_s = std::abs(s);
  // Drag: f_d = -k_d |s| s N / (N.N).
  Vec3<Scalar> f = (-m_kd * abs_s * s / nn) * n;
  if (jv) *jv = (-m_kd * 2 * abs_s / nn) * (n * n.transpose());
  if (drag_velocity_only) {
    jv = nullptr;
    jn = nullptr;
  }
  const Mat3<Scalar> id = Mat3<Scalar>::Identity();
  if (jn)
    *jn = -m_kd * ((2 * abs_s / nn) * (n * v.transpose()) + (abs_s * s / nn) * id -
                   (2 * abs_s * s / (nn * nn)) * (n * n.transpose()));
  const Scalar q = v.norm();
  if (m_kl == 0 || !(q > Scalar(1e-12))) return f;
  // Lift: f_l = -(k_l / |N|) (s q N - s^2 v / q).
  const Scalar len = std::sqrt(nn);
  f += (-m_kl / len) * (s * q * n - (s * s / q) * v);
  if (jv) {
    const Mat3<Scalar> d_t1 = n * (q * n.transpose() + (s / q) * v.transpose());
    const Mat3<Scalar> d_t2 =
        (2 * s / q) * (v * n.transpose()) + (s * s / q) * id - (s * s / (q * q * q)) * (v * v.transpose());
    *jv += (-m_kl / len) * (d_t1 - d_t2);
  }
  if (jn) {
    const Mat3<Scalar> d_t1 = (q / len) * (n * v.transpose() + s * id) - (s * q / (len * nn)) * (n * n.transpose());
    const Mat3<Scalar> d_t2 =
        (2 * s / (q * len)) * (v * v.transpose()) - (s * s / (q * len * nn)) * (v * n.transpose());
    *jn += -m_kl * (d_t1 - d_t2);
  }
  return f;
}

template <class Scalar>
void AerodynamicForce<Scalar>::add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t,
                                               ForceDerivatives<Scalar>& out, Ref3X<Scalar>* f) const {
  const bool symmetric = out.symmetric();
  const Mat3<Scalar> zero = Mat3<Scalar>::Zero();
  for_each_triangle([&](int a, int b, int c) {
    const std::array<int, 3> corner{a, b, c};
    const Vec3<Scalar> vr = relative_velocity(x, v, a, b, c, t);
    Mat3<Scalar> jv, jn;
    const Vec3<Scalar> third = triangle_force(x.col(a), x.col(b), x.col(c), vr, &jv, &jn, symmetric) / 3;
    if (f)
      for (int corner_node : corner) f->col(corner_node) += third;
    const Mat3<Scalar> dfdv = jv / 9;
    if (symmetric) {  // the drag's velocity blocks, lumped on the corners (3 J_v / 9 each)
      const Mat3<Scalar> lumped = jv / 3;
      for (int i = 0; i < 3; ++i) out.add_velocity(corner[i], corner[i], lumped);
      return;
    }
    // dN/dx_j = 1/2 [x_{j+2} - x_{j+1}]_x (cyclic); the centroid moves by dx_j / 3.
    std::array<Mat3<Scalar>, 3> dfdx;
    const Mat3<Scalar> wind =
        m_wind.uniform() ? zero : Mat3<Scalar>(jv * m_wind.gradient((x.col(a) + x.col(b) + x.col(c)) / 3, t) / 3);
    for (int j = 0; j < 3; ++j) {
      const Vec3<Scalar> edge = x.col(corner[(j + 2) % 3]) - x.col(corner[(j + 1) % 3]);
      dfdx[j] = (jn * (Scalar(0.5) * cross_matrix(edge)) - wind) / 3;
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.add(corner[i], corner[j], dfdx[j], dfdv);
  });
}

}  // namespace drape
