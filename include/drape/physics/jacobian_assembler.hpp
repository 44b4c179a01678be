#pragma once
/// \file jacobian_assembler.hpp
/// Assembles the force Jacobians and the linearised implicit Euler system into a fixed 3x3-block
/// pattern: fills the `LinearSystem` (linalg/linear_system.hpp) the solvers are handed.
///
/// The pattern is built once per cloth, together with each block row's incident springs in
/// ascending order. A step then writes every value in place (no zeroing, no triplets, no search, no
/// allocation) in two passes, each split statically over the threads:
/// 1. per spring: the symmetric (6 values; 9 for the Exact variant) block
///    \f$ C = \Delta t D + \Delta t^2 K \f$ into the system's edge operator and the spring's
///    right-hand-side term \f$ g \f$ into a scratch array; no two springs write the same place;
/// 2. per block row: the diagonal block (mass plus the incident springs' C), the off-diagonal
///    blocks (-C) and the right-hand side, gathered from pass 1.
/// So one barrier separates the passes (scattering into blocks would need one per spring colour),
/// and every value is summed in the same order (ascending springs) whatever the thread count.
/// The cloth's force terms (core/force_term.hpp) are added afterwards (on the team if they share
/// work, else on one thread): their force into b and their derivative blocks into A. Diagonal
/// blocks (air drag) also go to the edge operator's row blocks, so it stays valid; an off-diagonal
/// one marks it invalid for the step.
///
/// System (Baraff & Witkin 1998), with per-spring \f$ C = \Delta t D + \Delta t^2 K \f$
/// (spring_jacobian.hpp):
/// \f[ A = M - \Delta t \frac{\partial f}{\partial v} - \Delta t^2 \frac{\partial f}{\partial x}, \qquad
///     A_{aa} \mathrel{+}= C,\; A_{bb} \mathrel{+}= C,\; A_{ab} \mathrel{-}= C,\; A_{ba} \mathrel{-}= C, \f]
/// \f[ b = \Delta t \Bigl(f + \Delta t \frac{\partial f}{\partial x} v\Bigr), \qquad
///     b_a \mathrel{+}= g,\; b_b \mathrel{-}= g, \quad g = \Delta t (f_a + \Delta t K w). \f]

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "drape/config.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/linalg/block3.hpp"
#include "drape/linalg/linear_system.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/detail/jacobian_assembler_avx2.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"

namespace drape {

/// How pinned nodes enter the linear system.
enum class PinTreatment : std::uint8_t {
  Eliminate = 0,  ///< pinned DOFs are not in the system (any solver)
  Filter = 1,     ///< every node is in the system; pinned rows are fixed constraints (iterative solvers)
};

template <>
struct EnumNames<PinTreatment> {
  static constexpr const char* parameter = "pin_treatment";
  static constexpr std::array<EnumName<PinTreatment>, 2> values{
      {{PinTreatment::Eliminate, "eliminate"}, {PinTreatment::Filter, "filter"}}};
};

template <class Scalar = double>
class JacobianAssembler {
 public:
  static constexpr long long min_springs_per_thread = 4096;

  /// \param threads 0 = all available.
  explicit JacobianAssembler(const Cloth<Scalar>& cloth, PinTreatment pins = PinTreatment::Eliminate, int threads = 0)
      : JacobianAssembler(cloth, cloth.pins().nodes(), pins, threads) {}
  /// With `held` (sorted node ids) as the nodes whose velocity stays 0 instead of the cloth's pins:
  /// eliminated, or fixed rows under PinTreatment::Filter (an integrator's current pins that hold).
  JacobianAssembler(const Cloth<Scalar>& cloth, const std::vector<int>& held, PinTreatment pins, int threads);
  /// The assembler keeps a reference to the cloth: a temporary would dangle.
  JacobianAssembler(const Cloth<Scalar>&& cloth, PinTreatment pins = PinTreatment::Eliminate, int threads = 0) = delete;
  JacobianAssembler(const Cloth<Scalar>&& cloth, const std::vector<int>& held, PinTreatment pins, int threads) = delete;

  const Cloth<Scalar>& cloth() const { return *m_cloth; }
  PinTreatment pin_treatment() const { return m_pins; }
  /// Number of block rows (nodes in the system).
  int system_nodes() const { return static_cast<int>(m_node_of_row.size()); }
  /// Row of a node, -1 for eliminated (pinned) nodes.
  const std::vector<int>& row_of_node() const { return m_row_of_node; }
  const std::vector<int>& node_of_row() const { return m_node_of_row; }
  int threads() const { return effective_threads(m_threads, m_cloth->springs().size(), min_springs_per_thread); }

  /// A system for this cloth, values zero: the pattern (springs and the force terms' couplings),
  /// the edge operator's structure, the lattice layout, the constraints (the pinned rows fixed
  /// under PinTreatment::Filter) and b. Allocates; once per integrator.
  LinearSystem<Scalar> make_system() const;
  /// A matrix with the system's pattern (values zero).
  BlockSparseMatrix<Scalar> make_matrix() const { return m_pattern; }

  /// The system's A (blocks and, unless force terms add derivatives, the edge operator: symmetric
  /// unless `variant` is Exact) and b, for positions x, velocities v (3 x n) at `time`, step `dt`.
  /// `system` must come from make_system(). No allocation. Uses scratch memory of the assembler:
  /// do not call concurrently on the same assembler.
  void assemble_system(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time, Scalar dt,
                       JacobianVariant variant, LinearSystem<Scalar>& system) const;

  /// df/dx and df/dv restricted to the system's rows and columns (matrices from make_matrix()).
  void assemble_jacobians(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time,
                          JacobianVariant variant, BlockSparseMatrix<Scalar>& dfdx,
                          BlockSparseMatrix<Scalar>& dfdv) const;

 private:
  /// A spring incident on a block row; each row lists its springs in ascending order.
  struct Incidence {
    int spring;
    int block;   // off-diagonal block (this row, other end); -1 if the other end is eliminated
    int node_b;  // 1 if this row is the spring's node b (its right-hand side gets -g)
  };
  /// The force terms' derivative blocks into a system: A -= dt dfdv + dt^2 dfdx, b += dt^2 dfdx v.
  class SystemTermBlocks;
  /// The force terms' derivative blocks into df/dx, df/dv.
  class JacobianTermBlocks;

  template <class Body>
  void for_each_spring(Body&& body) const;
  template <bool Symmetric>
  void write_system(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar dt, JacobianVariant variant,
                    LinearSystem<Scalar>& system) const;
  /// The force terms' share of the system (after write_system()).
  void add_terms(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time, Scalar dt,
                 JacobianVariant variant, LinearSystem<Scalar>& system) const;
  /// Block of (node a's row, node b's row); -1 if either is eliminated. \throws std::logic_error if
  /// a force term writes a pair it did not declare in coupled_nodes().
  int term_block(const BlockSparseMatrix<Scalar>& a, int node_a, int node_b) const;

  const Cloth<Scalar>* m_cloth;
  PinTreatment m_pins;
  int m_threads;
  std::vector<int> m_held;  // nodes whose velocity stays 0
  std::vector<int> m_row_of_node, m_node_of_row;
  std::vector<std::array<int, 6>> m_slots;  // per spring: row a, row b, block aa, bb, ab, ba (-1 = none)
  std::vector<int> m_incidence_begin;       // per row, into m_incidence
  std::vector<Incidence> m_incidence;
  /// g of every spring, grouped like the edge values (EdgeOperator::value_index() with stride 3),
  /// written by pass 1.
  mutable std::vector<Scalar> m_spring_rhs;
  BlockSparseMatrix<Scalar> m_pattern;
  EdgeOperator<Scalar> m_edges;            // structure only
  bool m_term_derivatives = false;         // some force term adds derivative blocks
  std::vector<int> m_term_only_blocks;     // off-diagonal blocks only force terms write (zeroed first)
  mutable Matrix3X<Scalar> m_term_forces;  // the force terms' total (3 x n; empty without terms)
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
JacobianAssembler<Scalar>::JacobianAssembler(const Cloth<Scalar>& cloth, const std::vector<int>& held,
                                             PinTreatment pins, int threads)
    : m_cloth(&cloth), m_pins(pins), m_threads(threads), m_held(held) {
  const int n = cloth.node_count();
  Pins::validate(held, n);
  std::vector<std::uint8_t> is_held(static_cast<std::size_t>(n), 0);
  for (int node : held) is_held[static_cast<std::size_t>(node)] = 1;
  m_row_of_node.assign(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    if (is_held[static_cast<std::size_t>(i)] != 0 && pins == PinTreatment::Eliminate) continue;
    m_row_of_node[static_cast<std::size_t>(i)] = static_cast<int>(m_node_of_row.size());
    m_node_of_row.push_back(i);
  }
  const SpringSet<Scalar>& sp = cloth.springs();
  const std::size_t rows = m_node_of_row.size();
  const auto row = [&](int node) { return m_row_of_node[static_cast<std::size_t>(node)]; };
  std::vector<std::vector<int>> columns(rows);
  for (int s = 0; s < sp.size(); ++s) {
    const int ra = row(sp.a()[s]), rb = row(sp.b()[s]);
    if (ra >= 0 && rb >= 0) {
      columns[static_cast<std::size_t>(ra)].push_back(rb);
      columns[static_cast<std::size_t>(rb)].push_back(ra);
    }
  }
  // Force terms: their coupled node pairs join the pattern (both ways: it stays symmetric).
  std::vector<std::array<int, 2>> term_pairs;
  for (const auto& term : cloth.force_terms()) {
    if (!term->has_derivatives()) continue;
    m_term_derivatives = true;
    for (const std::array<int, 2>& pair : term->coupled_nodes()) {
      for (int node : pair)
        if (node < 0 || node >= n)
          detail::fail_argument("coupled node of force term '" + term->name() + "'", detail::to_text(node),
                                "[0, " + detail::to_text(n - 1) + "]");
      const int ra = row(pair[0]), rb = row(pair[1]);
      if (ra < 0 || rb < 0 || ra == rb) continue;
      columns[static_cast<std::size_t>(ra)].push_back(rb);
      columns[static_cast<std::size_t>(rb)].push_back(ra);
      term_pairs.push_back({ra, rb});
    }
  }
  m_pattern = BlockSparseMatrix<Scalar>(std::move(columns));
  // Edge operator (linalg/edge_operator.hpp): one edge per spring, in the springs' colours.
  std::vector<int> edge_rows(2 * static_cast<std::size_t>(sp.size()));
  for (int s = 0; s < sp.size(); ++s) {
    edge_rows[2 * static_cast<std::size_t>(s)] = row(sp.a()[s]);
    edge_rows[2 * static_cast<std::size_t>(s) + 1] = row(sp.b()[s]);
  }
  std::vector<Scalar> row_mass(rows);
  for (std::size_t r = 0; r < rows; ++r) row_mass[r] = cloth.masses()[m_node_of_row[r]];
  m_edges = EdgeOperator<Scalar>(std::move(edge_rows), sp.colour_begin(), std::move(row_mass));
  m_slots.resize(static_cast<std::size_t>(sp.size()));
  for (int s = 0; s < sp.size(); ++s) {
    const int ra = row(sp.a()[s]), rb = row(sp.b()[s]);
    const bool both = ra >= 0 && rb >= 0;
    m_slots[static_cast<std::size_t>(s)] = {ra,
                                            rb,
                                            ra >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(ra)] : -1,
                                            rb >= 0 ? m_pattern.diagonal()[static_cast<std::size_t>(rb)] : -1,
                                            both ? m_pattern.find(ra, rb) : -1,
                                            both ? m_pattern.find(rb, ra) : -1};
  }
  // Incidence lists, filled in ascending spring order.
  m_incidence_begin.assign(rows + 1, 0);
  for (const std::array<int, 6>& slot : m_slots)
    for (int side = 0; side < 2; ++side)
      if (slot[static_cast<std::size_t>(side)] >= 0)
        ++m_incidence_begin[static_cast<std::size_t>(slot[static_cast<std::size_t>(side)]) + 1];
  for (std::size_t r = 0; r < rows; ++r) m_incidence_begin[r + 1] += m_incidence_begin[r];
  m_incidence.resize(static_cast<std::size_t>(m_incidence_begin.back()));
  std::vector<int> next(m_incidence_begin.begin(), m_incidence_begin.end() - 1);
  std::vector<std::uint8_t> spring_block(static_cast<std::size_t>(m_pattern.block_count()), 0);
  for (int s = 0; s < sp.size(); ++s) {
    const std::array<int, 6>& slot = m_slots[static_cast<std::size_t>(s)];
    for (int side = 0; side < 2; ++side) {
      const int r = slot[static_cast<std::size_t>(side)];
      if (r < 0) continue;
      const int block = slot[4 + static_cast<std::size_t>(side)];
      if (block >= 0) {
        // Springs join distinct node pairs (spring_set.hpp), so each off-diagonal block is one spring's -C.
        DRAPE_ASSERT(!spring_block[static_cast<std::size_t>(block)],
                     "JacobianAssembler: two springs join the same nodes");
        spring_block[static_cast<std::size_t>(block)] = 1;
      }
      m_incidence[static_cast<std::size_t>(next[static_cast<std::size_t>(r)]++)] = Incidence{s, block, side};
    }
  }
  m_spring_rhs.assign(std::size_t(sp.size() + 3) / 4 * 12, Scalar(0));
  // Blocks that only force terms write: the row pass leaves them alone, so they are zeroed first.
  for (const std::array<int, 2>& pair : term_pairs)
    for (const int block : {m_pattern.find(pair[0], pair[1]), m_pattern.find(pair[1], pair[0])})
      if (!spring_block[static_cast<std::size_t>(block)]) {
        spring_block[static_cast<std::size_t>(block)] = 1;
        m_term_only_blocks.push_back(block);
      }
  if (!cloth.force_terms().empty()) m_term_forces.setZero(3, n);
  if (m_term_derivatives) m_edges.enable_row_blocks();  // for terms whose blocks are diagonal
}

template <class Scalar>
LinearSystem<Scalar> JacobianAssembler<Scalar>::make_system() const {
  LinearSystem<Scalar> system;
  system.matrix = m_pattern;
  system.edges = m_edges;
  if (m_cloth->is_grid()) system.layout = GridLayout{m_cloth->grid().nx(), m_cloth->grid().ny(), m_row_of_node};
  system.constraints = ConstraintFilter<Scalar>(system_nodes());
  if (m_pins == PinTreatment::Filter)
    for (int node : m_held) system.constraints.fix(m_row_of_node[static_cast<std::size_t>(node)]);
  system.rhs.setZero(3 * static_cast<Index>(system_nodes()));
  return system;
}

template <class Scalar>
template <class Body>
void JacobianAssembler<Scalar>::for_each_spring(Body&& body) const {
  const std::vector<int>& colour = m_cloth->springs().colour_begin();
  const int colours = m_cloth->springs().colour_count();
  run_in_team(threads(), [&] {
    for (int c = 0; c < colours; ++c) team_for(colour[c], colour[c + 1], body);
  });
}

template <class Scalar>
void JacobianAssembler<Scalar>::assemble_system(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time,
                                                Scalar dt, JacobianVariant variant,
                                                LinearSystem<Scalar>& system) const {
  DRAPE_ASSERT(system.matrix.block_count() == m_pattern.block_count(),
               "assemble_system(): system not made by make_system()");
  DRAPE_ASSERT(system.rhs.size() == 3 * system_nodes(), "assemble_system(): rhs has the wrong size");
  if (system.edges.edge_count() != m_edges.edge_count()) system.edges = m_edges;  // the caller dropped it: restore
  if (variant == JacobianVariant::Exact)
    write_system<false>(x, v, dt, variant, system);
  else
    write_system<true>(x, v, dt, variant, system);
  system.edges.set_valid(variant != JacobianVariant::Exact);
  if (!m_cloth->force_terms().empty()) add_terms(x, v, time, dt, variant, system);
}

template <class Scalar>
int JacobianAssembler<Scalar>::term_block(const BlockSparseMatrix<Scalar>& a, int node_a, int node_b) const {
  const int ra = m_row_of_node[static_cast<std::size_t>(node_a)], rb = m_row_of_node[static_cast<std::size_t>(node_b)];
  if (ra < 0 || rb < 0) return -1;
  const int block = ra == rb ? a.diagonal()[static_cast<std::size_t>(ra)] : a.find(ra, rb);
  if (block < 0)
    throw std::logic_error("drape: a force term wrote the block of nodes " + detail::to_text(node_a) + " and " +
                           detail::to_text(node_b) + " without listing the pair in coupled_nodes()");
  return block;
}

template <class Scalar>
class JacobianAssembler<Scalar>::SystemTermBlocks final : public ForceDerivatives<Scalar> {
 public:
  SystemTermBlocks(const JacobianAssembler& assembler, const ConstRef3X<Scalar>& v, Scalar dt,
                   LinearSystem<Scalar>& system, bool symmetric)
      : m_assembler(assembler),
        m_v(v),
        m_dt(dt),
        m_system(system),
        m_row_blocks(system.edges.row_blocks()),
        m_symmetric(symmetric) {}
  bool symmetric() const override { return m_symmetric; }
  void add(int a, int b, const Mat3<Scalar>& dfdx, const Mat3<Scalar>& dfdv) override {
    const int ra = m_assembler.m_row_of_node[static_cast<std::size_t>(a)];
    if (ra < 0) return;
    const Scalar dt2 = m_dt * m_dt;
    // b += dt^2 (df/dx) v for every column, eliminated or not.
    const std::array<Scalar, 3> kv = block_times(dfdx.data(), m_v.data() + 3 * static_cast<Index>(b));
    Scalar* rhs = m_system.rhs.data() + 3 * static_cast<Index>(ra);
    for (int k = 0; k < 3; ++k) rhs[k] += dt2 * kv[static_cast<std::size_t>(k)];
    std::array<Scalar, 9> d;  // A -= dt df/dv + dt^2 df/dx
    for (int q = 0; q < 9; ++q) d[static_cast<std::size_t>(q)] = m_dt * dfdv.data()[q] + dt2 * dfdx.data()[q];
    subtract(a, b, ra, d);
  }
  void add_velocity(int a, int b, const Mat3<Scalar>& dfdv) override {
    const int ra = m_assembler.m_row_of_node[static_cast<std::size_t>(a)];
    if (ra < 0) return;
    std::array<Scalar, 9> d;  // A -= dt df/dv
    for (int q = 0; q < 9; ++q) d[static_cast<std::size_t>(q)] = m_dt * dfdv.data()[q];
    subtract(a, b, ra, d);
  }
  /// True if every block the terms wrote lies on the diagonal: the edge form, with its row blocks,
  /// still describes A.
  bool edge_form_kept() const { return m_row_blocks && m_diagonal_only.load(std::memory_order_relaxed); }

 private:
  /// Block (a, b) of A -= d. A diagonal block goes to the edge form's row block too (the terms'
  /// whole share of it); any other block ends the edge form for this step.
  void subtract(int a, int b, int row_a, const std::array<Scalar, 9>& d) {
    const int block = m_assembler.term_block(m_system.matrix, a, b);
    if (block < 0) return;
    Scalar* values = m_system.matrix.values() + 9 * static_cast<Index>(block);
    for (std::size_t q = 0; q < 9; ++q) values[q] -= d[q];
    if (a == b && m_row_blocks) {
      Scalar* row_block = m_row_blocks + 9 * static_cast<Index>(row_a);
      for (std::size_t q = 0; q < 9; ++q) row_block[q] -= d[q];
    } else {
      m_diagonal_only.store(false, std::memory_order_relaxed);
    }
  }

  const JacobianAssembler& m_assembler;
  const ConstRef3X<Scalar>& m_v;
  Scalar m_dt;
  LinearSystem<Scalar>& m_system;
  Scalar* m_row_blocks;
  bool m_symmetric;
  std::atomic<bool> m_diagonal_only{true};
};

template <class Scalar>
class JacobianAssembler<Scalar>::JacobianTermBlocks final : public ForceDerivatives<Scalar> {
 public:
  JacobianTermBlocks(const JacobianAssembler& assembler, BlockSparseMatrix<Scalar>& dfdx,
                     BlockSparseMatrix<Scalar>& dfdv, bool symmetric)
      : m_assembler(assembler), m_dfdx(dfdx), m_dfdv(dfdv), m_symmetric(symmetric) {}
  bool symmetric() const override { return m_symmetric; }
  void add(int a, int b, const Mat3<Scalar>& dfdx, const Mat3<Scalar>& dfdv) override {
    const int block = m_assembler.term_block(m_dfdx, a, b);
    if (block < 0) return;
    m_dfdx.block(block) += dfdx;
    m_dfdv.block(block) += dfdv;
  }

 private:
  const JacobianAssembler& m_assembler;
  BlockSparseMatrix<Scalar>& m_dfdx;
  BlockSparseMatrix<Scalar>& m_dfdv;
  bool m_symmetric;
};

template <class Scalar>
void JacobianAssembler<Scalar>::add_terms(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time,
                                          Scalar dt, JacobianVariant variant, LinearSystem<Scalar>& system) const {
  m_term_forces.setZero();
  if (m_term_derivatives) {
    for (int block : m_term_only_blocks) system.matrix.block(block).setZero();
    if (system.edges.row_blocks()) std::fill_n(system.edges.row_blocks(), 9 * system_nodes(), Scalar(0));
    SystemTermBlocks blocks(*this, v, dt, system, variant != JacobianVariant::Exact);
    add_term_forces_and_derivatives<Scalar>(m_cloth->force_terms(), threads(), x, v, time, m_term_forces, blocks);
    if (blocks.edge_form_kept())
      system.edges.set_valid(variant != JacobianVariant::Exact, true);
    else
      system.edges.invalidate();  // it has no room for off-diagonal term blocks
  } else {
    add_term_forces<Scalar>(m_cloth->force_terms(), threads(), x, v, time, m_term_forces);
  }
  for (int r = 0; r < system_nodes(); ++r) {
    const Scalar* f = m_term_forces.data() + 3 * static_cast<Index>(m_node_of_row[static_cast<std::size_t>(r)]);
    for (int k = 0; k < 3; ++k) system.rhs[3 * static_cast<Index>(r) + k] += dt * f[k];
  }
}

template <class Scalar>
template <bool Symmetric>
void JacobianAssembler<Scalar>::write_system(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar dt,
                                             JacobianVariant variant, LinearSystem<Scalar>& system) const {
  constexpr int stride = Symmetric ? 6 : 9;  // edge-form values per spring
  const SpringSet<Scalar>& sp = m_cloth->springs();
  const int springs = sp.size();
  const int rows = system_nodes();
  const int* ia = sp.a().data();
  const int* ib = sp.b().data();
  const Scalar* rest = sp.rest_length().data();
  const Scalar* ks = sp.stiffness().data();
  const Scalar* kd = sp.damping().data();
  const Scalar* masses = m_cloth->masses().data();
  const int* node_of_row = m_node_of_row.data();
  const int* diagonal = system.matrix.diagonal().data();
  const int* incidence_begin = m_incidence_begin.data();
  const Incidence* incidence = m_incidence.data();
  const Vec3<Scalar> gravity = m_cloth->gravity();
  const Scalar dt2 = dt * dt;
  Scalar* blocks = system.edges.values();
  Scalar* g_all = m_spring_rhs.data();
  Scalar* values = system.matrix.values();
  Scalar* b = system.rhs.data();

  // Pass 1, per spring: C = p u u^T + q I (+ r u w^T, Exact) and g = dt (phi u + dt K w) with
  // K w = (k_uu w.u + k_uw w.w) u + k_i w.
  const auto spring = [&](int s) {
    const SpringLinearisation<Scalar> l = linearise_spring<Scalar>(x.col(ia[s]), x.col(ib[s]), v.col(ia[s]),
                                                                   v.col(ib[s]), rest[s], ks[s], kd[s], variant);
    const Scalar p = dt * kd[s] + dt2 * l.k_uu;
    const Scalar q = dt2 * l.k_i;
    const Scalar u0 = l.u[0], u1 = l.u[1], u2 = l.u[2];
    Scalar c[stride];
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
    for (int k = 0; k < stride; ++k) blocks[EdgeOperator<Scalar>::value_index(s, k, stride)] = c[k];
    for (int k = 0; k < 3; ++k) g_all[EdgeOperator<Scalar>::value_index(s, k, 3)] = g_u * l.u[k] + q * l.w[k];
  };
  constexpr int group = EdgeOperator<Scalar>::group;
  const int groups = (springs + group - 1) / group;
#if DRAPE_AVX2_DISPATCH
  constexpr bool vectorised = Symmetric && std::is_same_v<Scalar, double>;
  const bool avx2 = vectorised && instruction_set() == InstructionSet::Avx2;
#endif
  const auto spring_pass = [&]() {
    team_for(groups, [&](int g) {
      const int first = g * group, last = std::min(springs, first + group);
#if DRAPE_AVX2_DISPATCH
      if constexpr (vectorised) {
        if (avx2 && last - first == group) {
          detail::symmetric_spring_group_avx2(x.data(), v.data(), ia + first, ib + first, rest + first, ks + first,
                                              kd + first, dt, variant == JacobianVariant::Spd,
                                              blocks + EdgeOperator<Scalar>::value_index(first, 0, stride),
                                              g_all + EdgeOperator<Scalar>::value_index(first, 0, 3));
          return;
        }
      }
#endif
      for (int s = first; s < last; ++s) spring(s);
    });
  };
  // The full 3x3 block (column-major) of a spring's stored C.
  const auto expand = [](const Scalar* c, Scalar* full) {
    if constexpr (Symmetric) {
      expand_symmetric_block(c, full);
    } else {
      for (int k = 0; k < 9; ++k) full[k] = c[k];
    }
  };
  // Pass 2, per block row: diagonal m I + sum C, off-diagonal -C, b = dt m g + sum (+-g).
  const auto row_pass = [&]() {
    team_for(rows, [&](int row) {
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
        // Value q of a spring lies `group` places after value q - 1 (EdgeOperator::value_index()).
        const Scalar* spring_c = blocks + EdgeOperator<Scalar>::value_index(in.spring, 0, stride);
        const Scalar* spring_g = g_all + EdgeOperator<Scalar>::value_index(in.spring, 0, 3);
        Scalar c[stride];
        for (int q = 0; q < stride; ++q) c[q] = spring_c[std::size_t(group) * std::size_t(q)];
        for (int q = 0; q < stride; ++q) diag[q] += c[q];
        if (in.block >= 0) {
          Scalar full[9];
          expand(c, full);
          Scalar* off = values + 9 * in.block;
          for (int q = 0; q < 9; ++q) off[q] = -full[q];
        }
        const Scalar g[3] = {spring_g[0], spring_g[group], spring_g[2 * group]};
        if (in.node_b) {
          b0 -= g[0];
          b1 -= g[1];
          b2 -= g[2];
        } else {
          b0 += g[0];
          b1 += g[1];
          b2 += g[2];
        }
      }
      expand(diag, values + 9 * diagonal[row]);
      b[3 * row] = b0;
      b[3 * row + 1] = b1;
      b[3 * row + 2] = b2;
    });
  };
  run_in_team(threads(), [&] {
    spring_pass();  // its barrier publishes C and g to the row pass
    row_pass();
  });
}

template <class Scalar>
void JacobianAssembler<Scalar>::assemble_jacobians(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v,
                                                   Scalar time, JacobianVariant variant,
                                                   BlockSparseMatrix<Scalar>& dfdx,
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
    if (slot[2] >= 0) {
      dfdx.block(slot[2]) -= d.dfdx;
      dfdv.block(slot[2]) -= d.dfdv;
    }
    if (slot[3] >= 0) {
      dfdx.block(slot[3]) -= d.dfdx;
      dfdv.block(slot[3]) -= d.dfdv;
    }
    if (slot[4] >= 0) {
      dfdx.block(slot[4]) += d.dfdx;
      dfdv.block(slot[4]) += d.dfdv;
    }
    if (slot[5] >= 0) {
      dfdx.block(slot[5]) += d.dfdx;
      dfdv.block(slot[5]) += d.dfdv;
    }
  });
  if (!m_term_derivatives) return;
  JacobianTermBlocks blocks(*this, dfdx, dfdv, variant != JacobianVariant::Exact);
  add_term_derivatives<Scalar>(m_cloth->force_terms(), threads(), x, v, time, blocks);
}

}  // namespace drape
