// The stepping bindings: integrator options, the contact and self-collision reports and the
// step status, the integrators with step() and run(), the scene of several cloths, and the
// option names.

#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/variant.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/solvers/solver_registry.hpp"
#include "helpers.hpp"

namespace drape::python {

using namespace nb::literals;

namespace {

// ---- stepping -----------------------------------------------------------------------------------

/// How many steps `seconds` are at `dt` (drape-render's rounding), checked.
long long steps_for(double seconds, double dt) {
  if (!(std::isfinite(seconds) && seconds >= 0))
    drape::detail::fail_argument("seconds", drape::detail::to_text(seconds), "finite and >= 0");
  return std::llround(seconds / dt);
}

/// The step counts after which run() calls back: every step without `frame_time`, else the whole
/// frames k frame_time from the start (rounded to whole steps).
class CallbackPlan {
 public:
  CallbackPlan(long long total, double dt, std::optional<double> frame_time, bool has_callback)
      : m_total(total), m_dt(dt), m_frame_time(frame_time), m_has_callback(has_callback) {
    if (frame_time && !(std::isfinite(*frame_time) && *frame_time > 0))
      drape::detail::fail_argument("frame_time", drape::detail::to_text(*frame_time), "finite and > 0 (s)");
  }
  /// The step count of the next callback after `done` steps (the run's end if none is due before).
  long long next(long long done) {
    if (!m_has_callback) return m_total;
    if (!m_frame_time) return std::min(done + 1, m_total);
    long long target = done;
    while (target <= done) target = std::llround(double(++m_frame) * *m_frame_time / m_dt);
    return std::min(target, m_total);
  }
  /// True if a callback is due after `done` steps.
  bool due(long long done) const {
    if (!m_has_callback) return false;
    if (!m_frame_time) return true;
    return std::llround(double(m_frame) * *m_frame_time / m_dt) == done;
  }

 private:
  long long m_total;
  double m_dt;
  std::optional<double> m_frame_time;
  bool m_has_callback;
  long long m_frame = 0;
};

/// Calls `advance` (one step of the simulation, returning its status) `total` times with the GIL
/// released, and `callback(subject)` as planned with the GIL held. `take` copies the shared state
/// into the stepped one (at the start and after each callback, which may write into it), `share`
/// copies it back (before each callback and at the end). A callback returning False stops the run.
/// Returns the steps taken. \throws StepFailed (the shared state as after the last good step).
template <class Advance, class Share, class Take, class Time>
long long run_loop(long long total, double dt, const std::optional<nb::callable>& callback,
                   std::optional<double> frame_time, nb::handle subject, Advance&& advance, Share&& share, Take&& take,
                   Time&& time) {
  CallbackPlan plan(total, dt, frame_time, callback.has_value());
  long long done = 0;
  drape::StepStatus status;
  take();
  while (done < total) {
    const long long target = plan.next(done);
    {
      nb::gil_scoped_release released;
      while (done < target) {
        status = advance();
        if (!status) break;
        ++done;
      }
    }
    if (!status || pending_callback_error()) {
      share();
      fail_step(status, time());
    }
    if (plan.due(done)) {
      share();
      const nb::object answer = (*callback)(subject);
      take();
      if (answer.is(nb::bool_(false))) break;
    }
  }
  share();
  return done;
}

drape::StepStatus step_integrator(drape::Integrator<double>& integrator, SharedState& state) {
  BusyGuard busy({&integrator, &state}, "this integrator or state");
  state.copy_to(state.own_work);
  drape::StepStatus status;
  {
    nb::gil_scoped_release released;
    status = integrator.step(state.own_work);
  }
  if (!status || pending_callback_error()) fail_step(status, state.shared.time);
  state.copy_from(state.own_work);
  return status;
}

// ---- option names -------------------------------------------------------------------------------

template <class Enum>
std::vector<std::string> names_of() {
  return drape::names<Enum>();
}

}  // namespace

// ---- the bindings -------------------------------------------------------------------------------

void bind_options(nb::module_& m) {
  nb::class_<drape::IntegratorOptions>(m, "IntegratorOptions", "The time step and threads every integrator takes.")
      .def(
          "__init__",
          [](drape::IntegratorOptions* self, double dt, int threads) {
            new (self) drape::IntegratorOptions{dt, threads};
          },
          "dt"_a = 0.0005, "threads"_a = 0)
      .def_rw("dt", &drape::IntegratorOptions::dt, "s, > 0; the default suits the explicit integrators.")
      .def_rw("threads", &drape::IntegratorOptions::threads, "0 = all cores.")
      .def("validate", &drape::IntegratorOptions::validate, "Raises InvalidParameter naming 'dt' or 'threads'.");

  using Options = drape::ImplicitOptions;
  nb::class_<Options, drape::IntegratorOptions>(
      m, "ImplicitOptions",
      "The implicit integrator's options (docs/implicit.md): dt and threads, the Jacobian, the linear solver "
      "and its preconditioner, tolerance, pins, Newton iterations, contact rounds. Option names are strings.")
      .def(
          "__init__",
          [](Options* self, double dt, int threads, const std::string& jacobian, const std::string& solver,
             const std::string& preconditioner, double tolerance, int max_iterations, const std::string& pin_treatment,
             int newton_iterations, double newton_tolerance, int contact_rounds) {
            Options o;
            o.dt = dt;
            o.threads = threads;
            o.jacobian = drape::parse<drape::JacobianVariant>(jacobian);
            o.solver = drape::parse<drape::LinearSolverKind>(solver);
            o.preconditioner = drape::parse<drape::PreconditionerKind>(preconditioner);
            o.tolerance = tolerance;
            o.max_iterations = max_iterations;
            o.pin_treatment = drape::parse<drape::PinTreatment>(pin_treatment);
            o.newton_iterations = newton_iterations;
            o.newton_tolerance = newton_tolerance;
            o.contact_rounds = contact_rounds;
            new (self) Options(o);
          },
          "dt"_a = 0.0005, "threads"_a = 0, "jacobian"_a = "spd", "solver"_a = "cg", "preconditioner"_a = "multigrid-float",
          "tolerance"_a = 1e-6, "max_iterations"_a = 2000, "pin_treatment"_a = "eliminate", "newton_iterations"_a = 1,
          "newton_tolerance"_a = 1e-6, "contact_rounds"_a = 2,
          "Names are the library's (option_names()); a wrong one raises InvalidParameter listing the names.")
      .def_prop_rw(
          "jacobian", [](const Options& o) { return std::string(drape::to_string(o.jacobian)); },
          [](Options& o, const std::string& n) { o.jacobian = drape::parse<drape::JacobianVariant>(n); },
          "Jacobian variant, e.g. 'spd' (default) or 'exact'.")
      .def_prop_rw(
          "solver", [](const Options& o) { return std::string(drape::to_string(o.solver)); },
          [](Options& o, const std::string& n) { o.solver = drape::parse<drape::LinearSolverKind>(n); },
          "Linear solver: 'cg' (default), 'bicgstab', 'ldlt', 'lu' (and 'cholmod', 'umfpack' when built in).")
      .def_prop_rw(
          "preconditioner", [](const Options& o) { return std::string(drape::to_string(o.preconditioner)); },
          [](Options& o, const std::string& n) { o.preconditioner = drape::parse<drape::PreconditionerKind>(n); },
          "cg's preconditioner: 'multigrid-float' (default: the V-cycle in single precision inside the double CG), "
          "'multigrid', 'block-jacobi', 'amg' or 'amg-float' (the algebraic V-cycle, in double or in single "
          "precision; a mesh cloth takes it for 'multigrid' or 'multigrid-float').")
      .def_rw("tolerance", &Options::tolerance, "Relative residual of the iterative solvers, (0, 1).")
      .def_rw("max_iterations", &Options::max_iterations, "Iteration cap of the iterative solvers, >= 1.")
      .def_prop_rw(
          "pin_treatment", [](const Options& o) { return std::string(drape::to_string(o.pin_treatment)); },
          [](Options& o, const std::string& n) { o.pin_treatment = drape::parse<drape::PinTreatment>(n); },
          "'eliminate' (default) or 'filter'.")
      .def_rw("newton_iterations", &Options::newton_iterations, "1: Baraff & Witkin's single linearised step.")
      .def_rw("newton_tolerance", &Options::newton_tolerance, "Newton's stopping tolerance.")
      .def_rw("contact_rounds", &Options::contact_rounds, "Linear solves per step while contacts change, [1, 32].")
      .def("validate", &Options::validate, "Raises InvalidParameter naming the first invalid option.");
}

void bind_reports(nb::module_& m) {
  using Contact = drape::ContactReport<double>;
  nb::class_<Contact>(m, "ContactReport", "What the contacts with colliders did in the last step.")
      .def_ro("contacts", &Contact::contacts, "Nodes in contact.")
      .def_ro("sticking", &Contact::sticking, "Of which friction held still.")
      .def_ro("sliding", &Contact::sliding, "Of which slid.")
      .def_ro("corrected", &Contact::corrected, "Nodes the end-of-step check pushed out.")
      .def_ro("after_solve", &Contact::after_solve, "Contacts resolved by an impulse after the solve.")
      .def_ro("rounds", &Contact::rounds, "Implicit step: linear solves.")
      .def_ro("deepest", &Contact::deepest, "m: deepest penetration before the check.")
      .def_prop_ro(
          "normal_force", [](const Contact& c) { return array3(c.normal_force); }, "N, total.")
      .def_prop_ro(
          "friction_force", [](const Contact& c) { return array3(c.friction_force); }, "N, total.");

  using Self = drape::SelfCollisionReport;
  nb::class_<Self>(m, "SelfCollisionReport", "What self-collision did in the last step.")
      .def_ro("proximity_pairs", &Self::proximity_pairs, "Pairs closer than 2h at the start.")
      .def_ro("repulsions", &Self::repulsions, "Of which were stopped or pushed apart.")
      .def_ro("impacts", &Self::impacts, "Crossings resolved by impulses.")
      .def_ro("impulse_rounds", &Self::impulse_rounds, "Rounds of continuous tests.")
      .def_ro("zones", &Self::zones, "Impact zones moved rigidly.")
      .def_ro("zone_nodes", &Self::zone_nodes, "Nodes in those zones.")
      .def_ro("unresolved", &Self::unresolved, "Crossings left.");

  nb::class_<drape::StepStatus>(m, "StepStatus", "A successful step's solver statistics.")
      .def_ro("iterations", &drape::StepStatus::iterations, "Linear-solver iterations (0 for explicit steps).")
      .def_ro("residual", &drape::StepStatus::residual, "Final relative residual (0 for explicit steps).")
      .def("__repr__", [](const drape::StepStatus& s) {
        return "StepStatus(iterations=" + std::to_string(s.iterations) +
               ", residual=" + drape::detail::to_text(s.residual) + ")";
      });
}

const char* const run_doc =
    "Steps `state` for `seconds` (round(seconds / dt) steps) with the GIL released. Without `frame_time`, "
    "callback(state) is called after every step; with it, after every whole frame (k * frame_time from the "
    "start, rounded to steps). The state's arrays are current in the callback and may be written; a callback "
    "returning False stops the run. Returns the steps taken. Raises SimulationError (state as after the last "
    "good step) if a step fails.";

void bind_integrators(nb::module_& m) {
  using Integrator = drape::Integrator<double>;
  nb::class_<Integrator>(m, "Integrator",
                         "What every integrator shares: its cloth, time step, pins, contact reports, step() and "
                         "run().")
      .def_prop_rw("dt", &Integrator::dt, &Integrator::set_dt, "The time step (s), > 0.")
      .def_prop_ro("cloth", &Integrator::cloth, nb::rv_policy::reference_internal, "The cloth it advances.")
      .def_prop_ro("pins", nb::overload_cast<>(&Integrator::pins), nb::rv_policy::reference_internal,
                   "The pins of the run (PinSet).")
      .def_prop_ro("contact_report", &Integrator::contact_report, nb::rv_policy::copy,
                   "ContactReport of the last step (a copy).")
      .def_prop_ro("self_collision_report", &Integrator::self_collision_report, nb::rv_policy::copy,
                   "SelfCollisionReport of the last step (a copy).")
      .def(
          "step",
          [](Integrator& integrator, SharedState& state) {
            require_fits(integrator.cloth(), state);
            return step_integrator(integrator, state);
          },
          "state"_a,
          "Advances `state` by dt, with the GIL released. Returns a StepStatus; raises SimulationError (state "
          "unchanged) if the step fails.")
      .def(
          "run",
          [](Integrator& integrator, nb::handle_t<SharedState> handle, double seconds,
             std::optional<nb::callable> callback, std::optional<double> frame_time) {
            SharedState& state = nb::cast<SharedState&>(handle);
            require_fits(integrator.cloth(), state);
            BusyGuard busy({&integrator, &state}, "this integrator or state");
            return run_loop(
                steps_for(seconds, integrator.dt()), integrator.dt(), callback, frame_time, handle,
                [&] { return integrator.step(state.own_work); }, [&] { state.copy_from(state.own_work); },
                [&] { state.copy_to(state.own_work); }, [&] { return state.shared.time; });
          },
          "state"_a, "seconds"_a, "callback"_a = nb::none(), "frame_time"_a = nb::none(), run_doc);

  nb::class_<drape::Rk2<double>, Integrator>(m, "Rk2", "Explicit midpoint rule (RK2); conditionally stable.")
      .def(
          "__init__",
          [](drape::Rk2<double>* self, const drape::Clothd& cloth, std::optional<drape::IntegratorOptions> options,
             std::optional<double> dt, std::optional<int> threads) {
            drape::IntegratorOptions o = options.value_or(drape::IntegratorOptions{});
            if (dt) o.dt = *dt;
            if (threads) o.threads = *threads;
            new (self) drape::Rk2<double>(cloth, o);
          },
          "cloth"_a, "options"_a = nb::none(), nb::kw_only(), "dt"_a = nb::none(), "threads"_a = nb::none(),
          nb::keep_alive<1, 2>(), "dt and threads override `options` (IntegratorOptions).");

  nb::class_<drape::SymplecticEuler<double>, Integrator>(m, "SymplecticEuler",
                                                         "Symplectic (semi-implicit) Euler: one force pass per step.")
      .def(
          "__init__",
          [](drape::SymplecticEuler<double>* self, const drape::Clothd& cloth,
             std::optional<drape::IntegratorOptions> options, std::optional<double> dt, std::optional<int> threads) {
            drape::IntegratorOptions o = options.value_or(drape::IntegratorOptions{});
            if (dt) o.dt = *dt;
            if (threads) o.threads = *threads;
            new (self) drape::SymplecticEuler<double>(cloth, o);
          },
          "cloth"_a, "options"_a = nb::none(), nb::kw_only(), "dt"_a = nb::none(), "threads"_a = nb::none(),
          nb::keep_alive<1, 2>(), "dt and threads override `options` (IntegratorOptions).");

  using Implicit = drape::ImplicitEuler<double>;
  nb::class_<Implicit, Integrator>(m, "ImplicitEuler",
                                   "Linearised implicit Euler (Baraff & Witkin), stable at large steps.")
      .def(
          "__init__",
          [](Implicit* self, const drape::Clothd& cloth, std::optional<drape::ImplicitOptions> options,
             std::optional<double> dt, std::optional<int> threads) {
            drape::ImplicitOptions o = options.value_or(drape::ImplicitOptions{});
            if (dt) o.dt = *dt;
            if (threads) o.threads = *threads;
            new (self) Implicit(cloth, o);
          },
          "cloth"_a, "options"_a = nb::none(), nb::kw_only(), "dt"_a = nb::none(), "threads"_a = nb::none(),
          nb::keep_alive<1, 2>(), "dt and threads override `options` (ImplicitOptions).")
      .def_prop_ro("options", &Implicit::options, nb::rv_policy::copy, "The ImplicitOptions (a copy).")
      .def_prop_ro("newton_iterations_done", &Implicit::newton_iterations_done, "Newton iterations of the last step.")
      .def_prop_ro("newton_residual", &Implicit::newton_residual, "Its final relative residual.");

  m.def(
      "make_integrator",
      [](const drape::Clothd& cloth, const std::string& kind, std::optional<drape::ImplicitOptions> options) {
        return drape::make_integrator(cloth, drape::parse<drape::IntegratorKind>(kind),
                                      options.value_or(drape::ImplicitOptions{}));
      },
      "cloth"_a, "kind"_a = "rk2", "options"_a = nb::none(), nb::keep_alive<0, 1>(),
      "An integrator by name ('rk2', 'implicit', 'symplectic'); the explicit ones read dt and threads only.");
}

void bind_scene(nb::module_& m) {
  nb::class_<PyClothScene>(m, "ClothScene",
                           "Several cloths stepped together, each with its own integrator; with collisions on they "
                           "never pass through each other or themselves.")
      .def(
          "__init__",
          [](PyClothScene* self, const std::vector<ClothSpecWithAir>& cloths, const std::string& integrator,
             std::optional<drape::ImplicitOptions> options,
             std::optional<drape::SelfCollisionSettings<double>> collisions) {
            new (self) PyClothScene(cloths, drape::parse<drape::IntegratorKind>(integrator),
                                    options.value_or(drape::ImplicitOptions{}),
                                    collisions.value_or(drape::SelfCollisionSettings<double>{}));
          },
          "cloths"_a, "integrator"_a = "rk2", "options"_a = nb::none(), "collisions"_a = nb::none(),
          "One Cloth and integrator ('rk2', 'implicit', 'symplectic', with `options`) per ClothSpec; "
          "`collisions` (SelfCollisionSettings) between and within all of them.")
      .def_prop_ro(
          "cloth_count", [](PyClothScene& s) { return s.scene().cloth_count(); }, "Number of cloths.")
      .def(
          "cloth",
          [](PyClothScene& s, int k) -> const drape::Clothd& {
            (void)s.state(k);
            return s.scene().cloth(k);
          },
          "k"_a, nb::rv_policy::reference_internal, "Cloth k.")
      .def(
          "integrator",
          [](PyClothScene& s, int k) -> drape::Integrator<double>& {
            (void)s.state(k);
            return s.scene().integrator(k);
          },
          "k"_a, nb::rv_policy::reference_internal, "Cloth k's integrator (its pins, dt, reports).")
      .def("state", &PyClothScene::state, "k"_a, nb::rv_policy::reference_internal,
           "Cloth k's State: its arrays are shared and stay the same buffers for the scene's life.")
      .def_prop_ro(
          "states",
          [](nb::handle_t<PyClothScene> h) {
            PyClothScene& s = nb::cast<PyClothScene&>(h);
            nb::list states;
            for (int k = 0; k < s.scene().cloth_count(); ++k)
              states.append(nb::cast(&s.state(k), nb::rv_policy::reference_internal, h));
            return states;
          },
          "Every cloth's State.")
      .def(
          "node_offset", [](PyClothScene& s, int k) { return (void)s.state(k), s.scene().node_offset(k); }, "k"_a,
          "Cloth k's first node in the scene's numbering.")
      .def_prop_ro(
          "time", [](PyClothScene& s) { return s.state(0).shared.time; }, "s: the first cloth's time.")
      .def(
          "step",
          [](PyClothScene& s) {
            BusyGuard busy({&s}, "this scene");
            s.to_scene();
            s.apply_schedule();
            drape::StepStatus status;
            {
              nb::gil_scoped_release released;
              status = s.scene().step();
            }
            if (!status || pending_callback_error()) fail_step(status, s.state(0).shared.time);
            s.from_scene();
            return status;
          },
          "Advances every cloth by dt, then their collisions, with the GIL released. Raises SimulationError "
          "(no state changed) if a step fails.")
      .def(
          "run",
          [](nb::handle_t<PyClothScene> handle, double seconds, std::optional<nb::callable> callback,
             std::optional<double> frame_time) {
            PyClothScene& s = nb::cast<PyClothScene&>(handle);
            BusyGuard busy({&s}, "this scene");
            const double dt = s.scene().integrator(0).dt();
            return run_loop(
                steps_for(seconds, dt), dt, callback, frame_time, handle,
                [&] {
                  s.apply_schedule();
                  return s.scene().step();
                },
                [&] { s.from_scene(); }, [&] { s.to_scene(); }, [&] { return s.state(0).shared.time; });
          },
          "seconds"_a, "callback"_a = nb::none(), "frame_time"_a = nb::none(),
          "As Integrator.run for every cloth: callback(scene).")
      .def_prop_ro(
          "collision_report", [](PyClothScene& s) { return s.scene().collision_report(); },
          "SelfCollisionReport of the scene's handler, last step.")
      .def(
          "contact_force_on",
          [](PyClothScene& s, int k) { return (void)s.state(k), array3(s.scene().contact_force_on(k)); }, "k"_a,
          "N: mean force the other cloths put on cloth k over the last step.");
}

void bind_option_names(nb::module_& m) {
  m.def(
      "option_names",
      [] {
        nb::dict names;
        names["integrator"] = names_of<drape::IntegratorKind>();
        names["jacobian"] = names_of<drape::JacobianVariant>();
        std::vector<std::string> solvers;
        for (drape::LinearSolverKind k : drape::available_solvers()) solvers.emplace_back(drape::to_string(k));
        names["solver"] = solvers;
        names["preconditioner"] = names_of<drape::PreconditionerKind>();
        names["pin_treatment"] = names_of<drape::PinTreatment>();
        names["boundary"] = names_of<drape::BoundaryCondition>();
        names["interpolation"] = names_of<drape::Interpolation>();
        names["collider"] = names_of<drape::ShapeKind>();
        return names;
      },
      "The names each option accepts (the solvers: those built in).");
}

}  // namespace drape::python
