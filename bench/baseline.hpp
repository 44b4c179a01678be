#pragma once
/// \file baseline.hpp
/// THE TEXTBOOK BASELINE. Not part of drape: the reference every headline benchmark figure is a
/// ratio to (docs/benchmarks.md). It is written the way a straightforward, correct solution of the
/// mass-spring model writes it, plainly and without tuning, so "N x faster than the baseline" means "N x
/// faster than the obvious implementation", measured in the same binary and the same run.
///
/// - `BaselineRk2`: the explicit midpoint rule with a plain per-spring loop over a
///   `std::vector<Spring>` (array of structs), single-threaded, forces returned by value.
/// - `BaselineImplicit`: the linearised implicit Euler (Baraff & Witkin 1998),
///   \f[ (M - \Delta t\, \partial f/\partial v - \Delta t^2\, \partial f/\partial x)\,\Delta v
///       = \Delta t\,(f + \Delta t\, \partial f/\partial x\; v), \f]
///   with the symmetric Baraff-Witkin Jacobian (the x-derivative of the damping term dropped),
///   both Jacobians rebuilt from Eigen triplets every step, the system matrix formed with sparse
///   matrix sums, pinned DOFs handled simply (their rows and columns replaced by the identity,
///   right-hand side 0), and `Eigen::SimplicialLDLT` analysed and factorised every step.
///
/// Both operate on drape's `Cloth<double>` / `State<double>` so they simulate exactly the same
/// springs, masses and pins as drape does.

#include <vector>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "drape/integrators/step_status.hpp"
#include "drape/model/cloth.hpp"

namespace drape_bench {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Matrix3X = drape::Matrix3X<double>;

/// One spring, textbook style.
struct Spring {
  int a, b;
  double rest, ks, kd;
};

inline std::vector<Spring> baseline_springs(const drape::Cloth<double>& cloth) {
  const drape::SpringSet<double>& sp = cloth.springs();
  std::vector<Spring> springs;
  for (int s = 0; s < sp.size(); ++s)
    springs.push_back({sp.a()[s], sp.b()[s], sp.rest_length()[s], sp.stiffness()[s], sp.damping()[s]});
  return springs;
}

/// f(x, v): gravity plus every spring, one loop, returned by value.
inline Matrix3X baseline_forces(const drape::Cloth<double>& cloth, const std::vector<Spring>& springs,
                                const Matrix3X& x, const Matrix3X& v) {
  const int n = cloth.node_count();
  Matrix3X f(3, n);
  for (int i = 0; i < n; ++i) f.col(i) = cloth.grid().masses()[i] * cloth.gravity();
  for (const Spring& s : springs) {
    const Vec3 d = x.col(s.b) - x.col(s.a);
    const double len = d.norm();
    const Vec3 u = d / len;
    const double magnitude = s.ks * (len - s.rest) + s.kd * (v.col(s.b) - v.col(s.a)).dot(u);
    f.col(s.a) += magnitude * u;
    f.col(s.b) -= magnitude * u;
  }
  return f;
}

/// Textbook RK2 (explicit midpoint).
class BaselineRk2 {
 public:
  explicit BaselineRk2(const drape::Cloth<double>& cloth) : m_cloth(cloth), m_springs(baseline_springs(cloth)) {}

  drape::StepStatus step(drape::State<double>& state, double dt) {
    const Matrix3X& x = state.positions;
    const Matrix3X& v = state.velocities;
    Matrix3X a1 = accelerations(x, v);
    Matrix3X x_mid = x + 0.5 * dt * v;
    Matrix3X v_mid = v + 0.5 * dt * a1;
    Matrix3X a2 = accelerations(x_mid, v_mid);
    Matrix3X x_new = x + dt * v_mid;
    Matrix3X v_new = v + dt * a2;
    for (int p : m_cloth.pins().nodes()) {
      x_new.col(p) = x.col(p);
      v_new.col(p).setZero();
    }
    if (!(x_new.allFinite() && v_new.allFinite())) return {drape::StepError::NonFiniteState, 0, 0.0};
    state.positions = x_new;
    state.velocities = v_new;
    state.time += dt;
    return {};
  }

 private:
  Matrix3X accelerations(const Matrix3X& x, const Matrix3X& v) const {
    Matrix3X acc = baseline_forces(m_cloth, m_springs, x, v);
    for (int i = 0; i < m_cloth.node_count(); ++i)
      acc.col(i) = m_cloth.pins().is_pinned(i) ? Vec3::Zero().eval() : Vec3(acc.col(i) / m_cloth.grid().masses()[i]);
    return acc;
  }

  const drape::Cloth<double>& m_cloth;
  std::vector<Spring> m_springs;
};

/// Textbook linearised implicit Euler: triplets + SimplicialLDLT, everything rebuilt every step.
class BaselineImplicit {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double>;
  using Vector = Eigen::VectorXd;

  explicit BaselineImplicit(const drape::Cloth<double>& cloth) : m_cloth(cloth), m_springs(baseline_springs(cloth)) {}

  /// df/dx and df/dv of all springs, assembled from triplets. Spring a->b with u = (x_b-x_a)/L:
  /// df_a/dx_b = ks (u u^T + (1 - l/L)(I - u u^T)) =: K, df_a/dv_b = kd u u^T =: D;
  /// blocks (a,a) and (b,b) get -K, (a,b) and (b,a) get +K (likewise D).
  void jacobians(const Matrix3X& x, SparseMatrix& dfdx, SparseMatrix& dfdv) const {
    const int dofs = 3 * m_cloth.node_count();
    std::vector<Eigen::Triplet<double>> tx, tv;
    for (const Spring& s : m_springs) {
      const Vec3 d = x.col(s.b) - x.col(s.a);
      const double len = d.norm();
      const Vec3 u = d / len;
      const Mat3 uu = u * u.transpose();
      const Mat3 K = s.ks * (uu + (1.0 - s.rest / len) * (Mat3::Identity() - uu));
      const Mat3 D = s.kd * uu;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          tx.emplace_back(3 * s.a + r, 3 * s.a + c, -K(r, c));
          tx.emplace_back(3 * s.b + r, 3 * s.b + c, -K(r, c));
          tx.emplace_back(3 * s.a + r, 3 * s.b + c, K(r, c));
          tx.emplace_back(3 * s.b + r, 3 * s.a + c, K(r, c));
          tv.emplace_back(3 * s.a + r, 3 * s.a + c, -D(r, c));
          tv.emplace_back(3 * s.b + r, 3 * s.b + c, -D(r, c));
          tv.emplace_back(3 * s.a + r, 3 * s.b + c, D(r, c));
          tv.emplace_back(3 * s.b + r, 3 * s.a + c, D(r, c));
        }
      }
    }
    dfdx.resize(dofs, dofs);
    dfdv.resize(dofs, dofs);
    dfdx.setFromTriplets(tx.begin(), tx.end());
    dfdv.setFromTriplets(tv.begin(), tv.end());
  }

  /// The system A dv = rhs of one step, pinned DOFs replaced by identity rows and columns.
  void assemble(const Matrix3X& x, const Matrix3X& v, double dt, SparseMatrix& A, Vector& rhs) const {
    const int n = m_cloth.node_count();
    const int dofs = 3 * n;
    SparseMatrix dfdx, dfdv;
    jacobians(x, dfdx, dfdv);
    Matrix3X f = baseline_forces(m_cloth, m_springs, x, v);
    const Eigen::Map<const Vector> v_flat(v.data(), dofs);
    rhs = dt * (Eigen::Map<const Vector>(f.data(), dofs) + dt * (dfdx * v_flat));

    Vector mass_diagonal(dofs);
    for (int i = 0; i < n; ++i) mass_diagonal.segment<3>(3 * i).setConstant(m_cloth.grid().masses()[i]);
    SparseMatrix mass(dofs, dofs);
    mass.setIdentity();
    mass = mass_diagonal.asDiagonal() * mass;
    A = mass - dt * dfdv - (dt * dt) * dfdx;

    // Pinned DOFs: identity row and column, zero right-hand side, so their dv is 0.
    std::vector<char> pinned(static_cast<std::size_t>(dofs), 0);
    for (int p : m_cloth.pins().nodes())
      for (int k = 0; k < 3; ++k) pinned[static_cast<std::size_t>(3 * p + k)] = 1;
    for (int col = 0; col < A.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(A, col); it; ++it)
        if (pinned[static_cast<std::size_t>(it.row())] || pinned[static_cast<std::size_t>(it.col())])
          it.valueRef() = it.row() == it.col() ? 1.0 : 0.0;
    for (int k = 0; k < dofs; ++k)
      if (pinned[static_cast<std::size_t>(k)]) rhs[k] = 0.0;
  }

  /// Solves A dv = rhs with a fresh SimplicialLDLT (ordering, symbolic and numeric factorisation).
  static bool solve(const SparseMatrix& A, const Vector& rhs, Vector& dv) {
    Eigen::SimplicialLDLT<SparseMatrix> solver;
    solver.compute(A);
    if (solver.info() != Eigen::Success) return false;
    dv = solver.solve(rhs);
    return solver.info() == Eigen::Success;
  }

  drape::StepStatus step(drape::State<double>& state, double dt) {
    const int n = m_cloth.node_count();
    Matrix3X& x = state.positions;
    Matrix3X& v = state.velocities;
    SparseMatrix A;
    Vector rhs, dv;
    assemble(x, v, dt, A, rhs);
    if (!solve(A, rhs, dv)) return {drape::StepError::NotPositiveDefinite, 0, 0.0};
    Matrix3X v_new = v + Eigen::Map<const Matrix3X>(dv.data(), 3, n);
    Matrix3X x_new = x + dt * v_new;
    if (!(x_new.allFinite() && v_new.allFinite())) return {drape::StepError::NonFiniteState, 0, 0.0};
    x = x_new;
    v = v_new;
    state.time += dt;
    return {};
  }

  /// dv of one step from `state` (for the accuracy check), empty on failure.
  Vector step_dv(const drape::State<double>& state, double dt) const {
    SparseMatrix A;
    Vector rhs, dv;
    assemble(state.positions, state.velocities, dt, A, rhs);
    if (!solve(A, rhs, dv)) return {};
    return dv;
  }

 private:
  const drape::Cloth<double>& m_cloth;
  std::vector<Spring> m_springs;
};

}  // namespace drape_bench
