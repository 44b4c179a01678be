#pragma once
/// \file mesh_source.hpp
/// Where a scene's first cloth comes from when it is not the nx x ny grid: an OBJ file (through
/// drape::mesh_io), a sewing pattern (through drape::pattern_io) or a mesh the library generates (a
/// disk, a rectangle with a hole), with its
/// scale, mass per area, pins by group or box and dihedral bending. Every field is a flag of the
/// "Cloth mesh" group of drape-render and a key of a scene file (command_line.hpp).

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace drape::scene_file {

struct MeshSource {
  /// --mesh: an OBJ file; in a scene file, relative to the scene file's folder. Empty: `shape`.
  std::string file;
  /// --shape: grid (nx, ny, spacing) | disk | rectangle-with-hole, when no --mesh is given.
  std::string shape = "grid";
  double radius = 0.5;                          ///< --radius: the disk's, m
  double ring_radius = 0;                       ///< --ring-radius: the disk's ring of vertices, m (0: none)
  std::array<double, 2> size{1.0, 1.0};         ///< --size W H: the rectangle's, m (along x, z)
  double hole_radius = 0.1;                     ///< --hole-radius: m
  std::array<double, 2> hole_centre{0.5, 0.5};  ///< --hole-centre X Z: in the rectangle, m from its corner
  double edge_length = 0.03;                    ///< --edge-length: target edge of a generated mesh, m
  double scale = 1;                             ///< --scale: metres per unit of the OBJ file
  bool rest_from_uv = false;                    ///< --rest-from-uv: the OBJ file's vt as the rest pattern
  /// --density: kg/m^2; every node weighs its share of the rest area times this (0: --mass per node).
  double density = 0;
  std::vector<std::string> pin_groups;  ///< --pin-groups: groups of the mesh whose nodes are pinned
  /// --pin-box X0 Y0 Z0 X1 Y1 Z1: nodes starting inside this box (m) are pinned; empty: none.
  std::vector<double> pin_box;
  double bending = 0;     ///< --bending: dihedral bending stiffness, N m (0: off)
  double bending_kd = 0;  ///< --bending-kd: its damping, N m s

  /// --pattern: a GarmentCode JSON sewing pattern (through drape::pattern_io); in a scene file,
  /// relative to the scene file's folder. The cloth is then the garment sewn from it
  /// (drape/garment/garment.hpp): its panels meshed at --edge-length, in --fabric, the seams closing
  /// in --seam-closing-time, gravity on after them. Empty: --mesh or --shape.
  std::string pattern;
  std::string fabric = "cotton";   ///< --fabric: a preset of drape/garment/fabric.hpp (with --pattern)
  double seam_stiffness = 500;     ///< --seam-stiffness: N/m per sewn pair (with --pattern)
  double seam_closing_time = 1.0;  ///< --seam-closing-time: s (with --pattern)
  /// Scene file table [panel-offsets], `NAME = [x, y, z]` (m): moved placements of the pattern's
  /// panels, each added to panel NAME's translation before the garment is sewn (with --pattern).
  std::vector<std::pair<std::string, std::array<double, 3>>> panel_offsets;

  /// True when the cloth is not the plain grid of nx, ny and spacing.
  bool is_mesh() const { return !file.empty() || !pattern.empty() || shape != "grid"; }
};

}  // namespace drape::scene_file
