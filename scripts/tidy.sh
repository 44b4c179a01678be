#!/usr/bin/env bash
# clang-tidy on every library header (.clang-tidy: the naming rules of docs/conventions.md), in one
# translation unit that includes them all, the optional SuiteSparse ones too. Exit status 1 on any
# finding. Installs clang-tidy when it is missing (scripts/install-deps.sh tidy).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh tidy
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
tu="$scratch/all_headers.cpp"
for h in $(cd include && find drape -name '*.hpp' | sort); do echo "#include \"$h\""; done >"$tu"
clang-tidy --quiet --config-file=.clang-tidy "$tu" -- -x c++ -std=c++17 -DDRAPE_HAS_SUITESPARSE \
  -Iinclude -isystem /usr/include/eigen3 -isystem /usr/include/suitesparse
echo "tidy: $(grep -c include "$tu") headers, no findings"
