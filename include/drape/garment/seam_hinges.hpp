#pragma once
/// \file seam_hinges.hpp
/// Hinges across a garment's seams, so that a closed seam bends like the cloth across it.
///
/// The panels of a garment are separate pieces of one mesh: a seam's two edges are boundary edges
/// of different panels, joined by springs (physics/seam_springs.hpp), not by triangles, so the
/// mesh's dihedral bending (physics/dihedral_bending.hpp) has no hinge there and a closed seam turns
/// freely. For two consecutive sewn pairs (p_i, q_i), (p_i+1, q_i+1) of one stitch, the edge
/// (p_i, p_i+1) of panel A lies in one triangle of A (opposite corner c) and (q_i, q_i+1) in one
/// triangle of B (opposite corner d). The seam gets two hinges, one on each side's edge: A's edge
/// with c and B's d, and B's edge with d and A's c, each with half the cloth's stiffness and damping,
/// so that the closed seam, where both edges lie on each other, is as stiff as one interior edge.
///
/// Rest constants (DihedralBending::rest_constants()): the other panel's triangle is laid into
/// this panel's pattern plane across the edge, flat, its corners' share of the edge kept and its
/// rest area kept, so the rest angle is 0 and k_e = (k / 2) 3 |e|^2 / (A1 + A2) with |e| this
/// side's rest edge and A1, A2 the two triangles' rest areas. A seam's rest shape is therefore flat:
/// it resists a crease as the fabric does, whatever angle the garment's 3D shape asks of it there.

#include <array>
#include <cmath>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "drape/core/cloth_mesh.hpp"
#include "drape/garment/garment_mesh.hpp"
#include "drape/physics/dihedral_bending.hpp"

namespace drape {

/// The hinges across a garment's seams, for DihedralBending's explicit-hinge constructor.
struct SeamHinges {
  std::vector<Hinge> hinges;
  std::vector<DihedralBending<double>::HingeConstants> constants;  ///< per hinge
  /// Segments (consecutive pairs of one stitch) left without hinges: an edge that is not the
  /// boundary edge of exactly one triangle on both sides, or whose two opposite corners are sewn to
  /// each other (the two triangles would lie on each other once the seam closes: no angle). A
  /// pattern meshed by garment_mesh() has none of the first kind: the mesher keeps the outline's
  /// segments as boundary edges.
  int skipped_segments = 0;
};

/// The seam hinges of `garment` for a cloth of hinge stiffness `stiffness` (N m) and damping
/// `damping` (N m s), the values given to the mesh's DihedralBending (e.g. hinge_stiffness() and
/// Fabric::bending_damping): each hinge gets half of them. Corners where two stitches meet get no
/// hinge between them (consecutive pairs of different stitches are not a segment).
inline SeamHinges seam_hinges(const GarmentMesh& garment, double stiffness, double damping);

// ---------------------------------------------------------------------------------------------------

namespace detail {

/// A boundary edge's one triangle: the edge as the triangle runs it, and its opposite corner.
struct BoundarySide {
  int a = -1, b = -1, opposite = -1;
};

/// Where corner d of the rest triangle (qa, qb, d) goes when the triangle is laid across the edge
/// (a, b) on the side away from c (2D pattern coordinates): qa on a, qb on b, d at the same fraction
/// along the edge and at a height that keeps the triangle's area.
inline Eigen::Vector2d laid_across(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                                   const Eigen::Vector2d& qa, const Eigen::Vector2d& qb, const Eigen::Vector2d& d) {
  const Eigen::Vector2d e = b - a, f = qb - qa, r = d - qa;
  const double along = r.dot(f) / f.squaredNorm();
  const double twice_area = std::abs(f.x() * r.y() - f.y() * r.x());
  const Eigen::Vector2d left(-e.y(), e.x());  // |left| = |e|
  const double side = left.dot(c - a) > 0 ? -1.0 : 1.0;
  return a + along * e + (side * twice_area / e.squaredNorm()) * left;
}

}  // namespace detail

inline SeamHinges seam_hinges(const GarmentMesh& garment, double stiffness, double damping) {
  const ClothMesh<double>& mesh = garment.mesh;
  // Every edge's triangles: a boundary edge has one.
  struct EdgeSides {
    int count = 0;
    detail::BoundarySide side;
  };
  std::unordered_map<long long, EdgeSides> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const std::array<int, 3>& t : mesh.all_triangles())
    for (int k = 0; k < 3; ++k) {
      EdgeSides& e = edges[detail::edge_key(t[std::size_t(k)], t[std::size_t(k + 1) % 3])];
      ++e.count;
      e.side = {t[std::size_t(k)], t[std::size_t(k + 1) % 3], t[std::size_t(k + 2) % 3]};
    }
  const auto boundary_side = [&](int u, int v, detail::BoundarySide& out) {
    const auto it = edges.find(detail::edge_key(u, v));
    if (it == edges.end() || it->second.count != 1) return false;
    out = it->second.side;
    return true;
  };
  std::unordered_set<long long> sewn;
  for (const std::array<int, 2>& p : garment.seam_pairs) sewn.insert(detail::edge_key(p[0], p[1]));
  const auto rest = [&](int v) { return Eigen::Vector2d(mesh.rest_uv.col(v)); };
  const auto lift = [](const Eigen::Vector2d& p) { return Vec3<double>(p.x(), p.y(), 0); };

  SeamHinges out;
  const std::size_t pairs = garment.seam_pairs.size();
  for (std::size_t i = 0; i + 1 < pairs; ++i) {
    if (garment.seam_stitch[i] != garment.seam_stitch[i + 1]) continue;  // a corner between two stitches
    const std::array<int, 2>& first = garment.seam_pairs[i];
    const std::array<int, 2>& second = garment.seam_pairs[i + 1];
    std::array<detail::BoundarySide, 2> side;
    if (!boundary_side(first[0], second[0], side[0]) || !boundary_side(first[1], second[1], side[1]) ||
        sewn.count(detail::edge_key(side[0].opposite, side[1].opposite)) != 0) {
      ++out.skipped_segments;
      continue;
    }
    // One hinge on each side's edge, its own corner as c and the other side's as d.
    for (std::size_t s = 0; s < 2; ++s) {
      const detail::BoundarySide& own = side[s];
      const detail::BoundarySide& other = side[1 - s];
      // The other side's partners of a and b.
      const int partner_a = own.a == first[s] ? first[1 - s] : second[1 - s];
      const int partner_b = own.a == first[s] ? second[1 - s] : first[1 - s];
      const Eigen::Vector2d d = detail::laid_across(rest(own.a), rest(own.b), rest(own.opposite), rest(partner_a),
                                                    rest(partner_b), rest(other.opposite));
      out.hinges.push_back(Hinge{own.a, own.b, own.opposite, other.opposite});
      out.constants.push_back(DihedralBending<double>::rest_constants(lift(rest(own.a)), lift(rest(own.b)),
                                                                      lift(rest(own.opposite)), lift(d),
                                                                      0.5 * stiffness, 0.5 * damping));
    }
  }
  return out;
}

}  // namespace drape
