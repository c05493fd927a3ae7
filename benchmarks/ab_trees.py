"""A/B of `hardspheres bench` between source trees, by CPU time (robust to a shared machine).

Per-collision CPU time = (CPU(C2) - CPU(C1)) / (C2 - C1) of whole processes
(setup and warm-up cancel).  Rounds alternate the trees.
usage: ab.py ROUNDS N PHI C1 C2 [--sphere] TREE...
"""

import json
import os
import resource
import statistics
import subprocess
import sys


def cpu_run(tree, n, phi, coll, box):
    env = dict(os.environ, PYTHONPATH=os.path.join(tree, "src"))
    cmd = [
        sys.executable,
        "-m",
        "hardspheres",
        "bench",
        "--n",
        str(n),
        "--packing",
        str(phi),
        "--collisions",
        str(coll),
    ] + (["--box"] if box else [])
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    js = json.loads(out.stdout.strip().splitlines()[-1])
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), js


args = sys.argv[1:]
box = "--sphere" not in args
args = [a for a in args if a != "--sphere"]
rounds, n, phi, c1, c2 = int(args[0]), int(args[1]), float(args[2]), int(args[3]), int(args[4])
trees = args[5:]
per = {t: [] for t in trees}
for r in range(rounds):
    for t in trees if r % 2 == 0 else trees[::-1]:
        a, ja = cpu_run(t, n, phi, c1, box)
        b, jb = cpu_run(t, n, phi, c2, box)
        per[t].append((b - a) / (c2 - c1) * 1e6)
        print(
            f"round {r} {t}: {per[t][-1]:.4f} us CPU/collision (wall {jb['collisions_per_s'] / 1e6:.3f} M/s)",
            flush=True,
        )
base = statistics.median(per[trees[0]])
for t in trees:
    med = statistics.median(per[t])
    print(
        f"{t}: median {med:.4f} us/collision, spread {min(per[t]):.4f}-{max(per[t]):.4f}, "
        f"speed vs {trees[0]}: {base / med:.3f}"
    )
