#pragma once
/// \file air.hpp
/// The air of a scene in one settings struct: the wind (mean and gusts, wind_field.hpp), linear
/// drag on the nodes (air_drag.hpp) and aerodynamic drag and lift on the triangles
/// (aerodynamic_force.hpp). `air_force_terms()` turns it into the force terms of a ClothSpec; with
/// the defaults (no drag, no aerodynamics) there are none, and the wind alone moves nothing.

#include <array>
#include <memory>
#include <vector>

#include "drape/core/force_term.hpp"
#include "drape/physics/aerodynamic_force.hpp"
#include "drape/physics/air_drag.hpp"
#include "drape/physics/wind_field.hpp"

namespace drape {

struct AirSettings {
  std::array<double, 3> wind{0, 0, 0};  ///< mean wind (m/s)
  GustSettings gusts;                   ///< gusts on top of it (none by default)
  double drag = 0;                      ///< linear drag per node (N s/m)
  AerodynamicSettings aerodynamics{1.2, 0.0, 0.0};  ///< per-triangle drag and lift (off by default)

  /// True if the settings exert any force.
  bool active() const {
    return drag > 0 || aerodynamics.drag_coefficient > 0 || aerodynamics.lift_coefficient > 0;
  }
  /// \throws InvalidParameter naming `wind`, `air drag` or a gust or aerodynamic setting.
  void validate() const {
    for (double w : wind) detail::require_finite("wind", w);
    gusts.validate();
    detail::require_nonnegative_finite("air drag", drag);
    aerodynamics.validate();
  }
};

/// The force terms of `air` for a cloth with `triangles` (Grid::triangles()): an AirDrag if
/// `air.drag` > 0, an AerodynamicForce if a coefficient is > 0. \throws as AirSettings::validate().
template <class Scalar = double>
std::vector<std::shared_ptr<const ForceTerm<Scalar>>> air_force_terms(const AirSettings& air,
                                                                      std::vector<std::array<int, 3>> triangles) {
  air.validate();
  std::vector<std::shared_ptr<const ForceTerm<Scalar>>> terms;
  const WindField<Scalar> wind(Vec3<double>(air.wind[0], air.wind[1], air.wind[2]).template cast<Scalar>(), air.gusts);
  if (air.drag > 0) terms.push_back(std::make_shared<AirDrag<Scalar>>(Scalar(air.drag), wind));
  if (air.aerodynamics.drag_coefficient > 0 || air.aerodynamics.lift_coefficient > 0)
    terms.push_back(std::make_shared<AerodynamicForce<Scalar>>(std::move(triangles), wind, air.aerodynamics));
  return terms;
}

}  // namespace drape
