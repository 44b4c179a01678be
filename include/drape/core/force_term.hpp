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
#include <memory>
#include <string>
#include <vector>

#include "drape/core/types.hpp"
#include "drape/platform/team.hpp"

namespace drape {

/// Where a term's derivative blocks go (the implicit system assembly implements it).
template <class Scalar>
class ForceDerivatives {
 public:
  /// Adds \f$ \partial f_a / \partial x_b \f$ (`dfdx`, N/m) and \f$ \partial f_a / \partial v_b \f$
  /// (`dfdv`, N s/m). Either `a == b`, or the pair is one of the term's coupled_nodes(). Threads
  /// may call it at once for different nodes `a` (ForceTerm::shares_work()).
  virtual void add(int a, int b, const Mat3<Scalar>& dfdx, const Mat3<Scalar>& dfdv) = 0;
  /// add() with \f$ \partial f_a / \partial x_b = 0 \f$ (a block from a velocity dependence only).
  virtual void add_velocity(int a, int b, const Mat3<Scalar>& dfdv) { add(a, b, Mat3<Scalar>::Zero(), dfdv); }
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
  /// `3 x n`, at time `t` (s). Called by one thread unless the term shares_work(); forces on
  /// pinned nodes count toward the pins' reaction.
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

  /// add_force() and, if has_derivatives(), add_derivatives() at the same (x, v, t): the implicit
  /// step's assembly calls this. A term overrides it to share work between the two (e.g. to
  /// evaluate the wind once).
  virtual void add_force_and_derivatives(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar t,
                                         Ref3X<Scalar> f, ForceDerivatives<Scalar>& out) const {
    add_force(x, v, t, f);
    if (has_derivatives()) add_derivatives(x, v, t, out);
  }

  /// True if add_force() and add_derivatives() share their work with a team of threads
  /// (platform/team.hpp): every thread of the team calls them with the same arguments; they split the
  /// work with team_for(), which waits at the end, so that no two threads write the same node's
  /// force, or the blocks of the same node `a` through ForceDerivatives::add(), at once; and each
  /// sum is formed in an order that does not depend on the thread count. Outside a team they run
  /// on the calling thread. Such a term must not throw. Default: false, one thread calls the term.
  virtual bool shares_work() const { return false; }
};

/// The force terms of a cloth (ClothSpec::force_terms).
template <class Scalar>
using ForceTerms = std::vector<std::shared_ptr<const ForceTerm<Scalar>>>;

/// `call(term)` for every term: first those that do not share work, on the calling thread (their
/// exceptions reach the caller), then the others on a team of `threads` threads.
template <class Scalar, class Call>
void for_each_term(const ForceTerms<Scalar>& terms, int threads, Call&& call) {
  bool sharing = false;
  for (const auto& term : terms) {
    if (term->shares_work())
      sharing = true;
    else
      call(*term);
  }
  if (!sharing) return;
  run_in_team(threads, [&] {
    for (const auto& term : terms)
      if (term->shares_work()) call(*term);
  });
}

/// `f +=` every term's force at (x, v, t), in the order of for_each_term().
template <class Scalar>
void add_term_forces(const ForceTerms<Scalar>& terms, int threads, const ConstRef3X<Scalar>& x,
                     const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f) {
  for_each_term(terms, threads, [&](const ForceTerm<Scalar>& term) { term.add_force(x, v, t, f); });
}

/// add_term_forces() by the team already running (every thread calls it): the terms that do not
/// share work on one thread of it. The team waits at the end.
template <class Scalar>
void add_term_forces_in_team(const ForceTerms<Scalar>& terms, const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v,
                             Scalar t, Ref3X<Scalar> f) {
  team_single([&] {
    for (const auto& term : terms)
      if (!term->shares_work()) term->add_force(x, v, t, f);
  });
  for (const auto& term : terms)
    if (term->shares_work()) term->add_force(x, v, t, f);
}

/// add_term_forces() and every term's derivative blocks through `out`, in one pass per term
/// (ForceTerm::add_force_and_derivatives()).
template <class Scalar>
void add_term_forces_and_derivatives(const ForceTerms<Scalar>& terms, int threads, const ConstRef3X<Scalar>& x,
                                     const ConstRef3X<Scalar>& v, Scalar t, Ref3X<Scalar> f,
                                     ForceDerivatives<Scalar>& out) {
  for_each_term(terms, threads,
                [&](const ForceTerm<Scalar>& term) { term.add_force_and_derivatives(x, v, t, f, out); });
}

/// Every term's derivative blocks at (x, v, t) through `out`, in the order of for_each_term().
template <class Scalar>
void add_term_derivatives(const ForceTerms<Scalar>& terms, int threads, const ConstRef3X<Scalar>& x,
                          const ConstRef3X<Scalar>& v, Scalar t, ForceDerivatives<Scalar>& out) {
  for_each_term(terms, threads, [&](const ForceTerm<Scalar>& term) {
    if (term.has_derivatives()) term.add_derivatives(x, v, t, out);
  });
}

}  // namespace drape
