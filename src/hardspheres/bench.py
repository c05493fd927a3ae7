"""The benchmark: collisions per second of the compiled core on a generated system."""

import json
import resource
import time

import numpy as np

from .builders import random_spheres
from .containers import PeriodicBox, SphericalContainer
from .engine import Engine


def peak_rss_mb():
    """Peak resident memory of this process so far [MB]."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def bench(n, packing, collisions, seed=0, radius_ratio=1.0, mass_ratio=1.0, box=False):
    """Generate ``n`` spheres, warm up with ``n`` collisions, time ``collisions`` more.

    The container (or box) is sized so that the largest sphere has radius
    of order 1.  Returns a dict of figures (see ``hardspheres bench``).
    """
    t0 = time.perf_counter()
    if box:
        edge = (n * (4.0 / 3.0) * np.pi * 0.125 / packing) ** (1.0 / 3.0)
        where = PeriodicBox(edge)
    else:
        where = SphericalContainer(0.5 * (n / packing) ** (1.0 / 3.0))
    state = random_spheres(n, packing, where, seed=seed,
                           radius_ratio=radius_ratio, mass_ratio=mass_ratio)
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, where)
    e0 = eng.kinetic_energy()
    eng.advance(collisions=n, record=False)
    setup = time.perf_counter() - t0
    c0 = eng.counters
    t1 = time.perf_counter()
    eng.advance(collisions=collisions, record=False)
    seconds = time.perf_counter() - t1
    c1 = eng.counters
    events = sum(c1[k] - c0[k] for k in ("collisions", "reflections", "crossings", "stale"))
    coll = c1["collisions"] - c0["collisions"]
    return {
        "n": n, "packing": packing, "radius_ratio": radius_ratio,
        "container": "box" if box else "sphere",
        "collisions": coll, "reflections": c1["reflections"] - c0["reflections"],
        "crossings": c1["crossings"] - c0["crossings"], "stale": c1["stale"] - c0["stale"],
        "events": events, "seconds": seconds,
        "collisions_per_s": coll / seconds if seconds > 0 else float("inf"),
        "events_per_s": events / seconds if seconds > 0 else float("inf"),
        "setup_s": setup, "peak_rss_mb": peak_rss_mb(),
        "energy_rel_drift": abs(eng.kinetic_energy() - e0) / e0 if e0 > 0 else 0.0,
        "max_overlap": eng.max_overlap(), "outside": eng.outside(),
    }


def main(n, packing, collisions, **kw):
    """Print the figures, the JSON object last."""
    res = bench(n, packing, collisions, **kw)
    print(f"N={n} packing={packing}: {res['collisions_per_s'] / 1e6:.3f} M collisions/s, "
          f"{res['events_per_s'] / 1e6:.3f} M events/s, peak {res['peak_rss_mb']:.0f} MB")
    print(json.dumps(res))
    return res
