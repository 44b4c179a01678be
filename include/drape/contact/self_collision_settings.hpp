#pragma once
/// \file self_collision_settings.hpp
/// How the cloth collides with itself (contact/self_collision.hpp does it): off by default, and
/// off costs nothing. Two layers keep twice the cloth's half-thickness (`ClothSpec::contact_thickness`)
/// apart, the distance a node keeps from a collider's surface on each side.

#include <array>
#include <cstddef>
#include <vector>

#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar = double>
struct SelfCollisionSettings {
  bool enabled = false;
  /// Coulomb friction between layers: a sliding pair's tangential relative speed drops by at most
  /// `friction` times the normal impulse of the step (per unit effective mass).
  Scalar friction = Scalar(0.3);
  /// Rounds of continuous collision detection with impulses before the fail-safe (impact zones)
  /// takes the pairs that still cross.
  int impulse_rounds = 4;
  /// Fraction of the missing distance (2 h - d) that one step restores between two layers closer
  /// than 2 h; a position change only (no velocity is added), so layers do not bounce apart.
  Scalar separation_rate = Scalar(0.5);
  /// Pairs of nodes sewn together (a garment's seams, the pairs its seam springs close): features
  /// that touch either node of a pair count as sharing a node, so the two sides of a closed seam
  /// do not push each other apart. Pairs that share a node join all their nodes (a panel corner
  /// where two seams meet). None by default.
  std::vector<std::array<int, 2>> joined_nodes;

  /// \throws InvalidParameter naming `self friction` (finite, >= 0), `self impulse rounds`
  /// ([0, 64]) or `self separation rate` ((0, 1]). The joined nodes need the node count:
  /// validate(node_count).
  void validate() const {
    detail::require_nonnegative_finite("self friction", friction);
    detail::require_in_range("self impulse rounds", impulse_rounds, 0, 64);
    if (!(separation_rate > 0 && separation_rate <= 1))
      detail::fail_argument("self separation rate", detail::to_text(separation_rate), "(0, 1]");
  }
  /// validate(), and every pair of `joined_nodes` two distinct node ids in [0, node_count).
  /// \throws InvalidParameter as validate(), or naming `self joined nodes[k]`.
  void validate(int node_count) const {
    validate();
    for (std::size_t k = 0; k < joined_nodes.size(); ++k) {
      const std::array<int, 2>& p = joined_nodes[k];
      if (!(p[0] >= 0 && p[0] < node_count && p[1] >= 0 && p[1] < node_count && p[0] != p[1]))
        detail::fail_argument("self joined nodes[" + detail::to_text(k) + "]",
                              "(" + detail::to_text(p[0]) + ", " + detail::to_text(p[1]) + ")",
                              "two distinct node ids in [0, " + detail::to_text(node_count) + ")");
    }
  }
};

}  // namespace drape
