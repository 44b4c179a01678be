#include <catch2/catch.hpp>

#include <cstring>
#include <map>
#include <set>
#include <tuple>

#include "drape/physics/diagnostics.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/spring_kernel.hpp"
#include "drape/platform/team.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// The textbook assembly: gravity, then every spring added to a and subtracted from b.
template <class S>
Matrix3X<S> per_spring_forces(const Cloth<S>& cloth, const Matrix3X<S>& x, const Matrix3X<S>& v) {
  const SpringSet<S>& sp = cloth.springs();
  Matrix3X<S> f(3, cloth.node_count());
  for (int i = 0; i < cloth.node_count(); ++i) f.col(i) = cloth.grid().masses()[i] * cloth.gravity();
  for (int s = 0; s < sp.size(); ++s) {
    const int a = sp.a()[s], b = sp.b()[s];
    const Vec3<S> fa =
        spring_force<S>(x.col(a), x.col(b), v.col(a), v.col(b), sp.rest_length()[s], sp.stiffness()[s], sp.damping()[s]);
    f.col(a) += fa;
    f.col(b) -= fa;
  }
  return f;
}

// Shapes with and without bend springs in each direction, and more rows than one run holds.
const std::pair<int, int> shapes[] = {{2, 2}, {2, 5}, {5, 2}, {3, 3}, {7, 4}, {70, 3}, {33, 33}};

}  // namespace

TEST_CASE("spring families: every spring has exactly one slot and one run, with its offset and parameters",
          "[assembler][families]") {
  for (const auto& shape : shapes) {
    auto spec = test::small_spec<double>(shape.first, 10.0);
    spec.ny = shape.second;
    const Cloth<double> cloth(spec);
    const SpringSet<double>& sp = cloth.springs();
    const SpringFamilies<double> families(sp, cloth.node_count());
    INFO(shape.first << " x " << shape.second);
    REQUIRE(families.family_count() <= 6);
    // Slot (family, a) of every spring: unique, and the family's offset leads from a to b.
    std::set<std::pair<int, int>> slots;
    for (int s = 0; s < sp.size(); ++s) {
      const int k = families.family_of()[std::size_t(s)];
      REQUIRE(sp.b()[s] - sp.a()[s] == families.offsets()[std::size_t(k)]);
      REQUIRE(slots.insert({k, sp.a()[s]}).second);
      // The second node's slot index stays inside the padded force array.
      REQUIRE(std::abs(families.offsets()[std::size_t(k)]) <= families.padding());
    }
    // The runs cover exactly these slots, once each, with the springs' parameters.
    std::map<std::pair<int, int>, int> spring_at;
    for (int s = 0; s < sp.size(); ++s) spring_at[{families.family_of()[std::size_t(s)], sp.a()[s]}] = s;
    std::set<std::pair<int, int>> covered;
    for (const auto& run : families.runs()) {
      REQUIRE(run.count >= 1);
      REQUIRE(run.count <= SpringFamilies<double>::max_run_length);
      for (int j = 0; j < run.count; ++j) {
        const auto slot = std::make_pair(run.family, run.first + j);
        REQUIRE(spring_at.count(slot) == 1);
        const int s = spring_at[slot];
        REQUIRE(run.rest_length == sp.rest_length()[s]);
        REQUIRE(run.stiffness == sp.stiffness()[s]);
        REQUIRE(run.damping == sp.damping()[s]);
        REQUIRE(covered.insert(slot).second);
      }
    }
    REQUIRE(covered.size() == std::size_t(sp.size()));
    // Thread shares of the runs: contiguous, complete, in order, for any team size.
    for (int parts = 1; parts <= 4; ++parts) {
      int next = 0;
      for (int part = 0; part < parts; ++part) {
        const auto share = families.run_share(part, parts);
        REQUIRE(share.first == next);
        REQUIRE(share.second >= share.first);
        next = share.second;
      }
      REQUIRE(next == int(families.runs().size()));
    }
  }
}

TEST_CASE("node gather: each spring's slot is read by exactly its two nodes, with opposite signs",
          "[assembler][families]") {
  auto spec = test::small_spec<double>(7, 10.0);
  spec.ny = 5;
  const Cloth<double> cloth(spec);
  const SpringSet<double>& sp = cloth.springs();
  const SpringFamilies<double> families(sp, cloth.node_count());
  // The gather's rule: node i adds slot (k, i) and subtracts slot (k, i - offset_k).
  std::map<std::tuple<int, int, int>, int> reads;  // (family, slot, sign) -> reading node
  for (int i = 0; i < cloth.node_count(); ++i) {
    for (int k = 0; k < families.family_count(); ++k) {
      reads[{k, i, +1}] = i;
      reads[{k, i - families.offsets()[std::size_t(k)], -1}] = i;
    }
  }
  for (int s = 0; s < sp.size(); ++s) {
    const int k = families.family_of()[std::size_t(s)];
    REQUIRE(reads.at({k, sp.a()[s], +1}) == sp.a()[s]);
    REQUIRE(reads.at({k, sp.a()[s], -1}) == sp.b()[s]);
  }
}

TEMPLATE_TEST_CASE("the vectorised force pass equals the per-spring sum", "[assembler]", float, double) {
  using S = TestType;
  for (const auto& shape : shapes) {
    auto spec = test::small_spec<S>(shape.first, S(10));
    spec.ny = shape.second;
    spec.springs = {{S(300), S(2)}, {S(200), S(1)}, {S(50), S(0.5)}};
    const Cloth<S> cloth(spec);
    const Matrix3X<S> x = test::jiggled_positions(cloth, S(0.3), 21);
    const Matrix3X<S> v = test::random_velocities<S>(cloth.node_count(), S(2), 22);
    const Matrix3X<S> expected = per_spring_forces(cloth, x, v);
    for (int threads : {1, 2}) {
      Matrix3X<S> f(3, cloth.node_count());
      ForceAssembler<S>(cloth, threads).force(x, v, 0, f);
      INFO(shape.first << " x " << shape.second << ", " << threads << " thread(s)");
      const S tol = std::is_same<S, float>::value ? S(1e-5) : S(1e-13);
      REQUIRE((f - expected).cwiseAbs().maxCoeff() <= tol * expected.cwiseAbs().maxCoeff());
    }
  }
}

TEST_CASE("a zero-length spring gives a non-finite force, not a silent zero", "[assembler]") {
  const Cloth<double> cloth(test::small_spec<double>(4, 10.0));
  Matrix3X<double> x = cloth.grid().rest_positions();
  x.col(1) = x.col(0);  // structural spring 0 -> 1 collapses
  const Matrix3X<double> v = Matrix3X<double>::Zero(3, cloth.node_count());
  Matrix3X<double> f(3, cloth.node_count());
  ForceAssembler<double>(cloth, 1).force(x, v, 0, f);
  REQUIRE(!f.col(0).allFinite());
  REQUIRE(!f.col(1).allFinite());
  REQUIRE(f.col(cloth.node_count() - 1).allFinite());  // far away: untouched
}

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
    forces.force(x, v, 0, f);
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
  ForceAssembler<S>(cloth, 1).force(x, v, 0, f);
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
  ForceAssembler<double>(cloth, 1).force(x, v, 0, f);
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
  ForceAssembler<double>(cloth, 1).force(x, rigid, 0, f);
  REQUIRE(f.norm() <= 1e-12);
}

TEST_CASE("1 and 2 threads give bitwise identical forces", "[assembler][threads]") {
  for (int n : {33, 129}) {  // the default cloth (6.2k springs) already uses the second thread
    ClothSpec<double> spec;
    spec.nx = spec.ny = n;
    const Cloth<double> cloth(spec);
    const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 5);
    const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 6);
    Matrix3X<double> f1(3, cloth.node_count()), f2(3, cloth.node_count());
    ForceAssembler<double>(cloth, 1).force(x, v, 0, f1);
    const ForceAssembler<double> two(cloth, 2);
    REQUIRE(two.threads() == std::min(2, max_threads()));
    two.force(x, v, 0, f2);
    INFO(n << " x " << n);
    REQUIRE(std::memcmp(f1.data(), f2.data(), sizeof(double) * std::size_t(f1.size())) == 0);
  }
}
