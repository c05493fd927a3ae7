"""A rectangular 1:1:2 box against the cube: CPU time per collision, the two interleaved.

For each packing (0.3: cells, 0.45: neighbour lists), N spheres built by
``random_spheres`` (seed 0) in the cube and in a 1:1:2 box of the same
volume, each warmed up 10 collisions per sphere; then ROUNDS rounds, each
timing one chunk of 2x10^5 collisions in each box (the order reversed every
other round, so that a drift of the machine's load falls on both alike).
Prints the median and the best chunk of each and their ratio (box speed /
cube speed).

usage: python3 benchmarks/box_ab.py N ROUNDS   (e.g. 100000 12)
"""

import statistics
import sys
import time

import hardspheres as hs
from hardspheres.core.engine import Engine

CHUNK = 200_000


def main() -> None:
    n, rounds = int(sys.argv[1]), int(sys.argv[2])
    for phi in (0.3, 0.45):
        engines = {}
        for name, aspect in (("cube", None), ("1:1:2", (1, 1, 2))):
            if aspect is None:
                box = hs.PeriodicBox.for_packing(n, phi)
            else:
                box = hs.PeriodicBox.for_packing(n, phi, aspect)
            s = hs.random_spheres(n, phi, box, seed=0)
            e = Engine(s.masses, s.radii, s.positions, s.velocities, container=box)
            e.advance(collisions=10 * n, record=False)
            engines[name] = e
        per: dict[str, list[float]] = {k: [] for k in engines}
        for r in range(rounds):
            order = list(engines) if r % 2 == 0 else list(engines)[::-1]
            for k in order:
                t = time.process_time()
                engines[k].advance(collisions=CHUNK, record=False)
                per[k].append((time.process_time() - t) / CHUNK * 1e6)
        med = {k: statistics.median(v) for k, v in per.items()}
        best = {k: min(v) for k, v in per.items()}
        print(
            f"N = {n}, packing {phi}: cube {med['cube']:.3f} (best {best['cube']:.3f}) us/collision, "
            f"1:1:2 {med['1:1:2']:.3f} (best {best['1:1:2']:.3f}); speed 1:1:2/cube "
            f"{med['cube'] / med['1:1:2']:.3f} by median, {best['cube'] / best['1:1:2']:.3f} by best"
        )


if __name__ == "__main__":
    main()
