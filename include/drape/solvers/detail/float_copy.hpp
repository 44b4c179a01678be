#pragma once
/// \file float_copy.hpp
/// The float copy of a system that the mixed-precision preconditioners (single_precision_multigrid.hpp,
/// single_precision_algebraic_multigrid.hpp) run their V-cycle on inside a double CG: its structure,
/// made once, and the rounding of values and vectors, every update and every application.

#include <cstddef>
#include <utility>
#include <vector>

#include "drape/linalg/linear_system.hpp"
#include "drape/platform/team.hpp"

namespace drape::detail {

/// `to[i] = To(from[i])` for i < n, split over the team in fixed shares (the team waits at the end).
/// Each value is rounded on its own, so the result does not depend on the team size.
template <class From, class To>
void convert_in_team(const From* from, To* to, std::size_t n) {
  const auto share = even_share(static_cast<long long>(n), team_rank(), team_size());
  DRAPE_OMP_SIMD
  for (long long i = share.first; i < share.second; ++i) to[i] = static_cast<To>(from[i]);
  team_barrier();
}

/// A float system of `system`'s structure: the same block pattern (in the same sorted block order),
/// edge form (edge rows, colours, row masses, room for row blocks), lattice layout, and a constraint
/// filter of as many rows with none constrained. Its values are zero and its edge form invalid until
/// round_edges_and_constraints_in_team(). Allocates (a preconditioner's analyze()).
template <class Scalar>
LinearSystem<float> float_structure(const LinearSystem<Scalar>& system) {
  const BlockSparseMatrix<Scalar>& a = system.matrix;
  std::vector<std::vector<int>> columns(static_cast<std::size_t>(a.block_rows()));
  for (int r = 0; r < a.block_rows(); ++r)
    columns[static_cast<std::size_t>(r)].assign(a.column().begin() + a.row_begin()[static_cast<std::size_t>(r)],
                                                a.column().begin() + a.row_begin()[static_cast<std::size_t>(r) + 1]);
  LinearSystem<float> single;
  single.matrix = BlockSparseMatrix<float>(std::move(columns));
  const EdgeOperator<Scalar>& edges = system.edges;
  single.edges = EdgeOperator<float>(edges.edge_rows(), edges.colour_begin(),
                                     std::vector<float>(edges.row_mass().begin(), edges.row_mass().end()));
  if (edges.has_row_blocks()) single.edges.enable_row_blocks();
  single.layout = system.layout;
  single.constraints = ConstraintFilter<float>(system.block_rows());
  return single;
}

/// `single`'s edge form and constraints become `system`'s, rounded to float: the edge values and row
/// blocks if `round_edges` and `system`'s edge form is valid (else `single`'s is marked invalid, so
/// nothing reads stale values), then the validity flags and the constraint filter. Every thread of
/// the team calls it; the team waits at the end. No allocation once `single` has `system`'s structure
/// (float_structure()).
template <class Scalar>
void round_edges_and_constraints_in_team(const LinearSystem<Scalar>& system, LinearSystem<float>& single,
                                         bool round_edges = true) {
  const EdgeOperator<Scalar>& edges = system.edges;
  const bool rounded = round_edges && edges.valid();
  const bool row_blocks = edges.uses_row_blocks() || edges.uses_row_diagonal();
  if (rounded) {
    convert_in_team(edges.values(), single.edges.values(), edges.value_count());
    if (row_blocks)
      convert_in_team(edges.row_blocks(), single.edges.row_blocks(), 9 * static_cast<std::size_t>(edges.rows()));
  }
  team_single([&] {
    if (rounded)
      single.edges.set_valid(edges.symmetric(), row_blocks);
    else
      single.edges.invalidate();
    single.constraints.assign(system.constraints);
  });
}

}  // namespace drape::detail
