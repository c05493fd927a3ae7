"""CPU time per collision against the cell width (periodic box), on one warmed-up engine.

Cells FACTOR times the minimum width (nc = cells per axis / FACTOR), rounds
alternating the factors.  usage: cell_width.py N PHI C ROUNDS FACTOR...
"""

import statistics
import sys
import time
import numpy as np
from hardspheres.core import _core as core
from hardspheres.builders import random_spheres
from hardspheres.core.engine import Engine

n, phi, coll, rounds = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
factors = [float(f) for f in sys.argv[5:]]
edge = 10.0 * n ** (1 / 3)
s = random_spheres(n, phi, box=edge, seed=1)
eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=edge)
eng.advance(collisions=20 * n, record=False)
nc0 = int(eng.counts[core.C_CELLS])
span = edge


def regrid(f):
    nc = max(3, int(nc0 / f))
    eng._rebase()
    eng.counts[core.C_CELLS] = nc
    eng.scalars[core.F_W] = span / nc
    eng.cell_head = np.full(nc**3, -1, np.int64)
    eng._build()
    return nc


per = {f: [] for f in factors}
for r in range(rounds):
    for f in factors if r % 2 == 0 else factors[::-1]:
        nc = regrid(f)
        c0 = time.process_time()
        x0 = eng.counters["crossings"]
        k0 = eng.counters["collisions"]
        eng.advance(collisions=coll, record=False)
        per[f].append((time.process_time() - c0) / coll * 1e6)
        cr = (eng.counters["crossings"] - x0) / (eng.counters["collisions"] - k0)
        print(f"round {r} factor {f} nc {nc}: {per[f][-1]:.3f} us/coll, crossings/coll {cr:.2f}", flush=True)
for f in factors:
    v = per[f]
    print(f"factor {f}: median {statistics.median(v):.4f} us CPU/collision, spread {min(v):.4f}-{max(v):.4f}")
