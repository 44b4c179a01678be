#pragma once
/// \file make_integrator.hpp
/// An integrator chosen at run time (a command-line flag, a scene file), behind the Integrator
/// interface: `make_integrator(cloth, IntegratorKind::Implicit, options)->step(state)`.

#include <memory>

#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/integrators/rk2.hpp"

namespace drape {

/// A new integrator of `kind` for `cloth`. RK2 reads only the IntegratorOptions part of `options`
/// (dt, threads); the implicit integrator reads all of them.
/// \throws InvalidParameter as the integrator's constructor.
template <class Scalar = double>
std::unique_ptr<Integrator<Scalar>> make_integrator(const Cloth<Scalar>& cloth, IntegratorKind kind,
                                                    const ImplicitOptions& options = {}) {
  if (kind == IntegratorKind::Implicit) return std::make_unique<ImplicitEuler<Scalar>>(cloth, options);
  return std::make_unique<Rk2<Scalar>>(cloth, static_cast<const IntegratorOptions&>(options));
}
/// The integrator keeps a reference to the cloth: a temporary would dangle.
template <class Scalar = double>
std::unique_ptr<Integrator<Scalar>> make_integrator(const Cloth<Scalar>&& cloth, IntegratorKind kind,
                                                    const ImplicitOptions& options = {}) = delete;

}  // namespace drape
