#pragma once
/// \file pins.hpp
/// Fixed nodes (Dirichlet boundary conditions). Pinned nodes never move and keep zero velocity;
/// the integrators never change them.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drape/core/grid.hpp"

namespace drape {

/// The brief's two boundary conditions.
enum class BoundaryCondition : std::uint8_t {
  OneCorner = 1,   ///< node (0, 0) fixed
  TwoCorners = 2,  ///< nodes (0, 0) and (nx-1, 0) fixed, one cloth width apart
};

class Pins {
 public:
  Pins() = default;
  /// \throws std::invalid_argument if a node id is outside [0, node_count).
  Pins(std::vector<int> nodes, int node_count);

  /// The preset `bc` on `grid`.
  template <class Scalar>
  static Pins preset(BoundaryCondition bc, const Grid<Scalar>& grid);

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

inline Pins::Pins(std::vector<int> nodes, int node_count) : m_nodes(std::move(nodes)) {
  std::sort(m_nodes.begin(), m_nodes.end());
  m_nodes.erase(std::unique(m_nodes.begin(), m_nodes.end()), m_nodes.end());
  for (int n : m_nodes)
    if (n < 0 || n >= node_count)
      detail::fail_argument("pinned node", detail::to_text(n), "[0, " + detail::to_text(node_count - 1) + "]");
  m_mask.assign(static_cast<std::size_t>(node_count), 0);
  for (int n : m_nodes) m_mask[static_cast<std::size_t>(n)] = 1;
}

template <class Scalar>
Pins Pins::preset(BoundaryCondition bc, const Grid<Scalar>& grid) {
  switch (bc) {
    case BoundaryCondition::OneCorner: return Pins({grid.node(0, 0)}, grid.node_count());
    case BoundaryCondition::TwoCorners: return Pins({grid.node(0, 0), grid.node(grid.nx() - 1, 0)}, grid.node_count());
  }
  detail::fail_argument("boundary_condition", detail::to_text(static_cast<int>(bc)), "1 (one corner) or 2 (two corners)");
}

}  // namespace drape
