#pragma once
/// \file fabric.hpp
/// Named fabrics for garments: cotton, denim, silk and jersey, each with its areal density, stretch
/// stiffness, bending rigidity, damping and friction in SI units, and the two mappings from a
/// fabric to drape's parameters: the stiffness of one edge spring (core/spring_set.hpp, structural
/// family) and the stiffness k of the dihedral bending term (physics/dihedral_bending.hpp).
///
/// The values are measurements of real fabrics where one was found (Wang, O'Brien and Ramamoorthi
/// 2011, "Data-driven elastic models for cloth: modeling and measurement"; Temel, Johnson and Lloyd
/// 2022 for friction against skin) and estimates scaled from them where not (silk): docs/fabrics.md
/// has every number's source, the arithmetic from the source's units, and the model's limits
/// (isotropic, linear at small strain, no shear stiffness of its own, no hysteresis).
///
/// ```cpp
/// const drape::Fabric denim = drape::fabric_preset("denim");
/// spec.areal_density = denim.areal_density;
/// const double k = drape::edge_spring_stiffness(denim);
/// spec.springs = {{k, denim.stretch_damping}, {0.0, 0.0}, {0.0, 0.0}};
/// spec.force_terms.push_back(std::make_shared<drape::DihedralBending<double>>(
///     mesh, drape::hinge_stiffness(denim), denim.bending_damping));
/// collider.set_friction(denim.friction, denim.kinetic_friction);
/// ```

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "drape/core/validation.hpp"

namespace drape {

/// A fabric's mechanical constants, SI units. Isotropic: a woven's warp and weft (a knit's wales
/// and courses) combined into one value by their geometric mean.
struct Fabric {
  std::string name;
  /// kg/m^2.
  double areal_density;
  /// N/m: the in-plane (membrane) Young's modulus times thickness, E t, at small strain: the force
  /// per unit width that stretches a strip by a strain of 1 under uniaxial tension.
  double stretch_stiffness;
  /// N m: D, the bending moment per unit width per unit curvature.
  double bending_rigidity;
  /// N s/m per edge spring: edge_spring_stiffness() times fabric_stretch_damping_time, a
  /// stiffness-proportional damping (docs/fabrics.md, "Damping").
  double stretch_damping;
  /// N m s for the dihedral term: hinge_stiffness() times fabric_bending_damping_time.
  double bending_damping;
  /// Static Coulomb coefficient against skin (a cotton textile on the forearm, Temel et al. 2022;
  /// the same for every preset: docs/fabrics.md, "Friction").
  double friction;
  /// Kinetic Coulomb coefficient against skin (the same measurement).
  double kinetic_friction;
  /// A short citation of the measurements.
  std::string source;
};

/// s: stretch damping per spring = this time x the spring's stiffness.
inline constexpr double fabric_stretch_damping_time = 1e-3;
/// s: bending damping of the dihedral term = this time x its stiffness.
inline constexpr double fabric_bending_damping_time = 1e-2;

/// Stiffness of one edge spring (N/m) on a mesh of near-equilateral triangles that gives the
/// fabric's stretch stiffness. A triangular lattice of springs k has the 2D Young's modulus
/// 2k/sqrt(3) and Poisson ratio 1/3, independent of the edge length, so k = sqrt(3)/2 E t. Only the
/// structural family: shear and bend springs at 0 (the lattice's shear modulus is then 3/8 E t).
inline double edge_spring_stiffness(const Fabric& f) { return std::sqrt(3.0) / 2.0 * f.stretch_stiffness; }

/// Stiffness k (N m) of drape's dihedral bending term (physics/dihedral_bending.hpp) that gives the
/// fabric's bending rigidity: on meshes of near-equilateral triangles D = 3k (docs/bending.md,
/// "Stiffness per hinge"), so k = D / 3.
inline double hinge_stiffness(const Fabric& f) { return f.bending_rigidity / 3.0; }

namespace detail {

/// A preset from its measured constants; damping from the two damping times, friction from the
/// one measurement against skin.
inline Fabric make_fabric(std::string name, double areal_density, double stretch_stiffness, double bending_rigidity,
                          std::string source) {
  Fabric f;
  f.name = std::move(name);
  f.areal_density = areal_density;
  f.stretch_stiffness = stretch_stiffness;
  f.bending_rigidity = bending_rigidity;
  f.stretch_damping = fabric_stretch_damping_time * edge_spring_stiffness(f);
  f.bending_damping = fabric_bending_damping_time * hinge_stiffness(f);
  f.friction = 0.31;
  f.kinetic_friction = 0.25;
  f.source = std::move(source);
  return f;
}

}  // namespace detail

/// The presets, in a fixed order: cotton, denim, silk, jersey. docs/fabrics.md derives each number.
inline const std::vector<Fabric>& fabric_presets() {
  static const std::vector<Fabric> presets = {
      // Wang et al. 2011, "royal-target": a 65% cotton 35% polyester woven for trousers.
      detail::make_fabric("cotton", 0.220, 4051.0, 3.135e-5,
                          "Wang, O'Brien, Ramamoorthi 2011, sample royal-target (65/35 cotton/polyester woven), "
                          "ARCSim materials/royal-target.json"),
      // Wang et al. 2011, "11oz-black-denim": 99% cotton 1% spandex, for jeans.
      detail::make_fabric("denim", 0.324, 912.1, 1.972e-5,
                          "Wang, O'Brien, Ramamoorthi 2011, sample 11oz-black-denim (99/1 cotton/spandex), "
                          "ARCSim materials/11oz-black-denim.json"),
      // An estimate: a 14 momme crepe de chine, stiffnesses scaled from Wang et al.'s lightest
      // filament woven ("tango-red-jet-set", 113 g/m^2) by the ratio of areal densities.
      detail::make_fabric("silk", 0.06076, 55.40, 6.627e-7,
                          "estimate: 14 momme (60.76 g/m^2) crepe de chine; stiffnesses scaled from Wang, O'Brien, "
                          "Ramamoorthi 2011, sample tango-red-jet-set (polyester filament woven)"),
      // Wang et al. 2011, "gray-interlock": a 60% cotton 40% polyester knit for t-shirts.
      detail::make_fabric("jersey", 0.187, 47.84, 4.548e-6,
                          "Wang, O'Brien, Ramamoorthi 2011, sample gray-interlock (60/40 cotton/polyester t-shirt "
                          "knit), ARCSim materials/gray-interlock.json"),
  };
  return presets;
}

/// The preset named `name`.
/// \throws InvalidParameter naming `fabric`, with the allowed names "cotton | denim | silk | jersey".
inline Fabric fabric_preset(const std::string& name) {
  for (const Fabric& f : fabric_presets())
    if (f.name == name) return f;
  detail::fail_argument("fabric", name, "cotton | denim | silk | jersey");
}

}  // namespace drape
