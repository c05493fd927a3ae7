"""Speed of the assignment's program.

1. The twelve official cases (../shared/conformance), each a fresh process,
   as a user runs them: total wall time.
2. The report for N = 1000 spheres: sphere lines printed per second.

    python benchmarks/assignment.py
"""

import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONF = ROOT.parent / "shared" / "conformance"


def official():
    rows = [ln.split("\t") for ln in (CONF / "cases.tsv").read_text().splitlines()[1:]]
    t0 = time.perf_counter()
    for name, radius, end, _ in rows:
        with open(CONF / "inputs" / f"{name}.txt", "rb") as fh:
            subprocess.run([sys.executable, str(ROOT / "spheres.py"), radius, end],
                           stdin=fh, stdout=subprocess.DEVNULL, check=True)
    return len(rows), time.perf_counter() - t0


def big(n=1000, end="3"):
    scn = subprocess.run(["hardspheres", "generate", "--n", str(n), "--container", "30",
                          "--packing", "0.2", "--seed", "3"],
                         capture_output=True, check=True).stdout
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, str(ROOT / "spheres.py"), "30", end], input=scn,
                         capture_output=True, check=True).stdout
    seconds = time.perf_counter() - t0
    lines = sum(1 for ln in out.splitlines() if ln.startswith(b"s"))
    return lines, seconds


if __name__ == "__main__":
    k, s = official()
    print(f"official cases: {k} runs in {s:.2f} s wall")
    lines, s = big()
    print(f"N=1000 report: {lines} sphere lines in {s:.2f} s = {lines / s / 1e3:.0f} k lines/s")
