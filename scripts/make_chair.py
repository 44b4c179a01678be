#!/usr/bin/env python3
"""A chair as a triangle-mesh collider: a seat, four legs and a thin back rest, each a closed box.

Writes an OBJ (metres, y up, the seat's front towards +z, standing on y = 0) of five closed boxes
wound outward, which touch but do not overlap: the legs end at the underside of the seat, the back
rest stands on its top. The parts are thin (legs 3 cm square, back rest 2 cm thick) and every edge is
sharp, the cases a node's swept test against the triangles has to hold.

    scripts/make_chair.py scenes/objects/chair.obj
"""
import sys

SEAT_HALF = (0.22, 0.21)  # m, half width (x) and half depth (z)
SEAT_TOP, SEAT_THICKNESS = 0.46, 0.03
LEG = 0.03
BACK_THICKNESS, BACK_HEIGHT = 0.02, 0.44


def box(lo, hi):
    """Eight corners and six outward quads (counter-clockwise seen from outside)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    corners = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
               (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (3, 7, 6, 2), (0, 4, 7, 3), (1, 2, 6, 5)]
    return corners, faces


def chair():
    sx, sz = SEAT_HALF
    seat_bottom = SEAT_TOP - SEAT_THICKNESS
    parts = [box((-sx, seat_bottom, -sz), (sx, SEAT_TOP, sz))]
    for x in (-sx, sx - LEG):
        for z in (-sz, sz - LEG):
            parts.append(box((x, 0.0, z), (x + LEG, seat_bottom, z + LEG)))
    parts.append(box((-sx, SEAT_TOP, -sz), (sx, SEAT_TOP + BACK_HEIGHT, -sz + BACK_THICKNESS)))
    return parts


def main(target):
    lines = ["# A chair: seat, four legs and a back rest, closed boxes wound outward (scripts/make_chair.py)"]
    base = 1
    faces = []
    for corners, quads in chair():
        lines += ["v %.6f %.6f %.6f" % c for c in corners]
        faces += ["f " + " ".join(str(base + i) for i in q) for q in quads]
        base += len(corners)
    with open(target, "w") as out:
        out.write("\n".join(lines + faces) + "\n")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
