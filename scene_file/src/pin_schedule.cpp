#include "drape/scene_file/pin_schedule.hpp"

#include "drape/scene_file/build_scene.hpp"

namespace drape::scene_file {

PinSchedule::PinSchedule(const Settings& s) {
  for (const PinSpec& pin : s.moving_pins) m_pins.push_back({&pin, pin_node(s, pin), Stage::Waiting});
}

void PinSchedule::apply(double t, double dt, drape::PinSet<double>& pins) {
  const double reached = t + 1e-9 * dt;
  for (Entry& e : m_pins) {
    if (e.stage == Stage::Waiting && e.spec->start <= reached) {
      pins.pin(e.node, e.spec->path);
      e.stage = Stage::Pinned;
    }
    if (e.stage == Stage::Pinned && e.spec->release && *e.spec->release <= reached) {
      pins.release(e.node);
      e.stage = Stage::Released;
    }
  }
}

}  // namespace drape::scene_file
