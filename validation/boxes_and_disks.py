"""Checks of box shape and of disks: prints a Markdown table and its running time.

1. Z of spheres in a 1:1:2 periodic box equals the cube's within error at
   packing 0.3 and 0.45 (N = 2000 each, 4x10^5 collisions after 2x10^4;
   error bars by blocking, hardspheres.observables), by the z-score of
   the difference.
2. A hexagonal crystal of 32 x 32 disks at area fraction 0.75 keeps its
   hexatic order after 100 collisions per disk: |Psi6| (hs.Hexatic), and a
   liquid at 0.5 for contrast.

usage: python3 validation/boxes_and_disks.py
"""

import math
import time

import hardspheres as hs
from hardspheres.builders import hexagonal


def z_of(box, phi, n=2000, seed=1):
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box.length, seed=seed), box)
    sim.run(collisions=20000)
    obs = sim.observables.reset()
    sim.run(collisions=400000)
    return obs.Z(), obs.error("Z")


def main():
    t0 = time.time()
    print("| check | packing | ours | against | z |")
    print("|---|---|---|---|---|")
    for phi in (0.3, 0.45):
        zc, ec = z_of(hs.PeriodicBox.for_packing(2000, phi), phi)
        zr, er = z_of(hs.PeriodicBox.for_packing(2000, phi, (1, 1, 2)), phi)
        z = (zr - zc) / math.hypot(ec, er)
        ours, cube = f"{zr:.4f} +- {er:.4f}", f"{zc:.4f} +- {ec:.4f}"
        print(f"| Z, 1:1:2 box vs cube (N = 2000) | {phi} | {ours} | {cube} | {z:+.2f} |")
    s, box = hexagonal((32, 32), 0.75, seed=1)
    sim = hs.Simulation(s, box)
    sim.run(collisions=100 * s.n)
    order = hs.Hexatic().compute(sim).order
    name = "\\|Psi6\\| of a hexagonal crystal, 100 collisions per disk (N = 1024)"
    print(f"| {name} | 0.75 | {order:.3f} | > 0.9 | |")
    liquid = hs.Simulation(hs.random_spheres(1024, 0.5, box, seed=2), box)
    liquid.run(collisions=100 * 1024)
    fluid = hs.Hexatic().compute(liquid).order
    print(f"| \\|Psi6\\| of the liquid, same box and length of run | 0.5 | {fluid:.3f} | | |")
    print(f"\nrunning time: {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
