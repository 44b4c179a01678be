#pragma once
/// \file force_assembler.hpp
/// Total force on every node: the damped springs of equation (2) plus gravity \f$ m_i g \f$.
///
/// Forces are computed for pinned nodes too (the negative of a pinned node's force is the reaction
/// its pin exerts, see diagnostics.hpp); the integrators ignore them.
/// Threading: springs are processed colour by colour (spring_set.hpp), each colour split statically
/// between threads. Every node receives its contributions in the same order whatever the thread
/// count, so results are bitwise identical for 1 and N threads.

#include "drape/config.hpp"
#include "drape/core/cloth.hpp"
#include "drape/core/parallel.hpp"
#include "drape/physics/spring_kernel.hpp"

namespace drape {

template <class Scalar = double>
class ForceAssembler {
 public:
  /// Springs per thread below which extra threads are not woken.
  static constexpr long long min_springs_per_thread = 4096;

  /// \param threads 0 = all available (max_threads()).
  explicit ForceAssembler(const Cloth<Scalar>& cloth, int threads = 0) : m_cloth(&cloth), m_threads(threads) {}

  /// `f = spring forces(x, v) + M g`, `3 x n`; `f` must already have the right size.
  void force(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Matrix3X<Scalar>& f) const;

  const Cloth<Scalar>& cloth() const { return *m_cloth; }
  int threads() const { return effective_threads(m_threads, m_cloth->springs().size(), min_springs_per_thread); }

 private:
  const Cloth<Scalar>* m_cloth;
  int m_threads;
};

// ---------------------------------------------------------------------------------------------

template <class Scalar>
void ForceAssembler<Scalar>::force(const Matrix3X<Scalar>& x, const Matrix3X<Scalar>& v, Matrix3X<Scalar>& f) const {
  const Cloth<Scalar>& cloth = *m_cloth;
  const SpringSet<Scalar>& springs = cloth.springs();
  DRAPE_ASSERT(x.cols() == cloth.node_count() && v.cols() == cloth.node_count() && f.cols() == cloth.node_count(),
               "force(): x, v and f must have one column per node");
  const int* a = springs.a().data();
  const int* b = springs.b().data();
  const Scalar* rest = springs.rest_length().data();
  const Scalar* ks = springs.stiffness().data();
  const Scalar* kd = springs.damping().data();
  const std::vector<int>& colour = springs.colour_begin();
  const int colours = springs.colour_count();
  const Scalar* masses = cloth.grid().masses().data();
  const Vec3<Scalar> g = cloth.gravity();
  const Index n = cloth.node_count();

  const auto body = [&]() {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
    for (Index i = 0; i < n; ++i) f.col(i) = masses[i] * g;
    for (int c = 0; c < colours; ++c) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
      for (int s = colour[c]; s < colour[c + 1]; ++s) {
        const Vec3<Scalar> fa =
            spring_force<Scalar>(x.col(a[s]), x.col(b[s]), v.col(a[s]), v.col(b[s]), rest[s], ks[s], kd[s]);
        f.col(a[s]) += fa;
        f.col(b[s]) -= fa;
      }
    }
  };
#if defined(_OPENMP)
  const int t = threads();
  if (t > 1) {
#pragma omp parallel num_threads(t)
    body();
    return;
  }
#endif
  body();
}

}  // namespace drape
