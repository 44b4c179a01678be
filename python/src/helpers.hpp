#pragma once
// What the binding groups share (helpers.cpp): the state numpy sees, the spec with its air, the
// scene with Python's states, the guard against stepping one object from two threads, and the
// errors that become Python exceptions. Nothing here reads scene files or renders.

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <array>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "drape/model/cloth.hpp"
#include "drape/core/state.hpp"
#include "drape/fwd.hpp"
// The library's class templates compiled once, in drape_instances, not in each binding file.
#include "drape/instances.hpp"
#include "drape/physics/air.hpp"
#include "drape/scene/cloth_scene.hpp"

namespace drape::python {

namespace nb = nanobind;

using Vector = std::array<double, 3>;
/// (n, 3) node data in: positions or velocities, copied.
using NodeInput = nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

inline drape::Vec3<double> vec3(const Vector& v) { return {v[0], v[1], v[2]}; }
inline Vector array3(const drape::Vec3<double>& v) { return {v[0], v[1], v[2]}; }

/// A cloth's state as Python sees it. numpy views `shared`, whose buffers are never reallocated.
/// The integrators swap their own buffers with the state they step, so they never step `shared`:
/// they step a work state (`own_work`, or a ClothScene's), filled from `shared` before and copied
/// back after; run() copies only at its ends and around callbacks. `shared` is only written while
/// the GIL is held, so a Python thread never sees it half-written.
struct SharedState {
  explicit SharedState(drape::Stated state) : shared(std::move(state)), own_work(shared) {}
  drape::Stated shared;
  drape::Stated own_work;

  int node_count() const { return shared.node_count(); }
  /// Assignment between equal sizes: copies into the existing buffers.
  void copy_to(drape::Stated& work) const {
    work.positions = shared.positions;
    work.velocities = shared.velocities;
    work.time = shared.time;
  }
  void copy_from(const drape::Stated& work) {
    shared.positions = work.positions;
    shared.velocities = work.velocities;
    shared.time = work.time;
  }
};

/// \throws InvalidParameter naming `state` unless it has one node per node of `cloth`.
void require_fits(const drape::Clothd& cloth, const SharedState& state);

/// ClothSpec plus the air and the dihedral bending, which drape-render and these bindings turn into
/// the cloth's force terms (drape::air_force_terms, drape::DihedralBending) when the cloth is built:
/// Python cannot define force terms.
struct ClothSpecWithAir : drape::ClothSpecd {
  drape::AirSettings air;
  double bending = 0;          ///< N m: dihedral bending stiffness (0: off)
  double bending_damping = 0;  ///< N m s
};

/// The mesh of an OBJ file (drape::mesh_io). \throws InvalidParameter naming the file, line and
/// element, or std::runtime_error if the module was built without the OBJ reader.
drape::ClothMesh<double> read_obj_mesh(const std::string& path, double scale, bool rest_from_uv);

/// The spec with the air's force terms, as drape::Cloth takes it.
drape::ClothSpecd library_spec(const ClothSpecWithAir& spec);

/// A failed step: the state is unchanged; Python sees drape.SimulationError.
class StepFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A Python exception raised inside a pin path's callback during a step: the step sees a NaN
/// position and fails, and the error is raised once the step is over. Only touched with the GIL.
std::optional<nb::python_error>& pending_callback_error();

/// Raises the pending callback error if there is one, else StepFailed for `status` at `time`.
[[noreturn]] void fail_step(const drape::StepStatus& status, double time);

/// Refuses to step an integrator, state or scene that another thread is stepping (the GIL is
/// released while they step). \throws std::runtime_error naming what is busy.
class BusyGuard {
 public:
  BusyGuard(std::initializer_list<const void*> objects, const char* what);
  ~BusyGuard();
  BusyGuard(const BusyGuard&) = delete;
  BusyGuard& operator=(const BusyGuard&) = delete;

 private:
  std::vector<const void*> m_objects;
};

/// A ClothScene with Python's shared states, and what runs before each of its steps (a scene
/// file's [[moving-pins]] schedule, applied to the first cloth as drape-render does; files.cpp).
class PyClothScene {
 public:
  /// Called with the scene before each step.
  using BeforeStep = std::function<void(drape::ClothScene<double>&)>;

  PyClothScene(const std::vector<ClothSpecWithAir>& specs, drape::IntegratorKind kind,
               const drape::ImplicitOptions& options, const drape::SelfCollisionSettings<double>& collisions);
  /// The cloths of `specs` (with their force terms: not checked again), the first one starting
  /// from `start`; `before_step` is called once now and before each step.
  PyClothScene(const std::vector<drape::ClothSpecd>& specs, drape::IntegratorKind kind,
               const drape::ImplicitOptions& options, const drape::SelfCollisionSettings<double>& collisions,
               drape::Stated start, BeforeStep before_step);
  PyClothScene(const PyClothScene&) = delete;
  PyClothScene& operator=(const PyClothScene&) = delete;

  drape::ClothScene<double>& scene() { return m_scene; }
  SharedState& state(int k);
  /// Before a step: pins and releases what the scene file's schedule has due.
  void apply_schedule();
  /// Copies the shared states into the scene's and back.
  void to_scene();
  void from_scene();

 private:
  drape::ClothScene<double> m_scene;
  std::vector<std::unique_ptr<SharedState>> m_states;
  BeforeStep m_before_step;
};

}  // namespace drape::python
