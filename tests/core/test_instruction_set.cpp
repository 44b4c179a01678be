// The AVX2 versions of the hot loops give the baseline's bits (instruction_set.hpp): the exact
// square roots, the spring pass (a grid's and a mesh's), the edge product, and whole RK2,
// symplectic Euler and implicit Euler runs.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "drape/core/instruction_set_choice.hpp"
#include "drape/core/mesh_generators.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/platform/vector_sqrt.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// Restores the process's instruction set when a test ends.
struct InstructionSetScope {
  InstructionSet saved = instruction_set();
  ~InstructionSetScope() { use_instruction_set(saved); }
};

template <class S>
bool same_bits(const Matrix3X<S>& a, const Matrix3X<S>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(S) * std::size_t(a.size())) == 0;
}

/// The default cloth (two corners pinned, gravity), 21 x 21 nodes.
template <class S>
Cloth<S> falling_cloth() {
  ClothSpec<S> spec;
  spec.nx = 21;
  spec.ny = 21;
  return Cloth<S>(spec);
}

/// A disk of 0.5 m radius meshed at 3 cm (an irregular mesh: the general spring pass, about
/// 1,000 nodes and 6,000 springs, enough for two threads), hanging from two nodes at its rim.
template <class S>
Cloth<S> falling_disk() {
  ClothSpec<S> spec;
  spec.mesh = disk_mesh<S>(S(0.5), S(0.03));
  const Matrix3X<S>& x = spec.mesh->positions;
  Index left = 0, right = 0;
  for (Index i = 1; i < x.cols(); ++i) {
    if (x(0, i) < x(0, left)) left = i;
    if (x(0, i) > x(0, right)) right = i;
  }
  spec.pinned_nodes = std::vector<int>{int(left), int(right)};
  return Cloth<S>(spec);
}

/// 1.5 s of a cloth (falling_cloth()'s unless given) with one explicit integrator.
template <class S, class Integrator>
State<S> run_explicit(InstructionSet set, int threads, bool disk = false) {
  InstructionSetScope scope;
  use_instruction_set(set);
  const Cloth<S> cloth = disk ? falling_disk<S>() : falling_cloth<S>();
  IntegratorOptions options;
  options.dt = 0.0005;
  options.threads = threads;
  Integrator integrator(cloth, options);
  State<S> state = cloth.initial_state();
  for (int i = 0; i < 3000; ++i) REQUIRE(integrator.step(state).ok());
  return state;
}

/// `steps` implicit steps (dt = 1/60, default solver: CG, multigrid, Spd) of an n x n default cloth.
State<double> run_implicit(InstructionSet set, int n, int threads, int steps) {
  InstructionSetScope scope;
  use_instruction_set(set);
  ClothSpec<double> spec;
  spec.nx = spec.ny = n;
  const Cloth<double> cloth(spec);
  ImplicitOptions options;
  options.dt = 1.0 / 60;
  options.threads = threads;
  ImplicitEuler<double> integrator(cloth, options);
  State<double> state = cloth.initial_state();
  for (int i = 0; i < steps; ++i) REQUIRE(integrator.step(state).ok());
  return state;
}

template <class S>
std::vector<S> sqrt_inputs() {
  std::vector<S> a = {S(0),
                      S(-0.0),
                      S(1),
                      S(2),
                      S(3),
                      std::numeric_limits<S>::min(),
                      std::numeric_limits<S>::denorm_min(),
                      std::numeric_limits<S>::max(),
                      std::numeric_limits<S>::infinity()};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-30, 30);
  for (int i = 0; i < 1000; ++i) a.push_back(S(std::pow(10.0, exponent(rng))));
  return a;  // 1009 values: the vector loops and a scalar tail
}

#if DRAPE_AVX2_DISPATCH
/// detail::sqrt_avx2 over `a`, whole registers (the last one padded with ones).
template <class S>
__attribute__((target("avx2"))) void avx2_sqrt_in_place(std::vector<S>& a) {
  using V = typename detail::Avx2Vector<S>::type;
  constexpr std::size_t lanes = sizeof(V) / sizeof(S);
  for (std::size_t j = 0; j < a.size(); j += lanes) {
    S chunk[lanes];
    for (std::size_t i = 0; i < lanes; ++i) chunk[i] = j + i < a.size() ? a[j + i] : S(1);
    V p;
    std::memcpy(&p, chunk, sizeof p);
    p = detail::sqrt_avx2(p);
    std::memcpy(chunk, &p, sizeof p);
    for (std::size_t i = 0; i < lanes && j + i < a.size(); ++i) a[j + i] = chunk[i];
  }
}
#endif

}  // namespace

TEMPLATE_TEST_CASE("vector square roots are exact: the bits of std::sqrt in both versions", "[simd]", float, double) {
  const std::vector<TestType> input = sqrt_inputs<TestType>();
  std::vector<TestType> baseline = input, avx2 = input;
  detail::sqrt_in_place(baseline.data(), Index(baseline.size()));
#if DRAPE_AVX2_DISPATCH
  if (detected_instruction_set() == InstructionSet::Avx2)
    avx2_sqrt_in_place(avx2);
  else
    avx2 = baseline;
#else
  avx2 = baseline;
#endif
  for (std::size_t i = 0; i < input.size(); ++i) {
    INFO("sqrt(" << input[i] << ")");
    const TestType exact = std::sqrt(input[i]);
    REQUIRE(std::memcmp(&baseline[i], &exact, sizeof exact) == 0);
    REQUIRE(std::memcmp(&avx2[i], &exact, sizeof exact) == 0);
  }
  // A negative argument gives NaN (which the integrators report), not a finite value.
  TestType negative[5] = {-1, -2, -3, -4, -5};
  detail::sqrt_in_place(negative, 5);
  for (TestType n : negative) REQUIRE(std::isnan(n));
}

TEMPLATE_TEST_CASE("RK2 and symplectic Euler give the same bits with AVX2 and without", "[simd]", float, double) {
  if (detected_instruction_set() != InstructionSet::Avx2) {
    WARN("this CPU or build has no AVX2 version: nothing to compare");
    return;
  }
  for (int threads : {1, 2}) {
    INFO(threads << " thread(s)");
    const State<TestType> rk2_base = run_explicit<TestType, Rk2<TestType>>(InstructionSet::Baseline, threads);
    const State<TestType> rk2_avx2 = run_explicit<TestType, Rk2<TestType>>(InstructionSet::Avx2, threads);
    CHECK(same_bits(rk2_base.positions, rk2_avx2.positions));
    CHECK(same_bits(rk2_base.velocities, rk2_avx2.velocities));
    const State<TestType> se_base =
        run_explicit<TestType, SymplecticEuler<TestType>>(InstructionSet::Baseline, threads);
    const State<TestType> se_avx2 = run_explicit<TestType, SymplecticEuler<TestType>>(InstructionSet::Avx2, threads);
    CHECK(same_bits(se_base.positions, se_avx2.positions));
    CHECK(same_bits(se_base.velocities, se_avx2.velocities));
    // The cloth fell and swung: a comparison of two resting cloths would prove nothing.
    REQUIRE((rk2_base.positions - falling_cloth<TestType>().grid().rest_positions()).cwiseAbs().maxCoeff() >
            TestType(0.5));
  }
}

TEMPLATE_TEST_CASE("RK2 and symplectic Euler give the same bits with AVX2 and without on an irregular mesh", "[simd]",
                   float, double) {
  if (detected_instruction_set() != InstructionSet::Avx2) {
    WARN("this CPU or build has no AVX2 version: nothing to compare");
    return;
  }
  REQUIRE_FALSE(falling_disk<TestType>().is_grid());
  for (int threads : {1, 2}) {
    INFO(threads << " thread(s)");
    const State<TestType> rk2_base = run_explicit<TestType, Rk2<TestType>>(InstructionSet::Baseline, threads, true);
    const State<TestType> rk2_avx2 = run_explicit<TestType, Rk2<TestType>>(InstructionSet::Avx2, threads, true);
    CHECK(same_bits(rk2_base.positions, rk2_avx2.positions));
    CHECK(same_bits(rk2_base.velocities, rk2_avx2.velocities));
    const State<TestType> se_base =
        run_explicit<TestType, SymplecticEuler<TestType>>(InstructionSet::Baseline, threads, true);
    const State<TestType> se_avx2 =
        run_explicit<TestType, SymplecticEuler<TestType>>(InstructionSet::Avx2, threads, true);
    CHECK(same_bits(se_base.positions, se_avx2.positions));
    CHECK(same_bits(se_base.velocities, se_avx2.velocities));
    // The disk fell and swung.
    REQUIRE((rk2_base.positions - falling_disk<TestType>().mesh().positions).cwiseAbs().maxCoeff() > TestType(0.3));
  }
}

TEST_CASE("the edge product gives the same bits with AVX2 and without, and A x", "[simd][edges]") {
  // 9 x 7 nodes with three pins (rows outside the system: edge ends -1) and colours whose sizes
  // are not multiples of the vector width: whole groups of four edges, heads and tails.
  ClothSpec<double> spec;
  spec.nx = 9;
  spec.ny = 7;
  spec.pinned_nodes = std::vector<int>{0, 8, 31};
  const Cloth<double> cloth(spec);
  JacobianAssembler<double> assembler(cloth, PinTreatment::Eliminate, 1);
  LinearSystem<double> system = assembler.make_system();
  const Matrix3X<double> x = test::jiggled_positions(cloth, 0.3, 61u);
  const Matrix3X<double> v = test::random_velocities<double>(cloth.node_count(), 1.0, 62u);
  assembler.assemble_system(x, v, 0, 0.02, JacobianVariant::Spd, system);
  REQUIRE(system.edges.valid());
  REQUIRE(system.edges.symmetric());
  bool unaligned = false;
  for (int c : system.edges.colour_begin()) unaligned = unaligned || c % EdgeOperator<double>::group != 0;
  REQUIRE(unaligned);
  // Groups of every shape (edge_operator.hpp): consecutive rows (springs along j) and pairs in one
  // window of eight rows (structural and bend springs along i) load whole vectors, the rest gather.
  for (GroupShape shape :
       {GroupShape::Gathered, GroupShape::Consecutive, GroupShape::AdjacentPairs, GroupShape::TwoApartPairs}) {
    INFO("group shape " << int(shape));
    REQUIRE(system.edges.group_count(shape) > 0);
  }
  const VectorX<double> p = VectorX<double>::Random(system.size());
  const VectorX<double> dense = system.matrix.to_dense() * p;
  InstructionSetScope scope;
  for (int threads : {1, 2}) {
    INFO(threads << " thread(s)");
    VectorX<double> baseline(system.size()), avx2(system.size());
    use_instruction_set(InstructionSet::Baseline);
    system.edges.multiply(p.data(), baseline.data(), threads);
    if (detected_instruction_set() == InstructionSet::Avx2) use_instruction_set(InstructionSet::Avx2);
    system.edges.multiply(p.data(), avx2.data(), threads);
    CHECK(std::memcmp(baseline.data(), avx2.data(), sizeof(double) * std::size_t(avx2.size())) == 0);
    CHECK((avx2 - dense).cwiseAbs().maxCoeff() <= 1e-12 * dense.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("the implicit step gives the same bits with AVX2 and without", "[simd][implicit]") {
  if (detected_instruction_set() != InstructionSet::Avx2) {
    WARN("this CPU or build has no AVX2 version: nothing to compare");
    return;
  }
  // 21 x 21 on one thread; 81 x 81 on two, where CG and the finest multigrid level share the
  // edge product with the team.
  for (const auto& [n, threads] : {std::pair{21, 1}, std::pair{81, 2}}) {
    INFO(n << " x " << n << ", " << threads << " thread(s)");
    const State<double> base = run_implicit(InstructionSet::Baseline, n, threads, 12);
    const State<double> avx2 = run_implicit(InstructionSet::Avx2, n, threads, 12);
    CHECK(same_bits(base.positions, avx2.positions));
    CHECK(same_bits(base.velocities, avx2.velocities));
  }
}

TEST_CASE("the implicit system's assembly gives the same bits with AVX2 and without, both symmetric variants",
          "[simd][implicit]") {
  if (detected_instruction_set() != InstructionSet::Avx2) {
    WARN("this CPU or build has no AVX2 version: nothing to compare");
    return;
  }
  // 11 x 10 nodes (springs not a multiple of the group of four: a scalar tail), positions and
  // velocities jittered so that some springs are compressed (the Spd clamp acts) and some stretched.
  ClothSpec<double> spec;
  spec.nx = 11;
  spec.ny = 10;
  const Cloth<double> cloth(spec);
  REQUIRE(cloth.springs().size() % 4 != 0);
  State<double> state = cloth.initial_state();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  for (Index i = 0; i < state.positions.size(); ++i) {
    state.positions.data()[i] += jitter(rng);
    state.velocities.data()[i] = 20 * jitter(rng);
  }
  const JacobianAssembler<double> assembler(cloth);
  const auto assemble = [&](InstructionSet set, JacobianVariant variant) {
    InstructionSetScope scope;
    use_instruction_set(set);
    LinearSystem<double> system = assembler.make_system();
    assembler.assemble_system(state.positions, state.velocities, 0.0, 1.0 / 60, variant, system);
    return system;
  };
  for (JacobianVariant variant : {JacobianVariant::Symmetric, JacobianVariant::Spd}) {
    INFO(to_string(variant));
    const LinearSystem<double> base = assemble(InstructionSet::Baseline, variant);
    const LinearSystem<double> avx2 = assemble(InstructionSet::Avx2, variant);
    REQUIRE(base.edges.value_count() == avx2.edges.value_count());
    CHECK(std::memcmp(base.edges.values(), avx2.edges.values(), sizeof(double) * base.edges.value_count()) == 0);
    CHECK(std::memcmp(base.matrix.values(), avx2.matrix.values(),
                      sizeof(double) * 9 * std::size_t(base.matrix.block_count())) == 0);
    CHECK(std::memcmp(base.rhs.data(), avx2.rhs.data(), sizeof(double) * std::size_t(base.rhs.size())) == 0);
  }
  // The clamp acted: otherwise the Spd comparison would repeat the Symmetric one.
  const LinearSystem<double> symmetric = assemble(InstructionSet::Avx2, JacobianVariant::Symmetric);
  const LinearSystem<double> spd = assemble(InstructionSet::Avx2, JacobianVariant::Spd);
  REQUIRE(std::memcmp(symmetric.edges.values(), spd.edges.values(), sizeof(double) * spd.edges.value_count()) != 0);
}

TEST_CASE("the instruction set can be chosen, and an unsupported one is refused by name", "[simd]") {
  InstructionSetScope scope;
  use_instruction_set(InstructionSet::Baseline);
  REQUIRE(instruction_set() == InstructionSet::Baseline);
  if (detected_instruction_set() == InstructionSet::Avx2) {
    use_instruction_set(InstructionSet::Avx2);
    REQUIRE(instruction_set() == InstructionSet::Avx2);
  } else {
    REQUIRE_THROWS_WITH(use_instruction_set(InstructionSet::Avx2), Catch::Contains("instruction_set"));
  }
}
