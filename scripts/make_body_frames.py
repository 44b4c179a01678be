#!/usr/bin/env python3
"""Key frames of a body mesh with its arms lowered or raised, for an animated mesh collider.

Reads an OBJ body (the A-pose SMPL body of scenes/bodies/, y up, facing +z), turns each arm about
its shoulder in the body's frontal plane (about z) by `angle` degrees towards the body (a negative
angle raises the arms), and writes the result as an OBJ with the same vertices in the same order and the same faces. Vertices blend
from the torso into the arm over a band around the shoulder (a linear blend of the turn by a smooth
weight, as skinning does), so the surface stays connected and free of folds.

    scripts/make_body_frames.py scenes/bodies/f_smpl_average_A40.obj 20 scenes/bodies/f_smpl_arms_down20.obj
    scripts/make_body_frames.py scenes/bodies/f_smpl_average_A40.obj -20 scenes/bodies/f_smpl_arms_up20.obj
"""
import math
import sys


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def main(source, angle, target):
    lines = open(source).read().splitlines()
    out = []
    for line in lines:
        if not line.startswith("v "):
            if not line.startswith(("vn ", "vt ", "#")):  # normals and uvs would no longer fit
                out.append(line if not line.startswith("f ") else " ".join(
                    ["f"] + [t.split("/")[0] for t in line.split()[1:]]))
            continue
        x, y, z = (float(t) for t in line.split()[1:4])
        side = 1.0 if x > 0 else -1.0
        pivot_x, pivot_y = side * 0.17, 1.36  # the shoulder joint
        # 0 on the torso, 1 on the arm: by the distance out from the side of the chest; below the
        # armpits (y < 1.15) only far out, where the forearms and hands are and the hips are not.
        weight = smoothstep((abs(x) - 0.13) / 0.09)
        if y < 1.15:
            weight *= smoothstep((abs(x) - 0.28) / 0.05)
        turn = -side * math.radians(angle) * weight  # towards the body
        c, s = math.cos(turn), math.sin(turn)
        dx, dy = x - pivot_x, y - pivot_y
        out.append("v %.6f %.6f %.6f" % (pivot_x + c * dx - s * dy, pivot_y + s * dx + c * dy, z))
    with open(target, "w") as f:
        f.write("# %s with the arms turned %g degrees towards the body (scripts/make_body_frames.py)\n"
                % (source.split("/")[-1], angle))
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]), sys.argv[3])
