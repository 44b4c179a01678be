#pragma once
/// \file pin_set.hpp
/// The pins of a run: which nodes are pinned now and the path each follows (pin_path.hpp). An
/// integrator starts from the cloth's pins (all holding still) and owns the set, so pins can be
/// added, moved and released between steps (`integrator.pins()`). A pinned node ends every step
/// exactly at its path's position, with the velocity that took it there.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "drape/core/pin_path.hpp"
#include "drape/core/pins.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"

namespace drape {

template <class Scalar = double>
class PinSet {
 public:
  PinSet() = default;
  /// `initial`'s nodes, each holding still.
  explicit PinSet(const Pins& initial)
      : m_nodes(initial.nodes()), m_paths(initial.nodes().size()), m_mask(initial.mask()) {}

  /// Pins `node` to `path` (replacing its path if it is pinned already); default: holds it where
  /// it is. \throws InvalidParameter naming `pinned node` for a node outside [0, node count).
  void pin(int node, PinPath<Scalar> path = {}) {
    Pins::validate({node}, node_count());
    const auto it = std::lower_bound(m_nodes.begin(), m_nodes.end(), node);
    const auto k = static_cast<std::size_t>(it - m_nodes.begin());
    if (it != m_nodes.end() && *it == node) {
      m_paths[k] = std::move(path);
    } else {
      m_nodes.insert(it, node);
      m_paths.insert(m_paths.begin() + static_cast<std::ptrdiff_t>(k), std::move(path));
      m_mask[static_cast<std::size_t>(node)] = 1;
    }
    ++m_version;
  }
  /// Frees `node`; returns false if it was not pinned.
  bool release(int node) {
    const auto it = std::lower_bound(m_nodes.begin(), m_nodes.end(), node);
    if (it == m_nodes.end() || *it != node) return false;
    m_paths.erase(m_paths.begin() + (it - m_nodes.begin()));
    m_nodes.erase(it);
    m_mask[static_cast<std::size_t>(node)] = 0;
    ++m_version;
    return true;
  }

  bool is_pinned(int node) const { return m_mask[static_cast<std::size_t>(node)] != 0; }
  /// Pinned nodes, sorted.
  const std::vector<int>& nodes() const { return m_nodes; }
  /// The path of the k-th pinned node (in nodes() order).
  const PinPath<Scalar>& path(std::size_t k) const { return m_paths[k]; }
  /// 1 for pinned nodes, 0 for free ones; one entry per node.
  const std::vector<std::uint8_t>& mask() const { return m_mask; }
  int count() const { return static_cast<int>(m_nodes.size()); }
  int node_count() const { return static_cast<int>(m_mask.size()); }
  /// Pinned nodes that hold still (their velocity stays 0: the implicit step can eliminate them).
  std::vector<int> holding() const {
    std::vector<int> held;
    for (std::size_t k = 0; k < m_nodes.size(); ++k)
      if (m_paths[k].holds()) held.push_back(m_nodes[k]);
    return held;
  }
  /// Changes with every pin() and release(): an integrator lays its system out again.
  std::uint64_t version() const { return m_version; }

  /// Every pin's position at `t` (3 x count(), nodes() order); a holding pin's is its column of `x`.
  void positions(Scalar t, const ConstRef3X<Scalar>& x, Matrix3X<Scalar>& out) const {
    out.resize(3, count());
    for (std::size_t k = 0; k < m_nodes.size(); ++k)
      out.col(static_cast<Index>(k)) = m_paths[k].position(t, x.col(m_nodes[k]));
  }

 private:
  std::vector<int> m_nodes;
  std::vector<PinPath<Scalar>> m_paths;
  std::vector<std::uint8_t> m_mask;
  std::uint64_t m_version = 0;
};

}  // namespace drape
