"""Collisions per second in 2-D and 3-D, and in a rectangular box against the cube.

For each system (N particles, packing PHI): built by ``random_spheres``
(seed 0), warmed up 10 collisions per particle, then REPS chunks of C
collisions timed by CPU time; prints the median and the best chunk in
microseconds per collision and collisions per second.  Systems: spheres
in a cube at 0.3 and 0.45, spheres in a 1:1:2 box at 0.3 and 0.45, disks
in a sqrt(3)/2 box at 0.3 and 0.7.

usage: python3 benchmarks/dimensions.py [N] [REPS] [C]   (defaults 10000 5 200000)
"""

import statistics
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres.core.engine import Engine


def timed(state, container, reps, c):
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, container=container)
    eng.advance(collisions=10 * state.n, record=False)
    per = []
    for _ in range(reps):
        t = time.process_time()
        eng.advance(collisions=c, record=False)
        per.append((time.process_time() - t) / c * 1e6)
    return statistics.median(per), min(per)


def main():
    n, reps, c = (int(x) for x in (sys.argv[1:] + ["10000", "5", "200000"][len(sys.argv) - 1 :])[:3])
    rows = []
    for phi in (0.3, 0.45):
        cube = hs.PeriodicBox.for_packing(n, phi)
        rows.append(("spheres, cube", phi, cube))
        rows.append(("spheres, 1:1:2 box", phi, hs.PeriodicBox.for_packing(n, phi, (1, 1, 2))))
    for phi in (0.3, 0.7):
        side = np.sqrt(n * np.pi / (4 * phi) / (np.sqrt(3) / 2))
        rows.append(("disks, sqrt(3)/2 box", phi, hs.PeriodicBox((side, side * np.sqrt(3) / 2))))
    print(f"N = {n}, {reps} chunks of {c} collisions after 10 per particle; CPU time")
    print("| system | packing | us per collision (median; best) | collisions per second (median) |")
    print("|---|---|---|---|")
    for name, phi, box in rows:
        state = hs.random_spheres(n, phi, box, seed=0)
        med, best = timed(state, box, reps, c)
        print(f"| {name} | {phi} | {med:.3f}; {best:.3f} | {1e6 / med:.3g} |")


if __name__ == "__main__":
    main()
