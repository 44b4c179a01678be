// What the binding groups share (helpers.hpp): the spec's air and bending, the busy guard, the scene with
// Python's states, failed steps and the errors InvalidParameter and SimulationError.

#include "helpers.hpp"

#include <cstdio>
#include <mutex>
#include <set>
#include <utility>

#include "bindings.hpp"
#include "drape/core/mesh_generators.hpp"
#include "drape/physics/dihedral_bending.hpp"
#if DRAPE_PYTHON_HAS_MESH_IO
#include "drape/mesh_io/read_obj.hpp"
#endif

namespace drape::python {

// ---- errors -------------------------------------------------------------------------------------

namespace {

PyObject* invalid_parameter_type = nullptr;

/// drape.InvalidParameter (a ValueError) with the parameter, value and allowed range as attributes.
void translate_invalid_parameter(const std::exception_ptr& p, void*) {
  try {
    std::rethrow_exception(p);
  } catch (const drape::InvalidParameter& e) {
    nb::object error = nb::borrow(invalid_parameter_type)(nb::str(e.what()));
    nb::setattr(error, "parameter", nb::str(e.parameter().c_str()));
    nb::setattr(error, "value", nb::str(e.value().c_str()));
    nb::setattr(error, "allowed", nb::str(e.allowed().c_str()));
    PyErr_SetObject(invalid_parameter_type, error.ptr());
  }
}

/// Raises the pending callback error, if any.
void raise_pending_callback_error() {
  std::optional<nb::python_error>& pending = pending_callback_error();
  if (!pending) return;
  nb::python_error error = std::move(*pending);
  pending.reset();
  throw error;
}

}  // namespace

std::optional<nb::python_error>& pending_callback_error() {
  static auto* error = new std::optional<nb::python_error>();  // never destroyed: outlives the interpreter
  return *error;
}

[[noreturn]] void fail_step(const drape::StepStatus& status, double time) {
  raise_pending_callback_error();
  char at[64];
  std::snprintf(at, sizeof at, "%.17g", time);
  throw StepFailed(std::string("drape: the step from t = ") + at + " s failed: " + drape::to_string(status.error) +
                   "; the state is unchanged");
}

void bind_errors(nb::module_& m) {
  invalid_parameter_type =
      PyErr_NewExceptionWithDoc("_drape.InvalidParameter",
                                "A parameter outside its allowed range (a ValueError); .parameter, .value and "
                                ".allowed give the three parts of the message.",
                                PyExc_ValueError, nullptr);
  m.attr("InvalidParameter") = nb::handle(invalid_parameter_type);
  nb::register_exception_translator(translate_invalid_parameter);
  nb::exception<StepFailed>(m, "SimulationError", PyExc_RuntimeError).attr("__doc__") =
      "A step failed (diverged, or the linear solver failed); the state is as after the last good step.";
}

// ---- specs and states ---------------------------------------------------------------------------

drape::ClothMesh<double> read_obj_mesh(const std::string& path, double scale, bool rest_from_uv) {
#if DRAPE_PYTHON_HAS_MESH_IO
  drape::mesh_io::ObjOptions options;
  options.scale = scale;
  options.rest_from_uv = rest_from_uv;
  return drape::mesh_io::read_obj<double>(path, options).mesh;
#else
  (void)scale;
  (void)rest_from_uv;
  throw std::runtime_error("drape: ClothSpec.from_obj('" + path +
                           "'): this module reads no OBJ files (built without tinyobjloader: install "
                           "libtinyobjloader-dev and rebuild); ClothSpec.from_mesh takes numpy arrays");
#endif
}

drape::ClothSpecd library_spec(const ClothSpecWithAir& spec) {
  spec.validate();
  spec.air.validate();
  drape::ClothSpecd out = spec;
  const drape::ClothMesh<double> mesh = spec.mesh ? *spec.mesh : drape::grid_mesh(spec.nx, spec.ny, spec.spacing);
  if (spec.air.active())
    for (auto& term : drape::air_force_terms<double>(spec.air, mesh.all_triangles())) out.force_terms.push_back(term);
  if (spec.bending != 0 || spec.bending_damping != 0)
    out.force_terms.push_back(
        std::make_shared<drape::DihedralBending<double>>(mesh, spec.bending, spec.bending_damping));
  return out;
}

void require_fits(const drape::Clothd& cloth, const SharedState& state) {
  if (state.node_count() != cloth.node_count())
    drape::detail::fail_argument("state", std::to_string(state.node_count()) + " nodes",
                                 std::to_string(cloth.node_count()) + " nodes (the cloth's)");
}

// ---- the busy guard -----------------------------------------------------------------------------

namespace {
std::mutex busy_mutex;
std::set<const void*> busy_objects;
}  // namespace

BusyGuard::BusyGuard(std::initializer_list<const void*> objects, const char* what) {
  const std::lock_guard<std::mutex> lock(busy_mutex);
  for (const void* o : objects)
    if (busy_objects.count(o))
      throw std::runtime_error(std::string("drape: ") + what +
                               " is being stepped by another call (another thread, "
                               "or a callback of its run())");
  for (const void* o : objects) {
    busy_objects.insert(o);
    m_objects.push_back(o);
  }
}

BusyGuard::~BusyGuard() {
  const std::lock_guard<std::mutex> lock(busy_mutex);
  for (const void* o : m_objects) busy_objects.erase(o);
}

// ---- the scene ----------------------------------------------------------------------------------

namespace {
std::vector<drape::ClothSpecd> library_specs(const std::vector<ClothSpecWithAir>& specs) {
  std::vector<drape::ClothSpecd> out;
  for (std::size_t k = 0; k < specs.size(); ++k) {
    try {
      out.push_back(library_spec(specs[k]));
    } catch (const drape::InvalidParameter& e) {  // named as ClothScene names its cloths' errors
      throw drape::InvalidParameter("cloths[" + std::to_string(k) + "]." + e.parameter(), e.value(), e.allowed());
    }
  }
  return out;
}
}  // namespace

PyClothScene::PyClothScene(const std::vector<ClothSpecWithAir>& specs, drape::IntegratorKind kind,
                           const drape::ImplicitOptions& options,
                           const drape::SelfCollisionSettings<double>& collisions)
    : m_scene(library_specs(specs), kind, options, collisions) {
  for (int k = 0; k < m_scene.cloth_count(); ++k) m_states.push_back(std::make_unique<SharedState>(m_scene.state(k)));
}

PyClothScene::PyClothScene(const std::vector<drape::ClothSpecd>& specs, drape::IntegratorKind kind,
                           const drape::ImplicitOptions& options,
                           const drape::SelfCollisionSettings<double>& collisions, drape::Stated start,
                           BeforeStep before_step)
    : m_scene(specs, kind, options, collisions), m_before_step(std::move(before_step)) {
  m_scene.state(0) = std::move(start);
  apply_schedule();  // what is due at the start
  for (int k = 0; k < m_scene.cloth_count(); ++k) m_states.push_back(std::make_unique<SharedState>(m_scene.state(k)));
}

SharedState& PyClothScene::state(int k) {
  if (k < 0 || k >= m_scene.cloth_count())
    throw nb::index_error(
        ("drape: cloth " + std::to_string(k) + " of a scene of " + std::to_string(m_scene.cloth_count()) + " cloths")
            .c_str());
  return *m_states[std::size_t(k)];
}

void PyClothScene::apply_schedule() {
  if (m_before_step) m_before_step(m_scene);
}

void PyClothScene::to_scene() {
  for (std::size_t k = 0; k < m_states.size(); ++k) m_states[k]->copy_to(m_scene.state(int(k)));
}

void PyClothScene::from_scene() {
  for (std::size_t k = 0; k < m_states.size(); ++k) m_states[k]->copy_from(m_scene.state(int(k)));
}

}  // namespace drape::python
