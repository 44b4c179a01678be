#pragma once
/// \file team.hpp
/// Work sharing inside one OpenMP parallel region (a "team"), written so that the same functions
/// also run serially: outside a parallel region, or without OpenMP, the team is one thread and a
/// barrier does nothing. Shares are contiguous and depend only on the rank and the team size.

#include <utility>

#include "drape/core/parallel.hpp"

/// `#pragma omp simd` when compiled with OpenMP: the loop has no dependence between iterations
/// (vectorised even where the compiler's cost model or aliasing analysis would hesitate).
/// `DRAPE_OMP_SIMD_SUM(s)`: the same for a loop that also sums into the scalar `s`.
#define DRAPE_PRAGMA_TEXT(x) #x
#if defined(_OPENMP)
#define DRAPE_OMP_SIMD _Pragma("omp simd")
#define DRAPE_OMP_SIMD_SUM(s) _Pragma(DRAPE_PRAGMA_TEXT(omp simd reduction(+ : s)))
#else
#define DRAPE_OMP_SIMD
#define DRAPE_OMP_SIMD_SUM(s)
#endif

namespace drape {

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
void run_in_team(int threads, Body&& body) {
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

/// Part `part` of `parts` of [0, total) as [begin, end): contiguous, sizes differ by at most one.
inline std::pair<long long, long long> even_share(long long total, int part, int parts) {
  return {total * part / parts, total * (part + 1) / parts};
}

}  // namespace drape
