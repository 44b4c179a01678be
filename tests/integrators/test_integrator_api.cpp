// The integrators' shared interface: the time step's one owner, run-time choice by kind, solver
// objects supplied by the caller and validated by their own capabilities, node data passed as
// Eigen::Ref (a Map of the caller's memory works without a copy), and no integrator or assembler
// built on a temporary cloth.
#include <catch2/catch.hpp>

#include <memory>
#include <type_traits>
#include <vector>

#include "drape/fwd.hpp"
#include "drape/integrators/make_integrator.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/realtime/realtime_driver.hpp"
#include "drape/solvers/enable_ldlt.hpp"
#include "test_common.hpp"

using namespace drape;

TEST_CASE("no integrator or assembler can be built on a temporary cloth", "[integrator][lifetime]") {
  // They keep a reference to their cloth: built on a temporary it would dangle, so the rvalue
  // constructors are deleted (checked at run time so that a mutation shows up as a failed test).
  CHECK_FALSE(std::is_constructible_v<Rk2d, Clothd&&>);
  CHECK_FALSE(std::is_constructible_v<Rk2d, Clothd&&, IntegratorOptions>);
  CHECK_FALSE(std::is_constructible_v<ImplicitEulerd, Clothd&&>);
  CHECK_FALSE(std::is_constructible_v<ImplicitEulerd, Clothd&&, ImplicitOptions>);
  CHECK_FALSE(std::is_constructible_v<ForceAssembler<double>, Clothd&&>);
  CHECK_FALSE(std::is_constructible_v<JacobianAssemblerd, Clothd&&>);
  CHECK(std::is_constructible_v<Rk2d, const Clothd&>);
  CHECK(std::is_constructible_v<ImplicitEulerd, Clothd&, ImplicitOptions>);
  CHECK_FALSE(std::is_copy_constructible_v<Rk2d>);
}

namespace {

/// A caller's solver: cg underneath, counting its solves, with capabilities of the caller's choice.
class CountingSolver final : public LinearSolver<double> {
 public:
  explicit CountingSolver(SolverCapabilities capabilities, IterativeSettings settings = ImplicitOptions{}.iterative_settings())
      : m_inner(make_linear_solver<double>(LinearSolverKind::Cg, settings)), m_capabilities(capabilities) {}
  std::string name() const override { return "counting cg"; }
  SolverCapabilities capabilities() const override { return m_capabilities; }
  void analyze(const LinearSystem<double>& system) override { m_inner->analyze(system); }
  SolveStatus solve(const LinearSystem<double>& system, VectorX<double>& x) override {
    ++solves;
    return m_inner->solve(system, x);
  }
  int solves = 0;

 private:
  std::unique_ptr<LinearSolver<double>> m_inner;
  SolverCapabilities m_capabilities;
};

bool same(const Stated& a, const Stated& b) {
  return a.positions == b.positions && a.velocities == b.velocities && a.time == b.time;
}

}  // namespace

TEST_CASE("the integrator owns dt: set once, checked once, used by every step", "[integrator][dt]") {
  const Clothd cloth(test::small_spec<double>(5, 10.0));
  Rk2d rk2(cloth, {1e-3, 1});
  CHECK(rk2.dt() == 1e-3);
  Stated s = cloth.initial_state();
  REQUIRE(rk2.step(s).ok());
  CHECK(s.time == 1e-3);
  rk2.set_dt(2e-3);
  REQUIRE(rk2.step(s).ok());
  CHECK(s.time == Approx(3e-3));
  CHECK_THROWS_WITH(rk2.set_dt(-1), Catch::Contains("'dt'"));
  CHECK(rk2.dt() == 2e-3);  // a rejected dt changes nothing
  // The real-time driver paces with the integrator's dt.
  RealtimeDriver<> driver(rk2.dt(), {2.0, 10});
  CHECK(driver.dt() == rk2.dt());
  CHECK_THROWS_WITH(RealtimeDriver<>(rk2.dt(), {2.0, 0}), Catch::Contains("'max_steps_per_frame'"));
}

TEST_CASE("make_integrator gives the same steps as the integrators built directly", "[integrator][kind]") {
  const Clothd cloth(test::small_spec<double>(6, 10.0));
  ImplicitOptions o;
  o.dt = 0.01;
  o.threads = 1;
  for (IntegratorKind kind : {IntegratorKind::Rk2, IntegratorKind::Implicit}) {
    std::unique_ptr<Integrator<double>> chosen = make_integrator(cloth, kind, o);
    std::unique_ptr<Integrator<double>> direct;
    if (kind == IntegratorKind::Rk2)
      direct = std::make_unique<Rk2d>(cloth, IntegratorOptions{0.01, 1});
    else
      direct = std::make_unique<ImplicitEulerd>(cloth, o);
    CHECK(chosen->dt() == 0.01);
    Stated a = cloth.initial_state(), b = cloth.initial_state();
    for (int k = 0; k < 10; ++k) {
      chosen->step(a);
      direct->step(b);
    }
    INFO(to_string(kind));
    CHECK(same(a, b));
    CHECK(a.time > 0.09);
  }
}

TEST_CASE("a solver object from the caller: used as given, validated by its own capabilities", "[integrator][solver]") {
  const Clothd cloth(test::small_spec<double>(6, 10.0));
  ImplicitOptions o;
  o.dt = 1.0 / 60;
  o.threads = 1;
  const SolverCapabilities like_cg{true, true, true};
  auto counting = std::make_unique<CountingSolver>(like_cg);
  CountingSolver* handle = counting.get();
  ImplicitEulerd supplied(cloth, o, std::move(counting));
  ImplicitEulerd by_options(cloth, o);  // cg with the same settings
  Stated a = cloth.initial_state(), b = cloth.initial_state();
  for (int k = 0; k < 5; ++k) {
    REQUIRE(supplied.step(a).ok());
    REQUIRE(by_options.step(b).ok());
  }
  CHECK(handle->solves == 5);
  CHECK(same(a, b));
  CHECK(supplied.solver().name() == "counting cg");
  // Its capabilities decide what it may be used for.
  o.jacobian = JacobianVariant::Exact;
  CHECK_THROWS_WITH(ImplicitEulerd(cloth, o, std::make_unique<CountingSolver>(like_cg)),
                    Catch::Contains("'solver'") && Catch::Contains("counting cg"));
  o.jacobian = JacobianVariant::Spd;
  o.pin_treatment = PinTreatment::Filter;
  CHECK_THROWS_WITH(ImplicitEulerd(cloth, o, std::make_unique<CountingSolver>(SolverCapabilities{true, false, true})),
                    Catch::Contains("'pin_treatment'"));
  CHECK_NOTHROW(ImplicitEulerd(cloth, o, std::make_unique<CountingSolver>(like_cg)));
  CHECK_THROWS_WITH(ImplicitEulerd(cloth, o, nullptr), Catch::Contains("'solver'"));
  // The options' solver field is not checked for a supplied solver (it is not used).
  o.solver = LinearSolverKind::Lu;
  o.pin_treatment = PinTreatment::Eliminate;
  CHECK_NOTHROW(ImplicitEulerd(cloth, o, std::make_unique<CountingSolver>(like_cg)));
  // Contacts are constraints of the solve: a solver without them cannot take colliders.
  ClothSpecd with_floor = test::small_spec<double>(6, 10.0);
  with_floor.colliders.push_back(Colliderd::plane(Vec3<double>(0, -1, 0), Vec3<double>(0, 1, 0)));
  const Clothd on_floor(with_floor);
  CHECK_THROWS_WITH(ImplicitEulerd(on_floor, o, std::make_unique<CountingSolver>(SolverCapabilities{true, false, true})),
                    Catch::Contains("'solver'") && Catch::Contains("colliders"));
}

TEST_CASE("node data in the caller's memory (Eigen::Map) is used without a copy", "[integrator][ref]") {
  const Clothd cloth(test::small_spec<double>(5, 10.0));
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.2, 1u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 2u);
  std::vector<double> xs(x.data(), x.data() + x.size()), vs(v.data(), v.data() + v.size()), fs(x.size());
  const Eigen::Map<const Matrix3X<double>> xm(xs.data(), 3, x.cols()), vm(vs.data(), 3, v.cols());
  Eigen::Map<Matrix3X<double>> fm(fs.data(), 3, x.cols());
  const ForceAssembler<double> forces(cloth, 1);
  Matrix3X<double> f(3, cloth.node_count());
  forces.force(x, v, 0, f);
  forces.force(xm, vm, 0, fm);  // writes straight into fs
  CHECK(Matrix3X<double>(fm) == f);
  CHECK(spring_potential_energy(cloth, xm) == spring_potential_energy(cloth, x));
  CHECK(max_strain(cloth, xm) == max_strain(cloth, x));
  JacobianAssemblerd assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystemd from_map = assembler.make_system(), from_matrix = assembler.make_system();
  assembler.assemble_system(xm, vm, 0, 0.01, JacobianVariant::Spd, from_map);
  assembler.assemble_system(x, v, 0, 0.01, JacobianVariant::Spd, from_matrix);
  CHECK(from_map.matrix.to_dense() == from_matrix.matrix.to_dense());
  CHECK(from_map.rhs == from_matrix.rhs);
}
