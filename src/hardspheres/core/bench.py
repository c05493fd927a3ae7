"""The benchmark: collisions per second of the compiled core on an equilibrated fluid.

``hardspheres bench`` generates N spheres on a lattice
(:func:`hardspheres.builders.random_arrays`), warms them up into a fluid, then
times a number of collisions.  The warm-up matters: a lattice fresh from the
builder does not collide like a fluid (its collision rate starts up to 1.6x
the fluid's at PHI = 0.45 and takes 10-15 collisions per sphere to come down;
spheres at the contact spacing rattle at 10^7 times the fluid's rate and never
cross a cell), so a benchmark that times it measures something else at every
N.  The warm-up therefore runs in blocks until both the collision rate per
sphere and the cell-crossing rate per sphere stop changing
(:func:`settled`), and the output reports both, for the warm-up's blocks and
for the timed window.

Example:
    >>> res = bench(500, 0.3, 2000, seed=1, warmup=2)
    >>> res["warmup_per_sphere"], res["collisions"], res["outside"]
    (2.0, 2000, 0)
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..builders import random_arrays
from ..containers import CircularContainer, PeriodicBox, SphericalContainer
from ..eos import carnahan_starling, collision_rate_from_z
from ..errors import ArgumentError
from .engine import Engine

if TYPE_CHECKING:
    from ..containers import Container

#: Warm-up block: this many collisions per sphere, and at least :data:`BLOCK_MIN` collisions.
BLOCK_PER_SPHERE = 2.0

#: Fewest collisions in a warm-up block (small systems: the rates' noise stays below 0.5%).
BLOCK_MIN = 100_000

#: Settled: consecutive blocks' rates differ by less than this, relative ...
SETTLE_TOL = 0.01

#: ... or by less than this many standard deviations of their counting noise.
SETTLE_SIGMAS = 3.0

#: Settled only after this many agreeing pairs of blocks in a row.
SETTLE_PAIRS = 2

#: The warm-up gives up (``settled`` false) after this many collisions per sphere ...
WARMUP_MAX = 100.0

#: ... or this many blocks, whichever is more (small systems).
WARMUP_MAX_BLOCKS = 10


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far [MB] (POSIX: ``resource``; Windows has none)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def enskog_rate(packing: float) -> float:
    """Collisions per sphere per unit time of the equal-sphere fluid, Enskog with Carnahan-Starling.

    ``24 phi g(sigma) / sigma * sqrt(kT / (pi m))`` with ``g = (1 - phi/2) /
    (1 - phi)^3`` (Chapman & Cowling, *The Mathematical Theory of Non-uniform
    Gases*, 3rd ed. 1970, ch. 16: the collision frequency ``4 n sigma^2 g
    sqrt(pi kT / m)``), in the benchmark's units (sigma = 1, m = 1, kT = 1).

    Example:
        >>> round(enskog_rate(0.3), 3)
        10.067
    """
    return collision_rate_from_z(float(carnahan_starling(packing)))


def _rates(eng: Engine, c0: dict[str, int], t0: float, n: int) -> tuple[float, float, dict[str, int]]:
    """Collision and crossing rates per sphere per unit time since counters ``c0`` at ``t0``."""
    c1, dt = eng.counters, eng.time - t0
    if dt <= 0.0:
        return math.inf, math.inf, c1
    return (
        float(2.0 * (c1["collisions"] - c0["collisions"]) / (n * dt)),
        float((c1["crossings"] - c0["crossings"]) / (n * dt)),
        c1,
    )


def settled(prev: Sequence[float], last: Sequence[float], counts: Sequence[int]) -> bool:
    """True when two blocks' rates agree: within :data:`SETTLE_TOL` or their noise.

    Args:
        prev, last: ``(collision rate, crossing rate)`` of two consecutive blocks.
        counts: ``(collisions, crossings)`` in the last block (the noise of a
            rate measured from ``k`` events is about ``1/sqrt(k)`` relative).

    Example:
        >>> settled((10.0, 2.3), (10.05, 2.31), (200000, 40000))
        True
        >>> settled((12.0, 2.3), (10.05, 2.31), (200000, 40000))
        False
    """
    for a, b, k in zip(prev, last, counts):
        if a == b:
            continue
        tol = max(SETTLE_TOL, SETTLE_SIGMAS * math.sqrt(2.0 / max(k, 1)))
        if not abs(b - a) <= tol * max(abs(a), abs(b)):
            return False
    return True


def warm_up(eng: Engine, per_sphere: float | None = None) -> tuple[list[tuple[float, float, float]], bool]:
    """Run ``eng`` into a fluid, in blocks; say how each block's rates came out.

    Args:
        eng: the :class:`~hardspheres.core.engine.Engine`, fresh from the lattice.
        per_sphere: collisions per sphere to run (in blocks, as the
            criterion's), or ``None``: until :func:`settled` holds for
            :data:`SETTLE_PAIRS` pairs of consecutive blocks in a row, at most
            :data:`WARMUP_MAX` per sphere or :data:`WARMUP_MAX_BLOCKS` blocks.

    Returns:
        ``(blocks, settled)``: ``blocks`` a list of ``(collisions per sphere
        so far, collision rate, crossing rate)``, rates per sphere per unit
        time over each block; ``settled`` whether the criterion held (also
        when told ``per_sphere``, for the record).
    """
    n = eng.n
    block = max(int(BLOCK_PER_SPHERE * n), BLOCK_MIN)
    total = None if per_sphere is None else int(round(per_sphere * n))
    limit = max(int(WARMUP_MAX * n), WARMUP_MAX_BLOCKS * block) if total is None else total
    blocks, done, agree, ok = [], 0, 0, False
    c0, t0 = eng.counters, eng.time
    while done < limit:
        step = min(block, limit - done)
        eng.advance(collisions=step, record=False)
        done += step
        coll, cross, c1 = _rates(eng, c0, t0, n)
        blocks.append((done / n, coll, cross))
        if len(blocks) >= 2:
            counts = (c1["collisions"] - c0["collisions"], c1["crossings"] - c0["crossings"])
            agree = agree + 1 if settled(blocks[-2][1:], blocks[-1][1:], counts) else 0
            ok = agree >= SETTLE_PAIRS
        c0, t0 = c1, eng.time
        if total is None and ok:
            break
    return blocks, ok


def container_for(n: int, packing: float, box: bool = False, dimensions: int = 3) -> Container:
    """The container (or periodic box) that holds ``n`` spheres of radius 0.5 at ``packing``.

    The benchmarks' one sizing rule, so that every script times the same
    systems as ``hardspheres bench``.  ``dimensions = 2``: disks of radius
    0.5 in a circle, or (``box``) in a periodic square.

    Example:
        >>> round(container_for(1000, 0.3, box=True).length, 4)
        12.04
        >>> container_for(1000, 0.3, box=True, dimensions=2).sides
        (51.166335397324424, 51.166335397324424)
    """
    if dimensions == 2:
        if box:
            side = math.sqrt(n * np.pi * 0.25 / packing)
            return PeriodicBox((side, side))
        return CircularContainer(0.5 * math.sqrt(n / packing))
    if dimensions != 3:
        raise ArgumentError(f"dimensions must be 2 or 3, got {dimensions!r}")
    if box:
        return PeriodicBox((n * (4.0 / 3.0) * np.pi * 0.125 / packing) ** (1.0 / 3.0))
    return SphericalContainer(0.5 * (n / packing) ** (1.0 / 3.0))


def bench(
    n: int,
    packing: float,
    collisions: int,
    seed: int = 0,
    radius_ratio: float = 1.0,
    mass_ratio: float = 1.0,
    box: bool = False,
    warmup: float | None = None,
    dimensions: int = 3,
) -> dict[str, Any]:
    """Generate ``n`` spheres, warm them up into a fluid, time ``collisions`` more.

    Longer than 80 lines with this docstring (under 70 of code).

    The container (or box) is sized so that the largest sphere has radius
    of order 1 (equal spheres: radius 0.5, mass 1, kT = 1).

    Args:
        warmup: collisions per sphere before the clock starts, or ``None``
            (default): until the collision and crossing rates settle
            (:func:`warm_up`).
        dimensions: 3, or 2: disks (:func:`container_for`; no Enskog rate).

    Returns:
        A dict of figures (see ``hardspheres bench --help``); among them
        ``setup_s`` (generation and the engine's first predictions, not the
        warm-up), ``warmup_s``, ``warmup_per_sphere``, ``settled``, the rates
        per sphere per unit time over the warm-up's last block and over the
        timed window, and ``warmup_blocks``.
    """
    t0 = time.perf_counter()
    cpu0 = time.process_time()
    where = container_for(n, packing, box, dimensions)
    arrays = random_arrays(n, packing, where, seed=seed, radius_ratio=radius_ratio, mass_ratio=mass_ratio)
    generate = time.perf_counter() - t0
    eng = Engine(*arrays, container=where)
    del arrays  # the engine holds its own copies (the masses are shared)
    setup = time.perf_counter() - t0
    setup_cpu = time.process_time() - cpu0
    setup_rss = peak_rss_mb()
    e0 = eng.kinetic_energy()
    t1 = time.perf_counter()
    blocks, ok = warm_up(eng, warmup)
    warm = time.perf_counter() - t1
    c0, sim_t0 = eng.counters, eng.time
    t2 = time.perf_counter()
    cpu = time.process_time()
    eng.advance(collisions=collisions, record=False)
    seconds = time.perf_counter() - t2
    cpu = time.process_time() - cpu
    coll_rate, cross_rate, c1 = _rates(eng, c0, sim_t0, n)
    events = sum(c1[k] - c0[k] for k in ("collisions", "reflections", "crossings", "stale"))
    coll = c1["collisions"] - c0["collisions"]
    last = blocks[-1] if blocks else (0.0, None, None)  # JSON has no NaN
    return {
        "n": n,
        "packing": packing,
        "radius_ratio": radius_ratio,
        "container": ("box" if box else "sphere") if dimensions == 3 else ("box" if box else "circle"),
        "dimensions": dimensions,
        "collisions": coll,
        "reflections": c1["reflections"] - c0["reflections"],
        "crossings": c1["crossings"] - c0["crossings"],
        "stale": c1["stale"] - c0["stale"],
        "events": events,
        "seconds": seconds,
        "cpu_seconds": cpu,
        "collisions_per_s": coll / seconds if seconds > 0 else float("inf"),
        "events_per_s": events / seconds if seconds > 0 else float("inf"),
        "generate_s": generate,
        "setup_s": setup,
        "setup_cpu_s": setup_cpu,
        "setup_peak_rss_mb": setup_rss,
        "warmup_s": warm,
        "warmup_per_sphere": last[0],
        "settled": ok,
        "warmup_collision_rate": last[1],
        "warmup_crossing_rate": last[2],
        "collision_rate": coll_rate,
        "crossing_rate": cross_rate,
        "enskog_collision_rate": enskog_rate(packing) if radius_ratio == 1.0 and dimensions == 3 else None,
        "warmup_blocks": [[round(w, 3), round(a, 5), round(b, 5)] for w, a, b in blocks],
        "peak_rss_mb": peak_rss_mb(),
        "energy_rel_drift": abs(eng.kinetic_energy() - e0) / e0 if e0 > 0 else 0.0,
        "max_overlap": eng.max_overlap(),
        "outside": eng.outside(),
    }
