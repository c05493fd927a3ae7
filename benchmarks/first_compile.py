"""First compilation of the event core between source trees: a cold numba cache each time, trees alternating.

Each round runs, for every TREE in turn (the order reversed every other
round), one process with that tree's ``src`` on ``PYTHONPATH`` and a new,
empty ``NUMBA_CACHE_DIR``: it imports the package, builds an Engine of 64
spheres at packing 0.3 in a periodic box and advances it 100 collisions,
which compiles the core (``--dimensions 2``: 64 disks in a periodic square;
``3,2``: both, one after the other, in one process).  Prints each process's CPU and wall seconds from
its start (imports included), then per tree the median and minimum CPU
seconds (the CPU time is the figure on a shared machine: the wall time
grows with the other processes' load).

usage: first_compile.py ROUNDS TREE... [--dimensions 3|2|3,2]
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

CHILD = """
import json, time
t0, c0 = time.perf_counter(), time.process_time()
from hardspheres.builders import random_arrays
try:
    from hardspheres.core.bench import container_for
    from hardspheres.core.engine import Engine
except ImportError:  # a tree from before the layout by families (04aa93d and older)
    from hardspheres.bench import container_for
    from hardspheres.engine import Engine
for d in DIMENSIONS:
    if d == 3:
        where = container_for(64, 0.3, box=True)
    else:
        where = container_for(64, 0.3, box=True, dimensions=2)
    eng = Engine(*random_arrays(64, 0.3, where, seed=0), container=where)
    eng.advance(collisions=100, record=False)
print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0}))
"""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("rounds", type=int)
    p.add_argument("trees", nargs="+")
    p.add_argument("--dimensions", default="3", help="3, 2 or 3,2 (both in one process)")
    a = p.parse_args()
    got = {t: [] for t in a.trees}
    for r in range(a.rounds):
        for t in a.trees if r % 2 == 0 else a.trees[::-1]:
            cache = tempfile.mkdtemp(prefix="numba-cold-")
            try:
                env = dict(os.environ, PYTHONPATH=os.path.join(t, "src"), NUMBA_CACHE_DIR=cache)
                with open("/proc/loadavg") as fh:
                    load = " ".join(fh.read().split()[:3])
                out = subprocess.run(
                    [sys.executable, "-c", f"DIMENSIONS = ({a.dimensions},)\n" + CHILD],
                    env=env,
                    cwd=tempfile.gettempdir(),
                    capture_output=True,
                    text=True,
                    check=True,
                )
            finally:
                shutil.rmtree(cache, ignore_errors=True)
            run = json.loads(out.stdout.strip().splitlines()[-1])
            got[t].append(run)
            print(
                f"round {r} {t}: cpu {run['cpu']:.2f} s, wall {run['wall']:.2f} s (load {load})", flush=True
            )
    for t, runs in got.items():
        cpu = [x["cpu"] for x in runs]
        print(f"{t}: CPU median {statistics.median(cpu):.2f} s, min {min(cpu):.2f} s over {len(cpu)} runs")


if __name__ == "__main__":
    main()
