#pragma once
/// \file make_integrator.hpp
/// An integrator chosen at run time (a command-line flag, a scene file), behind the Integrator
/// interface: `make_integrator(cloth, IntegratorKind::Implicit, options)->step(state)`.

#include <memory>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"

namespace drape {

/// A new integrator of `kind` for `cloth`. The explicit ones (RK2, symplectic Euler) read only the
/// IntegratorOptions part of `options` (dt, threads); the implicit integrator reads all of them.
/// \throws InvalidParameter as the integrator's constructor.
template <class Scalar = double>
std::unique_ptr<Integrator<Scalar>> make_integrator(const Cloth<Scalar>& cloth, IntegratorKind kind,
                                                    const ImplicitOptions& options = {}) {
  const IntegratorOptions& explicit_options = options;
  switch (kind) {
    case IntegratorKind::Implicit: return std::make_unique<ImplicitEuler<Scalar>>(cloth, options);
    case IntegratorKind::Symplectic: return std::make_unique<SymplecticEuler<Scalar>>(cloth, explicit_options);
    case IntegratorKind::Rk2: break;
  }
  return std::make_unique<Rk2<Scalar>>(cloth, explicit_options);
}
/// The integrator keeps a reference to the cloth: a temporary would dangle.
template <class Scalar = double>
std::unique_ptr<Integrator<Scalar>> make_integrator(const Cloth<Scalar>&& cloth, IntegratorKind kind,
                                                    const ImplicitOptions& options = {}) = delete;

}  // namespace drape
