"""CPU time per collision with and without the engine's spatial order, on one machine, in one process.

Two engines on the same spheres: one kept in the input order (``reorder=0``),
one sorted in Morton order at the build and every ``engine.REORDER_EVERY``
collisions per sphere (the default from ``engine.REORDER_FROM`` spheres).
Both are warmed up ``WARM`` collisions per sphere, then rounds alternate
them, ``C`` collisions each (the sorted engine's sorts inside its rounds).
``--shuffle`` puts the input in random order first: what a fluid's order
becomes after a long run (the spheres diffuse away from their lattice
neighbours) and what random placement or a user's file gives; without it
the input is ``random_arrays``' lattice, already in rows.

usage: reorder.py N PHI C ROUNDS [--warm W] [--shuffle] [--sphere]
"""

import argparse
import statistics
import time

import numpy as np

from hardspheres.core import engine as engine_module
from hardspheres.builders import random_arrays
from hardspheres.core.engine import Engine

ap = argparse.ArgumentParser()
ap.add_argument("n", type=int)
ap.add_argument("phi", type=float)
ap.add_argument("collisions", type=int)
ap.add_argument("rounds", type=int)
ap.add_argument("--warm", type=float, default=5.0)
ap.add_argument("--shuffle", action="store_true")
ap.add_argument("--sphere", action="store_true")
a = ap.parse_args()

volume = a.n * (4.0 / 3.0) * np.pi * 0.5**3 / a.phi
where = {"container": (volume * 3.0 / (4.0 * np.pi)) ** (1 / 3)} if a.sphere else {"box": volume ** (1 / 3)}
m, r, p, v = random_arrays(a.n, a.phi, seed=0, **where)
if a.shuffle:
    k = np.random.default_rng(1).permutation(a.n)
    m, r, p, v = m[k], r[k], p[k], v[k]
engines = {}
for name, every in (("input order", 0.0), ("sorted", engine_module.REORDER_EVERY)):
    c0 = time.process_time()
    engines[name] = Engine(m, r, p, v, reorder=every, **where)
    c1 = time.process_time()
    engines[name].advance(collisions=int(a.warm * a.n), record=False)
    print(f"{name}: build {c1 - c0:.2f} s CPU, warm-up {time.process_time() - c1:.2f} s CPU", flush=True)
sorted_eng = engines["sorted"]
c0 = time.process_time()
sorted_eng._reorder()
print(f"one sort: {(time.process_time() - c0) * 1e3:.1f} ms CPU", flush=True)
per = {name: [] for name in engines}
names = list(engines)
for rnd in range(a.rounds):
    for name in names if rnd % 2 == 0 else names[::-1]:
        c0 = time.process_time()
        engines[name].advance(collisions=a.collisions, record=False)
        per[name].append((time.process_time() - c0) / a.collisions * 1e6)
        print(f"round {rnd} {name}: {per[name][-1]:.3f} us CPU/collision", flush=True)
base = statistics.median(per["input order"])
for name in names:
    med = statistics.median(per[name])
    print(
        f"{name}: median {med:.3f} us/collision, spread {min(per[name]):.3f}-{max(per[name]):.3f}, "
        f"speed vs input order {base / med:.3f}"
    )
