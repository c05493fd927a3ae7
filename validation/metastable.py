"""The metastable fluid at packing 0.54: Z against time after the compression.

    python validation/metastable.py OUT.csv N PHI RATE:SEED [RATE:SEED ...]

For each compression history (rate, seed): a fluid of N equal spheres at
0.3 (box, kT = 1) is compressed to PHI at that rate, then run in blocks of
25 collisions per sphere for 2000 collisions per sphere; each block's Z
(collision virial) is written with the collisions per sphere since the end
of the compression, and every 8th block the crystal-like fraction (freud,
12 neighbours).  docs/validation/dense.md quotes the summary this
prints (Z over windows of the run, with the standard error of the window's
block means from their spread, blocks of 100 collisions per sphere).
"""

import math
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres import eos

BLOCK = 25  # collisions per sphere per block
TOTAL = 2000  # collisions per sphere after the compression
WINDOWS = ((0, 200), (200, 700), (700, 2000), (200, 2000))


def history(n, phi, rate, seed):
    L = (n * 4.0 / 3.0 * math.pi / 0.3) ** (1.0 / 3.0)
    sim = hs.Simulation(hs.random_spheres(n, 0.3, box=L, seed=seed), hs.PeriodicBox(L))
    sim.run(collisions=5 * n)
    t0 = time.perf_counter()
    c0 = sim.counters["collisions"]
    sim.compress(packing=phi, rate=rate)
    c_comp = sim.counters["collisions"] - c0
    rows = []
    order = hs.BondOrder(num_neighbors=12)
    for k in range(TOTAL // BLOCK):
        sim.observables.reset()
        sim.run(collisions=BLOCK * n)
        xtal = order.compute(sim).crystal_fraction if k % 8 == 7 else math.nan
        rows.append(((k + 1) * BLOCK, sim.observables.compressibility(), xtal))
    return rows, c_comp, time.perf_counter() - t0


def window(rows, a, b, per=4):
    """Mean Z over blocks ending in (a, b], and its error from blocks of ``per`` blocks."""
    z = np.array([r[1] for r in rows if a < r[0] <= b])
    z = z[: len(z) // per * per].reshape(-1, per).mean(axis=1)
    return z.mean(), z.std(ddof=1) / math.sqrt(len(z))


if __name__ == "__main__":
    out, n, phi, *hist = sys.argv[1:]
    n, phi = int(n), float(phi)
    klm, hg = float(eos.kolafa(phi)), float(eos.hansen_goos(phi))
    with open(out, "w") as fh:
        fh.write("rate,seed,collisions_per_sphere,Z,crystal_fraction\n")
    print(f"phi {phi}: KLM {klm:.4f}, Hansen-Goos {hg:.4f}")
    print(
        "| rate | seed | compression collisions | "
        + " | ".join(f"Z, {a}-{b} coll/sphere" for a, b in WINDOWS)
        + " | crystal-like at end | wall s |"
    )
    print("|---" * (5 + len(WINDOWS)) + "|")
    for h in hist:
        rate, seed = float(h.split(":")[0]), int(h.split(":")[1])
        rows, c_comp, wall = history(n, phi, rate, seed)
        with open(out, "a") as fh:
            fh.writelines(f"{rate},{seed},{c},{z:.6f},{x:.4f}\n" for c, z, x in rows)
        cells = []
        for a, b in WINDOWS:
            z, s = window(rows, a, b)
            cells.append(f"{z:.3f} ± {s:.3f} ({(z - klm) / s:+.1f} σ KLM)")
        xt = [r[2] for r in rows if not math.isnan(r[2])][-1]
        print(
            f"| {rate:g} | {seed} | {c_comp} | " + " | ".join(cells) + f" | {xt:.2f} | {wall:.0f} |",
            flush=True,
        )
