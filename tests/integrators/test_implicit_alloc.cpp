// No heap allocation inside ImplicitEuler::step() once warmed up. This binary replaces the global
// operator new to count allocations (so it is a test executable of its own), and counts Eigen's
// own heap allocations (which use malloc, not operator new) through EIGEN_RUNTIME_NO_MALLOC with an
// eigen_assert that counts instead of aborting.
#include <atomic>

namespace alloc_test {
inline std::atomic<long> eigen_mallocs{0};
}
#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x)                                                          \
  do {                                                                           \
    if (!(x)) alloc_test::eigen_mallocs.fetch_add(1, std::memory_order_relaxed); \
  } while (false)

#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>

#include "drape/fwd.hpp"
#include "drape/integrators/implicit_euler.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

// The replacements pair malloc with free on purpose; GCC cannot see that and warns at inlined sites.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept { return operator new(size, tag); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace drape;

namespace {
long allocations_in_steps(const Clothd& cloth, ImplicitOptions options, int warmup, int steps) {
  options.dt = 1.0 / 60;
  ImplicitEuler<double> ie(cloth, options);
  State<double> s = cloth.initial_state();
  for (int k = 0; k < warmup; ++k) REQUIRE(ie.step(s).ok());
  const long before = g_allocations.load() + alloc_test::eigen_mallocs.load();
  bool ok = true;
  Eigen::internal::set_is_malloc_allowed(false);
  for (int k = 0; k < steps; ++k) ok = ie.step(s).ok() && ok;
  Eigen::internal::set_is_malloc_allowed(true);
  REQUIRE(ok);
  return g_allocations.load() + alloc_test::eigen_mallocs.load() - before;
}
}  // namespace

TEST_CASE("the allocation counters work", "[alloc]") {
  const long before = g_allocations.load();
  std::vector<int> v0(100);
  v0[7] = 1;
  CHECK(g_allocations.load() - before >= 1);
  CHECK(v0[7] == 1);
  const long eigen_before = alloc_test::eigen_mallocs.load();
  Eigen::internal::set_is_malloc_allowed(false);
  Eigen::VectorXd v(100);  // Eigen allocates with malloc: caught by the runtime check
  Eigen::internal::set_is_malloc_allowed(true);
  v.setZero();
  CHECK(alloc_test::eigen_mallocs.load() - eigen_before >= 1);
}

TEST_CASE("ImplicitEuler::step does not allocate after warm-up (PCG, one thread)", "[alloc]") {
  const Clothd cloth{ClothSpecd{}};
  ImplicitOptions o;
  o.threads = 1;
  CHECK(allocations_in_steps(cloth, o, 2, 5) == 0);
  o.preconditioner = PreconditionerKind::MultigridFloat;
  CHECK(allocations_in_steps(cloth, o, 2, 5) == 0);
  o.preconditioner = PreconditionerKind::AlgebraicMultigrid;  // its hierarchy is built in the first step
  CHECK(allocations_in_steps(cloth, o, 2, 5) == 0);
  o.preconditioner = PreconditionerKind::AlgebraicMultigridFloat;
  CHECK(allocations_in_steps(cloth, o, 2, 5) == 0);
  o.solver = LinearSolverKind::Bicgstab;
  CHECK(allocations_in_steps(cloth, o, 2, 5) == 0);
}

TEST_CASE("ImplicitEuler::step does not allocate after warm-up (PCG, two threads)", "[alloc][threads]") {
  ClothSpecd spec;
  spec.nx = spec.ny = 78;  // just large enough that assembly and PCG really use two threads
  const Clothd cloth(spec);
  ImplicitOptions o;
  o.threads = 2;
  CHECK(allocations_in_steps(cloth, o, 1, 1) == 0);
  o.preconditioner = PreconditionerKind::MultigridFloat;
  CHECK(allocations_in_steps(cloth, o, 1, 1) == 0);
  o.preconditioner = PreconditionerKind::AlgebraicMultigrid;
  CHECK(allocations_in_steps(cloth, o, 1, 1) == 0);
  o.preconditioner = PreconditionerKind::AlgebraicMultigridFloat;
  CHECK(allocations_in_steps(cloth, o, 1, 1) == 0);
}
