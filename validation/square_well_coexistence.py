"""The lambda = 1.5 square well's vapour-liquid coexistence and critical point, from a liquid slab.

N spheres (diameter, mass and well depth one) start as a liquid block
across the middle of a long periodic box, ``W x W x L`` (z the long side:
:func:`hardspheres.analysis.coexistence.vapour_liquid_slab`), with the
square well ``steps=[(1.5, -1.0)]`` and :class:`hardspheres.dense.Andersen`
at ``kT`` (``--rate`` resamplings per sphere per unit time).  The block
evaporates until a vapour stands at both its faces; after ``--equil`` time
units, a frame every ``--every`` for ``--time``: each frame's density
profile along z, centred on the slab's centre of the frame and folded
(:class:`~hardspheres.analysis.coexistence.VapourLiquidProfile`), and from
the plateaus the two coexistence densities with blocking errors
(:class:`~hardspheres.analysis.coexistence.CoexistenceDensities`, margin 3
interface widths; refused when not flat or drifting, then tried again at
margin 4 and 5, and the margin used is in the table).  The plateaus'
densities are slow (the vapour exchanges spheres with the slab over about
100 time units): blocking decides among levels of ``--min-blocks`` (6)
blocks or more, and where it finds no plateau the error is the largest of
those levels' (marked ``*``; ``--strict`` refuses instead).
``--save-frames`` keeps every frame's profile, and ``--reanalyse``
computes the table again from them (``--skip``, ``--min-blocks``).

The vapour's density is also compared with the one that Singh et al.'s
saturation pressure implies by the virial series to B3 (their fit ``ln p
= 3.5211 - 7.1939 / T``, as coded in the etomica package,
github.com/etomica/etomica, ``etomica.modules.adsorption.EOSSW``, which
cites the paper).

Then the critical point: the rectilinear diameter ``(rho_l + rho_v) / 2 =
rho_c + A (T_c - T)`` and the scaling law ``rho_l - rho_v = B (T_c -
T)^beta`` with the Ising ``beta = 0.326``, fitted jointly, errors by
resampling the densities (:func:`~hardspheres.analysis.coexistence.critical_point`),
against Singh, Kofke and Errington, J. Chem. Phys. 119, 3405 (2003):
``T_c = 1.2172, rho_c = 0.3079`` (lambda = 1.5).

Output: validation/results/square_well_coexistence.csv (one row per
temperature, written after each), ..._profiles.csv (the mean profiles) and
..._coexistence.txt (this script's printout: ``--fit`` re-reads the csv and
prints the fit alone).  docs/validation/square-well.md, section 6.

usage (about 8 minutes of CPU per temperature):
    for t in 1.0 0.9 1.1 0.95 1.05 1.15; do
        nice -n 10 python3 validation/square_well_coexistence.py --n 2000 --width 12 --length 48 \
            --equil 400 --time 1600 --rate 0.2 --temperatures $t --append --save-frames /tmp/swc/frames
    done
    python3 validation/square_well_coexistence.py --reanalyse --save-frames /tmp/swc/frames  # table, fit
    python3 validation/square_well_coexistence.py --n 1000 --width 10 --length 40 --equil 50 --time 200 \
        --temperatures 1.0 --out /tmp/quick      # a quick look (about a minute; refused: too short)
    python3 validation/square_well_coexistence.py --fit          # the fit from the csv
"""

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

import hardspheres as hs
from hardspheres import fileio
from hardspheres.analysis.coexistence import (
    CoexistenceDensities,
    VapourLiquidProfile,
    critical_point,
    vapour_liquid_slab,
)
from hardspheres.dense import Andersen
from hardspheres.errors import AnalysisInputError

LAM, EPS, BETA = 1.5, 1.0, 0.326
#: Singh, Kofke and Errington, J. Chem. Phys. 119, 3405 (2003), lambda = 1.5.
SKE_TC, SKE_RHOC = 1.2172, 0.3079
#: Wegner's first correction-to-scaling exponent, 3-D Ising (omega nu = 0.832 x 0.630; Pelissetto and
#: Vicari, Phys. Rep. 368, 549 (2002))
DELTA = 0.524
MARGINS = (3.0, 4.0, 5.0)
#: Singh, Kofke and Errington's saturation pressure, ``ln p = P0 - P1 / T`` (lambda = 1.5), as coded in
#: the etomica package (github.com/etomica/etomica, etomica.modules.adsorption.EOSSW, which cites the paper).
SKE_PSAT = (3.5211, 7.1939)
FIELDS = (
    "kT",
    "liquid",
    "liquid_error",
    "vapour",
    "vapour_error",
    "margin",
    "interface",
    "width",
    "liquid_flat",
    "vapour_flat",
    "liquid_drift",
    "vapour_drift",
    "liquid_plateau",
    "vapour_plateau",
    "frames",
    "time",
    "n",
    "kT_measured",
    "U_per_sphere",
    "cpu_s",
)
ROOT = Path(__file__).resolve().parent / "results"
DEFAULT_OUT = str(ROOT / "square_well_coexistence")


def start_density(kt: float) -> float:
    """A rough guess of the liquid's density at ``kt`` to build the block at (the run finds its own)."""
    return 0.65 - 1.0 * (kt - 1.0)


def densities(
    profile: VapourLiquidProfile | tuple[np.ndarray, np.ndarray], min_blocks: int, strict: bool = False
) -> tuple[CoexistenceDensities | None, float, str]:
    """The coexistence densities at the first of :data:`MARGINS` accepted, its margin, or the refusals."""
    why = []
    for margin in MARGINS:
        try:
            return (
                CoexistenceDensities(margin=margin, min_blocks=min_blocks, strict=strict).compute(profile),
                margin,
                "",
            )
        except AnalysisInputError as err:
            why.append(f"margin {margin:g}: {err}")
    return None, math.nan, "; ".join(why)


def run_temperature(kt: float, args: argparse.Namespace, seed: int) -> tuple[dict, VapourLiquidProfile]:
    """One temperature: build, equilibrate, sample the profile; the row of the table."""
    cpu = time.process_time()
    state, box = vapour_liquid_slab(args.n, args.width, args.length, start_density(kt), kT=kt, seed=seed)
    sim = hs.Simulation(state, box, steps=[(LAM, -EPS)])
    sim.set_thermostat(Andersen(kT=kt, rate=args.rate, seed=seed))
    sim.run(until=args.equil)
    if args.trajectory and abs(kt - args.picture_kt) < 1e-9:
        from hardspheres.io.trajectory import GSDWriter

        sim.writers.append(GSDWriter(args.trajectory, every=args.time / 4, events=False))
    profile = VapourLiquidProfile(bins=args.bins)
    t0, k_int, u = sim.time, sim.engine.transport_tallies(sim.time)["kinetic"][:3].sum(), []
    frames = int(round(args.time / args.every))
    for k in range(1, frames + 1):
        sim.run(until=t0 + k * args.every)
        profile.compute(sim, reset=(k == 1))
        u.append(sim.potential_energy() / sim.n)
    k_int = sim.engine.transport_tallies(sim.time)["kinetic"][:3].sum() - k_int  # int 2K dt
    if args.save_frames:  # every frame's profile, for a look at the series
        Path(args.save_frames).mkdir(parents=True, exist_ok=True)
        np.savez_compressed(
            f"{args.save_frames}/frames_{kt:g}.npz",
            z=profile.z,
            profiles=profile.profiles,
            centres=profile.centres,
            u=u,
        )
    row = {"kT": kt, "frames": frames - args.skip, "time": args.time, "n": args.n}
    row["kT_measured"] = float(k_int / (3.0 * sim.n * (sim.time - t0)))
    row["U_per_sphere"] = float(np.mean(u))
    update(row, (profile.z, profile.profiles[args.skip :]), args.min_blocks, args.strict)
    row["cpu_s"] = time.process_time() - cpu
    return row, profile


def update(row: dict, profile: tuple[np.ndarray, np.ndarray], min_blocks: int, strict: bool) -> None:
    """The row's densities from ``(z, profiles)``, or NaN and the refusals printed."""
    c, row["margin"], why = densities(profile, min_blocks, strict)
    names = ("liquid", "liquid_error", "vapour", "vapour_error", "interface", "width")
    if c is not None:
        row.update({k: getattr(c, k) for k in names})
        row.update(c.checks)
    else:
        checks = FIELDS[FIELDS.index("liquid_flat") : FIELDS.index("vapour_plateau") + 1]
        row.update({k: math.nan for k in names + checks})
        print(f"kT {row['kT']}: refused: {why}", flush=True)


def reanalyse(args: argparse.Namespace) -> None:
    """The csv's densities again from the frames saved by ``--save-frames`` (``--skip``, ``--min-blocks``)."""
    rows = sorted(read(args.out + ".csv"), key=lambda r: r["kT"])
    for r in rows:
        d = np.load(f"{args.save_frames}/frames_{r['kT']:g}.npz")
        update(r, (d["z"], d["profiles"][args.skip :]), args.min_blocks, args.strict)
        r["frames"] = len(d["profiles"]) - args.skip
    write_rows(args.out + ".csv", rows)


def write_rows(path: str, rows: list[dict]) -> None:
    """The table, rewritten whole after each temperature."""
    with fileio.atomic_write(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS, restval="")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def write_profiles(path: str, profiles: dict[float, tuple[np.ndarray, np.ndarray]]) -> None:
    """The mean profiles: kT, |z|, density."""
    with fileio.atomic_write(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["kT", "z", "density"])
        for kt, (zs, dens) in profiles.items():
            for z, rho in zip(zs, dens):
                w.writerow([kt, f"{z:.4f}", f"{rho:.6f}"])


def read(path: str) -> list[dict]:
    """The table's rows with numbers (empty fields: NaN)."""
    with open(path, newline="") as fh:
        return [{k: float(v) if v else math.nan for k, v in r.items()} for r in csv.DictReader(fh)]


def read_profiles(path: str) -> dict[float, tuple[np.ndarray, np.ndarray]]:
    """The mean profiles by temperature: ``{kT: (z, density)}``."""
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {float(t): (data[data[:, 0] == t, 1], data[data[:, 0] == t, 2]) for t in np.unique(data[:, 0])}


def vapour_from_psat(kt: float) -> float:
    """The vapour's density at Singh et al.'s saturation pressure, by the virial series to B3.

    Solves ``p / kT = rho + B2 rho^2 + B3 rho^3`` (the exact B2, B3 of the well at ``kt``) for
    the root nearest the ideal gas's; the terms left out (B4 rho^4 and beyond) make it an
    estimate to about ``(B2 rho)^3``.
    """
    from square_well import b2, b3

    p = math.exp(SKE_PSAT[0] - SKE_PSAT[1] / kt) / kt
    c2, c3 = b2(3, EPS / kt), b3(EPS / kt)
    rho = p
    for _ in range(200):  # fixed point from the ideal gas: rho = p / (1 + B2 rho + B3 rho^2)
        rho = p / (1.0 + c2 * rho + c3 * rho * rho)
    return rho


def table(rows: list[dict]) -> str:
    """The coexistence densities as a text table."""
    out = [
        "kT    rho_liquid        rho_vapour          margin  z0     width  flat l, v   drift l, v   <kT>"
        "    rho_v (p_sat, B3)"
    ]
    for r in rows:
        if math.isnan(r["liquid"]):
            out.append(f"{r['kT']:.3f} refused")
            continue
        marks = "".join("*" if r.get(f"{k}_plateau", 1.0) == 0.0 else " " for k in ("liquid", "vapour"))
        out.append(
            f"{r['kT']:.3f} {r['liquid']:.4f} +- {r['liquid_error']:.4f}{marks[0]} {r['vapour']:.5f} +- "
            f"{r['vapour_error']:.5f}{marks[1]} {r['margin']:.0f}       {r['interface']:5.2f}  "
            f"{r['width']:.2f}   "
            f"{r['liquid_flat']:+.1f} {r['vapour_flat']:+.1f}   {r['liquid_drift']:+.1f} "
            f"{r['vapour_drift']:+.1f}   {r['kT_measured']:.4f}  {vapour_from_psat(r['kT']):.5f}"
        )
    if any("*" in line for line in out[1:]):
        out.append("* blocking found no plateau: the error is the largest of the levels with enough blocks")
    return "\n".join(out)


def fit(rows: list[dict], samples: int = 2000, drop: int = 1) -> str:
    """The critical point from the rows, against Singh, Kofke and Errington (2003).

    Then the same without the ``drop`` lowest temperatures: how much the result depends on the range.
    """
    ok = [r for r in rows if not math.isnan(r["liquid"])]
    out = fit_rows(ok, samples)
    if drop and len(ok) - drop >= 3:
        out += f"\nwithout the lowest {drop} (kT >= {ok[drop]['kT']:g}):\n" + fit_rows(ok[drop:], samples)
    return out


def fit_rows(ok: list[dict], samples: int) -> str:
    """:func:`fit` on rows that all have densities, sorted by temperature: the leading law, then with
    Wegner's correction to scaling (``Delta = 0.524``)."""
    if len(ok) < 3:
        return f"critical point: {len(ok)} temperatures with densities, 3 or more needed: no fit"
    cols = [np.array([r[k] for r in ok]) for k in ("kT", "liquid", "vapour", "liquid_error", "vapour_error")]
    lines = []
    for delta in (0.0, DELTA) if len(ok) >= 4 else (0.0,):
        cp = critical_point(*cols, beta=BETA, samples=samples, seed=1, correction=delta)
        dt, dr = cp.t_c / SKE_TC - 1.0, cp.rho_c / SKE_RHOC - 1.0
        form = f"beta = {BETA}" + (f", correction Delta = {delta}, B1 = {cp.b1:.4f}" if delta else "")
        lines += [
            f"fit ({form}, {len(ok)} temperatures): T_c = {cp.t_c:.4f} +- {cp.t_c_error:.4f}, "
            f"rho_c = {cp.rho_c:.4f} +- {cp.rho_c_error:.4f}, A = {cp.a:.4f}, B = {cp.b:.4f}, "
            f"chi2 = {cp.chi2:.2f} over {cp.dof} degrees of freedom",
            f"Singh, Kofke and Errington 2003: T_c = {SKE_TC}, rho_c = {SKE_RHOC}; "
            f"ours {100 * dt:+.2f}% ({(cp.t_c - SKE_TC) / cp.t_c_error:+.1f} errors) and "
            f"{100 * dr:+.2f}% ({(cp.rho_c - SKE_RHOC) / cp.rho_c_error:+.1f} errors)",
        ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=4000, help="spheres")
    ap.add_argument("--width", type=float, default=16.0, help="the box's cross-section side [sigma]")
    ap.add_argument("--length", type=float, default=64.0, help="the box's long side [sigma]")
    ap.add_argument("--temperatures", type=float, nargs="+", default=[1.0, 0.9, 1.1, 0.95, 1.05])
    ap.add_argument("--equil", type=float, default=300.0, help="equilibration [time]")
    ap.add_argument("--time", type=float, default=1200.0, help="measured [time]")
    ap.add_argument("--every", type=float, default=1.0, help="between frames [time]")
    ap.add_argument("--bins", type=int, default=128, help="bins over the half box")
    ap.add_argument("--rate", type=float, default=0.5, help="Andersen resamplings per sphere per unit time")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--trajectory", default=None, help="GSD of the --picture-kt run (a picture)")
    ap.add_argument("--picture-kt", type=float, default=1.0)
    ap.add_argument("--out", default=DEFAULT_OUT, help="prefix of the .csv and _profiles.csv")
    ap.add_argument("--fit", action="store_true", help="only the fit, from the csv")
    ap.add_argument("--append", action="store_true", help="keep the csv's other temperatures")
    ap.add_argument("--save-frames", default=None, help="a folder for every frame's profile (npz per kT)")
    ap.add_argument("--skip", type=int, default=0, help="measured frames left out at the start")
    ap.add_argument(
        "--min-blocks", type=int, default=6, help="blocking's fewest blocks to decide (16: strict)"
    )
    ap.add_argument("--strict", action="store_true", help="refuse a density whose blocking finds no plateau")
    ap.add_argument("--reanalyse", action="store_true", help="the densities again from --save-frames' files")
    args = ap.parse_args()
    if args.reanalyse:
        reanalyse(args)
    if args.fit or args.reanalyse:
        rows = sorted(read(args.out + ".csv"), key=lambda r: r["kT"])
        print(table(rows))
        print(fit(rows))
        return
    print(
        f"N = {args.n}, box {args.width:g} x {args.width:g} x {args.length:g}, square well lambda {LAM}, "
        f"eps {EPS}; Andersen rate {args.rate}; equilibrate {args.equil:g}, measure {args.time:g} "
        f"(a frame every {args.every:g}), {args.bins} bins over the half box",
        flush=True,
    )
    rows: list[dict] = []
    profiles: dict[float, tuple[np.ndarray, np.ndarray]] = {}
    if args.append and Path(args.out + ".csv").exists():  # the temperatures run before, less those run again
        rows = [r for r in read(args.out + ".csv") if r["kT"] not in args.temperatures]
        old = read_profiles(args.out + "_profiles.csv")
        profiles = {t: p for t, p in old.items() if t not in args.temperatures}
    for kt in args.temperatures:
        row, prof = run_temperature(kt, args, seed=args.seed + int(round(1000 * kt)))
        rows.append(row)
        profiles[kt] = (prof.z, prof.density)
        write_rows(args.out + ".csv", sorted(rows, key=lambda r: r["kT"]))
        write_profiles(args.out + "_profiles.csv", dict(sorted(profiles.items())))
        print(f"kT {kt}: done in {row['cpu_s']:.0f} s of CPU", flush=True)
    rows = sorted(read(args.out + ".csv"), key=lambda r: r["kT"])
    print(table(rows))
    print(fit(rows))
    print(f"CPU time {sum(r['cpu_s'] for r in rows):.0f} s (all {len(rows)} temperatures)")


if __name__ == "__main__":
    main()
