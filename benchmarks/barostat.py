"""Cost of constant pressure: collisions per second with hardspheres.Barostat against NVE at the same state.

The fluid at beta P sigma^3 = 5 (Hansen-Goos's packing 0.3929 for NVE), N =
256 and 2048: NVE, then the barostat with 1, 4 and 16 volume moves per mean
free time (1 is the default), each after 20 collisions per sphere, timed
over 100 collisions per sphere (compilation excluded).  A move costs about
as much as N/2 collisions (the closest pair, then the cells, lists and
calendar made anew after an accepted move: O(N) each).

usage: python3 benchmarks/barostat.py [N ...]
"""

import sys
import time

import hardspheres as hs
from hardspheres.eos import packing_at_pressure


def rate(sim: hs.Simulation, n: int) -> float:
    sim.run(collisions=20 * n)
    c0 = sim.counters["collisions"]
    t = time.perf_counter()
    sim.run(collisions=100 * n)
    return (sim.counters["collisions"] - c0) / (time.perf_counter() - t)


def main() -> None:
    bp = 5.0
    phi = packing_at_pressure(bp)
    print("| N | NVE collisions/s | moves per free time | NPT collisions/s | NPT / NVE | acceptance |")
    print("|---|---|---|---|---|---|")
    for n in [int(x) for x in sys.argv[1:]] or [256, 2048]:
        box = hs.PeriodicBox.for_packing(n, phi)

        def make(n: int = n, box: hs.PeriodicBox = box) -> hs.Simulation:
            return hs.Simulation(hs.random_spheres(n, phi, box=box.length, seed=1), box)

        nve = rate(make(), n)
        for per in (1, 4, 16):
            sim = make()
            bar = hs.Barostat(pressure=bp, kT=1.0, seed=1)
            sim.set_barostat(bar)
            bar.attach(sim)
            bar.every /= per
            bar.next_time = sim.time + bar.every
            npt = rate(sim, n)
            ratio = npt / nve
            print(f"| {n} | {nve:.3g} | {per} | {npt:.3g} | {ratio:.2f} | {bar.acceptance:.2f} |", flush=True)


if __name__ == "__main__":
    main()
