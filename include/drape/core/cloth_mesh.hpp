#pragma once
/// \file cloth_mesh.hpp
/// A cloth as a surface mesh: vertices, faces and a rest shape. A cloth built from it
/// (model/cloth.hpp) takes its springs from the faces (core/spring_set.hpp) and its masses from a
/// uniform vertex mass or from the rest area times an areal density.
///
/// - Faces: triangles and quads. A quad's diagonals carry shear springs; anywhere else (collision,
///   rendering, bending) a quad counts as its two triangles (0, 1, 2) and (0, 2, 3). The corners of
///   every face run counter-clockwise seen from the mesh's front side.
/// - Rest shape: the mesh as given (3D), or 2D pattern coordinates per vertex (`rest_uv`, metres):
///   a flat panel laid out in space, its rest lengths from the pattern and its start from
///   `positions`.
/// - Lattice: the grid generator (core/mesh_generators.hpp) marks its meshes, and a cloth made of
///   such a mesh takes the grid's springs in the grid's order and its fast paths (grouped edge
///   products, geometric multigrid), so it steps bit for bit as the grid cloth does.
///
/// validate() rejects what no cloth can be made of, naming the element: an empty mesh, a vertex
/// id out of range, a non-finite coordinate, a degenerate (zero-area) face, an edge of more than
/// two faces (non-manifold), two faces that run an edge the same way (inconsistent orientation).
/// Vertices no face uses are allowed and reported as warnings (a cloth holds them where they are).

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar>
using Matrix2X = Eigen::Matrix<Scalar, 2, Eigen::Dynamic>;

/// The shape of a mesh made by grid_mesh(): nx x ny vertices `spacing` apart, grid.hpp's numbering.
template <class Scalar = double>
struct LatticeShape {
  int nx = 0;
  int ny = 0;
  Scalar spacing = Scalar(0);
};

/// An interior edge (a, b) of the triangulated mesh with the two triangles on either side:
/// (a, b, c) and (b, a, d), both counter-clockwise. Bending acts across it.
struct Hinge {
  int a, b;  ///< the shared edge, as triangle (a, b, c) runs it
  int c;     ///< the vertex opposite the edge in triangle (a, b, c)
  int d;     ///< the vertex opposite the edge in triangle (b, a, d)
};

template <class Scalar = double>
struct ClothMesh {
  /// m, 3 x n: where the vertices start (the cloth's placement moves and turns them as a whole).
  Matrix3X<Scalar> positions;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 4>> quads;
  /// m, 2 x n pattern coordinates: the rest shape is flat with these coordinates. Empty: the rest
  /// shape is `positions`.
  Matrix2X<Scalar> rest_uv;
  /// Named sets of vertices (an OBJ file's groups), e.g. for pins.
  std::map<std::string, std::vector<int>> groups;
  /// Set by grid_mesh() only.
  std::optional<LatticeShape<Scalar>> lattice;

  int vertex_count() const { return static_cast<int>(positions.cols()); }
  /// Triangles, then each quad's two triangles (0, 1, 2) and (0, 2, 3).
  std::vector<std::array<int, 3>> all_triangles() const;
  /// The rest shape, 3 x n: `positions`, or (u, v, 0) per vertex when `rest_uv` is set.
  Matrix3X<Scalar> rest_shape() const;
  /// m^2: a third of the rest area of every triangle around each vertex.
  VectorX<Scalar> vertex_areas() const;
  /// The interior edges of all_triangles() with their opposite vertices, in the order their first
  /// triangle appears. Meaningful on a mesh that passes validate().
  std::vector<Hinge> hinges() const;
  /// Name of face k of all_triangles() for messages: `triangles[k]` or `quads[q]`.
  std::string face_name(int k) const;

  /// \throws InvalidParameter whose parameter is `name` followed by the element (e.g.
  /// `mesh.triangles[17]`, `mesh.positions[3]`) for the first defect of the file comment.
  /// \returns one warning per kind of harmless oddity (unused vertices).
  std::vector<std::string> validate(const std::string& name = "mesh") const;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
std::vector<std::array<int, 3>> ClothMesh<Scalar>::all_triangles() const {
  std::vector<std::array<int, 3>> out = triangles;
  out.reserve(triangles.size() + 2 * quads.size());
  for (const std::array<int, 4>& q : quads) {
    out.push_back({q[0], q[1], q[2]});
    out.push_back({q[0], q[2], q[3]});
  }
  return out;
}

template <class Scalar>
Matrix3X<Scalar> ClothMesh<Scalar>::rest_shape() const {
  if (rest_uv.cols() == 0) return positions;
  Matrix3X<Scalar> x = Matrix3X<Scalar>::Zero(3, rest_uv.cols());
  x.topRows(2) = rest_uv;
  return x;
}

template <class Scalar>
VectorX<Scalar> ClothMesh<Scalar>::vertex_areas() const {
  const Matrix3X<Scalar> x = rest_shape();
  VectorX<Scalar> area = VectorX<Scalar>::Zero(vertex_count());
  for (const std::array<int, 3>& t : all_triangles()) {
    const Vec3<Scalar> e1 = x.col(t[1]) - x.col(t[0]), e2 = x.col(t[2]) - x.col(t[0]);
    const Scalar third = e1.cross(e2).norm() / Scalar(6);
    for (int v : t) area[v] += third;
  }
  return area;
}

template <class Scalar>
std::string ClothMesh<Scalar>::face_name(int k) const {
  const int t = static_cast<int>(triangles.size());
  if (k < t) return "triangles[" + detail::to_text(k) + "]";
  return "quads[" + detail::to_text((k - t) / 2) + "]";
}

namespace detail {
/// Key of the undirected edge {a, b}.
inline long long edge_key(int a, int b) {
  const long long lo = std::min(a, b), hi = std::max(a, b);
  return (hi << 32) | lo;
}
}  // namespace detail

template <class Scalar>
std::vector<Hinge> ClothMesh<Scalar>::hinges() const {
  const std::vector<std::array<int, 3>> tris = all_triangles();
  // First triangle and its corner opposite the edge, per undirected edge.
  struct Side {
    int a, b, opposite;
    int hinge = -1;
  };
  std::unordered_map<long long, Side> first;
  first.reserve(3 * tris.size());
  std::vector<Hinge> out;
  for (const std::array<int, 3>& t : tris)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
      auto [it, inserted] = first.try_emplace(detail::edge_key(a, b), Side{a, b, c});
      if (inserted || it->second.hinge >= 0) continue;
      it->second.hinge = static_cast<int>(out.size());
      out.push_back(Hinge{it->second.a, it->second.b, it->second.opposite, c});
    }
  return out;
}

template <class Scalar>
std::vector<std::string> ClothMesh<Scalar>::validate(const std::string& name) const {
  const int n = vertex_count();
  const std::vector<std::array<int, 3>> tris = all_triangles();
  if (n == 0 || tris.empty())
    detail::fail_argument(name, detail::to_text(n) + " vertices and " + detail::to_text(tris.size()) + " triangles",
                          "a mesh with at least one face");
  for (int v = 0; v < n; ++v)
    if (!positions.col(v).allFinite())
      detail::fail_argument(name + ".positions[" + detail::to_text(v) + "]", "a non-finite coordinate",
                            "finite coordinates (m)");
  if (rest_uv.cols() != 0) {
    if (rest_uv.cols() != n)
      detail::fail_argument(name + ".rest_uv", detail::to_text(rest_uv.cols()) + " columns",
                            "none, or one per vertex (" + detail::to_text(n) + ")");
    for (int v = 0; v < n; ++v)
      if (!rest_uv.col(v).allFinite())
        detail::fail_argument(name + ".rest_uv[" + detail::to_text(v) + "]", "a non-finite coordinate",
                              "finite coordinates (m)");
  }
  // Messages are made only when a check fails: a large mesh has millions of elements.
  const auto check_ids = [&](const char* kind, std::size_t face, const int* ids, int count) {
    const auto where = [&] { return name + "." + kind + "[" + detail::to_text(face) + "]"; };
    for (int k = 0; k < count; ++k) {
      if (ids[k] < 0 || ids[k] >= n)
        detail::fail_argument(where(), "vertex id " + detail::to_text(ids[k]),
                              "vertex ids in [0, " + detail::to_text(n - 1) + "]");
      for (int l = 0; l < k; ++l)
        if (ids[l] == ids[k])
          detail::fail_argument(where(), "vertex " + detail::to_text(ids[k]) + " twice", "distinct corners");
    }
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) check_ids("triangles", t, triangles[t].data(), 3);
  for (std::size_t q = 0; q < quads.size(); ++q) check_ids("quads", q, quads[q].data(), 4);

  // Degenerate faces, measured in the rest shape and in the start positions: zero area relative to
  // the squared longest edge (a sliver this thin has no usable stiffness).
  const Matrix3X<Scalar> rest = rest_shape();
  const Scalar tiny = std::is_same<Scalar, float>::value ? Scalar(1e-6) : Scalar(1e-12);
  for (std::size_t k = 0; k < tris.size(); ++k)
    for (const Matrix3X<Scalar>* x : {&rest, &positions}) {
      const std::array<int, 3>& t = tris[k];
      const Vec3<Scalar> e0 = x->col(t[1]) - x->col(t[0]), e1 = x->col(t[2]) - x->col(t[1]),
                         e2 = x->col(t[0]) - x->col(t[2]);
      const Scalar longest = std::max({e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()});
      if (!(e0.cross(e1).norm() > tiny * longest))
        detail::fail_argument(name + "." + face_name(static_cast<int>(k)),
                              std::string("a degenerate (zero-area) triangle in the ") +
                                  (x == &rest ? "rest shape" : "start positions"),
                              "faces of positive area");
    }

  // Manifold and consistently oriented: each directed edge once, each undirected edge at most twice.
  std::unordered_map<long long, std::array<int, 2>> faces_of_directed;  // (a -> b) -> face
  std::unordered_map<long long, int> uses;
  faces_of_directed.reserve(3 * tris.size());
  uses.reserve(3 * tris.size());
  for (std::size_t k = 0; k < tris.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      const int a = tris[k][static_cast<std::size_t>(c)], b = tris[k][static_cast<std::size_t>((c + 1) % 3)];
      const auto edge = [&] { return "edge (" + detail::to_text(a) + ", " + detail::to_text(b) + ")"; };
      if (++uses[detail::edge_key(a, b)] > 2)
        detail::fail_argument(name + "." + face_name(static_cast<int>(k)), edge() + " of a third face (non-manifold)",
                              "edges shared by at most two faces");
      const long long directed = (static_cast<long long>(a) << 32) | static_cast<long long>(b);
      auto [it, inserted] = faces_of_directed.try_emplace(directed, std::array<int, 2>{static_cast<int>(k), c});
      if (!inserted)
        detail::fail_argument(name + "." + face_name(static_cast<int>(k)),
                              edge() + " run the same way as by " + face_name(it->second[0]) +
                                  " (inconsistent orientation)",
                              "neighbouring faces that run their shared edge in opposite directions");
    }

  std::vector<std::string> warnings;
  std::vector<char> used(static_cast<std::size_t>(n), 0);
  for (const std::array<int, 3>& t : tris)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  const auto unused = std::count(used.begin(), used.end(), 0);
  if (unused > 0) {
    const int first = static_cast<int>(std::find(used.begin(), used.end(), 0) - used.begin());
    warnings.push_back(name + ": " + detail::to_text(unused) + " vertices belong to no face (the first is vertex " +
                       detail::to_text(first) + "); the cloth holds them where they are");
  }
  return warnings;
}

}  // namespace drape
