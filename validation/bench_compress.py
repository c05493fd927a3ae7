"""Cost per collision of compression against a plain run at the same density.

    python validation/bench_compress.py [N] [RATE] [REPEATS]

Compresses N equal spheres (periodic box) from packing 0.45 to 0.50 and
then runs the same number of collisions plain (NVE) at 0.50, REPEATS times
(default 3, each from a fresh fluid, alternating compression and plain
run); prints CPU time (``time.process_time``, steadier than wall time on a
shared machine) per collision of each and their ratio, then the median
and range of the ratios.
"""

import statistics
import sys
import time

import hardspheres as hs

n = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
rate = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-3
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
box = (n * 4.0 / 3.0 * 3.141592653589793 / 0.45) ** (1.0 / 3.0)  # radius 1 at 0.45
ratios = []
for k in range(repeats):
    state = hs.random_spheres(n, 0.45, box=box, seed=1 + k)
    sim = hs.Simulation(state, hs.PeriodicBox(box))
    sim.run(collisions=5 * n)
    sim.compress(packing=0.451, rate=rate)  # compile the growth path
    c0 = sim.counters["collisions"]
    t0 = time.process_time()
    sim.compress(packing=0.50, rate=rate)
    t_c = time.process_time() - t0
    coll = sim.counters["collisions"] - c0
    t0 = time.process_time()
    sim.run(collisions=coll)
    t_p = time.process_time() - t0
    ratios.append(t_c / t_p)
    print(
        f"N={n} rate={rate} repeat {k + 1}: {coll} collisions; compression "
        f"{t_c / coll * 1e6:.2f} us/collision, plain at 0.50 {t_p / coll * 1e6:.2f} us/collision "
        f"(CPU); ratio {t_c / t_p:.2f}",
        flush=True,
    )
print(
    f"ratio median {statistics.median(ratios):.2f}, range {min(ratios):.2f}-{max(ratios):.2f} "
    f"over {repeats} repeats"
)
