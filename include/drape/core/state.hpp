#pragma once
/// \file state.hpp
/// The dynamic state of a cloth: positions (m) and velocities (m/s), `3 x n`, and the time (s).

#include "drape/core/types.hpp"

namespace drape {

template <class Scalar = double>
struct State {
  Matrix3X<Scalar> positions;
  Matrix3X<Scalar> velocities;
  Scalar time = Scalar(0);

  int node_count() const { return static_cast<int>(positions.cols()); }
  bool all_finite() const { return positions.allFinite() && velocities.allFinite(); }
};

}  // namespace drape
