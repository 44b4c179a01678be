#include <catch2/catch.hpp>

#include "drape/physics/spring_kernel.hpp"
#include "test_common.hpp"

using namespace drape;

TEMPLATE_TEST_CASE("spring force is minus the central-difference gradient of its energy", "[kernel]", float,
                   double) {
  using S = TestType;
  // float: the difference quotient loses digits, so a larger step and a looser bound.
  const S h = std::is_same<S, float>::value ? S(1e-3) : S(1e-6);
  const S eps = std::is_same<S, float>::value ? S(2e-2) : S(1e-6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const S rest = S(0.1);
    // lengths from 0.3x (compressed) to 2x (stretched) of rest
    Vec3<S> dir(S(u(rng)), S(u(rng)), S(u(rng)));
    dir.normalize();
    const S length = rest * S(0.3 + 0.85 * (u(rng) + 1));
    const Vec3<S> xa(S(u(rng)), S(u(rng)), S(u(rng)));
    const Vec3<S> xb = xa + length * dir;
    const S ks = S(500);
    const Vec3<S> zero = Vec3<S>::Zero();
    const Vec3<S> fa = spring_force<S>(xa, xb, zero, zero, rest, ks, S(0));
    const Vec3<S> fb = -fa;
    for (int k = 0; k < 3; ++k) {
      Vec3<S> e = Vec3<S>::Zero();
      e[k] = h;
      const S dEa = (spring_energy<S>(xa + e, xb, rest, ks) - spring_energy<S>(xa - e, xb, rest, ks)) / (2 * h);
      const S dEb = (spring_energy<S>(xa, xb + e, rest, ks) - spring_energy<S>(xa, xb - e, rest, ks)) / (2 * h);
      INFO("trial " << trial << " component " << k << " length/rest " << length / rest);
      REQUIRE(test::close<S>(fa[k], -dEa, eps * ks * rest));
      REQUIRE(test::close<S>(fb[k], -dEb, eps * ks * rest));
    }
  }
}

TEMPLATE_TEST_CASE("damping force is kd (v_ij . u) u along the spring", "[kernel]", float, double) {
  using S = TestType;
  // Spring along +x: u = (1, 0, 0). v_ij = vb - va = (1, 2, -3) - (0.5, 0, 0) -> v_ij . u = 0.5.
  const Vec3<S> xa(0, 0, 0), xb(S(0.2), 0, 0);
  const Vec3<S> va(S(0.5), 0, 0), vb(1, 2, -3);
  const Vec3<S> fa = spring_force<S>(xa, xb, va, vb, S(0.2), S(0), S(3));
  REQUIRE(fa.x() == Approx(1.5));
  REQUIRE(fa.y() == 0);
  REQUIRE(fa.z() == 0);
  // Stretched by 0.05 with ks = 100: elastic part 5 N towards b, damping adds on top.
  const Vec3<S> both = spring_force<S>(xa, Vec3<S>(S(0.25), 0, 0), va, vb, S(0.2), S(100), S(3));
  REQUIRE(both.x() == Approx(5 + 1.5));
  // Oblique spring: the damping force is parallel to u and its size is kd (v_ij . u).
  const Vec3<S> xc(S(0.1), S(0.1), S(0.05));
  const Vec3<S> u = xc.normalized();
  const Vec3<S> fd = spring_force<S>(xa, xc, va, vb, xc.norm(), S(0), S(3));
  REQUIRE((fd - S(3) * (vb - va).dot(u) * u).norm() <= S(1e-5));
}
