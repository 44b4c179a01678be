"""drape.sweep: parameter sweeps on Dask distributed (docs/sweeps.md).

Tiny cloths and short runs; one 2-worker LocalCluster is shared by most tests (test_twelve_runs
starts its own through run_sweep). Nothing sleeps for a fixed time: conditions are polled with
timeouts."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import time
import tomllib

import pytest

pytest.importorskip("distributed")
pytest.importorskip("pyarrow")
pytest.importorskip("tqdm")

import pyarrow.parquet as pq  # noqa: E402
from conftest import REPO  # noqa: E402

from drape import sweep as ds  # noqa: E402

SCENE = """
integrator = "rk2"
dt = 0.0005
nx = 9
ny = 9
boundary = 1
duration = 1.0
"""


@pytest.fixture(scope="module")
def client():
    from distributed import Client

    cluster = ds.local_cluster(2)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    return path


def spec(scene, **extra):
    s = {"scene": str(scene), "seconds": 0.2,
         "grid": {"structural-ks": [5000.0, 10000.0, 20000.0], "shear-ks": [1000.0, 5000.0]},
         "random": {"samples": 2, "seed": 3, "bend-ks": {"range": [10.0, 1000.0], "log": True}}}
    s.update(extra)
    return s


def check_complete(out, table, n):
    rows = table.to_pylist()
    assert len(rows) == n
    assert sorted(r["index"] for r in rows) == list(range(n))
    runs = out / "runs"
    assert not [p.name for p in runs.iterdir() if p.name.startswith(".")], "temporary folders left"
    assert sorted(p.name for p in runs.iterdir()) == sorted(r["run_id"] for r in rows)
    for r in rows:
        folder = runs / r["run_id"]
        metrics = json.loads((folder / "metrics.json").read_text())
        assert metrics["status"] == r["status"]
        if r["status"] == "ok":
            assert (folder / "final.state").stat().st_size > 0
            assert (folder / "final.obj").stat().st_size > 0
        assert json.loads((folder / "run.json").read_text())["run_id"] == r["run_id"]
    on_disk = pq.read_table(out / "results.parquet")
    assert on_disk.to_pylist() == rows
    return rows


def wait_idle(client, runs=None, timeout=60):
    """Waits until the scheduler has no task and, if `runs` is given, no run is still being written
    there (a `.tmp-*` folder): a cancelled task already running goes on in its worker thread after
    the scheduler has let go of it."""
    end = time.monotonic() + timeout

    def busy():
        writing = runs is not None and runs.is_dir() and any(p.name.startswith(".tmp-") for p in runs.iterdir())
        return writing or any(client.processing().values())

    while busy():
        assert time.monotonic() < end, "the cluster did not become idle"
        time.sleep(0.05)


def test_twelve_runs_on_a_two_worker_local_cluster(scene, tmp_path):
    out = tmp_path / "out"
    table = ds.run_sweep(spec(scene), out, workers=2, progress=False)
    rows = check_complete(out, table, 12)
    assert all(r["status"] == "ok" and r["ran_now"] for r in rows)
    for r in rows:
        assert r["sim_time"] == pytest.approx(0.2)
        assert r["steps"] == 400
        assert r["max_strain"] > 0 and r["wall_time"] > 0
        assert r["lowest_y"] < 0
    # The cartesian product crossed with 2 log-uniform samples, reproducible from the seed.
    assert {(r["structural-ks"], r["shear-ks"]) for r in rows} == \
        {(a, b) for a in (5000.0, 10000.0, 20000.0) for b in (1000.0, 5000.0)}
    bends = sorted({r["bend-ks"] for r in rows})
    assert len(bends) == 2 and all(10 <= b <= 1000 for b in bends)
    assert [r["run_id"] for r in ds.load_spec(spec(scene)).runs] == [r["run_id"] for r in rows]


def test_a_killed_worker_still_gives_a_complete_table(scene, tmp_path, client):
    # Runs of ~0.1 s so that a worker is busy when it is killed.
    s = spec(scene, seconds=1.0, flags={"nx": 33, "ny": 33})
    killed = []

    def kill_a_busy_worker(record, c):
        if killed:
            return
        busy = [addr for addr, keys in c.processing().items() if keys]
        if not busy:
            return
        pid = c.run(os.getpid, workers=[busy[0]])[busy[0]]
        os.kill(pid, signal.SIGKILL)
        killed.append(pid)

    out = tmp_path / "out"
    table = ds.run_sweep(s, out, client=client, progress=False, on_result=kill_a_busy_worker)
    assert killed, "no worker was busy after a run completed"
    rows = check_complete(out, table, 12)
    assert all(r["status"] == "ok" for r in rows), [(r["run_id"], r["error"]) for r in rows]
    # The nanny restarted the worker.
    end = time.monotonic() + 60
    while len(client.scheduler_info()["workers"]) < 2:
        assert time.monotonic() < end, "the killed worker was not restarted"
        time.sleep(0.1)


def test_restart_runs_only_missing_runs(scene, tmp_path, client):
    out = tmp_path / "out"
    first = ds.run_sweep(spec(scene), out, client=client, progress=False).to_pylist()
    assert sum(r["ran_now"] for r in first) == 12
    mtimes = {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()}

    # A finished sweep: nothing runs, the table is the same.
    again = ds.run_sweep(spec(scene), out, client=client, progress=False).to_pylist()
    assert sum(r["ran_now"] for r in again) == 0
    assert {p.name: p.stat().st_mtime_ns for p in (out / "runs").iterdir()} == mtimes
    strip = lambda rows: [{k: v for k, v in r.items() if k != "ran_now"} for r in rows]  # noqa: E731
    assert strip(again) == strip(first)

    # Three run folders lost: only those run.
    import shutil

    lost = {first[i]["run_id"] for i in (1, 5, 10)}
    for run_id in lost:
        shutil.rmtree(out / "runs" / run_id)
    third = ds.run_sweep(spec(scene), out, client=client, progress=False)
    assert {r["run_id"] for r in third.to_pylist() if r["ran_now"]} == lost
    check_complete(out, third, 12)


def test_an_interrupted_sweep_resumes(scene, tmp_path, client):
    out = tmp_path / "out"
    seen = []

    class Stop(Exception):
        pass

    def stop_after_four(record, c):
        seen.append(record["run_id"])
        if len(seen) == 4:
            raise Stop

    slow = spec(scene, seconds=1.0, flags={"nx": 33, "ny": 33})     # ~0.1 s a run
    with pytest.raises(Stop):
        ds.run_sweep(slow, out, client=client, progress=False, on_result=stop_after_four)
    partial = pq.read_table(out / "results.parquet").to_pylist()
    assert {r["run_id"] for r in partial if r["status"] == "ok"} == set(seen)
    assert sum(r["status"] == "not run" for r in partial) == 8
    wait_idle(client, out / "runs")  # runs already started when it stopped may still finish
    done_before = {p.name for p in (out / "runs").iterdir() if (p / "metrics.json").is_file()}
    assert set(seen) <= done_before and len(done_before) < 12
    table = ds.run_sweep(slow, out, client=client, progress=False)
    rows = check_complete(out, table, 12)
    ran = {r["run_id"] for r in rows if r["ran_now"]}
    assert ran.isdisjoint(done_before) and ran | done_before == {r["run_id"] for r in rows}


@pytest.mark.parametrize("change, key", [
    ({"colour": "red"}, "colour"),
    ({"grid": {"structural-ks": []}}, "grid.structural-ks"),
    ({"random": {"samples": 3, "bend-ks": []}}, "random.bend-ks"),
    ({"random": {"samples": 3, "bend-ks": [100.0, 10.0]}}, "random.bend-ks"),
    ({"random": {"samples": 3, "bend-ks": {"range": [0.0, 10.0], "log": True}}}, "random.bend-ks"),
    ({"random": {"samples": 0, "bend-ks": [1.0, 10.0]}}, "random.samples"),
    ({"grid": {"structural-ks": [1000.0, -5.0]}}, "structural-ks"),
    ({"grid": {"no-such-flag": [1, 2]}}, "no-such-flag"),
    ({"flags": {"shear-ks": -1.0}}, "flags.shear-ks"),
    ({"flags": {"out": "x"}}, "flags.out"),
    ({"record": {"metrics": ["colour"]}}, "record.metrics"),
    ({"seconds": -1}, "seconds"),
])
def test_bad_specs_fail_before_any_run(scene, tmp_path, change, key):
    s = {"scene": str(scene), "seconds": 0.2, "grid": {"structural-ks": [1000.0]}}
    s.update(change)
    out = tmp_path / "out"
    with pytest.raises(ds.SweepSpecError, match=key):
        ds.run_sweep(s, out, workers=1, progress=False)
    assert not out.exists()


def test_bad_spec_from_the_command_line(scene, tmp_path, capsys):
    spec_file = tmp_path / "spec.toml"
    spec_file.write_text(f'scene = "{scene.name}"\n[grid]\nbend-ks = [100.0, -1.0]\n')
    assert ds.main([str(spec_file), "--out", str(tmp_path / "out"), "--no-progress"]) == 2
    assert "bend-ks" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_diverging_run_is_recorded_and_the_others_complete(scene, tmp_path, client, capsys):
    spec_file = tmp_path / "spec.toml"
    spec_file.write_text(f"""
scene = "{scene.name}"
seconds = 0.5
[flags]
frame-time = 0.02
[grid]
dt = [0.0005, 0.005, 0.00025]
""")
    out = tmp_path / "out"
    code = ds.main([str(spec_file), "--out", str(out), "--scheduler", client.scheduler.address,
                    "--no-progress"])
    assert code == 1
    assert "1 failed" in capsys.readouterr().err
    rows = check_complete(out, pq.read_table(out / "results.parquet"), 3)
    assert [r["status"] for r in rows] == ["ok", "failed", "ok"]
    assert rows[1]["error_type"] == "SimulationError" and "diverged" in rows[1]["error"]
    assert rows[1]["max_strain"] is None and rows[0]["sim_time"] == pytest.approx(0.5)
    # A restart does not run the failed run again, unless asked.
    again = ds.run_sweep(spec_file, out, client=client, progress=False)
    assert sum(again.column("ran_now").to_pylist()) == 0
    retried = ds.run_sweep(spec_file, out, client=client, progress=False, retry_failed=True)
    assert retried.column("ran_now").to_pylist() == [False, True, False]


def test_frames(scene, tmp_path, client):
    s = {"scene": str(scene), "seconds": 0.1, "grid": {"bend-ks": [100.0]},
         "flags": {"width": 64, "height": 48, "samples": 1, "frame-time": 0.05},
         "record": {"frames": True, "final_state": False, "metrics": ["sim_time", "max_strain"]}}
    out = tmp_path / "out"
    table = ds.run_sweep(s, out, client=client, progress=False)
    row = table.to_pylist()[0]
    assert row["status"] == "ok", row["error"]
    assert "wall_time" not in table.column_names
    frames = sorted(p.name for p in (out / "runs" / row["run_id"] / "frames").iterdir())
    assert frames == ["frame_00000.png", "frame_00001.png", "frame_00002.png"]
    assert not (out / "runs" / row["run_id"] / "final.state").exists()


# drape-sweep's entry point (pyproject.toml's [project.scripts]) in a Python where `hidden`
# cannot be imported, as after a `pip install .` without the extra `sweep`.
WITHOUT_PACKAGES = """
import sys

class Uninstalled:
    hidden = set(sys.argv.pop(1).split(","))

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in self.hidden:
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None

sys.meta_path.insert(0, Uninstalled())
from drape.sweep import main
sys.exit(main())
"""


def test_missing_optional_packages_are_named_before_anything_is_created(scene, tmp_path):
    spec_file = tmp_path / "spec.toml"
    spec_file.write_text(f'scene = "{scene.name}"\nseconds = 0.1\n[grid]\nbend-ks = [100.0]\n')
    out = tmp_path / "out"
    result = subprocess.run(
        [sys.executable, "-c", WITHOUT_PACKAGES, "distributed,pyarrow", str(spec_file), "--out", str(out),
         "--no-progress"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr, result.stderr
    assert "missing: distributed, pyarrow." in result.stderr, result.stderr
    assert 'pip install ".[sweep]"' in result.stderr
    assert not out.exists()
    # The packages checked are the extra's.
    with open(REPO / "pyproject.toml", "rb") as f:
        extra = tomllib.load(f)["project"]["optional-dependencies"]["sweep"]
    assert set(ds.DEPENDENCIES) == set(extra)
