"""Instructions, cache misses and mispredicted branches per collision, ours or the anchor's (cachegrind).

This machine has no hardware counters (``perf`` sees only a software clock),
so the work per collision is counted under valgrind's cachegrind, which
simulates the CPU: instructions, data references, misses of a 48 KiB L1d
and of a 2 MiB L2 (simulated as its last level), and conditional branches
with the mispredictions of a simple predictor.  The counts are exact and
repeatable (no noise from the machine's load), but they are a model: no
hardware prefetcher, no out-of-order overlap, so they say what work is
done, not how long it takes.

Two runs of the same system that differ only in the number of timed
collisions (C1 and C2, after N warm-up collisions from the same start) are
subtracted: start-up, compilation and warm-up drop out.

Ours: N spheres at packing PHI in a periodic box (``--sphere``: in the
spherical container, the assignment's), seed 0, ten collisions per sphere
of warm-up (as ``benchmarks/ab_chunks.py``; ``--warm``), from the source
tree ``--tree`` (default: this one), so that trees can be compared by
instructions, which a loaded machine does not disturb.  ``--ir-only``:
instructions alone (no cache or branch simulation; about twice as fast).
The second run also prints its crossings, stale predictions and
reflections per collision (the work the counts are made of).  valgrind cannot
run AVX-512 code, so the core is compiled for Haswell
(``NUMBA_CPU_NAME``/``NUMBA_CPU_FEATURES``, its own cache entries), outside
valgrind first.  ``--anchor Single|Cell``: the anchor's code instead, built
by ``../shared/anchor/anchor.sh`` with ``-march=haswell`` (its other flags
as in its Makefile), from its own initial configuration, N warm-up
collisions.  ``--dimensions 2``: disks (a periodic square, or with
``--sphere`` the circle).

usage: python3 benchmarks/cachegrind_core.py N PHI [--sphere] [--tree TREE] [--warm W] [--ir-only]
       [--dimensions 2|3] [--anchor VARIANT] [--c1 C1] [--c2 C2]
(from the project's root; needs valgrind)
"""

import argparse
import glob
import hashlib
import math
import os
import subprocess
import sys
import tempfile

HASWELL = (
    "+64bit,+avx,+avx2,+bmi,+bmi2,+cmov,+cx16,+f16c,+fma,+fsgsbase,+lzcnt,+mmx,+movbe,"
    "+pclmul,+popcnt,+rdrnd,+sahf,+sse,+sse2,+sse3,+sse4.1,+sse4.2,+ssse3,+xsave,+xsaveopt"
)
ANCHOR_CFLAGS = "-Wall -Ofast -funroll-loops -march=haswell"
CACHEGRIND = [
    "valgrind",
    "--tool=cachegrind",
    "--cache-sim=yes",
    "--branch-sim=yes",
    "--D1=49152,12,64",
    "--LL=2097152,16,64",
]


def inner(n, phi, c, sphere, warm, dimensions=3):
    from hardspheres.core import _core as core
    from hardspheres.core.bench import container_for, warm_up
    from hardspheres.builders import random_arrays
    from hardspheres.core.engine import Engine

    where = container_for(n, phi, box=not sphere, dimensions=dimensions)
    eng = Engine(*random_arrays(n, phi, where, seed=0), container=where)
    warm_up(eng, warm)
    before = eng.counts.copy()
    eng.advance(collisions=c, record=False)
    d = eng.counts - before
    coll = max(int(d[core.C_COLLISIONS]), 1)
    print(
        f"per collision: crossings {d[core.C_CROSSINGS] / coll:.4f}, stale {d[core.C_STALE] / coll:.4f}, "
        f"reflections {d[core.C_REFLECTIONS] / coll:.4f}"
    )


def summary(path):
    events = totals = None
    with open(path) as fh:
        for line in fh:
            if line.startswith("events:"):
                events = line.split()[1:]
            elif line.startswith("summary:"):
                totals = [int(x) for x in line.split()[1:]]
    return dict(zip(events, totals))


def ours_cmd(a, c):
    env = dict(os.environ, NUMBA_CPU_NAME="haswell", NUMBA_CPU_FEATURES=HASWELL, OPENBLAS_NUM_THREADS="1")
    env["PYTHONPATH"] = os.path.join(os.path.abspath(a.tree), "src")
    # sys.executable itself, not a launcher script valgrind would stop at
    cmd = [
        os.path.realpath(sys.executable),
        os.path.abspath(__file__),
        str(a.n),
        str(a.phi),
        "--inner",
        str(c),
    ]
    cmd += ["--warm", str(a.warm), "--dimensions", str(a.dimensions)] + (["--sphere"] if a.sphere else [])
    return cmd, env, None


def anchor_cmd(a, c):
    script = os.path.join(os.getcwd(), "..", "shared", "anchor", "anchor.sh")
    work = os.environ.get("ANCHOR_WORK", "/tmp/edmd-anchor")
    env = dict(os.environ, CFLAGS=ANCHOR_CFLAGS, ANCHOR_WORK=work)
    # builds the binary and the initial configuration (both cached by anchor.sh)
    subprocess.run(
        ["bash", script, str(a.n), str(a.phi), "1000", a.anchor], env=env, check=True, capture_output=True
    )
    tag = hashlib.md5((ANCHOR_CFLAGS + "\n").encode()).hexdigest()[:8]
    name = f"md_{a.anchor}_{tag}"
    if a.anchor == "Cell":  # anchor.sh's MAXCEL for this N and PHI, as it computes it
        side = math.exp(math.log(a.n * math.pi / 6 / a.phi) / 3)
        c = int(side - 0.0001)
        while c * c * c > 8 * a.n:
            c = int(c * 0.9)
        name = f"md_Cell_maxcel{max(c + 1, 75)}_{tag}"
    (binary,) = glob.glob(os.path.join(work, "bin", name))
    init = os.path.join(work, "init", f"n{a.n}_phi{a.phi}_s1.sph")
    return [binary, init, str(a.n), str(c)], env, tempfile.mkdtemp(prefix="cg_anchor_")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("n", type=int)
    p.add_argument("phi", type=float)
    p.add_argument("--anchor", choices=("Single", "Cell"), help="the anchor's variant instead of ours")
    p.add_argument("--c1", type=int, default=20000, help="timed collisions, first run")
    p.add_argument("--c2", type=int, default=60000, help="timed collisions, second run")
    p.add_argument("--sphere", action="store_true", help="the spherical container, not the periodic box")
    p.add_argument("--tree", default=os.getcwd(), help="the source tree whose src/ is run (default: here)")
    p.add_argument("--warm", type=float, default=10.0, help="warm-up collisions per sphere")
    p.add_argument("--ir-only", action="store_true", help="instructions only (no cache or branch simulation)")
    p.add_argument("--dimensions", type=int, default=3, choices=(2, 3), help="disks (2) or spheres (3)")
    p.add_argument(
        "--ll",
        type=int,
        default=2097152,
        help="simulated last-level cache, bytes (16-way, 64-byte lines); 33554432 is this machine's L3",
    )
    p.add_argument("--inner", type=int, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.inner is not None:
        inner(a.n, a.phi, a.inner, a.sphere, a.warm, a.dimensions)
        return
    make = anchor_cmd if a.anchor else ours_cmd
    if not a.anchor:
        cmd, env, _ = make(a, 1000)
        subprocess.run(cmd, env=env, check=True)  # compiled outside valgrind
    out = tempfile.mkdtemp(prefix="cachegrind_core_")
    procs = []
    for c in (a.c1, a.c2):
        cmd, env, cwd = make(a, c)
        dest = os.path.join(out, f"{c}.out")
        log = open(os.path.join(out, f"{c}.log"), "w")
        tool = CACHEGRIND[:2] + ["--cache-sim=no", "--branch-sim=no"] if a.ir_only else CACHEGRIND[:-1]
        tool = tool if a.ir_only else tool + [f"--LL={a.ll},16,64"]
        procs.append(
            subprocess.Popen(
                tool + [f"--cachegrind-out-file={dest}"] + cmd, env=env, cwd=cwd, stdout=log, stderr=log
            )
        )
    for proc in procs:
        if proc.wait() != 0:
            sys.exit(f"cachegrind_core: a valgrind run failed; see the logs in {out}")
    s1, s2 = summary(os.path.join(out, f"{a.c1}.out")), summary(os.path.join(out, f"{a.c2}.out"))
    d = {k: (s2[k] - s1[k]) / (a.c2 - a.c1) for k in s1}
    shape = ("circle" if a.sphere else "square") if a.dimensions == 2 else ("sphere" if a.sphere else "box")
    who = f"anchor {a.anchor}" if a.anchor else f"ours ({shape}, {a.tree})"
    line = f"{who}, N {a.n}, PHI {a.phi}, per collision: instructions {d['Ir']:.0f}"
    if "Dr" in d:
        line += (
            f", data references {d['Dr'] + d['Dw']:.0f}, L1d misses {d['D1mr'] + d['D1mw']:.1f}, "
            f"L2 misses {d['DLmr'] + d['DLmw']:.1f}, conditional branches {d['Bc']:.0f}, "
            f"mispredicted {d['Bcm']:.1f}"
        )
    if not a.anchor:
        with open(os.path.join(out, f"{a.c2}.log")) as fh:
            line += "; " + " ".join(x.strip() for x in fh if x.startswith("per collision"))
    print(line)


if __name__ == "__main__":
    main()
