// The float edge product with AVX2 (128-bit vectors, edge_operator.hpp) gives the bits of the
// scalar loop, at every group shape, with heads and tails, on one and two threads; and it is A x.
#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include "drape/core/instruction_set_choice.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// Restores the process's instruction set when a test ends.
struct InstructionSetScope {
  InstructionSet saved = instruction_set();
  ~InstructionSetScope() { use_instruction_set(saved); }
};

/// The Spd system of `spec`'s cloth (pins eliminated) at jiggled positions and random velocities.
LinearSystem<float> float_system(const ClothSpec<float>& spec, unsigned seed) {
  const Cloth<float> cloth(spec);
  JacobianAssembler<float> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<float> system = assembler.make_system();
  const Matrix3X<float> x = test::jiggled_positions(cloth, 0.3f, seed);
  const Matrix3X<float> v = test::random_velocities<float>(cloth.node_count(), 1.0f, seed + 1);
  assembler.assemble_system(x, v, 0, 0.02f, JacobianVariant::Spd, system);
  return system;
}

/// Baseline and AVX2 products of `system` bitwise the same (when the CPU has AVX2), and both A p.
void check_float_product(const LinearSystem<float>& system, std::initializer_list<int> thread_counts) {
  const VectorX<float> p = VectorX<float>::Random(system.size());
  const VectorX<float> dense = system.matrix.to_dense() * p;
  const float tolerance = 1e-5f * dense.cwiseAbs().maxCoeff();
  const bool avx2 = detected_instruction_set() == InstructionSet::Avx2;
  if (!avx2) WARN("this CPU or build has no AVX2 version: only the baseline product is checked");
  InstructionSetScope scope;
  for (int threads : thread_counts) {
    INFO(threads << " thread(s)");
    VectorX<float> baseline(system.size());
    use_instruction_set(InstructionSet::Baseline);
    system.edges.multiply(p.data(), baseline.data(), threads);
    CHECK((baseline - dense).cwiseAbs().maxCoeff() <= tolerance);
    if (!avx2) continue;
    VectorX<float> vector(system.size());
    use_instruction_set(InstructionSet::Avx2);
    system.edges.multiply(p.data(), vector.data(), threads);
    CHECK(std::memcmp(baseline.data(), vector.data(), sizeof(float) * std::size_t(vector.size())) == 0);
    CHECK((vector - dense).cwiseAbs().maxCoeff() <= tolerance);
  }
}

}  // namespace

TEST_CASE("the float edge product gives the same bits with AVX2 and without, and A x", "[simd][edges]") {
  // 9 x 7 nodes with three pins (edge ends -1) and colours whose sizes are not multiples of four:
  // whole groups, heads and tails.
  ClothSpec<float> spec;
  spec.nx = 9;
  spec.ny = 7;
  spec.pinned_nodes = std::vector<int>{0, 8, 31};
  const LinearSystem<float> system = float_system(spec, 61u);
  REQUIRE(system.edges.valid());
  REQUIRE(system.edges.symmetric());
  bool unaligned = false;
  for (int c : system.edges.colour_begin()) unaligned = unaligned || c % EdgeOperator<float>::group != 0;
  REQUIRE(unaligned);
  for (GroupShape shape :
       {GroupShape::Gathered, GroupShape::Consecutive, GroupShape::AdjacentPairs, GroupShape::TwoApartPairs}) {
    INFO("group shape " << int(shape));
    REQUIRE(system.edges.group_count(shape) > 0);
  }
  check_float_product(system, {1, 2});
}

TEST_CASE("the float edge product gives the same bits with AVX2 and without on long colours", "[simd][edges]") {
  // 33 x 33 nodes, default pins: most edges in whole groups, each thread's share of a colour with
  // its own head and tail.
  ClothSpec<float> spec;
  spec.nx = spec.ny = 33;
  const LinearSystem<float> system = float_system(spec, 71u);
  REQUIRE(system.edges.valid());
  REQUIRE(system.edges.symmetric());
  for (GroupShape shape : {GroupShape::Consecutive, GroupShape::AdjacentPairs, GroupShape::TwoApartPairs}) {
    INFO("group shape " << int(shape));
    REQUIRE(system.edges.group_count(shape) > 0);
  }
  check_float_product(system, {2});
}
