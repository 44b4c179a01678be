// The Cusick drape measures: the drape coefficient of a flat specimen (1) and of one hanging
// straight down (0), the shadow of overlapping and turned-over layers counted once, a shadow with
// a hole, a synthetic sinusoidal shadow's area and folds, the fold rule on its own, bad input named.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "drape/core/mesh_generators.hpp"
#include "drape/physics/drape_measures.hpp"

namespace {

const double pi = 3.14159265358979323846;

/// The area of the regular n-gon inscribed in a circle of radius r.
double inscribed_polygon_area(int n, double r) { return 0.5 * n * r * r * std::sin(2 * pi / n); }

/// A Cusick specimen whose overhang hangs from the disk's edge: the flat disk of `disk_radius`,
/// then rings of its boundary vertices `specimen_radius - disk_radius` down in steps of about h,
/// each `flare` further out at the bottom (0: a cylinder).
template <class S>
drape::ClothMesh<S> hanging_specimen(double disk_radius, double specimen_radius, double h, double flare) {
  drape::ClothMesh<S> mesh = drape::disk_mesh(S(disk_radius), S(h));
  const std::vector<int> top = mesh.groups.at("boundary");
  const int m = static_cast<int>(top.size()), first = mesh.vertex_count();
  const double drop = specimen_radius - disk_radius;
  const int layers = static_cast<int>(std::ceil(drop / h));
  mesh.positions.conservativeResize(3, first + layers * m);
  for (int l = 1; l <= layers; ++l)
    for (int j = 0; j < m; ++j) {
      const double angle = 2 * pi * j / m, radius = disk_radius + flare * l / layers;
      mesh.positions.col(first + (l - 1) * m + j) =
          drape::Vec3<S>(S(radius * std::cos(angle)), S(-drop * l / layers), S(radius * std::sin(angle)));
    }
  const auto ring_vertex = [&](int l, int j) {
    return l == 0 ? top[static_cast<std::size_t>(j % m)] : first + (l - 1) * m + j % m;
  };
  for (int l = 1; l <= layers; ++l)
    for (int j = 0; j < m; ++j) {
      const int a = ring_vertex(l - 1, j), b = ring_vertex(l - 1, j + 1), c = ring_vertex(l, j + 1),
                d = ring_vertex(l, j);
      mesh.triangles.push_back({a, c, b});
      mesh.triangles.push_back({a, d, c});
    }
  return mesh;
}

/// The flat disk `unit` (radius 1) stretched along each ray to r(theta) = r0 + a cos(n theta): a
/// shadow with n folds.
drape::ClothMesh<double> sinusoidal_shadow(drape::ClothMesh<double> unit, double r0, double a, int n) {
  for (int v = 0; v < unit.vertex_count(); ++v) {
    const double theta = std::atan2(unit.positions(2, v), unit.positions(0, v));
    unit.positions.col(v) *= r0 + a * std::cos(n * theta);
  }
  return unit;
}

/// The area of the polygon through the vertices of `loop` in the x-z plane (shoelace).
double loop_area(const drape::Matrix3X<double>& x, const std::vector<int>& loop) {
  double twice = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int a = loop[k], b = loop[(k + 1) % loop.size()];
    twice += x(0, a) * x(2, b) - x(0, b) * x(2, a);
  }
  return 0.5 * std::abs(twice);
}

}  // namespace

TEMPLATE_TEST_CASE("a flat specimen has drape coefficient 1 but for its polygon, and no folds", "[drape]", float,
                   double) {
  using S = TestType;
  const double disk_radius = 0.09, specimen_radius = 0.15, h = 0.005;
  drape::ClothMesh<S> mesh = drape::disk_mesh(S(specimen_radius), S(h));
  const drape::Vec3<S> centre(S(0.3), S(0.5), S(-0.2));
  mesh.positions.colwise() += centre;  // the specimen centred on the disk, resting on it
  const int rings = static_cast<int>(mesh.groups.at("boundary").size()) / 6;
  const drape::DrapeMeasures<S> m =
      drape::measure_drape(mesh.positions, mesh.triangles, centre, S(disk_radius), S(specimen_radius));

  // The shadow is the mesh's inscribed 6K-gon, measured to 1e-6 (float: its coordinates' rounding).
  const double polygon = inscribed_polygon_area(6 * rings, specimen_radius);
  const double accuracy = std::is_same<S, float>::value ? 2e-6 : 1e-6;
  REQUIRE(std::abs(double(m.shadow_area) - polygon) <= accuracy * polygon);
  const double disk_area = pi * disk_radius * disk_radius, specimen_area = pi * specimen_radius * specimen_radius;
  const double expected = (polygon - disk_area) / (specimen_area - disk_area);
  REQUIRE(std::abs(double(m.drape_coefficient) - expected) <= 2 * accuracy);
  // 1 but for the polygon's shortfall, pi^2 / (54 K^2) of the specimen's area.
  const double shortfall = pi * pi / (54.0 * rings * rings) * specimen_area / (specimen_area - disk_area);
  REQUIRE(1 - double(m.drape_coefficient) > 0.98 * shortfall);
  REQUIRE(1 - double(m.drape_coefficient) < 1.02 * shortfall);
  REQUIRE(drape::drape_coefficient(mesh.positions, mesh.triangles, centre, S(disk_radius), S(specimen_radius)) ==
          m.drape_coefficient);

  // The outline lies between the polygon's apothem and its circle; no folds.
  REQUIRE(m.outline_radius.size() == 3600);
  const double apothem = specimen_radius * std::cos(pi / (6 * rings));
  const double slack = 1e-6 * specimen_radius;
  REQUIRE(m.outline_radius.minCoeff() >= S(apothem - slack));
  REQUIRE(m.outline_radius.maxCoeff() <= S(specimen_radius + slack));
  REQUIRE(m.fold_count == 0);
  REQUIRE(drape::fold_count(mesh.positions, mesh.triangles, centre, S(disk_radius), S(specimen_radius)) == 0);
  REQUIRE(std::abs(double(m.outline_angle(0)) - pi / 3600) < 1e-7);
  REQUIRE(std::abs(double(m.outline_angle(900)) - (900.5 * 2 * pi / 3600)) < 1e-6);
}

TEST_CASE("a specimen hanging straight down has drape coefficient 0 but for its polygon; flared, it grows", "[drape]") {
  const double disk_radius = 0.09, specimen_radius = 0.15, h = 0.005;
  const double disk_area = pi * disk_radius * disk_radius, specimen_area = pi * specimen_radius * specimen_radius;
  const drape::Vec3<double> centre = drape::Vec3<double>::Zero();
  for (double flare : {0.0, 0.01, 0.03}) {
    const drape::ClothMesh<double> mesh = hanging_specimen<double>(disk_radius, specimen_radius, h, flare);
    const int m = static_cast<int>(mesh.groups.at("boundary").size());
    const drape::DrapeMeasures<double> measures =
        drape::measure_drape(mesh.positions, mesh.triangles, centre, disk_radius, specimen_radius);
    // The wall of a cylinder is seen edge-on and casts no shadow: the shadow is the disk's m-gon.
    // Flared, the bottom ring's m-gon.
    const double polygon = inscribed_polygon_area(m, disk_radius + flare);
    INFO("flare " << flare << ": drape coefficient " << measures.drape_coefficient);
    REQUIRE(std::abs(measures.shadow_area - polygon) <= 1e-6 * polygon);
    REQUIRE(std::abs(measures.drape_coefficient - (polygon - disk_area) / (specimen_area - disk_area)) <= 1e-6);
    if (flare == 0) {
      // 0 but for the m-gon's shortfall from the disk, (2 pi / m)^2 / 6 of the disk's area.
      const double shortfall = disk_area * std::pow(2 * pi / m, 2) / 6 / (specimen_area - disk_area);
      REQUIRE(measures.drape_coefficient <= 0);
      REQUIRE(-measures.drape_coefficient < 1.02 * shortfall);
      REQUIRE(-measures.drape_coefficient < 1e-3);
    }
    REQUIRE(measures.outline_radius.maxCoeff() <= disk_radius + flare + 1e-12);
    REQUIRE(measures.fold_count == 0);
  }
}

TEST_CASE("layers over one another and turned-over triangles cast one shadow; a shadow keeps its hole", "[drape]") {
  const drape::Vec3<double> centre = drape::Vec3<double>::Zero();
  SECTION("the specimen doubled: a second layer 1 cm above it") {
    const drape::ClothMesh<double> single = drape::disk_mesh(0.15, 0.01);
    const int n = single.vertex_count();
    drape::Matrix3X<double> x(3, 2 * n);
    x.leftCols(n) = single.positions;
    x.rightCols(n) = single.positions;
    x.rightCols(n).row(1).array() += 0.01;
    std::vector<std::array<int, 3>> triangles = single.triangles;
    for (const auto& t : single.triangles) triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
    const double once = drape::measure_drape(single.positions, single.triangles, centre, 0.09, 0.15).shadow_area;
    const double twice = drape::measure_drape(x, triangles, centre, 0.09, 0.15).shadow_area;
    REQUIRE(twice == Approx(once).epsilon(1e-12));
  }
  SECTION("two squares that overlap, one of them turned over") {
    // [-0.5, 0.5]^2 counter-clockwise and [-0.2, 0.8] x [-0.3, 0.7] clockwise: the union is 2 - 0.7 * 0.8.
    drape::Matrix3X<double> x(3, 8);
    x << -0.5, 0.5, 0.5, -0.5, -0.2, 0.8, 0.8, -0.2,  //
        0, 0, 0, 0, 0.1, 0.1, 0.1, 0.1,               //
        -0.5, -0.5, 0.5, 0.5, -0.3, -0.3, 0.7, 0.7;
    const std::vector<std::array<int, 3>> triangles = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}};
    const drape::DrapeMeasures<double> m = drape::measure_drape(x, triangles, centre, 0.1, 0.9);
    REQUIRE(m.shadow_area == Approx(2 - 0.7 * 0.8).epsilon(1e-5));
  }
  SECTION("an annulus: the hole is no shadow") {
    const int segments = 64;
    const double inner = 0.05, outer = 0.1;
    drape::Matrix3X<double> x(3, 2 * segments);
    std::vector<std::array<int, 3>> triangles;
    for (int j = 0; j < segments; ++j) {
      const double angle = 2 * pi * j / segments;
      x.col(j) << inner * std::cos(angle), 0, inner * std::sin(angle);
      x.col(segments + j) << outer * std::cos(angle), 0, outer * std::sin(angle);
      const int k = (j + 1) % segments;
      triangles.push_back({j, segments + j, segments + k});
      triangles.push_back({j, segments + k, k});
    }
    const drape::DrapeMeasures<double> m = drape::measure_drape(x, triangles, centre, 0.04, 0.12);
    const double area = inscribed_polygon_area(segments, outer) - inscribed_polygon_area(segments, inner);
    REQUIRE(m.shadow_area == Approx(area).epsilon(1e-6));
    REQUIRE(m.outline_radius.minCoeff() >= outer * std::cos(pi / segments) - 1e-12);
  }
}

TEST_CASE("a shadow with outline r0 + a cos(n phi) has n folds and area pi r0^2 + pi a^2 / 2", "[drape]") {
  const double r0 = 0.12, a = 0.025, disk_radius = 0.09, specimen_radius = 0.15;
  const drape::Vec3<double> centre = drape::Vec3<double>::Zero();
  const double analytic = pi * r0 * r0 + pi * a * a / 2;
  const drape::ClothMesh<double> coarse = drape::disk_mesh(1.0, 0.02), fine = drape::disk_mesh(1.0, 0.01);
  for (int n : {3, 5, 6, 9, 12}) {
    const drape::ClothMesh<double> mesh = sinusoidal_shadow(fine, r0, a, n);
    const drape::DrapeMeasures<double> m =
        drape::measure_drape(mesh.positions, mesh.triangles, centre, disk_radius, specimen_radius);
    INFO(n << " folds: area " << m.shadow_area << ", " << m.fold_count << " folds counted");
    REQUIRE(m.fold_count == n);
    // The measure: the mesh's own polygon to 1e-6. The mesh: the analytic area to its polygonal
    // error, about (2 pi / M)^2 / 6 (1 + O(n^2 a^2 / r0^2)) for M = 672 boundary vertices: at most
    // 1.5e-4 (n = 12), falling by 4 when the mesh's edges halve.
    const double polygon = loop_area(mesh.positions, mesh.groups.at("boundary"));
    REQUIRE(std::abs(m.shadow_area - polygon) <= 1e-6 * polygon);
    REQUIRE(std::abs(m.shadow_area - analytic) <= 2e-4 * analytic);
    const drape::ClothMesh<double> coarser = sinusoidal_shadow(coarse, r0, a, n);
    const double coarse_error =
        drape::measure_drape(coarser.positions, coarser.triangles, centre, disk_radius, specimen_radius).shadow_area -
        analytic;
    REQUIRE(coarse_error / (m.shadow_area - analytic) > 3.8);
    REQUIRE(coarse_error / (m.shadow_area - analytic) < 4.2);
    // The outline follows r(phi) at the rays' angles, to the chords' sag.
    for (int k = 0; k < m.outline_radius.size(); k += 37) {
      const double phi = m.outline_angle(k);
      REQUIRE(std::abs(m.outline_radius[k] - (r0 + a * std::cos(n * phi))) < 5e-4 * r0);
    }
  }
}

TEMPLATE_TEST_CASE("the fold rule: maxima of the smoothed outline that rise and fall by the prominence", "[drape]",
                   float, double) {
  using S = TestType;
  const int samples = 3600;
  const double r0 = 0.13, prominence = 0.0012;
  const auto outline = [&](auto&& radius) {
    drape::VectorX<S> r(samples);
    for (int k = 0; k < samples; ++k) r[k] = S(radius((k + 0.5) * 2 * pi / samples));
    return r;
  };
  REQUIRE(drape::count_outline_folds(outline([&](double) { return r0; }), S(prominence), 5.0) == 0);
  for (int n = 1; n <= 24; ++n)
    REQUIRE(drape::count_outline_folds(outline([&](double phi) { return r0 + 0.01 * std::cos(n * phi + 0.3); }),
                                       S(prominence), 5.0) == n);
  // A ripple every 4 degrees swinging four times the prominence: the 5 degree average removes it.
  const auto rippled =
      outline([&](double phi) { return r0 + 0.01 * std::cos(5 * phi) + 2 * prominence * std::cos(90 * phi); });
  REQUIRE(drape::count_outline_folds(rippled, S(prominence), 5.0) == 5);
  REQUIRE(drape::count_outline_folds(rippled, S(prominence), 0.0) == 90);
  // Unsmoothed, bumps that swing less than the prominence do not count; bumps that swing more do.
  const auto bumps = [&](double swing) {
    return outline([&](double phi) { return r0 + 0.01 * std::cos(4 * phi) + 0.5 * swing * std::cos(40 * phi); });
  };
  REQUIRE(drape::count_outline_folds(bumps(0.8 * prominence), S(prominence), 0.0) == 4);
  REQUIRE(drape::count_outline_folds(bumps(1.5 * prominence), S(prominence), 0.0) > 4);
}

TEST_CASE("drape measures reject bad input by name", "[drape][validation]") {
  using Catch::Matchers::Contains;
  const drape::ClothMesh<double> mesh = drape::disk_mesh(0.15, 0.03);
  const drape::Vec3<double> centre = drape::Vec3<double>::Zero();
  const auto measure = [&](const drape::Matrix3X<double>& x, const std::vector<std::array<int, 3>>& triangles,
                           const drape::Vec3<double>& c, double disk, double specimen,
                           const drape::DrapeMeasureOptions& options = {}) {
    return drape::measure_drape(x, triangles, c, disk, specimen, options);
  };
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0, 0.15), Contains("'disk_radius'"));
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0.09, std::nan("")),
                      Contains("'specimen_radius'"));
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0.15, 0.15),
                      Contains("'specimen_radius'") && Contains("> disk_radius"));
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, drape::Vec3<double>(0, std::nan(""), 0), 0.09, 0.15),
                      Contains("'disk_centre'"));
  drape::Matrix3X<double> bad = mesh.positions;
  bad(1, 3) = std::numeric_limits<double>::infinity();
  REQUIRE_THROWS_WITH(measure(bad, mesh.triangles, centre, 0.09, 0.15), Contains("'positions[3]'"));
  std::vector<std::array<int, 3>> triangles = mesh.triangles;
  triangles[1][2] = mesh.vertex_count();
  REQUIRE_THROWS_WITH(measure(mesh.positions, triangles, centre, 0.09, 0.15), Contains("'triangles[1]'"));
  drape::DrapeMeasureOptions options;
  options.ray_count = 4;
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0.09, 0.15, options), Contains("'ray_count'"));
  options = {};
  options.smoothing_degrees = 100;
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0.09, 0.15, options),
                      Contains("'smoothing_degrees'"));
  options = {};
  options.fold_prominence = -0.1;
  REQUIRE_THROWS_WITH(measure(mesh.positions, mesh.triangles, centre, 0.09, 0.15, options),
                      Contains("'fold_prominence'"));
  REQUIRE_THROWS_WITH(
      drape::count_outline_folds(drape::VectorX<double>(drape::VectorX<double>::Constant(2, 0.1)), 0.001, 5.0),
      Contains("'outline_radius'"));
  REQUIRE_THROWS_WITH(
      drape::count_outline_folds(drape::VectorX<double>(drape::VectorX<double>::Constant(90, 0.1)), -0.001, 5.0),
      Contains("'prominence'"));
}
