"""Instructions per lifting event of our event chains, counted by cachegrind (no noise from the load).

Two runs of the same chain from the same start (a perfect triangular crystal
of ``NX x NY`` disks at packing ``ETA``, 20000 lifts of warm-up) that differ
only in the number of timed lifts (``E1`` and ``E2``) run under valgrind's
cachegrind (instructions only); their difference over ``E2 - E1`` is the
work of one lift, start-up and compilation subtracted.  The core is compiled
for Haswell outside valgrind first (``NUMBA_CPU_NAME``, its own cache
entries), as ``benchmarks/cachegrind_core.py`` does for the event core.  A
count of work, not of time: it compares two versions of our code on a busy
machine.

usage (from the project's root; needs valgrind; about a minute)::

    nice -n 10 python3 benchmarks/cachegrind_ecmc.py 29 30 0.70 100000 400000
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile

HASWELL = (
    "+64bit,+avx,+avx2,+bmi,+bmi2,+cmov,+cx16,+f16c,+fma,+fsgsbase,+lzcnt,+mmx,+movbe,"
    "+pclmul,+popcnt,+rdrnd,+sahf,+sse,+sse2,+sse3,+sse4.1,+sse4.2,+ssse3,+xsave,+xsaveopt"
)


def inner(nx: int, ny: int, eta: float, events: int) -> None:
    from hardspheres.builders import hexagonal
    from hardspheres.mc.chain import EventChain

    state, box = hexagonal((nx, ny), eta)
    chain = EventChain(state, box, seed=0)
    chain.run(events=20000)
    chain.run(events=events)


def main() -> None:
    if sys.argv[1:2] == ["--inner"]:
        inner(int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5]))
        return
    nx, ny, eta, e1, e2 = sys.argv[1:6]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CPU_FEATURES=HASWELL, OPENBLAS_NUM_THREADS="1")
    env["PYTHONPATH"] = os.path.join(root, "src")
    py = os.path.realpath(sys.executable)
    me = os.path.abspath(__file__)
    subprocess.run([py, me, "--inner", nx, ny, eta, "1000"], env=env, check=True)  # compile outside valgrind
    counts = []
    with tempfile.TemporaryDirectory() as tmp:
        for events in (e1, e2):
            out = os.path.join(tmp, f"cg.{events}")
            subprocess.run(
                ["valgrind", "--tool=cachegrind", "--cache-sim=no", f"--cachegrind-out-file={out}"]
                + [py, me, "--inner", nx, ny, eta, events],
                env=env,
                check=True,
                capture_output=True,
            )
            with open(out) as fh:
                counts.append(next(int(line.split()[1]) for line in fh if line.startswith("summary:")))
    per = (counts[1] - counts[0]) / (int(e2) - int(e1))
    print(f"N = {int(nx) * int(ny)} ({nx}x{ny}), packing {eta}: {per:.0f} instructions per lift")


if __name__ == "__main__":
    main()
