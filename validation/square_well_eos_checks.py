"""The lambda = 1.5 square-well fluid's Z and U/N: another code's number and a Maxwell relation.

Two checks of the dense fluid's equation of state that need no fitted
equation of state (docs/validation/square-well.md, section 4):

* ``cross``, ``cross2``: the state points kT = 3 and kT = 1 at rho = 0.8 of
  HOOMD-blue's validation suite (github.com/glotzerlab/hoomd-validation,
  ``hoomd_validation/patchy_particle_pressure.py``, ``job_statepoints``, at
  commit f0e6510 of 2023-10-08; the kT = 3 row is still there at f1dd040):
  hard spheres with a full-coverage Kern-Frenkel patch of range 1.5 and
  depth 1 / T*, i.e. the square well at T* = 3 and 1; N = 4096; ``betaP``
  measured there by NVT Monte Carlo (the scale distribution function), no
  error given.
* ``maxwell``: the mixed second derivative of the excess free energy
  ``f(beta, rho) = beta A_ex / N`` two ways.  ``Z - 1 = rho df/drho`` and
  ``U/N = df/dbeta``, so ``dZ/dbeta (at rho) = rho dU/drho (at beta)``: the
  pressure (from the impulses of collisions, captures, releases and bounces)
  against the potential energy (from counting bonds), measured independently.
  Central differences around (kT = 1.5, rho = 0.5) and (kT = 2, rho = 0.7):
  Z at beta = 1/kT +- 0.06, U/N at rho +- 0.05.  The stencil's own error is measured on the
  fitted equation of state of Espindola-Heredia et al. (``teqp``), whose
  derivatives are exact.

Each state point: N = 1372 (FCC 7 x 7 x 7 start), Andersen thermostat at kT,
``--equil`` pair events of equilibration, then about ``--events`` in 256 blocks
(:func:`square_well_eos.measure`: blocking errors, the halves' test).  One state
point at a time; ``--csv`` is rewritten with every row as each finishes,
and a row already there is not run again (``--fresh`` starts over).

usage:
    python3 validation/square_well_eos_checks.py                 # about 40 minutes of CPU
    python3 validation/square_well_eos_checks.py --events 2e6 --equil 2e5 --csv /tmp/sw.csv  # a quick look
"""

import argparse
import csv
import math
import os
import time

from hardspheres.fileio import atomic_write
from square_well_eos import measure, reference

# (kT, rho, betaP) of hoomd-validation (NVT Monte Carlo, N = 4096), by row name
HOOMD = {"cross": (3.0, 0.8, 4.837436833423719), "cross2": (1.0, 0.8, 2.2766339608381325)}
CENTRES = {"": (1.5, 0.5), "2": (2.0, 0.7)}  # the Maxwell relation's centres (kT, rho), by name suffix
DBETA, DRHO = 0.06, 0.05
FIELDS = ("name", "kT", "rho", "Z", "Z_err", "U", "U_err", "Z_halves", "U_halves", "converged", "kT_meas")


def points() -> list[tuple[str, float, float]]:
    """The state points: ``(name, kT, rho)`` (in the order their seeds follow)."""
    out = [("cross", HOOMD["cross"][0], HOOMD["cross"][1])]
    for suffix, (kt, rho) in CENTRES.items():
        out += [
            ("beta-" + suffix, 1.0 / (1.0 / kt - DBETA), rho),
            ("beta+" + suffix, 1.0 / (1.0 / kt + DBETA), rho),
            ("rho-" + suffix, kt, rho - DRHO),
            ("rho+" + suffix, kt, rho + DRHO),
        ]
    return out + [("cross2", HOOMD["cross2"][0], HOOMD["cross2"][1])]


def load(path: str) -> dict[str, dict[str, float]]:
    """The rows already measured, by name."""
    if not os.path.exists(path):
        return {}
    with open(path, newline="") as f:
        return {r["name"]: {k: float(v) for k, v in r.items() if k != "name"} for r in csv.DictReader(f)}


def save(path: str, rows: dict[str, dict[str, float]]) -> None:
    """Write every row measured so far (through :func:`hardspheres.fileio.atomic_write`)."""
    with atomic_write(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(FIELDS)
        for name, r in rows.items():
            out.writerow([name] + [f"{r[key]:.10g}" for key in FIELDS[1:]])


def run(args: argparse.Namespace) -> dict[str, dict[str, float]]:
    """Measure every state point not yet in the csv, saving the rows after each."""
    rows = {} if args.fresh else load(args.csv)
    for k, (name, kt, rho) in enumerate(points()):
        if name in rows:
            continue
        cpu = time.process_time()
        r = measure(kt, rho, args.events, args.equil, seed=31 + k, cells=7)
        r["converged"] = float(r["Z_conv"] and r["U_conv"])
        rows[name] = r
        save(args.csv, rows)
        print(f"{name}: kT {kt:.4f} rho {rho:.3f} done in {time.process_time() - cpu:.0f} s", flush=True)
    return rows


def cross_report(r: dict[str, float], name: str) -> list[str]:
    """Our Z at HOOMD's state point against its betaP / rho (no error there: z from ours alone)."""
    kt, rho, beta_p = HOOMD[name]
    zh = beta_p / rho
    fit = reference(kt, rho)
    lines = [
        f"kT = {kt}, rho = {rho}: Z ours {r['Z']:.4f} +- {r['Z_err']:.4f} (halves {r['Z_halves']:+.1f}),"
        f" hoomd-validation betaP / rho = {zh:.4f}: {100 * (r['Z'] / zh - 1):+.2f}%,"
        f" z (our error only) {(r['Z'] - zh) / r['Z_err']:+.1f}",
        f"  U/N ours {r['U']:.4f} +- {r['U_err']:.4f} (halves {r['U_halves']:+.1f}); <kT> {r['kT_meas']:.4f}",
    ]
    if fit:
        lines.append(f"  the fit (Espindola-Heredia et al. 2009): Z {fit[0]:.4f}, U/N {fit[1]:.4f}")
    return lines


def stencil(z: list[float], u: list[float], rho: float, bm: float, bp: float) -> tuple[float, float]:
    """``dZ/dbeta`` and ``rho dU/drho`` by central differences: ``z`` at (bm, bp), ``u`` at rho -+ DRHO."""
    return (z[1] - z[0]) / (bp - bm), rho * (u[1] - u[0]) / (2.0 * DRHO)


def maxwell_report(rows: dict[str, dict[str, float]], suffix: str) -> list[str]:
    """The two sides of dZ/dbeta = rho dU/drho, their errors, and the stencil's error on the fit."""
    kt, rho = CENTRES[suffix]
    bm, bp = 1.0 / kt - DBETA, 1.0 / kt + DBETA
    names = [n + suffix for n in ("beta-", "beta+", "rho-", "rho+")]
    if not all(n in rows for n in names):
        return [f"around kT = {kt}, rho = {rho}: not all four state points measured yet"]
    zz, uu = [rows[n]["Z"] for n in names[:2]], [rows[n]["U"] for n in names[2:]]
    lhs, rhs = stencil(zz, uu, rho, bm, bp)
    e_l = math.hypot(rows[names[0]]["Z_err"], rows[names[1]]["Z_err"]) / (bp - bm)
    e_r = rho * math.hypot(rows[names[2]]["U_err"], rows[names[3]]["U_err"]) / (2.0 * DRHO)
    lines = [
        f"around kT = {kt}, rho = {rho}: dZ/dbeta = {lhs:.4f} +- {e_l:.4f} (Z at beta {bm:.4f}, {bp:.4f}),"
        f" rho dU/drho = {rhs:.4f} +- {e_r:.4f} (U/N at rho {rho - DRHO:.3f}, {rho + DRHO:.3f})",
        f"  difference {lhs - rhs:+.4f} +- {math.hypot(e_l, e_r):.4f}:"
        f" z {(lhs - rhs) / math.hypot(e_l, e_r):+.1f}",
    ]
    fit = [reference(rows[n]["kT"], rows[n]["rho"]) for n in names]
    if all(fit):
        fl, fr = stencil([f[0] for f in fit[:2]], [f[1] for f in fit[2:]], rho, bm, bp)  # type: ignore[index]
        lines.append(
            f"  the same stencil on the fit: {fl:.4f} and {fr:.4f} (the fit's exact identity: equal); the"
            f" stencil's truncation error: {fl - fr:+.4f}"
        )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--events", type=float, default=3e7, help="pair events measured per state point")
    ap.add_argument("--equil", type=float, default=2e6, help="pair events of equilibration")
    ap.add_argument("--csv", default="validation/results/square_well_eos_checks.csv", help="rows, kept")
    ap.add_argument("--fresh", action="store_true", help="discard the rows already in --csv")
    args = ap.parse_args()
    cpu = time.process_time()
    rows = run(args)
    print(f"N = 1372, lambda = 1.5, eps = 1, Andersen at kT; {args.equil:.0e} events equilibration,")
    print(f"about {args.events:.1e} measured per state point in 256 blocks")
    for name, r in rows.items():
        flag = "" if r["converged"] else " (blocking without plateau)"
        drift = " DRIFT" if max(abs(r["Z_halves"]), abs(r["U_halves"])) > 3.0 else ""
        print(
            f"{name:6s} kT {r['kT']:.4f} rho {r['rho']:.3f}  Z {r['Z']:.4f} +- {r['Z_err']:.4f}"
            f"  U/N {r['U']:.4f} +- {r['U_err']:.4f}  halves {r['Z_halves']:+.1f} {r['U_halves']:+.1f}"
            f"  <kT> {r['kT_meas']:.4f}{flag}{drift}"
        )
    out = [line for name in HOOMD if name in rows for line in cross_report(rows[name], name)]
    for suffix in CENTRES:
        out += maxwell_report(rows, suffix)
    print("\n".join(out))
    print(f"CPU time {time.process_time() - cpu:.0f} s (this call)")


if __name__ == "__main__":
    main()
