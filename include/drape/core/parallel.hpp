#pragma once
/// \file parallel.hpp
/// Thread-count policy. drape parallelises with OpenMP when the including target is compiled with
/// it (the CMake target `drape::drape` adds it when found) and runs serially otherwise.

#if defined(_OPENMP)
#include <omp.h>
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
/// each: below that, waking a second thread costs more than it saves (docs/benchmarks.md).
inline int effective_threads(int requested, long long work_items, long long min_work_per_thread) {
  int t = requested > 0 ? requested : max_threads();
  if (t > max_threads()) t = max_threads();
  const long long useful = work_items / (min_work_per_thread > 0 ? min_work_per_thread : 1);
  if (useful < t) t = static_cast<int>(useful < 1 ? 1 : useful);
  return t;
}

}  // namespace drape
