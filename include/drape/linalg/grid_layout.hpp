#pragma once
/// \file grid_layout.hpp
/// Where the block rows of a linear system sit on a structured `nx x ny` lattice (the cloth's grid).
/// Solvers that exploit the geometry (the multigrid preconditioner, solvers/multigrid.hpp) need
/// it; the others ignore it.

#include <vector>

namespace drape {

struct GridLayout {
  int nx = 0;  ///< nodes along i
  int ny = 0;  ///< nodes along j
  /// Block row of lattice node `j * nx + i`, or -1 if the node is not in the system (eliminated).
  std::vector<int> row_of_node;

  bool empty() const { return row_of_node.empty(); }
};

}  // namespace drape
