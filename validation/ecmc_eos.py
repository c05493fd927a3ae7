"""The event-chain pressure of fluid disks and spheres against our event dynamics and the equations of state.

Six fluids: disks at area fraction 0.3, 0.5 and 0.65 (N = 400, square
periodic box) and spheres at packing 0.2, 0.35 and 0.45 (N = 500, cubic
periodic box), diameter 1, kT = 1, from random spheres
(hardspheres.random_spheres, the same start for both engines).  For each:

* straight event chains (hs.EventChain, seed 1): ``--equilibrate`` lifts
  per sphere, then ``--lifts`` lifts per sphere measured; Z from the chains
  (Li et al., J. Chem. Phys. 157, 234111 (2022), Eq. 20-21) with its
  blocking error;
* event-driven dynamics (hs.Simulation): 200 collisions per sphere, then
  ``--collisions`` collisions per sphere measured; Z from the collision
  virial with its blocking error.

Scores, ``z = difference / combined standard error``:

* ECMC against EDMD at the same N and box (both finite-N canonical-like
  ensembles);
* ECMC against the equation of state the project uses (disks:
  hardspheres.eos.kolafa_rottner, J. Kolafa and M. Rottner, Mol. Phys. 104,
  3435 (2006); spheres: hardspheres.eos.hansen_goos, H. Hansen-Goos, J.
  Chem. Phys. 144, 164506 (2016)), both infinite-N, corrected to N by the
  canonical ensemble's 1/N term (docs/numerics.md, "The pressure of N spheres
  at constant volume"): ``Z_N = Z - phi K'(phi) / (2 N K(phi))``,
  ``K = d(phi Z)/d phi``.  The uncorrected z is printed too.  The
  equations' own errors (below 1e-4 relative) are neglected.

CPU seconds (process time) per run are printed and kept.  Results go to
``--out`` (default validation/results/ecmc_eos), a ``.csv`` and a ``.md``,
each written atomically.

usage: nice -n 10 python3 validation/ecmc_eos.py [--lifts M] [--collisions M] [--out STEM]
"""

from __future__ import annotations

import argparse
import csv
import math
import time

import hardspheres as hs
from hardspheres import eos, fileio

#: (dimensions, packing, N)
CASES = ((2, 0.30, 400), (2, 0.50, 400), (2, 0.65, 400), (3, 0.20, 500), (3, 0.35, 500), (3, 0.45, 500))


def reference(d: int) -> tuple[str, object]:
    """The equation of state for ``d`` dimensions: its name and function of the packing."""
    return ("Kolafa-Rottner", eos.kolafa_rottner) if d == 2 else ("Hansen-Goos", eos.hansen_goos)


def ensemble_term(d: int, phi: float, n: int, h: float = 1e-4) -> float:
    """``Z_N - Z``, the canonical 1/N term: ``-phi K'(phi) / (2 N K(phi))``, ``K = d(phi Z)/d phi``."""
    f = reference(d)[1]

    def k(p: float) -> float:
        return ((p + h) * float(f(p + h)) - (p - h) * float(f(p - h))) / (2 * h)

    dk = (k(phi + h) - k(phi - h)) / (2 * h)
    return -phi * dk / (2.0 * n * k(phi))


def run_chains(
    d: int, phi: float, n: int, equilibrate: int, lifts: int, seed: int = 1
) -> tuple[float, float, bool, float]:
    """Z, its error, whether the blocking converged, CPU seconds: straight event chains."""
    box = hs.PeriodicBox.for_packing(n, phi, (1.0,) * d)
    chain = hs.EventChain(hs.random_spheres(n, phi, box, seed=seed), box, seed=seed)
    t0 = time.process_time()
    chain.run(events=equilibrate * n)
    chain.observables.reset()
    chain.run(events=lifts * n)
    est = chain.observables.estimate("Z")
    return est.mean, est.sem, bool(est.converged), time.process_time() - t0


def run_dynamics(
    d: int, phi: float, n: int, collisions: int, seed: int = 1
) -> tuple[float, float, bool, float]:
    """Z, its error, whether the blocking converged, CPU seconds: event-driven dynamics."""
    box = hs.PeriodicBox.for_packing(n, phi, (1.0,) * d)
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=seed), box)
    t0 = time.process_time()
    sim.run(collisions=200 * n)
    obs = sim.observables.reset()
    sim.run(collisions=collisions * n)
    est = obs.estimate("Z")
    return est.mean, est.sem, bool(est.converged), time.process_time() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--equilibrate", type=int, default=2000, help="lifts per sphere before measuring")
    ap.add_argument(
        "--lifts", type=int, default=0, help="lifts per sphere measured (default 5e5 disks, 1.2e5 spheres)"
    )
    ap.add_argument(
        "--collisions", type=int, default=0, help="collisions per sphere (default 1e5 disks, 5e4 spheres)"
    )
    ap.add_argument("--out", default="validation/results/ecmc_eos")
    args = ap.parse_args()
    rows = []
    header = (
        "| d | packing | N | Z (ECMC) | Z (EDMD) | z ECMC-EDMD | equation | Z (equation, N) "
        "| z ECMC-equation | z uncorrected | CPU s ECMC | CPU s EDMD |"
    )
    lines = [header, "|" + "---|" * 12]
    print("\n".join(lines), flush=True)
    for d, phi, n in CASES:
        lifts = args.lifts or (500_000 if d == 2 else 120_000)
        coll = args.collisions or (100_000 if d == 2 else 50_000)
        zc, ec, cc, tc = run_chains(d, phi, n, args.equilibrate, lifts)
        zm, em, cm, tm = run_dynamics(d, phi, n, coll)
        name, f = reference(d)
        z_inf = float(f(phi))
        z_n = z_inf + ensemble_term(d, phi, n)
        row = {
            "d": d,
            "packing": phi,
            "N": n,
            "lifts_per_sphere": lifts,
            "collisions_per_sphere": coll,
            "Z_ecmc": zc,
            "err_ecmc": ec,
            "converged_ecmc": cc,
            "Z_edmd": zm,
            "err_edmd": em,
            "converged_edmd": cm,
            "z_ecmc_edmd": (zc - zm) / math.hypot(ec, em),
            "equation": name,
            "Z_equation": z_inf,
            "Z_equation_N": z_n,
            "z_ecmc_equation": (zc - z_n) / ec,
            "z_ecmc_equation_uncorrected": (zc - z_inf) / ec,
            "z_edmd_equation": (zm - z_n) / em,
            "cpu_s_ecmc": tc,
            "cpu_s_edmd": tm,
        }
        rows.append(row)
        line = (
            f"| {d} | {phi:.2f} | {n} | {zc:.5f}({round(ec * 1e5)}){'' if cc else '*'} "
            f"| {zm:.5f}({round(em * 1e5)}){'' if cm else '*'} | {row['z_ecmc_edmd']:+.2f} | {name} "
            f"| {z_n:.5f} | {row['z_ecmc_equation']:+.2f} | {row['z_ecmc_equation_uncorrected']:+.1f} "
            f"| {tc:.0f} | {tm:.0f} |"
        )
        lines.append(line)
        print(line, flush=True)
    worst_md = max(abs(r["z_ecmc_edmd"]) for r in rows)
    worst_eq = max(abs(r["z_ecmc_equation"]) for r in rows)
    total = sum(r["cpu_s_ecmc"] + r["cpu_s_edmd"] for r in rows)
    notes = [
        "",
        "Z(n) is Z with its blocking error in the last digits (5th decimal); * marks a blocking error "
        "that did not reach its plateau (a lower bound).",
        f"largest |z| ECMC against EDMD {worst_md:.2f}; against the equations (1/N term) {worst_eq:.2f}",
        f"CPU seconds in all: {total:.0f}",
    ]
    print("\n".join(notes))
    lines += notes
    with fileio.atomic_write(args.out + ".csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with fileio.atomic_write(args.out + ".md", "w") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
