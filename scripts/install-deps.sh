#!/usr/bin/env bash
# Installs the Debian 12 packages drape needs, only those that are missing.
#   scripts/install-deps.sh [test] [viewer] [bench] [fuzz] [tidy] [python]   (no argument: everything)
set -euo pipefail

core=(g++ cmake ninja-build pkg-config libeigen3-dev)
test=(catch2 libsuitesparse-dev libopenblas-dev libtinyobjloader-dev nlohmann-json3-dev)
viewer=(libosmesa6-dev libpng-dev libcli11-dev libtomlplusplus-dev libsuitesparse-dev libopenblas-dev
        libtinyobjloader-dev nlohmann-json3-dev)
bench=(libbenchmark-dev libsuitesparse-dev libopenblas-dev python3 python3-matplotlib)
# fuzz: the sanitized tree (CMakePresets.json "sanitize"), built with clang and its OpenMP runtime.
fuzz=(clang libclang-rt-14-dev libomp-14-dev catch2 libsuitesparse-dev libopenblas-dev libtinyobjloader-dev
      nlohmann-json3-dev)
tidy=(clang-tidy libsuitesparse-dev)
# The Python package (scripts/python.sh): the venv, the headers, Debian's numpy and matplotlib, the viewer's libraries.
python=(python3 python3-venv python3-dev python3-numpy python3-matplotlib libosmesa6-dev libpng-dev libcli11-dev
        libtomlplusplus-dev libtinyobjloader-dev nlohmann-json3-dev)

groups=("$@")
[ ${#groups[@]} -eq 0 ] && groups=(test viewer bench fuzz tidy python)
wanted=("${core[@]}")
for g in "${groups[@]}"; do
  case "$g" in
    test) wanted+=("${test[@]}") ;;
    viewer) wanted+=("${viewer[@]}") ;;
    bench) wanted+=("${bench[@]}") ;;
    fuzz) wanted+=("${fuzz[@]}") ;;
    tidy) wanted+=("${tidy[@]}") ;;
    python) wanted+=("${python[@]}") ;;
    *) echo "install-deps: unknown group '$g' (allowed: test viewer bench fuzz tidy python)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
