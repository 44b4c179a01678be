#pragma once
// The scene file's arrays of tables, which have no flags: [[colliders]] (the library's colliders,
// built as they are read), [[moving-pins]] (PinSpec) and [[cloths]] (ExtraCloth). Each message
// names the table's key, e.g. colliders[1].radius.

#include <toml++/toml.h>

#include "drape/scene_file/settings.hpp"

namespace drape::scene_file::detail {

/// The [[colliders]] tables, appended to s.cloth.colliders (their keys to s.collider_keys).
void read_colliders(const toml::node& node, Settings& s);

/// The [[moving-pins]] tables, appended to s.moving_pins; their nodes are checked against the grid
/// later (pin_node(), from validate()): flags may change nx and ny.
void read_moving_pins(const toml::node& node, Settings& s);

/// The [[cloths]] tables, appended to s.extra_cloths; their values are checked when the cloths
/// are built from the first one (cloth_specs(), from validate()).
void read_cloths(const toml::node& node, Settings& s);

/// The scene file's table [panel-offsets] (`NAME = [x, y, z]`, m), into s.mesh.panel_offsets.
void read_panel_offsets(const toml::node& node, Settings& s);

}  // namespace drape::scene_file::detail
