#pragma once
/// \file instruction_set_choice.hpp
/// Choosing the hot loops' instruction set by hand (platform/instruction_set.hpp detects and
/// keeps it), for comparisons and benchmarks: a choice this CPU or build cannot run is refused
/// with an InvalidParameter, which the platform layer below core does not know.

#include "drape/core/validation.hpp"
#include "drape/platform/instruction_set.hpp"

namespace drape {

/// Chooses the instruction set for the whole process (not while a step runs).
/// \throws InvalidParameter if this CPU or build does not support `set`.
inline void use_instruction_set(InstructionSet set) {
  if (!detail::choose_instruction_set(set))
    throw InvalidParameter("instruction_set", "avx2",
                           "baseline (this CPU has no AVX2, or the build already targets it)");
}

}  // namespace drape
