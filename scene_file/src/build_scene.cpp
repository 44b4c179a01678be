#include "drape/scene_file/build_scene.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "drape/core/mesh_generators.hpp"
#include "drape/io/state_io.hpp"
#include "drape/physics/dihedral_bending.hpp"
#include "drape/viewer/collider_mesh.hpp"
#include "error_names.hpp"
#include "resolve_mesh.hpp"

namespace drape::scene_file {

using detail::fail;

std::optional<double> fixed_floor_height(const Settings& s) {
  if (s.floor.height_given) return s.floor.height;
  std::optional<double> y;
  for (const drape::Colliderd& c : s.cloth.colliders) {
    const double height = c.motion().pose(0).translation.y();
    if (is_floor(c, height) && (!y || height > *y)) y = height;
  }
  return y;
}

bool is_floor(const drape::Colliderd& collider, double floor_height) {
  if (collider.kind() != drape::ShapeKind::Plane || !collider.motion().is_static()) return false;
  const drape::RigidPose<double> pose = collider.motion().pose(0);
  const drape::Vec3<double> normal = pose.rotation.col(1);
  return (normal - drape::Vec3<double>::UnitY()).norm() <= 1e-12 &&
         std::abs(pose.translation.y() - floor_height) <= 1e-9 * std::max(1.0, std::abs(floor_height));
}

drape::Colliderd floor_collider(const Settings& s, double y) {
  try {
    return drape::Colliderd::plane({0.0, y, 0.0}, drape::Vec3<double>::UnitY())
        .set_friction(s.floor.friction, s.floor.friction);
  } catch (const InvalidParameter& e) {
    const bool friction = e.parameter() == "static friction" || e.parameter() == "kinetic friction";
    fail(friction ? "--floor-friction" : "--floor-height", e.value(), e.allowed());
  }
}

drape::Clothd make_cloth(const Settings& s, const drape::ClothSpecd& spec) {
  try {
    return drape::Clothd(spec);
  } catch (const InvalidParameter& e) {
    const std::string& name = e.parameter();
    if (name.rfind("colliders[", 0) != 0) detail::fail_named(e);
    const std::size_t k = std::stoul(name.substr(10));
    const std::string what = k < s.collider_keys.size() ? s.collider_keys[k]
                             : s.floor.height_given     ? "--floor-height (of --floor-collider)"
                                                        : "--floor-collider";
    fail(what.rfind("colliders[", 0) == 0 ? "scene file '" + s.scene + "': " + what : what, e.value(), e.allowed());
  }
}

int pin_node(const Settings& s, const PinSpec& pin) {
  const int nx = s.cloth.nx, ny = s.cloth.ny;
  const std::string where = "scene file '" + s.scene + "': " + pin.key;
  if (s.cloth.mesh && !s.cloth.mesh->lattice) {  // a mesh's nodes have ids only
    const int n = s.cloth.mesh->vertex_count();
    if (pin.grid_node) fail(where + ".node", "[i, j] on a mesh cloth", "id = k, a vertex of the mesh");
    if (pin.id < 0 || pin.id >= n)
      fail(where + ".id", std::to_string(pin.id), "a vertex of the mesh: [0, " + std::to_string(n - 1) + "]");
    return pin.id;
  }
  if (pin.grid_node) {
    const auto [i, j] = *pin.grid_node;
    if (i < 0 || i >= nx || j < 0 || j >= ny)
      fail(where + ".node", "[" + std::to_string(i) + ", " + std::to_string(j) + "]",
           "a node of the grid: [i, j] with i in [0, " + std::to_string(nx - 1) + "] and j in [0, " +
               std::to_string(ny - 1) + "] (nx = " + std::to_string(nx) + ", ny = " + std::to_string(ny) + ")");
    return j * nx + i;
  }
  if (pin.id < 0 || pin.id >= nx * ny)
    fail(where + ".id", std::to_string(pin.id),
         "a node of the grid: an id in [0, " + std::to_string(nx * ny - 1) + "] (id = j*nx + i)");
  return pin.id;
}

namespace {

/// The dihedral bending term of `m` on `mesh`; none when its stiffness and damping are 0.
std::shared_ptr<const drape::ForceTerm<double>> dihedral_term(const MeshSource& m, const drape::ClothMesh<double>& mesh) {
  if (m.bending == 0 && m.bending_kd == 0) return nullptr;
  return std::make_shared<drape::DihedralBending<double>>(mesh, m.bending, m.bending_kd);
}

}  // namespace

std::vector<drape::ClothSpecd> cloth_specs(const Settings& s, const drape::ClothSpecd& first) {
  std::vector<drape::ClothSpecd> specs = {first};
  for (const ExtraCloth& c : s.extra_cloths) {
    drape::ClothSpecd spec = first;
    spec.mesh.reset();  // a [[cloths]] table has a grid or mesh of its own
    spec.areal_density.reset();
    spec.nx = c.nx.value_or(first.nx);
    spec.ny = c.ny.value_or(first.ny);
    spec.spacing = c.spacing.value_or(first.spacing);
    spec.node_mass = c.mass.value_or(first.node_mass);
    spec.pinned_nodes = c.pins;
    double* springs[] = {&spec.springs.structural.stiffness, &spec.springs.structural.damping,
                         &spec.springs.shear.stiffness,      &spec.springs.shear.damping,
                         &spec.springs.bend.stiffness,       &spec.springs.bend.damping};
    for (std::size_t k = 0; k < 6; ++k)
      if (c.springs[k]) *springs[k] = *c.springs[k];
    spec.placement.position = detail::vec3(c.position);
    spec.placement.rotation_degrees = detail::vec3(c.rotation);
    const std::string where = "scene file '" + s.scene + "': " + c.key;
    detail::apply_mesh_source(c.mesh, spec, [&where](const std::string& name) { return where + "." + name; });
    try {
      spec.validate();
      spec.force_terms.clear();  // the first cloth's terms act on its triangles: this cloth's own
      const drape::ClothMesh<double> mesh =
          spec.mesh ? *spec.mesh : drape::grid_mesh<double>(spec.nx, spec.ny, spec.spacing);
      if (s.air.active()) spec.force_terms = drape::air_force_terms<double>(s.air, mesh.all_triangles());
      if (auto bending = dihedral_term(c.mesh, mesh)) spec.force_terms.push_back(std::move(bending));
      (void)drape::Clothd(spec);  // pins clear of the colliders
    } catch (const InvalidParameter& e) {
      const std::map<std::string, std::string> key_of = {{"nx", "nx"},
                                                         {"ny", "ny"},
                                                         {"spacing", "spacing"},
                                                         {"node_mass", "mass"},
                                                         {"pinned node", "pins"},
                                                         {"placement.position", "position"},
                                                         {"placement.rotation", "rotation"},
                                                         {"structural.stiffness", "structural-ks"},
                                                         {"structural.damping", "structural-kd"},
                                                         {"shear.stiffness", "shear-ks"},
                                                         {"shear.damping", "shear-kd"},
                                                         {"bend.stiffness", "bend-ks"},
                                                         {"bend.damping", "bend-kd"}};
      const auto it = key_of.find(e.parameter());
      fail(where + "." + (it != key_of.end() ? it->second : e.parameter()), e.value(), e.allowed());
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

namespace {
/// The first cloth's mesh: its own, or the grid's.
drape::ClothMesh<double> first_mesh(const Settings& s) {
  return s.cloth.mesh ? *s.cloth.mesh : drape::grid_mesh<double>(s.cloth.nx, s.cloth.ny, s.cloth.spacing);
}
}  // namespace

std::vector<std::shared_ptr<const drape::ForceTerm<double>>> air_force_terms(const Settings& s) {
  s.air.validate();
  if (!s.air.active()) return {};
  return drape::air_force_terms<double>(s.air, first_mesh(s).all_triangles());
}

std::shared_ptr<const drape::ForceTerm<double>> bending_term(const Settings& s) {
  return dihedral_term(s.mesh, first_mesh(s));
}

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
  if (auto bending = bending_term(s)) scene.first.force_terms.push_back(std::move(bending));
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

}  // namespace drape::scene_file
