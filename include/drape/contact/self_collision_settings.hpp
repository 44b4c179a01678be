#pragma once
/// \file self_collision_settings.hpp
/// How the cloth collides with itself (contact/self_collision.hpp does it): off by default, and
/// off costs nothing. Two layers keep twice the cloth's half-thickness (`ClothSpec::contact_thickness`)
/// apart, the distance a node keeps from a collider's surface on each side.

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

  /// \throws InvalidParameter naming `self friction` (finite, >= 0), `self impulse rounds`
  /// ([0, 64]) or `self separation rate` ((0, 1]).
  void validate() const {
    detail::require_nonnegative_finite("self friction", friction);
    detail::require_in_range("self impulse rounds", impulse_rounds, 0, 64);
    if (!(separation_rate > 0 && separation_rate <= 1))
      detail::fail_argument("self separation rate", detail::to_text(separation_rate), "(0, 1]");
  }
};

}  // namespace drape
