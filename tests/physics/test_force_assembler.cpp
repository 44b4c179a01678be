#include <catch2/catch.hpp>

#include <cstring>

#include "drape/physics/diagnostics.hpp"
#include "drape/physics/force_assembler.hpp"
#include "test_common.hpp"

using namespace drape;

TEMPLATE_TEST_CASE("assembled force is minus the gradient of the total potential energy", "[assembler]", float,
                   double) {
  using S = TestType;
  const Cloth<S> cloth(test::small_spec<S>(4, S(10)));
  const ForceAssembler<S> forces(cloth, 1);
  const bool is_float = std::is_same<S, float>::value;
  const S h = is_float ? S(1e-3) : S(1e-6);
  const S eps = is_float ? S(3e-2) : S(1e-6);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    Matrix3X<S> x = test::jiggled_positions(cloth, S(0.4), seed);
    const Matrix3X<S> v = Matrix3X<S>::Zero(3, cloth.node_count());
    Matrix3X<S> f(3, cloth.node_count());
    forces.force(x, v, f);
    const auto potential = [&](const Matrix3X<S>& y) {
      return spring_potential_energy(cloth, y) + gravitational_potential_energy(cloth, y);
    };
    const S scale = S(300) * cloth.grid().spacing();
    for (Index k = 0; k < x.size(); ++k) {
      const S keep = x.data()[k];
      x.data()[k] = keep + h;
      const S e_plus = potential(x);
      x.data()[k] = keep - h;
      const S e_minus = potential(x);
      x.data()[k] = keep;
      INFO("seed " << seed << " dof " << k);
      REQUIRE(test::close<S>(f.data()[k], -(e_plus - e_minus) / (2 * h), eps * scale));
    }
  }
}

TEMPLATE_TEST_CASE("internal forces sum to zero and exert no net torque", "[assembler]", float, double) {
  using S = TestType;
  auto spec = test::small_spec<S>(6, S(0));
  spec.springs = {{S(300), S(2)}, {S(200), S(1)}, {S(50), S(0.5)}};
  const Cloth<S> cloth(spec);
  const Matrix3X<S> x = test::jiggled_positions(cloth, S(0.3), 11);
  const Matrix3X<S> v = test::random_velocities<S>(cloth.node_count(), S(2), 12);
  Matrix3X<S> f(3, cloth.node_count());
  ForceAssembler<S>(cloth, 1).force(x, v, f);
  const S tol = std::is_same<S, float>::value ? S(1e-3) : S(1e-10);
  REQUIRE(f.rowwise().sum().norm() <= tol * f.norm());
  Vec3<S> torque = Vec3<S>::Zero();
  for (int i = 0; i < cloth.node_count(); ++i) torque += x.col(i).cross(f.col(i));
  REQUIRE(torque.norm() <= tol * f.norm());
  REQUIRE(f.norm() > S(1));  // the configuration does load the springs
}

TEST_CASE("damping dissipates: power of the damping forces is -sum kd (v_ij . u)^2", "[assembler]") {
  auto spec = test::small_spec<double>(5, 0.0);
  spec.springs = {{0, 2}, {0, 1}, {0, 0.5}};
  const Cloth<double> cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.2, 3);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 4);
  Matrix3X<double> f(3, cloth.node_count());
  ForceAssembler<double>(cloth, 1).force(x, v, f);
  double expected = 0;
  const auto& sp = cloth.springs();
  for (int s = 0; s < sp.size(); ++s) {
    const Eigen::Vector3d u = (x.col(sp.b()[s]) - x.col(sp.a()[s])).normalized();
    const double w = (v.col(sp.b()[s]) - v.col(sp.a()[s])).dot(u);
    expected -= sp.damping()[s] * w * w;
  }
  const double power = (f.array() * v.array()).sum();
  REQUIRE(expected < 0);
  REQUIRE(power == Approx(expected).epsilon(1e-12));

  // A rigid motion (translation + rotation) stretches no spring at any rate: no damping force.
  Matrix3X<double> rigid(3, cloth.node_count());
  const Eigen::Vector3d omega(0.3, -1.0, 0.7), drift(1, 2, 3);
  for (int i = 0; i < cloth.node_count(); ++i) rigid.col(i) = drift + omega.cross(x.col(i));
  ForceAssembler<double>(cloth, 1).force(x, rigid, f);
  REQUIRE(f.norm() <= 1e-12);
}

TEST_CASE("1 and 2 threads give bitwise identical forces", "[assembler][threads]") {
  ClothSpec<double> spec;
  spec.nx = spec.ny = 129;  // large enough that the second thread is used
  const Cloth<double> cloth(spec);
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 5);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 6);
  Matrix3X<double> f1(3, cloth.node_count()), f2(3, cloth.node_count());
  ForceAssembler<double>(cloth, 1).force(x, v, f1);
  const ForceAssembler<double> two(cloth, 2);
  two.force(x, v, f2);
  INFO("threads used: " << two.threads());
  REQUIRE(std::memcmp(f1.data(), f2.data(), sizeof(double) * std::size_t(f1.size())) == 0);
}
