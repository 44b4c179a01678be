#pragma once
/// \file force_term.hpp
/// A force on the cloth's nodes besides its springs and gravity (air drag, wind, a user's field):
/// the one place a new force plugs in. Put terms into `ClothSpec::force_terms`; the explicit and
/// implicit integrators, the Newton iteration and the diagnostics (pin reactions) then include
/// them, and none of them has to change for a new term (drape's architecture.md).
///
/// Sign convention (drape's conventions.md): a term adds its force \f$ f \f$; its derivative blocks
/// are \f$ \partial f_a / \partial x_b \f$ and \f$ \partial f_a / \partial v_b \f$, the negative
/// Hessian for a conservative term. The implicit step forms
/// \f$ A \mathrel{-}= \Delta t\, \partial f/\partial v + \Delta t^2\, \partial f/\partial x \f$ and
/// \f$ b \mathrel{+}= \Delta t\, (f + \Delta t\, \partial f/\partial x\, v) \f$ from them.

#include <array>
#include <string>
#include <vector>

#include "drape/core/types.hpp"

namespace drape {

/// Where a term's derivative blocks go (the implicit system assembly implements it).
template <class Scalar>
class ForceDerivatives {
 public:
  /// Adds \f$ \partial f_a / \partial x_b \f$ (`dfdx`, N/m) and \f$ \partial f_a / \partial v_b \f$
  /// (`dfdv`, N s/m). Either `a == b`, or the pair is one of the term's coupled_nodes().
  virtual void add(int a, int b, const Mat3<Scalar>& dfdx, const Mat3<Scalar>& dfdv) = 0;
  /// True when the system must stay symmetric (the Symmetric and Spd Jacobian variants): a term
  /// then adds only the symmetric part of its derivatives it can vouch for (e.g. a damping-like
  /// velocity derivative) and leaves the rest explicit, as the Baraff-Witkin variant does with the
  /// springs' damping term. False for the Exact variant: add every block.
  virtual bool symmetric() const = 0;

 protected:
  ~ForceDerivatives() = default;
};

template <class Scalar>
class ForceTerm {
 public:
  virtual ~ForceTerm() = default;

  /// A short name for messages.
  virtual std::string name() const = 0;

  /// `f += ` the term's force (N) on every node, for positions `x` (m) and velocities `v` (m/s),
  /// `3 x n`, at time `t` (s). Called by one thread; forces on pinned nodes count toward the
  /// pins' reaction.
  virtual void add_force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f) const = 0;

  /// Node pairs (a, b), a != b, whose block add_derivatives() may write. Called once, when an
  /// implicit integrator lays out its system. Default: none (each node's force depends on that
  /// node alone).
  virtual std::vector<std::array<int, 2>> coupled_nodes() const { return {}; }

  /// Adds the term's derivative blocks at (x, v, t) through `out`. Default: none, and the implicit
  /// step then treats the term explicitly (its force enters the right-hand side only); a stiff
  /// term needs its derivatives to stay stable at large time steps.
  virtual void add_derivatives(const ConstRef3X<Scalar>& /*x*/, const ConstRef3X<Scalar>& /*v*/, Scalar /*t*/,
                               ForceDerivatives<Scalar>& /*out*/) const {}

  /// True if add_derivatives() adds anything (the implicit assembly skips the term otherwise).
  virtual bool has_derivatives() const { return false; }
};

}  // namespace drape
