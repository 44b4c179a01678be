#pragma once
/// \file read_obj.hpp
/// A cloth mesh (core/cloth_mesh.hpp) read from a Wavefront OBJ file through tinyobjloader
/// (docs/mesh.md, "Meshes from OBJ files").
///
/// - `v x y z`: the vertices, in file order (mesh vertex k is the file's vertex k + 1), times
///   `ObjOptions::scale`. A w and vertex colours after x y z are ignored.
/// - `f`: triangles and quads, corners counter-clockwise seen from the front. A face of fewer than 3
///   or more than 4 corners is an error: larger polygons are not triangulated (a fan over a concave
///   polygon folds over itself), the modelling tool splits them.
/// - `vt u v` with `ObjOptions::rest_from_uv`: the rest shape is the flat pattern (u, v) times
///   `uv_scale` (ClothMesh::rest_uv). A vertex with different uv in two faces (a seam of the uv
///   layout) is an error: a ClothMesh has one pattern point per vertex, and splitting the vertex
///   would cut the cloth apart along the seam.
/// - `g` and `o`: each name is a group of ClothMesh::groups holding the vertices of its faces.
/// - Normals, lines, points, materials and smoothing groups are ignored; no other file is opened.
///
/// Every defect throws ObjError (an InvalidParameter) naming the file, the line and the element;
/// no mesh is returned in part. The mesh passes ClothMesh::validate(), whose warnings come back with it.

#include <string>
#include <vector>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/validation.hpp"

namespace drape::mesh_io {

struct ObjOptions {
  /// Metres per file unit: positions are the file's coordinates times `scale`. Finite and > 0.
  double scale = 1;
  /// Take the rest shape from the `vt` coordinates (a flat pattern) instead of the positions.
  bool rest_from_uv = false;
  /// Metres per uv unit of the pattern (with rest_from_uv). Finite and > 0.
  double uv_scale = 1;

  /// \throws InvalidParameter (`ObjOptions::scale`, `ObjOptions::uv_scale`).
  void validate() const;
};

/// A defect of an OBJ file. parameter() is `PATH:LINE (ELEMENT)`, e.g. `shirt.obj:12 (face 3)`,
/// or `PATH (ELEMENT)` / `PATH` when no line holds the defect (an empty mesh, a file that cannot be read).
/// Elements count as the file does, from 1: `vertex 4` is the fourth `v` line, `face 3` the third `f`
/// line; where the mesh checks of ClothMesh::validate() found it, the mesh's name for it follows
/// (`face 3: quads[1]`) and the value's vertex ids are the mesh's, from 0.
class ObjError : public InvalidParameter {
 public:
  ObjError(std::string path, int line, const std::string& element, std::string value, std::string allowed);

  const std::string& path() const { return m_path; }
  /// 1-based line of the defect, 0 when it belongs to no line.
  int line() const { return m_line; }

 private:
  std::string m_path;
  int m_line;
};

/// The mesh read and the warnings of its checks (e.g. vertices that belong to no face).
template <class Scalar = double>
struct MeshRead {
  ClothMesh<Scalar> mesh;
  std::vector<std::string> warnings;
};

/// The mesh of the OBJ file `path` (Scalar: float or double). tinyobjloader reads the coordinates
/// in its own precision (double in Debian's tinyobjloader_double build), converted to Scalar after.
/// \throws ObjError for a file that cannot be read or holds a defect (docs/mesh.md lists them),
///   InvalidParameter for bad `options`.
template <class Scalar = double>
MeshRead<Scalar> read_obj(const std::string& path, const ObjOptions& options = {});

/// The mesh of OBJ text held in memory; `name` stands for the file in messages.
template <class Scalar = double>
MeshRead<Scalar> parse_obj(const std::string& text, const std::string& name, const ObjOptions& options = {});

}  // namespace drape::mesh_io
