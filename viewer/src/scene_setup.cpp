#include "scene_setup.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "drape/io/state_io.hpp"
#include "drape/viewer/collider_mesh.hpp"

namespace drape::render {

double run_length(const Settings& s) {
  return s.time.duration_given ? s.time.duration : double(s.time.frames - 1) * s.time.frame_time;
}

drape::viewer::Bounds framed_box(const Settings& s, const drape::Clothd& cloth, const drape::Stated& start,
                                 std::optional<double> floor_collider_y) {
  std::vector<int> pins = cloth.pins().nodes();
  for (const PinSpec& pin : s.moving_pins) pins.push_back(pin_node(s, pin));
  std::sort(pins.begin(), pins.end());
  pins.erase(std::unique(pins.begin(), pins.end()), pins.end());
  drape::viewer::Bounds box = drape::viewer::hanging_bounds(cloth, start.positions, pins);
  const float lowest = box.min.y();
  for (const PinSpec& pin : s.moving_pins) {
    const float node_y = float(start.positions(1, pin_node(s, pin)));
    for (const drape::Vec3<double>& p : pin.key_positions) {
      box.extend(p.cast<float>());
      box.extend(Eigen::Vector3f(float(p.x()), lowest + (float(p.y()) - node_y), float(p.z())));
    }
  }
  for (const drape::Colliderd& c : cloth.colliders()) {
    const std::vector<Eigen::Vector3f> local = drape::viewer::local_collider_mesh(c);
    const int samples = c.motion().is_static() ? 1 : 9;
    for (int k = 0; k < samples && !local.empty(); ++k) {
      const double t = start.time + (samples > 1 ? run_length(s) * k / (samples - 1) : 0.0);
      drape::viewer::extend(box, drape::viewer::place_mesh(local, c.motion().pose(t)));
    }
  }
  if (floor_collider_y) {
    const Eigen::Vector3f centre = box.centre();
    box.extend(Eigen::Vector3f(centre.x(), float(*floor_collider_y), centre.z()));
  }
  return box;
}

PreparedScene prepare_scene(const Settings& s) {
  PreparedScene scene;
  // The scene plus the air's force terms (none in still air, so such a run is unchanged).
  scene.first = s.cloth;
  for (auto& term : air_force_terms(s)) scene.first.force_terms.push_back(std::move(term));
  std::optional<drape::Clothd> cloth;
  cloth.emplace(make_cloth(s, scene.first));
  // Inputs are checked before any simulation or rendering.
  scene.start = cloth->initial_state();
  if (!s.load_state.empty()) {
    try {
      scene.start = drape::load_state<double>(s.load_state, cloth->node_count());
    } catch (const drape::StateFormatError& e) { throw SettingsError(std::string("--load-state: ") + e.what()); }
  }
  // The floor: at its fixed height, or just below the box the camera frames; --floor-collider puts
  // a plane collider there, so the cloth lands where the floor is drawn.
  const float aspect = float(s.output.width) / float(s.output.height);
  const std::optional<double> fixed_floor = fixed_floor_height(s);
  scene.framed = framed_box(s, *cloth, scene.start, s.floor.collider ? fixed_floor : std::nullopt);
  const std::vector<drape::ClothSpecd> more = cloth_specs(s, scene.first);
  for (std::size_t k = 1; k < more.size(); ++k) {  // the [[cloths]], where they start
    const drape::Matrix3X<double> x = drape::Clothd(more[k]).start_positions();
    for (Eigen::Index i = 0; i < x.cols(); ++i) scene.framed.extend(x.col(i).cast<float>());
  }
  scene.floor_y =
      fixed_floor
          ? *fixed_floor
          : double(drape::viewer::frame_bounds(scene.framed, aspect, float(s.output.azimuth), float(s.output.elevation))
                       .floor_height);
  if (s.floor.collider) {
    scene.first.colliders.push_back(floor_collider(s, scene.floor_y));
    (void)make_cloth(s, scene.first);  // its error names the floor's flags
  }
  scene.specs = cloth_specs(s, scene.first);
  return scene;
}

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

void framed_points(const drape::Matrix3X<double>& positions, const drape::viewer::Bounds& solids, bool has_solids,
                   drape::Matrix3X<double>& out) {
  out.resize(3, positions.cols() + (has_solids ? 8 : 0));
  out.leftCols(positions.cols()) = positions;
  for (int c = 0; c < 8 && has_solids; ++c)
    out.col(positions.cols() + c) =
        Eigen::Vector3f((c & 1) ? solids.max.x() : solids.min.x(), (c & 2) ? solids.max.y() : solids.min.y(),
                        (c & 4) ? solids.max.z() : solids.min.z())
            .cast<double>();
}

}  // namespace drape::render
