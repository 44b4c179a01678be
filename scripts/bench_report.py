#!/usr/bin/env python3
"""Turns drape_bench's JSON into docs/benchmarks.md and docs/images/bench_step_time.png.

    scripts/bench_report.py --bench docs/data/bench.json --machine docs/data/machine.json \
        --compile-time docs/data/compile_time.json --markdown docs/benchmarks.md \
        --plot docs/images/bench_step_time.png

Normally run by scripts/bench.sh. Every figure in the page comes from these JSON files: medians over
the repetitions of one run, ratios taken within that run; the page describes that run and nothing
else (docs/performance.md explains the figures). Run on the stored JSON it regenerates the same page
without running a benchmark; `--keep-plot` then links the plot without redrawing it (no matplotlib
needed). Benchmark names have the form `family/key=value/.../n:N/threads:T` (bench/bench_common.hpp).
"""
import argparse
import json
import math
import statistics
from collections import defaultdict

UNIT_TO_MS = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}
IGNORED_ARGS = {"min_time", "iterations", "repeats", "real_time", "process_time", "min_warmup_time"}
REALTIME_MS = 1000.0 / 60.0


# ---- reading ---------------------------------------------------------------------------------------
def parse_name(run_name):
    parts = run_name.split("/")
    attrs = {}
    for p in parts[1:]:
        if "=" in p:
            k, v = p.split("=", 1)
            attrs[k] = v
        elif ":" in p:
            k, v = p.split(":", 1)
            if k not in IGNORED_ARGS:
                attrs[k] = v
    return parts[0], attrs


class Result:
    def __init__(self, family, attrs):
        self.family = family
        self.attrs = attrs
        self.times_ms = []
        self.cpu_ms = []
        self.counters = defaultdict(list)

    @property
    def n(self):
        return int(self.attrs["n"])

    @property
    def nodes(self):
        return self.n * self.n

    @property
    def threads(self):
        return int(self.attrs.get("threads", 1))

    @property
    def median_ms(self):
        return statistics.median(self.times_ms)

    @property
    def median_cpu_ms(self):
        return statistics.median(self.cpu_ms) if self.cpu_ms else None

    def counter(self, name, how=statistics.median):
        values = self.counters.get(name)
        return how(values) if values else None

    def method(self):
        """Everything that names the method, i.e. all attributes except the grid size."""
        keys = [k for k in self.attrs if k != "n"]
        return tuple((k, self.attrs[k]) for k in keys)


COUNTER_KEYS = ("bytes_per_second", "cg_iterations", "residual_max", "failures", "compressed", "threads_used", "nodes",
                "agreement", "contacts", "solves", "items_per_second")


def load_results(path):
    doc = json.load(open(path))
    results = {}
    aggregates = defaultdict(dict)
    for b in doc["benchmarks"]:
        run_name = b.get("run_name", b["name"])
        if b.get("error_occurred"):
            continue
        family, attrs = parse_name(run_name)
        r = results.setdefault(run_name, Result(family, attrs))
        t = b["real_time"] * UNIT_TO_MS[b.get("time_unit", "ns")]
        if b.get("run_type", "iteration") == "aggregate":
            aggregates[run_name][b["aggregate_name"]] = t
            continue
        r.times_ms.append(t)
        r.cpu_ms.append(b["cpu_time"] * UNIT_TO_MS[b.get("time_unit", "ns")])
        for k in COUNTER_KEYS:
            if k in b:
                r.counters[k].append(b[k])
    for run_name, agg in aggregates.items():  # only aggregates were written: use their median
        r = results[run_name]
        if not r.times_ms and "median" in agg:
            r.times_ms.append(agg["median"])
    return doc.get("context", {}), [r for r in results.values() if r.times_ms and ("n" in r.attrs or r.family == "machine")]


# ---- helpers ---------------------------------------------------------------------------------------
def find(results, family, **attrs):
    """The results of `family` whose attributes include `attrs` (values compared as strings)."""
    want = {k: str(v) for k, v in attrs.items()}
    return [r for r in results if r.family == family and all(r.attrs.get(k) == v for k, v in want.items())]


def one(results, family, **attrs):
    found = find(results, family, **attrs)
    return found[0] if len(found) == 1 else None


def fmt_time(ms):
    if ms is None:
        return "-"
    if ms < 1:
        return f"{ms * 1000:.1f} us" if ms < 0.1 else f"{ms * 1000:.0f} us"
    if ms < 10:
        return f"{ms:.2f} ms"
    if ms < 1000:
        return f"{ms:.1f} ms"
    return f"{ms / 1000:.2f} s"


def fmt_ratio(x):
    if x is None:
        return "-"
    return f"{x:.2f}x" if x < 0.1 else f"{x:.1f}x" if x < 100 else f"{x:.0f}x"


def fit_exponent(points):
    """Least-squares slope of log(time) against log(nodes)."""
    if len(points) < 2:
        return None
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else None


def method_label(method):
    d = dict(method)
    parts = [d["impl"]] if "impl" in d else []
    for k in ("solver", "preconditioner", "jacobian", "what", "form"):
        if k in d:
            parts.append(d[k])
    if "dt" in d:
        parts.append(f"dt={d['dt'].replace('_', '/')}")
    if "threads" in d:
        parts.append(f"{d['threads']} thr")
    return " ".join(parts)


def by_method(results, family):
    groups = defaultdict(list)
    for r in results:
        if r.family == family:
            groups[r.method()].append(r)
    for g in groups.values():
        g.sort(key=lambda r: r.n)
    return groups


# ---- page --------------------------------------------------------------------------------------------
FAMILY_TEXT = {
    "force_assembly": ("Force assembly", "one evaluation of f(x, v) (springs + gravity) at the warm state"),
    "rk2_step": ("RK2 step", "one explicit midpoint step at the default dt = 0.5 ms (two force evaluations)"),
    "symplectic_step": ("Symplectic Euler step", "one symplectic Euler step at the same dt (one force evaluation); "
                        "the baseline is the textbook RK2 step, so the ratio is per simulated second at equal dt"),
    "jacobian_assembly": ("Jacobian assembly", "df/dx and df/dv (or the system matrix) at the warm state"),
    "linear_solve": ("Linear solve", "one solve of the implicit system at the warm state"),
    "matvec": ("Mat-vec", "one product y = A x of the implicit system (Spd, dt = 1/60) at the warm state: "
               "`edges` the per-spring edge form, `blocks` the block-row (block CSR) matrix, the baseline "
               "its scalar CSC matrix"),
    "implicit_step": ("Implicit step", "one linearised implicit Euler step (assembly + solve + update)"),
    "setup": ("Set-up", "building the scene and the integrator (pattern, symbolic analysis)"),
}

GROWTH_WHY = {
    "force_assembly": "one pass over the springs, whose number is proportional to the nodes: linear "
                      "work; an exponent above 1 means the data stopped fitting in cache.",
    "rk2_step": "two force passes plus vector updates, all linear in the nodes.",
    "symplectic_step": "one force pass plus the update: linear in the nodes, about half an RK2 step.",
    "jacobian_assembly": "one pass over the springs writing 3x3 blocks: linear in the nodes (the "
                         "triplet baseline adds a sort of all entries, n log n).",
    "matvec": "one pass over the springs (edge form) or the block rows: linear in the nodes; above 1 "
              "where the matrix stops fitting in cache.",
    "linear_solve": "CG: the iteration count does not grow with the grid (multigrid: ~10; block "
                    "Jacobi: 120-190, set by dt^2 ks / m), and each iteration costs a fixed number "
                    "of linear-cost mat-vecs (multigrid: the levels add up to ~4/3 of the finest), so "
                    "~linear; sparse Cholesky of a 2D grid has fill ~ n log n and factorisation work "
                    "~ n^1.5 (nested dissection), more with AMD ordering.",
    "implicit_step": "assembly is linear; the solve dominates and grows as in the linear-solve row; "
                     "the baseline refactorises from scratch (~n^1.5 and worse) every step.",
    "setup": "building springs and the pattern is linear; symbolic analysis of a direct solver "
             "grows faster (ordering).",
}


def family_table(results, family, baseline_match):
    groups = by_method(results, family)
    if not groups:
        return []
    title, what = FAMILY_TEXT.get(family, (family, ""))
    methods = sorted(groups, key=lambda m: (dict(m).get("impl") != "baseline", method_label(m)))
    sizes = sorted({r.n for g in groups.values() for r in g})
    lines = [f"### {title}", "", f"Median time of {what}; in brackets the speed-up over the textbook "
             "baseline of the same run (baseline time / this time).", ""]
    lines.append("| method | " + " | ".join(f"{n} x {n}" for n in sizes) + " | exponent |")
    lines.append("|---|" + "---|" * (len(sizes) + 1))
    for m in methods:
        row = {r.n: r for r in groups[m]}
        cells = []
        for n in sizes:
            r = row.get(n)
            if r is None:
                cells.append("-")
                continue
            cell = fmt_time(r.median_ms)
            base = baseline_match(results, r)
            if base is not None and base is not r:
                cell += f" ({fmt_ratio(base.median_ms / r.median_ms)})"
            cells.append(cell)
        k = fit_exponent([(r.nodes, r.median_ms) for r in groups[m]])
        lines.append(f"| {method_label(m)} | " + " | ".join(cells) + f" | {k:.2f} |" if k is not None else
                     f"| {method_label(m)} | " + " | ".join(cells) + " | - |")
    counter_rows = []
    for m in methods:
        if any(r.counter("cg_iterations") for r in groups[m]):
            row = {r.n: r for r in groups[m]}
            cells = []
            for n in sizes:
                r = row.get(n)
                if r is None:
                    cells.append("-")
                else:
                    it = r.counter("cg_iterations")
                    res = r.counter("residual_max", max)
                    cells.append(f"{it:.0f} it, {res:.1e}" if res is not None else f"{it:.0f} it")
            counter_rows.append(f"| {method_label(m)} | " + " | ".join(cells) + " |")
    if counter_rows:
        lines += ["", "Iterative solvers: mean CG iterations per step and the largest relative residual "
                  "seen (all repetitions).", "",
                  "| method | " + " | ".join(f"{n} x {n}" for n in sizes) + " |",
                  "|---|" + "---|" * len(sizes)] + counter_rows
    fails = [r for g in groups.values() for r in g if r.counter("failures", max)]
    if fails:
        lines += ["", "**Failed steps** (the step returned an error; state left unchanged): " +
                  ", ".join(f"{method_label(r.method())} at {r.n} x {r.n}: {r.counter('failures', max):.0f}"
                            for r in fails)]
    lines.append("")
    return lines


ENVIRONMENT_TEXT = {
    "drag": "linear drag in a steady wind",
    "drag_gusts": "linear drag in gusts",
    "aerodynamic": "per-triangle aerodynamic drag and lift, steady wind",
    "air": "all the air: drag, aerodynamics, gusts",
    "colliders8": "8 analytic colliders out of reach (detection alone)",
    "colliders8_touching": "8 colliders, one under the falling cloth (contacts in the solve)",
}
ENVIRONMENT_GOAL = {"drag": 5, "drag_gusts": 5, "colliders8": 15}


def environment_section(results):
    """The environment's costs: the environment against the bare cloth of the same run, the scenes, detection."""
    env = [r for r in results if r.family == "environment_step"]
    if not env:
        return []
    sizes = sorted({r.n for r in env})
    lines = ["## Contact and environment", "",
             "`environment_step`: one implicit step (dt = 1/60, default solver, 2 threads) of the hanging cloth "
             "with its environment; in brackets the cost over the bare cloth (`env=none`) of the same run. "
             "Goals: colliders at most +15%, drag and wind at most +5% ([performance.md](performance.md) has the "
             "measured limits of the per-triangle aerodynamics).", "",
             "| environment | goal | " + " | ".join(f"{n} x {n}" for n in sizes) + " |",
             "|---|---|" + "---|" * len(sizes)]
    bare = {r.n: r for r in env if r.attrs.get("env") == "none"}
    lines.append("| bare cloth (`none`) | | " + " | ".join(fmt_time(bare[n].median_ms) if n in bare else "-"
                                                        for n in sizes) + " |")
    for key, text in ENVIRONMENT_TEXT.items():
        row = {r.n: r for r in env if r.attrs.get("env") == key}
        if not row:
            continue
        cells = []
        for n in sizes:
            r = row.get(n)
            if r is None or n not in bare:
                cells.append("-")
                continue
            over = 100 * (r.median_ms / bare[n].median_ms - 1)
            cells.append(f"{fmt_time(r.median_ms)} ({over:+.0f}%)")
        goal = f"+{ENVIRONMENT_GOAL[key]}%" if key in ENVIRONMENT_GOAL else ""
        lines.append(f"| {text} (`{key}`) | {goal} | " + " | ".join(cells) + " |")
    lines.append("")
    scenes = [r for r in results if r.family == "scene_step"]
    if scenes:
        ssizes = sorted({r.n for r in scenes})
        lines += ["`scene_step`: one implicit step (dt = 1/60, 2 threads) of each example scene, timed from a moment "
                  "when it is in contact or in motion (bench/bench_scenes.cpp); "
                  "mean contacts, linear solves (contact rounds) and CG iterations per step.", "",
                  "| scene | " + " | ".join(f"{n} x {n}" for n in ssizes) + " |", "|---|" + "---|" * len(ssizes)]
        for name in sorted({r.attrs.get("scene") for r in scenes}):
            row = {r.n: r for r in scenes if r.attrs.get("scene") == name}
            cells = []
            for n in ssizes:
                r = row.get(n)
                if r is None:
                    cells.append("-")
                    continue
                c, so, it = r.counter("contacts"), r.counter("solves"), r.counter("cg_iterations")
                cells.append(f"{fmt_time(r.median_ms)}: {c or 0:.0f} contacts, {so or 0:.2f} solves, {it or 0:.0f} it")
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        lines.append("")
    detect = sorted((r for r in results if r.family == "contact_detection"), key=lambda r: r.n)
    if detect:
        k = fit_exponent([(r.nodes, r.median_ms) for r in detect])
        lines += ["`contact_detection`: finding the contacts of the drop-on-sphere scene (all nodes against its "
                  "colliders, swept over the step): " + ", ".join(
                      f"{fmt_time(r.median_ms)} at {r.n} x {r.n} ({r.nodes / r.median_ms / 1e3:.1f} M nodes/s)"
                      for r in detect) + (f"; time ~ nodes^{k:.2f}." if k is not None else "."), ""]
    return lines


def self_collision_section(results):
    """Self-collision's costs: the fold's step with self-collision on against off, and the broad phase per node."""
    fold = [r for r in results if r.family == "fold_step"]
    broad = sorted((r for r in results if r.family == "broad_phase"), key=lambda r: r.n)
    if not fold and not broad:
        return []
    lines = ["## Self-collision", ""]
    if fold:
        sizes = sorted({r.n for r in fold})
        lines += ["`fold_step`: one implicit step (dt = 1/60, 2 threads) of scenes/fold_on_sphere.toml's cloth at "
                  "n x n nodes from the state it folded into after 1.5 s, self-collision on (`self:1`) and off "
                  "(`self:0`) in the same run. Goal: on at most 3x off.", "",
                  "| | " + " | ".join(f"{n} x {n}" for n in sizes) + " |", "|---|" + "---|" * len(sizes)]
        on = {r.n: r for r in fold if r.attrs.get("self") == "1"}
        off = {r.n: r for r in fold if r.attrs.get("self") == "0"}
        lines.append("| off | " + " | ".join(fmt_time(off[n].median_ms) if n in off else "-" for n in sizes) + " |")
        lines.append("| on (on / off) | " + " | ".join(
            f"{fmt_time(on[n].median_ms)} ({on[n].median_ms / off[n].median_ms:.2f}x)" if n in on and n in off else "-"
            for n in sizes) + " |")
        lines.append("| proximity pairs per step | " + " | ".join(
            f"{on[n].counter('proximity') or 0:.0f}" if n in on else "-" for n in sizes) + " |")
        lines.append("")
    if broad:
        k = fit_exponent([(r.nodes, r.median_ms) for r in broad])
        lines += ["`broad_phase`: one refit of the triangle BVH to a swept step and the overlapping triangle pairs of "
                  "a cloth Z-folded three layers deep (serial): " + ", ".join(
                      f"{fmt_time(r.median_ms)} at {r.n} x {r.n} ({1e6 * r.median_ms / r.nodes:.0f} ns per node)"
                      for r in broad) + (f"; time ~ nodes^{k:.2f}." if k is not None else "."), ""]
    return lines


def baseline_for(results, r):
    """The baseline result comparable to r: same family, size and dt (and Jacobian family)."""
    if r.family not in ("force_assembly", "rk2_step", "symplectic_step", "implicit_step", "jacobian_assembly",
                        "linear_solve", "matvec"):
        return None
    attrs = {"impl": "baseline", "n": r.n}
    if "dt" in r.attrs:
        attrs["dt"] = r.attrs["dt"]
    return one(results, "rk2_step" if r.family == "symplectic_step" else r.family, **attrs)


def speedup_table(results):
    lines = ["### Two threads against one", "",
             "Median 1-thread time / median 2-thread time of the same method and size.", ""]
    rows = []
    for family in ("force_assembly", "rk2_step", "jacobian_assembly", "matvec", "linear_solve", "implicit_step"):
        for m, group in sorted(by_method(results, family).items(), key=lambda kv: method_label(kv[0])):
            d = dict(m)
            if d.get("threads") != "2":
                continue
            one_thread = dict(d, threads="1")
            cells = []
            for r2 in group:
                r1 = one(results, family, n=r2.n, **one_thread)
                ratio = r1.median_ms / r2.median_ms if r1 else None
                single = r2.counter("threads_used") == 1  # drape declined the second thread
                cells.append((r2.n, (ratio, single)))
            if all(c[0] is None for _, c in cells):
                continue
            rows.append((f"{FAMILY_TEXT[family][0]}: {method_label(m).replace(' 2 thr', '')}", cells))
    if not rows:
        return []
    sizes = sorted({n for _, cells in rows for n, _ in cells})
    lines.append("| method | " + " | ".join(f"{n} x {n}" for n in sizes) + " |")
    lines.append("|---|" + "---|" * len(sizes))
    for label, cells in rows:
        c = dict(cells)
        lines.append(f"| {label} | " + " | ".join(
            (fmt_ratio(c[n][0]) + ("*" if c[n][1] else "")) if n in c else "-" for n in sizes) + " |")
    return lines + ["", "\\* the \"2-thread\" run used one thread (`threads_used` = 1): below drape's work-per-thread "
                    "threshold (`min_springs_per_thread` = 4096 springs) the second thread is not woken, so the "
                    "ratio is noise. For the solves (no `threads_used` counter) PCG likewise stays on one thread "
                    "below 2 x 3000 block rows (`PcgSolver::min_rows_per_thread`), i.e. at 33 x 33 and 65 x 65 (4,223 free nodes).", ""]


def dispatch_section(results):
    """The AVX2 loops against the same step with them switched off (impl=drape-sse2)."""
    rows = []
    for family, name in (("rk2_step", "RK2"), ("symplectic_step", "symplectic Euler"),
                         ("implicit_step", "implicit Euler, dt = 1/60")):
        for r in sorted(find(results, family, impl="drape"), key=lambda r: (r.n, r.threads)):
            same = {k: v for k, v in r.attrs.items() if k not in ("impl", "n", "threads")}
            sse2 = one(results, family, impl="drape-sse2", n=r.n, threads=r.threads, **same)
            if sse2:
                rows.append(f"| {name} | {r.n} x {r.n} | {r.threads} | {fmt_time(sse2.median_ms)} | "
                            f"{fmt_time(r.median_ms)} | {fmt_ratio(sse2.median_ms / r.median_ms)} |")
    if not rows:
        return []
    return ["## Run-time instruction set: the AVX2 loops", "",
            "The explicit steps' spring and node passes, and the implicit solver's assembly (symmetric "
            "variants), edge product, multigrid residual, smoothing, transfers and Galerkin sums, have AVX2 versions chosen at run "
            "time when the CPU has them "
            "(include/drape/platform/instruction_set.hpp; the build itself targets plain x86-64). Both versions "
            "give the same bits (tests/core/test_instruction_set.cpp). `drape-sse2` is the same step with "
            "the AVX2 versions switched off, in the same run (implicit Euler: the default solver):", "",
            "| step | n x n | threads | SSE2 only | with AVX2 | speed-up |", "|---|---|---|---|---|---|"] + rows + [""]


def targets(results, context):
    default_solver = context.get("default_solver")
    default_pre = context.get("default_preconditioner")
    default_jac = context.get("default_jacobian")
    rows = []

    def implicit(n, dt, threads=2, impl="drape"):
        attrs = {"n": n, "dt": dt, "impl": impl}
        if impl == "drape":
            attrs.update(solver=default_solver, preconditioner=default_pre, jacobian=default_jac, threads=threads)
        return one(results, "implicit_step", **attrs)

    def rk2(n, threads=2, impl="drape"):
        attrs = {"n": n, "impl": impl}
        if impl == "drape":
            attrs["threads"] = threads
        return one(results, "rk2_step", **attrs)

    def timed(r):
        """Median wall time; for single-threaded runs also the calling thread's CPU time, which a
        busy machine does not inflate (time spent descheduled is not counted)."""
        if r is None:
            return "-"
        if r.threads == 1 and r.median_cpu_ms is not None:
            return f"{fmt_time(r.median_ms)} (CPU {fmt_time(r.median_cpu_ms)})"
        return fmt_time(r.median_ms)

    def row(name, goal, measured, ok):
        rows.append(f"| {name} | {goal} | {measured} | {'met' if ok else ('**missed**' if ok is not None else 'not measured')} |")

    imp, base = implicit(33, "1_60"), implicit(33, "1_60", impl="baseline")
    if imp and base:
        ratio = base.median_ms / imp.median_ms
        row("33 x 33 implicit step, default solver, dt = 1/60", "< 1 ms", timed(imp), imp.median_ms < 1)
        row("33 x 33 implicit step against the textbook baseline", ">= 25x",
            f"{fmt_ratio(ratio)} ({fmt_time(base.median_ms)} -> {fmt_time(imp.median_ms)})", ratio >= 25)
    else:
        row("33 x 33 implicit step: under 1 ms, against the textbook", "< 1 ms, >= 25x", "-", None)
    imp = implicit(129, "1_60")
    row("129 x 129 implicit step, default solver, dt = 1/60", "< 16.7 ms (real time)", timed(imp),
        imp.median_ms < REALTIME_MS if imp else None)
    # At 33 x 33 a user picks the faster thread count; at 257 the goal names 2 threads.
    fastest = min((r for r in (rk2(33, 1), rk2(33, 2)) if r), key=lambda r: r.median_ms, default=None)
    row("33 x 33 RK2 step (the faster of 1 and 2 threads)", "< 30 us",
        f"{timed(fastest)} ({fastest.threads} thread(s))" if fastest else "-",
        fastest.median_ms < 0.030 if fastest else None)
    r = rk2(257)
    row("257 x 257 RK2 step, 2 threads", "< 2 ms", timed(r), r.median_ms < 2 if r else None)
    for n in (129, 257):
        i1, i2 = implicit(n, "1_60", 1), implicit(n, "1_60", 2)
        s = i1.median_ms / i2.median_ms if i1 and i2 else None
        row(f"{n} x {n} implicit dt = 1/60, 2 threads against 1", ">= 1.7x",
            f"{s:.2f}x ({fmt_time(i1.median_ms)} -> {fmt_time(i2.median_ms)})" if s else "-", s >= 1.7 if s else None)
    # How far up real time holds: per size the faster of 1 and 2 threads (a user picks the faster),
    # the largest measured size under 1/60 s, and the fitted extrapolation beyond it.
    best = {}
    for r in find(results, "implicit_step", impl="drape", solver=default_solver, preconditioner=default_pre,
                  jacobian=default_jac, dt="1_60"):
        if r.n not in best or r.median_ms < best[r.n].median_ms:
            best[r.n] = r
    group = [best[n] for n in sorted(best)]
    realtime_note = None
    if group:
        under = [r for r in group if r.median_ms < REALTIME_MS]
        k = fit_exponent([(r.nodes, r.median_ms) for r in group])
        largest = under[-1] if under else None
        if largest and k:
            # t(N) = t_largest * (N / N_largest)^k = 16.7 ms
            nodes_rt = largest.nodes * (REALTIME_MS / largest.median_ms) ** (1 / k)
            realtime_note = (f"Real time at dt = 1/60 (step < {REALTIME_MS:.1f} ms, default solver, the faster of "
                             f"1 and 2 threads) holds up to {largest.n} x {largest.n} among the measured sizes "
                             f"({fmt_time(largest.median_ms)} on {largest.threads} thread(s)); extrapolating with "
                             f"the fitted exponent {k:.2f}, up to about {nodes_rt:.0f} nodes "
                             f"(~{math.sqrt(nodes_rt):.0f} x {math.sqrt(nodes_rt):.0f}).")
        else:
            realtime_note = ("Real time at dt = 1/60 (step < 16.7 ms, default solver) does not hold at any "
                             f"measured size (33 x 33: {fmt_time(group[0].median_ms)}).")
    return rows, realtime_note


def write_plot(results, context, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    default_solver = context.get("default_solver")
    fig, ax = plt.subplots(figsize=(8, 5.5))
    lines = []
    for family, dt in (("rk2_step", None), ("implicit_step", "1_60")):
        for m, group in by_method(results, family).items():
            d = dict(m)
            if dt and d.get("dt") != dt:
                continue
            # 2 threads for every method; 1 thread too for RK2 and the default implicit solver, whose
            # 2-thread figures a busy machine distorts most.
            is_default = (d.get("solver") == default_solver and d.get("jacobian") == context.get("default_jacobian")
                          and d.get("preconditioner") == context.get("default_preconditioner"))
            if d.get("impl") == "drape" and d.get("threads") != "2" and not (family == "rk2_step" or is_default):
                continue
            if d.get("impl") == "drape-sse2":  # the dispatch's gain is in the tables, not the plot
                continue
            label = ("RK2 " if family == "rk2_step" else "implicit ") + method_label(m)
            if is_default and d.get("impl") == "drape":
                label += " (default)"
            lines.append((label, group, d.get("impl") == "baseline"))
    colours = plt.get_cmap("tab20").colors
    for i, (label, group, is_base) in enumerate(sorted(lines)):
        ax.loglog([r.nodes for r in group], [r.median_ms for r in group], "--" if is_base else "-",
                  marker="o", label=label, color=colours[(2 * i) % 20 if i < 10 else (2 * i + 1) % 20])
    ax.axhline(REALTIME_MS, color="grey", lw=0.8, ls=":")
    ax.text(1100, REALTIME_MS * 1.1, "1/60 s (real time at dt = 1/60)", color="grey", fontsize=8)
    ax.set_xlabel("nodes (N x N grid)")
    ax.set_ylabel("median step time (ms)")
    ax.set_title("drape step time on 2 cores (dashed: textbook baseline)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", required=True)
    ap.add_argument("--machine")
    ap.add_argument("--compile-time")
    ap.add_argument("--markdown", required=True)
    ap.add_argument("--plot", help="the plot's path (drawn with matplotlib) and linked from the page")
    ap.add_argument("--keep-plot", action="store_true",
                    help="link the plot at --plot without redrawing it (the page regenerated from stored JSON)")
    args = ap.parse_args()

    context, results = load_results(args.bench)
    machine = json.load(open(args.machine)) if args.machine else {}
    ct = json.load(open(args.compile_time)) if args.compile_time else None
    reps = max((len(r.times_ms) for r in results), default=0)

    out = ["# Benchmarks", "",
           "<!-- Generated by scripts/bench_report.py from docs/data/*.json; do not edit by hand. -->", "",
           "Produced by `scripts/bench.sh` (Release build of `bench/`, Google Benchmark, "
           f"{reps} repetitions per benchmark in random interleaved order; every time below is the median "
           "of the repetitions and every ratio is taken between medians of the same run). "
           "Raw data: [`docs/data/bench.json`](data/bench.json).", ""]
    out += ["## Machine", "", "| | |", "|---|---|"]
    out.append(f"| CPU | {machine.get('cpu_model', '?')} (family {machine.get('cpu_family', '?')}), "
               f"{machine.get('cores', context.get('num_cpus', '?'))} cores, "
               f"{machine.get('threads_per_core', '?')} thread(s) per core"
               f"{', ' + machine['hypervisor'] + ' virtual machine' if machine.get('hypervisor') else ''} |")
    for r in sorted(find(results, "machine", what="stream_triad"), key=lambda r: r.threads):
        bw = r.counter("bytes_per_second")
        if bw:
            out.append(f"| memory bandwidth | {bw / 1e9:.1f} GB/s, STREAM triad on {r.threads} thread(s) "
                       "(`machine/what=stream_triad` in the JSON) |")
    if machine.get("simd"):
        out.append(f"| SIMD | {machine['simd']} |")
    out.append(f"| caches | L1d {machine.get('l1d', '?')}, L2 {machine.get('l2', '?')}, L3 {machine.get('l3', '?')} |")
    out.append(f"| compiler | {context.get('compiler', '?')}, flags `{context.get('cxx_flags', '?').strip()}` "
               f"(CMake Release defaults, no `-march`; the AVX2 spring pass is chosen at run time) |")
    out.append(f"| OpenMP | {context.get('openmp', '?')} (max threads {context.get('max_threads', '?')}) |")
    out.append(f"| Eigen | {context.get('eigen_version', '?')} |")
    if machine.get("blas"):
        out.append(f"| BLAS | `{machine['blas']}`, `OPENBLAS_NUM_THREADS={context.get('openblas_num_threads', '?')}` |")
    out.append(f"| run | {context.get('date', '?')}, drape {context.get('drape_version', '?')} at commit "
               f"{machine.get('git_commit', '?')}{' (+ uncommitted changes)' if machine.get('git_dirty') else ''} |")
    if machine.get("loadavg_before"):
        share = machine.get("other_processes_cpu_share")
        out.append(f"| load | load average before `{machine['loadavg_before']}`, after `{machine['loadavg_after']}`"
                   + (f"; other processes used {abs(max(share, 0)) * 100:.0f}% of the CPU time during the run" if share is not None else "")
                   + " |")
    out.append("")

    out += ["## Timed states and accuracy", "",
            "Scene: the default cloth (0.1 m spacing, 0.03 kg per node, g = 10 m/s^2, ks/kd = 20000/10 "
            "structural, 5000/5 shear, 500/1 bend), both corners (0,0) and (N-1,0) pinned, N x N nodes. "
            f"Every step benchmark starts from the state after a warm-up of {float(context.get('warm_up_time_s', 'nan')):g} s "
            f"of simulated time ({context.get('warm_up_method', '?')}), when the cloth is falling and "
            "swinging and part of the springs is compressed (the `compressed` counter in the JSON: "
            + ", ".join(f"{r.n} x {r.n}: {r.counter('compressed') * 100:.0f}%"
                        for r in sorted(find(results, "rk2_step", impl="baseline"), key=lambda r: r.n)
                        if r.counter("compressed") is not None)
            + "), steps on from there and resets to it, outside the timer, every "
              f"{context.get('rk2_window', '?')} RK2 steps or {context.get('implicit_window', '?')} implicit steps, "
              "so the timed steps sample the same stretch of motion however many iterations are run.", ""]
    if context.get("accuracy"):
        out += [context["accuracy"], ""]

    target_rows, realtime_note = targets(results, context)
    out += ["## Targets", "",
            "The per-step performance targets, checked against this run; [performance.md](performance.md) (\"The "
            "targets and what stops each\") says what stops each missed line. The target per simulated second, "
            "against the best peer, comes from `drape_sim_second` ([performance.md](performance.md), \"Per "
            "simulated second\"), not from this suite.", ""]
    share = machine.get("other_processes_cpu_share")
    load_before = float(machine.get("loadavg_before", "0").split()[0])
    if (share is not None and share > 0.1) or load_before >= 1.0:
        used = f"other processes used {abs(max(share, 0)) * 100:.0f}% of the machine's CPU time during this run, " if share is not None else ""
        out += [f"**Warning: the machine was busy: {used}load average {load_before:.1f} before the run and "
                + " / ".join(machine.get("loadavg_after", "? ? ?").split()[:3]) + " (1 / 5 / 15 min) after it. Wall times, "
                "and above all two-thread times, are inflated by the load: a thread of drape that is descheduled "
                "stalls the other at the next barrier. The single-thread CPU times in brackets do not count time "
                "spent descheduled and are the better estimate of an idle machine.**", ""]
    out += ["| target | goal | measured (median) | status |", "|---|---|---|---|"]
    out += target_rows
    out.append("")
    if realtime_note:
        out += [realtime_note, ""]
    if args.plot:
        out += ["![step time against nodes](images/bench_step_time.png)", ""]

    out += ["## Results by family", ""]
    for family in ("implicit_step", "linear_solve", "matvec", "jacobian_assembly", "rk2_step", "symplectic_step",
                   "force_assembly", "setup"):
        out += family_table(results, family, baseline_for)
    out += speedup_table(results)
    out += dispatch_section(results)
    out += environment_section(results)
    out += self_collision_section(results)

    out += ["## Cost growth", "",
            "The `exponent` column of each table is the least-squares slope of log(time) against "
            "log(nodes) over the measured sizes (time ~ nodes^k). Why each method grows as it does:", ""]
    for family in ("force_assembly", "rk2_step", "symplectic_step", "jacobian_assembly", "matvec", "linear_solve",
                   "implicit_step", "setup"):
        if by_method(results, family):
            out.append(f"- **{FAMILY_TEXT[family][0]}**: {GROWTH_WHY[family]}")
    out.append("")

    if ct:
        out += ["## Compile time", "",
                "Wall time to compile one translation unit (best of 3), measured by `scripts/bench.sh` with",
                "", f"    {ct['command']}", "", f"({ct['compiler']}"
                + (f"; 1-minute load average {ct['loadavg_1min_before']:.1f} when it started" if "loadavg_1min_before" in ct else "")
                + "):", "",
                "| translation unit | what it does | compile time |", "|---|---|---|"]
        what = {"include_only": "`#include <drape/drape.hpp>` and an empty `main`",
                "typical_use": "the umbrella header plus a cloth, an RK2 step, an implicit step (default options), diagnostics, OBJ export (double)"}
        for probe, t in ct["probes"].items():
            out.append(f"| `bench/compile_time/{probe}.cpp` | {what.get(probe, probe)} | {t:.2f} s |")
        out.append("")

    out += ["## Reproduce", "", "```sh", "scripts/bench.sh                      # build, run, regenerate this page",
            "DRAPE_BENCH_QUIET_WAIT=600 scripts/bench.sh   # first wait up to 10 min for an idle machine",
            "python3 scripts/bench_report.py --bench docs/data/bench.json --machine docs/data/machine.json \\",
            "  --compile-time docs/data/compile_time.json --markdown docs/benchmarks.md \\",
            "  --plot docs/images/bench_step_time.png --keep-plot   # this page again from the stored JSON",
            "build/bench/bench/drape_bench --benchmark_filter=rk2_step   # one family, console only",
            "build/bench/bench/drape_sim_second 33 65 129 257 --reference   # wall time per simulated second",
            "build/bench/bench/drape_memory 33 65 129 257                    # heap bytes per node",
            "build/bench/bench/drape_preconditioner_ab 33 1 41 60            # multigrid against multigrid-float",
            "build/bench/bench/drape_refinement                               # CG iterations against the grid size",
            "build/bench/bench/drape_amg_cost                                 # each preconditioner's set-up and solve (docs/amg.md)",
            "build/bench/bench/drape_mesh_step                                # disk meshes against grids (docs/mesh.md)",
            "build/bench/bench/drape_panel_meshing                            # garment panels meshed: time, angles (docs/panel_meshing.md)",
            "build/bench/bench/drape_usd_export 256 120 /tmp                 # the USD file against OBJ frames (docs/viewer.md)",
            "build/bench/bench/drape_body_contact 33 65 129                   # the body mesh's share of the shawl's step (docs/contact.md)",
            "build/bench/bench/drape_garment_cost 1 1.25 1.5 2                # what the T-shirt scene's time is spent on (docs/garments.md)",
            "```", "", "[performance.md](performance.md) explains the figures and gives the command behind each of its own.", ""]
    open(args.markdown, "w").write("\n".join(out))
    if args.plot and not args.keep_plot:
        write_plot(results, context, args.plot)


if __name__ == "__main__":
    main()
