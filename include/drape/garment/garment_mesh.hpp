#pragma once
/// \file garment_mesh.hpp
/// A garment's cloth mesh from its sewing pattern: every panel's outline sampled at the edge length
/// (outline_sampling.hpp), filled with near-equilateral triangles (panel_mesher.hpp) and placed in
/// 3D by the panel's transform, all panels in one mesh (each a separate piece of it), and the pairs
/// of vertices its stitches sew together.
///
/// One mesh, one cloth: the integrators step the whole garment as one system, the seams are
/// springs between its own vertices (physics/seam_springs.hpp) that couple the panels in that
/// system, and self-collision sees the whole garment. The rest shape is each vertex's panel
/// coordinates (`rest_uv`, metres), so every panel keeps its pattern's lengths wherever it is placed.
/// Triangles run counter-clockwise seen from outside the garment (the side of each panel that faces
/// away from the body: outward_normal()).

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "drape/core/cloth_mesh.hpp"
#include "drape/garment/outline_sampling.hpp"
#include "drape/garment/panel_mesher.hpp"
#include "drape/garment/sewing_pattern.hpp"

namespace drape {

struct GarmentMesh {
  /// Every panel's vertices, panel after panel in the pattern's order, placed in 3D; `rest_uv` the
  /// panel coordinates; group "panel NAME" each panel's vertices.
  ClothMesh<double> mesh;
  /// Pairs of vertices sewn together, stitch after stitch in the pattern's order (a panel corner
  /// where two stitches meet is in a pair of each).
  std::vector<std::array<int, 2>> seam_pairs;
  /// Per panel: its first vertex; the last entry is the vertex count.
  std::vector<int> panel_begin;
  /// Per seam pair: the stitch it belongs to.
  std::vector<int> seam_stitch;
};

/// The garment of `pattern` meshed at `edge_length` (metres, the target edge of the triangles and
/// the outline's spacing). \throws as sample_outlines() and mesh_panel().
inline GarmentMesh garment_mesh(const SewingPattern& pattern, double edge_length) {
  const PatternOutlines outlines = sample_outlines(pattern, edge_length);
  GarmentMesh out;
  std::vector<PanelMesh> panels;
  int total = 0;
  for (std::size_t k = 0; k < pattern.panels.size(); ++k) {
    const std::vector<Eigen::Vector2d>& points = outlines.panels[k].points;
    Eigen::Matrix2Xd outline(2, Eigen::Index(points.size()));
    for (std::size_t i = 0; i < points.size(); ++i) outline.col(Eigen::Index(i)) = points[i];
    panels.push_back(mesh_panel(outline, edge_length));
    out.panel_begin.push_back(total);
    total += int(panels.back().rest.cols());
  }
  out.panel_begin.push_back(total);
  ClothMesh<double>& mesh = out.mesh;
  mesh.positions.resize(3, total);
  mesh.rest_uv.resize(2, total);
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const PatternPanel& panel = pattern.panels[k];
    const PanelMesh& m = panels[k];
    const int begin = out.panel_begin[k];
    std::vector<int>& group = mesh.groups["panel " + panel.name];
    for (Eigen::Index i = 0; i < m.rest.cols(); ++i) {
      mesh.positions.col(begin + i) = panel_to_world(panel, m.rest.col(i));
      mesh.rest_uv.col(begin + i) = m.rest.col(i);
      group.push_back(begin + int(i));
    }
    // Counter-clockwise in the panel plane faces local +z; turned round where the outside is -z.
    const bool flip = outlines.panels[k].reversed;
    for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
      const int a = begin + m.triangles(0, t), b = begin + m.triangles(1, t), c = begin + m.triangles(2, t);
      mesh.triangles.push_back(flip ? std::array<int, 3>{a, c, b} : std::array<int, 3>{a, b, c});
    }
  }
  for (std::size_t s = 0; s < pattern.stitches.size(); ++s) {
    const Stitch& stitch = pattern.stitches[s];
    const int a = out.panel_begin[std::size_t(stitch.sides[0].panel)];
    const int b = out.panel_begin[std::size_t(stitch.sides[1].panel)];
    for (const auto& [i, j] : stitch_point_pairs(pattern, outlines, int(s))) {
      out.seam_pairs.push_back({a + i, b + j});
      out.seam_stitch.push_back(int(s));
    }
  }
  return out;
}

}  // namespace drape
