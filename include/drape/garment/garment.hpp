#pragma once
/// \file garment.hpp
/// A garment ready to step: its sewing pattern meshed and placed (garment_mesh.hpp), a fabric's
/// material (fabric.hpp) on its edges and hinges, the seams as springs that close over a set time
/// (physics/seam_springs.hpp) and as hinges that bend like the fabric once closed (seam_hinges.hpp),
/// gravity switched on once they have closed (physics/ramped_gravity.hpp), and self-collision with
/// the sewn vertices joined (contact/self_collision_settings.hpp). The result is a ClothSpec: add the
/// body as a collider and hand it to any integrator.
///
/// Why gravity waits: the panels start where the pattern places them, around the body and not on it;
/// under gravity from the start they would fall the closing time's free-fall distance (1.2 m in
/// 0.5 s) before the shoulder seams could hold them.

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "drape/core/validation.hpp"
#include "drape/garment/fabric.hpp"
#include "drape/garment/garment_mesh.hpp"
#include "drape/garment/seam_hinges.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/dihedral_bending.hpp"
#include "drape/physics/ramped_gravity.hpp"
#include "drape/physics/seam_springs.hpp"

namespace drape {

/// How a garment is sewn: the mesh's edge length and the seams' springs and timing.
struct SewingSettings {
  double edge_length = 0.015;      ///< m: the target edge of the panels' triangles
  double seam_stiffness = 500;     ///< N/m per sewn pair
  double seam_damping = 0.5;       ///< N s/m per sewn pair, on the pair's relative velocity
  double seam_closing_time = 1.0;  ///< s: the seams' rest lengths reach zero then
  double gravity_ramp = 0.2;       ///< s: gravity rises from 0 to g over this time after the closing time
  double gravity = 9.81;           ///< m/s^2, along -y

  /// \throws InvalidParameter naming `edge length`, `seam stiffness` (finite, > 0), `seam damping`,
  /// `seam closing time`, `gravity ramp` or `gravity` (finite, >= 0).
  void validate() const {
    detail::require_positive_finite("edge length", edge_length);
    detail::require_positive_finite("seam stiffness", seam_stiffness);
    detail::require_nonnegative_finite("seam damping", seam_damping);
    detail::require_nonnegative_finite("seam closing time", seam_closing_time);
    detail::require_nonnegative_finite("gravity ramp", gravity_ramp);
    detail::require_nonnegative_finite("gravity", gravity);
  }
};

/// A sewn garment: the cloth to step and what it was made of.
struct Garment {
  GarmentMesh pieces;  ///< the panels' mesh, the seam pairs and each pair's stitch
  /// The cloth: the garment's mesh, pinned nowhere, mass from the fabric's areal density, the
  /// fabric's edge springs (no bend or shear springs: the dihedral term bends it), the force terms
  /// `seams`, the mesh's dihedral bending, `seam_bending` and ramped gravity (ClothSpec::gravity is
  /// 0), self-collision on with the seam pairs joined. Colliders and the contact thickness are the
  /// caller's.
  ClothSpec<double> spec;
  std::shared_ptr<const SeamSprings<double>> seams;  ///< also in spec.force_terms
  /// The hinges across the seams (seam_hinges.hpp) in the fabric's bending, also in spec.force_terms:
  /// a closed seam bends like the fabric across it instead of turning freely.
  std::shared_ptr<const DihedralBending<double>> seam_bending;
};

/// The garment of `pattern` in `fabric`, sewn as `sewing` says.
/// \throws InvalidParameter as SewingSettings::validate(), PatternError or InvalidParameter as
/// garment_mesh().
inline Garment dress_garment(const SewingPattern& pattern, const Fabric& fabric, const SewingSettings& sewing = {}) {
  sewing.validate();
  Garment g;
  g.pieces = garment_mesh(pattern, sewing.edge_length);
  const ClothMesh<double>& mesh = g.pieces.mesh;
  ClothSpec<double>& spec = g.spec;
  spec.mesh = mesh;
  spec.pinned_nodes = std::vector<int>{};
  spec.areal_density = fabric.areal_density;
  spec.gravity = 0;
  spec.springs = {{edge_spring_stiffness(fabric), fabric.stretch_damping}, {0.0, 0.0}, {0.0, 0.0}};
  g.seams = std::make_shared<SeamSprings<double>>(g.pieces.seam_pairs, mesh.positions, sewing.seam_stiffness,
                                                  sewing.seam_damping, sewing.seam_closing_time);
  SeamHinges across = seam_hinges(g.pieces, hinge_stiffness(fabric), fabric.bending_damping);
  g.seam_bending = std::make_shared<DihedralBending<double>>(mesh.vertex_count(), std::move(across.hinges),
                                                             std::move(across.constants), "seam hinges");
  const VectorX<double> masses = mesh.vertex_areas() * fabric.areal_density;
  spec.force_terms = {g.seams,
                      std::make_shared<DihedralBending<double>>(mesh, hinge_stiffness(fabric), fabric.bending_damping),
                      g.seam_bending,
                      std::make_shared<RampedGravity<double>>(masses, sewing.gravity, sewing.seam_closing_time,
                                                              sewing.gravity_ramp)};
  spec.self_collision.enabled = true;
  spec.self_collision.joined_nodes = g.pieces.seam_pairs;
  return g;
}

}  // namespace drape
