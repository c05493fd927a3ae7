"""What one call of the compiled core's ``run`` costs with nothing to do.

    python benchmarks/core_call.py [CALLS]

Times ``_core.run`` returning at once (``until`` = the clock) on a small
system: the cost of passing the arrays, which the engine pays once per
chunk of up to 16384 events.  Works with the grouped signature (``Arrays``)
and the older one of 16 positional arrays, so two trees can be compared;
``--named`` passes the arrays as a named tuple instead of the engine's plain
one (what the grouping first tried).
"""

import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres.core import _core

numbers = [a for a in sys.argv[1:] if not a.startswith("--")]
calls = int(numbers[0]) if numbers else 200000
sim = hs.Simulation(hs.random_spheres(64, 0.2, box=8.0, seed=1), hs.PeriodicBox(8.0))
sim.run(collisions=100)
e = sim._engine
now = float(e.scalars[_core.F_CLOCK])
big = 10**9
if hasattr(_core, "ARRAYS"):
    rec = e._event_buffers
    if "--named" in sys.argv:
        import collections

        arrays = collections.namedtuple("Arrays", _core.ARRAYS)(*e.arrays)
    else:
        arrays = e.arrays

    def call():
        return _core.run(arrays, now, big, big, rec, True, (), ())

    def call_fresh():  # as the engine calls it: the tuple made per call
        return _core.run(e.arrays, now, big, big, rec, True, (), ())
else:
    args = (
        e.spheres,
        e.masses,
        e.book,
        e.due,
        e.shells,
        e.neighbours,
        e.cell_head,
        e.cell_next,
        e.cell_prev,
        e.heap,
        e.heap_t,
        e.heap_key,
        e.scalars,
        e.counts,
        e.scratch,
        e.images,
    )

    def call():
        return _core.run(*args, now, big, big, *e._event_buffers, (), ())

    call_fresh = call
assert call() == (0, 0)
for name, fn in (("run", call), ("run, arguments made per call", call_fresh)):
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        times.append((time.perf_counter() - t0) / calls * 1e6)
    print(f"{name}: {np.median(times):.2f} us per call (best {min(times):.2f}, {calls} calls x 5)")
