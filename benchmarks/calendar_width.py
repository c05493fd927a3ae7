"""CPU time per collision against the event calendar's bucket width (engine.CAL_PER_BUCKET).

One fluid, warmed up, then rounds that alternate the widths (entries per
bucket) on the same engine: each width's calendar is made anew and times
C collisions.  usage: calendar_width.py N PHI C ROUNDS [--sphere] WIDTH...
"""

import statistics
import sys
import time

from hardspheres.core import engine as engine_module
from hardspheres.builders import random_spheres
from hardspheres.core.engine import Engine

args = sys.argv[1:]
sphere = "--sphere" in args
args = [a for a in args if a != "--sphere"]
n, phi, coll, rounds = int(args[0]), float(args[1]), int(args[2]), int(args[3])
widths = [float(w) for w in args[4:]]
edge = 10.0 * n ** (1 / 3)
if sphere:
    s = random_spheres(n, phi, container=edge / 2, seed=1)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, container=edge / 2)
else:
    s = random_spheres(n, phi, box=edge, seed=1)
    eng = Engine(s.masses, s.radii, s.positions, s.velocities, box=edge)
eng.advance(collisions=20 * n, record=False)  # into a fluid
per = {w: [] for w in widths}
for r in range(rounds):
    for w in widths if r % 2 == 0 else widths[::-1]:
        engine_module.CAL_PER_BUCKET = w
        eng._requeue()
        c0 = time.process_time()
        eng.advance(collisions=coll, record=False)
        per[w].append((time.process_time() - c0) / coll * 1e6)
for w in widths:
    v = per[w]
    print(
        f"per bucket {w:g}: median {statistics.median(v):.4f} us CPU/collision, "
        f"spread {min(v):.4f}-{max(v):.4f}"
    )
