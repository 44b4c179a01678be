"""Throughput and scheduling overhead of drape.sweep on a LocalCluster (docs/sweeps.md).

    build/venv/bin/python python/examples/sweep_throughput.py --workers 1 2 --runs 40 --seconds 1

For each worker count: starts a LocalCluster (not timed), runs one warm-up sweep, then times
run_sweep() over --runs runs of scenes/one_corner.toml with RK2 (--nx x --nx nodes, --seconds
simulated each, no files but metrics.json). Prints runs per second and the overhead:
1 - (sum of the tasks' own times, measured inside them) / (sweep wall time x workers).
"""

import argparse
import json
import pathlib
import tempfile
import time

from distributed import Client

from drape.sweep import local_cluster, run_sweep

REPO = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per run")
    parser.add_argument("--nx", type=int, default=33)
    args = parser.parse_args()

    def spec(runs):
        return {"scene": str(REPO / "scenes" / "one_corner.toml"), "seconds": args.seconds,
                "flags": {"integrator": "rk2", "dt": 5e-4, "nx": args.nx, "ny": args.nx},
                # distinct runs: the bend stiffness differs by a part in a million
                "grid": {"bend-ks": [500.0 + 1e-3 * i for i in range(runs)]},
                "record": {"final_state": False}}

    base = None
    for workers in args.workers:
        cluster = local_cluster(workers)      # the cluster drape-sweep starts
        with Client(cluster) as client, tempfile.TemporaryDirectory() as tmp:
            run_sweep(spec(2 * workers), pathlib.Path(tmp) / "warm-up", client=client, progress=False)
            start = time.perf_counter()
            table = run_sweep(spec(args.runs), pathlib.Path(tmp) / "sweep", client=client,
                              progress=False)
            wall = time.perf_counter() - start
        cluster.close()
        rows = table.to_pylist()
        timing = json.loads(table.schema.metadata[b"drape.sweep.timing"])
        assert all(r["status"] == "ok" and r["ran_now"] for r in rows)
        task = sum(r["task_time"] for r in rows)
        stepping = sum(r["wall_time"] for r in rows)
        rate = len(rows) / wall
        base = base or rate
        print(f"workers {workers}: {len(rows)} runs in {wall:.2f} s = {rate:.2f} runs/s "
              f"(x{rate / base:.2f}); mean run: task {task / len(rows) * 1e3:.1f} ms, stepping "
              f"{stepping / len(rows) * 1e3:.1f} ms; overhead 1 - task sum / (wall x workers) = "
              f"{100 * (1 - task / (wall * workers)):.1f}%, of which validation {timing['validate']:.2f} s; "
              f"from first submission to last result: {timing['execute']:.2f} s, overhead "
              f"{100 * (1 - task / (timing['execute'] * workers)):.1f}%")


if __name__ == "__main__":
    main()
