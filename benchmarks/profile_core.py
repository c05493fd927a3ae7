"""Where the event core spends its time: perf samples mapped into its machine code.

numba's machine code has no symbols that ``perf report`` could show, so this
script runs a warmed-up engine under ``perf record -e cpu-clock`` (a software
clock: it works on machines without hardware counters), copies the memory
region that holds the compiled event loop (``_core.run``, its helpers
inlined), disassembles it with objdump and counts the samples per instruction.
It prints the share of samples in the core, the hottest 64-byte blocks, and
the annotated instructions around the hottest ones (``--show K``).  A load
that misses the cache shows up as samples on the instructions just after it.

usage:
    python3 benchmarks/profile_core.py N PHI [--sphere] [--collisions C] [--show K]

(Run from the project's root; needs perf and objdump.  Everything below runs
in one process, which perf follows: ``--inner`` is that process.)
"""

import argparse
import collections
import ctypes
import os
import subprocess
import sys
import tempfile
import time


def inner(a, out):

    from hardspheres.core import _core as core
    from hardspheres.core.bench import container_for, warm_up
    from hardspheres.builders import random_arrays
    from hardspheres.core.engine import Engine

    n, phi = a.n, a.packing
    where = container_for(n, phi, box=not a.sphere)
    eng = Engine(*random_arrays(n, phi, where, seed=0), container=where)
    warm_up(eng, 10)
    cres = list(core.run.overloads.values())[0]
    ptr = cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)
    with open("/proc/self/maps") as fh:
        for line in fh:
            lo, hi = (int(x, 16) for x in line.split()[0].split("-"))
            if lo <= ptr < hi:
                break
    with open(os.path.join(out, "code.bin"), "wb") as fh:
        fh.write(ctypes.string_at(lo, hi - lo))
    c0 = eng.counters
    t = time.process_time()
    eng.advance(collisions=a.collisions, record=False)
    cpu = time.process_time() - t
    c1 = eng.counters
    per = {k: (c1[k] - c0[k]) / a.collisions for k in ("crossings", "stale", "reflections")}
    with open(os.path.join(out, "region.txt"), "w") as fh:
        fh.write(f"{lo} {hi - lo} {cpu / a.collisions * 1e6} {per}\n")


def outer(a):
    out = tempfile.mkdtemp(prefix="profile_core_")
    data = os.path.join(out, "perf.data")
    cmd = [
        sys.executable,
        __file__,
        str(a.n),
        str(a.packing),
        "--collisions",
        str(a.collisions),
        "--inner",
        out,
    ]
    cmd += ["--sphere"] if a.sphere else []
    subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-o", data, "--"] + cmd, check=True)
    with open(os.path.join(out, "region.txt")) as fh:
        lo, size, us, per = fh.read().split(" ", 3)
    lo, size = int(lo), int(size)
    ips = subprocess.run(["perf", "script", "-i", data, "-F", "ip"], capture_output=True, text=True).stdout
    ips = [int(x, 16) for x in ips.split()]
    inside = collections.Counter(ip - lo for ip in ips if lo <= ip < lo + size)
    total = sum(inside.values())
    where = "sphere" if a.sphere else "box"
    print(f"{a.n} spheres, packing {a.packing}, {where}: {float(us):.3f} us CPU per collision")
    print(f"per collision: {per.strip()}")
    print(f"samples: {len(ips)}, in the core's code: {total} ({total / max(len(ips), 1):.0%})")
    blocks = collections.Counter()
    for off, k in inside.items():
        blocks[off // 64 * 64] += k
    print("hottest 64-byte blocks (offset: share of the core's samples):")
    print("  " + "  ".join(f"{b:x}: {k / total:.1%}" for b, k in blocks.most_common(24)))
    asm = subprocess.run(
        ["objdump", "-D", "-b", "binary", "-m", "i386:x86-64", os.path.join(out, "code.bin")],
        capture_output=True,
        text=True,
    ).stdout
    rows = []
    for line in asm.splitlines():
        head, _, rest = line.partition(":")
        try:
            off = int(head.strip(), 16)
        except ValueError:
            continue
        text = rest.split("\t")[-1].strip()
        if text and not (len(text) <= 3 and text[0].isdigit()):
            rows.append((off, text))
    for b, _ in blocks.most_common(a.show):
        print(f"--- block {b:x}: {blocks[b] / total:.1%}")
        for off, text in rows:
            if b - 32 <= off < b + 96:
                print(f"{inside.get(off, 0):6d} {off:6x}  {text}")
    print(f"(perf data and code in {out})")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("n", type=int)
    p.add_argument("packing", type=float)
    p.add_argument("--sphere", action="store_true", help="spherical container (default: periodic box)")
    p.add_argument("--collisions", type=int, default=2_000_000)
    p.add_argument("--show", type=int, default=3, help="annotate the K hottest blocks")
    p.add_argument("--inner", help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.inner:
        inner(a, a.inner)
    else:
        outer(a)


if __name__ == "__main__":
    main()
