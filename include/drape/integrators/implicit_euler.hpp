#pragma once
/// \file implicit_euler.hpp
/// Linearised implicit (backward) Euler, Baraff & Witkin 1998, the brief's part (b):
/// \f[ \Bigl(M - \Delta t \frac{\partial f}{\partial v} - \Delta t^2 \frac{\partial f}{\partial x}\Bigr) \Delta v
///     = \Delta t \Bigl(f(x_t, v_t) + \Delta t \frac{\partial f}{\partial x} v_t\Bigr), \qquad
///     v_{t+1} = v_t + \Delta v, \quad x_{t+1} = x_t + \Delta t\, v_{t+1}. \f]
/// Pinned nodes keep \f$ \Delta v = 0 \f$ (eliminated from the system or filtered, see
/// PinTreatment). The Jacobian variant and the linear solver are chosen at run time
/// (ImplicitOptions); docs/implicit.md has the derivation and the measurements behind the defaults.
///
/// A step that fails (solver failure, matrix not positive definite, no convergence, non-finite
/// result) returns the reason and leaves the state unchanged. After the first step, `step()`
/// performs no heap allocation with the iterative solvers (tested).

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "drape/core/cloth.hpp"
#include "drape/core/validation.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/solvers/solver_registry.hpp"

namespace drape {

struct ImplicitOptions {
  /// Spd: symmetric positive definite system for any deformation; measured the fastest and the
  /// most robust (docs/implicit.md, "Default Jacobian").
  JacobianVariant jacobian = JacobianVariant::Spd;
  /// Linear solver by name, see available_solvers() and solvers/solver_registry.hpp; cg was the
  /// fastest at every size measured at dt <= 1/60; direct solvers win only for very large dt
  /// (docs/implicit.md, "Default solver").
  std::string solver = "cg";
  /// Preconditioner of cg (the other solvers ignore it; bicgstab always uses block Jacobi).
  /// Multigrid needs ~10 iterations where block Jacobi needs 120-190 at dt = 1/60
  /// (docs/implicit.md, "Multigrid preconditioner").
  Preconditioner preconditioner = Preconditioner::Multigrid;
  double tolerance = 1e-6;     ///< relative residual |b - A dv| / |b| for iterative solvers
  int max_iterations = 2000;   ///< iteration cap of iterative solvers
  int threads = 0;             ///< 0 = all available
  PinTreatment pins = PinTreatment::Eliminate;
  /// 1 = the brief's single linearised step. More = Newton iterations on the nonlinear backward
  /// Euler equations \f$ M \Delta v = \Delta t\, f(x + \Delta t (v + \Delta v), v + \Delta v) \f$,
  /// starting from the linearised step; stops early when the residual is below
  /// `newton_tolerance` times \f$ |\Delta t\, f(x_t, v_t)| \f$.
  int newton_iterations = 1;
  double newton_tolerance = 1e-6;

  /// \throws std::invalid_argument naming the first invalid option (unknown solver, a solver this
  /// build lacks, tolerance not in (0, 1), max_iterations < 1, threads < 0, Exact Jacobian with a
  /// symmetric-only solver, filtered pins with a direct solver).
  void validate() const;
};

template <class Scalar = double>
class ImplicitEuler {
 public:
  /// \throws std::invalid_argument as ImplicitOptions::validate().
  explicit ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options = {});

  /// Advances `state` by `dt`; on failure `state` is unchanged and the status says why.
  /// \throws std::invalid_argument if dt is not finite and > 0 or the state has the wrong size.
  StepStatus step(State<Scalar>& state, Scalar dt);

  const ImplicitOptions& options() const { return m_options; }
  const Cloth<Scalar>& cloth() const { return m_assembler.cloth(); }
  const JacobianAssembler<Scalar>& assembler() const { return m_assembler; }
  /// The system of the last step: A, b and the solution dv (3 per system node, see
  /// JacobianAssembler::node_of_row()).
  const BlockSparseMatrix<Scalar>& system_matrix() const { return m_a; }
  const VectorX<Scalar>& rhs() const { return m_rhs; }
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
  BlockSparseMatrix<Scalar> m_a;
  VectorX<Scalar> m_rhs, m_dv;
  Matrix3X<Scalar> m_x_new, m_v_new;
  // Newton iterations only
  ForceAssembler<Scalar> m_forces;
  Matrix3X<Scalar> m_f;
  VectorX<Scalar> m_g, m_delta;
  int m_newton_done = 0;
  double m_newton_residual = 0;

  /// x+ = x + dt (v + dv), v+ = v + dv into m_x_new, m_v_new (pinned nodes fixed).
  void advance(const State<Scalar>& state, Scalar dt);
  /// g = M dv - dt f(m_x_new, m_v_new) on the system rows; returns |g|.
  double nonlinear_residual(Scalar dt);
};

// ---------------------------------------------------------------------------------------------

inline void ImplicitOptions::validate() const {
  detail::require_available_solver(solver);
  if (!(std::isfinite(tolerance) && tolerance > 0 && tolerance < 1))
    detail::fail_argument("tolerance", detail::to_text(tolerance), "finite, > 0 and < 1");
  detail::require_at_least("max_iterations", max_iterations, 1);
  detail::require_at_least("threads", threads, 0);
  detail::require_at_least("newton_iterations", newton_iterations, 1);
  if (!(std::isfinite(newton_tolerance) && newton_tolerance > 0))
    detail::fail_argument("newton_tolerance", detail::to_text(newton_tolerance), "finite and > 0");
  if (jacobian == JacobianVariant::Exact && solver_requires_symmetric(solver))
    detail::fail_argument("solver", "'" + solver + "' with jacobian = exact",
                          "a non-symmetric solver for the Exact Jacobian: bicgstab, lu or umfpack");
  if (pins == PinTreatment::Filter && !solver_supports_filter(solver))
    detail::fail_argument("pins", "filter with solver '" + solver + "'",
                          "eliminate, or filter with an iterative solver (cg, bicgstab)");
}

template <class Scalar>
ImplicitEuler<Scalar>::ImplicitEuler(const Cloth<Scalar>& cloth, const ImplicitOptions& options)
    : m_options((options.validate(), options)),
      m_assembler(cloth, options.pins, options.threads),
      m_forces(cloth, options.threads) {
  IterativeSettings settings;
  settings.tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  settings.threads = options.threads;
  settings.preconditioner = options.preconditioner;
  m_solver = make_linear_solver<Scalar>(options.solver, settings);
  m_solver->set_grid_layout({cloth.grid().nx(), cloth.grid().ny(), m_assembler.row_of_node()});
  m_a = m_assembler.make_matrix();
  m_rhs.setZero(m_a.size());
  m_dv.setZero(m_a.size());
  m_x_new.resize(3, cloth.node_count());
  m_v_new.resize(3, cloth.node_count());
  m_solver->analyze(m_a);  // symbolic work once per cloth
  if (options.newton_iterations > 1) {
    m_f.resize(3, cloth.node_count());
    m_g.setZero(m_a.size());
    m_delta.setZero(m_a.size());
  }
}

template <class Scalar>
void ImplicitEuler<Scalar>::advance(const State<Scalar>& state, Scalar dt) {
  m_v_new = state.velocities;
  const std::vector<int>& node_of_row = m_assembler.node_of_row();
  for (std::size_t r = 0; r < node_of_row.size(); ++r)
    m_v_new.col(node_of_row[r]) += m_dv.template segment<3>(3 * static_cast<Index>(r));
  for (int p : cloth().pins().nodes()) m_v_new.col(p).setZero();
  m_x_new = state.positions + dt * m_v_new;
  for (int p : cloth().pins().nodes()) m_x_new.col(p) = state.positions.col(p);
}

template <class Scalar>
double ImplicitEuler<Scalar>::nonlinear_residual(Scalar dt) {
  m_forces.force(m_x_new, m_v_new, m_f);
  const std::vector<int>& node_of_row = m_assembler.node_of_row();
  const VectorX<Scalar>& masses = cloth().grid().masses();
  double g2 = 0;
  for (std::size_t r = 0; r < node_of_row.size(); ++r) {
    const int node = node_of_row[r];
    const Index i = 3 * static_cast<Index>(r);
    m_g.template segment<3>(i) = masses[node] * m_dv.template segment<3>(i) - dt * m_f.col(node);
    if (m_assembler.filter()[r]) m_g.template segment<3>(i).setZero();
    g2 += double(m_g.template segment<3>(i).squaredNorm());
  }
  return std::sqrt(g2);
}

template <class Scalar>
StepStatus ImplicitEuler<Scalar>::step(State<Scalar>& state, Scalar dt) {
  detail::require_positive_finite("dt", dt);
  const int n = cloth().node_count();
  if (state.positions.cols() != n || state.velocities.cols() != n)
    detail::fail_argument("state", detail::to_text(state.positions.cols()) + " nodes",
                          detail::to_text(n) + " nodes (the cloth's)");
  m_assembler.assemble_system(state.positions, state.velocities, dt, m_options.jacobian, m_a, m_rhs);
  // m_dv still holds the previous step's solution: the warm start of iterative solvers.
  const std::uint8_t* filter = m_options.pins == PinTreatment::Filter ? m_assembler.filter().data() : nullptr;
  StepStatus status = m_solver->solve(m_a, m_rhs, m_dv, filter);
  if (!status.ok() || !m_dv.allFinite()) {
    m_dv.setZero();  // a failed solve is no warm start
    if (status.ok()) status.error = StepError::NonFiniteState;
    return status;
  }
  // v+ = v + dv on free nodes, 0 on pinned ones; x+ = x + dt v+ (pinned nodes stay put).
  advance(state, dt);
  m_newton_done = 1;
  m_newton_residual = 0;
  if (m_options.newton_iterations > 1) {
    // Newton on g(dv) = M dv - dt f(x + dt (v + dv), v + dv) = 0, whose Jacobian is the system
    // matrix assembled at the current iterate. Scale: |dt f(x_t, v_t)|.
    m_forces.force(state.positions, state.velocities, m_f);
    double scale = 0;
    for (std::size_t r = 0; r < m_assembler.node_of_row().size(); ++r)
      if (!m_assembler.filter()[r]) scale += double(m_f.col(m_assembler.node_of_row()[r]).squaredNorm());
    scale = std::max(double(dt) * std::sqrt(scale), 1e-300);
    double g = nonlinear_residual(dt);
    m_newton_residual = g / scale;
    while (m_newton_done < m_options.newton_iterations && m_newton_residual > m_options.newton_tolerance) {
      m_assembler.assemble_system(m_x_new, m_v_new, dt, m_options.jacobian, m_a, m_rhs);
      m_rhs = -m_g;
      m_delta.setZero();
      const StepStatus inner = m_solver->solve(m_a, m_rhs, m_delta, filter);
      if (!inner.ok() || !m_delta.allFinite()) {
        m_dv.setZero();
        StepStatus failed = inner;
        if (failed.ok()) failed.error = StepError::NonFiniteState;
        return failed;
      }
      status.iterations += inner.iterations;
      m_dv += m_delta;
      advance(state, dt);
      g = nonlinear_residual(dt);
      m_newton_residual = g / scale;
      ++m_newton_done;
    }
    if (m_newton_residual > m_options.newton_tolerance) {
      m_dv.setZero();
      return {StepError::NoConvergence, status.iterations, m_newton_residual};
    }
  }
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
