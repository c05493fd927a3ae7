"""Run `hardspheres bench` over N and packing fractions; print markdown tables.

Each configuration runs in its own process (so peak memory is its own):

    python benchmarks/table.py                      # N = 1e3..1e6, PHI = 0.1, 0.3, 0.45
    python benchmarks/table.py --n 10000 --collisions 2000000
    python benchmarks/table.py --n 1000000 4000000 10000000 --packing 0.3 \\
        --collisions 100000 --warmup 0 --time-v   # setup and peak memory only

Two tables: the speed (wall clock and CPU time of the timed part; on a
machine shared with other work, CPU time is the steadier of the two) with
setup, memory and accuracy, then the warm-up: collisions per sphere until the
collision and cell-crossing rates settled, and those rates per sphere per
unit time over the warm-up's last block and over the timed window (with
Enskog's collision rate for equal spheres, for reference).  ``--time-v``
runs each under ``/usr/bin/time -v`` and reports its maximum resident set
size and CPU seconds as well.
"""

import argparse
import json
import re
import subprocess
import sys


def bench(n, phi, collisions, extra=(), time_v=False):
    cmd = [sys.executable, "-m", "hardspheres", "bench", "--n", str(n), "--packing", str(phi),
           "--collisions", str(collisions), *extra]
    if time_v:
        cmd = ["/usr/bin/time", "-v", *cmd]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    if time_v:
        rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", out.stderr)
        user = re.search(r"User time \(seconds\): ([\d.]+)", out.stderr)
        system = re.search(r"System time \(seconds\): ([\d.]+)", out.stderr)
        res["time_v_rss_mb"] = int(rss.group(1)) / 1024 if rss else float("nan")
        res["time_v_cpu_s"] = (float(user.group(1)) + float(system.group(1))
                               if user and system else float("nan"))
    return res


def _f(x, fmt):
    return "-" if x is None else format(x, fmt)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--n", type=int, nargs="*", default=[10**3, 10**4, 10**5, 10**6])
    p.add_argument("--packing", type=float, nargs="*", default=[0.1, 0.3, 0.45])
    p.add_argument("--collisions", type=int, default=2_000_000)
    p.add_argument("--radius-ratio", type=float, default=1.0)
    p.add_argument("--box", action="store_true")
    p.add_argument("--warmup", default="auto")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--time-v", action="store_true", help="run under /usr/bin/time -v")
    a = p.parse_args()
    extra = ["--radius-ratio", str(a.radius_ratio), "--warmup", a.warmup, "--seed", str(a.seed)]
    extra += ["--box"] if a.box else []
    rows = [bench(n, phi, a.collisions, extra, a.time_v) for n in a.n for phi in a.packing]
    head = ("| N | PHI | M coll/s wall | M coll/s CPU | M events/s wall | setup s | setup CPU s "
            "| peak MB | energy drift | max overlap | outside |")
    if a.time_v:
        head += " time -v MB | time -v CPU s |"
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    for r in rows:
        line = (f"| {r['n']:.0e} | {r['packing']} | {r['collisions_per_s'] / 1e6:.3f} "
                f"| {r['collisions'] / r['cpu_seconds'] / 1e6:.3f} "
                f"| {r['events_per_s'] / 1e6:.3f} | {r['setup_s']:.1f} | {r['setup_cpu_s']:.1f} "
                f"| {r['peak_rss_mb']:.0f} | {r['energy_rel_drift']:.1e} "
                f"| {r['max_overlap']:.1e} | {r['outside']} |")
        if a.time_v:
            line += f" {r['time_v_rss_mb']:.0f} | {r['time_v_cpu_s']:.1f} |"
        print(line)
    print()
    print("| N | PHI | warm-up per sphere | settled | collision rate: warm-up / timed / Enskog-CS "
          "| crossing rate: warm-up / timed | warm-up s |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['n']:.0e} | {r['packing']} | {r['warmup_per_sphere']:g} | "
              f"{'yes' if r['settled'] else 'no'} | {_f(r['warmup_collision_rate'], '.3f')} / "
              f"{r['collision_rate']:.3f} / {_f(r['enskog_collision_rate'], '.3f')} "
              f"| {_f(r['warmup_crossing_rate'], '.3f')} / {r['crossing_rate']:.3f} "
              f"| {r['warmup_s']:.1f} |", flush=True)
    print(json.dumps(rows))


if __name__ == "__main__":
    sys.exit(main())
