"""Bytes per sphere of the engine's arrays, array by array (no run: sizes only).

Builds an :class:`~hardspheres.core.engine.Engine` of N spheres (seed 1) at
each packing, in the periodic box and in the spherical container, and
prints the bytes of each of the core's arrays (``_core.ARRAYS``) divided by
N, then the total.  Deterministic: the same tree prints the same table on
any machine.

usage: python3 benchmarks/memory.py [N] [--tree TREE]   (default N = 100000)
"""

import argparse
import os
import subprocess
import sys

CHILD = """
import sys
from hardspheres.builders import random_arrays
from hardspheres.core import _core
from hardspheres.core.bench import container_for
from hardspheres.core.engine import Engine

n = int(float(sys.argv[1]))
names = [a for a in _core.ARRAYS if a not in ("axes", "rule")]
print("| container | PHI | " + " | ".join(names) + " | total |")
print("|---" * (len(names) + 3) + "|")
for box in (True, False):
    for phi in (0.1, 0.3, 0.45):
        where = container_for(n, phi, box=box)
        eng = Engine(*random_arrays(n, phi, where, seed=1), container=where)
        sizes = [a.nbytes / n for name, a in zip(_core.ARRAYS, eng.arrays) if name in names]
        cells = " | ".join(f"{s:.1f}" for s in sizes)
        print(f"| {'box' if box else 'sphere'} | {phi} | {cells} | {sum(sizes):.1f} |")
"""


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("n", nargs="?", default="100000")
    p.add_argument("--tree", default=os.getcwd(), help="the source tree whose src/ is run (default: here)")
    a = p.parse_args()
    env = {**os.environ, "PYTHONPATH": os.path.join(a.tree, "src")}
    subprocess.run([sys.executable, "-c", CHILD, a.n], env=env, check=True)


if __name__ == "__main__":
    main()
