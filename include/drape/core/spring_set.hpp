#pragma once
/// \file spring_set.hpp
/// The springs of a cloth, generated from its grid or its mesh, stored as structure-of-arrays.
///
/// On a mesh (core/cloth_mesh.hpp): structural springs on the faces' edges, shear springs on both
/// diagonals of every quad, bend springs across every interior edge of the triangulated mesh between
/// its two opposite vertices (unless a spring already joins them). A mesh of triangles only has no
/// shear springs. Rest lengths come from the mesh's rest shape. A lattice mesh (grid_mesh()) gets
/// the grid's springs in the grid's order.
///
/// Springs are stored in *colours*: contiguous ranges in which no two springs share a node, so a
/// colour's springs can be processed by several threads without write races and with the same
/// summation order per node whatever the thread count (drape's conventions.md, "Determinism").

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "drape/core/cloth_mesh.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/core/grid.hpp"
#include "drape/core/validation.hpp"

namespace drape {

enum class SpringCategory : std::uint8_t {
  Structural = 0,  ///< neighbours along rows and columns, rest length h
  Shear = 1,       ///< both diagonals of every cell, rest length h*sqrt(2)
  Bend = 2,        ///< nodes two apart along rows and columns, rest length 2h
};
inline constexpr int spring_category_count = 3;

template <>
struct EnumNames<SpringCategory> {
  static constexpr const char* parameter = "spring category";
  static constexpr std::array<EnumName<SpringCategory>, 3> values{
      {{SpringCategory::Structural, "structural"}, {SpringCategory::Shear, "shear"}, {SpringCategory::Bend, "bend"}}};
};

/// Stiffness ks (N/m) and damping kd (N s/m) of one spring category.
template <class Scalar = double>
struct SpringParams {
  Scalar stiffness;
  Scalar damping;
};

/// One `SpringParams` per category.
template <class Scalar = double>
struct SpringCoefficients {
  SpringParams<Scalar> structural;
  SpringParams<Scalar> shear;
  SpringParams<Scalar> bend;

  const SpringParams<Scalar>& operator[](SpringCategory c) const {
    return c == SpringCategory::Structural ? structural : c == SpringCategory::Shear ? shear : bend;
  }
  /// \throws InvalidParameter naming e.g. `shear.stiffness` if a value is negative or not finite.
  void validate() const {
    detail::require_nonnegative_finite("structural.stiffness", structural.stiffness);
    detail::require_nonnegative_finite("structural.damping", structural.damping);
    detail::require_nonnegative_finite("shear.stiffness", shear.stiffness);
    detail::require_nonnegative_finite("shear.damping", shear.damping);
    detail::require_nonnegative_finite("bend.stiffness", bend.stiffness);
    detail::require_nonnegative_finite("bend.damping", bend.damping);
  }
};

template <class Scalar = double>
class SpringSet {
 public:
  /// Structural, shear and bend springs of `grid`; rest lengths from the undeformed grid.
  /// \throws InvalidParameter if a coefficient is negative or not finite.
  SpringSet(const Grid<Scalar>& grid, const SpringCoefficients<Scalar>& coefficients);
  /// The springs of `mesh` (the file comment's rule; a lattice mesh's are the grid's). The mesh
  /// must pass ClothMesh::validate(). \throws InvalidParameter if a coefficient is invalid.
  SpringSet(const ClothMesh<Scalar>& mesh, const SpringCoefficients<Scalar>& coefficients);

  int size() const { return static_cast<int>(m_a.size()); }
  int count(SpringCategory c) const { return m_category_count[static_cast<int>(c)]; }

  // Per-spring data, index s in [0, size()). Spring s joins nodes a(s) -> b(s).
  const std::vector<int>& a() const { return m_a; }
  const std::vector<int>& b() const { return m_b; }
  const std::vector<Scalar>& rest_length() const { return m_rest_length; }
  const std::vector<Scalar>& stiffness() const { return m_stiffness; }
  const std::vector<Scalar>& damping() const { return m_damping; }
  const std::vector<SpringCategory>& category() const { return m_category; }

  /// Colour c holds springs [colour_begin()[c], colour_begin()[c+1]); no two share a node.
  const std::vector<int>& colour_begin() const { return m_colour_begin; }
  int colour_count() const { return static_cast<int>(m_colour_begin.size()) - 1; }

 private:
  void add(int a, int b, SpringCategory c, const SpringParams<Scalar>& p, Scalar rest);
  /// Fills the springs of a grid (nx x ny nodes `h` apart).
  void add_grid(int nx, int ny, Scalar h, const SpringCoefficients<Scalar>& k);

  std::vector<int> m_a, m_b;
  std::vector<Scalar> m_rest_length, m_stiffness, m_damping;
  std::vector<SpringCategory> m_category;
  std::vector<int> m_colour_begin;
  std::array<int, spring_category_count> m_category_count{};
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void SpringSet<Scalar>::add(int a, int b, SpringCategory c, const SpringParams<Scalar>& p, Scalar rest) {
  m_a.push_back(a);
  m_b.push_back(b);
  m_rest_length.push_back(rest);
  m_stiffness.push_back(p.stiffness);
  m_damping.push_back(p.damping);
  m_category.push_back(c);
  ++m_category_count[static_cast<int>(c)];
}

template <class Scalar>
SpringSet<Scalar>::SpringSet(const Grid<Scalar>& grid, const SpringCoefficients<Scalar>& k) {
  k.validate();
  add_grid(grid.nx(), grid.ny(), grid.spacing(), k);
}

template <class Scalar>
void SpringSet<Scalar>::add_grid(int nx, int ny, Scalar h, const SpringCoefficients<Scalar>& k) {
  const auto contains = [&](int i, int j) { return i >= 0 && i < nx && j >= 0 && j < ny; };
  const auto node = [&](int i, int j) { return j * nx + i; };
  const Scalar diagonal = h * std::sqrt(Scalar(2));
  using C = SpringCategory;

  // A spring family is a fixed offset (di, dj) from its first node; within a family, springs whose
  // key (i or j, divided by `stride`) has the same parity share no node. Each (family, parity) is
  // one colour. Families that step along j (dj > 0) take j as key: a colour's springs then have
  // consecutive first and second nodes along each line, which the edge product loads as whole
  // groups (linalg/edge_operator.hpp); only the families along i (dj = 0) need i.
  struct Family {
    int di, dj, i0;  // second node = (i + di, j + dj); first node i starts at i0
    bool key_is_i;   // colour key taken from i (else j)
    int stride;      // key = coordinate / stride
    C category;
  };
  const Family families[] = {
      {1, 0, 0, true, 1, C::Structural}, {0, 1, 0, false, 1, C::Structural}, {1, 1, 0, false, 1, C::Shear},
      {-1, 1, 1, false, 1, C::Shear},    {2, 0, 0, true, 2, C::Bend},        {0, 2, 0, false, 2, C::Bend},
  };
  const std::size_t expected =
      static_cast<std::size_t>(2 * (nx - 1) * ny + 2 * nx * (ny - 1) + 2 * (nx - 1) * (ny - 1)) +
      static_cast<std::size_t>(std::max(0, nx - 2) * ny + nx * std::max(0, ny - 2));
  m_a.reserve(expected);
  m_b.reserve(expected);
  m_rest_length.reserve(expected);
  m_stiffness.reserve(expected);
  m_damping.reserve(expected);
  m_category.reserve(expected);

  m_colour_begin.push_back(0);
  for (const Family& f : families) {
    const Scalar rest = f.category == C::Structural ? h : f.category == C::Shear ? diagonal : 2 * h;
    for (int parity = 0; parity < 2; ++parity) {
      for (int j = 0; j < ny; ++j) {
        for (int i = f.i0; i < nx; ++i) {
          if (!contains(i + f.di, j + f.dj)) continue;
          const int key = (f.key_is_i ? i : j) / f.stride;
          if (key % 2 != parity) continue;
          add(node(i, j), node(i + f.di, j + f.dj), f.category, k[f.category], rest);
        }
      }
      if (size() != m_colour_begin.back()) m_colour_begin.push_back(size());
    }
  }
}

template <class Scalar>
SpringSet<Scalar>::SpringSet(const ClothMesh<Scalar>& mesh, const SpringCoefficients<Scalar>& k) {
  k.validate();
  if (mesh.lattice) {
    add_grid(mesh.lattice->nx, mesh.lattice->ny, mesh.lattice->spacing, k);
    return;
  }
  using C = SpringCategory;
  const Matrix3X<Scalar> rest = mesh.rest_shape();
  // Every pair joined once, the first family that asks for it wins: edges, quad diagonals, hinges.
  struct Pending {
    int a, b;
    C category;
  };
  std::vector<Pending> pending;
  std::unordered_map<long long, char> joined;
  const auto want = [&](int a, int b, C c) {
    if (joined.emplace(detail::edge_key(a, b), 1).second) pending.push_back({std::min(a, b), std::max(a, b), c});
  };
  for (const std::array<int, 3>& t : mesh.triangles)
    for (int e = 0; e < 3; ++e) want(t[e], t[(e + 1) % 3], C::Structural);
  for (const std::array<int, 4>& q : mesh.quads)
    for (int e = 0; e < 4; ++e) want(q[e], q[(e + 1) % 4], C::Structural);
  for (const std::array<int, 4>& q : mesh.quads) {
    want(q[0], q[2], C::Shear);
    want(q[1], q[3], C::Shear);
  }
  for (const Hinge& h : mesh.hinges()) want(h.c, h.d, C::Bend);

  // Greedy colouring in order of first node: the smallest colour neither end uses yet. Springs are
  // then stored colour by colour, each colour in order of first node (for locality).
  std::vector<std::vector<int>> colours_of_node(static_cast<std::size_t>(mesh.vertex_count()));
  std::vector<int> colour(pending.size());
  std::vector<std::size_t> order(pending.size());
  for (std::size_t s = 0; s < order.size(); ++s) order[s] = s;
  std::sort(order.begin(), order.end(), [&](std::size_t s, std::size_t t) {
    return pending[s].a != pending[t].a ? pending[s].a < pending[t].a : pending[s].b < pending[t].b;
  });
  int colours = 0;
  for (std::size_t s : order) {
    std::vector<int>& at_a = colours_of_node[static_cast<std::size_t>(pending[s].a)];
    std::vector<int>& at_b = colours_of_node[static_cast<std::size_t>(pending[s].b)];
    int c = 0;
    while (std::find(at_a.begin(), at_a.end(), c) != at_a.end() || std::find(at_b.begin(), at_b.end(), c) != at_b.end())
      ++c;
    colour[s] = c;
    at_a.push_back(c);
    at_b.push_back(c);
    colours = std::max(colours, c + 1);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t s, std::size_t t) { return colour[s] < colour[t]; });
  m_colour_begin.push_back(0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const Pending& p = pending[order[i]];
    add(p.a, p.b, p.category, k[p.category], (rest.col(p.b) - rest.col(p.a)).norm());
    if (i + 1 == order.size() || colour[order[i + 1]] != colour[order[i]]) m_colour_begin.push_back(size());
  }
}

}  // namespace drape
