#pragma once
/// \file team.hpp
/// Threads: how many to use, and the work sharing of one parallel region (a "team"). Every
/// parallel loop of drape goes through these helpers; they are the only place that speaks OpenMP.
///
/// drape parallelises with OpenMP when the including target is compiled with it (the CMake target
/// `drape::drape` adds it when found) and runs serially otherwise. The same code runs in both
/// cases: outside a parallel region, or without OpenMP, the team is one thread, a shared loop runs
/// every iteration on it and a barrier does nothing. Shares are contiguous and depend only on the
/// rank and the team size, never on scheduling, so results are reproducible for a thread count.

#include <utility>

#if defined(_OPENMP)
#include <omp.h>
#endif

/// `DRAPE_OMP_SIMD` before a loop: `#pragma omp simd` when compiled with OpenMP (the loop has no
/// dependence between iterations, so it is vectorised even where the compiler's cost model or
/// aliasing analysis would hesitate). `DRAPE_OMP_SIMD_SUM(s)`: the same for a loop that also sums
/// into the scalar `s`.
#define DRAPE_PRAGMA_TEXT(x) #x
#if defined(_OPENMP)
#define DRAPE_OMP_SIMD _Pragma("omp simd")
#define DRAPE_OMP_SIMD_SUM(s) _Pragma(DRAPE_PRAGMA_TEXT(omp simd reduction(+ : s)))
#else
#define DRAPE_OMP_SIMD
#define DRAPE_OMP_SIMD_SUM(s)
#endif

/// Forces inlining of the work-sharing helpers: their loop bodies keep their running sums in
/// registers only when the helper is inlined into the caller (measured: PCG 20% slower otherwise).
#if defined(__GNUC__)
#define DRAPE_INLINE_LOOP inline __attribute__((always_inline))
#else
#define DRAPE_INLINE_LOOP inline
#endif

namespace drape {

/// Threads available to drape: OpenMP's maximum, or 1 without OpenMP.
inline int max_threads() {
#if defined(_OPENMP)
  return omp_get_max_threads();
#else
  return 1;
#endif
}

/// `requested` threads (0 = max_threads()), but only as many as have `min_work_per_thread` items
/// each: below that, waking a second thread costs more than it saves (drape's benchmarks.md).
inline int effective_threads(int requested, long long work_items, long long min_work_per_thread) {
  int t = requested > 0 ? requested : max_threads();
  if (t > max_threads()) t = max_threads();
  const long long useful = work_items / (min_work_per_thread > 0 ? min_work_per_thread : 1);
  if (useful < t) t = static_cast<int>(useful < 1 ? 1 : useful);
  return t;
}

/// This thread's rank in the current team (0 outside a parallel region).
inline int team_rank() {
#if defined(_OPENMP)
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/// Threads in the current team (1 outside a parallel region).
inline int team_size() {
#if defined(_OPENMP)
  return omp_get_num_threads();
#else
  return 1;
#endif
}

/// Waits for the whole team.
inline void team_barrier() {
#if defined(_OPENMP)
#pragma omp barrier
#endif
}

/// Runs `body()` on a team of `threads` threads (serially if `threads` <= 1 or without OpenMP).
template <class Body>
DRAPE_INLINE_LOOP void run_in_team(int threads, Body&& body) {
#if defined(_OPENMP)
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    body();
    return;
  }
#endif
  (void)threads;
  body();
}

/// `body(i)` for every i in [begin, end), each thread of the team taking one contiguous share
/// (OpenMP's static schedule); the team waits at the end. Call from every thread of the team.
template <class Body>
DRAPE_INLINE_LOOP void team_for(int begin, int end, Body&& body) {
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
  for (int i = begin; i < end; ++i) body(i);
}

/// team_for() over [0, n).
template <class Body>
DRAPE_INLINE_LOOP void team_for(int n, Body&& body) {
  team_for(0, n, body);
}

/// team_for() without the wait at the end.
template <class Body>
DRAPE_INLINE_LOOP void team_for_nowait(int n, Body&& body) {
#if defined(_OPENMP)
#pragma omp for schedule(static) nowait
#endif
  for (int i = 0; i < n; ++i) body(i);
}

/// `body(i)` for every i in [0, n): shared by the team like team_for() if `shared`, otherwise all
/// on the calling thread, without any wait (for loops too short to be worth a barrier).
template <class Body>
DRAPE_INLINE_LOOP void team_for_if(bool shared, int n, Body&& body) {
  if (shared) {
    team_for(0, n, body);
  } else {
    for (int i = 0; i < n; ++i) body(i);
  }
}

/// One thread of the team runs `body()`; the team waits at the end.
template <class Body>
DRAPE_INLINE_LOOP void team_single(Body&& body) {
#if defined(_OPENMP)
#pragma omp single
#endif
  body();
}

/// Part `part` of `parts` of [0, total) as [begin, end): contiguous, sizes differ by at most one.
inline std::pair<long long, long long> even_share(long long total, int part, int parts) {
  return {total * part / parts, total * (part + 1) / parts};
}

}  // namespace drape
