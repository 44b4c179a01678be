#pragma once
/// \file force_assembler.hpp
/// Total force on every node: the damped springs (spring_kernel.hpp), gravity \f$ m_i g \f$ and
/// the cloth's further force terms (core/force_term.hpp).
///
/// Forces are computed for pinned nodes too (the negative of a pinned node's force is the reaction
/// its pin exerts, see diagnostics.hpp); the integrators ignore them.
///
/// Three phases with a barrier after each of the first two (spring_families.hpp explains the
/// storage):
/// 0. `copy_input`: the positions and velocities (3 x n, the components of a node side by side)
///    copied to one array per component, so that the spring pass loads whole vectors instead of
///    every third value (the copy costs a fraction of what the strided loads cost, measured).
/// 1. `spring_pass`: every spring's force on its first node, run by run, into per-family force
///    slots. A run's ends are contiguous in memory, so the loop vectorises (SSE2 by default).
/// 2. `node_pass`: every node sums gravity, its springs' slots and the force terms' share, in
///    blocks of `block_nodes` nodes, in a fixed order: results are bitwise identical for any
///    thread count.
/// A cloth that is not a grid (an irregular mesh) has as many spring offsets as springs, so phases 1
/// and 2 take the general form there: every spring's force into a per-spring array (its nodes'
/// values gathered, the arithmetic vectorised as a grid's), then every node sums its incident
/// springs' forces from a list made once (ascending spring order). The
/// phases and their barriers are the same, so the integrators do not tell the two apart.
/// Force terms are evaluated before phase 2 by `evaluate_terms` (those that share work on the
/// team, the others on one thread; nothing to do without terms). The phases are public so that an
/// integrator can fuse its own node updates into phase 2 and run a whole step in one parallel
/// region (rk2.hpp).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "drape/config.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/detail/force_assembler_avx2.hpp"
#include "drape/physics/spring_families.hpp"
#include "drape/physics/spring_kernel.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/team.hpp"
#include "drape/platform/vector_sqrt.hpp"

namespace drape {

/// Read-only node data by component: component k of node i at `p[k][i]`.
template <class Scalar>
struct NodeView {
  const Scalar* p[3];
};

/// Total forces of the nodes [begin, begin + count): component k of node begin + j is `f[k][j]`.
template <class Scalar>
struct ForceBlock {
  Index begin;
  int count;
  const Scalar* f[3];
};

template <class Scalar = double>
class ForceAssembler {
 public:
  /// Springs per thread below which extra threads are not woken (measured).
  static constexpr long long min_springs_per_thread = 2048;
  /// Nodes per block of node_pass: fixed, so the work per node does not depend on the threads.
  static constexpr int block_nodes = 64;

  /// \param threads 0 = all available (max_threads()).
  explicit ForceAssembler(const Cloth<Scalar>& cloth, int threads = 0);
  /// The assembler keeps a reference to the cloth: a temporary would dangle.
  ForceAssembler(const Cloth<Scalar>&& cloth, int threads = 0) = delete;

  /// `f = spring forces(x, v) + M g + force terms(x, v, time)`, `3 x n`; `f` must already have the
  /// right size. Not for concurrent calls on the same object (it uses the object's scratch memory).
  void force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time, Ref3X<Scalar> f) const;

  const Cloth<Scalar>& cloth() const { return *m_cloth; }
  int threads() const { return effective_threads(m_threads, m_cloth->springs().size(), min_springs_per_thread); }
  /// The springs by family (a grid cloth; an irregular mesh takes the general path).
  /// \throws std::logic_error for a cloth that is not a grid.
  const SpringFamilies<Scalar>& families() const {
    if (!m_families) throw std::logic_error("drape: ForceAssembler::families() of a cloth that is not a grid");
    return *m_families;
  }

  /// Phase 0 for this thread's share of the nodes: `x` and `v` (3 x n) into input_positions() and
  /// input_velocities() (call from every thread of a team, then team_barrier() before the spring
  /// pass reads them).
  void copy_input(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v) const;
  /// The data of the last copy_input(), one array per component.
  NodeView<Scalar> input_positions() const { return component_view(0); }
  NodeView<Scalar> input_velocities() const { return component_view(3); }

  /// Phase 1 for this thread's share of the runs (call from every thread of a team, then
  /// team_barrier() before node_pass).
  void spring_pass(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const;

  /// True if the cloth has force terms besides springs and gravity.
  bool has_terms() const { return !m_cloth->force_terms().empty(); }
  /// The force terms' total at (x, v, time) for the next node_pass (call outside the team). Does
  /// nothing without terms.
  void evaluate_terms(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time) const;
  /// evaluate_terms() by every thread of the running team, before the barrier that precedes
  /// node_pass; the team waits at the end.
  void evaluate_terms_in_team(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time) const;

  /// Phase 2 for this thread's share of the node blocks: calls `fn(const ForceBlock<Scalar>&)` with
  /// each block's total forces. No barrier at the end. Runs as AVX2 when spring_pass() does, `fn`
  /// included where the compiler inlines it.
  template <class BlockFn>
  void node_pass(BlockFn&& fn) const {
    if (!m_families) {
      node_pass_general(fn);
      return;
    }
#if DRAPE_AVX2_DISPATCH
    if (instruction_set() == InstructionSet::Avx2) {
      node_pass_avx2(fn);
      return;
    }
#endif
    node_pass_loops(fn);
  }

 private:
  /// spring_pass's loops, compiled once for the baseline instruction set and once for AVX2
  /// (instruction_set.hpp): inlined into each caller, so each caller's target applies.
  template <bool Avx2>
  DRAPE_INLINE_LOOP void spring_pass_loops(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const;
  /// copy_input's loop, inlined into both versions like spring_pass_loops.
  DRAPE_INLINE_LOOP void copy_input_loops(const Scalar* x, const Scalar* v) const;
#if DRAPE_AVX2_DISPATCH
  __attribute__((target("avx2"))) void spring_pass_avx2(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const {
    spring_pass_loops<true>(x, v);
  }
  __attribute__((target("avx2"))) void copy_input_avx2(const Scalar* x, const Scalar* v) const {
    copy_input_loops(x, v);
  }
#endif

  /// node_pass's loops, inlined into both versions like spring_pass_loops.
  template <class BlockFn>
  DRAPE_INLINE_LOOP void node_pass_loops(BlockFn& fn) const;
#if DRAPE_AVX2_DISPATCH
  template <class BlockFn>
  __attribute__((target("avx2"))) void node_pass_avx2(BlockFn& fn) const {
    node_pass_loops(fn);
  }
#endif

  /// The general form of phases 1 and 2 (the file comment).
  void spring_pass_general(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const;
  template <class BlockFn>
  void node_pass_general(BlockFn& fn) const;

  /// `out[j] = (start ? start[j] : mass[j] * g) + sum over q < K of (as_first[q][j] - as_second[q][j])`,
  /// summed in q order.
  template <int K>
  static DRAPE_INLINE_LOOP void add_families(Scalar* out, const Scalar* start, const Scalar* mass, Scalar g,
                                             const Scalar* const* as_first, const Scalar* const* as_second, int count) {
    DRAPE_OMP_SIMD
    for (Index j = 0; j < count; ++j) {
      Scalar t = start ? start[j] : mass[j] * g;
      for (int q = 0; q < K; ++q) t += as_first[q][j] - as_second[q][j];
      out[j] = t;
    }
  }

  /// Component k of the input's positions (first = 0) or velocities (first = 3).
  Scalar* input(int first, int k) const {
    return m_input.data() + std::size_t(first + k) * std::size_t(m_cloth->node_count());
  }
  NodeView<Scalar> component_view(int first) const { return {{input(first, 0), input(first, 1), input(first, 2)}}; }

  Scalar* slots(int family, int component) const {
    return m_slots.data() + (std::size_t(family) * 3 + std::size_t(component)) * std::size_t(m_families->slot_count()) +
           std::size_t(m_families->padding());
  }

  const Cloth<Scalar>* m_cloth;
  int m_threads;
  std::optional<SpringFamilies<Scalar>> m_families;  // grid cloths only
  /// General path: spring s's force on its node a at [k * springs + s], component k.
  mutable std::vector<Scalar> m_spring_forces;
  /// General path: node i's springs at [m_incident_begin[i], m_incident_begin[i + 1]) of
  /// m_incident, spring s as s + 1 where i is its node a and as -(s + 1) where i is its node b.
  std::vector<int> m_incident_begin, m_incident;
  /// Per family and component: the force of the spring whose first node is i at slot i, 0 where
  /// there is no spring (those slots are never written).
  mutable std::vector<Scalar> m_slots;
  /// copy_input()'s arrays: positions x, y, z, then velocities x, y, z, n values each.
  mutable std::vector<Scalar> m_input;
  /// The force terms' total of the last evaluate_terms() (3 x n; empty without terms).
  mutable Matrix3X<Scalar> m_term_forces;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
ForceAssembler<Scalar>::ForceAssembler(const Cloth<Scalar>& cloth, int threads)
    : m_cloth(&cloth),
      m_threads(threads),
      m_input(6 * std::size_t(cloth.node_count())) {
  if (has_terms()) m_term_forces.setZero(3, cloth.node_count());
  const SpringSet<Scalar>& springs = cloth.springs();
  if (cloth.is_grid()) {
    m_families.emplace(springs, cloth.node_count());
    m_slots.assign(std::size_t(m_families->family_count()) * 3 * std::size_t(m_families->slot_count()), Scalar(0));
    return;
  }
  m_spring_forces.assign(3 * std::size_t(springs.size()), Scalar(0));
  m_incident_begin.assign(std::size_t(cloth.node_count()) + 1, 0);
  for (int s = 0; s < springs.size(); ++s) {
    ++m_incident_begin[std::size_t(springs.a()[std::size_t(s)]) + 1];
    ++m_incident_begin[std::size_t(springs.b()[std::size_t(s)]) + 1];
  }
  for (std::size_t i = 1; i < m_incident_begin.size(); ++i) m_incident_begin[i] += m_incident_begin[i - 1];
  m_incident.resize(std::size_t(m_incident_begin.back()));
  std::vector<int> next(m_incident_begin.begin(), m_incident_begin.end() - 1);
  for (int s = 0; s < springs.size(); ++s) {
    m_incident[std::size_t(next[std::size_t(springs.a()[std::size_t(s)])]++)] = s + 1;
    m_incident[std::size_t(next[std::size_t(springs.b()[std::size_t(s)])]++)] = -(s + 1);
  }
}

template <class Scalar>
void ForceAssembler<Scalar>::evaluate_terms(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v,
                                            Scalar time) const {
  if (!has_terms()) return;
  m_term_forces.setZero();
  add_term_forces<Scalar>(m_cloth->force_terms(), threads(), x, v, time, m_term_forces);
}

template <class Scalar>
void ForceAssembler<Scalar>::evaluate_terms_in_team(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v,
                                                    Scalar time) const {
  if (!has_terms()) return;
  team_single([&] { m_term_forces.setZero(); });
  add_term_forces_in_team<Scalar>(m_cloth->force_terms(), x, v, time, Ref3X<Scalar>(m_term_forces));
}

template <class Scalar>
void ForceAssembler<Scalar>::copy_input(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v) const {
  DRAPE_ASSERT(x.cols() == m_cloth->node_count() && v.cols() == m_cloth->node_count(),
               "copy_input(): x and v must have one column per node");
#if DRAPE_AVX2_DISPATCH
  if (instruction_set() == InstructionSet::Avx2) {
    copy_input_avx2(x.data(), v.data());
    return;
  }
#endif
  copy_input_loops(x.data(), v.data());
}

template <class Scalar>
DRAPE_INLINE_LOOP void ForceAssembler<Scalar>::copy_input_loops(const Scalar* x, const Scalar* v) const {
  const Index n = m_cloth->node_count();
  // Shares of whole blocks, as node_pass: no two threads write to one cache line.
  const auto blocks = even_share((n + block_nodes - 1) / block_nodes, team_rank(), team_size());
  const Index begin = Index(blocks.first) * block_nodes, end = std::min<Index>(n, Index(blocks.second) * block_nodes);
  for (int first = 0; first < 6; first += 3) {
    const Scalar* from = first == 0 ? x : v;
    Scalar *to0 = input(first, 0), *to1 = input(first, 1), *to2 = input(first, 2);
    DRAPE_OMP_SIMD
    for (Index i = begin; i < end; ++i) {
      to0[i] = from[3 * i];
      to1[i] = from[3 * i + 1];
      to2[i] = from[3 * i + 2];
    }
  }
}

template <class Scalar>
void ForceAssembler<Scalar>::spring_pass(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const {
  if (!m_families) {
    spring_pass_general(x, v);
    return;
  }
#if DRAPE_AVX2_DISPATCH
  if (instruction_set() == InstructionSet::Avx2) {
    spring_pass_avx2(x, v);
    return;
  }
#endif
  spring_pass_loops<false>(x, v);
}

template <class Scalar>
template <bool Avx2>
DRAPE_INLINE_LOOP void ForceAssembler<Scalar>::spring_pass_loops(const NodeView<Scalar>& x,
                                                                 const NodeView<Scalar>& v) const {
  constexpr int max_run = SpringFamilies<Scalar>::max_run_length;
  // One run at a time. Baseline: three vectorised loops (d, |d|^2, w.d; sqrt; factor and force),
  // because the compiler vectorises no std::sqrt. AVX2: one loop in registers.
  alignas(64) Scalar d[3][max_run];
  alignas(64) Scalar length[max_run];
  alignas(64) Scalar w_dot_d[max_run];
  const std::vector<typename SpringFamilies<Scalar>::Run>& runs = m_families->runs();
  const std::vector<int>& offsets = m_families->offsets();
  const auto share = m_families->run_share(team_rank(), team_size());
  for (int r = share.first; r < share.second; ++r) {
    const typename SpringFamilies<Scalar>::Run& run = runs[std::size_t(r)];
    const Index a = run.first, b = a + offsets[std::size_t(run.family)];
    const Index count = run.count;
    Scalar* const f[3] = {slots(run.family, 0) + run.first, slots(run.family, 1) + run.first,
                          slots(run.family, 2) + run.first};
#if DRAPE_AVX2_DISPATCH
    if constexpr (Avx2) {
      detail::spring_run_avx2(x, v, a, b, count, run.rest_length, run.stiffness, run.damping, f);
      continue;
    }
#endif
    const Scalar *xa0 = x.p[0] + a, *xa1 = x.p[1] + a, *xa2 = x.p[2] + a;
    const Scalar *xb0 = x.p[0] + b, *xb1 = x.p[1] + b, *xb2 = x.p[2] + b;
    const Scalar *va0 = v.p[0] + a, *va1 = v.p[1] + a, *va2 = v.p[2] + a;
    const Scalar *vb0 = v.p[0] + b, *vb1 = v.p[1] + b, *vb2 = v.p[2] + b;
    DRAPE_OMP_SIMD
    for (Index j = 0; j < count; ++j) {
      const Scalar d0 = xb0[j] - xa0[j];
      const Scalar d1 = xb1[j] - xa1[j];
      const Scalar d2 = xb2[j] - xa2[j];
      d[0][j] = d0;
      d[1][j] = d1;
      d[2][j] = d2;
      length[j] = d0 * d0 + d1 * d1 + d2 * d2;
      w_dot_d[j] = (vb0[j] - va0[j]) * d0 + (vb1[j] - va1[j]) * d1 + (vb2[j] - va2[j]) * d2;
    }
    detail::sqrt_in_place(length, count);
    Scalar *f0 = f[0], *f1 = f[1], *f2 = f[2];
    DRAPE_OMP_SIMD
    for (Index j = 0; j < count; ++j) {
      const Scalar c = spring_force_factor(length[j], w_dot_d[j], run.rest_length, run.stiffness, run.damping);
      f0[j] = c * d[0][j];
      f1[j] = c * d[1][j];
      f2[j] = c * d[2][j];
    }
  }
}

template <class Scalar>
template <class BlockFn>
DRAPE_INLINE_LOOP void ForceAssembler<Scalar>::node_pass_loops(BlockFn& fn) const {
  alignas(64) Scalar total[3][block_nodes];
  const Index n = m_cloth->node_count();
  const Scalar* masses = m_cloth->masses().data();
  const Vec3<Scalar> g = m_cloth->gravity();
  const int families = m_families->family_count();
  const std::vector<int>& offsets = m_families->offsets();
  const bool terms = has_terms();
  const auto share = even_share((n + block_nodes - 1) / block_nodes, team_rank(), team_size());
  for (long long block = share.first; block < share.second; ++block) {
    const Index begin = Index(block) * block_nodes;
    const int count = int(std::min<Index>(block_nodes, n - begin));
    for (int k = 0; k < 3; ++k) {
      // Node i is the first node of slot i and the second node of slot i - offset; families are
      // added three at a time, always in family order.
      const Scalar* as_first[3];
      const Scalar* as_second[3];
      for (int family = 0; family < families || family == 0; family += 3) {
        const int group = std::min(3, families - family);
        for (int q = 0; q < group; ++q) {
          as_first[q] = slots(family + q, k) + begin;
          as_second[q] = as_first[q] - offsets[std::size_t(family + q)];
        }
        const Scalar* start = family == 0 ? nullptr : total[k];
        switch (group) {
          case 3: add_families<3>(total[k], start, masses + begin, g[k], as_first, as_second, count); break;
          case 2: add_families<2>(total[k], start, masses + begin, g[k], as_first, as_second, count); break;
          case 1: add_families<1>(total[k], start, masses + begin, g[k], as_first, as_second, count); break;
          default: add_families<0>(total[k], start, masses + begin, g[k], as_first, as_second, count); break;
        }
      }
      if (terms) {
        const Scalar* extra = m_term_forces.data() + 3 * begin + k;
        for (int j = 0; j < count; ++j) total[k][j] += extra[3 * j];
      }
    }
    fn(ForceBlock<Scalar>{begin, count, {total[0], total[1], total[2]}});
  }
}

template <class Scalar>
void ForceAssembler<Scalar>::spring_pass_general(const NodeView<Scalar>& x, const NodeView<Scalar>& v) const {
  const SpringSet<Scalar>& springs = m_cloth->springs();
  const int count = springs.size();
  const int* a = springs.a().data();
  const int* b = springs.b().data();
  const Scalar* rest = springs.rest_length().data();
  const Scalar* ks = springs.stiffness().data();
  const Scalar* kd = springs.damping().data();
  Scalar* const f[3] = {m_spring_forces.data(), m_spring_forces.data() + count, m_spring_forces.data() + 2 * count};
  const auto share = even_share(count, team_rank(), team_size());
#if DRAPE_AVX2_DISPATCH
  if (instruction_set() == InstructionSet::Avx2) {
    detail::spring_list_avx2(x, v, a, b, rest, ks, kd, share.first, share.second, f);
    return;
  }
#endif
  // Chunks of three loops as spring_pass_loops: gather the differences, the square roots several
  // at a time, then the factors and forces (vectorised).
  constexpr int chunk = SpringFamilies<Scalar>::max_run_length;
  alignas(64) Scalar d[3][chunk];
  alignas(64) Scalar length[chunk];
  alignas(64) Scalar w_dot_d[chunk];
  for (Index first = share.first; first < share.second; first += chunk) {
    const int n = int(std::min<Index>(chunk, share.second - first));
    for (int j = 0; j < n; ++j) {
      const Index p = a[first + j], q = b[first + j];
      const Scalar d0 = x.p[0][q] - x.p[0][p], d1 = x.p[1][q] - x.p[1][p], d2 = x.p[2][q] - x.p[2][p];
      d[0][j] = d0;
      d[1][j] = d1;
      d[2][j] = d2;
      length[j] = d0 * d0 + d1 * d1 + d2 * d2;
      w_dot_d[j] = (v.p[0][q] - v.p[0][p]) * d0 + (v.p[1][q] - v.p[1][p]) * d1 + (v.p[2][q] - v.p[2][p]) * d2;
    }
    detail::sqrt_in_place(length, n);
    Scalar *f0 = f[0] + first, *f1 = f[1] + first, *f2 = f[2] + first;
    const Scalar *l = rest + first, *k = ks + first, *c = kd + first;
    DRAPE_OMP_SIMD
    for (int j = 0; j < n; ++j) {
      const Scalar factor = spring_force_factor(length[j], w_dot_d[j], l[j], k[j], c[j]);
      f0[j] = factor * d[0][j];
      f1[j] = factor * d[1][j];
      f2[j] = factor * d[2][j];
    }
  }
}

template <class Scalar>
template <class BlockFn>
void ForceAssembler<Scalar>::node_pass_general(BlockFn& fn) const {
  alignas(64) Scalar total[3][block_nodes];
  const Index n = m_cloth->node_count();
  const Index springs = m_cloth->springs().size();
  const Scalar* masses = m_cloth->masses().data();
  const Vec3<Scalar> g = m_cloth->gravity();
  const bool terms = has_terms();
  const auto share = even_share((n + block_nodes - 1) / block_nodes, team_rank(), team_size());
  for (long long block = share.first; block < share.second; ++block) {
    const Index begin = Index(block) * block_nodes;
    const int count = int(std::min<Index>(block_nodes, n - begin));
    for (int j = 0; j < count; ++j) {
      const Index i = begin + j;
      Scalar t[3] = {masses[i] * g[0], masses[i] * g[1], masses[i] * g[2]};
      for (int e = m_incident_begin[std::size_t(i)]; e < m_incident_begin[std::size_t(i) + 1]; ++e) {
        const int code = m_incident[std::size_t(e)];
        const Index s = code > 0 ? code - 1 : -code - 1;
        for (int k = 0; k < 3; ++k) {
          const Scalar fk = m_spring_forces[std::size_t(k * springs + s)];
          t[k] += code > 0 ? fk : -fk;
        }
      }
      for (int k = 0; k < 3; ++k) total[k][j] = terms ? t[k] + m_term_forces(k, i) : t[k];
    }
    fn(ForceBlock<Scalar>{begin, count, {total[0], total[1], total[2]}});
  }
}

template <class Scalar>
void ForceAssembler<Scalar>::force(const ConstRef3X<Scalar>& x, const ConstRef3X<Scalar>& v, Scalar time,
                                   Ref3X<Scalar> f) const {
  const Index n = m_cloth->node_count();
  DRAPE_ASSERT(x.cols() == n && v.cols() == n && f.cols() == n, "force(): x, v and f must have one column per node");
  (void)n;
  evaluate_terms(x, v, time);
  Scalar* out = f.data();
  run_in_team(threads(), [&] {
    copy_input(x, v);
    team_barrier();
    spring_pass(input_positions(), input_velocities());
    team_barrier();
    node_pass([&](const ForceBlock<Scalar>& block) {
      Scalar* o = out + 3 * block.begin;
      for (int k = 0; k < 3; ++k) {
        const Scalar* t = block.f[k];
        DRAPE_OMP_SIMD
        for (int j = 0; j < block.count; ++j) o[3 * j + k] = t[j];
      }
    });
  });
}

}  // namespace drape
