#!/usr/bin/env bash
# Builds drape in Release and runs every test (ctest, then the Python package's pytest through
# scripts/python.sh). Installs missing Debian packages first.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh test viewer
# Explicit ON: render.sh shares this build folder with tests turned off.
cmake --preset release -DDRAPE_BUILD_TESTS=ON -DDRAPE_BUILD_EXAMPLES=ON -DDRAPE_BUILD_VIEWER=ON \
  -DDRAPE_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build --preset release
ctest --preset release -j2 --no-tests=error
# The Python package and its tests (pytest), against the drape-render built above.
# The module is built in build/release, linking the libraries compiled above.
DRAPE_PYTHON_BUILD_DIR=build/release DRAPE_RENDER="$PWD/build/release/viewer/drape-render" scripts/python.sh
