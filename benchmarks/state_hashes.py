"""Hashes of the engine's state after a run, for 16 systems: do two source trees give the same bits?

Spheres and disks, cells and neighbour lists, cube, 1:1:2 and sqrt(3)/2
boxes, sphere and circle, the simultaneity window, growth: each system is
run 20 collisions or reflections per sphere from a lattice start (seed
fixed), and the centres, velocities, virial, wall impulse, time and the
transport tallies are hashed.  Run it once per tree and compare the lines:

    PYTHONPATH=TREE_A/src python3 benchmarks/state_hashes.py > a.txt
    PYTHONPATH=TREE_B/src python3 benchmarks/state_hashes.py > b.txt
    diff a.txt b.txt

(Used for the true 2-D core, benchmarks/README.md "The 2-D core reads no z".)
"""

import hashlib

import numpy as np

from hardspheres.containers import CircularContainer, PeriodicBox, SphericalContainer
from hardspheres.core.engine import Engine


def lattice(n: int, d: int, L: float, rng: np.random.Generator) -> np.ndarray:
    k = int(np.ceil(n ** (1 / d)))
    g = np.stack(np.meshgrid(*[np.arange(k)] * d, indexing="ij"), -1).reshape(-1, d)[:n]
    return (g + 0.5) * (L / k) - L / 2


def system(
    d: int,
    n: int,
    phi: float,
    kind: str,
    seed: int,
    grow: float = 0.0,
    window: float = 0.0,
    aspect: tuple[float, ...] | None = None,
) -> Engine:
    rng = np.random.default_rng(seed)
    r = 0.5
    vol = n * (np.pi * r * r if d == 2 else 4 / 3 * np.pi * r**3) / phi
    if kind == "box":
        if aspect is None:
            L = vol ** (1 / d)
            sides = (L,) * d
        else:
            base = (vol / np.prod(aspect)) ** (1 / d)
            sides = tuple(a * base for a in aspect)
        cont = PeriodicBox(sides if (d == 2 or aspect is not None) else sides[0])
        k = int(np.ceil(n ** (1 / d)))
        g = np.stack(np.meshgrid(*[np.arange(k)] * d, indexing="ij"), -1).reshape(-1, d)[:n]
        x = (g + 0.5) * (np.array(sides) / k) - np.array(sides) / 2
    else:
        R = (vol / (np.pi if d == 2 else 4 / 3 * np.pi)) ** (1 / d)
        cont = CircularContainer(R) if d == 2 else SphericalContainer(R)
        L = 2 * R / np.sqrt(d) * 0.95
        x = lattice(n, d, L, rng)
    v = rng.normal(size=(n, d))
    e = Engine(np.ones(n), np.full(n, r * (0.9 if grow else 1.0)), x, v, cont, window=window)
    return e


cases = [
    (3, 500, 0.3, "box", 1),
    (3, 500, 0.45, "box", 2),
    (3, 2000, 0.5, "box", 3),
    (3, 300, 0.3, "sphere", 4),
    (3, 300, 0.45, "sphere", 5),
    (3, 400, 0.3, "box", 6, 0.0, 0.0, (1, 1, 2)),
    (3, 200, 0.3, "sphere", 7, 0.0, 1e-8),
    (2, 500, 0.3, "box", 11),
    (2, 2000, 0.7, "box", 12),
    (2, 300, 0.5, "sphere", 13),
    (2, 400, 0.6, "box", 14, 0.0, 0.0, (1, np.sqrt(3) / 2)),
    (2, 300, 0.3, "sphere", 15, 0.0, 1e-8),
]
for c in cases:
    e = system(*c)
    e.advance(events=20 * e.n)
    h = hashlib.sha256()
    for a in (
        e.positions_at(),
        e.velocities,
        np.array([e.virial, e.wall_impulse, e.time]),
        e.transport_tallies()["virial"],
        e.transport_tallies()["kinetic"],
    ):
        h.update(np.ascontiguousarray(a).tobytes())
    print(c[:5], h.hexdigest()[:16], e.counters["collisions"])
# growth
for d, kind in ((3, "box"), (3, "sphere"), (2, "box"), (2, "sphere")):
    e = system(d, 300, 0.3, kind, 21, grow=1.0)
    e.set_growth(0.01)
    e.advance(events=20 * e.n)
    h = hashlib.sha256()
    h.update(e.positions_at().tobytes())
    h.update(e.velocities.tobytes())
    print("grow", d, kind, h.hexdigest()[:16])
