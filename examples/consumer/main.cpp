#include <cstdio>

#include <drape/drape.hpp>

int main() {
  const drape::Clothd cloth{drape::ClothSpecd{}};
  drape::Rk2d rk2(cloth);
  drape::Stated state = cloth.initial_state();
  for (int k = 0; k < 200; ++k)
    if (!rk2.step(state)) return 1;
  std::printf("consumer: %d nodes, %d springs, t = %.3f s, lowest y = %.4f m\n", cloth.node_count(),
              cloth.springs().size(), state.time, state.positions.row(1).minCoeff());
  return 0;
}
