"""Parameter sweeps of drape-render scene files on Dask distributed (docs/sweeps.md).

A sweep is a scene file plus a small TOML spec naming what varies (drape-render flag names
without the dashes), how long to simulate and what to record. Every run is one Dask task; each
run writes its folder ``runs/<run id>/`` completely or not at all, and the sweep writes one
Parquet table of per-run metrics. Restarting a sweep runs only the runs that have no folder.

    from drape.sweep import run_sweep
    table = run_sweep("python/examples/stiffness_sweep.toml", "out/stiffness", workers=2)

or ``drape-sweep SPEC --out DIR [--workers N] [--scheduler ADDR] [--no-progress]``.
Needs dask, distributed, pyarrow and tqdm, the extra ``sweep`` (``pip install ".[sweep]"``);
without them run_sweep raises MissingDependencyError and drape-sweep exits with status 2, before
either creates anything.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import copy
import hashlib
import importlib
import itertools
import json
import math
import os
import pathlib
import random as _random
import shutil
import sys
import time
import tomllib
import uuid

__all__ = ["SweepSpecError", "MissingDependencyError", "Sweep", "load_spec", "run_sweep", "local_cluster",
           "check_dependencies", "main", "METRICS", "DEPENDENCIES"]

#: The packages a sweep needs besides drape: pyproject.toml's extra ``sweep``.
DEPENDENCIES = ("dask", "distributed", "pyarrow", "tqdm")

#: Per-run metrics, in the table's column order. Energies are summed over the scene's cloths,
#: max_strain and lowest_y are over all of them.
METRICS = (
    "sim_time",        # simulated time at the end of the run, s
    "steps",           # steps taken
    "wall_time",       # wall-clock seconds of the stepping (scene.run), measured in the task
    "setup_time",      # wall-clock seconds of parsing the scene and building it, in the task
    "task_time",       # wall-clock seconds of the whole task (setup, run, writing files)
    "kinetic_energy",
    "spring_energy",
    "gravity_energy",
    "total_energy",
    "max_strain",
    "lowest_y",        # the lowest node's y, m
)

_TOP_KEYS = {"scene", "seconds", "flags", "grid", "random", "record", "retries"}
_RECORD_KEYS = {"metrics", "final_state", "frames"}
_RANDOM_SETTINGS = {"samples", "seed"}
_RANDOM_PARAM_KEYS = {"range", "log"}
# drape-render flags a sweep sets itself or that make no sense in a task.
_RESERVED_FLAGS = {"scene", "out", "save-state", "obj", "usd", "video", "realtime", "realtime-factor",
                   "frames", "duration", "help"}


class SweepSpecError(ValueError):
    """A sweep spec that cannot run; the message names the key."""


class MissingDependencyError(ImportError):
    """A package of DEPENDENCIES cannot be imported; the message names it and the install command."""


def check_dependencies():
    """Raises MissingDependencyError naming every package of DEPENDENCIES that cannot be imported."""
    missing = []
    for name in DEPENDENCIES:
        try:
            importlib.import_module(name)
        except ModuleNotFoundError as error:
            if error.name is None or error.name.split(".")[0] != name:
                missing.append(f"{name} ({error})")     # installed, but something it imports is not
            else:
                missing.append(name)
        except ImportError as error:                    # installed but broken, e.g. built for another numpy
            missing.append(f"{name} ({error})")
    if missing:
        raise MissingDependencyError(
            f"a sweep needs {', '.join(DEPENDENCIES[:-1])} and {DEPENDENCIES[-1]}, which a plain "
            f"`pip install .` leaves out; missing: {', '.join(missing)}. Install them with "
            f"`pip install \".[sweep]\"` in drape's source folder (or `pip install {' '.join(DEPENDENCIES)}`).")


# --------------------------------------------------------------------------------------------
# The spec


def _flag_args(key, value):
    """drape-render command-line arguments for one key = value of the spec."""
    if isinstance(value, bool):
        return [f"--{key}"] if value else []
    if isinstance(value, (list, tuple)):
        return [f"--{key}", *(_scalar(v) for v in value)]
    return [f"--{key}", _scalar(value)]


def _scalar(value):
    if isinstance(value, float):
        return repr(value)          # shortest text that reads back as the same double
    return str(value)


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Sweep:
    """A validated sweep spec: the scene, the runs' parameters and flags, what to record.

    ``runs`` is a list of dicts: ``index``, ``run_id``, ``params`` (the varied keys' values),
    ``flags`` (all drape-render flags of the run)."""

    def __init__(self, spec, base_dir="."):
        if not isinstance(spec, dict):
            raise SweepSpecError("a sweep spec is a TOML table (dict)")
        spec = copy.deepcopy(spec)
        unknown = sorted(set(spec) - _TOP_KEYS)
        if unknown:
            raise SweepSpecError(f"unknown key(s) in the sweep spec: {', '.join(unknown)}; "
                                 f"allowed: {', '.join(sorted(_TOP_KEYS))}")
        if "scene" not in spec:
            raise SweepSpecError("key 'scene' is missing: the drape-render scene file to sweep")
        if not isinstance(spec["scene"], str):
            raise SweepSpecError("key 'scene' must be a path (string)")
        scene = pathlib.Path(spec["scene"])
        if not scene.is_absolute():
            scene = pathlib.Path(base_dir) / scene
        self.scene = scene.resolve()
        if not self.scene.is_file():
            raise SweepSpecError(f"key 'scene': no such file {self.scene}")
        self.scene_text = self.scene.read_text()

        self.seconds = spec.get("seconds")
        if self.seconds is not None and (not _is_number(self.seconds) or not self.seconds > 0
                                         or not math.isfinite(self.seconds)):
            raise SweepSpecError(f"key 'seconds' = {self.seconds!r} must be a number > 0")
        self.retries = spec.get("retries", 1)
        if not isinstance(self.retries, int) or isinstance(self.retries, bool) or self.retries < 0:
            raise SweepSpecError(f"key 'retries' = {self.retries!r} must be an integer >= 0")

        self.fixed = spec.get("flags", {})
        if not isinstance(self.fixed, dict):
            raise SweepSpecError("key 'flags' must be a table of drape-render flags")
        for key, value in self.fixed.items():
            self._check_flag_key(f"flags.{key}", key)
            if isinstance(value, dict):
                raise SweepSpecError(f"key 'flags.{key}': a value, not a table")

        record = spec.get("record", {})
        if not isinstance(record, dict):
            raise SweepSpecError("key 'record' must be a table")
        unknown = sorted(set(record) - _RECORD_KEYS)
        if unknown:
            raise SweepSpecError(f"unknown key(s) in [record]: {', '.join(unknown)}; "
                                 f"allowed: {', '.join(sorted(_RECORD_KEYS))}")
        self.metrics = record.get("metrics", list(METRICS))
        if not isinstance(self.metrics, list) or not self.metrics:
            raise SweepSpecError("key 'record.metrics' must be a non-empty list of metric names")
        bad = [m for m in self.metrics if m not in METRICS]
        if bad:
            raise SweepSpecError(f"key 'record.metrics': unknown metric(s) {', '.join(map(str, bad))}; "
                                 f"known: {', '.join(METRICS)}")
        self.metrics = [m for m in METRICS if m in self.metrics]
        for key in ("final_state", "frames"):
            if not isinstance(record.get(key, False), bool):
                raise SweepSpecError(f"key 'record.{key}' must be true or false")
        self.final_state = record.get("final_state", True)
        self.frames = record.get("frames", False)

        grid = self._grid(spec.get("grid", {}))
        samples = self._random(spec.get("random"))
        overlap = set(grid) & set(samples[0] if samples else {})
        if overlap:
            raise SweepSpecError(f"key(s) {', '.join(sorted(overlap))} in both [grid] and [random]")
        both = set(self.fixed) & (set(grid) | set(samples[0] if samples else {}))
        if both:
            raise SweepSpecError(f"key(s) {', '.join(sorted(both))} both fixed in [flags] and varied")
        self.varied = list(grid) + list(samples[0] if samples else {})

        grid_points = [dict(zip(grid, values)) for values in itertools.product(*grid.values())]
        params = [{**g, **s} for g in grid_points for s in (samples or [{}])]
        scene_hash = hashlib.sha256(self.scene_text.encode()).hexdigest()
        fixed_args = [a for key, value in self.fixed.items() for a in _flag_args(key, value)]
        if "threads" not in self.fixed:
            fixed_args += ["--threads", "1"]      # one core per run: Dask runs one task per core
        self.runs = []
        for index, p in enumerate(params):
            flags = fixed_args + [a for key, value in p.items() for a in _flag_args(key, value)]
            digest = hashlib.sha256(json.dumps(
                {"flags": flags, "seconds": self.seconds, "scene": scene_hash}, sort_keys=True).encode())
            self.runs.append({"index": index, "run_id": f"r{index:04d}-{digest.hexdigest()[:10]}",
                              "params": p, "flags": flags})
        self.spec = spec

    @staticmethod
    def _check_flag_key(where, key):
        if not isinstance(key, str) or not key or key.startswith("-"):
            raise SweepSpecError(f"key '{where}': flag names are written without dashes")
        if key in _RESERVED_FLAGS:
            raise SweepSpecError(f"key '{where}': --{key} is set by the sweep itself and cannot be given")

    def _grid(self, grid):
        if not isinstance(grid, dict):
            raise SweepSpecError("key 'grid' must be a table of lists")
        for key, values in grid.items():
            self._check_flag_key(f"grid.{key}", key)
            if not isinstance(values, list):
                raise SweepSpecError(f"key 'grid.{key}' must be a list of values")
            if not values:
                raise SweepSpecError(f"key 'grid.{key}' is an empty list")
        return grid

    def _random(self, table):
        if table is None:
            return []
        if not isinstance(table, dict):
            raise SweepSpecError("key 'random' must be a table")
        samples = table.get("samples")
        if samples is None:
            raise SweepSpecError("key 'random.samples' is missing: the number of random runs")
        if not isinstance(samples, int) or isinstance(samples, bool) or samples < 1:
            raise SweepSpecError(f"key 'random.samples' = {samples!r} must be an integer >= 1")
        seed = table.get("seed", 0)
        if not isinstance(seed, int) or isinstance(seed, bool):
            raise SweepSpecError(f"key 'random.seed' = {seed!r} must be an integer")
        ranges = {}
        for key, value in table.items():
            if key in _RANDOM_SETTINGS and not isinstance(value, (list, dict)):
                continue
            where = f"random.{key}"
            self._check_flag_key(where, key)
            log = False
            if isinstance(value, dict):
                unknown = sorted(set(value) - _RANDOM_PARAM_KEYS)
                if unknown:
                    raise SweepSpecError(f"unknown key(s) in '{where}': {', '.join(unknown)}; "
                                         f"allowed: log, range")
                log = value.get("log", False)
                if not isinstance(log, bool):
                    raise SweepSpecError(f"key '{where}.log' must be true or false")
                if "range" not in value:
                    raise SweepSpecError(f"key '{where}.range' is missing: [lo, hi]")
                value = value["range"]
            if not isinstance(value, list):
                raise SweepSpecError(f"key '{where}' must be a range [lo, hi] or "
                                     f"{{ range = [lo, hi], log = true }}")
            if not value:
                raise SweepSpecError(f"key '{where}' is an empty range; give [lo, hi]")
            if len(value) != 2 or not all(_is_number(v) and math.isfinite(v) for v in value):
                raise SweepSpecError(f"key '{where}' = {value!r} must be two finite numbers [lo, hi]")
            lo, hi = value
            if lo > hi:
                raise SweepSpecError(f"key '{where}': lo = {lo!r} > hi = {hi!r}")
            if log and lo <= 0:
                raise SweepSpecError(f"key '{where}': log = true needs lo > 0 (lo = {lo!r})")
            ranges[key] = (lo, hi, log, isinstance(lo, int) and isinstance(hi, int))
        if not ranges:
            raise SweepSpecError("key 'random' has no ranges: give e.g. structural-ks = [1000, 50000]")
        rng = _random.Random(seed)
        out = []
        for _ in range(samples):
            point = {}
            for key, (lo, hi, log, integer) in ranges.items():
                if log:
                    v = math.exp(rng.uniform(math.log(lo), math.log(hi)))
                    v = min(max(round(v), lo), hi) if integer else v
                else:
                    v = rng.randint(lo, hi) if integer else rng.uniform(lo, hi)
                point[key] = v
            out.append(point)
        return out

    def validate_runs(self):
        """Passes every run's flags through drape.load_scene and builds its scene (no stepping),
        so a value the library rejects fails before any run starts."""
        import drape

        cache = {}
        for run in self.runs:
            key = tuple(run["flags"])
            if key in cache:
                continue
            try:
                scene_file = drape.load_scene(str(self.scene), run["flags"])
                scene_file.make_scene()
            except (drape.SceneFileError, drape.InvalidParameter, ValueError) as error:
                message = str(error).splitlines()[0] if str(error) else type(error).__name__
                named = [k for k in run["params"] if f"--{k}" in str(error)]
                named_fixed = [k for k in self.fixed if f"--{k}" in str(error)]
                if named:
                    where = ", ".join(f"'{'grid' if k in self.spec.get('grid', {}) else 'random'}.{k}' "
                                      f"= {run['params'][k]!r}" for k in named)
                elif named_fixed:
                    where = ", ".join(f"'flags.{k}'" for k in named_fixed)
                else:
                    where = "run parameters " + json.dumps(run["params"])
                raise SweepSpecError(f"key {where} (run {run['run_id']}): {type(error).__name__}: "
                                     f"{message}") from error
            cache[key] = True


def load_spec(spec_or_path):
    """A Sweep from a TOML file path or a dict (a dict's relative scene path is relative to the
    current folder, a file's to the file's folder)."""
    if isinstance(spec_or_path, Sweep):
        return spec_or_path
    if isinstance(spec_or_path, dict):
        return Sweep(spec_or_path, ".")
    path = pathlib.Path(spec_or_path)
    try:
        with open(path, "rb") as f:
            spec = tomllib.load(f)
    except OSError as error:
        raise SweepSpecError(f"cannot read the sweep spec {path}: {error}") from error
    except tomllib.TOMLDecodeError as error:
        raise SweepSpecError(f"{path}: not TOML: {error}") from error
    return Sweep(spec, path.parent)


# --------------------------------------------------------------------------------------------
# One run (executed on a Dask worker)

# Every run of a worker process steps and renders on this one thread: OSMesa's context is current
# on the thread that made it, and Dask's executor thread is not guaranteed to stay the same.
_RUN_THREAD = None


def _run_task(task):
    """The Dask task: runs one sweep run and writes its folder atomically. Returns its record."""
    global _RUN_THREAD
    if _RUN_THREAD is None:
        _RUN_THREAD = concurrent.futures.ThreadPoolExecutor(1, thread_name_prefix="drape-sweep-run")
    return _RUN_THREAD.submit(_run_in_folder, task).result()


def _run_in_folder(task):
    started = time.perf_counter()
    runs = pathlib.Path(task["runs_dir"])
    final = runs / task["run_id"]
    if (final / "metrics.json").is_file():          # another attempt finished it
        return json.loads((final / "metrics.json").read_text())
    tmp = runs / f".tmp-{task['run_id']}-{os.getpid()}-{uuid.uuid4().hex[:8]}"
    tmp.mkdir(parents=True)
    try:
        (tmp / "run.json").write_text(json.dumps(
            {"run_id": task["run_id"], "index": task["index"], "params": task["params"],
             "flags": task["flags"], "scene": task["scene"], "seconds": task["seconds"]}, indent=2))
        record = {"run_id": task["run_id"], "status": "ok", "error_type": None, "error": None}
        try:
            record.update(_simulate(task, tmp))
        except Exception as error:            # a failed run is recorded; the sweep goes on
            record.update(status="failed", error_type=type(error).__name__,
                          error=str(error).splitlines()[0] if str(error) else "")
        record["task_time"] = time.perf_counter() - started
        record["worker_pid"] = os.getpid()
        # The completion marker, written last (atomically: temp file + rename).
        (tmp / "metrics.json.tmp").write_text(json.dumps(record, indent=2))
        os.replace(tmp / "metrics.json.tmp", tmp / "metrics.json")
        try:
            os.rename(tmp, final)
        except OSError:
            if (final / "metrics.json").is_file():   # a duplicate attempt won the race
                shutil.rmtree(tmp, ignore_errors=True)
                return json.loads((final / "metrics.json").read_text())
            raise
        return record
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def _simulate(task, folder):
    import drape

    t0 = time.perf_counter()
    scene_file = drape.load_scene(task["scene"], task["flags"])
    scene = scene_file.make_scene()
    seconds = task["seconds"] if task["seconds"] is not None else scene_file.seconds
    t1 = time.perf_counter()
    callback = None
    if task["frames"]:
        (folder / "frames").mkdir()
        renderer = scene_file.renderer(scene)
        frame_time = scene_file.frame_time

        def callback(s):
            renderer.render(str(folder / "frames" / f"frame_{round(s.time / frame_time):05d}.png"))

        renderer.render(str(folder / "frames" / "frame_00000.png"))
    steps = scene.run(seconds, callback, frame_time=scene_file.frame_time)
    t2 = time.perf_counter()
    out = {"sim_time": scene.time, "steps": steps, "wall_time": t2 - t1, "setup_time": t1 - t0}
    energies = {"kinetic_energy": 0.0, "spring_energy": 0.0, "gravity_energy": 0.0, "total_energy": 0.0}
    strain, lowest = -math.inf, math.inf
    count = scene.cloth_count
    for k in range(count):
        cloth, state = scene.cloth(k), scene.state(k)
        for name in energies:
            energies[name] += getattr(cloth, name)(state)
        strain = max(strain, cloth.max_strain(state))
        lowest = min(lowest, float(state.positions[:, 1].min()))
        if task["final_state"]:
            suffix = "" if count == 1 else f"_{k}"
            drape.save_state(str(folder / f"final{suffix}.state"), state)
            drape.write_obj(str(folder / f"final{suffix}.obj"), state.positions, cloth.triangles)
    out.update(energies, max_strain=strain, lowest_y=lowest)
    return out


# --------------------------------------------------------------------------------------------
# The sweep


def _completed(runs_dir, run_id):
    path = runs_dir / run_id / "metrics.json"
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def _write_table(path, rows, sweep, timing=None):
    import pyarrow as pa
    import pyarrow.parquet as pq

    columns = ["run_id", "index", *sweep.varied, "status", "error_type", "error", "ran_now",
               "folder", *sweep.metrics]
    data = {}
    for c in columns:
        values = [row.get(c) for row in rows]
        if c in sweep.varied and any(isinstance(v, float) for v in values) and \
                all(_is_number(v) for v in values):
            values = [float(v) for v in values]
        elif c in sweep.varied and not all(_is_number(v) for v in values):
            values = [json.dumps(v) if isinstance(v, (list, dict)) else str(v) for v in values]
        if c in sweep.metrics and c != "steps":
            values = [None if v is None else float(v) for v in values]
        if c in ("run_id", "status", "error_type", "error", "folder"):
            values = pa.array(values, type=pa.string())
        data[c] = values
    table = pa.table(data)
    table = table.replace_schema_metadata({"drape.sweep.spec": json.dumps(sweep.spec, default=str),
                                           "drape.sweep.scene": str(sweep.scene),
                                           "drape.sweep.timing": json.dumps(timing or {})})
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    pq.write_table(table, tmp)
    os.replace(tmp, path)
    return table


def run_sweep(spec_or_path, out_dir, workers=None, scheduler_address=None, progress=True,
              retry_failed=False, on_result=None, client=None):
    """Runs a sweep on Dask distributed and returns its per-run metrics as a pyarrow Table
    (also written to ``out_dir/results.parquet``).

    workers: worker processes of the LocalCluster started when no scheduler is given
    (default: the machine's cores; one thread each, drape on one thread per run).
    scheduler_address: an existing Dask scheduler ("tcp://host:8786") instead of a LocalCluster.
    client: an existing distributed.Client (instead of either).
    progress: a tqdm progress bar on stderr.
    retry_failed: runs recorded as failed are run again (otherwise a restart skips them).
    on_result: called as on_result(record, client) after each finished run (client side).

    The check of DEPENDENCIES (MissingDependencyError) and validation (SweepSpecError) happen
    before anything is written. Runs whose folder is complete are skipped; the column ``ran_now``
    tells which runs this call executed.
    """
    check_dependencies()
    t0 = time.perf_counter()
    sweep = load_spec(spec_or_path)
    sweep.validate_runs()
    timing = {"validate": time.perf_counter() - t0}

    out = pathlib.Path(out_dir).resolve()
    runs_dir = out / "runs"
    runs_dir.mkdir(parents=True, exist_ok=True)
    for leftover in runs_dir.glob(".tmp-*"):        # from a killed worker of an earlier sweep
        shutil.rmtree(leftover, ignore_errors=True)

    rows, todo = {}, []
    for run in sweep.runs:
        base = {"run_id": run["run_id"], "index": run["index"], **run["params"],
                "folder": str(pathlib.Path("runs") / run["run_id"]), "ran_now": False}
        done = _completed(runs_dir, run["run_id"])
        if done is not None and (done.get("status") == "ok" or not retry_failed):
            rows[run["run_id"]] = {**base, **done, **base}
            continue
        if done is not None:
            shutil.rmtree(runs_dir / run["run_id"], ignore_errors=True)
        rows[run["run_id"]] = {**base, "status": "not run", "folder": None}
        todo.append(run)

    try:
        if todo:
            _execute(sweep, todo, runs_dir, rows, workers, scheduler_address, progress, on_result,
                     client, timing)
    except BaseException:
        # Interrupted: the table says which runs are done ("not run" for the others), for a look
        # before the restart. Temporary folders stay: a run on an external cluster may still write.
        _write_table(out / "results.parquet", [rows[run["run_id"]] for run in sweep.runs], sweep)
        raise
    for leftover in runs_dir.glob(".tmp-*"):        # attempts interrupted by a dead worker
        shutil.rmtree(leftover, ignore_errors=True)
    ordered = [rows[run["run_id"]] for run in sweep.runs]
    return _write_table(out / "results.parquet", ordered, sweep, timing)


def local_cluster(workers=None):
    """The LocalCluster run_sweep starts: `workers` processes (default: cores), one thread each,
    no dashboard. Each worker is given up to 2 runs at a time (worker-saturation 2), so that the
    next run is already there when one finishes instead of a scheduler round trip later."""
    import logging

    import dask
    from distributed import LocalCluster

    with dask.config.set({"distributed.scheduler.worker-saturation": 2.0}):
        return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                            processes=True, dashboard_address=None, silence_logs=logging.ERROR)


def _execute(sweep, todo, runs_dir, rows, workers, scheduler_address, progress, on_result, client,
             timing):
    from distributed import Client, as_completed
    from tqdm import tqdm

    cluster = None
    own_client = client is None
    if client is None:
        if scheduler_address:
            client = Client(scheduler_address)
        else:
            cluster = local_cluster(workers)
            client = Client(cluster)
    try:
        started = time.perf_counter()
        futures = {}
        for run in todo:
            task = {"run_id": run["run_id"], "index": run["index"], "params": run["params"],
                    "flags": run["flags"], "scene": str(sweep.scene), "seconds": sweep.seconds,
                    "runs_dir": str(runs_dir), "final_state": sweep.final_state,
                    "frames": sweep.frames}
            future = client.submit(_run_task, task, key=f"drape-run-{run['run_id']}-{uuid.uuid4().hex[:6]}",
                                   pure=False, retries=sweep.retries)
            futures[future] = run
        bar = tqdm(total=len(todo), unit="run", disable=not progress, desc="drape-sweep")
        try:
            for future in as_completed(list(futures)):
                run = futures[future]
                row = rows[run["run_id"]]
                try:
                    record = future.result()
                    row.update(record)
                    row["folder"] = str(pathlib.Path("runs") / run["run_id"])
                except Exception as error:      # the task itself failed: e.g. its workers died
                    row.update(status="failed", error_type=type(error).__name__,
                               error=str(error).splitlines()[0] if str(error) else "", folder=None)
                row["ran_now"] = True
                bar.update(1)
                if on_result is not None:
                    on_result(dict(row), client)
            # From the first submission to the last result: what the runs cost on the cluster.
            timing["execute"] = time.perf_counter() - started
        except BaseException:
            # Interrupted (Ctrl-C, on_result raised): queued runs are cancelled; a run already
            # executing finishes its folder or leaves only a temporary folder, removed next time.
            client.cancel(list(futures))
            raise
        finally:
            bar.close()
    finally:
        if own_client:
            client.close()
        if cluster is not None:
            cluster.close()


# --------------------------------------------------------------------------------------------
# Command line


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="drape-sweep", description="Run a parameter sweep of a drape-render scene file on "
        "Dask distributed (docs/sweeps.md). Exit code 0 when every run succeeded.")
    parser.add_argument("spec", help="the sweep spec (TOML)")
    parser.add_argument("--out", required=True, help="output folder (runs/, results.parquet)")
    parser.add_argument("--workers", type=int, default=None,
                        help="worker processes of the local cluster (default: cores)")
    parser.add_argument("--scheduler", default=None,
                        help="address of an existing Dask scheduler instead of a local cluster")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--retry-failed", action="store_true",
                        help="run again the runs recorded as failed by an earlier attempt")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be >= 1")
    try:
        table = run_sweep(args.spec, args.out, workers=args.workers, scheduler_address=args.scheduler,
                          progress=not args.no_progress, retry_failed=args.retry_failed)
    except (SweepSpecError, MissingDependencyError) as error:
        print(f"drape-sweep: {error}", file=sys.stderr)
        return 2
    rows = table.to_pylist()
    failed = [r for r in rows if r["status"] != "ok"]
    ran = sum(1 for r in rows if r["ran_now"])
    print(f"drape-sweep: {len(rows)} runs, {ran} run now, {len(rows) - ran} already done, "
          f"{len(failed)} failed; table {pathlib.Path(args.out) / 'results.parquet'}", file=sys.stderr)
    for r in failed[:20]:
        print(f"  {r['run_id']}: {r['status']}: {r['error_type']}: {r['error']}", file=sys.stderr)
    if len(failed) > 20:
        print(f"  ... and {len(failed) - 20} more", file=sys.stderr)
    return 0 if not failed else 1


if __name__ == "__main__":
    sys.exit(main())
