#pragma once
/// \file jacobian_assembler.hpp
/// Assembles the force Jacobians and the linearised implicit Euler system into a fixed 3x3-block
/// pattern (solvers/block_sparse_matrix.hpp).
///
/// The pattern is built once per cloth, together with each block row's incident springs in
/// ascending order. A step then writes every value in place (no zeroing, no triplets, no search, no
/// allocation) in two passes, each split statically over the threads:
/// 1. per spring: the symmetric (6 values; 9 for the Exact variant) block
///    \f$ C = \Delta t D + \Delta t^2 K \f$ into the matrix's edge form and the spring's
///    right-hand-side term \f$ g \f$ into a scratch array; no two springs write the same place;
/// 2. per block row: the diagonal block (mass plus the incident springs' C), the off-diagonal
///    blocks (-C) and the right-hand side, gathered from pass 1.
/// So one barrier separates the passes (scattering into blocks would need one per spring colour),
/// and every value is summed in the same order (ascending springs) whatever the thread count.
///
/// System (Baraff & Witkin 1998), with per-spring \f$ C = \Delta t D + \Delta t^2 K \f$
/// (spring_jacobian.hpp):
/// \f[ A = M - \Delta t \frac{\partial f}{\partial v} - \Delta t^2 \frac{\partial f}{\partial x}, \qquad
///     A_{aa} \mathrel{+}= C,\; A_{bb} \mathrel{+}= C,\; A_{ab} \mathrel{-}= C,\; A_{ba} \mathrel{-}= C, \f]
/// \f[ b = \Delta t \Bigl(f + \Delta t \frac{\partial f}{\partial x} v\Bigr), \qquad
///     b_a \mathrel{+}= g,\; b_b \mathrel{-}= g, \quad g = \Delta t (f_a + \Delta t K w). \f]

#include <array>
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
  /// A matrix with the system's pattern and edge form (values zero).
  BlockSparseMatrix<Scalar> make_matrix() const { return m_pattern; }
  int threads() const { return effective_threads(m_threads, m_cloth->springs().size(), min_springs_per_thread); }

  /// `a` = A (every block and the edge form, symmetric unless `variant` is Exact), `rhs` = b
  /// (3 * system_nodes()), for positions x and velocities v (3 x n). `a` must come from
  /// make_matrix(); `rhs` must have the right size. No allocation. Uses a scratch array of the
  /// assembler: do not call concurrently on the same assembler.
  void assemble_system(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Scalar dt, JacobianVariant variant,
                       BlockSparseMatrix<Scalar>& a, VectorX<Scalar>& rhs) const;

  /// df/dx and df/dv restricted to the system's rows and columns (matrices from make_matrix()).
  void assemble_jacobians(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, JacobianVariant variant,
                          BlockSparseMatrix<Scalar>& dfdx, BlockSparseMatrix<Scalar>& dfdv) const;

 private:
  /// A spring incident on a block row; each row lists its springs in ascending order.
  struct Incidence {
    int spring;
    int block;            // off-diagonal block (this row, other end); -1 if the other end is eliminated
    int node_b;           // 1 if this row is the spring's node b (its right-hand side gets -g)
  };

  template <class Body>
  void for_each_spring(Body&& body) const;
  template <bool Symmetric>
  void write_system(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Scalar dt, JacobianVariant variant,
                       BlockSparseMatrix<Scalar>& a, VectorX<Scalar>& rhs) const;

  const Cloth<Scalar>* m_cloth;
  PinTreatment m_pins;
  int m_threads;
  std::vector<int> m_row_of_node, m_node_of_row;
  std::vector<std::uint8_t> m_filter;
  std::vector<std::array<int, 6>> m_slots;  // per spring: row a, row b, block aa, bb, ab, ba (-1 = none)
  std::vector<int> m_incidence_begin;       // per row, into m_incidence
  std::vector<Incidence> m_incidence;
  mutable std::vector<Scalar> m_spring_rhs;  // g of every spring (3 each), written by pass 1
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
  const std::size_t rows = m_node_of_row.size();
  std::vector<std::vector<int>> columns(rows);
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
  std::vector<Scalar> row_mass(rows);
  for (std::size_t r = 0; r < rows; ++r) row_mass[r] = cloth.grid().masses()[m_node_of_row[r]];
  m_pattern.set_edge_form(std::move(edge_rows), sp.colour_begin(), std::move(row_mass));
  m_slots.resize(static_cast<std::size_t>(sp.size()));
  for (int s = 0; s < sp.size(); ++s) {
    const int ra = m_row_of_node[static_cast<std::size_t>(sp.a()[s])], rb = m_row_of_node[static_cast<std::size_t>(sp.b()[s])];
    const bool both = ra >= 0 && rb >= 0;
    m_slots[static_cast<std::size_t>(s)] = {ra, rb, ra >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(ra)] : -1,
                                            rb >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(rb)] : -1,
                                            both ? m_pattern.find(ra, rb) : -1, both ? m_pattern.find(rb, ra) : -1};
  }
  // Incidence lists, filled in ascending spring order.
  m_incidence_begin.assign(rows + 1, 0);
  for (const std::array<int, 6>& slot : m_slots)
    for (int side = 0; side < 2; ++side)
      if (slot[static_cast<std::size_t>(side)] >= 0) ++m_incidence_begin[static_cast<std::size_t>(slot[static_cast<std::size_t>(side)]) + 1];
  for (std::size_t r = 0; r < rows; ++r) m_incidence_begin[r + 1] += m_incidence_begin[r];
  m_incidence.resize(static_cast<std::size_t>(m_incidence_begin.back()));
  std::vector<int> next(m_incidence_begin.begin(), m_incidence_begin.end() - 1);
  std::vector<std::uint8_t> block_seen(static_cast<std::size_t>(m_pattern.block_count()), 0);  // for the check
  for (int s = 0; s < sp.size(); ++s) {
    const std::array<int, 6>& slot = m_slots[static_cast<std::size_t>(s)];
    for (int side = 0; side < 2; ++side) {
      const int row = slot[static_cast<std::size_t>(side)];
      if (row < 0) continue;
      const int block = slot[4 + static_cast<std::size_t>(side)];
      if (block >= 0) {
        // Grid springs join distinct node pairs, so each off-diagonal block is one spring's -C.
        DRAPE_ASSERT(!block_seen[static_cast<std::size_t>(block)], "JacobianAssembler: two springs join the same nodes");
        block_seen[static_cast<std::size_t>(block)] = 1;
      }
      m_incidence[static_cast<std::size_t>(next[static_cast<std::size_t>(row)]++)] = Incidence{s, block, side};
    }
  }
  m_spring_rhs.assign(3 * static_cast<std::size_t>(sp.size()), Scalar(0));
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
  DRAPE_ASSERT(a.block_count() == m_pattern.block_count(), "assemble_system(): matrix not made by make_matrix()");
  DRAPE_ASSERT(rhs.size() == 3 * system_nodes(), "assemble_system(): rhs has the wrong size");
  if (a.edge_count() != m_pattern.edge_count())  // the caller dropped the edge form: restore it
    a.set_edge_form(m_pattern.edge_rows(), m_pattern.edge_colour_begin(), m_pattern.row_mass());
  if (variant == JacobianVariant::Exact)
    write_system<false>(x, v, dt, variant, a, rhs);
  else
    write_system<true>(x, v, dt, variant, a, rhs);
  a.mark_edge_form_valid(variant != JacobianVariant::Exact);
}

template <class Scalar>
template <bool Symmetric>
void JacobianAssembler<Scalar>::write_system(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Scalar dt,
                                             JacobianVariant variant, BlockSparseMatrix<Scalar>& a,
                                             VectorX<Scalar>& rhs) const {
  constexpr int stride = Symmetric ? 6 : 9;  // edge-form values per spring
  const SpringSet<Scalar>& sp = m_cloth->springs();
  const int springs = sp.size();
  const int rows = system_nodes();
  const int* ia = sp.a().data();
  const int* ib = sp.b().data();
  const Scalar* rest = sp.rest_length().data();
  const Scalar* ks = sp.stiffness().data();
  const Scalar* kd = sp.damping().data();
  const Scalar* masses = m_cloth->grid().masses().data();
  const int* node_of_row = m_node_of_row.data();
  const int* diagonal = a.diagonal().data();
  const int* incidence_begin = m_incidence_begin.data();
  const Incidence* incidence = m_incidence.data();
  const Vec3<Scalar> gravity = m_cloth->gravity();
  const Scalar dt2 = dt * dt;
  Scalar* blocks = a.edge_values();
  Scalar* g_all = m_spring_rhs.data();
  Scalar* values = a.values();
  Scalar* b = rhs.data();

  // Pass 1, per spring: C = p u u^T + q I (+ r u w^T, Exact) and g = dt (phi u + dt K w) with
  // K w = (k_uu w.u + k_uw w.w) u + k_i w.
  const auto spring_pass = [&]() {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int s = 0; s < springs; ++s) {
      const SpringLinearisation<Scalar> l =
          linearise_spring<Scalar>(x.col(ia[s]), x.col(ib[s]), v.col(ia[s]), v.col(ib[s]), rest[s], ks[s], kd[s], variant);
      const Scalar p = dt * kd[s] + dt2 * l.k_uu;
      const Scalar q = dt2 * l.k_i;
      const Scalar u0 = l.u[0], u1 = l.u[1], u2 = l.u[2];
      Scalar* c = blocks + stride * s;
      Scalar g_u = dt * l.phi + dt2 * l.k_uu * l.wu;
      if constexpr (Symmetric) {
        // Lower triangle, row by row: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2).
        const Scalar pu0 = p * u0, pu1 = p * u1, pu2 = p * u2;
        c[0] = pu0 * u0 + q;
        c[1] = pu1 * u0;
        c[2] = pu1 * u1 + q;
        c[3] = pu2 * u0;
        c[4] = pu2 * u1;
        c[5] = pu2 * u2 + q;
      } else {
        const Scalar r = dt2 * l.k_uw;
        g_u += dt2 * l.k_uw * l.w.squaredNorm();
        for (int j = 0; j < 3; ++j) {  // column j = (p u_j + r w_j) u + q e_j
          const Scalar cj = p * l.u[j] + r * l.w[j];
          c[3 * j] = cj * u0;
          c[3 * j + 1] = cj * u1;
          c[3 * j + 2] = cj * u2;
          c[4 * j] += q;
        }
      }
      Scalar* g = g_all + 3 * s;
      g[0] = g_u * u0 + q * l.w[0];
      g[1] = g_u * u1 + q * l.w[1];
      g[2] = g_u * u2 + q * l.w[2];
    }
  };
  // The full 3x3 block (column-major) of a spring's stored C.
  const auto expand = [](const Scalar* c, Scalar* full) {
    if constexpr (Symmetric) {
      full[0] = c[0]; full[1] = c[1]; full[2] = c[3];
      full[3] = c[1]; full[4] = c[2]; full[5] = c[4];
      full[6] = c[3]; full[7] = c[4]; full[8] = c[5];
    } else {
      for (int k = 0; k < 9; ++k) full[k] = c[k];
    }
  };
  // Pass 2, per block row: diagonal m I + sum C, off-diagonal -C, b = dt m g + sum (+-g).
  const auto row_pass = [&]() {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (int row = 0; row < rows; ++row) {
      const Scalar m = masses[node_of_row[row]];
      Scalar diag[stride];
      for (int k = 0; k < stride; ++k) diag[k] = 0;
      if constexpr (Symmetric) {
        diag[0] = diag[2] = diag[5] = m;
      } else {
        diag[0] = diag[4] = diag[8] = m;
      }
      const Vec3<Scalar> weight = (dt * m) * gravity;
      Scalar b0 = weight[0], b1 = weight[1], b2 = weight[2];
      for (int k = incidence_begin[row]; k < incidence_begin[row + 1]; ++k) {
        const Incidence& in = incidence[k];
        const Scalar* c = blocks + stride * in.spring;
        for (int q = 0; q < stride; ++q) diag[q] += c[q];
        if (in.block >= 0) {
          Scalar full[9];
          expand(c, full);
          Scalar* off = values + 9 * in.block;
          for (int q = 0; q < 9; ++q) off[q] = -full[q];
        }
        const Scalar* g = g_all + 3 * in.spring;
        if (in.node_b) {
          b0 -= g[0]; b1 -= g[1]; b2 -= g[2];
        } else {
          b0 += g[0]; b1 += g[1]; b2 += g[2];
        }
      }
      expand(diag, values + 9 * diagonal[row]);
      b[3 * row] = b0;
      b[3 * row + 1] = b1;
      b[3 * row + 2] = b2;
    }
  };
#if defined(_OPENMP)
  const int t = threads();
  if (t > 1) {
#pragma omp parallel num_threads(t)
    {
      spring_pass();  // its implicit barrier publishes C and g to the row pass
      row_pass();
    }
    return;
  }
#endif
  spring_pass();
  row_pass();
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
