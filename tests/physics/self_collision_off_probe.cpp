// Prints the exact end states (hex floats) of runs with self-collision off: every integrator, a
// collider with friction, a moving pin, non-default self-collision settings that must not matter.
// Built twice (tests/CMakeLists.txt): as is, and with DRAPE_BUILD_WITHOUT_SELF_COLLISION, which
// leaves the self-collision call out of the integrators; test_self_collision_off compares the two
// outputs byte for byte.
#include <cstdio>

#include "drape/integrators/make_integrator.hpp"

using namespace drape;

namespace {

template <class S>
void print_run(IntegratorKind kind, double dt, int steps) {
  ClothSpec<S> spec;
  spec.nx = 17;
  spec.ny = 17;
  spec.colliders.push_back(Collider<S>::sphere(Vec3<S>(S(0.8), S(-0.6), S(0.8)), S(0.4)).set_friction(S(0.4), S(0.3)));
  spec.self_collision.enabled = false;
  spec.self_collision.friction = S(0.9);
  spec.self_collision.impulse_rounds = 9;
  spec.contact_thickness = S(0.01);
  const Cloth<S> cloth(spec);
  ImplicitOptions options;
  options.dt = dt;
  options.threads = 1;
  auto integrator = make_integrator(cloth, kind, options);
  const Vec3<S> corner = cloth.initial_state().positions.col(cloth.grid().node(16, 16));
  integrator->pins().pin(cloth.grid().node(16, 16),
                         PinPath<S>::keyframes({S(0), S(0.5)}, {corner, corner + Vec3<S>(S(-0.2), S(0.3), S(0))}));
  State<S> state = cloth.initial_state();
  for (int k = 0; k < steps; ++k)
    if (!integrator->step(state).ok()) {
      std::printf("step %d failed\n", k);
      break;
    }
  std::printf("%s %zu-byte scalar t=%a\n", to_string(kind), sizeof(S), double(state.time));
  for (Index i = 0; i < state.positions.cols(); ++i)
    std::printf("%a %a %a %a %a %a\n", double(state.positions(0, i)), double(state.positions(1, i)),
                double(state.positions(2, i)), double(state.velocities(0, i)), double(state.velocities(1, i)),
                double(state.velocities(2, i)));
}

}  // namespace

int main() {
  print_run<double>(IntegratorKind::Implicit, 1.0 / 60, 60);
  print_run<float>(IntegratorKind::Implicit, 1.0 / 60, 60);
  print_run<double>(IntegratorKind::Symplectic, 5e-4, 1200);
  print_run<double>(IntegratorKind::Rk2, 1e-3, 600);
  return 0;
}
