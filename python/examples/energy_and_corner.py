"""Runs drape's default scene (the course model's 33 x 33 cloth, two corners pinned, RK2) and plots
its energies and the trajectory of the free corner (32, 32) into a PNG.

    python python/examples/energy_and_corner.py [--seconds 3] [--out energy_and_corner.png] [--threads 1]
"""

import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import drape  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=3.0, help="simulated seconds (default 3)")
    parser.add_argument("--out", default="energy_and_corner.png", help="the PNG to write")
    # RK2 gives the same bits for any thread count; at 33 x 33 a step is short enough that a second
    # thread gains little and stalls at every barrier when the machine is busy.
    parser.add_argument("--threads", type=int, default=1, help="threads of the simulation, 0 = all (default 1)")
    args = parser.parse_args()

    cloth = drape.Cloth(drape.ClothSpec())  # the default scene
    rk2 = drape.Rk2(cloth, threads=args.threads)  # the default dt, 0.5 ms
    state = cloth.initial_state()
    corner = cloth.node(cloth.nx - 1, cloth.ny - 1)

    rows = []  # time, kinetic, spring, gravity, corner x, y, z

    def record(s):
        rows.append((s.time, cloth.kinetic_energy(s), cloth.spring_energy(s), cloth.gravity_energy(s),
                     *s.positions[corner]))

    record(state)
    rk2.run(state, args.seconds, record, frame_time=0.01)  # a row every 10 ms of simulated time
    t, kinetic, spring, gravity, x, y, z = np.array(rows).T

    figure, (energy_axes, corner_axes) = plt.subplots(1, 2, figsize=(11, 4.2))
    energy_axes.plot(t, kinetic, label="kinetic")
    energy_axes.plot(t, spring, label="spring")
    energy_axes.plot(t, gravity, label="gravity")
    energy_axes.plot(t, kinetic + spring + gravity, "k", label="total")
    energy_axes.set(xlabel="t (s)", ylabel="energy (J)", title="Energies")
    energy_axes.legend()
    corner_axes.plot(x, y, lw=1)
    corner_axes.plot(x[0], y[0], "go", label="start")
    corner_axes.plot(x[-1], y[-1], "ro", label=f"t = {t[-1]:.2f} s")
    corner_axes.set(xlabel="x (m)", ylabel="y (m)", title=f"Free corner (node {corner}), seen along z")
    corner_axes.set_aspect("equal", adjustable="datalim")
    corner_axes.legend()
    figure.tight_layout()
    figure.savefig(args.out, dpi=110)
    print(f"{args.out}: {len(rows)} rows, total energy {rows[0][1] + rows[0][2] + rows[0][3]:.3f} J -> "
          f"{kinetic[-1] + spring[-1] + gravity[-1]:.3f} J")


if __name__ == "__main__":
    main()
