#include "resolve_mesh.hpp"

#include <cmath>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "drape/core/mesh_generators.hpp"
#include "error_names.hpp"
#if DRAPE_SCENE_FILE_HAS_MESH_IO
#include "drape/mesh_io/read_obj.hpp"
#endif
#if DRAPE_SCENE_FILE_HAS_PATTERN_IO
#include "drape/garment/garment.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"
#endif

namespace drape::scene_file::detail {

drape::ClothMesh<double> read_obj_mesh(const std::string& path, double scale, bool rest_from_uv, const KeyName& key,
                                       const std::string& file_key) {
#if DRAPE_SCENE_FILE_HAS_MESH_IO
  drape::mesh_io::ObjOptions options;
  options.scale = scale;
  options.rest_from_uv = rest_from_uv;
  try {
    return drape::mesh_io::read_obj<double>(path, options).mesh;
  } catch (const drape::mesh_io::ObjError& e) {
    throw SettingsError(key(file_key) + ": " + std::string(e.what()));
  } catch (const InvalidParameter& e) {
    fail(key(e.parameter() == "ObjOptions::scale" ? "scale" : file_key), e.value(), e.allowed());
  }
#else
  (void)scale;
  (void)rest_from_uv;
  throw SettingsError(key(file_key) + " '" + path +
                      "': this build reads no OBJ files (it was built without tinyobjloader: "
                      "apt-get install libtinyobjloader-dev and rebuild)");
#endif
}

namespace {

drape::ClothMesh<double> read_mesh_file(const MeshSource& m, const KeyName& key) {
  return read_obj_mesh(m.file, m.scale, m.rest_from_uv, key, "mesh");
}

/// Vertices a scene file may generate: a scene's mesh, not a stress test (the library's generators
/// take up to drape::max_generated_vertices through the API).
constexpr double max_scene_vertices = 100'000;

drape::ClothMesh<double> generated_mesh(const MeshSource& m, const KeyName& key) {
  // Near-equilateral triangles of edge h: about 2 / (sqrt(3) h^2) vertices per m^2.
  const double area = m.shape == "disk" ? 3.14159265358979 * m.radius * m.radius : m.size[0] * m.size[1];
  const double h = m.edge_length;
  if (std::isfinite(area) && std::isfinite(h) && h > 0 && area * 2 / (std::sqrt(3.0) * h * h) > max_scene_vertices)
    fail(key("edge-length"), number(h),
         "an edge length that gives the " + m.shape + " at most 100000 vertices (>= " +
             number(std::sqrt(area * 2 / (std::sqrt(3.0) * max_scene_vertices))) + " m)");
  try {
    if (m.shape == "disk") return drape::disk_mesh<double>(m.radius, m.edge_length, m.ring_radius);
    return drape::rectangle_with_hole_mesh<double>(m.size[0], m.size[1], {m.hole_centre[0], m.hole_centre[1]},
                                                   m.hole_radius, m.edge_length);
  } catch (const InvalidParameter& e) {
    throw SettingsError(key("shape") + " " + m.shape + ": " + e.what());
  }
}

/// The garment of m.pattern (drape/garment/garment.hpp) as `spec`'s mesh, springs, density and
/// force terms (seams, bending, gravity after the seams close: spec.gravity moves into that term),
/// its seam pairs joined for self-collision.
void apply_pattern(const MeshSource& m, drape::ClothSpecd& spec, const KeyName& key) {
  if (!m.file.empty()) fail(key("pattern"), "'" + m.pattern + "' with a mesh file", "a pattern or a mesh, not both");
  if (m.shape != "grid") fail(key("shape"), "'" + m.shape + "' with a pattern", "grid (the default) when a pattern gives the cloth");
  if (m.density != 0) fail(key("density"), number(m.density), "0 with a pattern: the fabric sets the density");
  if (m.bending != 0 || m.bending_kd != 0)
    fail(key(m.bending != 0 ? "bending" : "bending-kd"), number(m.bending != 0 ? m.bending : m.bending_kd),
         "0 with a pattern: the fabric sets the bending");
#if DRAPE_SCENE_FILE_HAS_PATTERN_IO
  drape::Fabric fabric;
  try {
    fabric = drape::fabric_preset(m.fabric);
  } catch (const InvalidParameter& e) { fail(key("fabric"), e.value(), e.allowed()); }
  drape::SewingSettings sewing;
  sewing.edge_length = m.edge_length;
  sewing.seam_stiffness = m.seam_stiffness;
  sewing.seam_closing_time = m.seam_closing_time;
  sewing.gravity = spec.gravity;
  const std::map<std::string, std::string> key_of = {{"edge length", "edge-length"},
                                                     {"seam stiffness", "seam-stiffness"},
                                                     {"seam closing time", "seam-closing-time"},
                                                     {"gravity", "gravity"}};
  try {
    sewing.validate();
  } catch (const InvalidParameter& e) {
    const auto it = key_of.find(e.parameter());
    fail(key(it != key_of.end() ? it->second : e.parameter()), e.value(), e.allowed());
  }
  drape::SewingPattern pattern;
  try {
    pattern = drape::pattern_io::read_sewing_pattern(m.pattern);
  } catch (const std::exception& e) {
    throw SettingsError(key("pattern") + " '" + m.pattern + "': " + e.what());
  }
  for (const auto& [name, offset] : m.panel_offsets) {
    try {
      drape::move_panel(pattern, name, Eigen::Vector3d(offset[0], offset[1], offset[2]));
    } catch (const InvalidParameter& e) {
      fail("[panel-offsets] " + name, e.value(), e.allowed() + " ('" + m.pattern + "')");
    }
  }
  drape::Garment garment;
  try {
    garment = drape::dress_garment(pattern, fabric, sewing);
  } catch (const std::exception& e) {
    throw SettingsError(key("pattern") + " '" + m.pattern + "': " + e.what());
  }
  spec.mesh = garment.spec.mesh;
  spec.areal_density = garment.spec.areal_density;
  spec.springs = garment.spec.springs;
  spec.gravity = 0;
  for (auto& term : garment.spec.force_terms) spec.force_terms.push_back(term);
  spec.self_collision.joined_nodes = garment.spec.self_collision.joined_nodes;
  if (!spec.pinned_nodes) spec.pinned_nodes = std::vector<int>{};
#else
  (void)spec;
  throw SettingsError(key("pattern") + " '" + m.pattern +
                      "': this build reads no sewing patterns (it was built without nlohmann-json: "
                      "apt-get install nlohmann-json3-dev and rebuild)");
#endif
}

}  // namespace

void apply_mesh_source(const MeshSource& m, drape::ClothSpecd& spec, const KeyName& key) {
  const std::vector<std::string> shapes = {"grid", "disk", "rectangle-with-hole"};
  if (std::find(shapes.begin(), shapes.end(), m.shape) == shapes.end())
    fail(key("shape"), "'" + m.shape + "'", "grid | disk | rectangle-with-hole");
  if (!m.file.empty() && m.shape != "grid")
    fail(key("shape"), "'" + m.shape + "' with a mesh file", "grid (the default) when a mesh file gives the mesh");
  if (m.ring_radius != 0 && (m.shape != "disk" || !m.file.empty() || !m.pattern.empty()))
    fail(key("ring-radius"), number(m.ring_radius), "0 unless the cloth is the disk (shape = disk)");
  if (m.shape == "disk" && m.ring_radius != 0 &&
      !(m.ring_radius >= m.edge_length && m.ring_radius <= m.radius - m.edge_length))
    fail(key("ring-radius"), number(m.ring_radius),
         "0 (no ring) or in [edge-length, radius - edge-length] = [" + number(m.edge_length) + ", " +
             number(m.radius - m.edge_length) + "] m");
  if (!(std::isfinite(m.scale) && m.scale > 0)) fail(key("scale"), number(m.scale), "finite and > 0");
  if (!(std::isfinite(m.density) && m.density >= 0)) fail(key("density"), number(m.density), "finite and >= 0 kg/m^2");
  if (!(std::isfinite(m.bending) && m.bending >= 0)) fail(key("bending"), number(m.bending), "finite and >= 0 N m");
  if (!(std::isfinite(m.bending_kd) && m.bending_kd >= 0))
    fail(key("bending-kd"), number(m.bending_kd), "finite and >= 0 N m s");
  if (!m.pin_box.empty()) {
    if (m.pin_box.size() != 6) fail(key("pin-box"), std::to_string(m.pin_box.size()) + " numbers", "6: X0 Y0 Z0 X1 Y1 Z1");
    for (int k = 0; k < 3; ++k)
      if (!(m.pin_box[std::size_t(k)] <= m.pin_box[std::size_t(k) + 3]))
        fail(key("pin-box"), "a box with X0 > X1, Y0 > Y1 or Z0 > Z1 (or a non-finite corner)",
             "finite corners X0 Y0 Z0 <= X1 Y1 Z1");
  }
  if (!m.pattern.empty()) {
    apply_pattern(m, spec, key);
  } else {
    if (!m.panel_offsets.empty())
      fail("[panel-offsets] " + m.panel_offsets.front().first, "an offset without --pattern",
           "the table only with a pattern, naming its panels");
    if (m.density > 0) spec.areal_density = m.density;
    if (m.is_mesh()) spec.mesh = m.file.empty() ? generated_mesh(m, key) : read_mesh_file(m, key);
  }
  if (m.pin_groups.empty() && m.pin_box.empty()) return;

  // Pins by group and box join the pins by id (--pins); without --pins, the boundary preset's
  // corners only on a grid.
  const drape::ClothMesh<double> mesh =
      spec.mesh ? *spec.mesh : drape::grid_mesh<double>(spec.nx, spec.ny, spec.spacing);
  std::vector<int> pinned = spec.pinned_nodes ? *spec.pinned_nodes : std::vector<int>{};
  if (!spec.pinned_nodes && !spec.mesh) {
    const drape::Grid<double> grid(spec.nx, spec.ny, spec.spacing, spec.node_mass);
    pinned = drape::Pins::preset(spec.boundary, grid).nodes();
  }
  for (const std::string& group : m.pin_groups) {
    const auto it = mesh.groups.find(group);
    if (it == mesh.groups.end()) {
      std::string names;
      for (const auto& [name, nodes] : mesh.groups) names += (names.empty() ? "" : ", ") + name;
      fail(key("pin-groups"), "'" + group + "'", "a group of the mesh: " + (names.empty() ? "(it has none)" : names));
    }
    pinned.insert(pinned.end(), it->second.begin(), it->second.end());
  }
  if (!m.pin_box.empty()) {
    const drape::Matrix3X<double> start = spec.placement.apply(mesh.positions);
    std::size_t inside = 0;
    for (Eigen::Index v = 0; v < start.cols(); ++v) {
      bool in = true;
      for (int k = 0; k < 3; ++k)
        in = in && start(k, v) >= m.pin_box[std::size_t(k)] && start(k, v) <= m.pin_box[std::size_t(k) + 3];
      if (in) {
        pinned.push_back(int(v));
        ++inside;
      }
    }
    if (inside == 0) fail(key("pin-box"), "a box that holds no node at the start", "a box around the nodes to pin");
  }
  spec.pinned_nodes = pinned;
}

void resolve_mesh(Settings& s) {
  apply_mesh_source(s.mesh, s.cloth, [](const std::string& name) { return "--" + name; });
}

}  // namespace drape::scene_file::detail
