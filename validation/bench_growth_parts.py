"""Where the growth path's extra cost per collision goes (a diagnostic).

    python validation/bench_growth_parts.py [N] [REPEATS]

N equal spheres at packing 0.50 (periodic box, radius 1); CPU time per
collision of 400 000 collisions each: plain (no growth); growth switched
on at a negligible rate (1e-12: the core's growth branch, with the room
to grow the engine picks for that rate, ``Engine._headroom``, 0.2%); the
same with a fixed 5% room (what the engine used before it picked one);
and plain with a velocity rescale every 32 000 collisions (what
``compress`` adds).  Cells per side in brackets.
"""

import math
import sys
import time

import hardspheres as hs
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine

n = int(sys.argv[1]) if len(sys.argv) > 1 else 4000
repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 2
C = 400_000
box = (n * 4 / 3 * math.pi / 0.50) ** (1 / 3)
sim = hs.Simulation(hs.random_spheres(n, 0.50, box=box, seed=3), hs.PeriodicBox(box))
sim.run(collisions=10 * n)
eng = sim._engine


def cpu(f):
    t0 = time.process_time()
    f()
    return (time.process_time() - t0) / C * 1e6


def chunked():
    for _ in range(C // 32000):
        eng.advance(collisions=32000, record=False)
        eng.rescale_velocities(1.0)


original = Engine._regrid


def five_percent(self):
    self._grid(self.n, 1.05 if self.scalars[core.F_GROW] else 1.0)
    self._build()


rows: dict[str, list[str]] = {}
for _ in range(repeats):
    for name, growth, patch, work in [
        ("plain", 0.0, False, lambda: eng.advance(collisions=C, record=False)),
        ("growth on, room from the rate", 1e-12, False, lambda: eng.advance(collisions=C, record=False)),
        ("growth on, 5% room (before)", 1e-12, True, lambda: eng.advance(collisions=C, record=False)),
        ("plain + rescale every 32000", 0.0, False, chunked),
    ]:
        Engine._regrid = five_percent if patch else original
        eng.set_growth(growth)
        us = cpu(work)
        rows.setdefault(name, []).append(f"{us:.2f} ({int(eng.counts[core.C_CELLS])})")
    Engine._regrid = original
eng.set_growth(0.0)
for name, vals in rows.items():
    print(f"{name:32s} us/collision (cells per side): {', '.join(vals)}")
