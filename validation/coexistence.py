"""Direct coexistence of hard-sphere crystal and fluid: the pressure by the drift, and from the virial.

The published value: Fernandez, Martin-Mayor, Seoane and Verrocchio, Phys.
Rev. Lett. 108, 165701 (2012), beta P sigma^3 = 11.5727(10) (its abstract,
arXiv:1103.2599); the coexisting packings 0.4917 (fluid) and 0.5433 (solid)
commonly quoted with it are not the paper's (its abstract gives the
pressure, not the densities); validation/coexisting_packings.py
measures each phase at 11.5727 in bulk.

Two measurements, on an FCC slab ((100) or (111) normal to z) beside a
fluid slab as long (hardspheres.analysis.coexistence.crystal_fluid_slab:
the fluid is compressed to its packing in a box of its own with the
crystal's cross-section before the two are joined):

* ``--pressures P ...``: constant normal pressure (hardspheres.Barostat,
  ``axes="z"``: the cross-section stays the crystal's).  At each pressure
  the crystal is built at Speedy's packing at P (hardspheres.eos.speedy_fcc,
  so its lateral spacing is the unstrained one at P) and the fluid at
  Hansen-Goos's, so that the only thing out of balance is the chemical
  potential: the crystal fraction by local q6 (SlabProfile) grows above the
  coexistence pressure and falls below it.  The drift is its slope over the
  run after ``--skip``; the box's length moves the other way (the crystal is
  denser).
* ``--nve``: constant volume, built at the published coexisting packings:
  the crystal grows or melts until both sides are at the coexistence
  pressure, which the collision virial gives (``P_zz``, the component
  normal to the interfaces: the tangential ones carry the interfaces'
  stress), and the profile's plateaus give the two packings.

Every sample is a CSV row (``--csv``); ``--profile`` writes the constant-volume
run's mean profile, and ``--plot`` draws it (docs/images/coexistence_profile.png).

Running time (10 x 10 x 20 cells, N about 15 000, this shared 2-core
machine at load average 6 to 8, ``nice -n 15``): ``--nve --until 200``
267 s; ``--nve --plane 111 --cells 14 16 36 --until 400`` 358 s;
``--pressures 11.0 12.2 --until 150`` 1112 s (3.0 s per time unit
at constant normal pressure: the volume moves cost 9 ms each, about 47 per
time unit; 1 to 3 minutes to build each slab); 2.4 s per profile (q6 of
every sphere).  Results and the commands: docs/validation/coexistence.md, "Direct
coexistence".

usage: python3 validation/coexistence.py [--pressures 11.0 12.2] [--nve] [--cells X Y Z] [--plane 100|111]
       [--until T] [--every T] [--skip T] [--seed S] [--csv FILE] [--profile FILE] [--plot PNG]
"""

from __future__ import annotations

import argparse
import csv
import math
import time

import numpy as np

import hardspheres as hs
from hardspheres import fileio
from hardspheres.analysis.coexistence import SlabProfile, crystal_fluid_slab
from hardspheres.eos import hansen_goos, packing_at_pressure, speedy_fcc

#: Fernandez, Martin-Mayor, Seoane and Verrocchio, PRL 108, 165701 (2012): the pressure (abstract);
#: the packings as commonly quoted with it (not the paper's).
P_COEX, PHI_FLUID, PHI_SOLID = 11.5727, 0.4917, 0.5433

FIELDS = ["mode", "pressure", "t", "n", "crystal_fraction", "Lz", "packing", "pzz_interval", "seconds"]


def _slope(ts: list[float], ys: list[float], skip: float) -> float:
    return _fit(ts, ys, skip)[0]


def _fit(ts: list[float], ys: list[float], skip: float) -> tuple[float, float]:
    """Least-squares slope after ``skip`` and its standard error from the residuals.

    The residuals are correlated in time (the interfaces wander), so the
    error is a lower bound on the slope's noise.
    """
    t, y = np.array(ts), np.array(ys)
    keep = t >= skip - 1e-9
    if keep.sum() < 3:
        return (float(np.polyfit(t[keep], y[keep], 1)[0]) if keep.sum() == 2 else math.nan), math.nan
    t, y = t[keep], y[keep]
    b, a = np.polyfit(t, y, 1)
    r = y - (a + b * t)
    se = math.sqrt(float(np.sum(r * r)) / (len(t) - 2) / float(np.sum((t - t.mean()) ** 2)))
    return float(b), se


#: The relaxed start shared by every pressure of a run with ``--crystal-packing`` (built once).
_START: dict[str, tuple[hs.State, hs.PeriodicBox]] = {}


def _start(pressure: float, args: argparse.Namespace, rows: list[dict]) -> hs.Simulation:
    """The slab a constant-pressure run starts from.

    By default built at ``pressure``'s own packings (Speedy's crystal,
    Hansen-Goos's fluid).  With ``--crystal-packing`` and ``--fluid-packing``
    built once at those (the coexisting ones) and run ``--relax`` at
    constant volume, where the crystal grows or melts until the slab is at
    the coexistence pressure: every pressure then starts from that same
    state, near coexistence, so the drift is the pressure's and not the
    build's.
    """
    if args.crystal_packing is None:
        phi_s = packing_at_pressure(pressure, speedy_fcc, bounds=(0.5, 0.74))
        phi_f = packing_at_pressure(pressure, hansen_goos)
        state, box = crystal_fluid_slab(
            tuple(args.cells), plane=args.plane, crystal_packing=phi_s, fluid_packing=phi_f, seed=args.seed
        )
        print(
            f"beta P {pressure:g}: crystal at {phi_s:.4f} (Speedy), fluid at {phi_f:.4f} (Hansen-Goos), "
            f"N {state.n}"
        )
        return hs.Simulation(state, box)
    if "relaxed" not in _START:
        t0 = time.time()
        state, box = crystal_fluid_slab(
            tuple(args.cells),
            plane=args.plane,
            crystal_packing=args.crystal_packing,
            fluid_packing=args.fluid_packing,
            seed=args.seed,
        )
        sim = hs.Simulation(state, box)
        print(
            f"start: crystal at {args.crystal_packing:.4f}, fluid at {args.fluid_packing:.4f}, N {sim.n}, "
            f"box {tuple(round(x, 3) for x in box.sides)}; built in {time.time() - t0:.0f} s; "
            f"{args.relax:g} time units at constant volume:",
            flush=True,
        )
        _series(sim, args, rows, "relax", math.nan, args.relax)
        _START["relaxed"] = (sim.state(), box)
    state, box = _START["relaxed"]
    return hs.Simulation(state, box)


def _series(
    sim: hs.Simulation, args: argparse.Namespace, rows: list[dict], mode: str, pressure: float, until: float
) -> tuple[list[float], list[float], list[float]]:
    """Run ``sim`` for ``until`` time units, a profile every ``--every``: the times, crystal fractions, Lz."""
    ts, fs, ls = [], [], []
    profile = SlabProfile(bins=_bins(args))
    t0 = time.time()
    start = sim.time
    sim.observables.reset()
    integral = elapsed = 0.0
    while True:
        profile.compute(sim)
        ts.append(sim.time - start)
        fs.append(profile.crystal_fraction)
        ls.append(sim.container.sides[2])
        e = sim.observables.elapsed
        now = sim.observables.pressure_tensor()[2, 2] * e if e > 0 else 0.0
        pzz = (now - integral) / (e - elapsed) if e > elapsed else math.nan
        integral, elapsed = now, e
        rows.append(
            dict(
                mode=mode,
                pressure=pressure,
                t=ts[-1],
                n=sim.n,
                crystal_fraction=fs[-1],
                Lz=ls[-1],
                packing=sim.packing,
                pzz_interval=pzz,
                seconds=time.time() - t0,
            )
        )
        _write(args.csv, rows)
        bar = sim.barostat
        print(
            f"  t {ts[-1]:7.1f}  crystal fraction {fs[-1]:.4f}  packing {sim.packing:.4f}  Lz {ls[-1]:.3f}"
            + (f"  P_zz(last) {pzz:.3f}" if bar is None else f"  acceptance {bar.acceptance:.2f}")
            + f"  ({time.time() - t0:.0f} s)",
            flush=True,
        )
        if ts[-1] >= until - 1e-9:
            break
        sim.run(until=start + min(until, ts[-1] + args.every))
    return ts, fs, ls


def _barostat(sim: hs.Simulation, pressure: float, args: argparse.Namespace) -> hs.Barostat:
    """``Barostat(axes="z")`` making ``--moves-per-free-time`` moves per (auto) mean free time."""
    probe = hs.Barostat(pressure=pressure, kT=1.0, axes="z", seed=args.seed)
    probe.attach(sim)  # sets the auto interval (the Enskog mean free time) and step from the state
    every = float(probe.every) / args.moves_per_free_time  # type: ignore[arg-type]
    return hs.Barostat(pressure=pressure, kT=1.0, axes="z", every=every, seed=args.seed)


def drift(pressure: float, args: argparse.Namespace, rows: list[dict]) -> tuple[float, float]:
    """Slopes [1/time] of the crystal fraction and [length/time] of Lz after ``--skip``, at constant P_zz."""
    sim = _start(pressure, args, rows)
    if pressure > 0:
        sim.set_barostat(_barostat(sim, pressure, args))
        print(f"beta P {pressure:g}, constant normal pressure:", flush=True)
    else:
        print("control: the same start at constant volume:", flush=True)
    ts, fs, ls = _series(sim, args, rows, "npt" if pressure > 0 else "nve", pressure, args.until)
    (d, d_err), (dl, dl_err) = _fit(ts, fs, args.skip), _fit(ts, ls, args.skip)
    ERRORS[pressure] = (d_err, dl_err)
    return d, dl


#: The slopes' standard errors by pressure (0: the constant-volume control), set by :func:`drift`.
ERRORS: dict[float, tuple[float, float]] = {}


def constant_volume(args: argparse.Namespace, rows: list[dict]) -> None:
    """The virial's P_zz and the plateaus' packings at constant volume, built at the published packings."""
    state, box = crystal_fluid_slab(
        tuple(args.cells),
        plane=args.plane,
        crystal_packing=PHI_SOLID,
        fluid_packing=PHI_FLUID,
        seed=args.seed,
    )
    sim = hs.Simulation(state, box)
    if args.trajectory:  # frames for the pictures (render --slice x=0: the slab side-on)
        from hardspheres.io.trajectory import GSDWriter

        sim.writers.append(GSDWriter(args.trajectory, every=args.every, events=False))
    profile = SlabProfile(bins=_bins(args))
    print(
        f"constant volume: N {sim.n}, box {tuple(round(s, 3) for s in box.sides)}, packing {sim.packing:.4f}"
    )
    t0 = time.time()
    packs, crys, solid, fluid = [], [], [], []
    sim.observables.reset()
    integral = elapsed = 0.0  # of P_zz dt, and the time, since the last reset: each interval's mean
    while True:
        profile.compute(sim)
        measuring = sim.time >= args.skip - 1e-9
        e = sim.observables.elapsed
        now = sim.observables.pressure_tensor()[2, 2] * e if e > 0 else 0.0
        pzz_interval = (now - integral) / (e - elapsed) if e > elapsed else math.nan
        integral, elapsed = now, e
        line = f"  t {sim.time:7.1f}  crystal fraction {profile.crystal_fraction:.4f}"
        line += f"  P_zz(last) {pzz_interval:.3f}"
        if measuring:
            if not packs:
                sim.observables.reset()
                integral = elapsed = 0.0
            s, f = profile.plateaus()
            packs.append(profile.packing.copy())
            crys.append(profile.crystal.copy())
            solid.append(s)
            fluid.append(f)
            line += f"  plateaus {s:.4f} {f:.4f}"
            if sim.observables.elapsed > 0:
                line += f"  P_zz {sim.observables.pressure_tensor()[2, 2]:.4f}"
        rows.append(
            dict(
                mode="nve",
                pressure=math.nan,
                t=sim.time,
                n=sim.n,
                crystal_fraction=profile.crystal_fraction,
                Lz=sim.container.sides[2],
                packing=sim.packing,
                pzz_interval=pzz_interval,
                seconds=time.time() - t0,
            )
        )
        _write(args.csv, rows)
        print(line + f"  ({time.time() - t0:.0f} s)", flush=True)
        if sim.time >= args.until - 1e-9:
            break
        sim.run(until=min(args.until, sim.time + args.every))
    obs = sim.observables
    pzz = obs.estimate("pressure_zz")
    pxx, pyy = obs.pressure_tensor()[0, 0], obs.pressure_tensor()[1, 1]
    ps = float(np.nanmean(solid)), float(np.nanstd(solid) / math.sqrt(max(len(solid) - 1, 1)))
    pf = float(np.nanmean(fluid)), float(np.nanstd(fluid) / math.sqrt(max(len(fluid) - 1, 1)))
    print(f"\nconstant volume, t {args.skip:g} to {sim.time:g} ({len(solid)} profiles):")
    print(
        f"  P_zz = {pzz.mean:.4f} +- {pzz.sem:.4f}  "
        f"(published {P_COEX}; {100 * (pzz.mean / P_COEX - 1):+.2f} %)"
    )
    print(f"  P_xx, P_yy = {pxx:.4f}, {pyy:.4f}  (tangential)")
    print(f"  solid plateau {ps[0]:.4f} +- {ps[1]:.4f}  (published {PHI_SOLID})")
    print(f"  fluid plateau {pf[0]:.4f} +- {pf[1]:.4f}  (published {PHI_FLUID})")
    if args.profile:
        z = profile.z
        with fileio.atomic_write(args.profile, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["z", "packing", "crystal"])
            for row in zip(z, np.mean(packs, axis=0), np.mean(crys, axis=0)):
                w.writerow([f"{x:.6g}" for x in row])
        print(f"  profile: {args.profile}")


def _bins(args: argparse.Namespace) -> int:
    """One bin per cubic cell of the crystal (two (100) layers), or per three (111) layers (ABC)."""
    return args.cells[2] * 2 if args.plane == "100" else max(2, args.cells[2] * 2 // 3)


def _write(path: str | None, rows: list[dict]) -> None:
    if not path:
        return
    with fileio.atomic_write(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def plot(profile_csv: str, png: str, plane: str = "100") -> None:
    """The constant-volume run's mean packing and crystal fraction along z."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = np.genfromtxt(profile_csv, delimiter=",", names=True)
    fig, ax = plt.subplots(figsize=(7, 3.6))
    ax.plot(d["z"], d["packing"], "o-", ms=3, color="C0", label="packing")
    for phi, what in ((PHI_SOLID, "solid"), (PHI_FLUID, "fluid")):
        ax.axhline(phi, color="0.5", lw=0.8, ls="--")
        ax.text(d["z"][0], phi + 0.002, f"{what} {phi} (Fernandez et al. 2012)", fontsize=7, color="0.3")
    ax.set_xlabel("z / sigma")
    ax.set_ylabel("packing fraction", color="C0")
    ax2 = ax.twinx()
    ax2.plot(d["z"], d["crystal"], "s-", ms=3, color="C3", label="crystal-like (q6)")
    ax2.set_ylabel("crystal-like fraction (local q6)", color="C3")
    ax2.set_ylim(-0.05, 1.05)
    ax.set_title(f"FCC ({plane}) slab and fluid at constant volume (mean profile)", fontsize=9)
    fig.tight_layout()
    with fileio.atomic_write(png, "wb") as fh:
        fig.savefig(fh, format="png", dpi=110)
    print(f"picture: {png}")


def plot_drift(csvs: list[str], png: str) -> None:
    """The crystal-like fraction against time at each constant normal pressure in ``csvs`` (``--csv``)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    runs: dict[float, list[tuple[float, float]]] = {}
    for path in csvs:
        with open(path, newline="") as fh:
            for r in csv.DictReader(fh):
                if r["mode"] == "npt":
                    runs.setdefault(float(r["pressure"]), []).append(
                        (float(r["t"]), float(r["crystal_fraction"]))
                    )
    for i, (p, pts) in enumerate(sorted(runs.items())):
        t, f = np.array(pts).T
        ax.plot(t, f, "o-", ms=3, color=f"C{i}", label=f"beta P sigma^3 = {p:g}")
    ax.set_xlabel("time [sigma sqrt(m / kT)]")
    ax.set_ylabel("crystal-like fraction (local q6)")
    ax.set_title(
        f"constant normal pressure, N = 15 000 (coexistence {P_COEX}, Fernandez et al. 2012)", fontsize=8
    )
    ax.legend(fontsize=8)
    fig.tight_layout()
    with fileio.atomic_write(png, "wb") as fh:
        fig.savefig(fh, format="png", dpi=110)
    print(f"picture: {png}")


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--pressures", type=float, nargs="*", default=[])
    ap.add_argument("--nve", action="store_true", help="the constant-volume run at the published packings")
    ap.add_argument("--cells", type=int, nargs=3, default=[10, 10, 20])
    ap.add_argument("--plane", default="100", choices=["100", "111"])
    ap.add_argument("--until", type=float, default=300.0)
    ap.add_argument("--every", type=float, default=10.0)
    ap.add_argument("--skip", type=float, default=20.0, help="time before the drift's fit / the averages")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--csv", default=None)
    ap.add_argument("--profile", default=None, help="CSV of the constant-volume run's mean profile")
    ap.add_argument("--plot", default=None, help="PNG of --profile's profile")
    ap.add_argument(
        "--trajectory", default=None, help="GSD of the constant-volume run, a frame every --every"
    )
    ap.add_argument(
        "--crystal-packing",
        type=float,
        default=None,
        help="--pressures: build the slab once at this crystal packing (and --fluid-packing), relax it",
    )
    ap.add_argument("--fluid-packing", type=float, default=None, help="with --crystal-packing")
    ap.add_argument(
        "--relax", type=float, default=40.0, help="with --crystal-packing: time at constant volume first"
    )
    ap.add_argument(
        "--moves-per-free-time", type=float, default=1.0, help="--pressures: volume moves per mean free time"
    )
    ap.add_argument(
        "--control",
        action="store_true",
        help="with --crystal-packing: also the same start at constant volume",
    )
    ap.add_argument(
        "--plot-drift",
        nargs="+",
        default=None,
        metavar=("PNG", "CSV"),
        help="PNG of the crystal fraction against time from the CSVs after it, and stop",
    )
    args = ap.parse_args()
    if args.plot_drift:
        plot_drift(args.plot_drift[1:], args.plot_drift[0])
        return
    if (args.crystal_packing is None) != (args.fluid_packing is None):
        ap.error("give --crystal-packing and --fluid-packing together")
    if args.control and args.crystal_packing is None:
        ap.error("--control needs --crystal-packing (a shared start)")
    t0 = time.time()
    rows: list[dict] = []
    if args.nve:
        constant_volume(args, rows)
    table = [(p, *drift(p, args, rows)) for p in args.pressures + ([0.0] if args.control else [])]
    if table:
        print(
            "\n| beta P sigma^3 | crystal fraction drift [1/time] | +- | Lz drift [sigma/time] | +- "
            "| the crystal |"
        )
        print("|---|---|---|---|---|---|")
        for p, d, dl in table:
            e, el = ERRORS.get(p, (math.nan, math.nan))
            what = "grows" if d > 0 else "melts"
            if abs(d) < 2 * e:
                what += " (within 2 errors of 0)"
            name = "constant volume" if p == 0 else f"{p:g}"
            print(f"| {name} | {d:+.2e} | {e:.1e} | {dl:+.2e} | {el:.1e} | {what} |")
        table = [r for r in table if r[0] > 0]
        grows = [p for p, d, _ in table if d > 0]
        melts = [p for p, d, _ in table if not d > 0]
        if grows and melts and max(melts) < min(grows):
            print(
                f"\ncoexistence bracketed: {max(melts):g} < beta P sigma^3 < {min(grows):g} "
                f"(published {P_COEX})"
            )
        else:
            print(f"\nnot bracketed by these pressures (published {P_COEX})")
    if args.plot and args.profile:
        plot(args.profile, args.plot, args.plane)
    print(f"total {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
