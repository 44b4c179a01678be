#!/usr/bin/env bash
# Proves the tests can fail: applies each deliberate bug listed in tests/mutations.tsv to a scratch
# copy of the committed tree (HEAD), rebuilds the named test binaries and requires at least one to fail.
#   scripts/mutation_check.sh            (needs a configured tree; takes a few minutes)
#   DRAPE_MUTATIONS_MATCH=multigrid scripts/mutation_check.sh   (only mutations whose name matches)
# tests/mutations.tsv: one mutation per line, TAB-separated: name, file, exact text, replacement,
# space-separated test targets (a replacement of `-` deletes the text). Lines starting with # are comments.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
git -C "$root" archive HEAD | tar -x -C "$scratch"   # the committed tree, as CI sees it
cmake -S "$scratch" -B "$scratch/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRAPE_BUILD_BENCHMARKS=OFF \
  -DDRAPE_BUILD_EXAMPLES=OFF >/dev/null
survivors=0
total=0
while IFS=$'\t' read -r name file old new targets; do
  [[ -z "$name" || "$name" == \#* ]] && continue
  [[ -n "${DRAPE_MUTATIONS_MATCH:-}" && ! "$name" =~ ${DRAPE_MUTATIONS_MATCH} ]] && continue
  total=$((total + 1))
  cp "$scratch/$file" "$scratch/$file.orig"
  [ "$new" = "-" ] && new=""
  /usr/bin/python3 - "$scratch/$file" "$old" "$new" <<'PY'
import sys
path, old, new = sys.argv[1:]
text = open(path).read()
if old not in text:
    sys.exit(f"mutation text not found in {path}: {old}")
open(path, "w").write(text.replace(old, new, 1))
PY
  caught=""
  # A CTest entry test_cli_* (one scene's run) is the program test_cli, which runs drape-render.
  build_targets=$(printf '%s\n' $targets | sed 's/^test_cli_.*/test_cli/' | sort -u | tr '\n' ' ')
  [[ " $build_targets " == *" test_cli "* ]] && build_targets="$build_targets drape-render"
  if ! cmake --build "$scratch/build" --target $build_targets >"$scratch/build.log" 2>&1; then
    printf 'INVALID   %-40s does not compile:\n' "$name"
    grep -m3 -E 'error' "$scratch/build.log" || tail -3 "$scratch/build.log"
    survivors=$((survivors + 1))
    mv "$scratch/$file.orig" "$scratch/$file"
    touch "$scratch/$file"   # newer than the mutated objects, so the next build recompiles them
    continue
  else
    for t in $targets; do
      # Through CTest: it sets each test's environment (test_cli needs DRAPE_RENDER).
      if ! ctest --test-dir "$scratch/build" -R "^${t}\$" --no-tests=error >/dev/null 2>&1; then caught="$caught $t"; fi
    done
  fi
  mv "$scratch/$file.orig" "$scratch/$file"
  touch "$scratch/$file"
  if [ -n "$caught" ]; then
    printf 'caught    %-40s by:%s\n' "$name" "$caught"
  else
    printf 'SURVIVED  %-40s (%s)\n' "$name" "$targets"
    survivors=$((survivors + 1))
  fi
done < "$scratch/tests/mutations.tsv"   # the committed list, like the code
echo "$((total - survivors)) of $total mutations caught"
[ "$survivors" -eq 0 ]
