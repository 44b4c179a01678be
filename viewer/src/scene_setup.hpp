#pragma once
// The scene drape-render builds from its settings before the first frame: every cloth's spec (the
// air's force terms and the floor collider added), the first cloth's start state, the box the
// fixed camera frames and the floor's height; and the [[moving-pins]] tables applied over time.
// Shared by drape-render and the Python module (python/), so a scene file means the same in both.

#include <cstdint>
#include <optional>
#include <vector>

#include "drape/core/pin_set.hpp"
#include "drape/fwd.hpp"
#include "drape/model/cloth.hpp"
#include "drape/viewer/camera.hpp"
#include "render_settings.hpp"

namespace drape::render {

/// What a run starts from (prepare_scene()).
struct PreparedScene {
  drape::ClothSpecd first;               ///< s.cloth with the air's force terms and the floor collider
  std::vector<drape::ClothSpecd> specs;  ///< every cloth: `first`, then one per [[cloths]] table
  drape::Stated start;                   ///< the first cloth's: its initial state, or --load-state
  drape::viewer::Bounds framed;          ///< the box the fixed camera frames (framed_box())
  double floor_y = 0;                    ///< the floor's height (drawn, and the floor collider)
};

/// The scene of validated settings `s`, built as drape-render builds it.
/// \throws SettingsError for a bad --load-state file or a cloth the library rejects (naming the
/// flag or key), drape::InvalidParameter for a check with no flag of its own.
PreparedScene prepare_scene(const Settings& s);

/// Simulated seconds the run covers after its start (for framing moving colliders).
double run_length(const Settings& s);

/// The box the fixed camera frames: where the cloth can hang from its pins and the nodes of the
/// [[moving-pins]] tables (hanging_bounds), every key position of a [[moving-pins]] path and the
/// cloth hanging below it (as far as below the node at the start), every collider but the planes
/// over the whole run (a moving one at 9 times), and the floor collider's height (the cloth can
/// land there). Without colliders and [[moving-pins]]: hanging_bounds alone.
drape::viewer::Bounds framed_box(const Settings& s, const drape::Clothd& cloth, const drape::Stated& start,
                                 std::optional<double> floor_collider_y);

/// What the following camera frames: the nodes, and the 8 corners of the colliders' box when
/// there are colliders (`has_solids`). `out` is resized to fit.
void framed_points(const drape::Matrix3X<double>& positions, const drape::viewer::Bounds& solids, bool has_solids,
                   drape::Matrix3X<double>& out);

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

}  // namespace drape::render
