#pragma once
/// \file implicit_euler.hpp
/// Linearised implicit (backward) Euler (Baraff & Witkin 1998, "Large steps in cloth simulation"):
/// \f[ \Bigl(M - \Delta t \frac{\partial f}{\partial v} - \Delta t^2 \frac{\partial f}{\partial x}\Bigr) \Delta v
///     = \Delta t \Bigl(f(x_t, v_t) + \Delta t \frac{\partial f}{\partial x} v_t\Bigr), \qquad
///     v_{t+1} = v_t + \Delta v, \quad x_{t+1} = x_t + \Delta t\, v_{t+1}. \f]
/// Pinned nodes keep \f$ \Delta v = 0 \f$ (eliminated from the system or fixed by its constraints,
/// see PinTreatment). The path of a step: JacobianAssembler fills a LinearSystem (matrix, edge
/// operator, lattice layout, constraints, b), the linear solver solves it, the step commits.
/// The Jacobian variant and the linear solver are chosen at run time (ImplicitOptions), or the
/// caller hands over a solver object; drape's implicit.md has the derivation and the measurements
/// behind the defaults.
///
/// A step that fails (solver failure, matrix not positive definite, no convergence, non-finite
/// result) returns the reason and leaves the state unchanged. After the first step, `step()`
/// performs no heap allocation with the iterative solvers (tested).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "drape/core/validation.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/solvers/solver_registry.hpp"

namespace drape {

/// The implicit integrator's settings: the time step and threads of every integrator, plus its own.
struct ImplicitOptions : IntegratorOptions {
  /// Spd: symmetric positive definite system for any deformation; measured the fastest and the
  /// most robust (drape's implicit.md, "Default Jacobian").
  JacobianVariant jacobian = JacobianVariant::Spd;
  /// cg was the fastest at every size measured at dt <= 1/60; direct solvers win only for very
  /// large dt (drape's implicit.md, "Default solver"). See solvers/solver_kind.hpp.
  LinearSolverKind solver = LinearSolverKind::Cg;
  /// Preconditioner of cg (bicgstab always uses block Jacobi; direct solvers none). Multigrid
  /// needs ~10 iterations where block Jacobi needs 120-190 at dt = 1/60 (drape's implicit.md,
  /// "Multigrid preconditioner"); its V-cycle in float takes the same iterations and moves half
  /// the bytes (implicit.md, "Mixed precision"; for a float integrator it is the plain V-cycle).
  PreconditionerKind preconditioner = PreconditionerKind::MultigridFloat;
  double tolerance = 1e-6;    ///< relative residual |S(b - A dv)| / |S b| of iterative solvers
  int max_iterations = 2000;  ///< iteration cap of iterative solvers
  PinTreatment pin_treatment = PinTreatment::Eliminate;
  /// 1 = the single linearised step of Baraff & Witkin. More = Newton iterations on the nonlinear
  /// backward Euler equations \f$ M \Delta v = \Delta t\, f(x + \Delta t (v + \Delta v), v + \Delta v) \f$,
  /// starting from the linearised step; stops early when the residual is below
  /// `newton_tolerance` times \f$ |\Delta t\, f(x_t, v_t)| \f$.
  int newton_iterations = 1;
  double newton_tolerance = 1e-6;
  /// With colliders: at most this many linear solves per step while the contact set changes
  /// (nodes let go or newly reached; contact/contact_handler.hpp). After the last one, contacts
  /// the solve lets go are free from the next step and nodes it newly brings to a collider get an
  /// impulse and are constraints from the next step (1: Baraff and Witkin's lagged active set;
  /// cheapest, but impacts strain the cloth more: docs/contact.md has the measurements behind 2).
  int contact_rounds = 2;

  /// The iterative solvers' share of these options.
  IterativeSettings iterative_settings() const { return {tolerance, max_iterations, threads, preconditioner}; }

  /// \throws InvalidParameter naming the first invalid option: dt, threads, tolerance,
  /// max_iterations, newton settings, a solver this program lacks, or a solver that does not fit
  /// the Jacobian variant or pin treatment (see require_solver_fits()).
  void validate() const;
  /// validate() without the `solver` field (for a solver object the caller supplies).
  void validate_except_solver() const;
};

/// \throws InvalidParameter if a solver with `capabilities` (named `name` in the message) cannot
/// solve the systems of `jacobian` (Exact needs a non-symmetric solver) with `pins` (Filter needs
/// one that honours constraints).
inline void require_solver_fits(const std::string& name, const SolverCapabilities& capabilities,
                                JacobianVariant jacobian, PinTreatment pins) {
  if (jacobian == JacobianVariant::Exact && capabilities.symmetric_only)
    detail::fail_argument("solver", "'" + name + "' with jacobian = exact",
                          "a non-symmetric solver for the Exact Jacobian: bicgstab, lu or umfpack");
  if (pins == PinTreatment::Filter && !capabilities.supports_constraints)
    detail::fail_argument("pin_treatment", "filter with solver '" + name + "'",
                          "eliminate the pins, or filter them with a solver that takes constraints (cg, bicgstab)");
}

template <class Scalar = double>
class ImplicitEuler final : public Integrator<Scalar> {
 public:
  /// \throws InvalidParameter as ImplicitOptions::validate().
  explicit ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options = {});
  /// With a linear solver the caller made (`options.solver` is ignored).
  /// \throws InvalidParameter as ImplicitOptions::validate_except_solver(), if `solver` is null, or
  /// if its capabilities() do not fit the options (require_solver_fits()).
  ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options,
                std::unique_ptr<LinearSolver<Scalar>> solver);
  /// The integrator keeps a reference to the cloth: a temporary would dangle.
  ImplicitEuler(const Cloth<Scalar>&& cloth, const ImplicitOptions& options = {}) = delete;
  ImplicitEuler(const Cloth<Scalar>&& cloth, const ImplicitOptions& options,
                std::unique_ptr<LinearSolver<Scalar>>) = delete;

  StepStatus step(State<Scalar>& state) override;

  const ImplicitOptions& options() const { return m_options; }
  const JacobianAssembler<Scalar>& assembler() const { return m_assembler; }
  /// The system of the last step: A, b, the constraints (one block row per system node, see
  /// JacobianAssembler::node_of_row()).
  const LinearSystem<Scalar>& system() const { return m_system; }
  /// The last step's solution dv (3 per system node).
  const VectorX<Scalar>& dv() const { return m_dv; }
  /// Newton iterations of the last step (1 without newton_iterations > 1) and its final
  /// relative residual |M dv - dt f(x+, v+)| / |dt f(x, v)| (0 if not computed).
  int newton_iterations_done() const { return m_newton_done; }
  double newton_residual() const { return m_newton_residual; }
  LinearSolver<Scalar>& solver() { return *m_solver; }

 private:
  ImplicitOptions m_options;
  JacobianAssembler<Scalar> m_assembler;
  std::unique_ptr<LinearSolver<Scalar>> m_solver;
  LinearSystem<Scalar> m_system;
  VectorX<Scalar> m_dv;
  Matrix3X<Scalar> m_x_new, m_v_new;
  // Newton iterations only
  ForceAssembler<Scalar> m_forces;
  Matrix3X<Scalar> m_f;
  VectorX<Scalar> m_g, m_delta;
  int m_newton_done = 0;
  double m_newton_residual = 0;
  Matrix3X<Scalar> m_pin_end;         // the pins' positions at the end of the step
  std::uint64_t m_pins_laid_out = 0;  // pins().version() of the system's layout

  /// Checks the solver against the options and sets up the system (both constructors).
  void set_up();
  /// The system's layout for the current pins (holding pins eliminated or fixed), and the
  /// solver's analysis of it: at construction and after the pins change.
  void lay_out();
  /// Rows of pins that move: fixed to the velocity change that puts them on their paths.
  void constrain_moving_pins(const State<Scalar>& state, Scalar dt);
  /// x+ = x + dt (v + dv), v+ = v + dv into m_x_new, m_v_new (pinned nodes fixed).
  void advance(const State<Scalar>& state, Scalar dt);
  /// g = S(M dv - dt f(m_x_new, m_v_new)) on the system rows at `time`; returns |g|.
  double nonlinear_residual(Scalar time, Scalar dt);
};

// ---------------------------------------------------------------------------------------------

inline void ImplicitOptions::validate_except_solver() const {
  IntegratorOptions::validate();
  iterative_settings().validate();
  detail::require_at_least("newton_iterations", newton_iterations, 1);
  detail::require_in_range("contact_rounds", contact_rounds, 1, 32);
  if (!(std::isfinite(newton_tolerance) && newton_tolerance > 0))
    detail::fail_argument("newton_tolerance", detail::to_text(newton_tolerance), "finite and > 0");
}

inline void ImplicitOptions::validate() const {
  validate_except_solver();
  require_solver_available(solver);
  require_solver_fits(to_string(solver), solver_info(solver).capabilities, jacobian, pin_treatment);
}

template <class Scalar>
ImplicitEuler<Scalar>::ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options)
    : Integrator<Scalar>(cloth, (options.validate(), options)),
      m_options(options),
      m_assembler(cloth, options.pin_treatment, options.threads),
      m_solver(make_linear_solver<Scalar>(options.solver, options.iterative_settings())),
      m_forces(cloth, options.threads) {
  set_up();
}

template <class Scalar>
ImplicitEuler<Scalar>::ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options,
                                     std::unique_ptr<LinearSolver<Scalar>> solver)
    : Integrator<Scalar>(cloth, (options.validate_except_solver(), options)),
      m_options(options),
      m_assembler(cloth, options.pin_treatment, options.threads),
      m_solver(std::move(solver)),
      m_forces(cloth, options.threads) {
  if (!m_solver) detail::fail_argument("solver", "a null pointer", "a linear solver");
  set_up();
}

template <class Scalar>
void ImplicitEuler<Scalar>::set_up() {
  require_solver_fits(m_solver->name(), m_solver->capabilities(), m_options.jacobian, m_options.pin_treatment);
  if (!this->cloth().colliders().empty() && !m_solver->capabilities().supports_constraints)
    detail::fail_argument("solver", "'" + m_solver->name() + "' with colliders",
                          "a solver that takes constraints (contacts are constraints of the solve)");
  const int n = this->cloth().node_count();
  m_x_new.resize(3, n);
  m_v_new.resize(3, n);
  if (m_options.newton_iterations > 1) m_f.resize(3, n);
  m_pins_laid_out = this->pins().version();
  lay_out();
}

template <class Scalar>
void ImplicitEuler<Scalar>::lay_out() {
  if (this->pins().version() != m_pins_laid_out) {
    m_assembler =
        JacobianAssembler<Scalar>(this->cloth(), this->pins().holding(), m_options.pin_treatment, m_options.threads);
    m_pins_laid_out = this->pins().version();
  }
  m_system = m_assembler.make_system();
  m_dv.setZero(m_system.size());
  m_solver->analyze(m_system);  // symbolic work once per layout
  if (m_options.newton_iterations > 1) {
    m_g.setZero(m_system.size());
    m_delta.setZero(m_system.size());
  }
}

template <class Scalar>
void ImplicitEuler<Scalar>::constrain_moving_pins(const State<Scalar>& state, Scalar dt) {
  const PinSet<Scalar>& pins = this->pins();
  const std::vector<int>& row_of_node = m_assembler.row_of_node();
  for (std::size_t k = 0; k < pins.nodes().size(); ++k) {
    if (pins.path(k).holds()) continue;
    const int node = pins.nodes()[k];
    const Vec3<Scalar> velocity = (m_pin_end.col(Index(k)) - state.positions.col(node)) / dt;
    m_system.constraints.fix(row_of_node[static_cast<std::size_t>(node)], velocity - state.velocities.col(node));
  }
}

template <class Scalar>
void ImplicitEuler<Scalar>::advance(const State<Scalar>& state, Scalar dt) {
  m_v_new = state.velocities;
  const std::vector<int>& node_of_row = m_assembler.node_of_row();
  for (std::size_t r = 0; r < node_of_row.size(); ++r)
    m_v_new.col(node_of_row[r]) += m_dv.template segment<3>(3 * static_cast<Index>(r));
  const std::vector<int>& pins = this->pins().nodes();
  for (std::size_t k = 0; k < pins.size(); ++k)
    m_v_new.col(pins[k]) = (m_pin_end.col(Index(k)) - state.positions.col(pins[k])) / dt;
  m_x_new = state.positions + dt * m_v_new;
  for (std::size_t k = 0; k < pins.size(); ++k) m_x_new.col(pins[k]) = m_pin_end.col(Index(k));
}

template <class Scalar>
double ImplicitEuler<Scalar>::nonlinear_residual(Scalar time, Scalar dt) {
  m_forces.force(m_x_new, m_v_new, time, m_f);
  const std::vector<int>& node_of_row = m_assembler.node_of_row();
  const VectorX<Scalar>& masses = this->cloth().masses();
  double g2 = 0;
  for (std::size_t r = 0; r < node_of_row.size(); ++r) {
    const int node = node_of_row[r];
    const Index i = 3 * static_cast<Index>(r);
    m_g.template segment<3>(i) = masses[node] * m_dv.template segment<3>(i) - dt * m_f.col(node);
    m_system.constraints.project_row(static_cast<int>(r), m_g.data() + i);
    g2 += double(m_g.template segment<3>(i).squaredNorm());
  }
  return std::sqrt(g2);
}

template <class Scalar>
StepStatus ImplicitEuler<Scalar>::step(State<Scalar>& state) {
  this->require_state_fits(state);
  const Scalar dt = this->dt();
  if (this->pins().version() != m_pins_laid_out) lay_out();
  this->pins().positions(state.time + dt, state.positions, m_pin_end);
  m_assembler.assemble_system(state.positions, state.velocities, state.time, dt, m_options.jacobian, m_system);
  constrain_moving_pins(state, dt);
  // Contacts become velocity constraints of the solve; solved again while the set changes.
  ContactHandler<Scalar>& contacts = this->contacts();
  const std::vector<int>& row_of_node = m_assembler.row_of_node();
  if (contacts.active())
    contacts.constrain(state.positions, state.velocities, state.time, dt, row_of_node, m_system.constraints);
  // m_dv still holds the previous step's solution: the warm start of iterative solvers.
  SolveStatus solved = m_solver->solve(m_system, m_dv);
  int iterations = solved.iterations;
  for (int solves = 1;
       solved.ok() && m_dv.allFinite() &&
       contacts.revise(m_system, m_dv, state.positions, state.velocities, dt, row_of_node, m_system.constraints) &&
       solves < m_options.contact_rounds;
       ++solves) {
    solved = m_solver->solve(m_system, m_dv);
    iterations += solved.iterations;
  }
  StepStatus status{step_error(solved.error), iterations, solved.residual};
  if (!solved.ok() || !m_dv.allFinite()) {
    m_dv.setZero();  // a failed solve is no warm start
    if (status.ok()) status.error = StepError::NonFiniteState;
    return status;
  }
  // v+ = v + dv on free nodes; pinned nodes on their paths; x+ = x + dt v+.
  advance(state, dt);
  m_newton_done = 1;
  m_newton_residual = 0;
  if (m_options.newton_iterations > 1) {
    // Newton on g(dv) = M dv - dt f(x + dt (v + dv), v + dv) = 0, whose Jacobian is the system
    // matrix assembled at the current iterate. Scale: |dt f(x_t, v_t)| on the unconstrained rows.
    const Scalar end = state.time + dt;
    m_forces.force(state.positions, state.velocities, state.time, m_f);
    double scale = 0;
    for (std::size_t r = 0; r < m_assembler.node_of_row().size(); ++r) {
      const auto f = m_f.col(m_assembler.node_of_row()[r]);
      switch (m_system.constraints.kind(static_cast<int>(r))) {
        case ConstraintKind::Free: scale += double(f.squaredNorm()); break;
        case ConstraintKind::Fixed: break;
        case ConstraintKind::Projected: {
          Vec3<Scalar> free = f;
          m_system.constraints.project_row(static_cast<int>(r), free.data());
          scale += double(free.squaredNorm());
          break;
        }
      }
    }
    scale = std::max(double(dt) * std::sqrt(scale), 1e-300);
    m_system.constraints.zero_values();  // dv meets the constraints: the corrections keep them
    double g = nonlinear_residual(end, dt);
    m_newton_residual = g / scale;
    while (m_newton_done < m_options.newton_iterations && m_newton_residual > m_options.newton_tolerance) {
      m_assembler.assemble_system(m_x_new, m_v_new, end, dt, m_options.jacobian, m_system);
      m_system.rhs = -m_g;
      m_delta.setZero();
      const SolveStatus inner = m_solver->solve(m_system, m_delta);
      if (!inner.ok() || !m_delta.allFinite()) {
        m_dv.setZero();
        StepStatus failed{step_error(inner.error), inner.iterations, inner.residual};
        if (failed.ok()) failed.error = StepError::NonFiniteState;
        return failed;
      }
      status.iterations += inner.iterations;
      m_dv += m_delta;
      advance(state, dt);
      g = nonlinear_residual(end, dt);
      m_newton_residual = g / scale;
      ++m_newton_done;
    }
    if (m_newton_residual > m_options.newton_tolerance) {
      m_dv.setZero();
      return {StepError::NoConvergence, status.iterations, m_newton_residual};
    }
  }
  this->respond_to_contacts(state, dt, m_x_new, m_v_new);
  if (!(m_x_new.allFinite() && m_v_new.allFinite())) {
    m_dv.setZero();
    status.error = StepError::NonFiniteState;
    return status;
  }
  state.positions.swap(m_x_new);
  state.velocities.swap(m_v_new);
  state.time += dt;
  return status;
}

}  // namespace drape
