#pragma once
/// \file instruction_set.hpp
/// Which x86-64 vector instructions drape's hot loops use, chosen at run time.
///
/// A build without `-march` targets every x86-64 (SSE2). The hot loops (the explicit integrators'
/// spring and node passes, the implicit system's assembly, edge product and multigrid residual)
/// are also compiled for AVX2 and pick that version when the CPU has it: 4 doubles or 8 floats per
/// instruction, above all for the square root and the division of every spring
/// (docs/benchmarks.md has the measured gain). Both versions use the same
/// correctly rounded operations in the same order and no fused multiply-add, so the results are
/// bitwise the same whichever runs.
///
/// `use_instruction_set()` (core/instruction_set_choice.hpp) chooses by hand, for comparisons and
/// benchmarks; the environment variable `DRAPE_INSTRUCTION_SET=baseline` does the same for a whole
/// process.

#include <atomic>
#include <cstdlib>
#include <cstring>

/// 1 where drape compiles an AVX2 version beside the baseline one (GCC or Clang on x86-64, unless
/// the whole build already targets AVX2).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(__AVX2__)
#define DRAPE_AVX2_DISPATCH 1
#else
#define DRAPE_AVX2_DISPATCH 0
#endif

namespace drape {

enum class InstructionSet {
  Baseline,  ///< what the build targets (SSE2 for a plain x86-64 build)
  Avx2,      ///< AVX2 versions of the hot loops (only where DRAPE_AVX2_DISPATCH is 1)
};

/// The best instruction set this CPU and build support.
inline InstructionSet detected_instruction_set() {
#if DRAPE_AVX2_DISPATCH
  static const bool avx2 = [] {
    __builtin_cpu_init();  // needed if the first call comes from a static constructor
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2 ? InstructionSet::Avx2 : InstructionSet::Baseline;
#else
  return InstructionSet::Baseline;
#endif
}

namespace detail {
inline std::atomic<InstructionSet>& chosen_instruction_set() {
  static std::atomic<InstructionSet> chosen{[] {
    const char* env = std::getenv("DRAPE_INSTRUCTION_SET");
    return env && std::strcmp(env, "baseline") == 0 ? InstructionSet::Baseline : detected_instruction_set();
  }()};
  return chosen;
}
}  // namespace detail

/// The instruction set the hot loops use now.
inline InstructionSet instruction_set() { return detail::chosen_instruction_set().load(std::memory_order_relaxed); }

namespace detail {
/// Chooses `set` for the whole process if this CPU and build support it; returns false (and
/// changes nothing) otherwise. use_instruction_set() is the checked entry point.
inline bool choose_instruction_set(InstructionSet set) {
  if (set == InstructionSet::Avx2 && detected_instruction_set() != InstructionSet::Avx2) return false;
  chosen_instruction_set().store(set, std::memory_order_relaxed);
  return true;
}
}  // namespace detail

}  // namespace drape
