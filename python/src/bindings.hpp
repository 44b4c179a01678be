#pragma once
// The binding functions, one group of the module's classes and functions each, called by
// NB_MODULE (module.cpp) in the order of the stubs. What the groups share: helpers.hpp.

#include <nanobind/nanobind.h>

namespace drape::python {

namespace nb = nanobind;

// helpers.cpp: InvalidParameter, SimulationError.
void bind_errors(nb::module_& m);

// model.cpp: SpringParams, SpringCoefficients, Placement, SelfCollisionSettings, the air settings;
// Collider; ClothSpec, Cloth; State; PinPath, PinSet.
void bind_settings(nb::module_& m);
void bind_collider(nb::module_& m);
void bind_spec_and_cloth(nb::module_& m);
void bind_state(nb::module_& m);
void bind_pins(nb::module_& m);

// stepping.cpp: IntegratorOptions, ImplicitOptions; ContactReport, SelfCollisionReport,
// StepStatus; Integrator, Rk2, SymplecticEuler, ImplicitEuler, make_integrator; ClothScene;
// option_names.
void bind_options(nb::module_& m);
void bind_reports(nb::module_& m);
void bind_integrators(nb::module_& m);
void bind_scene(nb::module_& m);
void bind_option_names(nb::module_& m);

// files.cpp: SceneFileError, StateFormatError, FileWriteError; write_obj, save_state, load_state;
// SceneFile, load_scene.
void bind_file_errors(nb::module_& m);
void bind_io(nb::module_& m);
void bind_scene_files(nb::module_& m);

// rendering.cpp (with OSMesa) or rendering_unavailable.cpp (without): SceneFile.renderer, Renderer.
void bind_rendering(nb::module_& m);

}  // namespace drape::python
