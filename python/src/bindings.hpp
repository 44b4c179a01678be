#pragma once
// The binding functions, each adding one group of classes and functions to the module (called in
// the order of the stubs by NB_MODULE in module.cpp). What they share: helpers.hpp.

#include <nanobind/nanobind.h>

namespace drape::python {

namespace nb = nanobind;

/// drape.InvalidParameter and drape.SimulationError (helpers.cpp).
void bind_errors(nb::module_& m);

/// The scene-file and renderer bindings (render_bindings.cpp).
void bind_scene_file_and_renderer(nb::module_& m);

}  // namespace drape::python
