"""Cost per collision of compression against a plain run at the same density.

    python validation/bench_compress.py [N] [RATE]

Compresses N equal spheres (periodic box) from packing 0.45 to 0.50 and
then runs the same number of collisions plain (NVE) at 0.50; prints the
collisions per second of each and their ratio.
"""
import sys
import time

import hardspheres as hs

n = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
rate = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-3
box = (n * 4.0 / 3.0 * 3.141592653589793 / 0.45) ** (1.0 / 3.0)  # radius 1 at 0.45
state = hs.random_spheres(n, 0.45, box=box, seed=1)
sim = hs.Simulation(state, hs.PeriodicBox(box))
sim.run(collisions=5 * n)
sim.compress(packing=0.451, rate=rate)  # compile the growth path
t0 = time.perf_counter()
c0 = sim.counters["collisions"]
res = sim.compress(packing=0.50, rate=rate)
t_c = time.perf_counter() - t0
coll = sim.counters["collisions"] - c0
t0 = time.perf_counter()
sim.run(collisions=coll)
t_p = time.perf_counter() - t0
print(f"N={n} rate={rate}: compression 0.45->0.50 {coll} collisions, "
      f"{coll / t_c / 1e6:.3f} M coll/s; plain at 0.50 {coll / t_p / 1e6:.3f} M coll/s; "
      f"cost ratio {t_c / t_p:.2f}")
