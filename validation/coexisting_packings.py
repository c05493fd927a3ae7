"""The two coexisting packings at the coexistence pressure, each phase in bulk.

At ``beta P sigma^3 = 11.5727`` (Fernandez, Martin-Mayor, Seoane and
Verrocchio, Phys. Rev. Lett. 108, 165701 (2012)), each phase alone in a
periodic box, two ways:

* ``--npt`` (constant pressure, hardspheres.Barostat, one volume move per
  mean free time): the FCC crystal with every side free (``axes="xyz"``: a
  random side per move, so its lattice takes whatever shape and spacing the
  pressure gives it), from the perfect crystal at Speedy's packing at P; the
  fluid with isotropic moves, from random spheres at Hansen-Goos's packing
  at P, melted.  The mean packing after ``--equilibrate`` moves over
  ``--moves`` moves, its blocked standard error (hardspheres.blocking), as
  validation/constant_pressure.py does.
* ``--nvt`` (constant volume, the default): the collision virial's pressure
  at three packings around each phase's coexisting one (``--crystal``,
  ``--fluid``), N = 4000 each (10 x 10 x 10 FCC cells; the fluid placed at
  0.42, melted and compressed: hardspheres.analysis.coexistence's
  equilibrated_fluid, since random spheres start on a lattice, which does
  not melt at 0.49), each with its blocked standard error, and the packing
  at which the quadratic through them reaches P (the equation of state's
  inverse); its error propagated from the three pressures' errors.  For
  the cubic crystal in a cubic box the stress is isotropic by symmetry
  (the script prints P_xx, P_yy, P_zz), so free sides change its mean
  shape in nothing and this is the packing the constant-pressure run
  measures, in far less time: the volume moves' random walk needs about N
  moves per independent sample (validation/constant_pressure.py), the
  virial none.

``z = (measured - quoted) / error`` against the coexisting packings the
project quotes for that paper (:data:`PHI_FLUID`, :data:`PHI_SOLID`: see
there), and against the project's equations of state at P (Hansen-Goos's
fluid, Speedy's crystal: hardspheres.eos).  The references are for infinite
N; the runs' corrections are O(1/N) and not removed.  Prints the rows and
the running time; ``--csv`` writes them, ``--rescore CSV ...`` prints the
table of such files again (with the references as they are now), and
``--refit LOG`` fits the virial lines of a ``--nvt`` run's log again (the
run of 2026-12-02 printed a straight line's fit, which the curvature biases
by 6e-5; its points are refitted so: docs/validation/coexistence.md).

usage: python3 validation/coexisting_packings.py [--nvt] [--npt] [--only FCC,fluid] [--cells C] [--n N]
       [--moves M] [--equilibrate E] [--time T] [--crystal PHI ...] [--fluid PHI ...] [--csv FILE]
       python3 validation/coexisting_packings.py --rescore CSV ... | --refit LOG
"""

from __future__ import annotations

import argparse
import csv
import math
import re
import time

import numpy as np

import hardspheres as hs
from hardspheres import eos, fileio
from hardspheres.analysis.coexistence import equilibrated_fluid
from hardspheres.blocking import blocking
from hardspheres.builders import crystal

#: Coexistence pressure: Fernandez, Martin-Mayor, Seoane and Verrocchio, PRL 108, 165701
#: (2012), its abstract (arXiv:1103.2599).
P_COEX = 11.5727
#: The coexisting packings (fluid, solid) commonly quoted with that pressure
#: (validation/coexistence.py): rho sigma^3 = 0.9391 and 1.0376 (``packing = pi/6 rho``).  Not
#: the paper's: its abstract gives the pressure and the interfacial free energy.  No errors
#: are quoted with them.
PHI_FLUID, PHI_SOLID = 0.4917, 0.5433

FIELDS = ["method", "phase", "N", "packing", "packing_err", "published", "z", "eos", "z_eos"]
FIELDS += ["note", "wall_s"]


def _eos_packing(phase: str) -> float:
    """The packing at P_COEX by the project's equations of state: Speedy's crystal, Hansen-Goos's fluid."""
    if phase == "FCC":
        return eos.packing_at_pressure(P_COEX, eos.speedy_fcc, (0.5, 0.74))
    return eos.packing_at_pressure(P_COEX)


def _row(method: str, phase: str, n: int, phi: float, err: float, note: str, wall: float) -> dict:
    ref = PHI_SOLID if phase == "FCC" else PHI_FLUID
    ref_eos = _eos_packing(phase)
    return dict(
        method=method,
        phase=phase,
        N=n,
        packing=phi,
        packing_err=err,
        published=ref,
        z=(phi - ref) / err,
        eos=ref_eos,
        z_eos=(phi - ref_eos) / err,
        note=note,
        wall_s=wall,
    )


def _root(x: np.ndarray, y: np.ndarray, w: np.ndarray) -> float:
    """Where the weighted least-squares polynomial (quadratic from 3 points, else a line) reaches P_COEX."""
    deg = min(2, len(x) - 1)
    x0 = float(np.mean(x))
    c = np.polyfit(x - x0, y, deg, w=np.sqrt(w))
    c[-1] -= P_COEX
    roots = np.roots(c)
    roots = roots[np.isreal(roots)].real + x0
    return float(roots[np.argmin(np.abs(roots - x0))])


def _fluid(n: int, phi: float, seed: int) -> hs.Simulation:
    """A melted fluid of about ``n`` spheres at ``phi`` in a cube.

    Random spheres start on lattice sites, which at 0.49 do not melt
    (the crystal is stable there); equilibrated_fluid places them at 0.42,
    melts them and compresses them to ``phi`` (Lubachevsky-Stillinger).
    """
    side = (n * math.pi / 6.0 / phi) ** (1.0 / 3.0)
    x = equilibrated_fluid((side,) * 3, phi, seed=seed)
    m = len(x)
    v = np.random.default_rng(seed).normal(size=(m, 3))
    v -= v.mean(axis=0)
    v *= math.sqrt(3.0 * (m - 1) / float(np.sum(v * v)))  # kT = 1 exactly
    return hs.Simulation(hs.State.from_arrays(np.ones(m), np.full(m, 0.5), x, v), hs.PeriodicBox(side))


def nvt(phase: str, packings: list[float], args: argparse.Namespace) -> dict:
    """The packing at which the virial's P(phi) at ``packings`` (interpolated) is P_COEX."""
    t0 = time.time()
    ps, es = [], []
    for phi in packings:
        t1 = time.time()
        if phase == "FCC":
            state, box = crystal("fcc", (args.cells,) * 3, phi, seed=args.seed)
            sim = hs.Simulation(state, box)
        else:
            sim = _fluid(args.n, phi, args.seed)
        sim.run(until=sim.time + args.settle)
        sim.observables.reset()
        sim.run(until=sim.time + args.time)
        obs = sim.observables
        kt = obs.temperature()  # constant at constant volume (no thermostat): beta P = P / kT
        est = obs.estimate("pressure")
        diag = np.diag(obs.pressure_tensor()) / kt
        ps.append(est.mean / kt)
        es.append(est.sem / kt)
        print(
            f"  {phase} N {sim.n} packing {phi:.4f}: beta P sigma^3 = {ps[-1]:.4f} +- {es[-1]:.4f}"
            f" (plateau {'yes' if est.converged else 'no'}; P_xx, P_yy, P_zz {diag[0]:.3f} {diag[1]:.3f} "
            f"{diag[2]:.3f}; kT {kt:.6f}; {args.time:g} time units, {time.time() - t1:.0f} s)",
            flush=True,
        )
    n = 4 * args.cells**3 if phase == "FCC" else args.n
    return _fitted(phase, n, packings, ps, es, time.time() - t0)


def _fitted(phase: str, n: int, packings: list[float], ps: list[float], es: list[float], wall: float) -> dict:
    """The row: where the virial's pressures ``ps`` (errors ``es``) at ``packings`` reach P_COEX."""
    x, y, e = np.array(packings), np.array(ps), np.array(es)
    w = 1.0 / e**2
    phi = _root(x, y, w)
    # the error: each packing's run is independent, so d phi = sum_i (d phi / d P_i) dP_i
    grad = np.empty(len(x))
    for i in range(len(x)):
        dy = np.zeros(len(x))
        dy[i] = e[i]
        grad[i] = _root(x, y + dy, w) - phi
    err = float(np.sqrt(np.sum(grad**2)))
    slope = float(np.polyval(np.polyder(np.polyfit(x, y, min(2, len(x) - 1))), phi))
    note = (
        f"NVT virial at {', '.join(f'{p:.4f}' for p in packings)}; "
        f"{'quadratic' if len(x) > 2 else 'line'} through them, d(beta P)/d phi = {slope:.1f} there"
    )
    return _row("constant volume", phase, n, phi, err, note, wall)


#: A virial line of the log: ``  FCC N 4000 packing 0.5390: beta P sigma^3 = 11.2487 +- 0.0028 (... 38 s)``.
_POINT = re.compile(
    r"^\s+(FCC|fluid) N (\d+) packing ([\d.]+): beta P sigma\^3 = ([\d.]+) \+- ([\d.]+) .*, (\d+) s\)$"
)


def refit(log: str) -> list[dict]:
    """The constant-volume rows again from the virial lines of a ``--nvt`` log (4 decimals)."""
    points: dict[str, list[tuple[int, float, float, float, float]]] = {}
    with open(log) as fh:
        for line in fh:
            m = _POINT.match(line.rstrip("\n"))
            if m:
                phase, n, phi, p, e, wall = m.groups()
                points.setdefault(phase, []).append((int(n), float(phi), float(p), float(e), float(wall)))
    return [
        _fitted(
            phase,
            pts[0][0],
            [q[1] for q in pts],
            [q[2] for q in pts],
            [q[3] for q in pts],
            sum(q[4] for q in pts),
        )
        for phase, pts in points.items()
    ]


def npt(phase: str, args: argparse.Namespace) -> dict:
    """Mean packing at P_COEX at constant pressure: FCC with every side free, the fluid isotropic."""
    t0 = time.time()
    if phase == "FCC":
        phi0 = eos.packing_at_pressure(P_COEX, eos.speedy_fcc, (0.5, 0.74))
        state, box = crystal("fcc", (args.cells,) * 3, phi0, seed=args.seed)
        sim = hs.Simulation(state, box)
        axes: str | None = "xyz"
    else:
        phi0 = eos.packing_at_pressure(P_COEX)
        sim = _fluid(args.n, phi0, args.seed)
        axes = None
    sim.set_barostat(hs.Barostat(pressure=P_COEX, kT=1.0, axes=axes, seed=args.seed))
    bar = sim.barostat
    assert bar is not None
    bar.attach(sim)
    sim.run(until=bar.next_time + (args.equilibrate - 1) * bar.every)
    vols = np.empty(args.moves)
    shape = np.empty((args.moves, 3))
    for k in range(args.moves):
        sim.run(until=bar.next_time)  # the move at next_time is made as the run reaches it
        vols[k] = sim.container.volume
        shape[k] = sim.container.sides
    solid = sim.packing * sim.container.volume
    b = blocking(solid / vols)
    var = float(np.var(solid / vols))
    tau = len(vols) * b.sem**2 / var if var > 0 else math.nan
    sides = shape.mean(axis=0)
    note = (
        f"NPT {'every side free' if axes else 'isotropic'}, from {phi0:.4f}; "
        f"{args.equilibrate} + {args.moves} moves,"
        f" plateau {'yes' if b.converged else 'no'}, tau {tau:.0f} moves, acceptance {bar.acceptance:.2f};"
        f" mean sides {sides[0]:.4f} {sides[1]:.4f} {sides[2]:.4f}"
    )
    return _row("constant pressure", phase, sim.n, float(b.mean), float(b.sem), note, time.time() - t0)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--nvt", action="store_true", help="the virial at constant volume (the default)")
    ap.add_argument("--npt", action="store_true", help="constant pressure (slow: about N moves a sample)")
    ap.add_argument("--only", default="FCC,fluid", help="phases: FCC, fluid or both")
    ap.add_argument("--cells", type=int, default=10, help="FCC cells per side (4 spheres each)")
    ap.add_argument("--n", type=int, default=4000, help="spheres of the fluid")
    ap.add_argument("--crystal", type=float, nargs="+", default=[0.539, 0.543, 0.547])
    ap.add_argument("--fluid", type=float, nargs="+", default=[0.4875, 0.4915, 0.4955])
    ap.add_argument("--settle", type=float, default=5.0, help="time before the virial's average")
    ap.add_argument("--time", type=float, default=200.0, help="time of each virial average")
    ap.add_argument("--moves", type=int, default=300000, help="volume moves sampled (--npt)")
    ap.add_argument("--equilibrate", type=int, default=20000, help="volume moves first (--npt)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--csv")
    ap.add_argument("--rescore", nargs="+", metavar="CSV", help="print the table of these --csv files")
    ap.add_argument("--refit", metavar="LOG", help="the --nvt rows again from the virial lines of its log")
    args = ap.parse_args()
    t0 = time.time()
    phases = args.only.split(",")
    rows = []
    if args.refit:
        rows = refit(args.refit)
    elif args.rescore:
        for path in args.rescore:
            with open(path, newline="") as fh:
                for r in csv.DictReader(fh):
                    rows.append(
                        _row(
                            r["method"],
                            r["phase"],
                            int(r["N"]),
                            float(r["packing"]),
                            float(r["packing_err"]),
                            r["note"],
                            float(r["wall_s"]),
                        )
                    )
    elif args.nvt or not args.npt:
        for phase in phases:
            rows.append(nvt(phase, args.crystal if phase == "FCC" else args.fluid, args))
    if args.npt and not (args.rescore or args.refit):
        for phase in phases:
            rows.append(npt(phase, args))
            print(f"  {rows[-1]['note']} ({rows[-1]['wall_s']:.0f} s)", flush=True)
    print(f"\nbeta P sigma^3 = {P_COEX} (Fernandez et al. 2012); quoted packings {PHI_FLUID}, {PHI_SOLID}\n")
    print("| method | phase | N | packing | +- | quoted | z | equation of state | z | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            "| {method} | {phase} | {N} | {packing:.5f} | {packing_err:.5f} | {published:.4f} | {z:+.1f} "
            "| {eos:.5f} | {z_eos:+.1f} | {wall_s:.0f} |".format(**r)
        )
    for r in rows:
        print(f"  {r['method']}, {r['phase']}: {r['note']}")
    print(f"\ntotal {time.time() - t0:.0f} s")
    if args.csv:
        with fileio.atomic_write(args.csv, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=FIELDS)
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
