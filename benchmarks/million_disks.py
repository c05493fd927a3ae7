"""A million disks: set-up and run of N = K^2 disks at area fraction 0.70.

Two starts, each in a fresh engine: ``random_spheres`` in the sqrt(3)/2 box
(seed 1) and the perfect crystal ``builders.hexagonal((K, K), 0.70)``.  For
each: the builder's time, the engine's build (cells or neighbour lists, every
prediction, the calendar; the compiled core loaded from its cache first, so
that is not counted), then C collisions; wall-clock and CPU seconds, the
process's peak memory, collisions per second, the largest overlap and the
kinetic energy's drift.  JSON on the last line.

usage: python3 benchmarks/million_disks.py [K] [C]   (defaults 1024 2000000)
"""

import json
import resource
import sys
import time

import hardspheres as hs
from hardspheres.builders import hexagonal
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine
from hardspheres.core.warmup import ensure_compiled


def _clock():
    return time.perf_counter(), time.process_time()


def _since(start):
    wall, cpu = _clock()
    return round(wall - start[0], 2), round(cpu - start[1], 2)


def one(name, build, collisions):
    start = _clock()
    state, box = build()
    built = _since(start)
    start = _clock()
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, container=box)
    engine = _since(start)
    e0 = eng.kinetic_energy()
    start = _clock()
    eng.advance(collisions=collisions, record=False)
    run = _since(start)
    row = {
        "start": name,
        "n": eng.n,
        "lists": bool(eng.scalars[core.F_SHELL] > 0.0),
        "builder_s": built,
        "engine_s": engine,
        "setup_wall_s": round(built[0] + engine[0], 2),
        "run_s": run,
        "collisions_per_cpu_s": round(collisions / run[1]) if run[1] > 0 else None,
        "counters": eng.counters,
        "max_overlap": eng.max_overlap(),
        "energy_drift": abs(eng.kinetic_energy() / e0 - 1.0),
        "peak_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024),
    }
    print(
        f"{name}: N = {eng.n}, set-up {row['setup_wall_s']} s wall (builder {built[0]} s, engine {engine[0]} s), "
        f"{collisions} collisions in {run[0]} s wall / {run[1]} s CPU "
        f"({row['collisions_per_cpu_s']} per CPU s), max overlap {row['max_overlap']:.1e}, "
        f"energy drift {row['energy_drift']:.1e}, peak {row['peak_mb']} MB",
        flush=True,
    )
    return row


def main():
    args = [int(float(x)) for x in sys.argv[1:3]]
    k, collisions = (args + [1024, 2_000_000][len(args) :])[:2]
    n = k * k
    ensure_compiled()

    def random_start():
        box = hs.PeriodicBox.for_packing(n, 0.70, (1, 3**0.5 / 2))
        return hs.random_spheres(n, 0.70, box, seed=1), box

    rows = [
        one("random", random_start, collisions),
        one("hexagonal", lambda: hexagonal((k, k), 0.70), collisions),
    ]
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
