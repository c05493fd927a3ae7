"""Constant pressure: mean packings and volume fluctuations against published equations of state.

Each row is one run of hardspheres.Barostat (Monte Carlo volume moves
between event-driven stretches, one move per mean free time) at fixed
``beta P sigma^d`` (diameter 1, mass 1, kT = 1):

* the hard-sphere fluid at beta P sigma^3 = 2, 5, 10 (isotropic moves, a
  cubic box, from random spheres at Hansen-Goos's packing for that
  pressure) against the inverse of Hansen-Goos's equation of state (J.
  Chem. Phys. 144, 164506 (2016)), and its volume fluctuations
  ``N <dV^2> / <V>^2`` against ``1 / (d(phi Z)/d phi)`` from the same
  equation (``<dV^2> = kT V kappa_T``);
* the FCC crystal at beta P sigma^3 = 12, 15, 20 (per-axis moves,
  ``axes="xyz"``, from the perfect crystal at Speedy's packing) against
  Speedy's crystal equation of state (J. Phys.: Condens. Matter 10, 4387
  (1998), Eq. 2 and Table 1), fluctuations likewise;
* hard disks at beta P sigma^2 = 1, 3, 6 (isotropic moves, a square box)
  against Kolafa & Rottner's hard-disk equation of state (Mol. Phys. 104,
  3435 (2006)).

After ``--equilibrate`` moves the box is sampled after each of ``--moves``
moves; the mean packing and ``N var(V) / <V>^2`` get blocked standard errors
(hardspheres.blocking), and ``z = (measured - reference) / error``. The
table says whether each blocking reached its plateau (``no``: the error is a
lower bound, run longer) and the volume's statistical inefficiency ``tau``
in moves (``n sem^2 / var`` of the packing: about twice its integrated
autocorrelation time). A move changes ``ln V`` by at most about ``3 / (N (Z
- 1))``, so the volume walks slowly: ``tau`` is a few thousand moves for the
crystal at N = 108, and 40000 moves (the default until 2026-12-02) were too
few: no plateau, and the crystal's fluctuations 2-11 of those errors low.
The references are for infinite N; the finite-N corrections of an NPT mean
are O(1/N) and are not removed. Prints a Markdown table and its running
time: about 30 minutes on one core of this (shared) machine with the
defaults (N = 108 spheres, 3 x 3 x 3 FCC cells = 108, 108 disks; 20000 +
400000 moves; the fluid and disks 18 of them, the crystal 11), 7 more for
``--only fcc --fcc-axes none``; ``--csv`` writes the rows.

usage: python3 validation/constant_pressure.py [--moves M] [--equilibrate E]
       [--only fluid,fcc,disks] [--fcc-axes xyz|none] [--csv FILE]
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from collections.abc import Callable

import numpy as np

import hardspheres as hs
from hardspheres import eos, fileio
from hardspheres.blocking import blocking
from hardspheres.builders import crystal

FLUID = (2.0, 5.0, 10.0)
FCC = (12.0, 15.0, 20.0)
DISKS = (1.0, 3.0, 6.0)


def sample(sim: hs.Simulation, equilibrate: int, moves: int) -> np.ndarray:
    """The box's volume after each of ``moves`` volume moves, after ``equilibrate`` moves."""
    bar = sim.barostat
    assert bar is not None
    bar.attach(sim)  # (its interval and step: what the runs below would fix as they start)
    sim.run(until=bar.next_time + (equilibrate - 1) * bar.every)
    vols = np.empty(moves)
    for k in range(moves):
        sim.run(until=bar.next_time)  # the move at next_time is made as the run reaches it
        vols[k] = sim.container.volume
    return vols


def score(
    name: str, bp: float, sim: hs.Simulation, vols: np.ndarray, ref_phi: float, ref_k: float, wall: float
) -> dict[str, float | str]:
    """One row: mean packing and fluctuations with errors and z against the references."""
    solid = sim.packing * sim.container.volume
    phi = solid / vols
    b = blocking(phi)
    n = sim.n
    vbar = float(vols.mean())
    q = n * (vols - vbar) ** 2 / vbar**2
    bq = blocking(q)
    bar = sim.barostat
    assert bar is not None
    var = float(np.var(phi))
    return {
        "system": name,
        "betaP": bp,
        "N": n,
        "packing": float(b.mean),
        "packing_err": float(b.sem),
        "packing_ref": ref_phi,
        "z_packing": float((b.mean - ref_phi) / b.sem),
        "fluct": float(bq.mean),
        "fluct_err": float(bq.sem),
        "fluct_ref": 1.0 / ref_k,
        "z_fluct": float((bq.mean - 1.0 / ref_k) / bq.sem),
        "plateau": ("yes" if b.converged else "no") + "/" + ("yes" if bq.converged else "no"),
        "tau_moves": float(len(phi) * b.sem**2 / var) if var > 0 else math.nan,
        "moves": len(phi),
        "acceptance": bar.acceptance,
        "wall_s": wall,
    }


def fluid(bp: float, n: int, equilibrate: int, moves: int, seed: int = 1) -> dict[str, float | str]:
    t0 = time.time()
    phi0 = eos.packing_at_pressure(bp)
    box = hs.PeriodicBox.for_packing(n, phi0)
    sim = hs.Simulation(hs.random_spheres(n, phi0, box=box.length, seed=seed), box)
    sim.run(collisions=20 * n)  # the lattice melts
    sim.set_barostat(hs.Barostat(pressure=bp, kT=1.0, seed=seed))
    vols = sample(sim, equilibrate, moves)
    return score("fluid", bp, sim, vols, phi0, float(eos.inverse_compressibility(phi0)), time.time() - t0)


def fcc(
    bp: float,
    cells: tuple[int, int, int],
    equilibrate: int,
    moves: int,
    seed: int = 1,
    axes: str | None = "xyz",
) -> dict[str, float | str]:
    t0 = time.time()
    bounds = (0.5, 0.74)
    phi0 = eos.packing_at_pressure(bp, eos.speedy_fcc, bounds)
    state, box = crystal("fcc", cells, phi0, seed=seed)
    sim = hs.Simulation(state, box)
    sim.set_barostat(hs.Barostat(pressure=bp, kT=1.0, axes=axes, seed=seed))
    vols = sample(sim, equilibrate, moves)
    k = float(eos.inverse_compressibility(phi0, eos.speedy_fcc))
    return score("FCC" if axes is None else f"FCC ({axes})", bp, sim, vols, phi0, k, time.time() - t0)


def disks(bp: float, n: int, equilibrate: int, moves: int, seed: int = 1) -> dict[str, float | str]:
    t0 = time.time()
    phi0 = eos.packing_at_pressure(bp, eos.kolafa_rottner, (0.0, 0.70), dimensions=2)
    side = math.sqrt(n * math.pi / (4.0 * phi0))
    box = hs.PeriodicBox((side, side))
    sim = hs.Simulation(hs.random_spheres(n, phi0, box, seed=seed), box)
    sim.run(collisions=20 * n)
    sim.set_barostat(hs.Barostat(pressure=bp, kT=1.0, seed=seed))
    vols = sample(sim, equilibrate, moves)
    k = float(eos.inverse_compressibility(phi0, eos.kolafa_rottner))
    return score("disks", bp, sim, vols, phi0, k, time.time() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--moves", type=int, default=400000, help="volume moves sampled per row")
    ap.add_argument("--equilibrate", type=int, default=20000, help="volume moves before sampling")
    ap.add_argument("--n", type=int, default=108, help="spheres of the fluid, disks likewise")
    ap.add_argument("--cells", type=int, default=3, help="FCC cells per side (4 spheres each)")
    ap.add_argument("--only", default="fluid,fcc,disks")
    ap.add_argument(
        "--fcc-axes", default="xyz", help="the crystal's moves: 'xyz' (per side) or 'none' (isotropic)"
    )
    ap.add_argument("--csv")
    args = ap.parse_args()
    t0 = time.time()
    runs: list[Callable[[], dict[str, float | str]]] = []
    which = args.only.split(",")
    if "fluid" in which:
        runs += [lambda bp=bp: fluid(bp, args.n, args.equilibrate, args.moves) for bp in FLUID]
    if "fcc" in which:
        runs += [
            lambda bp=bp: fcc(
                bp,
                (args.cells,) * 3,
                args.equilibrate,
                args.moves,
                axes=None if args.fcc_axes == "none" else args.fcc_axes,
            )
            for bp in FCC
        ]
    if "disks" in which:
        runs += [lambda bp=bp: disks(bp, args.n, args.equilibrate, args.moves) for bp in DISKS]
    print(
        "| system | beta P | N | mean packing | +- | reference | z | N var(V)/<V>^2 | +- | reference | z "
        "| plateau | tau (moves) | moves | acceptance | wall s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for run in runs:
        r = run()
        rows.append(r)
        print(
            "| {system} | {betaP:g} | {N} | {packing:.5f} | {packing_err:.5f} | {packing_ref:.5f} | "
            "{z_packing:+.2f} | {fluct:.4f} | {fluct_err:.4f} | {fluct_ref:.4f} | {z_fluct:+.2f} | "
            "{plateau} | {tau_moves:.0f} | {moves} | {acceptance:.2f} | {wall_s:.0f} |".format(**r),
            flush=True,
        )
    print(f"\n{args.equilibrate} + {args.moves} volume moves per row; total {time.time() - t0:.0f} s")
    if args.csv:
        with fileio.atomic_write(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
