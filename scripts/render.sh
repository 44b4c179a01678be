#!/usr/bin/env bash
# The main job: render the default scene (the 33 x 33 cloth, two corners pinned, RK2) to a
# folder of PNG frames with the headless viewer. Installs missing Debian packages first.
#   scripts/render.sh [drape-render flags...]     e.g. --boundary 1 --integrator implicit --dt 0.005
# Frames go to out/frames unless --out is given; `drape-render --help` lists every flag.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh viewer
cmake --preset release -DDRAPE_BUILD_TESTS=OFF -DDRAPE_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build --preset release --target drape-render
out=(--out out/frames)
for arg in "$@"; do
  case "$arg" in --out|--out=*|--scene|--scene=*) out=() ;; esac
done
build/release/viewer/drape-render "${out[@]}" "$@"
