#pragma once
/// \file read_sewing_pattern.hpp
/// A sewing pattern (garment/sewing_pattern.hpp) read from GarmentCode's JSON "specification"
/// (drape's garments.md, "Sewing patterns"), the reading of pygarment/pattern/core.py and the
/// placement of pygarment/meshgen/boxmeshgen.py:
///
/// - `properties.units_in_meter` (default 100: centimetres) scales vertices, translations and
///   circle radii to metres. `properties.curvature_coords` must be "relative" (the default),
///   `properties.normalized_edge_loops` true (the default); `normalize_panel_translation` true moves
///   each panel's vertices so that their mean is the origin and adds that mean to the translation's
///   x and y, as GarmentCode does.
/// - `pattern.panels.NAME`: `vertices` ([x, y] each), `edges` (`{"endpoints": [i, j], "curvature":
///   ...}`, one closed loop in order), `translation` [x, y, z], `rotation` [x, y, z] Euler degrees
///   (R = Rz Ry Rx). Panels keep the file's order.
/// - `curvature`: `{"type": "quadratic", "params": [[t, s]]}`, `{"type": "cubic", "params": [[t1, s1],
///   [t2, s2]]}` (t along the edge, s to its left, in edge lengths), `{"type": "circle", "params":
///   [radius, large_arc, right]}` (flags 0/1 or false/true), or GarmentCode's older bare `[t, s]`
///   (quadratic).
/// - `pattern.stitches`: `[{"panel": NAME, "edge": i}, {"panel": NAME, "edge": j}]`, optionally with a
///   third element "right_wrong".
/// - Other members (`parameters`, `parameter_order`, `panel_order`, edge labels) are ignored.
///
/// Every defect throws a PatternError naming the file and the place in the JSON, e.g.
/// `shirt.json: pattern.panels.left_ftorso.edges[3].curvature.type: unknown curve type "spline"
/// (allowed: quadratic, cubic, circle)`; the pattern read passes validate(). Nothing is returned in part.

#include <string>
#include <string_view>

#include "drape/garment/sewing_pattern.hpp"

namespace drape::pattern_io {

/// Bounds on what a file may hold, so that reading any input takes bounded time and memory (about
/// half a second per megabyte of JSON, mostly nlohmann-json's parse; GarmentCode's patterns have
/// 20-100 kB, 6-12 panels, up to 30 edges a panel).
constexpr long long max_pattern_bytes = 16LL << 20;
constexpr int max_pattern_panels = 1000;
constexpr int max_panel_vertices = 1000;
constexpr int max_panel_edges = 1000;
constexpr int max_pattern_edges = 20000;  ///< over all panels
constexpr int max_pattern_stitches = 20000;

/// The pattern of the JSON file `path`.
/// \throws PatternError for a file that cannot be read or holds a defect (docs/garments.md lists them).
SewingPattern read_sewing_pattern(const std::string& path, const PatternCheckOptions& options = {});

/// The pattern of JSON text held in memory; `source_name` stands for the file in messages.
/// \throws PatternError as read_sewing_pattern().
SewingPattern parse_sewing_pattern(std::string_view json_text, const std::string& source_name,
                                   const PatternCheckOptions& options = {});

}  // namespace drape::pattern_io
