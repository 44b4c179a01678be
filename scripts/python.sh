#!/usr/bin/env bash
# The Python package (docs/python.md): installs the Debian packages it needs, makes the venv
# build/venv (with Debian's numpy and matplotlib), pip-installs drape from this checkout, builds
# drape-render (the C++ program the bit-identity tests compare against) and runs pytest.
#   scripts/python.sh [pytest arguments...]        e.g. scripts/python.sh -k bit_identity
# Build folders: build/py-<wheel tag> (the module, kept, so a second run only relinks what
# changed; DRAPE_PYTHON_BUILD_DIR names another CMake tree to build it in, below) and build/py-ref
# (drape-render, unless DRAPE_RENDER names one). DRAPE_JOBS sets the parallel compile jobs
# (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh python
jobs=${DRAPE_JOBS:-$(nproc)}

venv=build/venv
if [ ! -x "$venv/bin/python" ]; then
  # Debian's python3, not whichever python3 is first on PATH; Debian's numpy and matplotlib are reused.
  /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
pip=("$venv/bin/python" -m pip --disable-pip-version-check -q)
# The build requirements of pyproject.toml, installed once so the build below needs no isolation,
# and the sweep's (drape.sweep, docs/sweeps.md): pyarrow < 20 because later ones need numpy >= 2
# and the venv uses Debian 12's numpy 1.24. usd-core (Pixar's USD library) only for the tests: they
# read drape-render's USD file with it (python/tests/test_usd_export.py).
"${pip[@]}" install "scikit-build-core>=0.10" "nanobind>=2.2" pytest numpy matplotlib \
  dask distributed "pyarrow<20" tqdm usd-core
# DRAPE_PYTHON_BUILD_DIR: build the module in that CMake tree (scripts/test.sh passes build/release),
# with the tree's own options, so it links the objects already compiled there (the compiled
# instances, the viewer and scene-file libraries are position-independent) instead of compiling them
# again in build/py-<wheel tag>.
reuse=()
if [ -n "${DRAPE_PYTHON_BUILD_DIR:-}" ]; then
  cache="$DRAPE_PYTHON_BUILD_DIR/CMakeCache.txt"
  [ -f "$cache" ] || { echo "python.sh: DRAPE_PYTHON_BUILD_DIR has no CMakeCache.txt: $cache" >&2; exit 2; }
  reuse=(--config-settings "build-dir=$DRAPE_PYTHON_BUILD_DIR")
  prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:[A-Z]*=//p' "$cache")
  with_python=$(sed -n 's/^DRAPE_BUILD_PYTHON:[A-Z]*=//p' "$cache")
  for option in DRAPE_BUILD_TESTS DRAPE_BUILD_EXAMPLES DRAPE_BUILD_BENCHMARKS DRAPE_WITH_SUITESPARSE; do
    value=$(sed -n "s/^$option:[A-Z]*=//p" "$cache")
    [ -n "$value" ] && reuse+=(--config-settings "cmake.define.$option=$value")
  done
fi
CMAKE_BUILD_PARALLEL_LEVEL=$jobs "${pip[@]}" install --no-build-isolation "${reuse[@]}" ./
if [ -n "${DRAPE_PYTHON_BUILD_DIR:-}" ]; then
  # The tree's own install prefix and Python switch back (pip's configure set a temporary prefix).
  cmake -S . -B "$DRAPE_PYTHON_BUILD_DIR" -DCMAKE_INSTALL_PREFIX="$prefix" -DDRAPE_BUILD_PYTHON="$with_python" >/dev/null
fi

# The C++ program the bit-identity tests compare against: DRAPE_RENDER if given (scripts/test.sh
# passes the one it built), else built here.
render=${DRAPE_RENDER:-}
if [ -z "$render" ]; then
  cmake -S . -B build/py-ref -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRAPE_BUILD_TESTS=OFF -DDRAPE_BUILD_EXAMPLES=OFF \
    -DDRAPE_BUILD_BENCHMARKS=OFF -DDRAPE_BUILD_VIEWER=ON >/dev/null
  cmake --build build/py-ref --target drape-render -j "$jobs"
  render=$PWD/build/py-ref/viewer/drape-render
fi
render=$(realpath "$render")

# From build/: the installed package is imported, not the sources in python/drape.
cd build
DRAPE_RENDER="$render" DRAPE_REQUIRE_REFERENCE=1 venv/bin/python -m pytest ../python/tests -q -p no:cacheprovider "$@"
