#!/usr/bin/env bash
# Soak test (not part of the unit tests): the default scene for a million steps with each
# integrator (RK2 at its default dt = 0.5 ms, implicit Euler at dt = 1/60 s), checking that every
# step succeeds, the state stays finite, the total energy never rises above its start, and peak
# memory does not grow after the warm-up. Builds tests/soak/soak.cpp in Release in build/soak.
#   scripts/soak.sh [RK2_STEPS=1000000] [IMPLICIT_STEPS=1000000] [THREADS=1]
# Measured figures: docs/reliability.md ("Soak").
set -euo pipefail
cd "$(dirname "$0")/.."
rk2_steps=${1:-1000000}
implicit_steps=${2:-1000000}
threads=${3:-1}
cmake -S . -B build/soak -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRAPE_BUILD_EXAMPLES=OFF \
  -DDRAPE_BUILD_BENCHMARKS=OFF -DDRAPE_BUILD_VIEWER=OFF >/dev/null
cmake --build build/soak --target drape_soak
soak=build/soak/tests/reliability/drape_soak
status=0
"$soak" rk2 "$rk2_steps" 0.0005 "$threads" || status=1
"$soak" implicit "$implicit_steps" 0.016666666666666666 "$threads" || status=1
[ $status -eq 0 ] && echo "soak: passed" || echo "soak: FAILED" >&2
exit $status
