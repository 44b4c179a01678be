#pragma once
/// \file refined_cloth.hpp
/// The default cloth's material refined to n x n nodes over the same 3.2 m square, as the bench
/// tools scale it (refinement.cpp, amg_cost.cpp, mesh_step.cpp): the node mass with the area (the
/// same mass per square metre), the springs unchanged (the same membrane stiffness and viscosity).
/// Bend springs times (h0 / h)^bend_exponent, h0 the default spacing (refinement.cpp says why).

#include <cmath>

#include "drape/model/cloth.hpp"

namespace drape_bench {

inline drape::ClothSpec<double> refined_default_spec(int n, double bend_exponent = 0) {
  const drape::ClothSpec<double> base;
  drape::ClothSpec<double> spec = base;
  const double side = (base.nx - 1) * base.spacing;
  spec.nx = spec.ny = n;
  spec.spacing = side / (n - 1);
  const double ratio = spec.spacing / base.spacing;
  spec.node_mass = base.node_mass * ratio * ratio;
  const double bend = std::pow(ratio, -bend_exponent);
  spec.springs.bend.stiffness = base.springs.bend.stiffness * bend;
  spec.springs.bend.damping = base.springs.bend.damping * bend;
  return spec;
}

}  // namespace drape_bench
