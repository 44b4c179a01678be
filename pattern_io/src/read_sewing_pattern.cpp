// The sewing-pattern reader: nlohmann-json parses the text into a tree (keeping the order of the
// panels), which is walked with the JSON path of every value at hand so that each defect names it.
// The model's own checks (validate()) run last and name places in the same layout.
#include "drape/pattern_io/read_sewing_pattern.hpp"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace drape::pattern_io {

namespace {

using Json = nlohmann::ordered_json;

std::string text(long long value) { return detail::to_text(value); }

std::string quoted(const std::string& s) {
  const std::size_t shown = 60;
  return "\"" + s.substr(0, shown) + (s.size() > shown ? "...\"" : "\"");
}

/// A JSON value for a message: its text, cut short.
std::string shown(const Json& value) {
  std::string out = value.dump(-1, ' ', false, nlohmann::detail::error_handler_t::replace);
  if (out.size() > 60) out = out.substr(0, 57) + "...";
  return out;
}

std::string type_of(const Json& value) {
  if (value.is_number()) return "a number";
  if (value.is_boolean()) return "a boolean";
  if (value.is_null()) return "null";
  if (value.is_string()) return "a string";
  if (value.is_array()) return "an array";
  return "an object";
}

std::string plural(long long n, const char* one, const char* many) { return text(n) + " " + (n == 1 ? one : many); }

/// Walks the tree; every check names the JSON path of the value it looks at.
class Reader {
 public:
  Reader(std::string source, const PatternCheckOptions& options) : m_source(std::move(source)), m_options(options) {}

  SewingPattern read(const Json& root);

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw PatternError(m_source, path, message);
  }

  const Json& object(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_object()) fail(path, "expected " + std::string(what) + " (a JSON object), found " + type_of(value));
    return value;
  }

  const Json& array(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_array()) fail(path, "expected " + std::string(what) + " (a JSON array), found " + type_of(value));
    return value;
  }

  /// The member `key` of the object `parent` (at `path`); fails if missing.
  const Json& member(const Json& parent, const std::string& path, const char* key, const char* needed_by) const {
    const auto it = parent.find(key);
    if (it == parent.end()) fail(join(path, key), std::string("missing (") + needed_by + ")");
    return *it;
  }

  static std::string join(const std::string& path, const char* key) { return path.empty() ? key : path + "." + key; }
  static std::string at(const std::string& path, std::size_t index) { return path + "[" + text(long(index)) + "]"; }

  double number(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_number()) fail(path, "expected " + std::string(what) + " (a number), found " + type_of(value) + " " + shown(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, std::string(what) + " " + shown(value) + " is not a finite number");
    return x;
  }

  int integer(const Json& value, const std::string& path, const char* what) const {
    if (!value.is_number_integer())
      fail(path, "expected " + std::string(what) + " (an integer), found " + type_of(value) + " " + shown(value));
    if (value.is_number_unsigned()) {
      const auto u = value.get<std::uint64_t>();
      if (u > std::uint64_t(std::numeric_limits<int>::max())) fail(path, std::string(what) + " " + shown(value) + " is out of range");
      return int(u);
    }
    const auto i = value.get<std::int64_t>();
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
      fail(path, std::string(what) + " " + shown(value) + " is out of range");
    return int(i);
  }

  /// An array of exactly `n` numbers.
  std::vector<double> numbers(const Json& value, const std::string& path, std::size_t n, const char* what) const {
    if (!value.is_array() || value.size() != n)
      fail(path, "expected " + std::string(what) + " (an array of " + text(long(n)) + " numbers), found " +
                     (value.is_array() ? "an array of " + plural(long(value.size()), "element", "elements")
                                       : type_of(value) + " " + shown(value)));
    std::vector<double> out;
    for (std::size_t k = 0; k < n; ++k) out.push_back(number(value[k], at(path, k), what));
    return out;
  }

  bool flag(const Json& value, const std::string& path, const char* what) const {
    if (value.is_boolean()) return value.get<bool>();
    if (value.is_number_integer() && (value == 0 || value == 1)) return value == 1;
    fail(path, std::string(what) + " " + shown(value) + " (allowed: 0, 1, false or true)");
  }

  void read_properties(const Json& root);
  PatternPanel read_panel(const std::string& name, const Json& value, const std::string& path);
  CurveShape read_curvature(const Json& value, const std::string& path, const Eigen::Vector2d& start,
                            const Eigen::Vector2d& end);
  Stitch read_stitch(const SewingPattern& pattern, const Json& value, const std::string& path);

  std::string m_source;
  const PatternCheckOptions& m_options;
  double m_units_in_meter = 100;
  bool m_normalize_translation = false;
  long long m_edges = 0;
};

void Reader::read_properties(const Json& root) {
  const auto it = root.find("properties");
  if (it == root.end()) return;  // GarmentCode warns and scales nothing: centimetres
  const Json& properties = object(*it, "properties", "the pattern's properties");
  if (const auto units = properties.find("units_in_meter"); units != properties.end()) {
    m_units_in_meter = number(*units, "properties.units_in_meter", "the units in a metre");
    if (!(m_units_in_meter > 0))
      fail("properties.units_in_meter", shown(*units) + " units in a metre (allowed: > 0, e.g. 100 for centimetres)");
  }
  if (const auto coords = properties.find("curvature_coords"); coords != properties.end()) {
    if (!coords->is_string() || coords->get<std::string>() != "relative")
      fail("properties.curvature_coords",
           shown(*coords) + " (allowed: \"relative\"; GarmentCode converts \"absolute\" control points when it loads "
                            "a pattern, drape reads the converted file)");
  }
  if (const auto loops = properties.find("normalized_edge_loops"); loops != properties.end()) {
    if (!loops->is_boolean()) fail("properties.normalized_edge_loops", "expected a boolean, found " + type_of(*loops));
    if (!loops->get<bool>())
      fail("properties.normalized_edge_loops",
           "false (allowed: true; GarmentCode re-orders and mirrors edge loops that are not normalized when it loads "
           "a pattern, drape reads the normalized file)");
  }
  if (const auto centre = properties.find("normalize_panel_translation"); centre != properties.end()) {
    if (!centre->is_boolean())
      fail("properties.normalize_panel_translation", "expected a boolean, found " + type_of(*centre));
    m_normalize_translation = centre->get<bool>();
  }
}

CurveShape Reader::read_curvature(const Json& value, const std::string& path, const Eigen::Vector2d& start,
                                  const Eigen::Vector2d& end) {
  CurveShape shape;
  const auto relative = [&](const Json& point, const std::string& point_path) {
    const std::vector<double> ts = numbers(point, point_path, 2, "a control point [t, s]");
    return relative_to_absolute(start, end, ts[0], ts[1]);
  };
  if (value.is_array()) {  // GarmentCode's older form: the quadratic curve's control point alone
    shape.type = CurveType::Quadratic;
    shape.control[0] = relative(value, path);
    return shape;
  }
  object(value, path, "a curvature {\"type\": ..., \"params\": [...]}");
  const Json& type = member(value, path, "type", "quadratic, cubic or circle");
  const std::string type_path = join(path, "type");
  if (!type.is_string()) fail(type_path, "expected a curve type (a string), found " + type_of(type));
  const std::string name = type.get<std::string>();
  const Json& params = member(value, path, "params", "the curve's parameters");
  const std::string params_path = join(path, "params");
  array(params, params_path, "the curve's parameters");
  if (name == "quadratic" || name == "cubic") {
    const std::size_t n = name == "quadratic" ? 1 : 2;
    if (params.size() != n)
      fail(params_path, plural(long(params.size()), "control point", "control points") + " for a " + name +
                            " curve (allowed: " + text(long(n)) + (n == 1 ? ", as [[t, s]])" : ", as [[t1, s1], [t2, s2]])"));
    shape.type = n == 1 ? CurveType::Quadratic : CurveType::Cubic;
    for (std::size_t k = 0; k < n; ++k) shape.control[k] = relative(params[k], at(params_path, k));
    return shape;
  }
  if (name == "circle") {
    if (params.size() != 3)
      fail(params_path, plural(long(params.size()), "parameter", "parameters") +
                            " for a circle arc (allowed: 3, as [radius, large_arc, right])");
    shape.type = CurveType::Circle;
    shape.radius = number(params[0], at(params_path, 0), "the radius") / m_units_in_meter;
    shape.large_arc = flag(params[1], at(params_path, 1), "large_arc");
    shape.right = flag(params[2], at(params_path, 2), "right");
    return shape;
  }
  fail(type_path, "unknown curve type " + quoted(name) + " (allowed: quadratic, cubic, circle)");
}

PatternPanel Reader::read_panel(const std::string& name, const Json& value, const std::string& path) {
  object(value, path, "a panel");
  const char* needed = "a panel has vertices, edges, translation and rotation";
  PatternPanel panel;
  panel.name = name;

  const std::string vertices_path = join(path, "vertices");
  const Json& vertices = array(member(value, path, "vertices", needed), vertices_path, "the panel's vertices");
  if (vertices.size() > std::size_t(max_panel_vertices))
    fail(vertices_path, plural(long(vertices.size()), "vertex", "vertices") + " (allowed: at most " +
                            text(max_panel_vertices) + " per panel)");
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const std::vector<double> xy = numbers(vertices[v], at(vertices_path, v), 2, "a vertex [x, y]");
    panel.vertices.emplace_back(xy[0] / m_units_in_meter, xy[1] / m_units_in_meter);
  }

  const std::vector<double> t = numbers(member(value, path, "translation", needed), join(path, "translation"), 3,
                                        "the translation [x, y, z]");
  panel.translation = Eigen::Vector3d(t[0], t[1], t[2]) / m_units_in_meter;
  const std::vector<double> r =
      numbers(member(value, path, "rotation", needed), join(path, "rotation"), 3, "the rotation [x, y, z] in degrees");
  panel.rotation = rotation_from_euler_degrees(Eigen::Vector3d(r[0], r[1], r[2]));

  if (m_normalize_translation && !panel.vertices.empty()) {
    // GarmentCode's core.py (_normalize_panel_translation): the vertices' mean to the origin, added
    // to the translation's x and y as they are (not turned by the rotation).
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& p : panel.vertices) mean += p;
    mean /= double(panel.vertices.size());
    for (Eigen::Vector2d& p : panel.vertices) p -= mean;
    panel.translation.x() += mean.x();
    panel.translation.y() += mean.y();
  }

  const std::string edges_path = join(path, "edges");
  const Json& edges = array(member(value, path, "edges", needed), edges_path, "the panel's edges");
  m_edges += long(edges.size());
  if (edges.size() > std::size_t(max_panel_edges) || m_edges > max_pattern_edges)
    fail(edges_path, plural(long(edges.size()), "edge", "edges") + " (allowed: at most " + text(max_panel_edges) +
                         " per panel and " + text(max_pattern_edges) + " in all)");
  const int vertex_count = int(panel.vertices.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const std::string edge_path = at(edges_path, e);
    object(edges[e], edge_path, "an edge {\"endpoints\": [i, j], ...}");
    const std::string ends_path = join(edge_path, "endpoints");
    const Json& ends = member(edges[e], edge_path, "endpoints", "an edge joins two vertices");
    if (!ends.is_array() || ends.size() != 2)
      fail(ends_path, "expected two vertex indices [i, j], found " +
                          (ends.is_array() ? "an array of " + plural(long(ends.size()), "element", "elements")
                                           : type_of(ends) + " " + shown(ends)));
    PatternEdge edge;
    int* end_ids[2] = {&edge.start, &edge.end};
    for (std::size_t k = 0; k < 2; ++k) {
      const int id = integer(ends[k], at(ends_path, k), "a vertex index");
      if (id < 0 || id >= vertex_count)
        fail(at(ends_path, k), "vertex " + text(id) + " out of range (panel " + name + " has " +
                                   plural(vertex_count, "vertex", "vertices") + ")");
      *end_ids[k] = id;
    }
    if (const auto curvature = edges[e].find("curvature"); curvature != edges[e].end())
      edge.curve = read_curvature(*curvature, join(edge_path, "curvature"), panel.vertices[std::size_t(edge.start)],
                                  panel.vertices[std::size_t(edge.end)]);
    panel.edges.push_back(edge);
  }
  return panel;
}

Stitch Reader::read_stitch(const SewingPattern& pattern, const Json& value, const std::string& path) {
  if (!value.is_array() || value.size() < 2 || value.size() > 3)
    fail(path, "expected a stitch [{\"panel\": ..., \"edge\": ...}, {\"panel\": ..., \"edge\": ...}] (and optionally "
               "\"right_wrong\"), found " +
                   (value.is_array() ? "an array of " + plural(long(value.size()), "element", "elements")
                                     : type_of(value) + " " + shown(value)));
  Stitch stitch;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::string side_path = at(path, k);
    object(value[k], side_path, "a stitch side {\"panel\": NAME, \"edge\": i}");
    const Json& panel_name = member(value[k], side_path, "panel", "a stitch side names a panel and an edge");
    const std::string panel_path_text = join(side_path, "panel");
    if (!panel_name.is_string()) fail(panel_path_text, "expected a panel name (a string), found " + type_of(panel_name));
    const int p = pattern.find_panel(panel_name.get<std::string>());
    if (p < 0) {
      std::string names;
      for (std::size_t q = 0; q < pattern.panels.size() && q < 20; ++q)
        names += (q ? ", " : "") + pattern.panels[q].name;
      if (pattern.panels.size() > 20) names += ", ...";
      fail(panel_path_text, "unknown panel " + quoted(panel_name.get<std::string>()) + " (the pattern's panels: " + names + ")");
    }
    const std::string edge_path = join(side_path, "edge");
    const int e = integer(member(value[k], side_path, "edge", "a stitch side names a panel and an edge"), edge_path,
                          "an edge index");
    const PatternPanel& panel = pattern.panels[std::size_t(p)];
    if (e < 0 || e >= int(panel.edges.size()))
      fail(edge_path, "edge " + text(e) + " out of range (panel " + panel.name + " has " +
                          plural(long(panel.edges.size()), "edge", "edges") + ")");
    stitch.sides[k] = {p, e};
  }
  if (value.size() == 3) {
    if (!value[2].is_string() || value[2].get<std::string>() != "right_wrong")
      fail(at(path, 2), shown(value[2]) + " (allowed: \"right_wrong\", or no third element)");
    stitch.right_wrong = true;
  }
  return stitch;
}

SewingPattern Reader::read(const Json& root) {
  if (!root.is_object()) fail("", "expected a sewing pattern (a JSON object at the top), found " + type_of(root));
  read_properties(root);
  const Json& pattern_json = object(member(root, "", "pattern", "the panels and stitches"), "pattern", "the pattern");
  const Json& panels = object(member(pattern_json, "pattern", "panels", "a pattern has panels"), "pattern.panels",
                              "the panels by name");
  if (panels.empty()) fail("pattern.panels", "the pattern has no panels");
  if (panels.size() > std::size_t(max_pattern_panels))
    fail("pattern.panels", plural(long(panels.size()), "panel", "panels") + " (allowed: at most " +
                               text(max_pattern_panels) + ")");
  SewingPattern pattern;
  for (const auto& [name, panel] : panels.items()) pattern.panels.push_back(read_panel(name, panel, panel_path(name)));
  validate_panels(pattern, m_source, m_options);  // sound panels before the stitches that refer to them

  if (const auto stitches = pattern_json.find("stitches"); stitches != pattern_json.end()) {
    array(*stitches, "pattern.stitches", "the stitches");
    if (stitches->size() > std::size_t(max_pattern_stitches))
      fail("pattern.stitches", plural(long(stitches->size()), "stitch", "stitches") + " (allowed: at most " +
                                   text(max_pattern_stitches) + ")");
    for (std::size_t s = 0; s < stitches->size(); ++s)
      pattern.stitches.push_back(read_stitch(pattern, (*stitches)[s], stitch_path(int(s))));
  }
  validate_stitches(pattern, m_source, m_options);
  return pattern;
}

}  // namespace

SewingPattern parse_sewing_pattern(std::string_view json_text, const std::string& source_name,
                                   const PatternCheckOptions& options) {
  if (json_text.size() > std::size_t(max_pattern_bytes))
    throw PatternError(source_name, "", text(long(json_text.size())) + " bytes (allowed: at most " +
                                            text(max_pattern_bytes) + ")");
  Json root;
  try {
    root = Json::parse(json_text.begin(), json_text.end());
  } catch (const Json::parse_error& e) {
    // nlohmann's message: "[json.exception.parse_error.101] parse error at line 3, column 5: ...".
    std::string message = e.what();
    const std::size_t where = message.find(" at line ");
    message = where == std::string::npos ? ": " + message : message.substr(where);
    throw PatternError(source_name, "", "invalid JSON" + message);
  } catch (const Json::exception& e) {
    // A number out of double's range: "[json.exception.out_of_range.406] number overflow parsing '1e999'",
    // without a place; the place is that of the number's first appearance in the text.
    std::string message = e.what();
    const std::size_t bracket = message.find("] ");
    if (bracket != std::string::npos) message = message.substr(bracket + 2);
    std::string where;
    const std::size_t open = message.find('\''), close = message.rfind('\'');
    if (open != std::string::npos && close > open + 1) {
      const std::size_t at_byte = json_text.find(message.substr(open + 1, close - open - 1));
      if (at_byte != std::string_view::npos) {
        long long line = 1, column = 1;
        for (std::size_t i = 0; i < at_byte; ++i) {
          if (json_text[i] == '\n') {
            ++line;
            column = 1;
          } else {
            ++column;
          }
        }
        where = " at line " + text(line) + ", column " + text(column);
      }
    }
    throw PatternError(source_name, "", "invalid JSON" + where + ": " + message);
  }
  return Reader(source_name, options).read(root);
}

SewingPattern read_sewing_pattern(const std::string& path, const PatternCheckOptions& options) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) throw PatternError(path, "", std::string("cannot open the file (") + std::strerror(errno) + ")");
  std::string content;
  char chunk[1 << 16];
  std::size_t got = 0;
  bool too_big = false;
  while ((got = std::fread(chunk, 1, sizeof chunk, file)) > 0) {
    content.append(chunk, got);
    if (content.size() > std::size_t(max_pattern_bytes)) {
      too_big = true;
      break;
    }
  }
  const bool failed = std::ferror(file) != 0;
  const int error = errno;
  std::fclose(file);
  if (failed) throw PatternError(path, "", std::string("cannot read the file (") + std::strerror(error) + ")");
  if (too_big) throw PatternError(path, "", "more than " + text(max_pattern_bytes) + " bytes");
  return parse_sewing_pattern(content, path, options);
}

}  // namespace drape::pattern_io
