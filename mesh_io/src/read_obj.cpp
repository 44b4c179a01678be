// The OBJ reader: tinyobjloader's callback interface walks the statements in file order; a stream
// buffer over the whole text tells which line each callback comes from, so every error names it.
#include "drape/mesh_io/read_obj.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <map>
#include <streambuf>
#include <string_view>
#include <utility>

namespace drape::mesh_io {

void ObjOptions::validate() const {
  detail::require_positive_finite("ObjOptions::scale", scale);
  detail::require_positive_finite("ObjOptions::uv_scale", uv_scale);
}

namespace {

std::string where(const std::string& path, int line, const std::string& element) {
  std::string out = path;
  if (line > 0) out += ":" + detail::to_text(line);
  if (!element.empty()) out += " (" + element + ")";
  return out;
}

}  // namespace

ObjError::ObjError(std::string path, int line, const std::string& element, std::string value, std::string allowed)
    : InvalidParameter(where(path, line, element), std::move(value), std::move(allowed)),
      m_path(std::move(path)),
      m_line(line) {}

namespace {

/// The lines of the text as tinyobjloader splits them (after "\n", "\r\n" or a lone "\r").
class LineTable {
 public:
  explicit LineTable(const std::string& text) {
    std::size_t begin = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] != '\n' && text[i] != '\r') continue;
      const std::size_t content_end = i;
      if (text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      m_lines.push_back({begin, content_end, i + 1});
      begin = i + 1;
    }
    if (begin < text.size()) m_lines.push_back({begin, text.size(), text.size()});
  }

  /// 1-based number of the line whose end (terminator included) is at `offset`: the line
  /// tinyobjloader has just read when it calls back.
  int line_ending_at(std::size_t offset) const {
    const auto it = std::lower_bound(m_lines.begin(), m_lines.end(), offset,
                                     [](const Line& l, std::size_t o) { return l.end < o; });
    return static_cast<int>(it - m_lines.begin()) + 1;
  }

  /// The text of 1-based line `line` as tinyobjloader sees it: up to its terminator or a NUL.
  std::string_view text(const std::string& all, int line) const {
    const Line& l = m_lines[static_cast<std::size_t>(line - 1)];
    std::string_view s(all.data() + l.begin, l.content_end - l.begin);
    return s.substr(0, s.find('\0'));
  }

 private:
  struct Line {
    std::size_t begin, content_end, end;
  };
  std::vector<Line> m_lines;
};

/// An input buffer over the whole text that tells how much has been read.
class TextBuffer : public std::streambuf {
 public:
  explicit TextBuffer(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
  std::size_t consumed() const { return static_cast<std::size_t>(gptr() - eback()); }
};

/// What tinyobjloader reads as one number: after spaces and tabs, up to a space, tab or CR (parseReal).
std::string_view next_number_token(std::string_view& rest) {
  const std::size_t start = std::min(rest.find_first_not_of(" \t"), rest.size());
  rest.remove_prefix(start);
  const std::size_t length = std::min(rest.find_first_of(" \t\r"), rest.size());
  const std::string_view token = rest.substr(0, length);
  rest.remove_prefix(length);
  return token;
}

/// A decimal number that tinyobjloader reads whole: [+-] digits [. digits] [e [+-] digits], or
/// [+-] . digits [e ...]. tinyobjloader reads "nan", "inf", "0x1p3" or "1.5cm" as 0 or as their
/// numeric start without complaint; these are rejected here.
bool is_whole_number(std::string_view t) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t from = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return i - from;
  };
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  std::size_t mantissa = digits();
  if (i < t.size() && t[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == t.size();
}

std::string quoted(std::string_view token) {
  const std::size_t shown = 40;
  return "'" + std::string(token.substr(0, shown)) + (token.size() > shown ? "...'" : "'");
}

/// A value for a message: nan without the sign the library prints ("-nan").
std::string number_text(double value) { return std::isnan(value) ? "nan" : detail::to_text(value); }

struct Corner {
  int vertex;  ///< 0-based; a positive index is checked against the file's vertices at the end
  int uv;      ///< 0-based texture coordinate, -1 without one
  int vertex_in_file, uv_in_file;  ///< the indices as written, for messages
};

struct Face {
  int first_corner, corners, line;
};

/// An element of the file, e.g. vertex 4 (the fourth `v` line); its text is made only for a message.
struct Element {
  const char* kind;
  std::size_t number;  ///< from 1
  std::string text() const { return std::string(kind) + " " + detail::to_text(number); }
};

std::string corner_text(int k) { return "corner " + detail::to_text(k + 1) + ": "; }

/// The statements of one file as tinyobjloader hands them over, checked as they come.
class ObjParser {
 public:
  ObjParser(std::string name, const ObjOptions& options, std::string& text)
      : m_name(std::move(name)), m_options(options), m_text(text), m_lines(text), m_buffer(text) {}

  void parse() {
    tinyobj::callback_t callback{};
    callback.vertex_cb = [](void* self, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
      static_cast<ObjParser*>(self)->on_vertex(x, y, z);
    };
    callback.texcoord_cb = [](void* self, tinyobj::real_t u, tinyobj::real_t v, tinyobj::real_t) {
      static_cast<ObjParser*>(self)->on_texcoord(u, v);
    };
    callback.index_cb = [](void* self, tinyobj::index_t* corners, int count) {
      static_cast<ObjParser*>(self)->on_face(corners, count);
    };
    callback.group_cb = [](void* self, const char** names, int count) {
      static_cast<ObjParser*>(self)->on_group(names, count);
    };
    callback.object_cb = [](void* self, const char* name) { static_cast<ObjParser*>(self)->on_object(name); };
    std::istream stream(&m_buffer);
    // No material reader: mtllib lines open no file. The callbacks throw ObjError through the loader.
    tinyobj::LoadObjWithCallback(stream, callback, this, nullptr, nullptr, nullptr);
    check_indices();
  }

  /// The mesh in double, not yet checked by ClothMesh::validate(); remembers where its parts come from.
  ClothMesh<double> mesh();

  /// ClothMesh::validate()'s element (after the mesh's name) as a line of the file and an element.
  std::pair<int, std::string> locate(const std::string& element) const;

 private:
  [[noreturn]] void fail(int line, const Element& element, const std::string& value,
                         const std::string& allowed) const {
    throw ObjError(m_name, line, element.text(), value, allowed);
  }

  int current_line() const { return m_lines.line_ending_at(m_buffer.consumed()); }

  /// The first `count` numbers of the current `keyword` line, checked on the text: tinyobjloader
  /// reads a missing or malformed number as 0. `values` are its readings of them.
  void check_numbers(const char* keyword, const Element& element, const double* values, int count,
                     const char* allowed) const {
    const int line = current_line();
    std::string_view rest = m_lines.text(m_text, line);
    rest.remove_prefix(std::min(rest.find_first_not_of(" \t"), rest.size()));
    rest.remove_prefix(std::min(std::strlen(keyword) + 1, rest.size()));
    for (int k = 0; k < count; ++k) {
      const std::string_view token = next_number_token(rest);
      if (token.empty())
        fail(line, element, detail::to_text(k) + " of " + detail::to_text(count) + " numbers", allowed);
      if (!is_whole_number(token)) fail(line, element, "the number " + quoted(token), allowed);
      // Both readings: the standard one overflows to inf where tinyobjloader's exponent arithmetic
      // does not, and tinyobjloader's gives nan for 0e1000.
      const double standard = std::strtod(std::string(token).c_str(), nullptr);
      if (!std::isfinite(standard) || !std::isfinite(values[k]))
        fail(line, element, "the number " + quoted(token) + " (read as " + number_text(values[k]) + ")", allowed);
    }
  }

  void on_vertex(double x, double y, double z) {
    const double xyz[3] = {x, y, z};
    const std::size_t number = m_vertex_lines.size() + 1;
    check_numbers("v", {"vertex", number}, xyz, 3,
                  "x y z as finite numbers (a w and vertex colours after them are ignored)");
    m_positions.insert(m_positions.end(), xyz, xyz + 3);
    m_vertex_lines.push_back(current_line());
  }

  void on_texcoord(double u, double v) {
    if (!m_options.rest_from_uv) return;  // uv only matter as a pattern
    const double uv[2] = {u, v};
    const std::size_t number = m_uv_lines.size() + 1;
    check_numbers("vt", {"texture coordinate", number}, uv, 2,
                  "u v as finite numbers (a w after them is ignored)");
    m_uv.insert(m_uv.end(), uv, uv + 2);
    m_uv_lines.push_back(current_line());
  }

  void on_face(const tinyobj::index_t* corners, int count) {
    const int line = current_line();
    const Element element{"face", m_faces.size() + 1};
    if (count < 3 || count > 4)
      fail(line, element, detail::to_text(count) + (count == 1 ? " corner" : " corners"),
           "3 (a triangle) or 4 (a quad); larger polygons are split into triangles or quads in the modelling tool");
    for (int k = 0; k < count; ++k) {
      const tinyobj::index_t& c = corners[k];
      const int vertex =
          resolve(c.vertex_index, static_cast<int>(m_vertex_lines.size()), "vertex", line, element, k, true);
      // Texture coordinates count only as a pattern; without rest_from_uv their indices are not read.
      const int uv = m_options.rest_from_uv
                         ? resolve(c.texcoord_index, static_cast<int>(m_uv_lines.size()), "texture coordinate",
                                   line, element, k, false)
                         : -1;
      m_corners.push_back({vertex, uv, c.vertex_index, c.texcoord_index});
    }
    const int face = static_cast<int>(m_faces.size());
    m_faces.push_back({static_cast<int>(m_corners.size()) - count, count, line});
    for (const std::string& group : m_active_groups) m_group_faces[group].push_back(face);
    if (!m_object.empty()) m_group_faces[m_object].push_back(face);
  }

  /// The 0-based index of an OBJ index (from 1, or negative: back from the last one defined so far),
  /// -1 for a missing optional one. A positive index past the end is checked in check_indices().
  int resolve(int index, int defined, const char* what, int line, const Element& element, int corner,
              bool required) const {
    if (index > 0) return index - 1;
    if (index == 0) {
      if (!required) return -1;  // tinyobjloader gives 0 for "no texture coordinate"
      fail(line, element, corner_text(corner) + what + " index 0 (or not a number)", range(what, defined));
    }
    if (index < -defined)
      fail(line, element, corner_text(corner) + what + " index " + detail::to_text(index), range(what, defined));
    return defined + index;
  }

  static std::string range(const char* what, int defined_before) {
    std::string out = std::string(what) + " indices from 1 (the first in the file) up";
    if (defined_before > 0)
      out += ", or from -1 (the last before the face) down to -" + detail::to_text(defined_before);
    return out;
  }

  void on_group(const char** names, int count) {
    m_active_groups.assign(names, names + count);
  }

  void on_object(const char* name) {
    // tinyobjloader hands over the rest of the line, spaces included.
    const std::string_view text(name);
    const std::size_t first = text.find_first_not_of(" \t");
    m_object = first == std::string_view::npos
                   ? ""
                   : std::string(text.substr(first, text.find_last_not_of(" \t") + 1 - first));
    m_active_groups.clear();  // a new object starts outside any group
  }

  /// Positive indices against the whole file; with rest_from_uv, a texture coordinate on every
  /// corner and one per vertex.
  void check_indices() const {
    const int vertices = static_cast<int>(m_vertex_lines.size());
    const int uvs = static_cast<int>(m_uv_lines.size());
    std::vector<int> uv_of_vertex(static_cast<std::size_t>(vertices), -1), uv_line(uv_of_vertex.size(), 0);
    for (std::size_t f = 0; f < m_faces.size(); ++f) {
      const Face& face = m_faces[f];
      const Element element{"face", f + 1};
      for (int k = 0; k < face.corners; ++k) {
        const Corner& c = m_corners[static_cast<std::size_t>(face.first_corner + k)];
        const auto corner = [k] { return corner_text(k); };
        if (c.vertex >= vertices)
          fail(face.line, element, corner() + "vertex index " + detail::to_text(c.vertex_in_file),
               vertices == 0 ? "none: the file has no vertices"
                             : "1 to " + detail::to_text(vertices) + " (the file's vertices)");
        if (!m_options.rest_from_uv) continue;
        if (c.uv < 0)
          fail(face.line, element, corner() + "no texture coordinate",
               "v/vt or v/vt/vn on every corner when the rest shape comes from the uv (rest_from_uv)");
        if (c.uv >= uvs)
          fail(face.line, element, corner() + "texture coordinate index " + detail::to_text(c.uv_in_file),
               uvs == 0 ? "none: the file has no texture coordinates"
                        : "1 to " + detail::to_text(uvs) + " (the file's texture coordinates)");
        int& first = uv_of_vertex[static_cast<std::size_t>(c.vertex)];
        if (first < 0) {
          first = c.uv;
          uv_line[static_cast<std::size_t>(c.vertex)] = face.line;
        } else if (!same_uv(first, c.uv)) {
          fail(face.line, element,
               corner() + "vertex " + detail::to_text(c.vertex + 1) + " with uv " + uv_text(c.uv) + " here and " +
                   uv_text(first) + " on line " + detail::to_text(uv_line[static_cast<std::size_t>(c.vertex)]) +
                   " (a seam of the uv layout)",
               "one uv per vertex (a ClothMesh has one pattern point per vertex): split the vertex along the seam "
               "in the file, or read the mesh without rest_from_uv");
        }
      }
    }
  }

  bool same_uv(int a, int b) const {
    return m_uv[2 * std::size_t(a)] == m_uv[2 * std::size_t(b)] &&
           m_uv[2 * std::size_t(a) + 1] == m_uv[2 * std::size_t(b) + 1];
  }

  std::string uv_text(int uv) const {
    return "(" + detail::to_text(m_uv[2 * std::size_t(uv)]) + ", " + detail::to_text(m_uv[2 * std::size_t(uv) + 1]) +
           ")";
  }

  std::string m_name;
  const ObjOptions& m_options;
  std::string& m_text;
  LineTable m_lines;
  TextBuffer m_buffer;

  std::vector<double> m_positions, m_uv;  // 3 and 2 per entry, as read
  std::vector<int> m_vertex_lines, m_uv_lines;
  std::vector<Corner> m_corners;
  std::vector<Face> m_faces;
  std::vector<std::string> m_active_groups;  // names of the last `g` line since the last `o` line
  std::string m_object;                      // name of the last `o` line
  std::map<std::string, std::vector<int>> m_group_faces;

  // Where the mesh's parts come from: the file's face of triangles[t] and quads[q], the texture
  // coordinate of rest_uv[v] (0-based).
  std::vector<int> m_face_of_triangle, m_face_of_quad, m_uv_of_vertex;
};

ClothMesh<double> ObjParser::mesh() {
  ClothMesh<double> mesh;
  const int n = static_cast<int>(m_vertex_lines.size());
  mesh.positions = Eigen::Map<const Matrix3X<double>>(m_positions.data(), 3, n) * m_options.scale;
  m_face_of_triangle.clear();
  m_face_of_quad.clear();
  for (std::size_t f = 0; f < m_faces.size(); ++f) {
    const Face& face = m_faces[f];
    const Corner* c = &m_corners[static_cast<std::size_t>(face.first_corner)];
    if (face.corners == 3) {
      mesh.triangles.push_back({c[0].vertex, c[1].vertex, c[2].vertex});
      m_face_of_triangle.push_back(static_cast<int>(f));
    } else {
      mesh.quads.push_back({c[0].vertex, c[1].vertex, c[2].vertex, c[3].vertex});
      m_face_of_quad.push_back(static_cast<int>(f));
    }
  }
  if (m_options.rest_from_uv) {
    // A vertex of no face keeps (0, 0): no face measures its rest shape.
    mesh.rest_uv = Matrix2X<double>::Zero(2, n);
    m_uv_of_vertex.assign(static_cast<std::size_t>(n), -1);
    for (const Corner& c : m_corners) {
      mesh.rest_uv.col(c.vertex) = m_options.uv_scale * Eigen::Vector2d(m_uv[2 * std::size_t(c.uv)],
                                                                         m_uv[2 * std::size_t(c.uv) + 1]);
      m_uv_of_vertex[static_cast<std::size_t>(c.vertex)] = c.uv;
    }
  }
  for (const auto& [group, faces] : m_group_faces) {
    std::vector<int>& vertices = mesh.groups[group];
    for (int f : faces) {
      const Face& face = m_faces[static_cast<std::size_t>(f)];
      for (int k = 0; k < face.corners; ++k)
        vertices.push_back(m_corners[static_cast<std::size_t>(face.first_corner + k)].vertex);
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  }
  return mesh;
}

/// Reads validate()'s `triangles[7]`-style element: the name and the index.
bool split_element(const std::string& element, std::string& name, int& index) {
  const std::size_t open = element.find('[');
  if (open == std::string::npos || element.back() != ']') return false;
  name = element.substr(0, open);
  index = std::atoi(element.c_str() + open + 1);
  return true;
}

std::pair<int, std::string> ObjParser::locate(const std::string& element) const {
  std::string kind;
  int index = 0;
  if (!split_element(element, kind, index) || index < 0) return {0, element};
  const auto face = [&](const std::vector<int>& face_of, int k) -> std::pair<int, std::string> {
    if (k >= static_cast<int>(face_of.size())) return {0, element};
    const int f = face_of[static_cast<std::size_t>(k)];
    return {m_faces[static_cast<std::size_t>(f)].line, "face " + detail::to_text(f + 1) + ": " + element};
  };
  if (kind == "triangles") return face(m_face_of_triangle, index);
  if (kind == "quads") return face(m_face_of_quad, index);
  if (index >= static_cast<int>(m_vertex_lines.size())) return {0, element};
  if (kind == "positions")
    return {m_vertex_lines[static_cast<std::size_t>(index)], "vertex " + detail::to_text(index + 1) + ": " + element};
  if (kind == "rest_uv" && index < static_cast<int>(m_uv_of_vertex.size())) {
    const int uv = m_uv_of_vertex[static_cast<std::size_t>(index)];
    if (uv >= 0)
      return {m_uv_lines[static_cast<std::size_t>(uv)],
              "texture coordinate " + detail::to_text(uv + 1) + ": " + element};
  }
  return {0, element};
}

template <class Scalar>
ClothMesh<Scalar> converted(ClothMesh<double> mesh) {
  if constexpr (std::is_same_v<Scalar, double>) {
    return mesh;
  } else {
    ClothMesh<Scalar> out;
    out.positions = mesh.positions.cast<Scalar>();
    out.triangles = std::move(mesh.triangles);
    out.quads = std::move(mesh.quads);
    out.rest_uv = mesh.rest_uv.cast<Scalar>();
    out.groups = std::move(mesh.groups);
    return out;
  }
}

template <class Scalar>
MeshRead<Scalar> read_text(std::string text, const std::string& name, const ObjOptions& options) {
  options.validate();
  ObjParser parser(name, options, text);
  parser.parse();
  MeshRead<Scalar> read;
  read.mesh = converted<Scalar>(parser.mesh());
  try {
    read.warnings = read.mesh.validate(name);
  } catch (const InvalidParameter& e) {
    // validate() names the element after the mesh's name: put the file's line to it.
    const std::string& parameter = e.parameter();
    const bool ours = parameter.compare(0, name.size(), name) == 0;
    std::string element = ours ? parameter.substr(name.size()) : parameter;
    if (!element.empty() && element[0] == '.') element.erase(0, 1);
    if (element.empty()) element = "mesh";
    const auto [line, located] = parser.locate(element);
    throw ObjError(name, line, located, e.value(), e.allowed());
  }
  return read;
}

std::string file_text(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file)
    throw ObjError(path, 0, "", std::string("a file that cannot be opened (") + std::strerror(errno) + ")",
                   "a readable OBJ file");
  std::string text;
  char chunk[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(chunk, 1, sizeof chunk, file)) > 0) text.append(chunk, got);
  const bool failed = std::ferror(file) != 0;
  const int error = errno;
  std::fclose(file);
  if (failed)
    throw ObjError(path, 0, "", std::string("a file that cannot be read (") + std::strerror(error) + ")",
                   "a readable OBJ file");
  return text;
}

}  // namespace

template <class Scalar>
MeshRead<Scalar> read_obj(const std::string& path, const ObjOptions& options) {
  options.validate();
  return read_text<Scalar>(file_text(path), path, options);
}

template <class Scalar>
MeshRead<Scalar> parse_obj(const std::string& text, const std::string& name, const ObjOptions& options) {
  return read_text<Scalar>(text, name, options);
}

template MeshRead<float> read_obj<float>(const std::string&, const ObjOptions&);
template MeshRead<double> read_obj<double>(const std::string&, const ObjOptions&);
template MeshRead<float> parse_obj<float>(const std::string&, const std::string&, const ObjOptions&);
template MeshRead<double> parse_obj<double>(const std::string&, const std::string&, const ObjOptions&);

}  // namespace drape::mesh_io
