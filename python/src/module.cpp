// The Python module drape._drape (docs/python.md). Its bindings are in one file per group
// (bindings.hpp): the model, stepping, scene and other files, rendering.

#include <nanobind/stl/string.h>

#include <string>

#include "bindings.hpp"
#include "drape/config.hpp"

NB_MODULE(_drape, m) {
  using namespace drape::python;
  m.doc() =
      "drape: mass-spring cloth simulation (C++ library bindings). See docs/python.md; the pure-Python package "
      "`drape` re-exports everything here.";
  m.attr("__version__") = std::to_string(DRAPE_VERSION_MAJOR) + "." + std::to_string(DRAPE_VERSION_MINOR) + "." +
                          std::to_string(DRAPE_VERSION_PATCH);

  // In the order the stubs list them.
  bind_errors(m);
  bind_file_errors(m);
  bind_settings(m);
  bind_collider(m);
  bind_spec_and_cloth(m);
  bind_state(m);
  bind_options(m);
  bind_pins(m);
  bind_reports(m);
  bind_integrators(m);
  bind_scene(m);
  bind_io(m);
  bind_scene_files(m);
  bind_rendering(m);
  bind_option_names(m);
}
