#!/usr/bin/env bash
# The main job: simulate the default scene and write the result. Installs missing packages first.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh test
cmake --preset release -DDRAPE_BUILD_BENCHMARKS=OFF -DDRAPE_BUILD_TESTS=OFF >/dev/null
cmake --build --preset release --target hanging_cloth
mkdir -p out
build/release/examples/hanging_cloth --out out "$@"
