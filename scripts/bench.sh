#!/usr/bin/env bash
# Builds drape's benchmark suite in Release, runs it (repetitions, medians), measures the compile time
# of the umbrella header, and regenerates docs/benchmarks.md and docs/images/bench_step_time.png.
#
#   scripts/bench.sh [extra drape_bench arguments, e.g. --benchmark_filter=rk2_step]
#
# Environment:
#   DRAPE_BENCH_BUILD        build directory            (default build/bench)
#   DRAPE_BENCH_DATA         directory for the JSON     (default docs/data)
#   DRAPE_BENCH_DOCS         directory for benchmarks.md and images/ (default docs)
#   DRAPE_BENCH_REPETITIONS  repetitions per benchmark  (default 3; the report uses their median)
#   DRAPE_BENCH_QUIET_WAIT   seconds to wait for the 1-minute load average to fall below 0.5 before
#                            running (default 0). Two-thread timings on a busy 2-core machine
#                            measure the other processes, not drape.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${DRAPE_BENCH_BUILD:-build/bench}
data=${DRAPE_BENCH_DATA:-docs/data}
docs=${DRAPE_BENCH_DOCS:-docs}
reps=${DRAPE_BENCH_REPETITIONS:-3}
quiet_wait=${DRAPE_BENCH_QUIET_WAIT:-0}

python=python3
for p in python3 /usr/bin/python3; do
  if "$p" -c "import matplotlib" 2>/dev/null; then python=$p; break; fi
done

scripts/install-deps.sh bench
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRAPE_BUILD_BENCHMARKS=ON \
  -DDRAPE_BUILD_TESTS=OFF -DDRAPE_BUILD_EXAMPLES=OFF -DDRAPE_BUILD_VIEWER=OFF >/dev/null
# Every benchmark program, not only the suite: the companion tools the docs quote
# (drape_sim_second, drape_memory, ...) must time the same code as the suite.
cmake --build "$build"
mkdir -p "$data" "$docs/images"

# ---- compile time of a translation unit that includes the umbrella header (best of 3) ------------
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
ct_json="$data/compile_time.json"
"$python" - "$cxx" "$ct_json" "$build" <<'PY'
import json, subprocess, sys, time
cxx, out, build = sys.argv[1:4]
flags = ["-std=c++17", "-O3", "-DNDEBUG", "-fopenmp", "-Iinclude", "-isystem", "/usr/include/eigen3"]
probes = {}
load_before = float(open("/proc/loadavg").read().split()[0])
for probe in ("include_only", "typical_use"):
    best = None
    for _ in range(3):
        t0 = time.perf_counter()
        subprocess.run([cxx, *flags, "-c", f"bench/compile_time/{probe}.cpp", "-o", f"{build}/ct_{probe}.o"], check=True)
        t = time.perf_counter() - t0
        best = t if best is None else min(best, t)
    probes[probe] = round(best, 3)
version = subprocess.run([cxx, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
json.dump({"compiler": version, "command": " ".join([cxx, *flags, "-c", "bench/compile_time/<probe>.cpp"]),
           "probes": probes, "loadavg_1min_before": load_before}, open(out, "w"), indent=2)
PY
echo "bench.sh: compile times -> $ct_json"

# ---- wait for a quiet machine (optional) ----------------------------------------------------------
busy() { awk '{ exit !($1 >= 0.5) }' /proc/loadavg; }
waited=0
while [ "$waited" -lt "$quiet_wait" ] && busy; do
  sleep 10
  waited=$((waited + 10))
done
busy &&
  echo "bench.sh: warning: load average $(cut -d" " -f1 /proc/loadavg) before the run; two-thread figures will be pessimistic" >&2

# ---- run ------------------------------------------------------------------------------------------
load_before=$(cat /proc/loadavg)
# Busy CPU time of the whole machine (USER_HZ ticks) and of this run, to report how much of the
# machine other processes took while the suite ran.
cpu_busy() { awk '/^cpu /{ print $2 + $3 + $4 + $7 + $8 + $9 }' /proc/stat; }
# CPU seconds of this shell's finished children (cutime + cstime of /proc/$$/stat; a `times` inside
# $(...) would only see the subshell).
children_cpu() { awk -v hz="$(getconf CLK_TCK)" '{ sub(/^.*\) /, ""); print ($14 + $15) / hz }' "/proc/$$/stat"; }
busy_before=$(cpu_busy)
own_before=$(children_cpu)
wall_before=$(date +%s.%N)
# OpenBLAS (behind CHOLMOD) must not keep spinning threads next to drape's own (docs/implicit.md).
OPENBLAS_NUM_THREADS=1 "$build/bench/drape_bench" \
  --benchmark_repetitions="$reps" \
  --benchmark_enable_random_interleaving=true \
  --benchmark_display_aggregates_only=true \
  --benchmark_out="$data/bench.json" --benchmark_out_format=json "$@"
load_after=$(cat /proc/loadavg)
busy_after=$(cpu_busy)
wall_after=$(date +%s.%N)
own_cpu=$(awk -v a="$(children_cpu)" -v b="$own_before" 'BEGIN { print a - b }')
hz=$(getconf CLK_TCK)
other_share=$(awk -v b0="$busy_before" -v b1="$busy_after" -v hz="$hz" -v own="$own_cpu" -v w0="$wall_before" \
  -v w1="$wall_after" -v n="$(nproc)" 'BEGIN { printf "%.3f", ((b1 - b0) / hz - own) / ((w1 - w0) * n) }')
echo "bench.sh: other processes used $other_share of the machine's CPU time during the run"

# ---- machine description --------------------------------------------------------------------------
"$python" - "$data/machine.json" "$load_before" "$load_after" "$other_share" <<'PY'
import json, os, platform, subprocess, sys
out, before, after, other = sys.argv[1:5]
lscpu = {}
for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
    k, _, v = line.partition(":")
    lscpu[k.strip()] = v.strip()
flags = set(lscpu.get("Flags", "").split())
def sh(*cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True).stdout.strip()
    except OSError:
        return ""
blas = sh("readlink", "-f", "/usr/lib/x86_64-linux-gnu/libblas.so.3")
json.dump({
    "cpu_model": lscpu.get("Model name", "?"),
    "cpu_family": lscpu.get("CPU family", "?"),
    "cores": os.cpu_count(),
    "threads_per_core": lscpu.get("Thread(s) per core", "?"),
    "hypervisor": lscpu.get("Hypervisor vendor", ""),
    "l1d": lscpu.get("L1d cache", ""), "l2": lscpu.get("L2 cache", ""), "l3": lscpu.get("L3 cache", ""),
    "simd": " ".join(f for f in ("avx2", "fma", "avx512f") if f in flags),
    "kernel": platform.release(),
    "blas": blas,
    "git_commit": sh("git", "rev-parse", "--short", "HEAD"),
    "git_dirty": bool(sh("git", "status", "--porcelain", "--", "include", "bench")),
    "loadavg_before": before, "loadavg_after": after,
    "other_processes_cpu_share": float(other),
}, open(out, "w"), indent=2)
PY

"$python" scripts/bench_report.py --bench "$data/bench.json" --machine "$data/machine.json" \
  --compile-time "$ct_json" --markdown "$docs/benchmarks.md" --plot "$docs/images/bench_step_time.png"
