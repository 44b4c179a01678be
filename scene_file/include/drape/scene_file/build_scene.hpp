#pragma once
/// \file build_scene.hpp
/// The scene a run starts from, built from validated settings (validate.hpp): every cloth's
/// drape::ClothSpec (the air's force terms, the floor collider, the [[cloths]] tables), the first
/// cloth's start state, the box the fixed camera frames and the floor's height. drape-render, the
/// Python package and the sweeps build scenes here, so a scene file means the same in all of them.

#include <memory>
#include <optional>
#include <vector>

#include "drape/model/cloth.hpp"
#include "drape/fwd.hpp"
#include "drape/scene_file/settings.hpp"
#include "drape/viewer/camera.hpp"

namespace drape::scene_file {

/// What a run starts from (prepare_scene()).
struct PreparedScene {
  drape::ClothSpecd first;               ///< s.cloth with the air's force terms and the floor collider
  std::vector<drape::ClothSpecd> specs;  ///< every cloth: `first`, then one per [[cloths]] table
  drape::Stated start;                   ///< the first cloth's: its initial state, or --load-state
  drape::viewer::Bounds framed;          ///< the box the fixed camera frames (framed_box())
  double floor_y = 0;                    ///< the floor's height (drawn, and the floor collider)
};

/// The scene of validated settings `s`: the one entry drape-render and the Python package use.
/// \throws SettingsError for a bad --load-state file or a cloth the library rejects (naming the
/// flag or key), drape::InvalidParameter for a check with no flag of its own.
PreparedScene prepare_scene(const Settings& s);

/// The force terms of `s.air` for the cloth of `s.cloth` (drape::air_force_terms() on its mesh's or
/// grid's triangles); none when the
/// air exerts no force (AirSettings::active() is false), so a still-air run is unchanged.
std::vector<std::shared_ptr<const drape::ForceTerm<double>>> air_force_terms(const Settings& s);

/// The dihedral bending term of `s.mesh` (--bending, --bending-kd) on the first cloth's mesh;
/// null when both are 0.
std::shared_ptr<const drape::ForceTerm<double>> bending_term(const Settings& s);

/// The height of the floor (drawn, and the floor collider) if the settings fix it: --floor-height,
/// else the highest static plane collider whose normal is +y; nullopt: the camera puts it just
/// below the box it frames (chosen at run time from the start state).
std::optional<double> fixed_floor_height(const Settings& s);

/// True if `collider` is drawn as the floor: a static plane facing +y at `floor_height`.
bool is_floor(const drape::Colliderd& collider, double floor_height);

/// The plane collider of --floor-collider at height y, with --floor-friction.
/// \throws SettingsError naming --floor-friction or --floor-height.
drape::Colliderd floor_collider(const Settings& s, double y);

/// drape::Cloth(spec) for the settings `s`: `spec` is s.cloth (plus force terms), its colliders
/// s.cloth.colliders and at most the floor collider after them. The library's error about a collider
/// touching a pinned node (`colliders[k]`) names the key or flag that made collider k.
/// \throws SettingsError.
drape::Clothd make_cloth(const Settings& s, const drape::ClothSpecd& spec);

/// Every cloth of the scene: `first` (s.cloth with its force terms and the floor collider), then
/// one per [[cloths]] table, built from `first` with its own grid, pins, placement and air.
/// \throws SettingsError naming the table's key (cloths[k].nx).
std::vector<drape::ClothSpecd> cloth_specs(const Settings& s, const drape::ClothSpecd& first);

/// The node id of `pin` in the grid of `s.cloth` (id = j*nx + i).
/// \throws SettingsError naming moving-pins[k].node or moving-pins[k].id when the grid has no such node.
int pin_node(const Settings& s, const PinSpec& pin);

/// Simulated seconds the run covers after its start (for framing moving colliders).
double run_length(const Settings& s);

/// The box the fixed camera frames: where the cloth can hang from its pins and the nodes of the
/// [[moving-pins]] tables (hanging_bounds), every key position of a [[moving-pins]] path and the
/// cloth hanging below it (as far as below the node at the start), every collider but the planes
/// over the whole run (a moving one at 9 times), and the floor collider's height (the cloth can
/// land there). Without colliders and [[moving-pins]]: hanging_bounds alone.
drape::viewer::Bounds framed_box(const Settings& s, const drape::Clothd& cloth, const drape::Stated& start,
                                 std::optional<double> floor_collider_y);

}  // namespace drape::scene_file
