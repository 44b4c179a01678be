#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "drape/platform/sine.hpp"

using drape::detail::cosine;
using drape::detail::sine;

TEST_CASE("own sine and cosine: within 1e-15 of libm over the wind's phases, exact at the landmarks", "[sine]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> near(-40.0, 40.0), far(-6e6, 6e6), tiny(-1e-3, 1e-3);
  double sine_error = 0, cosine_error = 0;
  for (int k = 0; k < 300000; ++k) {
    const double x = k % 3 == 0 ? near(rng) : k % 3 == 1 ? far(rng) : tiny(rng);
    sine_error = std::max(sine_error, std::abs(sine(x) - std::sin(x)));
    cosine_error = std::max(cosine_error, std::abs(cosine(x) - std::cos(x)));
  }
  CHECK(sine_error < 1e-15);
  CHECK(cosine_error < 1e-15);
  // Every fold of the reduction: the quadrant edges and their neighbours.
  const double pi = 3.14159265358979323846;
  for (int q = -16; q <= 16; ++q)
    for (double eps : {-1e-9, 0.0, 1e-9}) {
      const double x = q * pi / 2 + eps;
      INFO("x = " << x);
      CHECK(std::abs(sine(x) - std::sin(x)) < 1e-15);
      CHECK(std::abs(cosine(x) - std::cos(x)) < 1e-15);
    }
  CHECK(sine(0.0) == 0.0);
  CHECK(cosine(0.0) == 1.0);
  CHECK(sine(1e-300) == 1e-300);  // the odd series keeps tiny arguments exact
  CHECK(sine(-0.5) == -sine(0.5));
  CHECK(cosine(-0.5) == cosine(0.5));
}
