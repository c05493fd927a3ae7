"""Shear flow on the compiled core: the flow curve eta(g) at packing 0.3 and 0.45.

**Flow curve.**  N = 500 equal spheres (sigma = m = kT = 1) in a cubic
Lees-Edwards box (``PeriodicBox.for_packing(n, phi, (1, 1, 1))
.sheared_by(g)``), started from random spheres with the linear profile
added, total momentum zero, held at kT = 1 by isokinetic rescaling of the
peculiar velocities (``PeculiarRescale``).  Each rate: a transient (at
least 20 time units and 5 strain units), then production runs, doubled
until the viscosity's blocking error is below ``--target`` (relative) and
converged, or ``--max-time`` is reached (then reported as not converged).
``hs.Simulation``'s summary gives eta = -P_xy / g, N_1 = P_xx - P_yy,
N_2 = P_yy - P_zz with blocking errors; the mean peculiar kT is sampled
between rescalings (at phases spread over the interval).

**Equilibrium** (``--equilibrium T``): the Einstein-Helfand viscosity of
the same system unsheared (``ShearViscosity``), the zero-rate reference.
DynamO's sheared granular test is ``validation/shear_dynamo.py``.

usage:
    python3 validation/shear_flow.py                      # both packings, about 50 minutes
    python3 validation/shear_flow.py --packings 0.3 --rates 0.5 1 --target 0.05   # a quick look
    python3 validation/shear_flow.py --equilibrium 3000 --seeds 1 2 3           # zero rate, 5 minutes
    python3 validation/shear_flow.py --tables                                     # the tables
    python3 validation/shear_flow.py --plot docs/images/shear_flow.png            # from the CSV

Results: ``validation/results/shear_flow.csv`` (one row per rate,
appended as each finishes) and ``validation/results/shear_flow_equilibrium.csv``;
the printed tables are kept in ``validation/results/shear_flow.txt``.

Units: sigma = m = kT = 1 (rates in sqrt(kT/m)/sigma, eta in sqrt(m kT)/sigma^2).
"""

import argparse
import csv
import math
import os
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres.dense import PeculiarRescale

HERE = os.path.dirname(os.path.abspath(__file__))
CSV = os.path.join(HERE, "results", "shear_flow.csv")
EQ_CSV = os.path.join(HERE, "results", "shear_flow_equilibrium.csv")

#: rates per packing (1/time)
RATES = {0.3: (0.05, 0.1, 0.2, 0.5, 1.0, 2.0), 0.45: (0.02, 0.05, 0.1, 0.2, 0.5, 1.0)}
#: thermostat interval at small rates (about half a mean free time at 0.3, 0.6 at 0.45)
INTERVAL = {0.3: 0.05, 0.45: 0.02}
#: the equilibrium viscosity (Einstein-Helfand) for the heating estimate only
ETA_GUESS = {0.3: 0.73, 0.45: 3.2}

FIELDS = [
    "packing", "n", "rate", "seed", "interval", "transient", "time", "strain", "collisions",
    "eta", "eta_error", "eta_converged", "n1", "n1_error", "n2", "n2_error",
    "kT_mean", "Z", "Z_error", "mean_free_time", "cpu_s",
]  # fmt: skip


def interval_for(phi: float, rate: float) -> float:
    """The rescaling interval: ``INTERVAL``, shortened so the fluid heats by at most 2% between actions."""
    heating = 2.0 * ETA_GUESS[phi] * rate**2 * (math.pi / (6.0 * phi)) / 3.0  # d kT / dt
    return min(INTERVAL[phi], 0.02 / heating)


def start(n: int, phi: float, rate: float, seed: int) -> tuple[hs.Simulation, hs.PeriodicBox]:
    """Random spheres in the sheared cube, kT = 1 peculiar, no drift, on the linear profile."""
    box = hs.PeriodicBox.for_packing(n, phi, (1, 1, 1)).sheared_by(rate)
    s = hs.random_spheres(n, phi, box, seed=seed)
    v = s.velocities - s.velocities.mean(axis=0)
    v *= math.sqrt(1.0 / (np.sum(v * v) / (3 * n - 3)))
    v[:, 0] += rate * s.positions[:, 1]
    s.velocities[:] = v
    return hs.Simulation(s, box), box


def run_for(sim: hs.Simulation, duration: float, chunk: float, kts: list[float]) -> None:
    """Run ``duration`` in chunks of ``chunk``, sampling the peculiar kT after each."""
    end = sim.time + duration
    while sim.time < end - 1e-12:
        sim.run(until=min(sim.time + chunk, end))
        kts.append(sim.observables.temperature())


def flow_point(
    phi: float, rate: float, n: int, seed: int, target: float, min_time: float, max_time: float
) -> dict:
    cpu0 = time.process_time()
    sim, _ = start(n, phi, rate, seed)
    dt = interval_for(phi, rate)
    sim.set_thermostat(PeculiarRescale(1.0, dt))
    chunk = 7.37 * dt  # samples of kT at phases spread over the interval
    transient = max(20.0, 5.0 / rate)
    run_for(sim, transient, chunk, [])
    c0 = sim.engine.counters["collisions"]
    sim.observables.reset()
    kts: list[float] = []
    t_prod = min_time
    run_for(sim, t_prod, chunk, kts)
    while True:
        sm = sim.observables.summary()
        rel = sm["viscosity_error"] / abs(sm["viscosity"])
        if (rel <= target and sm["viscosity_converged"]) or 2 * t_prod > max_time:
            break
        run_for(sim, t_prod, chunk, kts)  # double the production
        t_prod *= 2
    coll = sim.engine.counters["collisions"] - c0
    return {
        "packing": phi,
        "n": n,
        "rate": rate,
        "seed": seed,
        "interval": round(dt, 6),
        "transient": transient,
        "time": t_prod,
        "strain": rate * t_prod,
        "collisions": coll,
        "eta": sm["viscosity"],
        "eta_error": sm["viscosity_error"],
        "eta_converged": bool(sm["viscosity_converged"]),
        "n1": sm["normal_stress_1"],
        "n1_error": sm["normal_stress_1_error"],
        "n2": sm["normal_stress_2"],
        "n2_error": sm["normal_stress_2_error"],
        "kT_mean": float(np.mean(kts)),
        "Z": sm["Z"],
        "Z_error": sm["Z_error"],
        "mean_free_time": t_prod * n / (2.0 * coll),
        "cpu_s": time.process_time() - cpu0,
    }


def equilibrium_point(phi: float, n: int, seed: int, duration: float) -> dict:
    """Einstein-Helfand viscosity of the same system unsheared (``ShearViscosity``, its plateau window)."""
    from hardspheres.analysis.transport import ShearViscosity

    cpu0 = time.process_time()
    sim, _ = start(n, phi, 0.0, seed)
    sim.run(until=20.0)
    sim.observables.reset(every=0.1 if phi < 0.4 else 0.05)  # about a mean free time
    sim.run(until=20.0 + duration)
    eta, err = ShearViscosity().compute(sim).value()
    return {"packing": phi, "n": n, "seed": seed, "time": duration, "eta": eta, "eta_error": err,
            "cpu_s": time.process_time() - cpu0}  # fmt: skip


def append(path: str, row: dict, fields: list[str]) -> None:
    new = not os.path.exists(path)
    with open(path, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        if new:
            w.writeheader()
        w.writerow(row)


def plot(csv_path: str, png: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    groups = sorted({(float(x["packing"]), int(x["n"])) for x in rows})
    for phi, n in groups:
        colour = "C0" if phi < 0.4 else "C3"
        big = n != 500
        r = [x for x in rows if abs(float(x["packing"]) - phi) < 1e-9 and int(x["n"]) == n]
        g = np.array([float(x["rate"]) for x in r]) * (1.05 if big else 1.0)  # side by side

        def col(name: str, r: list = r) -> np.ndarray:
            return np.array([float(x[name]) for x in r])

        eq, eq_err = equilibrium(phi)
        ok = np.array([x["eta_converged"] == "True" for x in r])
        style = dict(fmt="s" if big else "o", color=colour, capsize=3, ms=4 if big else 5)
        ratio, ratio_err = col("eta") / eq, col("eta_error") / eq
        ax.errorbar(g[ok], ratio[ok], ratio_err[ok], label=f"packing {phi}, N = {n}", **style)
        if (~ok).any():
            ax.errorbar(g[~ok], ratio[~ok], ratio_err[~ok], mfc="none", **style)
        if not big:
            ax.axhspan(1 - eq_err / eq, 1 + eq_err / eq, color=colour, alpha=0.15, lw=0)
            vol = math.pi / (6.0 * phi)  # volume per sphere, sigma = 1
            for name, mark, fill in (("n1", "o", colour), ("n2", "^", "none")):
                y, e = col(name) * vol, col(f"{name}_error") * vol  # per kT per sphere
                label = f"{'$N_1$' if name == 'n1' else '$N_2$'}, packing {phi}"
                bx.errorbar(g, y, e, fmt=mark, color=colour, mfc=fill, capsize=3, label=label)
    ax.axhline(1.0, color="0.4", lw=0.8, ls="--")
    ax.set_xscale("log")
    ax.set_xlabel(r"shear rate $\dot\gamma$  [$\sqrt{kT/m}/\sigma$]")
    ax.set_ylabel(r"$\eta(\dot\gamma)\,/\,\eta_0$ (Einstein-Helfand, N = 500)")
    ax.set_title("Viscosity: shear thinning (bands: $\\eta_0$'s error)", fontsize=10)
    ax.legend(fontsize=8)
    bx.axhline(0.0, color="0.4", lw=0.8)
    bx.set_xscale("log")
    bx.set_xlabel(r"shear rate $\dot\gamma$  [$\sqrt{kT/m}/\sigma$]")
    bx.set_ylabel(r"normal stress difference $\times V/N$  [kT]")
    bx.set_title("$N_1 = P_{xx} - P_{yy}$, $N_2 = P_{yy} - P_{zz}$ (N = 500)", fontsize=10)
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    print(f"wrote {png}")


def read_csv(path: str) -> list[dict]:
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def equilibrium(phi: float, n: int = 500) -> tuple[float, float]:
    """The zero-rate viscosity: the weighted mean of the Einstein-Helfand runs in ``EQ_CSV`` and its error.

    The error is the larger of the weighted mean's and the runs' spread over sqrt(runs).

    Raises:
        SystemExit: no such run: run ``--equilibrium`` first.
    """
    rows = [r for r in read_csv(EQ_CSV) if abs(float(r["packing"]) - phi) < 1e-9 and int(r["n"]) == n]
    if not rows:
        raise SystemExit(f"shear_flow: no equilibrium run at packing {phi}, N = {n}: run --equilibrium first")
    e = np.array([float(r["eta"]) for r in rows])
    w = 1.0 / np.array([float(r["eta_error"]) for r in rows]) ** 2
    spread = float(np.std(e, ddof=1) / math.sqrt(e.size)) if e.size > 1 else 0.0
    return float(np.sum(w * e) / np.sum(w)), max(float(1.0 / math.sqrt(np.sum(w))), spread)


def _pm(x: float, err: float, digits: int = 4) -> str:
    """``x(err)`` with the error in units of the last digit."""
    return f"{x:.{digits}f}({err * 10**digits:.0f})"


def fits(rows: list[dict], phi: float, n: int = 500) -> list[str]:
    """Weighted straight lines eta = eta_0 + A g^p through all rates, p = 1/2, 1, 2: eta_0, A and chi^2."""
    r = [x for x in rows if abs(float(x["packing"]) - phi) < 1e-9 and int(x["n"]) == n]
    if len(r) < 3:
        return []
    g = np.array([float(x["rate"]) for x in r])
    eta = np.array([float(x["eta"]) for x in r])
    err = np.array([float(x["eta_error"]) for x in r])
    out = []
    for p in (0.5, 1.0, 2.0):
        a = np.vstack([np.ones_like(g), g**p]).T / err[:, None]
        coef = np.linalg.lstsq(a, eta / err, rcond=None)[0]
        cov = np.linalg.inv(a.T @ a)
        chi2 = float(np.sum((a @ coef - eta / err) ** 2))
        out.append(
            f"    eta = eta_0 + A g^{p:g}: eta_0 = {_pm(coef[0], math.sqrt(cov[0, 0]))}, "
            f"A = {_pm(coef[1], math.sqrt(cov[1, 1]))}, chi^2 = {chi2:.1f} for {len(g) - 2} d.o.f."
        )
    return out


def tables(csv_path: str) -> None:
    """The results as markdown tables: the equilibrium runs, the flow curves against them."""
    eq_rows = read_csv(EQ_CSV)
    for phi in (0.3, 0.45):
        eqs = [r for r in eq_rows if abs(float(r["packing"]) - phi) < 1e-9]
        if eqs:
            m, se = equilibrium(phi)
            runs = ", ".join(_pm(float(r["eta"]), float(r["eta_error"]), 3) for r in eqs)
            cpu = sum(float(r["cpu_s"]) for r in eqs)
            head = f"N = {eqs[0]['n']}, {len(eqs)} runs of {float(eqs[0]['time']):g}"
            print(f"packing {phi}: equilibrium (Einstein-Helfand, {head}: {runs}; {cpu:.0f} s CPU)")
            print(f"    eta_0 = {m:.4f} +- {se:.4f} (weighted; error: its own or spread/sqrt(runs))")
    cols = ["packing", "N", "g", "g t_mf", "time", "strain", "eta", "eta / eta_0", "z", "N_1", "N_2"]
    cols += ["kT (mean)", "Z", "CPU s"]
    print()
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    order = sorted(read_csv(csv_path), key=lambda r: (float(r["packing"]), int(r["n"]), float(r["rate"])))
    for r in order:
        f = {k: float(v) for k, v in r.items() if k != "eta_converged"}
        e0, e0_err = equilibrium(f["packing"])
        z = (f["eta"] - e0) / math.hypot(f["eta_error"], e0_err)
        conv = "" if r["eta_converged"] == "True" else " (not converged)"
        cells = [f"{f['packing']:g}", r["n"], f"{f['rate']:g}", f"{f['rate'] * f['mean_free_time']:.4f}"]
        cells += [f"{f['time']:g}", f"{f['strain']:g}", _pm(f["eta"], f["eta_error"]) + conv]
        cells += [
            f"{f['eta'] / e0:.3f}",
            f"{z:+.1f}",
            _pm(f["n1"], f["n1_error"]),
            _pm(f["n2"], f["n2_error"]),
        ]
        cells += [f"{f['kT_mean']:.4f}", f"{f['Z']:.3f}", f"{f['cpu_s']:.0f}"]
        print("| " + " | ".join(cells) + " |")
    rows = read_csv(csv_path)
    for phi in (0.3, 0.45):
        lines = fits(rows, phi)
        if lines:
            print(f"\npacking {phi}, N = 500: fits through all rates")
            print("\n".join(lines))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packings", type=float, nargs="+", default=[0.3, 0.45])
    ap.add_argument("--rates", type=float, nargs="+", help="default: per packing, see RATES")
    ap.add_argument("-n", type=int, default=500)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--target", type=float, default=0.03, help="relative error of eta to reach")
    ap.add_argument("--min-time", type=float, default=100.0)
    ap.add_argument("--max-time", type=float, default=3200.0)
    ap.add_argument("--csv", default=CSV)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--plot", metavar="PNG", help="draw the flow curve from --csv instead")
    ap.add_argument("--equilibrium", type=float, metavar="T", help="Einstein-Helfand runs (T time units)")
    ap.add_argument("--tables", action="store_true", help="print the results' tables (markdown) instead")
    args = ap.parse_args()
    if args.tables:
        tables(args.csv)
        return 0
    if args.equilibrium:
        fields = ["packing", "n", "seed", "time", "eta", "eta_error", "cpu_s"]
        for phi in args.packings:
            for seed in args.seeds:
                r = equilibrium_point(phi, args.n, seed, args.equilibrium)
                append(EQ_CSV if args.csv == CSV else args.csv, r, fields)
                print(
                    f"equilibrium phi {phi} N {args.n} seed {seed} t {args.equilibrium:g}: "
                    f"eta = {r['eta']:.4f} +- {r['eta_error']:.4f}  ({r['cpu_s']:.0f} s)",
                    flush=True,
                )
        return 0
    if args.plot:
        if not os.path.exists(args.csv):
            print(f"shear_flow: no results file {args.csv}: run the flow curve first", file=sys.stderr)
            return 1
        plot(args.csv, args.plot)
        return 0
    bad = [phi for phi in args.packings if phi not in RATES]
    if bad:
        print(f"shear_flow: packing {bad[0]} has no rates or interval here: use 0.3 or 0.45", file=sys.stderr)
        return 1
    pad = " " * 15
    print(f" phi    g      dt      time    eta{pad}conv  N1{pad}  N2{pad}  kT_mean  Z        cpu s")
    for phi in args.packings:
        for g in args.rates or RATES[phi]:
            r = flow_point(phi, g, args.n, args.seed, args.target, args.min_time, args.max_time)
            append(args.csv, r, FIELDS)
            print(
                f"{phi:4.2f}  {g:5.2f}  {r['interval']:.4f}  {r['time']:6.0f}  "
                f"{r['eta']:.4f} +- {r['eta_error']:.4f}  {'yes' if r['eta_converged'] else 'NO '}   "
                f"{r['n1']:+.4f} +- {r['n1_error']:.4f}  {r['n2']:+.4f} +- {r['n2_error']:.4f}  "
                f"{r['kT_mean']:.4f}   {r['Z']:.4f}  {r['cpu_s']:.0f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
