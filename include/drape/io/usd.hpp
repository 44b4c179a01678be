#pragma once
/// \file usd.hpp
/// An animation of meshes as one USD text file (`.usda`), for Blender, Omniverse and the other
/// tools that read Universal Scene Description. Each mesh keeps its faces for the whole animation
/// and has its points (and its bounding box, `extent`) time-sampled, one sample per frame:
/// \code
///   #usda 1.0
///   (
///       defaultPrim = "drape"
///       endTimeCode = 2
///       framesPerSecond = 30
///       metersPerUnit = 1
///       startTimeCode = 0
///       timeCodesPerSecond = 30
///       upAxis = "Y"
///   )
///
///   def Xform "drape"
///   {
///       def Mesh "cloth"
///       {
///           uniform bool doubleSided = true
///           float3[] extent.timeSamples = {
///               0: [(-1, 0, -1), (1, 0, 1)],
///               ...
///           }
///           int[] faceVertexCounts = [3, 3]
///           int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]
///           point3f[] points.timeSamples = {
///               0: [(-1, 0, -1), (1, 0, -1), (1, 0, 1), (-1, 0, 1)],
///               ...
///           }
///           uniform token subdivisionScheme = "none"
///       }
///   }
/// \endcode
/// Frame k is time code k; `timeCodesPerSecond` is the frame rate. Coordinates are USD's `point3f`,
/// single precision, printed with 9 significant digits, which read back to the same float. A mesh
/// whose points are the same in every frame (a collider at rest) has them once, as `points` and
/// `extent` without time samples, which hold at every time code.
///
/// Memory stays at one frame whatever the length of the animation: each finished frame goes, as
/// floats, to a temporary file beside the target (unlinked at once on POSIX systems, so nothing is
/// left behind), and finish() assembles the file from it, atomically (atomic_file.hpp): a failed
/// or unfinished writer leaves no file and an earlier file of that name untouched.

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <sys/types.h>
#endif

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/io/atomic_file.hpp"

namespace drape {

/// How a viewer shows a mesh; no effect on its geometry.
struct UsdMeshLook {
  bool double_sided = true;  ///< both sides drawn (cloth); false: back faces culled (closed solids)
  std::optional<std::array<float, 3>> display_color;  ///< linear RGB in [0, 1]; unset: the viewer's default
};

/// `name` made a valid USD prim name: letters, digits and `_`, not starting with a digit
/// (every other character becomes `_`; an empty name becomes `mesh`).
inline std::string usd_identifier(const std::string& name) {
  std::string id = name.empty() ? std::string("mesh") : name;
  for (char& c : id) {
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    if (!letter && !(c >= '0' && c <= '9')) c = '_';
  }
  if (id[0] >= '0' && id[0] <= '9') id.insert(id.begin(), '_');
  return id;
}

/// Writes meshes of fixed faces with moving points as one `.usda` file: add_mesh() for each mesh,
/// then for every frame set_points() of each mesh and end_frame(), then finish().
class UsdAnimationWriter {
 public:
  /// \param path the `.usda` file finish() writes.
  /// \param frames_per_second the frame rate (`timeCodesPerSecond`), finite and > 0.
  /// \param root_name the `Xform` that holds the meshes, the file's default prim (made a valid name).
  /// \throws InvalidParameter for a bad frame rate; FileWriteError if the temporary file beside
  /// `path` cannot be created (the folder is missing or not writable).
  UsdAnimationWriter(std::string path, double frames_per_second, const std::string& root_name = "drape")
      : m_path(std::move(path)), m_fps(frames_per_second), m_root(usd_identifier(root_name)) {
    detail::require_positive_finite("usd frames_per_second", frames_per_second);
    const std::string samples = m_path + ".samples.tmp";
    m_samples = std::fopen(samples.c_str(), "w+b");
    if (!m_samples)
      throw FileWriteError("cannot write '" + m_path + "': cannot create '" + samples + "': " + std::strerror(errno));
#if defined(__unix__) || defined(__APPLE__)
    std::remove(samples.c_str());  // the open file stays readable and vanishes with it
#else
    m_samples_path = samples;
#endif
  }

  ~UsdAnimationWriter() {
    if (m_samples) std::fclose(m_samples);
    if (!m_samples_path.empty()) std::remove(m_samples_path.c_str());
  }
  UsdAnimationWriter(const UsdAnimationWriter&) = delete;
  UsdAnimationWriter& operator=(const UsdAnimationWriter&) = delete;

  /// Adds a mesh of `point_count` points and polygonal faces: face f has `face_vertex_counts[f]`
  /// (>= 3) corners, the next ones of `face_vertex_indices` (0-based point ids). Before the first
  /// frame only. \returns the mesh's id for set_points().
  /// \throws InvalidParameter naming the mesh for a face that does not fit the points.
  int add_mesh(const std::string& name, Index point_count, std::vector<int> face_vertex_counts,
               std::vector<int> face_vertex_indices, const UsdMeshLook& look = {}) {
    if (m_frames > 0 || m_frame_started) throw std::logic_error("UsdAnimationWriter: add_mesh() after the first frame");
    const std::string what = "usd mesh '" + name + "'";
    if (point_count < 1 || point_count > std::numeric_limits<int>::max())
      detail::fail_argument(what + " point count", std::to_string(point_count), "[1, 2^31 - 1]");
    std::size_t corners = 0;
    for (std::size_t f = 0; f < face_vertex_counts.size(); ++f) {
      if (face_vertex_counts[f] < 3)
        detail::fail_argument(what + " face " + std::to_string(f) + " corners", std::to_string(face_vertex_counts[f]),
                              ">= 3");
      corners += std::size_t(face_vertex_counts[f]);
    }
    if (corners != face_vertex_indices.size())
      detail::fail_argument(what + " face vertex indices", std::to_string(face_vertex_indices.size()) + " indices",
                            std::to_string(corners) + " (the sum of the faces' corner counts)");
    for (std::size_t k = 0; k < face_vertex_indices.size(); ++k)
      if (face_vertex_indices[k] < 0 || face_vertex_indices[k] >= point_count)
        detail::fail_argument(what + " face vertex index " + std::to_string(k), std::to_string(face_vertex_indices[k]),
                              "[0, " + std::to_string(point_count - 1) + "]");
    Mesh mesh;
    mesh.name = unique_name(usd_identifier(name));
    mesh.offset = m_frame_floats;
    mesh.point_count = point_count;
    mesh.counts = std::move(face_vertex_counts);
    mesh.indices = std::move(face_vertex_indices);
    mesh.look = look;
    m_frame_floats += 3 * std::size_t(point_count);
    m_meshes.push_back(std::move(mesh));
    return int(m_meshes.size()) - 1;
  }

  /// A triangle mesh (0-based corner ids), as add_mesh() above.
  int add_mesh(const std::string& name, Index point_count, const std::vector<std::array<int, 3>>& triangles,
               const UsdMeshLook& look = {}) {
    std::vector<int> indices;
    indices.reserve(3 * triangles.size());
    for (const std::array<int, 3>& t : triangles) indices.insert(indices.end(), t.begin(), t.end());
    return add_mesh(name, point_count, std::vector<int>(triangles.size(), 3), std::move(indices), look);
  }

  /// The mesh's prim name in the file: its name made a valid identifier, unique among the meshes
  /// (`cloth`, `cloth_1`, ...).
  const std::string& mesh_name(int mesh) const { return m_meshes.at(std::size_t(mesh)).name; }
  int mesh_count() const { return int(m_meshes.size()); }
  /// Frames ended so far.
  int frame_count() const { return m_frames; }
  const std::string& path() const { return m_path; }

  /// The points of `mesh` in the current frame: `3 x n` (a Matrix3X, a Map, any Eigen expression),
  /// n its point count.
  /// \throws InvalidParameter for the wrong number of points or a coordinate that is not finite
  /// or does not fit a float (beyond 3.4e38); the mesh has no points in the frame then.
  template <class Derived>
  void set_points(int mesh, const Eigen::MatrixBase<Derived>& points) {
    static_assert(Derived::RowsAtCompileTime == 3 || Derived::RowsAtCompileTime == Eigen::Dynamic,
                  "set_points: points must be 3 x n");
    Mesh& m = m_meshes.at(std::size_t(mesh));
    const std::string what = "usd mesh '" + m.name + "'";
    if (points.rows() != 3 || points.cols() != m.point_count)
      detail::fail_argument(what + " points",
                            std::to_string(points.rows()) + " x " + std::to_string(points.cols()),
                            "3 x " + std::to_string(m.point_count));
    if (!m_frame_started) {
      m_frame.assign(m_frame_floats, 0.0f);
      m_set.assign(m_meshes.size(), false);
      m_frame_started = true;
    }
    float* out = m_frame.data() + m.offset;
    for (Index i = 0; i < points.cols(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double v = double(points(c, i));
        if (!(std::abs(v) <= double(std::numeric_limits<float>::max())))  // NaN too
          detail::fail_argument(what + " points", "point " + std::to_string(i) + " of frame " +
                                                      std::to_string(m_frames) + " = (" + coordinates(points, i) + ")",
                                "finite coordinates that fit a float (|x| <= 3.4e38)");
        out[3 * i + c] = static_cast<float>(v);
      }
    m_set[std::size_t(mesh)] = true;
  }

  /// Ends the frame: every mesh must have its points.
  /// \throws std::logic_error if a mesh has none; FileWriteError if the temporary file cannot be written.
  void end_frame() {
    if (m_meshes.empty()) throw std::logic_error("UsdAnimationWriter: end_frame() without meshes");
    for (std::size_t k = 0; k < m_meshes.size(); ++k)
      if (!m_frame_started || !m_set[k])
        throw std::logic_error("UsdAnimationWriter: frame " + std::to_string(m_frames) + " has no points for mesh '" +
                               m_meshes[k].name + "'");
    if (std::fwrite(m_frame.data(), sizeof(float), m_frame.size(), m_samples) != m_frame.size())
      throw FileWriteError("cannot write '" + m_path + "': its temporary samples: " + std::strerror(errno));
    for (Mesh& m : m_meshes) {
      std::array<float, 6> box{};
      const float* p = m_frame.data() + m.offset;
      for (int c = 0; c < 3; ++c) box[std::size_t(c)] = box[std::size_t(c + 3)] = p[c];
      for (Index i = 1; i < m.point_count; ++i)
        for (int c = 0; c < 3; ++c) {
          box[std::size_t(c)] = std::min(box[std::size_t(c)], p[3 * i + c]);
          box[std::size_t(c + 3)] = std::max(box[std::size_t(c + 3)], p[3 * i + c]);
        }
      m.extents.push_back(box);
      if (m_frames == 0)
        m.first.assign(p, p + 3 * m.point_count);
      else
        m.still = m.still && std::memcmp(m.first.data(), p, m.first.size() * sizeof(float)) == 0;
    }
    m_frame_started = false;
    ++m_frames;
  }

  /// Writes the file: every mesh with its faces and one sample per frame ended, time codes
  /// 0 .. frame_count() - 1. A frame begun with set_points() but not ended is left out.
  /// \throws std::logic_error without meshes or frames; FileWriteError if the file cannot be
  /// written (then no file is created or changed).
  void finish() {
    if (m_meshes.empty() || m_frames == 0)
      throw std::logic_error("UsdAnimationWriter: finish() needs a mesh and a frame");
    if (std::fflush(m_samples) != 0)
      throw FileWriteError("cannot write '" + m_path + "': its temporary samples: " + std::strerror(errno));
    write_file_atomically(m_path, [&](std::FILE* f) { return write_usda(f); });
  }

 private:
  struct Mesh {
    std::string name;
    std::size_t offset = 0;  // of its points in a frame, in floats
    Index point_count = 0;
    std::vector<int> counts, indices;
    UsdMeshLook look;
    std::vector<std::array<float, 6>> extents;  // per frame: min xyz, max xyz
    std::vector<float> first;                   // its points in frame 0
    bool still = true;                          // every frame's points are frame 0's, bit for bit
  };

  std::string unique_name(const std::string& base) const {
    const auto taken = [&](const std::string& n) {
      return std::any_of(m_meshes.begin(), m_meshes.end(), [&](const Mesh& m) { return m.name == n; });
    };
    std::string name = base;
    for (int k = 1; taken(name); ++k) name = base + "_" + std::to_string(k);
    return name;
  }

  template <class Derived>
  static std::string coordinates(const Eigen::MatrixBase<Derived>& points, Index i) {
    return detail::to_text(double(points(0, i))) + ", " + detail::to_text(double(points(1, i))) + ", " +
           detail::to_text(double(points(2, i)));
  }

  /// Appends `(x, y, z)` with 9 significant digits (a float's max_digits10).
  static void append_point(std::string& out, const float* p) {
    char text[64];
    const int n = std::snprintf(text, sizeof text, "(%.9g, %.9g, %.9g)", double(p[0]), double(p[1]), double(p[2]));
    out.append(text, std::size_t(n));
  }

  /// Moves to byte `at` (beyond 2 GB too where `long` has 32 bits, on POSIX systems).
  static bool seek(std::FILE* f, std::size_t at) {
#if defined(__unix__) || defined(__APPLE__)
    return ::fseeko(f, off_t(at), SEEK_SET) == 0;
#else
    return at <= std::size_t(std::numeric_limits<long>::max()) && std::fseek(f, long(at), SEEK_SET) == 0;
#endif
  }

  static bool put(std::FILE* f, const std::string& text) {
    return std::fwrite(text.data(), 1, text.size(), f) == text.size();
  }

  static bool put_ints(std::FILE* f, const char* prefix, const std::vector<int>& values) {
    std::string line = prefix;
    line += '[';
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (k > 0) line += ", ";
      line += std::to_string(values[k]);
    }
    line += "]\n";
    return put(f, line);
  }

  static std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.15g", v);
    return text;
  }

  /// Appends `[(x, y, z), ...]`: `n` points.
  static void append_points(std::string& out, const float* p, Index n) {
    out += '[';
    for (Index i = 0; i < n; ++i) {
      if (i > 0) out += ", ";
      append_point(out, p + 3 * i);
    }
    out += ']';
  }

  /// The lines `t: [...],` of `m`'s points in every frame, read back from the temporary file.
  bool write_samples(std::FILE* f, const Mesh& m) {
    std::vector<float> points(3 * std::size_t(m.point_count));
    std::string line;
    for (int t = 0; t < m_frames; ++t) {
      if (!seek(m_samples, (std::size_t(t) * m_frame_floats + m.offset) * sizeof(float)) ||
          std::fread(points.data(), sizeof(float), points.size(), m_samples) != points.size())
        return false;
      line = "            " + std::to_string(t) + ": ";
      append_points(line, points.data(), m.point_count);
      line += ",\n";
      if (!put(f, line)) return false;
    }
    return true;
  }

  bool write_usda(std::FILE* f) {
    const std::string indent = "        ", sample = indent + "    ";
    std::string head = "#usda 1.0\n(\n";
    head += "    defaultPrim = \"" + m_root + "\"\n";
    head += "    endTimeCode = " + std::to_string(m_frames - 1) + "\n";
    head += "    framesPerSecond = " + number(m_fps) + "\n";
    head += "    metersPerUnit = 1\n";
    head += "    startTimeCode = 0\n";
    head += "    timeCodesPerSecond = " + number(m_fps) + "\n";
    head += "    upAxis = \"Y\"\n)\n\ndef Xform \"" + m_root + "\"\n{\n";
    if (!put(f, head)) return false;
    std::string line;
    for (std::size_t k = 0; k < m_meshes.size(); ++k) {
      const Mesh& m = m_meshes[k];
      line = (k > 0 ? "\n" : "") + std::string("    def Mesh \"") + m.name + "\"\n    {\n";
      line += indent + "uniform bool doubleSided = " + (m.look.double_sided ? "true" : "false") + "\n";
      if (m.still) {  // one value for every time code
        line += indent + "float3[] extent = ";
        append_points(line, m.extents[0].data(), 2);
        line += "\n";
      } else {
        line += indent + "float3[] extent.timeSamples = {\n";
        for (int t = 0; t < m_frames; ++t) {
          line += sample + std::to_string(t) + ": ";
          append_points(line, m.extents[std::size_t(t)].data(), 2);
          line += ",\n";
        }
        line += indent + "}\n";
      }
      if (!put(f, line) || !put_ints(f, (indent + "int[] faceVertexCounts = ").c_str(), m.counts) ||
          !put_ints(f, (indent + "int[] faceVertexIndices = ").c_str(), m.indices))
        return false;
      if (m.still) {
        line = indent + "point3f[] points = ";
        append_points(line, m.first.data(), m.point_count);
        line += "\n";
      } else {
        if (!put(f, indent + "point3f[] points.timeSamples = {\n")) return false;
        if (!write_samples(f, m)) return false;
        line = indent + "}\n";
      }
      if (m.look.display_color) {
        const std::array<float, 3>& c = *m.look.display_color;
        char colour[96];
        std::snprintf(colour, sizeof colour, "color3f[] primvars:displayColor = [(%g, %g, %g)]\n", double(c[0]),
                      double(c[1]), double(c[2]));
        line += indent + colour;
      }
      line += indent + "uniform token subdivisionScheme = \"none\"\n    }\n";
      if (!put(f, line)) return false;
    }
    return put(f, "}\n");
  }

  std::string m_path;
  double m_fps;
  std::string m_root;
  std::FILE* m_samples = nullptr;
  std::string m_samples_path;  // removed by the destructor where it could not be unlinked at once
  std::vector<Mesh> m_meshes;
  std::size_t m_frame_floats = 0;  // floats of one frame: 3 per point of every mesh
  std::vector<float> m_frame;      // the frame being set
  std::vector<bool> m_set;         // which meshes have their points in it
  bool m_frame_started = false;
  int m_frames = 0;
};

}  // namespace drape
