"""Mixtures against equal spheres at the same packing, alternating, in fresh processes.

    python benchmarks/mixtures.py                         # N = 1e4, 1e5; PHI = 0.15
    python benchmarks/mixtures.py --n 10000 --packing 0.3 --ratios 1 1.4 --reps 3

For each N, REPS rounds; each round runs `hardspheres bench` once per radius
ratio (radii uniform between 1 and the ratio, equal masses), in turn, so all
see the same machine load.  Prints the medians (M collisions/s over CPU time
and over wall time of the timed part) and each ratio's speed relative to
equal spheres (the medians of the per-round quotients), then a JSON list.
Every run warms up until its rates settle (`--warmup auto`).
"""

import argparse
import json
import statistics
import subprocess
import sys


def bench(n, phi, collisions, ratio, seed, box):
    cmd = [sys.executable, "-m", "hardspheres", "bench", "--n", str(n), "--packing", str(phi),
           "--collisions", str(collisions), "--radius-ratio", str(ratio), "--seed", str(seed)]
    cmd += ["--box"] if box else []
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--n", type=int, nargs="*", default=[10_000, 100_000])
    p.add_argument("--packing", type=float, default=0.15)
    p.add_argument("--ratios", type=float, nargs="*", default=[1.0, 1.4, 10.0])
    p.add_argument("--collisions", type=int, default=1_000_000)
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--box", action="store_true")
    a = p.parse_args()
    rows = []
    print("| N | PHI | radius ratio | M coll/s CPU | M coll/s wall | speed / equal, CPU "
          "(range) | warm-up per sphere |")
    print("|---|---|---|---|---|---|---|")
    for n in a.n:
        runs = {r: [] for r in a.ratios}
        for _ in range(a.reps):
            for r in a.ratios:
                runs[r].append(bench(n, a.packing, a.collisions, r, a.seed, a.box))
        cpu = {r: [x["collisions"] / x["cpu_seconds"] for x in v] for r, v in runs.items()}
        base = cpu[a.ratios[0]]
        for r in a.ratios:
            quot = [c / b for c, b in zip(cpu[r], base)]
            row = {"n": n, "packing": a.packing, "radius_ratio": r,
                   "cpu_rate": statistics.median(cpu[r]),
                   "wall_rate": statistics.median(x["collisions_per_s"] for x in runs[r]),
                   "vs_first": statistics.median(quot), "vs_first_min": min(quot),
                   "vs_first_max": max(quot),
                   "warmup_per_sphere": statistics.median(x["warmup_per_sphere"] for x in runs[r]),
                   "settled": all(x["settled"] for x in runs[r])}
            rows.append(row)
            print(f"| {n:.0e} | {a.packing} | {r:g} | {row['cpu_rate'] / 1e6:.3f} "
                  f"| {row['wall_rate'] / 1e6:.3f} | {row['vs_first']:.2f} "
                  f"({row['vs_first_min']:.2f}-{row['vs_first_max']:.2f}) "
                  f"| {row['warmup_per_sphere']:g}{'' if row['settled'] else ' (not settled)'} |",
                  flush=True)
    print(json.dumps(rows))


if __name__ == "__main__":
    sys.exit(main())
