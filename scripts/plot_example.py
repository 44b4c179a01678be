#!/usr/bin/python3
"""Plots the output of examples/hanging_cloth: the final mesh (two views) and the energy log.

usage: plot_example.py OUT_DIR_TWO_CORNERS OUT_DIR_ONE_CORNER IMAGE_PREFIX
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PolyCollection
import csv


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(tuple(float(p) for p in parts[1:4]))
            elif parts[0] == "f":
                faces.append(tuple(int(p) - 1 for p in parts[1:4]))
    return verts, faces


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def main():
    two, one, prefix = sys.argv[1], sys.argv[2], sys.argv[3]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    for ax, folder, title in ((axes[0], two, "two corners pinned"), (axes[1], one, "one corner pinned")):
        verts, faces = read_obj(f"{folder}/hanging_cloth.obj")
        # front view: x right, y up; painter's order by z so nearer triangles overdraw
        polys = sorted(faces, key=lambda t: -sum(verts[i][2] for i in t))
        coll = PolyCollection([[(verts[i][0], verts[i][1]) for i in t] for t in polys],
                              facecolors=[plt.cm.viridis(min(1, max(0, sum(verts[i][2] for i in t) / 9.6))) for t in polys],
                              edgecolors="k", linewidths=0.1)
        ax.add_collection(coll)
        xs = [v[0] for v in verts]
        ys = [v[1] for v in verts]
        ax.set_xlim(min(xs) - 0.2, max(xs) + 0.2)
        ax.set_ylim(min(ys) - 0.2, max(ys) + 0.2)
        ax.set_aspect("equal")
        ax.set_title(f"RK2, t = 3 s, {title}\n(front view, colour = depth z)", fontsize=9)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.tight_layout()
    fig.savefig(f"{prefix}_mesh.png", dpi=90)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for folder, style, title in ((two, "-", "two corners"), (one, "--", "one corner")):
        d = read_csv(f"{folder}/hanging_cloth_energy.csv")
        for key, colour in (("kinetic", "C0"), ("spring", "C1"), ("gravity", "C2"), ("total", "k")):
            ax.plot(d["time"], d[key], style, color=colour, label=f"{key} ({title})")
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title("Energy of the default scene with RK2 (dt = 0.5 ms): spring damping dissipates")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(f"{prefix}_energy.png", dpi=90)


if __name__ == "__main__":
    main()
