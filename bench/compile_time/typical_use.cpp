// Compile-time probe (scripts/bench.sh, compiled with -c only, never run): the umbrella header
// plus what a typical program instantiates for double: a cloth, an RK2 step, an implicit step
// (default options: the built-in solvers cg and bicgstab are instantiated behind the run-time
// registry; the opt-in Eigen direct solvers are not, solver_registry.hpp), diagnostics and OBJ
// export.
#include <drape/drape.hpp>

int main(int argc, char** argv) {
  const drape::Cloth<double> cloth(drape::ClothSpec<double>{});
  drape::State<double> state = cloth.initial_state();
  drape::Rk2<double> rk2(cloth, {0.0005});
  drape::ImplicitOptions options;
  options.dt = 0.01;
  drape::ImplicitEuler<double> implicit(cloth, options);
  const drape::StepStatus status = rk2.step(state);
  const drape::StepStatus implicit_status = implicit.step(state);
  drape::write_obj(argc > 1 ? argv[1] : "cloth.obj", state.positions, cloth.grid().triangles());
  return status.ok() && implicit_status.ok() && drape::total_energy(cloth, state) < 1e9 ? 0 : 1;
}
