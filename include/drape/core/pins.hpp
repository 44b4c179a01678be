#pragma once
/// \file pins.hpp
/// Fixed nodes (Dirichlet boundary conditions). Pinned nodes never move and keep zero velocity;
/// the integrators never change them.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drape/core/enum_names.hpp"
#include "drape/core/grid.hpp"

namespace drape {

/// The course model's two boundary conditions.
enum class BoundaryCondition : std::uint8_t {
  OneCorner = 1,   ///< node (0, 0) fixed
  TwoCorners = 2,  ///< nodes (0, 0) and (nx-1, 0) fixed, one cloth width apart
};

template <>
struct EnumNames<BoundaryCondition> {
  static constexpr const char* parameter = "boundary_condition";
  static constexpr std::array<EnumName<BoundaryCondition>, 2> values{
      {{BoundaryCondition::OneCorner, "one-corner"}, {BoundaryCondition::TwoCorners, "two-corners"}}};
};

class Pins {
 public:
  Pins() = default;
  /// \throws InvalidParameter if a node id is outside [0, node_count).
  Pins(std::vector<int> nodes, int node_count);

  /// The preset `bc` on `grid`. \throws InvalidParameter as validate(bc).
  template <class Scalar>
  static Pins preset(BoundaryCondition bc, const Grid<Scalar>& grid);

  /// \throws InvalidParameter naming `pinned node` for a node id outside [0, node_count).
  static void validate(const std::vector<int>& nodes, int node_count);
  /// \throws InvalidParameter naming `boundary_condition` unless `bc` is one of the presets.
  static void validate(BoundaryCondition bc);

  /// Sorted, without duplicates.
  const std::vector<int>& nodes() const { return m_nodes; }
  bool is_pinned(int node) const { return m_mask[static_cast<std::size_t>(node)] != 0; }
  /// 1 for pinned nodes, 0 for free ones; one entry per node.
  const std::vector<std::uint8_t>& mask() const { return m_mask; }
  int count() const { return static_cast<int>(m_nodes.size()); }

 private:
  std::vector<int> m_nodes;
  std::vector<std::uint8_t> m_mask;
};

// ---------------------------------------------------------------------------------------------

inline void Pins::validate(const std::vector<int>& nodes, int node_count) {
  for (int n : nodes)
    if (n < 0 || n >= node_count)
      detail::fail_argument("pinned node", detail::to_text(n), "[0, " + detail::to_text(node_count - 1) + "]");
}

inline void Pins::validate(BoundaryCondition bc) {
  if (bc != BoundaryCondition::OneCorner && bc != BoundaryCondition::TwoCorners)
    detail::fail_argument("boundary_condition", detail::to_text(static_cast<int>(bc)),
                          "1 (one corner) or 2 (two corners)");
}

inline Pins::Pins(std::vector<int> nodes, int node_count) : m_nodes(std::move(nodes)) {
  std::sort(m_nodes.begin(), m_nodes.end());
  m_nodes.erase(std::unique(m_nodes.begin(), m_nodes.end()), m_nodes.end());
  validate(m_nodes, node_count);
  m_mask.assign(static_cast<std::size_t>(node_count), 0);
  for (int n : m_nodes) m_mask[static_cast<std::size_t>(n)] = 1;
}

template <class Scalar>
Pins Pins::preset(BoundaryCondition bc, const Grid<Scalar>& grid) {
  validate(bc);
  if (bc == BoundaryCondition::OneCorner) return Pins({grid.node(0, 0)}, grid.node_count());
  return Pins({grid.node(0, 0), grid.node(grid.nx() - 1, 0)}, grid.node_count());
}

}  // namespace drape
