#pragma once
/// \file pin_schedule.hpp
/// The [[moving-pins]] tables of a scene file applied over a run: each node pinned to its path
/// from its start time on and released at its release time, between steps.

#include <cstdint>
#include <vector>

#include "drape/core/pin_set.hpp"
#include "drape/scene_file/settings.hpp"

namespace drape::scene_file {

/// The [[moving-pins]] tables over time: each node is pinned to its path once the run reaches its
/// start and released at its release time, between steps (the integrator's PinSet).
class PinSchedule {
 public:
  /// Keeps pointers into `s.moving_pins`: `s` must outlive the schedule.
  explicit PinSchedule(const Settings& s);

  /// Pins and releases what is due at `t`, the start of the next step (or of the run): a time
  /// within 1e-9 dt counts as reached, so events on step boundaries happen at that step whatever
  /// the rounding of the accumulated time.
  void apply(double t, double dt, drape::PinSet<double>& pins);

 private:
  enum class Stage : std::uint8_t { Waiting, Pinned, Released };
  struct Entry {
    const PinSpec* spec;
    int node;
    Stage stage;
  };
  std::vector<Entry> m_pins;
};

}  // namespace drape::scene_file
