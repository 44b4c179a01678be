// The float V-cycle's AVX2 loops give the float baseline's bits (instruction_set.hpp): the smoother, the
// block-row residual, the transfers and the Galerkin sums one by one, then whole multigrid updates and
// V-cycles, with and without constraints, on one and two threads.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "drape/core/instruction_set_choice.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/platform/team.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/multigrid.hpp"
#include "test_common.hpp"

using namespace drape;

namespace {

/// Restores the process's instruction set when a test ends.
struct InstructionSetScope {
  InstructionSet saved = instruction_set();
  ~InstructionSetScope() { use_instruction_set(saved); }
};

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(float) * a.size()) == 0;
}

/// False, with a warning, where there is no AVX2 version to compare with the baseline.
bool has_avx2() {
  if (detected_instruction_set() == InstructionSet::Avx2) return true;
  WARN("this CPU or build has no AVX2 version: nothing to compare");
  return false;
}

/// `run()` with the baseline, then with AVX2: both results.
template <class Run>
auto baseline_and_avx2(Run&& run) {
  InstructionSetScope scope;
  use_instruction_set(InstructionSet::Baseline);
  auto baseline = run();
  use_instruction_set(InstructionSet::Avx2);
  auto avx2 = run();
  return std::pair{std::move(baseline), std::move(avx2)};
}

/// `n` values in [-1, 1].
std::vector<float> random_values(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

/// The implicit system (Spd, dt = 1/60), assembled in float, of a deformed, moving n x n default
/// cloth with both top corners pinned (eliminated, or kept in the system under the filter).
struct Problem {
  Cloth<float> cloth;
  JacobianAssembler<float> assembler;
  LinearSystem<float> system;

  Problem(int n, PinTreatment pins)
      : cloth([n] {
          ClothSpec<float> spec;
          spec.nx = spec.ny = n;
          return spec;
        }()),
        assembler(cloth, pins, 1) {
    const Matrix3X<float> x = test::jiggled_positions(cloth, 0.05f, 7u);
    Matrix3X<float> v = test::random_velocities<float>(cloth.node_count(), 1.0f, 8u);
    for (int p : cloth.pins().nodes()) v.col(p).setZero();
    system = assembler.make_system();
    assembler.assemble_system(x, v, 0, 1.0f / 60, JacobianVariant::Spd, system);
  }
  int rows() const { return system.block_rows(); }
  std::size_t size() const { return std::size_t(system.size()); }
};

/// Row ranges: all, one not starting or ending on a multiple of anything, a single row, the last row.
std::vector<std::pair<int, int>> row_ranges(int rows) { return {{0, rows}, {3, rows - 2}, {5, 6}, {rows - 1, rows}}; }

const char* pins_name(PinTreatment pins) { return pins == PinTreatment::Filter ? "filtered pins" : "eliminated pins"; }

}  // namespace

TEST_CASE("float block-Jacobi smoothing gives the same bits with AVX2 and without", "[simd][multigrid][float]") {
  if (!has_avx2()) return;
  const Problem p(33, PinTreatment::Filter);  // fixed rows: zero inverse blocks among the others
  BlockJacobi<float> jacobi;
  jacobi.resize(p.rows());
  REQUIRE(jacobi.invert_rows(p.system.matrix, &p.system.constraints, false));
  const std::vector<float> t = random_values(p.size(), 1u), x0 = random_values(p.size(), 2u);
  for (bool first : {true, false})
    for (const auto& [begin, end] : row_ranges(p.rows())) {
      INFO("first " << first << ", rows [" << begin << ", " << end << ")");
      const auto [baseline, avx2] = baseline_and_avx2([&, begin = begin, end = end] {
        std::vector<float> x = x0;
        jacobi.smooth_rows(t.data(), 0.8f, first, x.data(), begin, end);
        return x;
      });
      CHECK(same_bits(baseline, avx2));
      CHECK_FALSE(same_bits(baseline, x0));  // the step did something
    }
}

TEST_CASE("the float block-row residual gives the same bits with AVX2 and without", "[simd][multigrid][float]") {
  if (!has_avx2()) return;
  const Problem p(33, PinTreatment::Eliminate);
  const BlockSparseMatrix<float>& a = p.system.matrix;
  const std::vector<float> b = random_values(p.size(), 3u), x = random_values(p.size(), 4u);
  const std::vector<float> r0 = random_values(p.size(), 5u);  // rows outside the range keep these
  for (const auto& [begin, end] : row_ranges(p.rows())) {
    INFO("rows [" << begin << ", " << end << ")");
    const auto [baseline, avx2] = baseline_and_avx2([&, begin = begin, end = end] {
      std::vector<float> r = r0;
      a.residual_rows(b.data(), x.data(), r.data(), begin, end);
      return r;
    });
    CHECK(same_bits(baseline, avx2));
    CHECK_FALSE(same_bits(baseline, r0));
  }
}

TEST_CASE("float multigrid restriction and prolongation give the same bits with AVX2 and without",
          "[simd][multigrid][float]") {
  if (!has_avx2()) return;
  for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    const Problem p(33, pins);
    MultigridHierarchy<float> hierarchy;
    hierarchy.analyze(p.system.layout, p.system.matrix, 16, true);
    REQUIRE(hierarchy.level_count() >= 4);
    for (int l = 1; l < hierarchy.level_count(); ++l)
      for (int threads : {1, 2}) {
        INFO(pins_name(pins) << ", level " << l << ", " << threads << " thread(s)");
        const std::size_t fine_size = 3 * std::size_t(hierarchy.rows(l - 1));
        const std::size_t coarse_size = 3 * std::size_t(hierarchy.rows(l));
        const std::vector<float> fine = random_values(fine_size, 10u + unsigned(l));
        const std::vector<float> coarse = random_values(coarse_size, 20u + unsigned(l));
        // Restricted into a vector of other values (overwritten), prolonged onto `fine` (added to).
        const auto [baseline, avx2] = baseline_and_avx2([&] {
          std::pair<std::vector<float>, std::vector<float>> out{random_values(coarse_size, 30u), fine};
          run_in_team(threads, [&] {
            hierarchy.restrict_to(l, fine.data(), out.first.data(), threads > 1);
            hierarchy.prolong_add(l, coarse.data(), out.second.data(), threads > 1);
          });
          return out;
        });
        CHECK(same_bits(baseline.first, avx2.first));
        CHECK(same_bits(baseline.second, avx2.second));
        CHECK_FALSE(same_bits(baseline.second, fine));
      }
  }
}

namespace {

/// The values of every coarse operator and the V-cycle of `r` (the system's rhs, then random values)
/// of a float multigrid preconditioner updated for `p` on `threads` threads.
struct Cycle {
  std::vector<std::vector<float>> levels;
  std::vector<float> z, z_random;
};

Cycle update_and_apply(const Problem& p, const MultigridSettings& settings, int threads) {
  MultigridPreconditioner<float> mg(settings);
  mg.analyze(p.system);
  Cycle out;
  out.z.assign(p.size(), 0.0f);
  out.z_random.assign(p.size(), 0.0f);
  const std::vector<float> r = random_values(p.size(), 40u);
  std::atomic<bool> ok{true};
  run_in_team(threads, [&] {
    if (!mg.update_in_team(p.system)) ok = false;
    mg.apply_in_team(p.system.rhs.data(), out.z.data());
    mg.apply_in_team(r.data(), out.z_random.data());
  });
  REQUIRE(ok);
  REQUIRE(mg.level_count() >= 4);
  for (int l = 1; l < mg.level_count(); ++l) {
    const BlockSparseMatrix<float>& a = mg.level_matrix(l);
    out.levels.emplace_back(a.values(), a.values() + 9 * std::size_t(a.block_count()));
  }
  return out;
}

}  // namespace

TEST_CASE("float multigrid: Galerkin operators and V-cycles give the same bits with AVX2 and without",
          "[simd][multigrid][float]") {
  if (!has_avx2()) return;
  for (PinTreatment pins : {PinTreatment::Eliminate, PinTreatment::Filter}) {
    const Problem p(33, pins);
    REQUIRE(p.system.constraints.empty() == (pins == PinTreatment::Eliminate));
    // Routed (level 1 through the routing, or the routed operator filtered, then summed), and not.
    for (bool route : {true, false})
      // Two threads with the default settings run every level on one thread (33 x 33 is below
      // min_team_rows); with a low threshold the finest levels are shared by the team.
      for (const auto& [team, min_team_rows] : {std::pair{1, 2048}, std::pair{2, 2048}, std::pair{2, 64}}) {
        const int threads = team;  // a lambda captures a variable, not a structured binding (C++17)
        INFO(pins_name(pins) << (route ? ", routed" : ", not routed") << ", " << threads << " thread(s), min_team_rows "
                             << min_team_rows);
        MultigridSettings settings;
        settings.route_through_midpoints = route;
        settings.min_team_rows = min_team_rows;
        const auto [baseline, avx2] = baseline_and_avx2([&] { return update_and_apply(p, settings, threads); });
        REQUIRE(baseline.levels.size() == avx2.levels.size());
        for (std::size_t l = 0; l < baseline.levels.size(); ++l) {
          INFO("level " << l + 1);
          CHECK(same_bits(baseline.levels[l], avx2.levels[l]));
        }
        CHECK(same_bits(baseline.z, avx2.z));
        CHECK(same_bits(baseline.z_random, avx2.z_random));
        CHECK(baseline.z != std::vector<float>(p.size(), 0.0f));
      }
  }
}
