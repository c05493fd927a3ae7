"""A/B of the event core between source trees: CPU time per collision in chunks, trees alternating.

Each round runs, for every TREE in turn (the order reversed every other
round), one process with that tree's ``src`` on ``PYTHONPATH``: N spheres at
packing PHI (periodic box, or ``--sphere``), warmed up ``--warm`` collisions
per sphere from the lattice (seed 0, so every tree sees the same events),
then REPS chunks of C collisions, each timed by CPU time.  Prints each
process's chunks, then per tree the median of the processes' medians and the
minimum over all chunks (the least disturbed figure on a shared machine).

usage: ab_chunks.py ROUNDS N PHI REPS C [--sphere] [--warm W] TREE...
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import time


def one(a):

    from hardspheres.builders import random_arrays

    try:
        from hardspheres.core.bench import container_for, warm_up
        from hardspheres.core.engine import Engine
    except ImportError:  # a tree from before the layout by families (04aa93d and older)
        from hardspheres.bench import container_for, warm_up
        from hardspheres.engine import Engine

    where = container_for(a.n, a.phi, box=not a.sphere)
    eng = Engine(*random_arrays(a.n, a.phi, where, seed=0), container=where)
    warm_up(eng, a.warm)
    per = []
    for _ in range(a.reps):
        t = time.process_time()
        eng.advance(collisions=a.c, record=False)
        per.append((time.process_time() - t) / a.c * 1e6)
    print(json.dumps(per))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("rounds", type=int)
    p.add_argument("n", type=int)
    p.add_argument("phi", type=float)
    p.add_argument("reps", type=int)
    p.add_argument("c", type=int)
    p.add_argument("trees", nargs="*")
    p.add_argument("--sphere", action="store_true")
    p.add_argument("--warm", type=float, default=10.0)
    p.add_argument("--one", action="store_true", help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.one:
        one(a)
        return
    got = {t: [] for t in a.trees}
    for r in range(a.rounds):
        for t in a.trees if r % 2 == 0 else a.trees[::-1]:
            env = dict(os.environ, PYTHONPATH=os.path.join(t, "src"))
            cmd = [sys.executable, __file__, "1", str(a.n), str(a.phi), str(a.reps), str(a.c), "--one"]
            cmd += ["--warm", str(a.warm)] + (["--sphere"] if a.sphere else [])
            out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
            per = json.loads(out.stdout.strip().splitlines()[-1])
            got[t].append(per)
            print(f"round {r} {t}: " + " ".join(f"{x:.3f}" for x in per), flush=True)
    base = None
    for t, runs in got.items():
        med = statistics.median(statistics.median(x) for x in runs)
        low = min(min(x) for x in runs)
        base = base or (med, low)
        print(
            f"{t}: median {med:.3f} us/collision, min {low:.3f}; "
            f"speed vs {a.trees[0]}: {base[0] / med:.3f} (median), {base[1] / low:.3f} (min)"
        )


if __name__ == "__main__":
    main()
