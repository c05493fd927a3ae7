"""Cost of constant pressure: collisions per second with hardspheres.Barostat against NVE at the same state.

The fluid at beta P sigma^3 = 5 (Hansen-Goos's packing 0.3929 for NVE), N =
256 and 2048: NVE, then the barostat with 1, 4 and 16 volume moves per mean
free time (1 is the default), each after 20 collisions per sphere, timed
over 100 collisions per sphere (compilation excluded), by the wall clock
and by this process's CPU time (less moved by other work on a shared
machine); the load average is printed before and after.  A move costs about
as much as N/2 collisions (the closest pair, then the cells, lists and
calendar made anew after an accepted move: O(N) each).

usage: python3 benchmarks/barostat.py [N ...] [--per K ...]
"""

import os
import sys
import time

import hardspheres as hs
from hardspheres.eos import packing_at_pressure


def rate(sim: hs.Simulation, n: int) -> tuple[float, float]:
    """Collisions per second over 100 per sphere: by the wall clock, by CPU time."""
    sim.run(collisions=20 * n)
    c0 = sim.counters["collisions"]
    t, c = time.perf_counter(), time.process_time()
    sim.run(collisions=100 * n)
    done = sim.counters["collisions"] - c0
    return done / (time.perf_counter() - t), done / (time.process_time() - c)


def main() -> None:
    bp = 5.0
    phi = packing_at_pressure(bp)
    args = sys.argv[1:]
    pers = [int(x) for x in args[args.index("--per") + 1 :]] if "--per" in args else [1, 4, 16]
    sizes = [int(x) for x in (args[: args.index("--per")] if "--per" in args else args)] or [256, 2048]
    print("load average before: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))
    print(
        "| N | NVE collisions/s | moves per free time | NPT collisions/s | NPT / NVE "
        "| NVE CPU collisions/s | NPT CPU collisions/s | NPT / NVE (CPU) | acceptance |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for n in sizes:
        box = hs.PeriodicBox.for_packing(n, phi)

        def make(n: int = n, box: hs.PeriodicBox = box) -> hs.Simulation:
            return hs.Simulation(hs.random_spheres(n, phi, box=box.length, seed=1), box)

        nve, nve_cpu = rate(make(), n)
        for per in pers:
            sim = make()
            bar = hs.Barostat(pressure=bp, kT=1.0, seed=1)
            sim.set_barostat(bar)
            bar.attach(sim)
            bar.every /= per
            bar.next_time = sim.time + bar.every
            npt, npt_cpu = rate(sim, n)
            print(
                f"| {n} | {nve:.3g} | {per} | {npt:.3g} | {npt / nve:.2f} | {nve_cpu:.3g} | {npt_cpu:.3g} "
                f"| {npt_cpu / nve_cpu:.2f} | {bar.acceptance:.2f} |",
                flush=True,
            )
    print("load average after: {:.2f} {:.2f} {:.2f}".format(*os.getloadavg()))


if __name__ == "__main__":
    main()
