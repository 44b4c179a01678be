#pragma once
// What the two binding files share: the state numpy sees, the spec with its air, the guard against
// stepping one object from two threads, and the errors that become Python exceptions.

#include <nanobind/nanobind.h>

#include <array>
#include <initializer_list>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "drape/core/state.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/air.hpp"
#include "drape/scene/cloth_scene.hpp"
#include "scene_setup.hpp"

namespace drape::python {

namespace nb = nanobind;

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

/// ClothSpec plus the air, which drape-render and these bindings turn into the cloth's force terms
/// (drape::air_force_terms) when the cloth is built: Python cannot define force terms.
struct ClothSpecWithAir : drape::ClothSpecd {
  drape::AirSettings air;
};

/// The spec with the air's force terms, as drape::Cloth takes it.
drape::ClothSpecd library_spec(const ClothSpecWithAir& spec);

/// A failed step: the state is unchanged; Python sees drape.SimulationError.
class StepFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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

/// A ClothScene with Python's shared states, and when it comes from a scene file, the file's
/// settings and its [[moving-pins]] schedule (applied to the first cloth before each step, as
/// drape-render does).
class PyClothScene {
 public:
  PyClothScene(const std::vector<ClothSpecWithAir>& specs, drape::IntegratorKind kind,
               const drape::ImplicitOptions& options, const drape::SelfCollisionSettings<double>& collisions);
  /// The scene of a scene file: its cloths, the first one starting from `start`, its moving pins.
  PyClothScene(std::shared_ptr<const drape::render::Settings> settings, const std::vector<drape::ClothSpecd>& specs,
               drape::Stated start);
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
  std::shared_ptr<const drape::render::Settings> m_settings;
  std::optional<drape::render::PinSchedule> m_schedule;
};

/// The scene-file and renderer bindings (render_bindings.cpp).
void bind_scene_file_and_renderer(nb::module_& m);

/// drape::parse with the library's error, for option names given as strings.
template <class Enum>
Enum parse_name(const std::string& text) {
  return drape::parse<Enum>(text);
}

}  // namespace drape::python
