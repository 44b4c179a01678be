// libFuzzer target: drape::pattern_io's sewing-pattern reader (nlohmann-json and the checks around
// it) on arbitrary bytes, then the outlines of what it accepts sampled and their stitches paired. The
// reader must either return a pattern that passes validate() or throw PatternError; the sampling
// may refuse an edge length with InvalidParameter or PatternError. Any other exception escapes and
// is reported as a crash, as are crashes, leaks, undefined behaviour and inputs slower than the
// run's -timeout.
#include <cstdint>
#include <string_view>

#include "drape/garment/outline_sampling.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  drape::SewingPattern pattern;
  try {
    pattern = drape::pattern_io::parse_sewing_pattern(text, "fuzz.json");
  } catch (const drape::PatternError&) {
    return 0;
  }
  drape::validate(pattern);  // throws on a pattern the reader should have refused: reported as a crash
  // An edge length that gives about 200 points round all the panels' outlines.
  double total = 0;
  for (const drape::PatternPanel& panel : pattern.panels)
    for (int e = 0; e < int(panel.edges.size()); ++e) total += drape::edge_length(panel, e);
  try {
    const drape::PatternOutlines outlines = drape::sample_outlines(pattern, total / 200);
    for (std::size_t p = 0; p < pattern.panels.size(); ++p) {
      const drape::PanelOutline& outline = outlines.panels[p];
      const int n = int(outline.points.size());
      if (drape::twice_signed_area(outline.points) <= 0) __builtin_trap();
      for (const auto& indices : outline.edge_points)
        for (int i : indices)
          if (i < 0 || i >= n) __builtin_trap();
    }
    for (int s = 0; s < int(pattern.stitches.size()); ++s) {
      const drape::Stitch& stitch = pattern.stitches[std::size_t(s)];
      const auto pairs = drape::stitch_point_pairs(pattern, outlines, s);
      const auto& a = outlines.panels[std::size_t(stitch.sides[0].panel)];
      const auto& b = outlines.panels[std::size_t(stitch.sides[1].panel)];
      if (pairs.size() != a.edge_points[std::size_t(stitch.sides[0].edge)].size() ||
          pairs.size() != b.edge_points[std::size_t(stitch.sides[1].edge)].size())
        __builtin_trap();
    }
  } catch (const drape::PatternError&) {
  } catch (const drape::InvalidParameter&) {
  }
  return 0;
}
