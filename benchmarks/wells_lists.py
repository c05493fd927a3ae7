"""Events per CPU second of a dense square-well fluid, neighbour lists against cells.

1372 spheres from an FCC lattice at rho = 0.8 (sigma = 1), a square well
lambda = 1.5, eps = 1, velocities at kT = 1.5; 20 events per sphere of
warm-up, then three chunks of 200000 events, CPU seconds.  ``cells`` forces
the cells (the lists' packing threshold set above 1).

usage: python3 benchmarks/wells_lists.py lists|cells
"""

import sys
import time

import numpy as np

from hardspheres.containers import PeriodicBox
from hardspheres.core import _core as core
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine


def main() -> None:
    mode = sys.argv[1]
    if mode == "cells":
        engine_module.LISTS_FROM = 2.0
    rng = np.random.default_rng(1)
    k = 7
    a = (4 / 0.8) ** (1 / 3)
    side = k * a
    base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    cells = [np.array([i, j, m]) for i in range(k) for j in range(k) for m in range(k)]
    x = np.array([(c + b) * a for c in cells for b in base]) - side / 2
    n = len(x)
    v = rng.normal(0, np.sqrt(1.5), (n, 3))
    e = Engine(np.ones(n), np.full(n, 0.5), x, v, container=PeriodicBox(side), steps=[(1.5, -1.0)])
    e.advance(events=20 * n)
    for _ in range(3):
        t0 = time.process_time()
        e.advance(events=200000)
        dt = time.process_time() - t0
        print(f"{mode}: shell factor {e.scalars[core.F_SHELL]:g}, {200000 / dt:.3g} events per CPU second")


if __name__ == "__main__":
    main()
