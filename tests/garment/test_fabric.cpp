// The fabric presets (drape/garment/fabric.hpp): their values and units, the orderings their
// sources support, and the two mappings to drape's parameters measured on meshes: a strip of
// equilateral triangles pulled by a known force stretches by F / (W E t), and a patch bent into a
// cylinder stores the energy of a plate of rigidity D.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drape/garment/fabric.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/model/cloth.hpp"
#include "drape/physics/dihedral_bending.hpp"

using namespace drape;

namespace {

/// A lattice of equilateral triangles of side h in the x-y plane: ny rows of nx vertices, row j at
/// y = j h sqrt(3)/2, odd rows shifted by h/2 in x; vertex (i, j) is j nx + i. Its width, the width
/// of every strip between two rows, is (nx - 1) h.
ClothMesh<double> equilateral_lattice(int nx, int ny, double h) {
  ClothMesh<double> mesh;
  const double dy = h * std::sqrt(3.0) / 2;
  mesh.positions = Matrix3X<double>::Zero(3, nx * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) mesh.positions.col(j * nx + i) = Vec3<double>(i * h + (j % 2) * h / 2, j * dy, 0);
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = (j + 1) * nx + i;  // (i, j) and (i, j + 1)
      if (j % 2 == 0) {
        mesh.triangles.push_back({a, a + 1, b});
        mesh.triangles.push_back({a + 1, b + 1, b});
      } else {
        mesh.triangles.push_back({a, b + 1, b});
        mesh.triangles.push_back({a, a + 1, b + 1});
      }
    }
  return mesh;
}

/// Constant forces on the first and last rows of a lattice: +F along y on the last, -F on the
/// first, each row's share by the trapezoid rule (a uniform traction F / W along the row).
class EndLoads final : public ForceTerm<double> {
 public:
  EndLoads(int nx, int ny, double total) : m_forces(Matrix3X<double>::Zero(3, nx * ny)) {
    for (int i = 0; i < nx; ++i) {
      const double share = total * ((i == 0 || i == nx - 1) ? 0.5 : 1.0) / (nx - 1);
      m_forces(1, i) = -share;
      m_forces(1, (ny - 1) * nx + i) = share;
    }
  }
  std::string name() const override { return "end loads"; }
  void add_force(const ConstRef3X<double>& /*x*/, const ConstRef3X<double>& /*v*/, double /*t*/,
                 Ref3X<double> f) const override {
    f += m_forces;
  }

 private:
  Matrix3X<double> m_forces;
};

/// Mean y of row j of an nx-wide lattice.
double row_y(const Matrix3X<double>& x, int nx, int j) { return x.row(1).segment(j * nx, nx).mean(); }

/// The rest area of triangle (a, b, c) of `x`.
double triangle_area(const Matrix3X<double>& x, int a, int b, int c) {
  return (x.col(b) - x.col(a)).cross(x.col(c) - x.col(a)).norm() / 2;
}

}  // namespace

TEST_CASE("fabric presets: cotton, denim, silk, jersey with positive finite values", "[garment][fabric]") {
  const std::vector<Fabric>& presets = fabric_presets();
  REQUIRE(presets.size() == 4);
  const std::array<std::string, 4> names = {"cotton", "denim", "silk", "jersey"};
  for (std::size_t p = 0; p < presets.size(); ++p) {
    const Fabric& f = presets[p];
    INFO(f.name);
    CHECK(f.name == names[p]);
    for (const double value : {f.areal_density, f.stretch_stiffness, f.bending_rigidity, f.stretch_damping,
                               f.bending_damping, f.friction, f.kinetic_friction, edge_spring_stiffness(f),
                               hinge_stiffness(f)}) {
      CHECK(std::isfinite(value));
      CHECK(value > 0);
    }
    CHECK_FALSE(f.source.empty());
    CHECK(f.kinetic_friction <= f.friction);
    // The same preset by name, and the same object each call.
    CHECK(fabric_preset(f.name).bending_rigidity == f.bending_rigidity);
    CHECK(&fabric_presets()[p] == &f);
  }
}

TEST_CASE("fabric presets: an unknown name names `fabric` and the allowed names", "[garment][fabric]") {
  try {
    fabric_preset("wool");
    FAIL("no exception");
  } catch (const InvalidParameter& e) {
    CHECK(e.parameter() == "fabric");
    CHECK(e.value() == "wool");
    CHECK(e.allowed() == "cotton | denim | silk | jersey");
    const std::string what = e.what();
    CHECK(what.find("'fabric'") != std::string::npos);
    CHECK(what.find("cotton | denim | silk | jersey") != std::string::npos);
  }
  CHECK_THROWS_AS(fabric_preset("Denim"), InvalidParameter);  // names are lower case
  CHECK_THROWS_AS(fabric_preset(""), InvalidParameter);
}

TEST_CASE("fabric presets: areal densities in kg/m^2", "[garment][fabric]") {
  // Garment fabrics weigh 30-500 g/m^2; a value in g/m^2 would be a thousand times too large.
  for (const Fabric& f : fabric_presets()) {
    INFO(f.name);
    CHECK(f.areal_density > 0.03);
    CHECK(f.areal_density < 0.5);
  }
  // The denim is sold as 11 oz/yd^2 (372.96 g/m^2); Wang et al. weighed it at 324 g/m^2.
  const double ounce_per_square_yard = 0.028349523125 / (0.9144 * 0.9144);  // kg/m^2
  CHECK(fabric_preset("denim").areal_density == Approx(11 * ounce_per_square_yard).epsilon(0.15));
  // The silk is 14 momme: 14 lb per 100 yd of 45 in cloth.
  const double momme = 0.45359237 / (100 * 0.9144 * 45 * 0.0254);  // kg/m^2
  CHECK(fabric_preset("silk").areal_density == Approx(14 * momme).epsilon(1e-3));
}

TEST_CASE("fabric presets: the orderings of the measurements", "[garment][fabric]") {
  const Fabric cotton = fabric_preset("cotton"), denim = fabric_preset("denim"), silk = fabric_preset("silk"),
               jersey = fabric_preset("jersey");
  // Silk the lightest, denim the heaviest.
  for (const Fabric& f : {cotton, denim, jersey}) {
    CHECK(silk.areal_density < f.areal_density);
    if (f.name != "denim") CHECK(f.areal_density < denim.areal_density);
  }
  // Denim bends less easily than the silk and the knit.
  CHECK(denim.bending_rigidity > silk.bending_rigidity);
  CHECK(denim.bending_rigidity > jersey.bending_rigidity);
  // The knit stretches far more easily than the two wovens (by more than 10 times at small strain).
  CHECK(10 * jersey.stretch_stiffness < cotton.stretch_stiffness);
  CHECK(10 * jersey.stretch_stiffness < denim.stretch_stiffness);
  // Damping proportional to stiffness.
  for (const Fabric& f : {cotton, denim, silk, jersey}) {
    CHECK(f.stretch_damping == Approx(fabric_stretch_damping_time * edge_spring_stiffness(f)));
    CHECK(f.bending_damping == Approx(fabric_bending_damping_time * hinge_stiffness(f)));
  }
}

TEST_CASE("fabric presets: a strip of edge springs stretches by F / (W E t)", "[garment][fabric]") {
  // A free strip of equilateral triangles, 61 vertices wide (W = 1.2 m) and 13 rows long (0.21 m),
  // structural springs only, pulled at both ends by +-F along its length (a uniform traction F / W)
  // and settled by 20 implicit steps of 0.05 s (it is at rest after 15). Uniaxial stress F / W: the
  // strain between rows 3 and 9 is F / (W E t), F chosen for a strain of 1e-3. A free edge of the
  // lattice is a little stiffer than its share of the area (its springs have one triangle, not
  // two), and the loaded rows are near: measured, the strain is 1.5% below F / (W E t), the same for
  // every preset (2.3% on a strip 13 vertices wide and 61 rows long). Within 3%; with k = E t instead
  // of sqrt(3)/2 E t it is 13% smaller.
  const int nx = 61, ny = 13;
  const double h = 0.02, width = (nx - 1) * h, target_strain = 1e-3;
  const ClothMesh<double> mesh = equilateral_lattice(nx, ny, h);
  for (const Fabric& f : fabric_presets()) {
    INFO(f.name);
    const double force = target_strain * f.stretch_stiffness * width;
    ClothSpecd spec;
    spec.mesh = mesh;
    spec.areal_density = f.areal_density;
    spec.gravity = 0;
    spec.springs = {{edge_spring_stiffness(f), f.stretch_damping}, {0.0, 0.0}, {0.0, 0.0}};
    spec.pinned_nodes = std::vector<int>{};
    spec.force_terms = {std::make_shared<EndLoads>(nx, ny, force)};
    const Clothd cloth(spec);
    ImplicitOptions options;
    options.dt = 0.05;
    options.threads = 1;
    options.preconditioner = PreconditionerKind::AlgebraicMultigrid;
    ImplicitEuler<double> implicit(cloth, options);
    State<double> s = cloth.initial_state();
    for (int step = 0; step < 20; ++step) REQUIRE(implicit.step(s).ok());
    REQUIRE(s.positions.allFinite());
    const int j1 = 3, j2 = 9;
    const double rest = row_y(cloth.start_positions(), nx, j2) - row_y(cloth.start_positions(), nx, j1);
    const double strain = (row_y(s.positions, nx, j2) - row_y(s.positions, nx, j1)) / rest - 1;
    const double expected = force / (width * f.stretch_stiffness);
    INFO("strain " << strain << ", F / (W E t) = " << expected);
    CHECK(strain == Approx(expected).epsilon(0.03));
    CHECK(s.velocities.cwiseAbs().maxCoeff() < 1e-3 * expected);  // at rest
  }
}

TEST_CASE("fabric presets: a patch bent into a cylinder stores the energy of a plate of rigidity D",
          "[garment][fabric]") {
  // A 1 m x 1 m patch of equilateral triangles (h = 0.05 m) wrapped onto a cylinder of radius 2 m,
  // its axis along either side: drape's dihedral term with k = hinge_stiffness() stores
  // E = 1/2 D kappa^2 A over the area A of the hinges' regions (docs/bending.md measures D/k at
  // 2.96-3.02 on such meshes). Within 3%; with k = D instead of D/3 the energy is 3 times too large.
  const double h = 0.05, radius = 2.0, kappa = 1 / radius;
  const int nx = 21, ny = 24;
  const ClothMesh<double> mesh = equilateral_lattice(nx, ny, h);
  const Matrix3X<double>& rest = mesh.positions;
  double hinge_area = 0;
  for (const Hinge& e : mesh.hinges())
    hinge_area += (triangle_area(rest, e.a, e.b, e.c) + triangle_area(rest, e.b, e.a, e.d)) / 3;
  for (const int axis : {0, 1}) {  // bent across x (cylinder axis along y), then across y
    Matrix3X<double> bent = rest;
    for (int v = 0; v < rest.cols(); ++v) {
      const double s = rest(axis, v);
      bent(axis, v) = radius * std::sin(s / radius);
      bent(2, v) = radius * (1 - std::cos(s / radius));
    }
    for (const Fabric& f : fabric_presets()) {
      INFO(f.name << ", bent across " << (axis == 0 ? "x" : "y"));
      const DihedralBending<double> bending(mesh, hinge_stiffness(f), f.bending_damping);
      const double energy = bending.energy(bent);
      const double rigidity = 2 * energy / (kappa * kappa * hinge_area);
      INFO("D measured " << rigidity << " N m, preset " << f.bending_rigidity);
      CHECK(rigidity == Approx(f.bending_rigidity).epsilon(0.03));
    }
  }
}
