// The model's bindings: spring coefficients, placement, self-collision and air settings,
// colliders, the cloth spec and the cloth (with its energies), the state numpy sees, pin paths
// and pin sets.

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/variant.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bindings.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/garment/sewing_pattern.hpp"
#if DRAPE_PYTHON_HAS_PATTERN_IO
#include "drape/garment/garment.hpp"
#include "drape/pattern_io/read_sewing_pattern.hpp"
#endif
#include "helpers.hpp"

namespace drape::python {

using namespace nb::literals;
using NodeArray = nb::ndarray<nb::numpy, double, nb::shape<-1, 3>, nb::c_contig>;

namespace {

// ---- node arrays --------------------------------------------------------------------------------

/// A (n, 3) numpy view of 3 x n node data (column-major 3 x n is row-major n x 3), kept alive by `owner`.
NodeArray node_view(drape::Matrix3X<double>& m, nb::handle owner) {
  return NodeArray(m.data(), {std::size_t(m.cols()), 3}, owner);
}

/// Copies an (n, 3) array into 3 x n node data of the same size.
void assign_nodes(drape::Matrix3X<double>& m, const NodeInput& a, const char* name) {
  if (a.shape(0) != std::size_t(m.cols()))
    drape::detail::fail_argument(name, "an array of " + std::to_string(a.shape(0)) + " nodes",
                                 "(n, 3) with n = " + std::to_string(m.cols()) + " (the cloth's nodes)");
  std::copy(a.data(), a.data() + 3 * a.shape(0), m.data());
}

drape::Matrix3X<double> matrix_of(const NodeInput& a) {
  drape::Matrix3X<double> m(3, Index(a.shape(0)));
  std::copy(a.data(), a.data() + 3 * a.shape(0), m.data());
  return m;
}

using TriangleInput = nb::ndarray<const int, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using UvInput = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;

/// The ClothMesh of numpy arrays (checked when the cloth is built).
drape::ClothMesh<double> mesh_of(const NodeInput& vertices, const TriangleInput& triangles,
                                 const std::optional<UvInput>& rest_uv) {
  drape::ClothMesh<double> mesh;
  mesh.positions = matrix_of(vertices);
  const int* t = triangles.data();
  for (std::size_t k = 0; k < triangles.shape(0); ++k) mesh.triangles.push_back({t[3 * k], t[3 * k + 1], t[3 * k + 2]});
  if (rest_uv) {
    if (rest_uv->shape(0) != vertices.shape(0))
      drape::detail::fail_argument("rest_uv", "an array of " + std::to_string(rest_uv->shape(0)) + " rows",
                                   "(n, 2) with n = " + std::to_string(vertices.shape(0)) + " (one per vertex)");
    mesh.rest_uv.resize(2, Index(rest_uv->shape(0)));
    std::copy(rest_uv->data(), rest_uv->data() + 2 * rest_uv->shape(0), mesh.rest_uv.data());
  }
  return mesh;
}

nb::ndarray<nb::numpy, int, nb::shape<-1, 3>> triangle_array(const std::vector<std::array<int, 3>>& triangles) {
  auto* data = new std::vector<std::array<int, 3>>(triangles);
  nb::capsule owner(data, [](void* p) noexcept { delete static_cast<std::vector<std::array<int, 3>>*>(p); });
  return {data->data(), {data->size(), 3}, owner};
}

// ---- pin paths ----------------------------------------------------------------------------------

/// A Python function of time as a pin path: called with the GIL (the step runs without it); its
/// error fails the step (a NaN position) and is raised after it.
drape::PinPath<double> callback_path(nb::callable function) {
  // The function is released with the GIL held, wherever the last copy of the path dies.
  std::shared_ptr<nb::object> held(new nb::object(function), [](nb::object* o) {
    nb::gil_scoped_acquire gil;
    delete o;
  });
  return drape::PinPath<double>::callback([held](double t) -> drape::Vec3<double> {
    nb::gil_scoped_acquire gil;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    try {
      const Vector p = nb::cast<Vector>((*held)(t));
      return vec3(p);
    } catch (nb::python_error& e) {
      if (!pending_callback_error()) pending_callback_error().emplace(std::move(e));
    } catch (const std::exception& e) {
      PyErr_SetString(PyExc_TypeError,
                      (std::string("drape: a pin path function must return (x, y, z): ") + e.what()).c_str());
      if (!pending_callback_error()) pending_callback_error().emplace();
    }
    return {nan, nan, nan};
  });
}

// ---- springs ------------------------------------------------------------------------------------

using SpringInput = std::variant<drape::SpringParams<double>, std::pair<double, double>>;
drape::SpringParams<double> spring_params(const SpringInput& in) {
  if (const auto* p = std::get_if<drape::SpringParams<double>>(&in)) return *p;
  const auto& pair = std::get<std::pair<double, double>>(in);
  return {pair.first, pair.second};
}

/// A rotation given as 3 rows, or the identity.
drape::Mat3<double> rotation_matrix(const std::optional<std::array<Vector, 3>>& rows) {
  drape::Mat3<double> r = drape::Mat3<double>::Identity();
  if (rows)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r(i, j) = (*rows)[std::size_t(i)][std::size_t(j)];
  return r;
}

// ---- states -------------------------------------------------------------------------------------

/// `state`, checked to have one node per node of `cloth`.
const drape::Stated& fitting_state(const drape::Clothd& cloth, const SharedState& state) {
  require_fits(cloth, state);
  return state.shared;
}

}  // namespace

// ---- the bindings -------------------------------------------------------------------------------

void bind_settings(nb::module_& m) {
  nb::class_<drape::SpringParams<double>>(m, "SpringParams",
                                          "Stiffness ks (N/m) and damping kd (N s/m) of one spring category.")
      .def(nb::init<double, double>(), "stiffness"_a, "damping"_a)
      .def_rw("stiffness", &drape::SpringParams<double>::stiffness, "ks in N/m, >= 0.")
      .def_rw("damping", &drape::SpringParams<double>::damping, "kd in N s/m, >= 0.")
      .def("__repr__", [](const drape::SpringParams<double>& p) {
        return "SpringParams(stiffness=" + drape::detail::to_text(p.stiffness) +
               ", damping=" + drape::detail::to_text(p.damping) + ")";
      });

  using Coefficients = drape::SpringCoefficients<double>;
  nb::class_<Coefficients>(m, "SpringCoefficients",
                           "One SpringParams per category: structural, shear and bend (docs/conventions.md).")
      .def(
          "__init__",
          [](Coefficients* self, std::optional<SpringInput> structural, std::optional<SpringInput> shear,
             std::optional<SpringInput> bend) {
            new (self) Coefficients(drape::ClothSpecd::default_springs());
            if (structural) self->structural = spring_params(*structural);
            if (shear) self->shear = spring_params(*shear);
            if (bend) self->bend = spring_params(*bend);
          },
          nb::kw_only(), "structural"_a = nb::none(), "shear"_a = nb::none(), "bend"_a = nb::none(),
          "The defaults of docs/parameters.md, with the categories given replaced; each is a SpringParams or "
          "a pair (stiffness, damping).")
      .def_rw("structural", &Coefficients::structural, "Row and column neighbours, rest length h.")
      .def_rw("shear", &Coefficients::shear, "Both cell diagonals, rest length h sqrt(2).")
      .def_rw("bend", &Coefficients::bend, "Nodes two apart along rows and columns, rest length 2h.")
      .def("validate", &Coefficients::validate, "Raises InvalidParameter naming e.g. 'shear.stiffness'.");

  using Placement = drape::Placement<double>;
  nb::class_<Placement>(m, "Placement", "Where a cloth's flat grid starts: node 0's position (m) and a rotation.")
      .def(
          "__init__",
          [](Placement* self, const Vector& position, const Vector& rotation_degrees) {
            new (self) Placement();
            self->position = vec3(position);
            self->rotation_degrees = vec3(rotation_degrees);
          },
          "position"_a = Vector{0, 0, 0}, "rotation_degrees"_a = Vector{0, 0, 0})
      .def_prop_rw(
          "position", [](const Placement& p) { return array3(p.position); },
          [](Placement& p, const Vector& v) { p.position = vec3(v); }, "m: where the grid's node 0 goes.")
      .def_prop_rw(
          "rotation_degrees", [](const Placement& p) { return array3(p.rotation_degrees); },
          [](Placement& p, const Vector& v) { p.rotation_degrees = vec3(v); },
          "Degrees about x, then y, then z (fixed axes).");

  using SelfCollision = drape::SelfCollisionSettings<double>;
  nb::class_<SelfCollision>(m, "SelfCollisionSettings",
                            "How cloth collides with itself and with other cloths (docs/contact.md); off by default.")
      .def(
          "__init__",
          [](SelfCollision* self, bool enabled, double friction, int impulse_rounds, double separation_rate) {
            new (self) SelfCollision{enabled, friction, impulse_rounds, separation_rate, {}};
          },
          "enabled"_a = false, "friction"_a = 0.3, "impulse_rounds"_a = 4, "separation_rate"_a = 0.5)
      .def_rw("enabled", &SelfCollision::enabled, "On: layers keep twice the contact thickness apart.")
      .def_rw("friction", &SelfCollision::friction, "Coulomb friction between layers, >= 0.")
      .def_rw("impulse_rounds", &SelfCollision::impulse_rounds,
              "Continuous-collision rounds with impulses before impact zones, [0, 64].")
      .def_rw("separation_rate", &SelfCollision::separation_rate,
              "Fraction of the missing distance restored per step, (0, 1].")
      .def_rw("joined_nodes", &SelfCollision::joined_nodes,
              "Pairs [a, b] of node ids sewn together: features touching either count as sharing a node.")
      .def("validate", nb::overload_cast<>(&SelfCollision::validate, nb::const_), "Raises InvalidParameter naming the setting.");

  nb::class_<drape::GustSettings>(m, "GustSettings", "Gusts on top of the mean wind (none by default).")
      .def(
          "__init__",
          [](drape::GustSettings* self, double amplitude, double period, double wavelength, int waves,
             std::uint64_t seed) {
            new (self) drape::GustSettings{amplitude, period, wavelength, waves, seed};
          },
          "amplitude"_a = 0.0, "period"_a = 2.0, "wavelength"_a = 8.0, "waves"_a = 4, "seed"_a = 1)
      .def_rw("amplitude", &drape::GustSettings::amplitude, "m/s: largest gust speed (0: no gusts).")
      .def_rw("period", &drape::GustSettings::period, "s: typical time between gusts, > 0.")
      .def_rw("wavelength", &drape::GustSettings::wavelength, "m: typical gust size, > 0.")
      .def_rw("waves", &drape::GustSettings::waves, "Travelling waves summed, [1, 64].")
      .def_rw("seed", &drape::GustSettings::seed, "The gusts' seed.");

  nb::class_<drape::AerodynamicSettings>(m, "AerodynamicSettings", "Per-triangle aerodynamic drag and lift.")
      .def(
          "__init__",
          [](drape::AerodynamicSettings* self, double density, double drag_coefficient, double lift_coefficient) {
            new (self) drape::AerodynamicSettings{density, drag_coefficient, lift_coefficient};
          },
          "density"_a = 1.2, "drag_coefficient"_a = 0.0, "lift_coefficient"_a = 0.0)
      .def_rw("density", &drape::AerodynamicSettings::density, "kg/m^3, >= 0.")
      .def_rw("drag_coefficient", &drape::AerodynamicSettings::drag_coefficient, "C_d, >= 0 (0: off).")
      .def_rw("lift_coefficient", &drape::AerodynamicSettings::lift_coefficient, "C_l, >= 0 (0: off).");

  nb::class_<drape::AirSettings>(m, "AirSettings",
                                 "Wind, gusts, linear drag and aerodynamic drag and lift; still and inactive by "
                                 "default (the cloth gets force terms only when active).")
      .def(
          "__init__",
          [](drape::AirSettings* self, const Vector& wind, std::optional<drape::GustSettings> gusts, double drag,
             std::optional<drape::AerodynamicSettings> aerodynamics) {
            new (self) drape::AirSettings();
            self->wind = wind;
            if (gusts) self->gusts = *gusts;
            self->drag = drag;
            if (aerodynamics) self->aerodynamics = *aerodynamics;
          },
          "wind"_a = Vector{0, 0, 0}, "gusts"_a = nb::none(), "drag"_a = 0.0, "aerodynamics"_a = nb::none())
      .def_rw("wind", &drape::AirSettings::wind, "Mean wind (m/s).")
      .def_rw("gusts", &drape::AirSettings::gusts, "GustSettings.")
      .def_rw("drag", &drape::AirSettings::drag, "Linear drag per node (N s/m), -c (v - wind).")
      .def_rw("aerodynamics", &drape::AirSettings::aerodynamics, "AerodynamicSettings.")
      .def_prop_ro("active", &drape::AirSettings::active, "True if the air exerts any force.")
      .def("validate", &drape::AirSettings::validate, "Raises InvalidParameter naming the setting.");
}

void bind_collider(nb::module_& m) {
  using Collider = drape::Colliderd;
  nb::class_<Collider>(m, "Collider",
                       "A rigid shape the cloth cannot enter (plane, sphere, capsule, box, cylinder, triangle mesh), static or moving "
                       "with constant velocities, with Coulomb friction (docs/contact.md).")
      .def_static(
          "plane", [](const Vector& point, const Vector& normal) { return Collider::plane(vec3(point), vec3(normal)); },
          "point"_a, "normal"_a, "The half-space below the plane through `point` with outward `normal` (any length).")
      .def_static(
          "sphere", [](const Vector& center, double radius) { return Collider::sphere(vec3(center), radius); },
          "center"_a, "radius"_a, "A sphere.")
      .def_static(
          "capsule",
          [](const Vector& a, const Vector& b, double radius) { return Collider::capsule(vec3(a), vec3(b), radius); },
          "a"_a, "b"_a, "radius"_a, "The segment a-b inflated by `radius`.")
      .def_static(
          "box",
          [](const Vector& center, const Vector& half_extents, std::optional<std::array<Vector, 3>> rotation,
             double rounding) {
            return Collider::box(vec3(center), vec3(half_extents), rotation_matrix(rotation), rounding);
          },
          "center"_a, "half_extents"_a, "rotation"_a = nb::none(), "rounding"_a = 0.0,
          "A box; `rotation` a 3x3 rotation matrix (rows), `rounding` the radius of its edges and corners.")
      .def_static(
          "cylinder",
          [](const Vector& center, double radius, double half_height, std::optional<std::array<Vector, 3>> rotation,
             double rounding) {
            return Collider::cylinder(vec3(center), radius, half_height, rotation_matrix(rotation), rounding);
          },
          "center"_a, "radius"_a, "half_height"_a, "rotation"_a = nb::none(), "rounding"_a = 0.0,
          "A cylinder about its local y axis from -half_height to half_height; `rotation` a 3x3 rotation matrix "
          "(rows), `rounding` the radius of its two rims.")
      .def_static(
          "mesh",
          [](const NodeInput& vertices, const TriangleInput& triangles, const Vector& center,
             std::optional<std::array<Vector, 3>> rotation) {
            return Collider::mesh(mesh_of(vertices, triangles, std::nullopt), vec3(center), rotation_matrix(rotation));
          },
          "vertices"_a, "triangles"_a, "center"_a = Vector{0, 0, 0}, "rotation"_a = nb::none(),
          "The solid a closed triangle mesh bounds: vertices (n, 3) in m in its own frame, triangles (m, 3) of "
          "vertex ids counter-clockwise seen from outside, placed at `center` turned by `rotation` (3x3, rows). "
          "An open mesh is allowed (its front side is outside). Raises InvalidParameter naming 'collider mesh' "
          "and the element (docs/contact.md).")
      .def_static(
          "animated_mesh",
          [](const std::vector<NodeInput>& frames, const TriangleInput& triangles, const std::vector<double>& times,
             const Vector& center, std::optional<std::array<Vector, 3>> rotation) {
            if (frames.empty()) drape::detail::fail_argument("collider frames", "none", "at least one key frame");
            std::vector<drape::Matrix3X<double>> positions;
            for (const NodeInput& f : frames) positions.push_back(matrix_of(f));
            return Collider::animated_mesh(mesh_of(frames.front(), triangles, std::nullopt), positions, times,
                                           vec3(center), rotation_matrix(rotation));
          },
          "frames"_a, "triangles"_a, "times"_a, "center"_a = Vector{0, 0, 0}, "rotation"_a = nb::none(),
          "A mesh whose vertices move: frames, a list of (n, 3) vertex arrays of the same triangles, at times "
          "(s, strictly increasing), linear in between and held outside; placed as mesh(). Raises "
          "InvalidParameter naming 'collider frames[k]' and the element or 'collider frame times'.")
      .def_static(
          "from_obj",
          [](const std::string& path, double scale, const Vector& center, std::optional<std::array<Vector, 3>> rotation) {
            return Collider::mesh(read_obj_mesh(path, scale, false), vec3(center), rotation_matrix(rotation));
          },
          "path"_a, "scale"_a = 1.0, "center"_a = Vector{0, 0, 0}, "rotation"_a = nb::none(),
          "A mesh collider of an OBJ file (triangles and quads; `scale` m per file unit), as mesh().")
      .def(
          "set_friction",
          [](Collider& c, double static_coefficient, std::optional<double> kinetic_coefficient) -> Collider& {
            return c.set_friction(static_coefficient, kinetic_coefficient.value_or(static_coefficient));
          },
          "static"_a, "kinetic"_a = nb::none(), nb::rv_policy::reference,
          "Coulomb coefficients (kinetic defaults to static); returns the collider.")
      .def(
          "moving",
          [](Collider& c, const Vector& velocity, const Vector& angular_velocity) -> Collider& {
            return c.moving(vec3(velocity), vec3(angular_velocity));
          },
          "velocity"_a, "angular_velocity"_a = Vector{0, 0, 0}, nb::rv_policy::reference,
          "Constant velocities (m/s, rad/s) from its placement at t = 0, spinning about its centre; returns "
          "the collider.")
      .def_prop_ro(
          "kind", [](const Collider& c) { return std::string(drape::to_string(c.kind())); },
          "'plane', 'sphere', 'capsule', 'box', 'cylinder' or 'mesh'.")
      .def_prop_ro("radius", &Collider::radius, "Sphere, capsule and cylinder radius (0 otherwise).")
      .def_prop_ro("half_length", &Collider::half_length, "Capsule half length (0 otherwise).")
      .def_prop_ro(
          "half_extents", [](const Collider& c) { return array3(c.half_extents()); }, "Box half extents.")
      .def_prop_ro("half_height", &Collider::half_height, "Cylinder half height (0 otherwise).")
      .def_prop_ro("rounding", &Collider::rounding, "Box edge and cylinder rim rounding.")
      .def_prop_ro("deforms", &Collider::deforms, "True for a mesh with key frames (animated_mesh).")
      .def_prop_ro("static_friction", &Collider::static_friction, "Static friction coefficient.")
      .def_prop_ro("kinetic_friction", &Collider::kinetic_friction, "Kinetic friction coefficient.")
      .def_prop_ro(
          "is_static", [](const Collider& c) { return c.motion().is_static(); }, "True if it never moves.")
      .def(
          "query",
          [](const Collider& c, const Vector& x, double t) {
            const drape::ColliderContact<double> q = c.query(vec3(x), t);
            return std::make_tuple(q.distance, array3(q.normal), array3(q.velocity));
          },
          "x"_a, "t"_a = 0.0, "(signed distance, outward normal, surface velocity) at world point x and time t.")
      .def("__repr__", [](const Collider& c) { return std::string("Collider(") + drape::to_string(c.kind()) + ")"; });
}

void bind_spec_and_cloth(nb::module_& m) {
  nb::class_<ClothSpecWithAir>(m, "ClothSpec",
                               "Everything that defines a cloth. Defaults: the course model (33 x 33 nodes 0.1 m "
                               "apart, 0.03 kg each, g = 10 m/s^2, two corners pinned), the springs of "
                               "docs/parameters.md, still air, no colliders.")
      .def(
          "__init__",
          [](ClothSpecWithAir* self, std::optional<int> nx, std::optional<int> ny, std::optional<double> spacing,
             std::optional<double> node_mass, std::optional<double> gravity,
             std::optional<drape::SpringCoefficients<double>> springs, std::optional<SpringInput> structural,
             std::optional<SpringInput> shear, std::optional<SpringInput> bend, std::optional<std::string> boundary,
             std::optional<std::vector<int>> pinned_nodes, std::optional<std::vector<drape::Colliderd>> colliders,
             std::optional<double> contact_thickness,
             std::optional<drape::SelfCollisionSettings<double>> self_collision,
             std::optional<drape::Placement<double>> placement, std::optional<drape::AirSettings> air) {
            new (self) ClothSpecWithAir();
            if (nx) self->nx = *nx;
            if (ny) self->ny = *ny;
            if (spacing) self->spacing = *spacing;
            if (node_mass) self->node_mass = *node_mass;
            if (gravity) self->gravity = *gravity;
            if (springs) self->springs = *springs;
            if (structural) self->springs.structural = spring_params(*structural);
            if (shear) self->springs.shear = spring_params(*shear);
            if (bend) self->springs.bend = spring_params(*bend);
            if (boundary) self->boundary = drape::parse<drape::BoundaryCondition>(*boundary);
            if (pinned_nodes) self->pinned_nodes = *pinned_nodes;
            if (colliders) self->colliders = *colliders;
            if (contact_thickness) self->contact_thickness = *contact_thickness;
            if (self_collision) self->self_collision = *self_collision;
            if (placement) self->placement = *placement;
            if (air) self->air = *air;
          },
          nb::kw_only(), "nx"_a = nb::none(), "ny"_a = nb::none(), "spacing"_a = nb::none(), "node_mass"_a = nb::none(),
          "gravity"_a = nb::none(), "springs"_a = nb::none(), "structural"_a = nb::none(), "shear"_a = nb::none(),
          "bend"_a = nb::none(), "boundary"_a = nb::none(), "pinned_nodes"_a = nb::none(), "colliders"_a = nb::none(),
          "contact_thickness"_a = nb::none(), "self_collision"_a = nb::none(), "placement"_a = nb::none(),
          "air"_a = nb::none(),
          "Keyword arguments set the fields of the same name (None keeps the default); structural, shear and "
          "bend replace one category of `springs` each (a SpringParams or (stiffness, damping)). Nothing is "
          "checked until validate() or Cloth(spec).")
      .def_static(
          "from_mesh",
          [](const NodeInput& vertices, const TriangleInput& triangles, std::optional<UvInput> rest_uv) {
            ClothSpecWithAir spec;
            spec.mesh = mesh_of(vertices, triangles, rest_uv);
            return spec;
          },
          "vertices"_a, "triangles"_a, "rest_uv"_a = nb::none(),
          "A cloth of any triangle mesh: vertices (n, 3) in m where the cloth starts (before `placement`), "
          "triangles (m, 3) of vertex ids counter-clockwise seen from the front, and optionally rest_uv (n, 2), a "
          "flat pattern in m that sets the rest shape (else the vertices do). No node is pinned (set pinned_nodes); "
          "the other fields keep their defaults. The mesh is checked by validate() or Cloth(spec) (docs/mesh.md).")
      .def_static(
          "from_obj",
          [](const std::string& path, double scale, bool rest_from_uv) {
            ClothSpecWithAir spec;
            spec.mesh = read_obj_mesh(path, scale, rest_from_uv);
            return spec;
          },
          "path"_a, "scale"_a = 1.0, "rest_from_uv"_a = false,
          "A cloth of the mesh of an OBJ file (triangles and quads; `scale` m per file unit; rest_from_uv: its vt "
          "as the rest pattern), as from_mesh. Raises InvalidParameter naming the file, line and element.")
      .def_prop_ro(
          "has_mesh", [](const ClothSpecWithAir& s) { return s.mesh.has_value(); },
          "True for a spec of from_mesh or from_obj (nx, ny and spacing are then unused).")
      .def_rw("areal_density", &ClothSpecWithAir::areal_density,
              "kg/m^2 or None: each node weighs its share of the rest area times this, instead of node_mass.")
      .def_rw("bending", &ClothSpecWithAir::bending,
              "N m: dihedral-angle bending stiffness, >= 0 (0: off; docs/bending.md).")
      .def_rw("bending_damping", &ClothSpecWithAir::bending_damping, "N m s: dihedral bending damping, >= 0.")
      .def_rw("nx", &ClothSpecWithAir::nx, "Nodes along x, [2, 10000].")
      .def_rw("ny", &ClothSpecWithAir::ny, "Nodes along z, [2, 10000].")
      .def_rw("spacing", &ClothSpecWithAir::spacing, "m between neighbours, > 0.")
      .def_rw("node_mass", &ClothSpecWithAir::node_mass, "kg per node, > 0.")
      .def_rw("gravity", &ClothSpecWithAir::gravity, "m/s^2 along -y, >= 0.")
      .def_rw("springs", &ClothSpecWithAir::springs,
              "SpringCoefficients (edit in place: spec.springs.shear.stiffness).")
      .def_prop_rw(
          "boundary", [](const ClothSpecWithAir& s) { return std::string(drape::to_string(s.boundary)); },
          [](ClothSpecWithAir& s, const std::string& name) {
            s.boundary = drape::parse<drape::BoundaryCondition>(name);
          },
          "'one-corner' or 'two-corners': the pins unless pinned_nodes is set.")
      .def_rw("pinned_nodes", &ClothSpecWithAir::pinned_nodes,
              "Node ids (j*nx + i) pinned instead of the boundary preset; None: the preset.")
      .def_rw("colliders", &ClothSpecWithAir::colliders, "List of Collider (assign a new list to change it).")
      .def_rw("contact_thickness", &ClothSpecWithAir::contact_thickness,
              "m: the cloth's half-thickness; nodes rest this far from a collider, >= 0.")
      .def_rw("self_collision", &ClothSpecWithAir::self_collision, "SelfCollisionSettings of this cloth alone.")
      .def_rw("placement", &ClothSpecWithAir::placement, "Placement of the flat grid.")
      .def_rw("air", &ClothSpecWithAir::air, "AirSettings: its force terms are added when the Cloth is built.")
      .def(
          "validate", [](const ClothSpecWithAir& s) { (void)library_spec(s); },
          "Raises InvalidParameter naming the first invalid parameter (e.g. 'shear.damping').");

  using Cloth = drape::Clothd;
  nb::class_<Cloth>(m, "Cloth",
                    "The model built from a ClothSpec (grid, springs, pins, gravity, air, colliders), read-only; "
                    "integrators keep it alive.")
      .def(
          "__init__", [](Cloth* self, const ClothSpecWithAir& spec) { new (self) Cloth(library_spec(spec)); },
          "spec"_a = ClothSpecWithAir(), "Validates `spec`: InvalidParameter names the parameter.")
      .def_prop_ro("node_count", &Cloth::node_count, "Number of nodes, nx * ny.")
      .def_prop_ro(
          "nx", [](const Cloth& c) { return c.grid().nx(); }, "Nodes along x.")
      .def_prop_ro(
          "ny", [](const Cloth& c) { return c.grid().ny(); }, "Nodes along z.")
      .def_prop_ro(
          "spacing", [](const Cloth& c) { return c.grid().spacing(); }, "m between neighbours.")
      .def_prop_ro(
          "gravity", [](const Cloth& c) { return array3(c.gravity()); }, "Gravity vector (m/s^2).")
      .def_prop_ro(
          "pinned_nodes", [](const Cloth& c) { return c.pins().nodes(); }, "The pinned node ids, sorted.")
      .def_prop_ro("colliders", &Cloth::colliders, "The colliders (copies).")
      .def_prop_ro("contact_thickness", &Cloth::contact_thickness, "m.")
      .def_prop_ro(
          "force_terms",
          [](const Cloth& c) {
            std::vector<std::string> names;
            for (const auto& t : c.force_terms()) names.push_back(t->name());
            return names;
          },
          "Names of the forces besides springs and gravity (the air's).")
      .def_prop_ro(
          "spring_count", [](const Cloth& c) { return c.springs().size(); }, "Number of springs.")
      .def(
          "node", [](const Cloth& c, int i, int j) { return c.grid().node(i, j); }, "i"_a, "j"_a,
          "The id of node (i, j): j * nx + i.")
      .def_prop_ro(
          "triangles", [](const Cloth& c) { return triangle_array(c.triangles()); }, nb::rv_policy::automatic,
          "(m, 3) int32 node ids of the mesh's triangles, counter-clockwise seen from +y.")
      .def_prop_ro(
          "start_positions",
          [](const Cloth& c) {
            drape::Matrix3X<double> x = c.start_positions();
            return NodeArray(x.data(), {std::size_t(x.cols()), 3}).cast();
          },
          "(n, 3) copy of the start positions (the flat grid, placed).")
      .def(
          "initial_state", [](const Cloth& c) { return SharedState(c.initial_state()); },
          "A new State: the flat grid where the placement puts it, at rest, t = 0.")
      .def(
          "kinetic_energy",
          [](const Cloth& c, const SharedState& s) { return drape::kinetic_energy(c, fitting_state(c, s)); }, "state"_a,
          "J.")
      .def(
          "spring_energy",
          [](const Cloth& c, const SharedState& s) {
            return drape::spring_potential_energy(c, fitting_state(c, s).positions);
          },
          "state"_a, "J: elastic energy of the springs.")
      .def(
          "gravity_energy",
          [](const Cloth& c, const SharedState& s) {
            return drape::gravitational_potential_energy(c, fitting_state(c, s).positions);
          },
          "state"_a, "J: -m g . x summed (0 at the rest height).")
      .def(
          "total_energy",
          [](const Cloth& c, const SharedState& s) { return drape::total_energy(c, fitting_state(c, s)); }, "state"_a,
          "J: kinetic + spring + gravity.")
      .def(
          "max_strain",
          [](const Cloth& c, const SharedState& s) { return drape::max_strain(c, fitting_state(c, s).positions); },
          "state"_a, "Largest relative spring elongation (L - l) / l.")
      .def(
          "pin_reaction",
          [](const Cloth& c, const SharedState& s) { return array3(drape::pin_reaction(c, fitting_state(c, s))); },
          "state"_a, "N: the force the cloth's own pins exert on it (balances the weight at rest).");

  nb::exception<drape::PatternError>(m, "PatternError", PyExc_ValueError).attr("__doc__") =
      "A sewing pattern drape cannot use: the message names the file and the JSON path "
      "(pattern.stitches[7][1].panel) and what is allowed there.";
  m.def(
      "load_pattern",
      [](const std::string& path, double edge_length, const std::string& fabric, double seam_stiffness,
         double seam_closing_time, double gravity, const std::map<std::string, std::array<double, 3>>& panel_offsets) {
#if DRAPE_PYTHON_HAS_PATTERN_IO
        drape::SewingSettings sewing;
        sewing.edge_length = edge_length;
        sewing.seam_stiffness = seam_stiffness;
        sewing.seam_closing_time = seam_closing_time;
        sewing.gravity = gravity;
        drape::SewingPattern pattern = drape::pattern_io::read_sewing_pattern(path);
        for (const auto& [name, offset] : panel_offsets)
          drape::move_panel(pattern, name, Eigen::Vector3d(offset[0], offset[1], offset[2]));
        const drape::Garment garment = drape::dress_garment(pattern, drape::fabric_preset(fabric), sewing);
        ClothSpecWithAir spec;
        static_cast<drape::ClothSpecd&>(spec) = garment.spec;
        return spec;
#else
        (void)edge_length, (void)fabric, (void)seam_stiffness, (void)seam_closing_time, (void)gravity,
            (void)panel_offsets;
        throw std::runtime_error("drape: load_pattern('" + path +
                                 "'): this module was built without the sewing-pattern reader (apt-get install "
                                 "nlohmann-json3-dev and rebuild)");
#endif
      },
      "path"_a, "edge_length"_a = 0.015, "fabric"_a = "cotton", "seam_stiffness"_a = 500.0,
      "seam_closing_time"_a = 1.0, "gravity"_a = 9.81,
      "panel_offsets"_a = std::map<std::string, std::array<double, 3>>{},
      "The garment of a GarmentCode JSON sewing pattern as a ClothSpec (docs/garments.md): every panel meshed at "
      "edge_length (m) and placed by its transform, the fabric's springs, density and bending ('cotton', 'denim', "
      "'silk', 'jersey'), seam springs (N/m per sewn pair) whose rest lengths reach zero at seam_closing_time (s), "
      "gravity (m/s^2) coming on after that (spec.gravity is 0: a force term carries it), self-collision on with "
      "the sewn vertices joined (spec.self_collision.joined_nodes); panel_offsets ({name: (x, y, z)}, m) moves "
      "panels from the pattern's placement. Add the body to spec.colliders. Raises "
      "PatternError (a ValueError) naming the file and the JSON path of a bad pattern, InvalidParameter naming "
      "the setting.");
}

void bind_state(nb::module_& m) {
  nb::class_<SharedState>(m, "State",
                          "Positions (m) and velocities (m/s) as (n, 3) numpy arrays shared with the C++ state (no "
                          "copy; writing into them changes the state; the same buffers for the state's life), and "
                          "the time (s).")
      .def(
          "__init__",
          [](SharedState* self, const NodeInput& positions, std::optional<NodeInput> velocities, double time) {
            drape::Stated s;
            s.positions = matrix_of(positions);
            s.velocities = drape::Matrix3X<double>::Zero(3, s.positions.cols());
            if (velocities) assign_nodes(s.velocities, *velocities, "velocities");
            s.time = time;
            new (self) SharedState(std::move(s));
          },
          "positions"_a, "velocities"_a = nb::none(), "time"_a = 0.0,
          "A state from (n, 3) positions (copied), velocities (zero if None) and time.")
      .def_prop_rw(
          "positions",
          [](nb::handle_t<SharedState> self) { return node_view(nb::cast<SharedState&>(self).shared.positions, self); },
          [](SharedState& s, const NodeInput& a) { assign_nodes(s.shared.positions, a, "positions"); },
          nb::rv_policy::reference_internal,
          "(n, 3) float64 view of the positions; assigning copies into the same buffer.")
      .def_prop_rw(
          "velocities",
          [](nb::handle_t<SharedState> self) {
            return node_view(nb::cast<SharedState&>(self).shared.velocities, self);
          },
          [](SharedState& s, const NodeInput& a) { assign_nodes(s.shared.velocities, a, "velocities"); },
          nb::rv_policy::reference_internal,
          "(n, 3) float64 view of the velocities; assigning copies into the same buffer.")
      .def_prop_rw(
          "time", [](const SharedState& s) { return s.shared.time; },
          [](SharedState& s, double t) { s.shared.time = t; }, "s.")
      .def_prop_ro("node_count", &SharedState::node_count, "Number of nodes.")
      .def(
          "copy", [](const SharedState& s) { return SharedState(s.shared); }, "An independent copy.")
      .def(
          "all_finite", [](const SharedState& s) { return s.shared.all_finite(); },
          "True if no position or velocity is NaN or infinite.")
      .def("__repr__", [](const SharedState& s) {
        return "State(nodes=" + std::to_string(s.node_count()) + ", time=" + drape::detail::to_text(s.shared.time) +
               ")";
      });
}

void bind_pins(nb::module_& m) {
  using Path = drape::PinPath<double>;
  nb::class_<Path>(m, "PinPath",
                   "Where a pinned node is at time t: held where it is (PinPath()), along key frames, or given "
                   "by a Python function of time.")
      .def(nb::init<>(), "Holds the node where it is.")
      .def_static(
          "keyframes",
          [](std::vector<double> times, const std::vector<Vector>& positions, const std::string& interpolation) {
            std::vector<drape::Vec3<double>> p;
            for (const Vector& v : positions) p.push_back(vec3(v));
            return Path::keyframes(std::move(times), std::move(p), drape::parse<drape::Interpolation>(interpolation));
          },
          "times"_a, "positions"_a, "interpolation"_a = "smooth",
          "Through `positions` (m) at `times` (s, increasing); 'smooth' (C1, at rest at the ends) or 'linear'.")
      .def_static("callback", &callback_path, "position"_a,
                  "position(t) -> (x, y, z), called with the GIL during steps; an exception it raises fails the "
                  "step and is re-raised.")
      .def_prop_ro("holds", &Path::holds, "True for a pin that stays where it is.")
      .def(
          "position",
          [](const Path& p, double t, const Vector& current) { return array3(p.position(t, vec3(current))); }, "t"_a,
          "current"_a = Vector{0, 0, 0}, "The position at t (`current` for a holding pin).");

  using Set = drape::PinSet<double>;
  nb::class_<Set>(m, "PinSet",
                  "The pins of an integrator's run: start as the cloth's, holding; pin, move and release nodes "
                  "between steps.")
      .def(
          "pin", [](Set& s, int node, std::optional<Path> path) { s.pin(node, path ? *path : Path()); }, "node"_a,
          "path"_a = nb::none(), "Pins `node` to `path` (default: holds it where it is).")
      .def("release", &Set::release, "node"_a, "Frees `node`; False if it was not pinned.")
      .def(
          "is_pinned",
          [](const Set& s, int node) {
            drape::Pins::validate({node}, s.node_count());
            return s.is_pinned(node);
          },
          "node"_a, "True if `node` is pinned.")
      .def_prop_ro("nodes", &Set::nodes, "Pinned nodes, sorted.")
      .def_prop_ro("count", &Set::count, "Number of pinned nodes.")
      .def("__len__", &Set::count, "Number of pinned nodes.");
}

}  // namespace drape::python
