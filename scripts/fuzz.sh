#!/usr/bin/env bash
# Bounded fuzzing of drape's input handling with libFuzzer (clang): the state-file loader, the
# scene-file parser, the command-line handling of drape-render, the OBJ mesh reader and the
# sewing-pattern reader.
#   scripts/fuzz.sh [SECONDS_PER_TARGET=20] [TARGET...]     (targets: state_io scene cli obj pattern)
# Builds the fuzzers in the sanitized tree (cmake --preset sanitize: clang, ASan + UBSan, build/asan,
# where the sanitized test suite is built too, so drape's compiled instances are compiled once for
# both), runs each for SECONDS from fuzz/corpus/<target> (new inputs go to build/fuzz/corpus/<target>,
# the repository's seed corpus is not modified), stops by itself, and exits non-zero if any target
# found a crash (the reproducer is printed and kept in build/fuzz/artifacts/). Prints the executions
# per target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(state_io scene cli obj pattern)
command -v clang++ >/dev/null || { echo "fuzz.sh: needs clang++ (scripts/install-deps.sh fuzz)" >&2; exit 2; }

cmake --preset sanitize >/dev/null
cmake --build --preset sanitize --target $(printf 'fuzz_%s ' "${targets[@]}")
fuzzers=build/asan/fuzz
build=build/fuzz

mkdir -p "$build/artifacts"
status=0
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  mkdir -p "$work"
  log="$build/fuzz_$t.log"
  echo "== fuzz_$t: ${seconds} s"
  # -close_fd_mask=1: the parsers' own stdout (CLI11 help text) is noise; libFuzzer reports on stderr.
  # -rss_limit_mb / -malloc_limit_mb: an input that makes the code allocate > 1 GB is a finding.
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     "$fuzzers/fuzz_$t" "$work" "fuzz/corpus/$t" -max_total_time="$seconds" -timeout=10 \
       -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=4096 -close_fd_mask=1 \
       -artifact_prefix="$build/artifacts/${t}-" -print_final_stats=1 >"$log" 2>&1; then
    execs=$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
    echo "fuzz_$t: ${execs:-?} executions, no crash (corpus: $(ls "$work" | wc -l) inputs in $work)"
  else
    status=1
    echo "fuzz_$t: FAILED, see $log; reproducer:" >&2
    grep -E 'ERROR|SUMMARY|Test unit written|==[0-9]+==' "$log" | head -20 >&2
  fi
done
exit $status
