"""Run `hardspheres bench` over N and packing fractions; print a markdown table.

Each configuration runs in its own process (so peak memory is its own):

    python benchmarks/table.py                      # N = 1e3..1e6, PHI = 0.1, 0.3, 0.45
    python benchmarks/table.py --n 10000 --collisions 2000000
"""

import argparse
import json
import subprocess
import sys


def bench(n, phi, collisions, extra=()):
    cmd = ["hardspheres", "bench", "--n", str(n), "--packing", str(phi),
           "--collisions", str(collisions), *extra]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--n", type=int, nargs="*", default=[10**3, 10**4, 10**5, 10**6])
    p.add_argument("--packing", type=float, nargs="*", default=[0.1, 0.3, 0.45])
    p.add_argument("--collisions", type=int, default=2_000_000)
    p.add_argument("--radius-ratio", type=float, default=1.0)
    p.add_argument("--box", action="store_true")
    a = p.parse_args()
    extra = ["--radius-ratio", str(a.radius_ratio)] + (["--box"] if a.box else [])
    print("| N | PHI | M coll/s | M events/s | seconds | setup s | peak MB "
          "| energy drift | max overlap | outside |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in a.n:
        for phi in a.packing:
            r = bench(n, phi, a.collisions, extra)
            print(f"| {n:.0e} | {phi} | {r['collisions_per_s'] / 1e6:.3f} "
                  f"| {r['events_per_s'] / 1e6:.3f} | {r['seconds']:.2f} | {r['setup_s']:.1f} "
                  f"| {r['peak_rss_mb']:.0f} | {r['energy_rel_drift']:.1e} "
                  f"| {r['max_overlap']:.1e} | {r['outside']} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
