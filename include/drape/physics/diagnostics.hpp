#pragma once
/// \file diagnostics.hpp
/// Energies, strain and pin reactions of a state. All sums run in node / spring order, so they are
/// deterministic.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/spring_kernel.hpp"

namespace drape {

/// \f$ \tfrac12 \sum_i m_i |v_i|^2 \f$ (J).
template <class Scalar>
Scalar kinetic_energy(const Cloth<Scalar>& cloth, const State<Scalar>& state) {
  return Scalar(0.5) * (state.velocities.colwise().squaredNorm().transpose().cwiseProduct(cloth.masses())).sum();
}

/// \f$ \sum_s \tfrac12 k_s (L_s - l_s)^2 \f$ (J).
template <class Scalar>
Scalar spring_potential_energy(const Cloth<Scalar>& cloth, const detail::NonDeducedT<ConstRef3X<Scalar>>& x) {
  const SpringSet<Scalar>& sp = cloth.springs();
  Scalar e = 0;
  for (int s = 0; s < sp.size(); ++s)
    e += spring_energy<Scalar>(x.col(sp.a()[s]), x.col(sp.b()[s]), sp.rest_length()[s], sp.stiffness()[s]);
  return e;
}

/// \f$ -\sum_i m_i\, g \cdot x_i \f$ (J), zero at the rest height y = 0.
template <class Scalar>
Scalar gravitational_potential_energy(const Cloth<Scalar>& cloth, const detail::NonDeducedT<ConstRef3X<Scalar>>& x) {
  return -(cloth.gravity().transpose() * x * cloth.masses()).value();
}

template <class Scalar>
Scalar total_energy(const Cloth<Scalar>& cloth, const State<Scalar>& state) {
  return kinetic_energy(cloth, state) + spring_potential_energy(cloth, state.positions) +
         gravitational_potential_energy(cloth, state.positions);
}

/// Largest relative stretch \f$ \max_s (L_s - l_s) / l_s \f$ (negative if every spring is compressed).
template <class Scalar>
Scalar max_strain(const Cloth<Scalar>& cloth, const detail::NonDeducedT<ConstRef3X<Scalar>>& x) {
  const SpringSet<Scalar>& sp = cloth.springs();
  Scalar worst = -std::numeric_limits<Scalar>::infinity();
  for (int s = 0; s < sp.size(); ++s) {
    const Scalar l = sp.rest_length()[s];
    worst = std::max(worst, ((x.col(sp.b()[s]) - x.col(sp.a()[s])).norm() - l) / l);
  }
  return worst;
}

/// Force each pin in `pinned` exerts on its node (N, 3 x pinned.size()): what moves the node as
/// it moves, \f$ m a - f \f$, with f all other forces (springs, gravity, force terms) and
/// `acceleration` the pinned nodes' accelerations (3 x pinned.size(); zero for pins that hold).
template <class Scalar>
Matrix3X<Scalar> pin_forces(const Cloth<Scalar>& cloth, const State<Scalar>& state, const std::vector<int>& pinned,
                            const Matrix3X<Scalar>& acceleration) {
  Matrix3X<Scalar> f(3, cloth.node_count());
  ForceAssembler<Scalar>(cloth, 1).force(state.positions, state.velocities, state.time, f);
  Matrix3X<Scalar> r(3, static_cast<Index>(pinned.size()));
  for (std::size_t k = 0; k < pinned.size(); ++k)
    r.col(Index(k)) = cloth.masses()[pinned[k]] * acceleration.col(Index(k)) - f.col(pinned[k]);
  return r;
}

/// Total force the pins exert on the cloth (N): minus the sum of all forces (springs, gravity, force
/// terms) on the pinned nodes (the cloth's, or `pinned`). At static equilibrium it balances the
/// cloth's weight.
template <class Scalar>
Vec3<Scalar> pin_reaction(const Cloth<Scalar>& cloth, const State<Scalar>& state, const std::vector<int>& pinned) {
  Matrix3X<Scalar> f(3, cloth.node_count());
  ForceAssembler<Scalar>(cloth, 1).force(state.positions, state.velocities, state.time, f);
  Vec3<Scalar> r = Vec3<Scalar>::Zero();
  for (int p : pinned) r -= f.col(p);
  return r;
}
template <class Scalar>
Vec3<Scalar> pin_reaction(const Cloth<Scalar>& cloth, const State<Scalar>& state) {
  return pin_reaction(cloth, state, cloth.pins().nodes());
}

/// Largest force norm on a free node (N): zero at static equilibrium.
template <class Scalar>
Scalar max_free_force(const Cloth<Scalar>& cloth, const State<Scalar>& state) {
  Matrix3X<Scalar> f(3, cloth.node_count());
  ForceAssembler<Scalar>(cloth, 1).force(state.positions, state.velocities, state.time, f);
  Scalar worst = 0;
  for (int i = 0; i < cloth.node_count(); ++i)
    if (!cloth.pins().is_pinned(i)) worst = std::max(worst, f.col(i).norm());
  return worst;
}

}  // namespace drape
