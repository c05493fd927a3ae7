"""Events per second of our event chains against HistoricDisks' C++ StraightECMC, side by side.

The anchor is Li et al.'s straight ECMC for hard disks (github
jellyfysh/HistoricDisks, ``CPP/StraightECMC``; J. Chem. Phys. 157, 234111
(2022)), built and run by ``../shared/anchor/ecmc/anchor.sh`` (its README:
the flags, the patch, the units).  Both start from the same perfect
triangular crystal of ``NX x NY`` disks at packing ``ETA`` in its box
(``NX a`` by ``NY a sqrt(3)/2``), move chains of the same length (0.24 of the
square root of the area, the anchor's ``3.125 sqrt(N) lambda_0``), along x
and y in turn, and count the same events: lifts only.

For each size the two programs run alternately (anchor, ours, anchor, ours,
...), ``--repeats`` times each, and the median of each is reported: a load
that comes and goes falls on both.  The anchor's figure is its own
``events_per_s`` (a steady clock around its sampling loop only); ours is
``EventChain.run(events=E)`` timed by ``time.perf_counter`` after a warm-up
of ``--warm`` lifts (compilation and the numba cache are outside it), with
``E`` the anchor's event count of the same repeat (``--events`` to fix it).
The CPU seconds of both are printed beside the wall figures, with the load
averages, so a busy machine shows.

usage (from the project's root; ``nice`` it on a shared machine)::

    nice -n 10 python3 benchmarks/ecmc_side_by_side.py                 # N = 72, 870, 16384 at 0.70
    nice -n 10 python3 benchmarks/ecmc_side_by_side.py --sizes 870 --length 0.5 --repeats 5
    nice -n 10 python3 benchmarks/ecmc_side_by_side.py --tiny          # a check that it runs (seconds)

Sizes and their lattices: 72 = 9 x 8, 870 = 29 x 30 (the repository's N = 870
set), 16384 = 128 x 128; any ``NXxNY`` (``--sizes 16x16``) as well.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ANCHOR = ROOT.parent / "shared" / "anchor" / "ecmc" / "anchor.sh"
LATTICES = {72: (9, 8), 870: (29, 30), 16384: (128, 128)}


def lattice(text: str) -> tuple[int, int]:
    """``NX, NY`` from ``72``, ``870``, ``16384`` or ``NXxNY``."""
    if "x" in text:
        nx, ny = (int(t) for t in text.split("x"))
        return nx, ny
    n = int(text)
    if n not in LATTICES:
        raise SystemExit(f"--sizes {text}: give one of {sorted(LATTICES)} or NXxNY")
    return LATTICES[n]


def load() -> str:
    try:
        with open("/proc/loadavg") as fh:
            return " ".join(fh.read().split()[:3])
    except OSError:
        return ""


def anchor(nx: int, ny: int, eta: float, length: float) -> dict:
    """One run of the C++ anchor: its JSON line."""
    out = subprocess.run(
        [str(ANCHOR), str(nx), str(ny), str(eta), "crystal", str(length)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def ours(nx: int, ny: int, eta: float, events: int, warm: int) -> dict:
    """One run of ours from the same crystal: lifts per second (wall and CPU)."""
    sys.path.insert(0, str(ROOT / "src"))
    from hardspheres.builders import hexagonal
    from hardspheres.mc.chain import EventChain

    state, box = hexagonal((nx, ny), eta)
    chain = EventChain(state, box, seed=0)
    chain.run(events=warm)
    e0 = chain.counters["events"]
    l0 = load()
    w0, c0 = time.perf_counter(), time.process_time()
    chain.run(events=events)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    done = chain.counters["events"] - e0
    z = chain.observables.estimate("Z").mean  # from the start (a crystal): a rough check only
    return {
        "events": done,
        "seconds": wall,
        "cpu_seconds": cpu,
        "events_per_s": done / wall,
        "chains": chain.counters["chains"],
        "beta_P_d2": 4.0 * eta / 3.141592653589793 * z,
        "loadavg_before": l0,
        "loadavg_after": load(),
    }


def main() -> None:
    """Run the comparison; print one JSON line per run and the table of medians."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="72,870,16384", help="comma-separated: 72, 870, 16384 or NXxNY")
    p.add_argument("--eta", type=float, default=0.70, help="packing fraction (default 0.70)")
    p.add_argument("--length", type=float, default=0.2, help="the anchor's LENGTH (0.2: about 3.5e7 lifts)")
    p.add_argument("--repeats", type=int, default=3, help="runs of each program per size (median)")
    p.add_argument("--events", type=int, help="our lifts per run (default: the anchor's of that repeat)")
    p.add_argument("--warm", type=int, default=200_000, help="our lifts before the clock starts")
    p.add_argument("--tiny", action="store_true", help="N = 72, LENGTH 0.005, one repeat: does it run?")
    args = p.parse_args()
    if args.tiny:
        args.sizes, args.length, args.repeats, args.warm = "72", 0.005, 1, 10_000
    if not ANCHOR.exists():
        raise SystemExit(f"{ANCHOR} is missing: the anchor lives beside the project (../shared/anchor/ecmc)")
    ours(9, 8, args.eta, 1000, 1000)  # compile (or load numba's cache) before any clock
    table = []
    for text in args.sizes.split(","):
        nx, ny = lattice(text)
        a_runs, o_runs = [], []
        for rep in range(args.repeats):
            a = anchor(nx, ny, args.eta, args.length)
            a_runs.append(a)
            print(json.dumps({**a, "side": "anchor", "n": nx * ny, "repeat": rep}), flush=True)
            o = ours(nx, ny, args.eta, args.events or int(a["events"]), args.warm)
            o_runs.append(o)
            print(json.dumps({**o, "side": "ours", "n": nx * ny, "repeat": rep}), flush=True)
        ma = statistics.median(r["events_per_s"] for r in a_runs)
        mo = statistics.median(r["events_per_s"] for r in o_runs)
        table.append((nx * ny, f"{nx}x{ny}", ma / 1e6, mo / 1e6, mo / ma))
    print(
        f"\nevents (lifts) per second, median of {args.repeats}, packing {args.eta}, "
        f"anchor LENGTH {args.length}, cpu {os.cpu_count()}"
    )
    print("| N | lattice | anchor M/s | ours M/s | ours / anchor |")
    print("|---|---|---|---|---|")
    for n, lat, ma, mo, ratio in table:
        print(f"| {n} | {lat} | {ma:.3g} | {mo:.3g} | {ratio:.2f} |")


if __name__ == "__main__":
    main()
