"""A dilute sheared granular gas (uniform shear flow) against Boltzmann kinetic theory.

N inelastic hard spheres (sigma = m = 1, restitution e) in a cubic
Lees-Edwards box at packing ``phi`` (0.01-0.02), sheared at rate g, no
thermostat: the gas heats by viscous work and cools by its collisions
until the two balance (uniform shear flow, USF).  In that steady state
the reduced shear rate

    a* = g / nu_0(T),   nu_0(T) = p / eta_0(T) = (16/5) n sigma^2 sqrt(pi T / m)

and the reduced viscosity eta* = eta / eta_0(T), with eta_0(T) =
(5 / (16 sigma^2)) sqrt(m T / pi) the elastic Boltzmann viscosity (first
Sonine approximation) at the steady peculiar temperature T, depend on e
alone.  Grad's moment method for the Boltzmann equation gives (cooling
rate and collision coefficient in units of nu_0)

    zeta* = (5/12)(1 - e^2),   beta = (1 + e)(3 - e)/4,
    a*^2 = (3/2) zeta* beta^2 / (beta - zeta*),   eta* = (beta - zeta*) / beta^2,

see docs/validation/shear.md for the source and the definitions.

Measured: T, the peculiar kT sampled every ``--sample`` time units over
the production run (blocking error); eta = -P_xy / g (the pressure
tensor's kinetic and collisional parts, blocking error); the collision
rate per sphere; the cooling rate (the energy lost in collisions).  The
finite packing adds Enskog's corrections (at packing 0.01 about +1% to
a* and eta* and +3% to the collision rate and zeta*, measured): three
packings per e and a straight line to packing 0 separate them.

usage:
    python3 validation/shear_granular.py --e 0.9 --packing 0.01 --strain 10000   # one row, about a minute
    python3 validation/shear_granular.py --tables                   # the table from the CSV

Results: ``validation/results/shear_granular.csv`` (one row per run,
appended), the printed table in ``validation/results/shear_granular.txt``.
Units: sigma = m = 1; the time unit is 1/g with g = 1 by default (T is
then in units of m (g sigma)^2).
"""

import argparse
import csv
import math
import os
import time

import numpy as np

import hardspheres as hs
from hardspheres.blocking import blocking

HERE = os.path.dirname(os.path.abspath(__file__))
CSV = os.path.join(HERE, "results", "shear_granular.csv")

FIELDS = [
    "e", "packing", "n", "rate", "seed", "transient", "time", "strain", "collisions",
    "kT", "kT_error", "eta", "eta_error", "eta_converged", "pxx", "pyy", "pzz", "pxy",
    "collision_rate", "collision_rate_error", "a_star", "a_star_error", "eta_star",
    "eta_star_error", "zeta_star", "work_over_dissipation", "cpu_s",
]  # fmt: skip


def grad(e: float) -> tuple[float, float]:
    """``(a*, eta*)`` of steady USF, Grad's solution of the Boltzmann equation (3-D)."""
    zeta = 5.0 / 12.0 * (1.0 - e * e)
    beta = (1.0 + e) * (3.0 - e) / 4.0
    return math.sqrt(1.5 * zeta * beta**2 / (beta - zeta)), (beta - zeta) / beta**2


def nu0(density: float, kT: float) -> float:
    """``p / eta_0``: (16/5) n sqrt(pi T) [1/time], sigma = m = 1."""
    return 16.0 / 5.0 * density * math.sqrt(math.pi * kT)


def eta0(kT: float) -> float:
    """Boltzmann's elastic viscosity (first Sonine) (5/16) sqrt(T / pi), sigma = m = 1."""
    return 5.0 / 16.0 * math.sqrt(kT / math.pi)


def run(e: float, phi: float, n: int, rate: float, seed: int, strain: float, transient: float,
        sample: float) -> dict:  # fmt: skip
    cpu0 = time.process_time()
    box = hs.PeriodicBox.for_packing(n, phi, (1, 1, 1)).sheared_by(rate)
    state = hs.random_spheres(n, phi, box, seed=seed)
    a_guess, _ = grad(e)
    density = n / box.volume
    kT0 = (rate / (a_guess * nu0(density, 1.0))) ** 2  # start near the steady temperature
    v = state.velocities - state.velocities.mean(axis=0)
    v *= math.sqrt(kT0 / (np.sum(v * v) / (3 * n - 3)))
    v[:, 0] += rate * state.positions[:, 1]
    state.velocities[:] = v
    sim = hs.Simulation(state, box, restitution=e)
    sim.run(until=transient / rate)
    sim.observables.reset()
    c0 = sim.engine.counters["collisions"]
    t_end = sim.time + strain / rate
    kts = []
    while sim.time < t_end - 1e-12:
        sim.run(until=min(sim.time + sample / rate, t_end))
        kts.append(sim.observables.temperature())
    coll = sim.engine.counters["collisions"] - c0
    lost = sim.observables.dissipated()
    elapsed = strain / rate
    bt = blocking(np.array(kts))
    eta = sim.observables.estimate("viscosity")
    cr = sim.observables.estimate("collision_rate")
    p = sim.observables.pressure_tensor()
    kT, kT_err = bt.mean, bt.sem
    a_star = rate / nu0(density, kT)
    e_star = eta.mean / eta0(kT)
    return {
        "e": e, "packing": phi, "n": n, "rate": rate, "seed": seed, "transient": transient,
        "time": strain / rate, "strain": strain, "collisions": coll,
        "kT": kT, "kT_error": kT_err, "eta": eta.mean, "eta_error": eta.sem,
        "eta_converged": bool(eta.converged and bt.converged),
        "pxx": p[0, 0], "pyy": p[1, 1], "pzz": p[2, 2], "pxy": p[0, 1],
        "collision_rate": cr.mean, "collision_rate_error": cr.sem,
        "a_star": a_star, "a_star_error": 0.5 * a_star * kT_err / kT,
        "eta_star": e_star,
        "eta_star_error": e_star * math.hypot(eta.sem / eta.mean, 0.5 * kT_err / kT),
        # the cooling rate measured: zeta = (energy lost per time) / (peculiar kinetic energy (3N - 3) T / 2)
        "zeta_star": lost / elapsed / (1.5 * (n - 1) * kT) / nu0(density, kT),
        # the shear's work -g P_xy V over the energy lost: 1 in a steady state
        "work_over_dissipation": -rate * p[0, 1] * box.volume * elapsed / lost,
        "cpu_s": time.process_time() - cpu0,
    }  # fmt: skip


def tables(path: str) -> None:
    with open(path) as f:
        rows = list(csv.DictReader(f))
    print("| e | packing | N | g | strain | collisions | a* | a* Grad | eta* | eta* Grad | "
          "zeta* | zeta* Grad | work / loss | nu_coll / nu_0 | converged | CPU s |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: (-float(r["e"]), float(r["packing"]), float(r["rate"]))):
        e, phi = float(r["e"]), float(r["packing"])
        ag, eg = grad(e)
        density = 6.0 * phi / math.pi
        ratio = float(r["collision_rate"]) / nu0(density, float(r["kT"]))
        print(
            f"| {e:g} | {phi:g} | {r['n']} | {float(r['rate']):g} | {float(r['strain']):g} | "
            f"{int(r['collisions']):.2e} | {float(r['a_star']):.4f}({1e4 * float(r['a_star_error']):.0f}) | "
            f"{ag:.4f} | {float(r['eta_star']):.4f}({1e4 * float(r['eta_star_error']):.0f}) | {eg:.4f} | "
            f"{float(r['zeta_star']):.4f} | {5.0 / 12.0 * (1.0 - e * e):.4f} | "
            f"{float(r['work_over_dissipation']):.4f} | {ratio:.4f} | {r['eta_converged']} | "
            f"{float(r['cpu_s']):.0f} |"
        )
    print()
    print("Straight lines in the packing to packing 0 (per e and g, two packings or more):")
    keys = sorted({(float(r["e"]), float(r["rate"])) for r in rows}, reverse=True)
    for e, g in keys:
        sub = [r for r in rows if float(r["e"]) == e and float(r["rate"]) == g]
        phis = sorted({float(r["packing"]) for r in sub})
        if len(phis) < 2:
            continue
        x = np.array([float(r["packing"]) for r in sub])
        for name in ("a_star", "eta_star"):
            y = np.array([float(r[name]) for r in sub])
            w = 1.0 / np.array([float(r[f"{name}_error"]) for r in sub]) ** 2
            # weighted least squares y = c0 + c1 x
            a = np.vstack([np.ones_like(x), x]).T
            cov = np.linalg.inv(a.T @ (a * w[:, None]))
            c = cov @ (a.T @ (w * y))
            ag, eg = grad(e)
            ref = ag if name == "a_star" else eg
            print(f"e = {e:g}, g = {g:g}: {name} at packing 0 = {c[0]:.4f} +- {math.sqrt(cov[0, 0]):.4f}"
                  f" (slope {c[1]:.2f}); Grad {ref:.4f}")  # fmt: skip


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--e", type=float, default=0.9, help="restitution (default 0.9)")
    p.add_argument("--packing", type=float, default=0.01)
    p.add_argument("-n", type=int, default=500)
    p.add_argument("--rate", type=float, default=1.0, help="shear rate g (default 1)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--strain", type=float, default=2000.0, help="production strain g t (default 2000)")
    p.add_argument("--transient", type=float, default=100.0, help="strain to the steady state (default 100)")
    p.add_argument("--sample", type=float, default=0.5, help="strain between kT samples (default 0.5)")
    p.add_argument("--tables", action="store_true", help="print the table from the CSV and stop")
    p.add_argument("--csv", default=CSV)
    args = p.parse_args()
    if args.tables:
        tables(args.csv)
        return
    row = run(args.e, args.packing, args.n, args.rate, args.seed, args.strain, args.transient, args.sample)
    ag, eg = grad(args.e)
    print(
        f"e {args.e:g} packing {args.packing:g} N {args.n} g {args.rate:g}: kT {row['kT']:.5g}"
        f"({row['kT_error']:.2g}), a* {row['a_star']:.4f}({row['a_star_error']:.4f}) [Grad {ag:.4f}], "
        f"eta* {row['eta_star']:.4f}({row['eta_star_error']:.4f}) [Grad {eg:.4f}], "
        f"zeta* {row['zeta_star']:.4f} [{5.0 / 12.0 * (1.0 - args.e**2):.4f}], "
        f"work/loss {row['work_over_dissipation']:.4f}, "
        f"{row['collisions']} collisions, converged {row['eta_converged']}, CPU {row['cpu_s']:.0f} s",
        flush=True,
    )
    new = not os.path.exists(args.csv)
    with open(args.csv, "a", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        if new:
            w.writeheader()
        w.writerow(row)


if __name__ == "__main__":
    main()
