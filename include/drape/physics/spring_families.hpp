#pragma once
/// \file spring_families.hpp
/// The springs regrouped for a vectorised, barrier-light force pass (force_assembler.hpp).
///
/// A *family* is a set of springs with the same node offset `b - a` in which no two springs share
/// their first node a. A grid cloth has six (structural x/y, two shear diagonals, bend x/y). Spring
/// forces are stored by family and first node ("slot" `a` of family k), so node i finds all its
/// springs without an index list: \f$ f_i = m_i g + \sum_k (F_k[i] - F_k[i - o_k]) \f$, where
/// \f$ o_k \f$ is family k's offset and slots without a spring hold zero.
///
/// A *run* is a range of at most `max_run_length` springs of one family whose first nodes are
/// consecutive and that share rest length, stiffness and damping: positions and velocities of both
/// ends are then contiguous, so a run vectorises without gathers. A grid cloth's runs are its rows
/// (cut into pieces of max_run_length). Runs are ordered by first node (row-major), so a thread's
/// share of runs touches a band of rows and their force slots.

#include <algorithm>
#include <cstdlib>
#include <map>
#include <utility>
#include <vector>

#include "drape/core/spring_set.hpp"

namespace drape {

template <class Scalar = double>
class SpringFamilies {
 public:
  /// Springs [first, first + count) of `family` join nodes a = first + k and a + offset.
  struct Run {
    int family;
    int first;
    int count;
    Scalar rest_length, stiffness, damping;
  };

  /// Longest run: one run is one SIMD batch of the force pass (its scratch lives on the stack).
  static constexpr int max_run_length = 64;

  SpringFamilies(const SpringSet<Scalar>& springs, int node_count);

  int node_count() const { return m_node_count; }
  int family_count() const { return static_cast<int>(m_offsets.size()); }
  /// Node offset b - a of every family.
  const std::vector<int>& offsets() const { return m_offsets; }
  const std::vector<Run>& runs() const { return m_runs; }
  /// Zero slots before and after the node range of every family's force array, so that
  /// `F_k[i - o_k]` stays inside the array for every node i.
  int padding() const { return m_padding; }
  /// Length of one family's force array (per component): node_count + 2 padding.
  int slot_count() const { return m_node_count + 2 * m_padding; }
  /// Family of spring s (its slot is its first node `springs.a()[s]`).
  const std::vector<int>& family_of() const { return m_family_of; }
  /// Runs [begin, end) of part `part` of `parts`: contiguous, about the same number of springs each.
  std::pair<int, int> run_share(int part, int parts) const { return {run_at(part, parts), run_at(part + 1, parts)}; }

 private:
  int m_node_count;
  int m_padding = 0;
  std::vector<int> m_offsets;
  std::vector<Run> m_runs;
  std::vector<int> m_family_of;
  std::vector<long long> m_springs_before;  // springs in runs [0, r), one entry per run and one more

  /// First run of part `part` of `parts`: the first run starting at or after its share of springs.
  int run_at(int part, int parts) const {
    const long long target = m_springs_before.back() * part / parts;
    return static_cast<int>(std::lower_bound(m_springs_before.begin(), m_springs_before.end() - 1, target) -
                            m_springs_before.begin());
  }
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
SpringFamilies<Scalar>::SpringFamilies(const SpringSet<Scalar>& springs, int node_count) : m_node_count(node_count) {
  const int count = springs.size();
  const std::vector<int>& a = springs.a();
  const std::vector<int>& b = springs.b();
  // Family of each spring: the first family with its offset whose slot a is still free.
  std::map<int, std::vector<int>> families_by_offset;
  std::vector<std::vector<char>> used;
  m_family_of.resize(static_cast<std::size_t>(count));
  for (int s = 0; s < count; ++s) {
    const int offset = b[s] - a[s];
    std::vector<int>& candidates = families_by_offset[offset];
    int family = -1;
    for (int k : candidates)
      if (!used[static_cast<std::size_t>(k)][static_cast<std::size_t>(a[s])]) family = k;
    if (family < 0) {
      family = family_count();
      candidates.push_back(family);
      m_offsets.push_back(offset);
      used.emplace_back(static_cast<std::size_t>(node_count), 0);
      m_padding = std::max(m_padding, std::abs(offset));
    }
    used[static_cast<std::size_t>(family)][static_cast<std::size_t>(a[s])] = 1;
    m_family_of[static_cast<std::size_t>(s)] = family;
  }

  // Runs: springs sorted by (first node, family) would interleave families, so sort by
  // (family, first node), cut runs there, then order the runs by first node.
  std::vector<int> order(static_cast<std::size_t>(count));
  for (int s = 0; s < count; ++s) order[static_cast<std::size_t>(s)] = s;
  std::sort(order.begin(), order.end(), [&](int s, int t) {
    const int fs = m_family_of[static_cast<std::size_t>(s)], ft = m_family_of[static_cast<std::size_t>(t)];
    return fs != ft ? fs < ft : a[s] < a[t];
  });
  const std::vector<Scalar>& rest = springs.rest_length();
  const std::vector<Scalar>& ks = springs.stiffness();
  const std::vector<Scalar>& kd = springs.damping();
  for (int s : order) {
    const int family = m_family_of[static_cast<std::size_t>(s)];
    if (!m_runs.empty()) {
      Run& r = m_runs.back();
      if (r.family == family && r.first + r.count == a[s] && r.count < max_run_length && r.rest_length == rest[s] &&
          r.stiffness == ks[s] && r.damping == kd[s]) {
        ++r.count;
        continue;
      }
    }
    m_runs.push_back({family, a[s], 1, rest[s], ks[s], kd[s]});
  }
  std::stable_sort(m_runs.begin(), m_runs.end(), [](const Run& r, const Run& t) { return r.first < t.first; });
  m_springs_before.assign(1, 0);
  for (const Run& r : m_runs) m_springs_before.push_back(m_springs_before.back() + r.count);
}

}  // namespace drape
