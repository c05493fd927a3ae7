"""The assignment's program on its first run (an empty numba cache) against a warm compiled run.

For each N and END_TIME: a scenario from ``hardspheres generate`` (N
spheres at packing PHI in a container of radius 30 x (N / 1000)^(1/3),
seed 3), then ``spheres.py RADIUS END_TIME`` run

* cold: a new, empty ``NUMBA_CACHE_DIR`` and no engine forced (the
  program chooses: :class:`~hardspheres.core.scan.Scan` while the compiled
  core is not cached);
* warm: ``HARDSPHERES_ENGINE=compiled`` with a cache compiled beforehand.

Prints the wall seconds of each (best of ``--reps``), the events, and
whether the two reports are the same bytes.  The bar (benchmarks/README.md,
"The first run"): cold under 2 s wherever warm is under 1 s.

usage: python3 benchmarks/first_run.py [--n 100 300 1000] [--end 1 5 20] [--packing 0.2] [--reps 3]
(from the project's root)
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def timed(args, stdin, env, reps):
    best, out = float("inf"), b""
    for _ in range(reps):
        t0 = time.perf_counter()
        res = subprocess.run(args, input=stdin, capture_output=True, env=env, check=True)
        best = min(best, time.perf_counter() - t0)
        out = res.stdout
    return best, out


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, nargs="+", default=[100, 300, 1000])
    p.add_argument("--end", nargs="+", default=["1", "5", "20"])
    p.add_argument("--packing", type=float, default=0.2)
    p.add_argument("--reps", type=int, default=3)
    a = p.parse_args()
    base = {k: v for k, v in os.environ.items() if k not in ("HARDSPHERES_ENGINE", "NUMBA_CACHE_DIR")}
    base["PYTHONPATH"] = str(ROOT / "src")
    warm_cache = tempfile.mkdtemp(prefix="first-run-warm-")
    warm = {**base, "NUMBA_CACHE_DIR": warm_cache, "HARDSPHERES_ENGINE": "compiled"}
    subprocess.run([sys.executable, "-c", "from hardspheres.core.warmup import ensure_compiled; ensure_compiled()"],
                   env=warm, check=True)  # fmt: skip
    print("| N | END_TIME | events | cold s (chosen engine) | warm compiled s | same bytes |")
    print("|---|---|---|---|---|---|")
    for n in a.n:
        radius = f"{30 * (n / 1000) ** (1 / 3):.4g}"
        gen = [sys.executable, "-m", "hardspheres", "generate", "--n", str(n), "--container", radius,
               "--packing", str(a.packing), "--seed", "3"]  # fmt: skip
        scn = subprocess.run(gen, capture_output=True, env=base, check=True).stdout
        for end in a.end:
            args = [sys.executable, str(ROOT / "spheres.py"), radius, end]
            cold_s = float("inf")
            for _ in range(a.reps):
                with tempfile.TemporaryDirectory(prefix="first-run-cold-") as cold_cache:
                    s, cold_out = timed(args, scn, {**base, "NUMBA_CACHE_DIR": cold_cache}, 1)
                    cold_s = min(cold_s, s)
            warm_s, warm_out = timed(args, scn, warm, a.reps)
            events = cold_out.count(b"time of event")
            print(f"| {n} | {end} | {events} | {cold_s:.2f} | {warm_s:.2f} | {cold_out == warm_out} |", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")


if __name__ == "__main__":
    main()
