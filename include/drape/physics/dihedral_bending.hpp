#pragma once
/// \file dihedral_bending.hpp
/// Bending of a cloth mesh by the dihedral angle of its hinges (Bridson, Marino and Fedkiw 2003,
/// "Simulation of clothing with folds and wrinkles"; Grinspun, Hirani, Desbrun and Schroeder 2003,
/// "Discrete shells"). drape's bending.md derives everything below.
///
/// Every interior edge (a, b) of the mesh, with c opposite it in triangle (a, b, c) and d in
/// (b, a, d) (ClothMesh::hinges()), is a hinge of signed angle
/// \f[ \theta = \operatorname{atan2}\bigl((n_1 \times n_2) \cdot \hat e,\; n_1 \cdot n_2\bigr), \f]
/// with \f$ n_1, n_2 \f$ the unit normals of the two triangles and \f$ \hat e \f$ the unit edge
/// a -> b: 0 when flat, positive when the hinge bends away from the front side (the side the
/// counter-clockwise corners face), in (-pi, pi]. Its energy and damping force are
/// \f[ E = \tfrac12 k_e\, (\theta - \theta_0)^2, \qquad f = -c_e\, \nabla\theta\, (\nabla\theta \cdot v), \f]
/// \f$ \theta_0 \f$ the hinge's angle in the mesh's rest shape (0 for a flat pattern: a curved 3D
/// mesh keeps its shape) and \f$ \theta - \theta_0 \f$ taken in (-pi, pi]. The per-hinge constants
/// \f$ k_e = k\, 3 |e|^2 / (A_1 + A_2) \f$ and \f$ c_e = c\, 3 |e|^2 / (A_1 + A_2) \f$ (rest edge
/// length, rest triangle areas; k in N m, c in N m s) make the energy of a bent shape independent
/// of the mesh's resolution.
///
/// The term is built from a mesh (its interior edges) or from explicit hinges with their own
/// constants, e.g. hinges across a garment's seams between vertices the mesh does not join
/// (garment/seam_hinges.hpp); rest_constants() gives both their k_e, c_e and rest angle.
///
/// Derivatives: the Exact Jacobian gets the exact \f$ \partial f / \partial x \f$ (the Hessian of E,
/// \f$ -k_e (\nabla\theta \nabla\theta^T + (\theta - \theta_0) \nabla^2\theta) \f$, and the damping
/// force's position derivative) and \f$ \partial f / \partial v = -c_e \nabla\theta \nabla\theta^T \f$;
/// a symmetric system gets the Gauss-Newton part \f$ -k_e \nabla\theta \nabla\theta^T \f$ (negative
/// semi-definite: the SPD system stays SPD) and the same \f$ \partial f / \partial v \f$.
///
/// Threads and memory: the hinges, sorted by their smallest vertex id, form chunks of
/// consecutive hinges (a patch of the mesh whose rows stay in cache while its hinges write them),
/// and the chunks are sorted into colours in which no two chunks share a vertex. A team takes a
/// colour at a time and a thread a whole chunk, so each vertex receives its hinges' forces and
/// blocks in the same order whatever the thread count, and threads write different rows only.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/force_term.hpp"
#include "drape/core/validation.hpp"
#include "drape/platform/team.hpp"

namespace drape {

template <class Scalar = double>
class DihedralBending final : public ForceTerm<Scalar> {
 public:
  /// The blocks \f$ \partial^2 \theta / \partial x_k \partial x_j \f$ of a hinge, k and j in
  /// (a, b, c, d) order (1/m^2).
  using AngleHessian = std::array<std::array<Mat3<Scalar>, 4>, 4>;

  /// One hinge's constants: stiffness k_e (N m), damping c_e (N m s) and rest angle (rad).
  struct HingeConstants {
    Scalar stiffness, damping, rest_angle;
  };

  /// Every interior edge of `mesh` a hinge, with `stiffness` k (N m) and `damping` c (N m s); each
  /// hinge's k_e and c_e are these times 3 |e|^2 / (A1 + A2) (rest_constants()). On
  /// near-equilateral meshes the bending rigidity is about 3 k (drape's bending.md, "Stiffness per
  /// hinge").
  /// \throws InvalidParameter naming `bending stiffness` or `bending damping` unless finite and
  /// >= 0, or as ClothMesh::validate() (naming `mesh`).
  DihedralBending(const ClothMesh<Scalar>& mesh, Scalar stiffness, Scalar damping = Scalar(0));
  /// The given hinges of a cloth of `node_count` nodes, hinge k with `constants[k]`; `name` is the
  /// term's name() (a garment's hinges across its seams: "seam hinges").
  /// \throws InvalidParameter naming `node count` (>= 1), `hinge constants` (one per hinge),
  /// `hinges[k]` (four distinct ids in [0, node_count)), `hinge constants[k].stiffness` or
  /// `.damping` (finite, >= 0) or `.rest_angle` (finite, in [-pi, pi]).
  DihedralBending(int node_count, std::vector<Hinge> hinges, std::vector<HingeConstants> constants,
                  std::string name = "dihedral bending");

  /// The constants of a hinge whose rest shape is (xa, xb, xc, xd) (edge (a, b), c opposite it in
  /// triangle (a, b, c), d in (b, a, d)), for the cloth's `stiffness` k and `damping` c: k and c
  /// times 3 |e|^2 / (A1 + A2) (rest edge length, rest triangle areas) and the rest shape's angle.
  /// \throws InvalidParameter naming `hinge rest shape` when a triangle has no area or the edge no
  /// length.
  static HingeConstants rest_constants(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc,
                                       const Vec3<Scalar>& xd, Scalar stiffness, Scalar damping);

  std::string name() const override { return m_name; }
  /// The mesh constructor's k and c; 0 for a term of explicit hinges, whose constants are per hinge.
  Scalar stiffness() const { return m_stiffness; }
  Scalar damping() const { return m_damping; }
  int node_count() const { return m_node_count; }

  /// Hinges per chunk (the last chunk of the mesh may have fewer).
  static constexpr int hinges_per_chunk = 64;
  /// The mesh's hinges in the order they are worked on: chunk q is [chunk_begin()[q],
  /// chunk_begin()[q + 1]), colour c the chunks [colour_begin()[c], colour_begin()[c + 1]).
  const std::vector<Hinge>& hinges() const { return m_hinges; }
  const std::vector<int>& chunk_begin() const { return m_chunk_begin; }
  const std::vector<int>& colour_begin() const { return m_colour_begin; }
  /// Hinge k's (of hinges()) stiffness k_e (N m), damping c_e (N m s) and rest angle (rad).
  Scalar hinge_stiffness(int k) const { return m_constants[static_cast<std::size_t>(k)].stiffness; }
  Scalar hinge_damping(int k) const { return m_constants[static_cast<std::size_t>(k)].damping; }
  Scalar rest_angle(int k) const { return m_constants[static_cast<std::size_t>(k)].rest_angle; }

  /// The signed dihedral angle (rad, in (-pi, pi]) of the hinge with edge (a, b), c opposite it in
  /// triangle (a, b, c) and d in (b, a, d); 0 when a triangle has no area.
  static Scalar angle(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc, const Vec3<Scalar>& xd);
  /// angle() into `theta`, its gradient (1/m) for a, b, c, d into `gradient` and, if `hessian` is
  /// given, its Hessian blocks. \returns false, and leaves the outputs alone, when a triangle has
  /// no area or the edge no length (the angle is not defined).
  static bool angle_derivatives(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc,
                                const Vec3<Scalar>& xd, Scalar& theta, std::array<Vec3<Scalar>, 4>& gradient,
                                AngleHessian* hessian = nullptr);

  /// J: the elastic energy at positions `x` (3 x node_count()), summed in hinge order.
  Scalar energy(const ConstRef3X<Scalar>& x) const;

  void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar, Ref3X<Scalar> f) const override {
    pass(x, v, &f, nullptr);
  }
  /// Every pair of the four vertices of each hinge, each pair once (smaller id first), sorted.
  std::vector<std::array<int, 2>> coupled_nodes() const override;
  bool has_derivatives() const override { return m_active; }
  /// Chunks of hinges in colours that share no vertex: a team takes a colour at a time.
  bool shares_work() const override { return true; }
  void add_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar,
                       ForceDerivatives<Scalar>& out) const override {
    pass(x, v, nullptr, &out);
  }
  /// One pass over the hinges for both: each hinge's angle and gradient are computed once.
  void add_force_and_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar, Ref3X<Scalar> f,
                                 ForceDerivatives<Scalar>& out) const override {
    pass(x, v, &f, &out);
  }

 private:
  /// Sorts the hinges by smallest vertex id, cuts them into chunks and sorts the chunks into
  /// colours, greedily in that order: each takes the first colour that no chunk sharing a vertex
  /// with it has taken. Constants already given move with their hinges.
  void arrange_hinges();
  /// `body(k)` for every hinge k, shared by the calling team a colour at a time, a chunk per thread.
  template <class Body>
  void for_each_hinge(Body&& body) const {
    for (std::size_t c = 0; c + 1 < m_colour_begin.size(); ++c)
      team_for(m_colour_begin[c], m_colour_begin[c + 1], [&](int q) {
        const int end = m_chunk_begin[static_cast<std::size_t>(q) + 1];
        for (int k = m_chunk_begin[static_cast<std::size_t>(q)]; k < end; ++k) body(k);
      });
  }
  /// The force into `*f` and the blocks into `*out`, whichever is given.
  void pass(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Ref3X<Scalar>* f,
            ForceDerivatives<Scalar>* out) const;
  /// `d` moved into (-pi, pi] by a whole turn.
  static Scalar wrapped(Scalar d) {
    const Scalar pi = Scalar(3.14159265358979323846);
    if (d > pi) return d - 2 * pi;
    if (d <= -pi) return d + 2 * pi;
    return d;
  }

  Scalar m_stiffness = 0, m_damping = 0;
  bool m_active = false;  // some hinge has stiffness or damping
  bool m_damped = false;  // some hinge has damping
  int m_node_count = 0;
  std::string m_name = "dihedral bending";
  std::vector<Hinge> m_hinges;  // by colour, then chunk
  std::vector<HingeConstants> m_constants;
  std::vector<int> m_chunk_begin;   // chunk q: hinges [begin[q], begin[q + 1])
  std::vector<int> m_colour_begin;  // colour c: chunks [begin[c], begin[c + 1])
};

// ---------------------------------------------------------------------------------------------

namespace detail {

/// What the angle of a hinge and its derivatives share: the edge e = x_b - x_a, the wings
/// r_1 = x_c - x_a and r_2 = x_d - x_a, the area-weighted normals N_1 = e x r_1 and N_2 = r_2 x e
/// (both toward the front), and the projections s_i = r_i . e / |e|^2 of the wing tips on the edge.
template <class Scalar>
struct HingeGeometry {
  Vec3<Scalar> e;
  std::array<Vec3<Scalar>, 2> r, normal;
  std::array<Scalar, 2> normal_sq, s;
  Scalar length_sq, length, angle;

  /// False when a triangle has no area or the edge no length.
  bool init(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc, const Vec3<Scalar>& xd) {
    e = xb - xa;
    r[0] = xc - xa;
    r[1] = xd - xa;
    normal[0] = e.cross(r[0]);
    normal[1] = r[1].cross(e);
    length_sq = e.squaredNorm();
    normal_sq[0] = normal[0].squaredNorm();
    normal_sq[1] = normal[1].squaredNorm();
    if (!(length_sq > 0 && normal_sq[0] > 0 && normal_sq[1] > 0)) return false;
    length = std::sqrt(length_sq);
    s[0] = r[0].dot(e) / length_sq;
    s[1] = r[1].dot(e) / length_sq;
    // atan2((n1 x n2) . e^, n1 . n2), both arguments times |N1| |N2| |e| > 0.
    angle = std::atan2(normal[0].cross(normal[1]).dot(e), length * normal[0].dot(normal[1]));
    return true;
  }

  /// dtheta/dx_c (i = 0) or dx_d (i = 1): -|e| N_i / |N_i|^2, the wing's unit normal over its height.
  Vec3<Scalar> wing_gradient(std::size_t i) const { return (-length / normal_sq[i]) * normal[i]; }

  /// Bridson et al.'s gradient: the wing tips' as above, the edge ends' from their share of each
  /// tip's projection on the edge.
  void gradient(std::array<Vec3<Scalar>, 4>& g) const {
    const Vec3<Scalar> w0 = wing_gradient(0), w1 = wing_gradient(1);
    g[0] = (s[0] - 1) * w0 + (s[1] - 1) * w1;
    g[1] = -s[0] * w0 - s[1] * w1;
    g[2] = w0;
    g[3] = w1;
  }

  /// The Hessian of theta: each wing's gradient terms G_a = (s - 1) w, G_b = -s w, G_o = w
  /// differentiated through w(e, r) and s(e, r) (drape's bending.md), the upper blocks computed
  /// and mirrored.
  void hessian(std::array<std::array<Mat3<Scalar>, 4>, 4>& h) const {
    for (auto& row : h)
      for (Mat3<Scalar>& block : row) block.setZero();
    const Vec3<Scalar> e_hat = e / length;
    for (int i = 0; i < 2; ++i) {
      const std::size_t wing = static_cast<std::size_t>(i);
      const Scalar sigma = i == 0 ? Scalar(1) : Scalar(-1);  // N = sigma e x r
      const Vec3<Scalar>& n = normal[wing];
      const Scalar nn = normal_sq[wing];
      const Scalar si = s[wing];
      const Vec3<Scalar> w = wing_gradient(wing);
      // dw = -(N / |N|^2) dl - (l / |N|^2) (I - 2 N N^T / |N|^2) dN, dN = sigma ([e]x dr - [r]x de).
      const Scalar scale = length / nn;
      const Mat3<Scalar> p_e = reflected_cross(e, n, nn), p_r = reflected_cross(r[wing], n, nn);
      const Mat3<Scalar> w_r = (-sigma * scale) * p_e;
      const Mat3<Scalar> w_e = (-1 / nn) * n * e_hat.transpose() + (sigma * scale) * p_r;
      // ds/dr = e / l^2, ds/de = (r - 2 s e) / l^2.
      const Vec3<Scalar> s_r = e / length_sq, s_e = (r[wing] - 2 * si * e) / length_sq;
      // Derivatives by corner a, b, o (x_a moves e and r, x_b moves e, x_o moves r).
      const std::array<int, 3> corner{0, 1, 2 + i};
      const std::array<Mat3<Scalar>, 3> dw{Mat3<Scalar>(-w_e - w_r), w_e, w_r};
      const std::array<Vec3<Scalar>, 3> ds{Vec3<Scalar>(-s_e - s_r), s_e, s_r};
      const std::array<Scalar, 3> coef{si - 1, -si, Scalar(1)}, dcoef{Scalar(1), Scalar(-1), Scalar(0)};
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t j = k; j < 3; ++j) {
          Mat3<Scalar>& block = h[static_cast<std::size_t>(corner[k])][static_cast<std::size_t>(corner[j])];
          block += coef[k] * dw[j];
          if (dcoef[k] != 0) block += dcoef[k] * w * ds[j].transpose();
        }
    }
    for (std::size_t k = 0; k < 4; ++k) {
      h[k][k] = Scalar(0.5) * (h[k][k] + h[k][k].transpose()).eval();
      for (std::size_t j = k + 1; j < 4; ++j) h[j][k] = h[k][j].transpose();
    }
  }

  /// (I - 2 N N^T / |N|^2) [u]x, with [u]x y = u x y.
  static Mat3<Scalar> reflected_cross(const Vec3<Scalar>& u, const Vec3<Scalar>& n, Scalar nn) {
    Mat3<Scalar> m;
    m << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
    // N^T [u]x = (u x y) . N = (N x u) . y
    m -= (2 / nn) * n * n.cross(u).transpose();
    return m;
  }
};

}  // namespace detail

template <class Scalar>
DihedralBending<Scalar>::DihedralBending(const ClothMesh<Scalar>& mesh, Scalar stiffness, Scalar damping)
    : m_stiffness(stiffness), m_damping(damping) {
  detail::require_nonnegative_finite("bending stiffness", stiffness);
  detail::require_nonnegative_finite("bending damping", damping);
  mesh.validate("mesh");
  m_active = stiffness > 0 || damping > 0;
  m_damped = damping > 0;
  m_node_count = mesh.vertex_count();
  m_hinges = mesh.hinges();
  arrange_hinges();
  const Matrix3X<Scalar> rest = mesh.rest_shape();
  m_constants.reserve(m_hinges.size());
  // validate() has rejected triangles without area in the rest shape.
  for (const Hinge& h : m_hinges)
    m_constants.push_back(
        rest_constants(rest.col(h.a), rest.col(h.b), rest.col(h.c), rest.col(h.d), stiffness, damping));
}

template <class Scalar>
DihedralBending<Scalar>::DihedralBending(int node_count, std::vector<Hinge> hinges,
                                         std::vector<HingeConstants> constants, std::string term_name)
    : m_node_count(node_count),
      m_name(std::move(term_name)),
      m_hinges(std::move(hinges)),
      m_constants(std::move(constants)) {
  detail::require_at_least("node count", node_count, 1);
  if (m_constants.size() != m_hinges.size())
    detail::fail_argument("hinge constants", detail::to_text(m_constants.size()) + " entries",
                          "one per hinge (" + detail::to_text(m_hinges.size()) + ")");
  const Scalar pi = Scalar(3.14159265358979323846);
  for (std::size_t k = 0; k < m_hinges.size(); ++k) {
    const Hinge& h = m_hinges[k];
    const std::array<int, 4> v{h.a, h.b, h.c, h.d};
    const std::string where = "hinges[" + detail::to_text(k) + "]";
    for (std::size_t i = 0; i < 4; ++i) {
      if (v[i] < 0 || v[i] >= node_count)
        detail::fail_argument(where, "vertex id " + detail::to_text(v[i]),
                              "vertex ids in [0, " + detail::to_text(node_count - 1) + "]");
      for (std::size_t j = 0; j < i; ++j)
        if (v[j] == v[i])
          detail::fail_argument(where, "vertex " + detail::to_text(v[i]) + " twice", "four distinct vertices");
    }
    const HingeConstants& c = m_constants[k];
    const std::string name = "hinge constants[" + detail::to_text(k) + "]";
    detail::require_nonnegative_finite((name + ".stiffness").c_str(), c.stiffness);
    detail::require_nonnegative_finite((name + ".damping").c_str(), c.damping);
    if (!(std::isfinite(c.rest_angle) && std::abs(c.rest_angle) <= pi))
      detail::fail_argument(name + ".rest_angle", detail::to_text(c.rest_angle), "finite, in [-pi, pi]");
    m_active = m_active || c.stiffness > 0 || c.damping > 0;
    m_damped = m_damped || c.damping > 0;
  }
  arrange_hinges();
}

template <class Scalar>
typename DihedralBending<Scalar>::HingeConstants DihedralBending<Scalar>::rest_constants(
    const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc, const Vec3<Scalar>& xd, Scalar stiffness,
    Scalar damping) {
  detail::HingeGeometry<Scalar> geometry{};
  if (!geometry.init(xa, xb, xc, xd))
    detail::fail_argument("hinge rest shape", "a triangle without area or an edge without length",
                          "two triangles with area on an edge with length");
  // 3 |e|^2 / (A1 + A2) with A_i = |N_i| / 2.
  const Scalar scale = 6 * geometry.length_sq / (std::sqrt(geometry.normal_sq[0]) + std::sqrt(geometry.normal_sq[1]));
  return {stiffness * scale, damping * scale, geometry.angle};
}

template <class Scalar>
void DihedralBending<Scalar>::arrange_hinges() {
  const auto corners = [](const Hinge& h) { return std::array<int, 4>{h.a, h.b, h.c, h.d}; };
  const auto smallest = [&](const Hinge& h) {
    const std::array<int, 4> v = corners(h);
    return *std::min_element(v.begin(), v.end());
  };
  // Where each hinge came from, so that given constants follow it.
  const int hinge_count = static_cast<int>(m_hinges.size());
  std::vector<int> origin(m_hinges.size());
  for (int k = 0; k < hinge_count; ++k) origin[static_cast<std::size_t>(k)] = k;
  std::stable_sort(origin.begin(), origin.end(), [&](int p, int q) {
    return smallest(m_hinges[static_cast<std::size_t>(p)]) < smallest(m_hinges[static_cast<std::size_t>(q)]);
  });
  {
    std::vector<Hinge> by_smallest;
    by_smallest.reserve(m_hinges.size());
    for (int k : origin) by_smallest.push_back(m_hinges[static_cast<std::size_t>(k)]);
    m_hinges = std::move(by_smallest);
  }
  const int chunks = (hinge_count + hinges_per_chunk - 1) / hinges_per_chunk;
  const auto chunk_of = [&](int k) { return k / hinges_per_chunk; };
  // The chunks of each vertex, each once, ascending.
  std::vector<int> begin(static_cast<std::size_t>(m_node_count) + 1, 0), of_vertex, last(begin.size(), -1);
  const auto each_vertex_chunk = [&](auto&& visit) {
    std::fill(last.begin(), last.end(), -1);
    for (int k = 0; k < hinge_count; ++k)
      for (int v : corners(m_hinges[static_cast<std::size_t>(k)]))
        if (last[static_cast<std::size_t>(v)] != chunk_of(k)) {
          last[static_cast<std::size_t>(v)] = chunk_of(k);
          visit(v, chunk_of(k));
        }
  };
  each_vertex_chunk([&](int v, int) { ++begin[static_cast<std::size_t>(v) + 1]; });
  for (std::size_t v = 0; v < static_cast<std::size_t>(m_node_count); ++v) begin[v + 1] += begin[v];
  of_vertex.resize(static_cast<std::size_t>(begin.back()));
  std::vector<int> next(begin.begin(), begin.end() - 1);
  each_vertex_chunk(
      [&](int v, int q) { of_vertex[static_cast<std::size_t>(next[static_cast<std::size_t>(v)]++)] = q; });
  // Greedy: stamp the colours of the coloured chunks that share a vertex, take the first colour not stamped.
  std::vector<int> colour(static_cast<std::size_t>(chunks), -1), stamp;
  for (int q = 0; q < chunks; ++q) {
    for (int k = q * hinges_per_chunk; k < std::min(hinge_count, (q + 1) * hinges_per_chunk); ++k)
      for (int v : corners(m_hinges[static_cast<std::size_t>(k)]))
        for (int p = begin[static_cast<std::size_t>(v)]; p < begin[static_cast<std::size_t>(v) + 1]; ++p) {
          const int c = colour[static_cast<std::size_t>(of_vertex[static_cast<std::size_t>(p)])];
          if (c >= 0) stamp[static_cast<std::size_t>(c)] = q;
        }
    int c = 0;
    while (c < static_cast<int>(stamp.size()) && stamp[static_cast<std::size_t>(c)] == q) ++c;
    if (c == static_cast<int>(stamp.size())) stamp.push_back(-1);
    colour[static_cast<std::size_t>(q)] = c;
  }
  // Chunks sorted by colour (stable), their hinges with them.
  const std::size_t colours = stamp.size();
  m_colour_begin.assign(colours + 1, 0);
  for (int c : colour) ++m_colour_begin[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 0; c < colours; ++c) m_colour_begin[c + 1] += m_colour_begin[c];
  std::vector<int> order(static_cast<std::size_t>(chunks));
  std::vector<int> slot(m_colour_begin.begin(), m_colour_begin.end() - 1);
  for (int q = 0; q < chunks; ++q)
    order[static_cast<std::size_t>(slot[static_cast<std::size_t>(colour[static_cast<std::size_t>(q)])]++)] = q;
  std::vector<Hinge> sorted;
  sorted.reserve(m_hinges.size());
  std::vector<HingeConstants> constants;
  constants.reserve(m_constants.size());
  m_chunk_begin.assign(1, 0);
  for (int q : order) {
    for (int k = q * hinges_per_chunk; k < std::min(hinge_count, (q + 1) * hinges_per_chunk); ++k) {
      sorted.push_back(m_hinges[static_cast<std::size_t>(k)]);
      if (!m_constants.empty())
        constants.push_back(m_constants[static_cast<std::size_t>(origin[static_cast<std::size_t>(k)])]);
    }
    m_chunk_begin.push_back(static_cast<int>(sorted.size()));
  }
  m_hinges = std::move(sorted);
  m_constants = std::move(constants);
}

template <class Scalar>
Scalar DihedralBending<Scalar>::angle(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc,
                                      const Vec3<Scalar>& xd) {
  detail::HingeGeometry<Scalar> geometry;
  return geometry.init(xa, xb, xc, xd) ? geometry.angle : Scalar(0);
}

template <class Scalar>
bool DihedralBending<Scalar>::angle_derivatives(const Vec3<Scalar>& xa, const Vec3<Scalar>& xb, const Vec3<Scalar>& xc,
                                                const Vec3<Scalar>& xd, Scalar& theta,
                                                std::array<Vec3<Scalar>, 4>& gradient, AngleHessian* hessian) {
  detail::HingeGeometry<Scalar> geometry;
  if (!geometry.init(xa, xb, xc, xd)) return false;
  theta = geometry.angle;
  geometry.gradient(gradient);
  if (hessian) geometry.hessian(*hessian);
  return true;
}

template <class Scalar>
Scalar DihedralBending<Scalar>::energy(const ConstRef3X<Scalar>& x) const {
  Scalar sum = 0;
  for (std::size_t k = 0; k < m_hinges.size(); ++k) {
    const Hinge& h = m_hinges[k];
    detail::HingeGeometry<Scalar> geometry{};
    if (!geometry.init(x.col(h.a), x.col(h.b), x.col(h.c), x.col(h.d))) continue;
    const Scalar strain = wrapped(geometry.angle - m_constants[k].rest_angle);
    sum += Scalar(0.5) * m_constants[k].stiffness * strain * strain;
  }
  return sum;
}

template <class Scalar>
std::vector<std::array<int, 2>> DihedralBending<Scalar>::coupled_nodes() const {
  std::vector<std::array<int, 2>> pairs;
  pairs.reserve(6 * m_hinges.size());
  for (const Hinge& h : m_hinges) {
    const std::array<int, 4> v{h.a, h.b, h.c, h.d};
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = i + 1; j < 4; ++j) pairs.push_back({std::min(v[i], v[j]), std::max(v[i], v[j])});
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

template <class Scalar>
void DihedralBending<Scalar>::pass(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Ref3X<Scalar>* f,
                                   ForceDerivatives<Scalar>* out) const {
  if (!m_active) return;
  const bool exact = out && !out->symmetric();
  const bool damped = m_damped;
  for_each_hinge([&](int k) {
    const Hinge& hinge = m_hinges[static_cast<std::size_t>(k)];
    const HingeConstants& constants = m_constants[static_cast<std::size_t>(k)];
    const std::array<int, 4> node{hinge.a, hinge.b, hinge.c, hinge.d};
    detail::HingeGeometry<Scalar> geometry{};
    if (!geometry.init(x.col(node[0]), x.col(node[1]), x.col(node[2]), x.col(node[3]))) return;
    std::array<Vec3<Scalar>, 4> g;
    geometry.gradient(g);
    Scalar rate = 0;  // dtheta/dt = grad(theta) . v
    if (damped)
      for (std::size_t i = 0; i < 4; ++i) rate += g[i].dot(v.col(node[i]));
    // f = -(k_e (theta - theta0) + c_e dtheta/dt) grad(theta)
    const Scalar magnitude =
        constants.stiffness * wrapped(geometry.angle - constants.rest_angle) + constants.damping * rate;
    if (f)
      for (std::size_t i = 0; i < 4; ++i) f->col(node[i]) -= magnitude * g[i];
    if (!out) return;
    if (!exact) {
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 0; j < 4; ++j) {
          const Mat3<Scalar> gg = g[i] * g[j].transpose();
          out->add(node[i], node[j], -constants.stiffness * gg, -constants.damping * gg);
        }
      return;
    }
    AngleHessian h;
    geometry.hessian(h);
    // d(dtheta/dt)/dx_j = sum_m H(j, m) v_m (H symmetric).
    std::array<Vec3<Scalar>, 4> rate_gradient;
    for (std::size_t j = 0; j < 4; ++j) {
      rate_gradient[j].setZero();
      if (damped)
        for (std::size_t m = 0; m < 4; ++m) rate_gradient[j] += h[j][m] * v.col(node[m]);
    }
    for (std::size_t i = 0; i < 4; ++i)
      for (std::size_t j = 0; j < 4; ++j) {
        const Vec3<Scalar> row = constants.stiffness * g[j] + constants.damping * rate_gradient[j];
        const Mat3<Scalar> dfdx = -magnitude * h[i][j] - g[i] * row.transpose();
        out->add(node[i], node[j], dfdx, (-constants.damping * g[i]) * g[j].transpose());
      }
  });
}

}  // namespace drape
