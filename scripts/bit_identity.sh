#!/usr/bin/env bash
# Proves a refactoring changed no result: runs two drape-render builds on the same matrix of scenes
# (both integrators, every Jacobian x solver x preconditioner x pin treatment, 1 and 2 threads,
# grids from 9 x 9 to 97 x 97) and compares their final states (17 significant digits, so equal
# text means equal bits) and the deterministic columns of their CSV logs.
#   scripts/bit_identity.sh REFERENCE_DRAPE_RENDER CANDIDATE_DRAPE_RENDER
# e.g. build the previous commit in a scratch worktree and compare it with build/release:
#   git worktree add /tmp/ref HEAD~1 && cmake --preset release -S /tmp/ref && cmake --build /tmp/ref/build/release
#   scripts/bit_identity.sh /tmp/ref/build/release/viewer/drape-render build/release/viewer/drape-render
# Exit status 0 if every run gives identical bits, 1 otherwise. Solvers that one of the builds lacks
# (cholmod, umfpack without SuiteSparse) are reported as skipped.
set -uo pipefail
reference=${1:?usage: bit_identity.sh REFERENCE CANDIDATE}
candidate=${2:?usage: bit_identity.sh REFERENCE CANDIDATE}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

common="--width 32 --height 24 --samples 1 --no-floor --quiet --camera fixed"
runs=()
# Explicit midpoint: both boundary conditions, one and two threads, a grid whose spring pass splits.
for n in 17 33 65; do
  for b in 1 2; do
    for t in 1 2; do runs+=("--integrator rk2 --nx $n --ny $n --boundary $b --threads $t --frames 4 --frame-time 0.05"); done
  done
done
# Linearised implicit Euler: every valid Jacobian / solver / preconditioner / pin treatment.
implicit="--integrator implicit --frames 6 --frame-time 0.05"
for n in 9 33; do
  for t in 1 2; do
    for dt in 0.01 0.025; do
      base="$implicit --nx $n --ny $n --threads $t --dt $dt"
      for j in spd symmetric; do
        for p in multigrid block-jacobi; do
          for pins in eliminate filter; do runs+=("$base --jacobian $j --solver cg --preconditioner $p --pin-treatment $pins"); done
        done
        runs+=("$base --jacobian $j --solver ldlt" "$base --jacobian $j --solver cholmod")
      done
      for j in spd symmetric exact; do
        for pins in eliminate filter; do runs+=("$base --jacobian $j --solver bicgstab --pin-treatment $pins"); done
        runs+=("$base --jacobian $j --solver lu" "$base --jacobian $j --solver umfpack")
      done
    done
  done
done
# Grids large enough for the two-thread paths of PCG and the multigrid levels; one corner pinned.
for t in 1 2; do
  runs+=("$implicit --nx 97 --ny 97 --threads $t --dt 0.0166666666666666667")
  runs+=("$implicit --nx 97 --ny 97 --threads $t --dt 0.01 --boundary 1 --preconditioner block-jacobi")
  runs+=("$implicit --nx 97 --ny 97 --threads $t --dt 0.01 --pin-treatment filter")
done

# Keeps the CSV columns that do not depend on the wall clock (wall_time, achieved_factor), chosen by
# name from the reference's header: columns a newer candidate appends to log.csv are not compared,
# a column it lacks or renames is a difference.
#   deterministic_csv FILE REFERENCE_FILE
deterministic_csv() {
  awk -F, -v ref="$2" '
    BEGIN { getline header < ref; n = split(header, want, ",") }
    NR == 1 { for (i = 1; i <= NF; i++) column[$i] = i }
    {
      line = ""
      for (k = 1; k <= n; k++) {
        if (want[k] == "wall_time" || want[k] == "achieved_factor") continue
        line = line ((want[k] in column) ? $(column[want[k]]) : "<no " want[k] ">") ","
      }
      print line
    }' "$1"
}

same=0; different=0; skipped=0
for i in "${!runs[@]}"; do
  args="${runs[$i]} $common"
  ok=1
  for side in reference candidate; do
    bin=$reference; [ "$side" = candidate ] && bin=$candidate
    out="$scratch/$side/$i"
    mkdir -p "$out"
    # shellcheck disable=SC2086
    "$bin" $args --out "$out/frames" --save-state "$out/state.txt" >"$out/stderr" 2>&1
    echo $? >"$out/code"
  done
  r="$scratch/reference/$i"; c="$scratch/candidate/$i"
  if grep -q "needs SuiteSparse" "$r/stderr" "$c/stderr"; then
    skipped=$((skipped + 1)); continue
  fi
  cmp -s "$r/code" "$c/code" || ok=0
  if [ -f "$r/state.txt" ] || [ -f "$c/state.txt" ]; then cmp -s "$r/state.txt" "$c/state.txt" || ok=0; fi
  if [ -f "$r/frames/log.csv" ]; then
    cmp -s <(deterministic_csv "$r/frames/log.csv" "$r/frames/log.csv") \
      <(deterministic_csv "$c/frames/log.csv" "$r/frames/log.csv") || ok=0
  fi
  if [ $ok = 1 ]; then
    same=$((same + 1))
  else
    different=$((different + 1))
    echo "DIFFERENT: ${runs[$i]} (exit $(cat "$r/code") vs $(cat "$c/code"))"
    head -3 "$c/stderr"
  fi
done
echo "bit_identity: $same identical, $different different, $skipped skipped (of ${#runs[@]} runs)"
[ $different -eq 0 ]
