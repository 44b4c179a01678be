#pragma once
/// \file jacobian_assembler.hpp
/// Assembles the force Jacobians and the linearised implicit Euler system into a fixed 3x3-block
/// pattern (solvers/block_sparse_matrix.hpp).
///
/// The pattern is built once per cloth. For every spring the indices of its four blocks
/// (aa, bb, ab, ba) in the value array are precomputed, so each step writes values in place: no
/// triplets, no search, no allocation. Springs are processed colour by colour (spring_set.hpp):
/// within a colour no two springs touch the same node, hence the same block, so threads never race
/// and every block receives its terms in the same order whatever the thread count.
///
/// System (Baraff & Witkin 1998), with per-spring \f$ C = \Delta t D + \Delta t^2 K \f$
/// (spring_jacobian.hpp):
/// \f[ A = M - \Delta t \frac{\partial f}{\partial v} - \Delta t^2 \frac{\partial f}{\partial x}, \qquad
///     A_{aa} \mathrel{+}= C,\; A_{bb} \mathrel{+}= C,\; A_{ab} \mathrel{-}= C,\; A_{ba} \mathrel{-}= C, \f]
/// \f[ b = \Delta t \Bigl(f + \Delta t \frac{\partial f}{\partial x} v\Bigr), \qquad
///     b_a \mathrel{+}= \Delta t (f_a + \Delta t K w),\; b_b \mathrel{-}= \Delta t (f_a + \Delta t K w). \f]

#include <cstdint>
#include <vector>

#include "drape/config.hpp"
#include "drape/core/cloth.hpp"
#include "drape/core/parallel.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/solvers/block_sparse_matrix.hpp"

namespace drape {

/// How pinned nodes enter the linear system.
enum class PinTreatment : std::uint8_t {
  Eliminate = 0,  ///< pinned DOFs are not in the system (any solver)
  Filter = 1,     ///< every node is in the system; iterative solvers project pinned DOFs out
};

template <class Scalar = double>
class JacobianAssembler {
 public:
  static constexpr long long min_springs_per_thread = 4096;

  /// \param threads 0 = all available.
  explicit JacobianAssembler(const Cloth<Scalar>& cloth, PinTreatment pins = PinTreatment::Eliminate, int threads = 0);

  const Cloth<Scalar>& cloth() const { return *m_cloth; }
  PinTreatment pin_treatment() const { return m_pins; }
  /// Number of block rows (nodes in the system).
  int system_nodes() const { return static_cast<int>(m_node_of_row.size()); }
  /// Row of a node, -1 for eliminated (pinned) nodes.
  const std::vector<int>& row_of_node() const { return m_row_of_node; }
  const std::vector<int>& node_of_row() const { return m_node_of_row; }
  /// Per row: 1 if the node is pinned (only in PinTreatment::Filter), else 0.
  const std::vector<std::uint8_t>& filter() const { return m_filter; }
  /// A matrix with the system's pattern (values zero).
  BlockSparseMatrix<Scalar> make_matrix() const { return m_pattern; }
  int threads() const { return effective_threads(m_threads, m_cloth->springs().size(), min_springs_per_thread); }

  /// `a` = A, `rhs` = b (3 * system_nodes()), for positions x and velocities v (3 x n).
  /// `a` must come from make_matrix(); `rhs` must have the right size. No allocation.
  void assemble_system(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Scalar dt, JacobianVariant variant,
                       BlockSparseMatrix<Scalar>& a, VectorX<Scalar>& rhs) const;

  /// df/dx and df/dv restricted to the system's rows and columns (matrices from make_matrix()).
  void assemble_jacobians(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, JacobianVariant variant,
                          BlockSparseMatrix<Scalar>& dfdx, BlockSparseMatrix<Scalar>& dfdv) const;

 private:
  template <class Body>
  void for_each_spring(Body&& body) const;

  const Cloth<Scalar>* m_cloth;
  PinTreatment m_pins;
  int m_threads;
  std::vector<int> m_row_of_node, m_node_of_row;
  std::vector<std::uint8_t> m_filter;
  std::vector<std::array<int, 6>> m_slots;  // per spring: row a, row b, block aa, bb, ab, ba (-1 = none)
  BlockSparseMatrix<Scalar> m_pattern;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
JacobianAssembler<Scalar>::JacobianAssembler(const Cloth<Scalar>& cloth, PinTreatment pins, int threads)
    : m_cloth(&cloth), m_pins(pins), m_threads(threads) {
  const int n = cloth.node_count();
  m_row_of_node.assign(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    const bool pinned = cloth.pins().is_pinned(i);
    if (pinned && pins == PinTreatment::Eliminate) continue;
    m_row_of_node[static_cast<std::size_t>(i)] = static_cast<int>(m_node_of_row.size());
    m_node_of_row.push_back(i);
    m_filter.push_back(pinned ? 1 : 0);
  }
  const SpringSet<Scalar>& sp = cloth.springs();
  std::vector<std::vector<int>> columns(m_node_of_row.size());
  for (int s = 0; s < sp.size(); ++s) {
    const int ra = m_row_of_node[static_cast<std::size_t>(sp.a()[s])], rb = m_row_of_node[static_cast<std::size_t>(sp.b()[s])];
    if (ra >= 0 && rb >= 0) {
      columns[static_cast<std::size_t>(ra)].push_back(rb);
      columns[static_cast<std::size_t>(rb)].push_back(ra);
    }
  }
  m_pattern = BlockSparseMatrix<Scalar>(std::move(columns));
  // Edge form (block_sparse_matrix.hpp): one edge per spring, in the springs' colours.
  std::vector<int> edge_rows(2 * static_cast<std::size_t>(sp.size()));
  for (int s = 0; s < sp.size(); ++s) {
    edge_rows[2 * static_cast<std::size_t>(s)] = m_row_of_node[static_cast<std::size_t>(sp.a()[s])];
    edge_rows[2 * static_cast<std::size_t>(s) + 1] = m_row_of_node[static_cast<std::size_t>(sp.b()[s])];
  }
  std::vector<Scalar> row_mass(m_node_of_row.size());
  for (std::size_t r = 0; r < m_node_of_row.size(); ++r) row_mass[r] = cloth.grid().masses()[m_node_of_row[r]];
  m_pattern.set_edge_form(std::move(edge_rows), sp.colour_begin(), std::move(row_mass));
  m_slots.resize(static_cast<std::size_t>(sp.size()));
  for (int s = 0; s < sp.size(); ++s) {
    const int ra = m_row_of_node[static_cast<std::size_t>(sp.a()[s])], rb = m_row_of_node[static_cast<std::size_t>(sp.b()[s])];
    const bool both = ra >= 0 && rb >= 0;
    m_slots[static_cast<std::size_t>(s)] = {ra, rb, ra >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(ra)] : -1,
                                            rb >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(rb)] : -1,
                                            both ? m_pattern.find(ra, rb) : -1, both ? m_pattern.find(rb, ra) : -1};
  }
}

template <class Scalar>
template <class Body>
void JacobianAssembler<Scalar>::for_each_spring(Body&& body) const {
  const std::vector<int>& colour = m_cloth->springs().colour_begin();
  const int colours = m_cloth->springs().colour_count();
  const auto run = [&]() {
    for (int c = 0; c < colours; ++c) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
      for (int s = colour[c]; s < colour[c + 1]; ++s) body(s);
    }
  };
#if defined(_OPENMP)
  const int t = threads();
  if (t > 1) {
#pragma omp parallel num_threads(t)
    run();
    return;
  }
#endif
  run();
}

template <class Scalar>
void JacobianAssembler<Scalar>::assemble_system(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Scalar dt,
                                                JacobianVariant variant, BlockSparseMatrix<Scalar>& a,
                                                VectorX<Scalar>& rhs) const {
  const Cloth<Scalar>& cloth = *m_cloth;
  const SpringSet<Scalar>& sp = cloth.springs();
  DRAPE_ASSERT(a.block_count() == m_pattern.block_count(), "assemble_system(): matrix not made by make_matrix()");
  DRAPE_ASSERT(rhs.size() == 3 * system_nodes(), "assemble_system(): rhs has the wrong size");
  const Scalar* masses = cloth.grid().masses().data();
  const Vec3<Scalar> g = cloth.gravity();
  // Mass on the diagonal, dt m g in the right-hand side.
  a.set_zero();
  for (int r = 0; r < system_nodes(); ++r) {
    const Scalar m = masses[m_node_of_row[static_cast<std::size_t>(r)]];
    a.block(a.diagonal()[static_cast<std::size_t>(r)]).diagonal().setConstant(m);
    rhs.template segment<3>(3 * r) = (dt * m) * g;
  }
  const int* ia = sp.a().data();
  const int* ib = sp.b().data();
  const Scalar* rest = sp.rest_length().data();
  const Scalar* ks = sp.stiffness().data();
  const Scalar* kd = sp.damping().data();
  const Scalar dt2 = dt * dt;
  const bool has_edges = a.edge_count() == sp.size();
  for_each_spring([&](int s) {
    const std::array<int, 6>& slot = m_slots[static_cast<std::size_t>(s)];
    const Vec3<Scalar> va = v.col(ia[s]), vb = v.col(ib[s]);
    const SpringDerivatives<Scalar> d =
        spring_derivatives<Scalar>(x.col(ia[s]), x.col(ib[s]), va, vb, rest[s], ks[s], kd[s], variant);
    const Mat3<Scalar> c = dt * d.dfdv + dt2 * d.dfdx;
    const Vec3<Scalar> g_s = dt * (d.force + dt * (d.dfdx * (vb - va)));
    if (slot[0] >= 0) rhs.template segment<3>(3 * slot[0]) += g_s;
    if (slot[1] >= 0) rhs.template segment<3>(3 * slot[1]) -= g_s;
    if (slot[2] >= 0) a.block(slot[2]) += c;
    if (slot[3] >= 0) a.block(slot[3]) += c;
    if (slot[4] >= 0) a.block(slot[4]) -= c;
    if (slot[5] >= 0) a.block(slot[5]) -= c;
    if (has_edges) a.edge_block(s) = c;
  });
  if (has_edges) a.mark_edge_form_valid();
}

template <class Scalar>
void JacobianAssembler<Scalar>::assemble_jacobians(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v,
                                                   JacobianVariant variant, BlockSparseMatrix<Scalar>& dfdx,
                                                   BlockSparseMatrix<Scalar>& dfdv) const {
  const SpringSet<Scalar>& sp = m_cloth->springs();
  dfdx.set_zero();
  dfdv.set_zero();
  for_each_spring([&](int s) {
    const std::array<int, 6>& slot = m_slots[static_cast<std::size_t>(s)];
    const int a = sp.a()[s], b = sp.b()[s];
    const SpringDerivatives<Scalar> d = spring_derivatives<Scalar>(
        x.col(a), x.col(b), v.col(a), v.col(b), sp.rest_length()[s], sp.stiffness()[s], sp.damping()[s], variant);
    // df_a/dx_a = df_b/dx_b = -K, df_a/dx_b = df_b/dx_a = +K (and D likewise).
    if (slot[2] >= 0) { dfdx.block(slot[2]) -= d.dfdx; dfdv.block(slot[2]) -= d.dfdv; }
    if (slot[3] >= 0) { dfdx.block(slot[3]) -= d.dfdx; dfdv.block(slot[3]) -= d.dfdv; }
    if (slot[4] >= 0) { dfdx.block(slot[4]) += d.dfdx; dfdv.block(slot[4]) += d.dfdv; }
    if (slot[5] >= 0) { dfdx.block(slot[5]) += d.dfdx; dfdv.block(slot[5]) += d.dfdv; }
  });
}

}  // namespace drape
