#!/usr/bin/env python3
"""The Cusick scene's drape coefficient as its specimen's mesh is refined, with the specimen's ring
of vertices on the support's edge (the scene's own mesh) and without it (--ring-radius 0).

Runs drape-render once per edge length and mesh, writes the coefficients to a CSV file and plots
them (docs/cusick.md, "The simulated test under mesh refinement").

usage: cusick_refinement.py DRAPE_RENDER OUT_CSV OUT_PNG
"""
import csv
import os
import re
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "cusick.toml")
WITH_RING_MM = [17, 14, 12, 10, 8.5, 7, 6, 5, 4.2, 3.5, 3, 2.5, 2]
WITHOUT_RING_MM = [17, 14, 12, 10, 8.5, 7, 6, 5, 4.2, 3.5]


def drape_coefficient(render, edge_mm, flags):
    with tempfile.TemporaryDirectory() as out:
        run = subprocess.run(
            [render, "--scene", SCENE, "--edge-length", str(edge_mm / 1000), "--frame-time", "3", "--width", "16",
             "--height", "16", "--samples", "1", "--out", out] + flags,
            capture_output=True, text=True, check=True)
    found = re.search(r"drape coefficient ([-0-9.]+), (\d+) folds", run.stdout + run.stderr)
    if not found:
        sys.exit(f"drape-render printed no drape coefficient at {edge_mm} mm:\n{run.stdout}{run.stderr}")
    return float(found.group(1)), int(found.group(2))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    render, out_csv, out_png = sys.argv[1:]
    rows = []
    for mesh, edges, flags in (("with ring", WITH_RING_MM, []), ("without ring", WITHOUT_RING_MM, ["--ring-radius", "0"])):
        for edge in edges:
            dc, folds = drape_coefficient(render, edge, flags)
            print(f"{mesh:13s} {edge:5.1f} mm  DC {dc:.4f}  {folds} folds", flush=True)
            rows.append((mesh, edge, dc, folds))
    with open(out_csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mesh", "edge_mm", "drape_coefficient", "folds"])
        w.writerows(rows)

    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    for mesh, style in (("with ring", "o-"), ("without ring", "s--")):
        points = [(edge, dc) for m, edge, dc, _ in rows if m == mesh]
        ax.plot([p[0] for p in points], [p[1] for p in points], style, label=f"specimen {mesh}")
    ax.set_xscale("log")
    ax.invert_xaxis()
    ax.set_xticks([20, 14, 10, 7, 5, 3.5, 2.5, 2])
    ax.set_xticklabels(["20", "14", "10", "7", "5", "3.5", "2.5", "2"])
    ax.set_xlabel("specimen edge length (mm)")
    ax.set_ylabel("drape coefficient at 3 s")
    ax.set_title("scenes/cusick.toml under mesh refinement")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out_png)


if __name__ == "__main__":
    main()
