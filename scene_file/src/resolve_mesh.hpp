#pragma once
// The first cloth's mesh, density and pins by group and box from Settings::mesh (mesh_source.hpp).

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file::detail {

/// Sets s.cloth.mesh (read or generated), s.cloth.areal_density and the pins by group and box
/// (joined to --pins, or to the boundary preset's corners on a grid). The placement must be set.
/// \throws SettingsError naming the flag.
void resolve_mesh(Settings& s);

}  // namespace drape::scene_file::detail
