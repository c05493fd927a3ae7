"""Hard disks' Z at area fraction 0.1 to 0.65 against Kolafa & Rottner's equation of state.

N = 10^4 equal disks (diameter 1, mass 1, kT = 1) in a square periodic box,
from random disks (hardspheres.random_spheres), 200 collisions per disk to
equilibrate, then ``--collisions`` collisions measured (default 1.5x10^7);
Z from the collision virial with its blocked standard error
(hardspheres.observables), scored by ``z = (Z - Z_KR) / error`` against
hardspheres.eos.kolafa_rottner (Mol. Phys. 104, 3435 (2006), extrapolated
to infinite N; its own error is below 2e-5 relative here and is neglected).
Prints a Markdown table, the largest |z| and relative error, and its running
time (about 6-8 min on one core of this machine, shared); ``--csv`` writes it.

usage: python3 validation/disks_eos.py [--collisions M] [--csv FILE]
"""

import argparse
import csv
import math
import time

import hardspheres as hs
from hardspheres import eos, fileio

PACKINGS = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.65)
N = 10000


def measure(phi: float, collisions: int, seed: int = 1) -> tuple[float, float, float]:
    """Z, its standard error and the wall time of one run at area fraction ``phi``."""
    t0 = time.time()
    side = math.sqrt(N * math.pi / (4.0 * phi))
    box = hs.PeriodicBox((side, side))
    sim = hs.Simulation(hs.random_spheres(N, phi, box, seed=seed), box)
    sim.run(collisions=200 * N)
    obs = sim.observables.reset()
    sim.run(collisions=collisions)
    return obs.Z(), obs.error("Z"), time.time() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--collisions", type=int, default=15_000_000)
    ap.add_argument("--csv")
    args = ap.parse_args()
    t0 = time.time()
    rows = []
    print("| area fraction | Z | +- | relative error | Z (Kolafa-Rottner) | z | wall s |")
    print("|---|---|---|---|---|---|---|")
    for phi in PACKINGS:
        z, err, wall = measure(phi, args.collisions)
        ref = float(eos.kolafa_rottner(phi))
        rows.append((phi, z, err, err / z, ref, (z - ref) / err, wall))
        print(
            "| {:.2f} | {:.5f} | {:.5f} | {:.3%} | {:.5f} | {:+.2f} | {:.0f} |".format(*rows[-1]), flush=True
        )
    worst = max(rows, key=lambda r: abs(r[5]))
    print(f"\nN = {N}, {args.collisions} collisions measured per packing after {200 * N}")
    print(
        f"largest |z| {abs(worst[5]):.2f} (area fraction {worst[0]}); largest relative error "
        f"{max(r[3] for r in rows):.3%}"
    )
    print(f"running time: {time.time() - t0:.0f} s")
    if args.csv:
        with fileio.atomic_write(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["phi", "Z", "error", "relative_error", "Z_KR", "z", "wall_s"])
            w.writerows(rows)


if __name__ == "__main__":
    main()
