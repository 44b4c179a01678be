#pragma once
// Checks of the dihedral bending term (physics/dihedral_bending.hpp) shared by its tests and the
// seam hinges' (garment/seam_hinges.hpp): the force and the derivative blocks as dense matrices,
// and central differences of the force to hold them against.

#include <array>
#include <atomic>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "drape/physics/dihedral_bending.hpp"

namespace drape::test::dihedral {

using Dense = Eigen::MatrixXd;

/// `x` moved by up to `amplitude` in every coordinate.
template <class S>
Matrix3X<S> jittered(const Matrix3X<S>& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Matrix3X<S> out = x;
  for (Index k = 0; k < out.size(); ++k) out.data()[k] += S(u(rng));
  return out;
}

template <class S>
Matrix3X<S> force_of(const DihedralBending<S>& term, const Matrix3X<S>& x, const Matrix3X<S>& v) {
  Matrix3X<S> f = Matrix3X<S>::Zero(3, x.cols());
  term.add_force(x, v, S(0), f);
  return f;
}

/// Dense derivative blocks, checked as the implicit assembly needs them: a pair a != b only if
/// coupled_nodes() lists it, and no two threads in the same row a at once.
template <class S>
class Recorder final : public ForceDerivatives<S> {
 public:
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  Recorder(const ForceTerm<S>& term, int n, bool symmetric)
      : dfdx(Matrix::Zero(3 * n, 3 * n)), dfdv(Matrix::Zero(3 * n, 3 * n)), m_symmetric(symmetric), m_busy(n) {
    for (const std::array<int, 2>& pair : term.coupled_nodes()) {
      m_pairs.insert({pair[0], pair[1]});
      m_pairs.insert({pair[1], pair[0]});
    }
    for (std::atomic<int>& b : m_busy) b = 0;
  }
  bool symmetric() const override { return m_symmetric; }
  void add(int a, int b, const Mat3<S>& x_block, const Mat3<S>& v_block) override {
    if (a != b && m_pairs.count({a, b}) == 0) ++undeclared;
    if (m_busy[static_cast<std::size_t>(a)].fetch_add(1) != 0) ++overlapping;
    dfdx.template block<3, 3>(3 * a, 3 * b) += x_block;
    dfdv.template block<3, 3>(3 * a, 3 * b) += v_block;
    m_busy[static_cast<std::size_t>(a)].fetch_sub(1);
  }
  Matrix dfdx, dfdv;
  std::atomic<int> undeclared{0}, overlapping{0};

 private:
  bool m_symmetric;
  std::set<std::pair<int, int>> m_pairs;
  std::vector<std::atomic<int>> m_busy;
};

/// Central differences of the force with respect to positions (`wrt_x`) or velocities, in S.
template <class S>
Dense fd_jacobian(const DihedralBending<S>& term, const Matrix3X<S>& x, const Matrix3X<S>& v, bool wrt_x, S h) {
  Dense j(x.size(), x.size());
  for (Index k = 0; k < x.size(); ++k) {
    Matrix3X<S> xp = x, xm = x, vp = v, vm = v;
    (wrt_x ? xp : vp).data()[k] += h;
    (wrt_x ? xm : vm).data()[k] -= h;
    const Matrix3X<S> df = force_of(term, xp, vp) - force_of(term, xm, vm);
    for (Index q = 0; q < x.size(); ++q) j(q, k) = double(df.data()[q]) / (2 * double(h));
  }
  return j;
}

/// Largest entry of |a - b| over the largest of |b|.
inline double relative_error(const Dense& a, const Dense& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

template <class S>
Dense dense(const Matrix3X<S>& m) {
  return m.template cast<double>();
}
template <class M>
Dense dense_matrix(const M& m) {
  return m.template cast<double>();
}

}  // namespace drape::test::dihedral
