"""Ours against the C anchor by CPU time, for a machine shared with other work.

    python benchmarks/side_by_side_cpu.py --n 10000 --packing 0.1 0.3 0.45 --reps 2

The same runs as ``../shared/anchor/side_by_side.py`` (the anchor's Cell and
Single variants through its ``anchor.sh``, then ``hardspheres bench --box``
and ``hardspheres bench``, alternating, REPS times, 2x10^6 timed collisions at
N <= 10^4, else 10 N capped at 2x10^6), but each rate is collisions over the
CPU time of the timed part (both report it: the anchor's ``cpu_seconds``,
ours ``cpu_seconds``) instead of wall-clock time.  When other processes
share the cores, wall-clock rates measure how much of a core each run got;
CPU-time rates are steadier (though still inflated by what the others do
to the caches).  Prints a markdown table of medians (M collisions/s of CPU)
and the ratios ours / best anchor variant, then a JSON list.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys

ANCHOR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared",
                      "anchor", "anchor.sh")


def last_json(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, nargs="*", default=[10_000])
    p.add_argument("--packing", type=float, nargs="*", default=[0.1, 0.3, 0.45])
    p.add_argument("--reps", type=int, default=2)
    p.add_argument("--anchor", default=ANCHOR, help="path of anchor.sh")
    a = p.parse_args()
    rows = []
    print("| N | PHI | anchor Cell | anchor Single | ours box | ours sphere "
          "| box / best anchor | sphere / best anchor |")
    print("|---|---|---|---|---|---|---|---|")
    for n in a.n:
        for phi in a.packing:
            coll = 2_000_000 if n <= 10_000 else min(2_000_000, 10 * n)
            got = {"Cell": [], "Single": [], "box": [], "sphere": []}
            for _ in range(a.reps):
                for v in ("Cell", "Single"):
                    r = last_json([a.anchor, str(n), str(phi), str(coll), v])
                    got[v].append(r["collisions"] / r["cpu_seconds"])
                for box in (True, False):
                    r = last_json([sys.executable, "-m", "hardspheres", "bench", "--n", str(n),
                                   "--packing", str(phi), "--collisions", str(coll),
                                   "--seed", "7"] + (["--box"] if box else []))
                    if r["max_overlap"] > 1e-9 or r["outside"] or r["energy_rel_drift"] > 1e-10:
                        sys.exit(f"invalid run: {r}")
                    got["box" if box else "sphere"].append(r["collisions"] / r["cpu_seconds"])
            med = {k: statistics.median(v) / 1e6 for k, v in got.items()}
            best = max(med["Cell"], med["Single"])
            row = {"n": n, "packing": phi, **{k: round(v, 4) for k, v in med.items()},
                   "box_ratio": round(med["box"] / best, 3),
                   "sphere_ratio": round(med["sphere"] / best, 3), "runs": got}
            rows.append(row)
            print(f"| {n:.0e} | {phi} | {med['Cell']:.3f} | {med['Single']:.3f} "
                  f"| {med['box']:.3f} | {med['sphere']:.3f} | {row['box_ratio']:.2f} "
                  f"| {row['sphere_ratio']:.2f} |", flush=True)
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
