#pragma once
/// \file fwd.hpp
/// Forward declarations and the float/double aliases of drape's templates.

namespace drape {

template <class Scalar>
class Grid;
template <class Scalar>
class SpringSet;
template <class Scalar>
struct State;
template <class Scalar>
struct ClothSpec;
template <class Scalar>
class Cloth;
template <class Scalar>
class ForceTerm;
template <class Scalar>
class Collider;
template <class Scalar>
class ForceAssembler;
template <class Scalar>
class JacobianAssembler;
template <class Scalar>
class BlockSparseMatrix;
template <class Scalar>
struct LinearSystem;
template <class Scalar>
class LinearSolver;
template <class Scalar>
class Integrator;
template <class Scalar>
class Rk2;
template <class Scalar>
class ImplicitEuler;
template <class Scalar>
class SymplecticEuler;
template <class Scalar>
struct SelfCollisionSettings;
template <class Scalar>
struct Placement;
template <class Scalar>
class ClothScene;
class Pins;
struct IntegratorOptions;
struct ImplicitOptions;

using Gridd = Grid<double>;
using Gridf = Grid<float>;
using SpringSetd = SpringSet<double>;
using SpringSetf = SpringSet<float>;
using Stated = State<double>;
using Statef = State<float>;
using ClothSpecd = ClothSpec<double>;
using ClothSpecf = ClothSpec<float>;
using Clothd = Cloth<double>;
using Clothf = Cloth<float>;
using Colliderd = Collider<double>;
using Colliderf = Collider<float>;
using LinearSystemd = LinearSystem<double>;
using LinearSystemf = LinearSystem<float>;
using Rk2d = Rk2<double>;
using Rk2f = Rk2<float>;
using SymplecticEulerd = SymplecticEuler<double>;
using SymplecticEulerf = SymplecticEuler<float>;
using JacobianAssemblerd = JacobianAssembler<double>;
using JacobianAssemblerf = JacobianAssembler<float>;
using ImplicitEulerd = ImplicitEuler<double>;
using ImplicitEulerf = ImplicitEuler<float>;
using SelfCollisionSettingsd = SelfCollisionSettings<double>;
using SelfCollisionSettingsf = SelfCollisionSettings<float>;
using Placementd = Placement<double>;
using Placementf = Placement<float>;
using ClothScened = ClothScene<double>;
using ClothScenef = ClothScene<float>;

}  // namespace drape
