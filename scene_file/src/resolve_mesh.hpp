#pragma once
// A cloth's mesh, density and pins by group and box from a MeshSource (mesh_source.hpp): the first
// cloth's from the flags and scene keys, another's from its [[cloths]] table.

#include <functional>
#include <string>

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file::detail {

/// How an error names the setting `name` ("edge-length"): "--edge-length" for the flags,
/// "scene file 'a.toml': cloths[1].edge-length" for a [[cloths]] table.
using KeyName = std::function<std::string(const std::string& name)>;

/// The mesh of the OBJ file at `path`, `scale` metres per file unit, its rest shape from the `vt`
/// coordinates if `rest_from_uv`. \throws SettingsError naming key(file_key), or key("scale").
drape::ClothMesh<double> read_obj_mesh(const std::string& path, double scale, bool rest_from_uv, const KeyName& key,
                                       const std::string& file_key);

/// Sets spec.mesh (read or generated from `m`; none when `m` is the grid), spec.areal_density and
/// the pins by group and box (joined to spec.pinned_nodes, or to the boundary preset's corners on a
/// grid without them). The placement must be set.
/// \throws SettingsError naming the setting by `key`.
void apply_mesh_source(const MeshSource& m, drape::ClothSpecd& spec, const KeyName& key);

/// apply_mesh_source() of the first cloth: s.mesh to s.cloth, errors naming the flags.
void resolve_mesh(Settings& s);

}  // namespace drape::scene_file::detail
