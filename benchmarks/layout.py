"""One 128-byte row per sphere against the engine's separate arrays: CPU time per collision, one process.

An experiment on the memory layout (benchmarks/README.md, "Where the time
goes"): three engines on the same spheres, in the input order (no spatial
sorting), warmed up 10 collisions per sphere, then rounds alternating them,
C collisions each:

* ``plain``: the engine as it is (``spheres`` 64 B a row, ``due``, the cell
  links and ``images`` in arrays of their own);
* ``row``: ``spheres``, ``due``, the cell links and ``images`` as views into
  one 64-byte-aligned array of 128-byte rows, so that what a crossing
  touches of its sphere sits in two adjacent cache lines;
* ``control``: the same array types as ``row`` (numba compiles the core
  for non-contiguous views once more), each array in its own aligned
  128-byte rows: the cost of the views' type without the sharing.

All three process the same events (checked at the end).

usage: python3 benchmarks/layout.py N PHI C ROUNDS
"""

import argparse
import copy
import statistics
import time

import numpy as np

from hardspheres.core.bench import container_for, warm_up
from hardspheres.builders import random_arrays
from hardspheres.core.engine import Engine


def aligned(n):
    """An (n, 16) float64 array whose rows start on 64-byte boundaries."""
    raw = np.zeros(n * 16 + 8)
    off = (-raw.ctypes.data % 64) // 8
    return raw[off : off + n * 16].reshape(n, 16)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("n", type=int)
    p.add_argument("phi", type=float)
    p.add_argument("c", type=int)
    p.add_argument("rounds", type=int)
    a = p.parse_args()
    where = container_for(a.n, a.phi, box=True)
    plain = Engine(*random_arrays(a.n, a.phi, where, seed=0), container=where, reorder=0)
    warm_up(plain, 10)
    engines = {"plain": plain}
    for mode in ("row", "control"):
        e = copy.deepcopy(plain)
        rows = aligned(a.n)
        rows[:, :8] = e.spheres
        e.spheres = rows[:, :8]
        if mode == "row":
            ints = rows.view(np.int64)
            rows[:, 8:10] = e.due
            e.due = rows[:, 8:10]
            ints[:, 10], ints[:, 11], ints[:, 12:15] = e.cell_next, e.cell_prev, e._images
            e.cell_next, e.cell_prev, e._images = ints[:, 10], ints[:, 11], ints[:, 12:15]
        else:
            due = aligned(a.n)
            nxt, prv, img = (aligned(a.n).view(np.int64) for _ in range(3))
            due[:, :2], nxt[:, 0], prv[:, 0], img[:, :3] = e.due, e.cell_next, e.cell_prev, e._images
            e.due, e.cell_next, e.cell_prev, e._images = due[:, :2], nxt[:, 0], prv[:, 0], img[:, :3]
        engines[mode] = e
    for name, e in engines.items():
        t = time.process_time()
        e.advance(collisions=2000, record=False)  # (compiles the core for the views' type once)
        print(f"{name}: first call {time.process_time() - t:.1f} s CPU", flush=True)
    names = list(engines)
    per = {name: [] for name in names}
    for r in range(a.rounds):
        for name in names if r % 2 == 0 else names[::-1]:
            t = time.process_time()
            engines[name].advance(collisions=a.c, record=False)
            per[name].append((time.process_time() - t) / a.c * 1e6)
    for name, e in engines.items():
        assert np.array_equal(e.spheres, plain.spheres), name
    base = min(per["plain"])
    for name in names:
        print(
            f"{name}: min {min(per[name]):.3f} us/collision, median {statistics.median(per[name]):.3f}, "
            f"speed vs plain by min {base / min(per[name]):.3f}"
        )


if __name__ == "__main__":
    main()
