#pragma once
/// \file mesh_generators.hpp
/// Meshes the examples and tests need, made in the library: the grid (the lattice of grid.hpp as a
/// mesh, marked so that a cloth made of it keeps the grid's springs and fast paths), a disk (the
/// Cusick drape test's specimen) and a rectangle with a circular hole.
///
/// All three lie flat in the x-z plane at height 0 (y up) with triangles counter-clockwise seen
/// from +y, as grid.hpp orients them. The disk and the rectangle are made of near-equilateral
/// triangles at a target edge length; their named boundaries are vertex groups (`mesh.groups`,
/// each in order along its boundary) so that a scene can pin by name. They are built in double
/// whatever Scalar is, so the float and the double mesh share their connectivity.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/detail/planar_triangulation.hpp"
#include "drape/core/grid.hpp"

namespace drape {

/// The nx x ny grid of grid.hpp (node (i, j) at (i h, 0, j h), id j nx + i, its triangles), marked
/// as a lattice. \throws InvalidParameter as Grid's constructor.
template <class Scalar = double>
ClothMesh<Scalar> grid_mesh(int nx, int ny, Scalar spacing) {
  const Grid<Scalar> grid(nx, ny, spacing, Scalar(1));
  ClothMesh<Scalar> mesh;
  mesh.positions = grid.rest_positions();
  mesh.triangles = grid.triangles();
  mesh.lattice = LatticeShape<Scalar>{nx, ny, spacing};
  return mesh;
}

/// The largest mesh the generators make, as Grid::max_nodes.
constexpr long long max_generated_vertices = 16'000'000;

/// A disk of `radius` centred at the origin, of near-equilateral triangles whose edges average
/// `edge_length`. K = round(1.12 radius / edge_length) concentric rings: ring k (k = 1..K) has 6k
/// vertices equally spaced at radius k radius / K from angle 0 (the +x axis) towards +z, the
/// centre is vertex 0 and the rings follow one another (vertex ids ring by ring), neighbouring
/// rings stitched in order of angle (topologically the hexagonal lattice). The interior vertices
/// are then smoothed (core/detail/planar_triangulation.hpp: 6 passes that move each vertex only to
/// enlarge the smallest angle around it, the mesh flipped to Delaunay after each). The boundary is
/// ring K, exactly on the circle, and the centre stays at the origin: the mesh covers the
/// inscribed regular 6K-gon, of area 3 K radius^2 sin(pi / (3K)), which falls short of pi radius^2
/// by pi^2 / (54 K^2) of it to leading order (second order in edge_length). Every angle is above
/// 43 degrees (60 for K = 1). Group "boundary": ring K.
///
/// With `ring_radius` > 0 one ring lies exactly on the circle of that radius as well (a support's
/// edge, a clamp, where the cloth must be able to bend): the K_i = round(1.12 ring_radius /
/// edge_length) rings inside it and the K - K_i = round(1.12 (radius - ring_radius) /
/// edge_length) outside are each evenly spaced, ring K_i and its sides stay as they are while
/// smoothing, and group "ring" is its 6 K_i vertices in order of angle. Without it a ring of vertices falls on
/// such a circle only by chance, and the cloth bends over it at the nearest ring instead: up to
/// half an edge away, differently at each edge length.
///
/// \throws InvalidParameter unless radius and edge_length are finite and > 0 and edge_length <=
/// radius (one ring at least), ring_radius is 0 or in [edge_length, radius - edge_length],
/// with at most max_generated_vertices vertices.
template <class Scalar = double>
ClothMesh<Scalar> disk_mesh(Scalar radius, Scalar edge_length, Scalar ring_radius = 0);

/// The rectangle [0, width] x [0, height] of the x-z plane (like the grid, from the origin along +x
/// and +z) with a circular hole of `hole_radius` centred at `hole_centre` = (x, z), of
/// near-equilateral triangles whose edges average `edge_length`. The sides are straight and the
/// four corners are vertices; the hole's boundary is a regular N-gon inscribed in its circle, N =
/// max(6, round(2 pi hole_radius / edge_length)), from angle 0 (+x) towards +z. Inside, the
/// vertices start on a triangular lattice with rows along x (round(height / (edge_length sqrt(3) /
/// 2)) rows, round(width / edge_length) columns) and a ring of vertices around the hole; they are
/// triangulated (Delaunay) and smoothed as the disk's, the side vertices sliding along their sides.
/// Vertex ids follow a Hilbert curve through the rectangle, for memory locality. The area is
/// width height - N/2 hole_radius^2 sin(2 pi / N): the hole's area falls short of pi hole_radius^2
/// by (2 pi / N)^2 / 6 of it to leading order. Every angle is above 30 degrees (32 at worst over
/// 1500 random rectangles, holes and edge lengths). Groups: "left" (x = 0), "right" (x = width),
/// "bottom" (z = 0), "top" (z = height), each in order of its other coordinate; "corners" ((0, 0),
/// (width, 0), (width, height), (0, height)); "boundary" (the sides in that order, from (0, 0));
/// "hole" (its N-gon in order).
/// \throws InvalidParameter unless every size is finite and > 0, the centre finite, edge_length <=
/// hole_radius (six edges at least around the hole), the hole at least edge_length from every side,
/// and the mesh within max_generated_vertices vertices.
template <class Scalar = double>
ClothMesh<Scalar> rectangle_with_hole_mesh(Scalar width, Scalar height, const Eigen::Matrix<Scalar, 2, 1>& hole_centre,
                                           Scalar hole_radius, Scalar edge_length);

// ---------------------------------------------------------------------------------------------

namespace detail {

constexpr double full_turn = 2 * 3.14159265358979323846;
/// Mean edge length of the smoothed ring disk over its ring spacing: rings radius / K apart give
/// edges averaging this much more.
constexpr double disk_edge_per_ring_spacing = 1.12;
constexpr int generator_smoothing_passes = 6;

/// A mesh in the plane: (x, z) points, triangles counter-clockwise in (x, z), groups.
struct PlanarMesh {
  std::vector<Point2> points;
  std::vector<std::array<int, 3>> triangles;
  std::map<std::string, std::vector<int>> groups;
};

inline int disk_ring_count(double radius, double edge_length) {
  return std::max(1, static_cast<int>(std::lround(disk_edge_per_ring_spacing * radius / edge_length)));
}

/// The disk's K = `rings` rings, evenly spaced; with `inner_rings` > 0, ring `inner_rings` at
/// `ring_radius` and the rings inside and outside it each evenly spaced.
inline PlanarMesh disk_in_plane(double radius, int rings, int inner_rings = 0, double ring_radius = 0) {
  const auto ring_at = [&](int k) {
    if (k == rings) return radius;
    if (inner_rings == 0) return radius * k / rings;
    if (k == inner_rings) return ring_radius;
    if (k < inner_rings) return ring_radius * k / inner_rings;
    return ring_radius + (radius - ring_radius) * (k - inner_rings) / (rings - inner_rings);
  };
  PlanarMesh mesh;
  mesh.points.push_back(Point2::Zero());
  for (int k = 1; k <= rings; ++k) {
    const double r = ring_at(k);
    for (int j = 0; j < 6 * k; ++j) {
      const double angle = full_turn * j / (6 * k);
      mesh.points.emplace_back(r * std::cos(angle), r * std::sin(angle));
    }
  }
  const auto first_of_ring = [](int k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  for (int j = 0; j < 6; ++j) mesh.triangles.push_back({0, 1 + j, 1 + (j + 1) % 6});
  for (int k = 2; k <= rings; ++k) {
    // Walk both rings in order of angle: the next vertex of lower angle closes the next triangle.
    const int f0 = first_of_ring(k - 1), n0 = 6 * (k - 1), f1 = first_of_ring(k), n1 = 6 * k;
    int i = 0, o = 0;
    while (i < n0 || o < n1) {
      const long long outer_next = static_cast<long long>(o + 1) * n0, inner_next = static_cast<long long>(i + 1) * n1;
      if (i == n0 || (o < n1 && outer_next < inner_next)) {
        mesh.triangles.push_back({f0 + i % n0, f1 + o, f1 + (o + 1) % n1});
        ++o;
      } else {
        mesh.triangles.push_back({f0 + i, f1 + o % n1, f0 + (i + 1) % n0});
        ++i;
      }
    }
  }
  std::vector<int>& boundary = mesh.groups["boundary"];
  for (int j = 0; j < 6 * rings; ++j) boundary.push_back(first_of_ring(rings) + j);
  if (inner_rings > 0) {
    std::vector<int>& ring = mesh.groups["ring"];
    for (int j = 0; j < 6 * inner_rings; ++j) ring.push_back(first_of_ring(inner_rings) + j);
  }

  PlanarTriangulation smoothing(mesh.points);
  smoothing.adopt(mesh.triangles);
  if (inner_rings > 0) {  // the ring's sides stay edges: the cloth bends along them
    const std::vector<int>& ring = mesh.groups.at("ring");
    std::vector<std::array<int, 2>> sides;
    for (std::size_t j = 0; j < ring.size(); ++j) sides.push_back({ring[j], ring[(j + 1) % ring.size()]});
    smoothing.constrain(sides);
  }
  std::vector<VertexFreedom> freedom(mesh.points.size(), VertexFreedom::Free);
  for (const auto& [name, group] : mesh.groups)
    for (int v : group) freedom[static_cast<std::size_t>(v)] = VertexFreedom::Fixed;
  freedom[0] = VertexFreedom::Fixed;  // the centre, where symmetry holds it anyway
  smoothing.smooth(freedom, generator_smoothing_passes);
  mesh.points = std::move(smoothing.points);
  mesh.triangles = std::move(smoothing.triangles);
  return mesh;
}

/// Where a vertex of the rectangle with a hole comes from: its groups and whether smoothing moves it.
enum class RectanglePoint { Interior, Side, Hole };

inline PlanarMesh rectangle_with_hole_in_plane(double width, double height, const Point2& centre, double hole_radius,
                                               double edge_length) {
  const double h = edge_length, row_height = h * std::sqrt(3.0) / 2;
  const int columns = std::max(1, static_cast<int>(std::lround(width / h)));
  const int rows = std::max(1, static_cast<int>(std::lround(height / row_height)));
  const int hole_count = std::max(6, static_cast<int>(std::lround(full_turn * hole_radius / h)));
  const double a = width / columns, b = height / rows;

  std::vector<Point2> points;
  std::vector<RectanglePoint> kinds;
  const auto add = [&](double x, double z, RectanglePoint kind) {
    points.emplace_back(x, z);
    kinds.push_back(kind);
  };
  // The hole's vertices and a ring of vertices one row further out; no lattice vertex within half
  // an edge of that ring, so the hole's edges are Delaunay edges with room to spare.
  for (int j = 0; j < hole_count; ++j) {
    const double angle = full_turn * j / hole_count;
    add(centre.x() + hole_radius * std::cos(angle), centre.y() + hole_radius * std::sin(angle), RectanglePoint::Hole);
  }
  const double hole_edge = 2 * hole_radius * std::sin(full_turn / (2 * hole_count));
  const double ring_radius = hole_radius + hole_edge * std::sqrt(3.0) / 2;
  const int ring_count = std::max(hole_count, static_cast<int>(std::lround(full_turn * ring_radius / h)));
  const auto clear_of_sides = [&](double x, double z) { return std::min({x, width - x, z, height - z}) >= 0.5 * h; };
  for (int j = 0; j < ring_count; ++j) {
    const double angle = full_turn * (j + 0.5) / ring_count;
    const double x = centre.x() + ring_radius * std::cos(angle), z = centre.y() + ring_radius * std::sin(angle);
    if (clear_of_sides(x, z)) add(x, z, RectanglePoint::Interior);
  }
  const double lattice_radius = ring_radius + 0.5 * h;
  for (int row = 0; row <= rows; ++row) {
    const double z = row == rows ? height : row * b;
    const bool on_side_row = row == 0 || row == rows;
    const auto add_lattice = [&](double x, bool on_side) {
      if (on_side) {
        add(x, z, RectanglePoint::Side);
      } else if ((Point2(x, z) - centre).norm() >= lattice_radius) {
        add(x, z, RectanglePoint::Interior);
      }
    };
    add_lattice(0, true);
    if (row % 2 == 0) {
      for (int i = 1; i < columns; ++i) add_lattice(i * a, on_side_row);
    } else {
      for (int i = 0; i < columns; ++i) add_lattice((i + 0.5) * a, on_side_row);
    }
    add_lattice(width, true);
  }

  // Vertex ids along a Hilbert curve through cells of half an edge.
  const double cell = 0.5 * h;
  std::uint32_t side = 1;
  while (side < 2 + std::max(width, height) / cell) side *= 2;
  std::vector<std::uint64_t> key(points.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    key[v] = hilbert_index(side, static_cast<std::uint32_t>(points[v].x() / cell),
                           static_cast<std::uint32_t>(points[v].y() / cell));
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int p, int q) { return key[static_cast<std::size_t>(p)] < key[static_cast<std::size_t>(q)]; });
  std::vector<Point2> sorted(points.size());
  std::vector<RectanglePoint> sorted_kinds(points.size());
  std::vector<int> id_of(points.size());
  for (std::size_t v = 0; v < order.size(); ++v) {
    sorted[v] = points[static_cast<std::size_t>(order[v])];
    sorted_kinds[v] = kinds[static_cast<std::size_t>(order[v])];
    id_of[static_cast<std::size_t>(order[v])] = static_cast<int>(v);
  }

  PlanarMesh mesh;
  const auto find_corner = [&](double x, double z) {
    for (std::size_t v = 0; v < sorted.size(); ++v)
      if (sorted[v].x() == x && sorted[v].y() == z) return static_cast<int>(v);
    throw std::logic_error("drape: rectangle_with_hole_mesh: a corner is missing");
  };
  std::vector<int>& corners = mesh.groups["corners"];
  corners = {find_corner(0, 0), find_corner(width, 0), find_corner(width, height), find_corner(0, height)};
  PlanarTriangulation triangulation(sorted);
  triangulation.start_with_quad(corners[0], corners[1], corners[2], corners[3]);
  for (int v = 0; v < static_cast<int>(sorted.size()); ++v)
    if (std::find(corners.begin(), corners.end(), v) == corners.end()) triangulation.insert(v);

  // The hole is convex and holds no vertex: its triangles are those of hole vertices alone.
  std::vector<char> keep(triangulation.triangles.size(), 1);
  for (std::size_t t = 0; t < keep.size(); ++t) {
    const std::array<int, 3>& f = triangulation.triangles[t];
    keep[t] = !std::all_of(f.begin(), f.end(),
                           [&](int v) { return sorted_kinds[static_cast<std::size_t>(v)] == RectanglePoint::Hole; });
  }
  triangulation.keep_triangles(keep);
  std::vector<int>& hole = mesh.groups["hole"];
  for (int j = 0; j < hole_count; ++j) hole.push_back(id_of[static_cast<std::size_t>(j)]);
  for (int j = 0; j < hole_count; ++j) {
    // The domain lies outside the hole, so its triangle runs the hole's edge clockwise.
    const int from = hole[static_cast<std::size_t>((j + 1) % hole_count)], to = hole[static_cast<std::size_t>(j)];
    const bool found =
        std::any_of(triangulation.triangles.begin(), triangulation.triangles.end(), [&](const std::array<int, 3>& f) {
          for (int k = 0; k < 3; ++k)
            if (f[static_cast<std::size_t>(k)] == from && f[static_cast<std::size_t>((k + 1) % 3)] == to) return true;
          return false;
        });
    if (!found) throw std::logic_error("drape: rectangle_with_hole_mesh: the triangulation misses an edge of the hole");
  }

  // Side vertices slide along their side, so the sides stay straight; corners and the hole stay.
  std::vector<VertexFreedom> freedom(sorted.size(), VertexFreedom::Free);
  for (std::size_t v = 0; v < sorted.size(); ++v) {
    const bool on_x_side = sorted[v].x() == 0 || sorted[v].x() == width,
               on_z_side = sorted[v].y() == 0 || sorted[v].y() == height;
    if (sorted_kinds[v] == RectanglePoint::Hole || (on_x_side && on_z_side)) {
      freedom[v] = VertexFreedom::Fixed;
    } else if (sorted_kinds[v] == RectanglePoint::Side) {
      freedom[v] = on_z_side ? VertexFreedom::AlongX : VertexFreedom::AlongY;
    }
  }
  triangulation.smooth(freedom, generator_smoothing_passes);
  mesh.points = std::move(triangulation.points);
  mesh.triangles = std::move(triangulation.triangles);

  // The sides, each from its lower coordinate up, and the boundary counter-clockwise from (0, 0).
  const auto side_group = [&](int axis, double value) {
    std::vector<int> ids;
    for (std::size_t v = 0; v < mesh.points.size(); ++v)
      if (sorted_kinds[v] == RectanglePoint::Side && mesh.points[v][axis] == value) ids.push_back(static_cast<int>(v));
    std::sort(ids.begin(), ids.end(), [&](int p, int q) {
      return mesh.points[static_cast<std::size_t>(p)][1 - axis] < mesh.points[static_cast<std::size_t>(q)][1 - axis];
    });
    return ids;
  };
  mesh.groups["left"] = side_group(0, 0);
  mesh.groups["right"] = side_group(0, width);
  mesh.groups["bottom"] = side_group(1, 0);
  mesh.groups["top"] = side_group(1, height);
  std::vector<int>& boundary = mesh.groups["boundary"];
  const std::vector<int>&bottom = mesh.groups["bottom"], &right = mesh.groups["right"], &top = mesh.groups["top"],
        &left = mesh.groups["left"];
  boundary.assign(bottom.begin(), bottom.end() - 1);
  boundary.insert(boundary.end(), right.begin(), right.end() - 1);
  boundary.insert(boundary.end(), top.rbegin(), top.rend() - 1);
  boundary.insert(boundary.end(), left.rbegin(), left.rend() - 1);
  return mesh;
}

/// The plane mesh in x-z at height 0, its triangles turned to face +y and sorted by their smallest
/// vertex (each starting there) so neighbouring triangles are near in memory.
template <class Scalar>
ClothMesh<Scalar> to_cloth_mesh(PlanarMesh plane) {
  ClothMesh<Scalar> mesh;
  mesh.positions.resize(3, static_cast<Index>(plane.points.size()));
  for (std::size_t v = 0; v < plane.points.size(); ++v)
    mesh.positions.col(static_cast<Index>(v)) =
        Vec3<Scalar>(static_cast<Scalar>(plane.points[v].x()), Scalar(0), static_cast<Scalar>(plane.points[v].y()));
  for (std::array<int, 3>& f : plane.triangles) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    std::swap(f[1], f[2]);  // counter-clockwise in (x, z) is clockwise seen from +y
  }
  std::sort(plane.triangles.begin(), plane.triangles.end());
  mesh.triangles = std::move(plane.triangles);
  mesh.groups = std::move(plane.groups);
  return mesh;
}

}  // namespace detail

template <class Scalar>
ClothMesh<Scalar> disk_mesh(Scalar radius, Scalar edge_length, Scalar ring_radius) {
  detail::require_positive_finite("radius", radius);
  detail::require_positive_finite("edge_length", edge_length);
  if (!(edge_length <= radius))
    detail::fail_argument("edge_length", detail::to_text(edge_length),
                          "<= radius (" + detail::to_text(radius) + "): one ring of triangles at least");
  const double r = double(radius), h = double(edge_length), ring = double(ring_radius);
  if (!(ring == 0 || (ring >= h && ring <= r - h)))
    detail::fail_argument("ring_radius", detail::to_text(ring_radius),
                          "0 (no ring) or in [edge_length, radius - edge_length] = [" + detail::to_text(h) + ", " +
                              detail::to_text(r - h) + "]: a ring of triangles at least on either side");
  const int inner_rings = ring == 0 ? 0 : detail::disk_ring_count(ring, h);
  const int rings = ring == 0 ? detail::disk_ring_count(r, h) : inner_rings + detail::disk_ring_count(r - ring, h);
  const long long vertices = 3LL * rings * (rings + 1) + 1;
  if (vertices > max_generated_vertices)
    detail::fail_argument("radius / edge_length", detail::to_text(r / h),
                          "a disk of at most " + detail::to_text(max_generated_vertices) + " vertices (" +
                              detail::to_text(vertices) + " asked)");
  return detail::to_cloth_mesh<Scalar>(detail::disk_in_plane(r, rings, inner_rings, ring));
}

template <class Scalar>
ClothMesh<Scalar> rectangle_with_hole_mesh(Scalar width, Scalar height, const Eigen::Matrix<Scalar, 2, 1>& hole_centre,
                                           Scalar hole_radius, Scalar edge_length) {
  detail::require_positive_finite("width", width);
  detail::require_positive_finite("height", height);
  detail::require_positive_finite("hole_radius", hole_radius);
  detail::require_positive_finite("edge_length", edge_length);
  const std::string centre_text =
      "(" + detail::to_text(hole_centre.x()) + ", " + detail::to_text(hole_centre.y()) + ")";
  if (!hole_centre.allFinite()) detail::fail_argument("hole_centre", centre_text, "finite coordinates (x, z)");
  if (!(edge_length <= hole_radius))
    detail::fail_argument("edge_length", detail::to_text(edge_length),
                          "<= hole_radius (" + detail::to_text(hole_radius) + "): six edges at least around the hole");
  const Scalar margin = hole_radius + edge_length;
  if (!(hole_centre.x() >= margin && hole_centre.x() <= width - margin && hole_centre.y() >= margin &&
        hole_centre.y() <= height - margin))
    detail::fail_argument("hole_centre", centre_text,
                          "a hole of radius " + detail::to_text(hole_radius) +
                              " at least edge_length = " + detail::to_text(edge_length) + " from every side: x in [" +
                              detail::to_text(margin) + ", " + detail::to_text(width - margin) + "], z in [" +
                              detail::to_text(margin) + ", " + detail::to_text(height - margin) + "]");
  const double columns = std::round(double(width) / double(edge_length)),
               rows = std::round(double(height) / (double(edge_length) * std::sqrt(3.0) / 2));
  const double vertices = (columns + 2) * (rows + 1);
  if (vertices > double(max_generated_vertices))
    detail::fail_argument("width x height / edge_length^2",
                          detail::to_text(double(width) * double(height) / (double(edge_length) * double(edge_length))),
                          "a rectangle of at most " + detail::to_text(max_generated_vertices) + " vertices");
  return detail::to_cloth_mesh<Scalar>(detail::rectangle_with_hole_in_plane(
      double(width), double(height), detail::Point2(double(hole_centre.x()), double(hole_centre.y())),
      double(hole_radius), double(edge_length)));
}

}  // namespace drape
