"""Time the scenario builder alone: CPU seconds and peak memory of `random_arrays`.

    python benchmarks/generate.py 10000000 0.3          # spherical container
    python benchmarks/generate.py 10000000 0.3 --box    # periodic box

Sizes the container as `hardspheres bench` does (largest radius 0.5), runs
`hardspheres.builders.random_arrays` once in this process and prints its CPU
time, wall time and the process's peak resident memory (which includes the
interpreter and numpy, about 30 MB).
"""

import argparse
import resource
import time

import numpy as np

from hardspheres.builders import random_arrays
from hardspheres.containers import PeriodicBox, SphericalContainer


def main():
    p = argparse.ArgumentParser()
    p.add_argument("n", type=float)
    p.add_argument("packing", type=float)
    p.add_argument("--box", action="store_true")
    p.add_argument("--radius-ratio", type=float, default=1.0)
    a = p.parse_args()
    n = int(a.n)
    if a.box:
        where = PeriodicBox((n * np.pi / 6.0 / a.packing) ** (1.0 / 3.0))
    else:
        where = SphericalContainer(0.5 * (n / a.packing) ** (1.0 / 3.0))
    cpu, wall = time.process_time(), time.perf_counter()
    random_arrays(n, a.packing, where, seed=0, radius_ratio=a.radius_ratio)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"N={n} packing={a.packing} {'box' if a.box else 'sphere'}: CPU {cpu:.2f} s, "
          f"wall {wall:.2f} s, peak {peak:.0f} MB ({peak * 2**20 / n:.0f} bytes per sphere)")


if __name__ == "__main__":
    main()
