"""Granular gases: Haff's law and a_2 in the homogeneous cooling state (docs/validation/granular.md).

Equal spheres (sigma = m = 1, kT = 1 at the start, total momentum zero) at
packing 0.1 and 0.3 in a periodic box, restitution e, no driving: the gas cools
in its homogeneous cooling state (HCS).  For each dimension and e, several
seeds are run from C = 0 to C_END collisions per sphere (each collision
counts for both), sampled every half collision per sphere.

* Cooling per collision: the slope of ln T against C over C_START..C_END
  (least squares, per seed; mean and standard error over seeds), against
  Haff's law to first order, (1 - e^2) / d, and with the first Sonine
  correction (1 + 3 a_2 / 16) / (1 - a_2 / 16) (van Noije and Ernst,
  Granular Matter 1, 57 (1998); the Enskog factor cancels per collision).
* a_2 = <v^4> / (<v^2>^2 (1 + 2/d)) - 1 averaged over the samples past
  C_START, less the finite-N offset of a gas at fixed energy and momentum,
  -2 / (d (N - 1) + 2) (checked by the elastic control row), against van
  Noije and Ernst's first Sonine a_2 = 16 (1 - e)(1 - 2 e^2) / (9 + 24 d -
  e (41 - 8 d) + 30 e^2 (1 - e)).
* The collision rate against Enskog's, nu_E = chi (Boltzmann's rate) at
  the temperature of each interval, times (1 - a_2 / 16); chi from
  Carnahan-Starling (3-D) or Henderson (2-D).

The box side stays below the shear instability's critical length
L_c = 2 pi / k_c, k_c^2 = zeta_0 rho / (2 eta) (linearised hydrodynamics of
the HCS, Goldhirsch and Zanetti, Phys. Rev. Lett. 70, 1619 (1993); Brilliantov
and Poeschel, Kinetic Theory of Granular Gases, OUP 2004), with Boltzmann's
viscosity and collision rate: L_c = 10.78 lambda / sqrt(1 - e^2) in 3-D and
10.03 lambda / sqrt(1 - e^2) in 2-D (lambda the mean free path); each row
prints L / L_c.

The driven steady state (``driven``): white-noise kicks
(:class:`hardspheres.dense.RandomKicks`) at the strength xi_0^2 whose
steady temperature is kT = 1 by Enskog's theory with van Noije and Ernst's
first Sonine a_2 of the white-noise driven state (Granular Matter 1, 57
(1998)), a_2 = 16 (1 - e)(1 - 2 e^2) / (73 + 56 d - 3 e (35 + 8 d) + 30 e^2
(1 - e)): the measured kT against 1, against the energy balance with the
measured collision rate, and the measured a_2 against the formula.

    python3 validation/granular.py            # every part but long
    python3 validation/granular.py hcs        # validation/results/granular.txt
    python3 validation/granular.py driven     # validation/results/granular_driven.txt
    python3 validation/granular.py clusters   # validation/results/granular_clusters.txt (and .gsd)
    python3 validation/granular.py cluster-pictures   # reads them: docs/images/granular_*.png
    python3 validation/granular.py long       # 1e8 collisions, TC model (not in the default run)
"""

import math
import os
import sys
import time
import warnings

import numpy as np

import hardspheres as hs
import hardspheres.errors
from hardspheres.fileio import atomic_write

PHI = 0.1
C_START, C_END = 5.0, 40.0
#: (d, packing, e, N, seeds): N small enough for L < L_c (Enskog's; see the docstring)
CASES = [
    (3, 0.1, 1.0, 1000, 10),
    (3, 0.1, 0.9, 1000, 10),
    (3, 0.1, 0.8, 500, 10),
    (3, 0.1, 0.6, 250, 10),
    (2, 0.1, 1.0, 200, 10),
    (2, 0.1, 0.9, 200, 10),
    (2, 0.1, 0.8, 100, 10),
    (2, 0.1, 0.6, 64, 10),
    (3, 0.3, 1.0, 300, 10),
    (3, 0.3, 0.9, 300, 10),
    (3, 0.3, 0.8, 120, 20),
    (3, 0.3, 0.6, 50, 40),
    (2, 0.3, 1.0, 72, 40),
    (2, 0.3, 0.9, 72, 40),
    (2, 0.3, 0.8, 36, 40),
    (2, 0.3, 0.6, 20, 40),
]


def a2_sonine(e: float, d: int) -> float:
    """van Noije and Ernst's first Sonine a_2 of the HCS in d dimensions."""
    denominator = 9.0 + 24.0 * d - e * (41.0 - 8.0 * d) + 30.0 * e * e * (1.0 - e)
    return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) / denominator


def chi(d: int, phi: float) -> float:
    """Contact value of the pair correlation: Carnahan-Starling (3-D), Henderson (2-D)."""
    if d == 3:
        return (1.0 - phi / 2.0) / (1.0 - phi) ** 3
    return (1.0 - 7.0 * phi / 16.0) / (1.0 - phi) ** 2


def boltzmann_rate(d: int, n_density: float, kT: float) -> float:
    """Collisions per sphere per unit time of a dilute gas of unit diameter and mass."""
    if d == 3:
        return 4.0 * n_density * math.sqrt(math.pi * kT)
    return 2.0 * n_density * math.sqrt(math.pi * kT)


def critical_length(d: int, e: float, n_density: float) -> float:
    """The shear mode's critical length L_c of the HCS (Boltzmann transport), inf at e = 1."""
    if e >= 1.0:
        return math.inf
    if d == 3:
        lam = 1.0 / (math.sqrt(2.0) * math.pi * n_density)
        return 2.0 * math.pi * lam / math.sqrt(16.0 * (1.0 - e * e) / (15.0 * math.pi))
    lam = 1.0 / (2.0 * math.sqrt(2.0) * n_density)
    return 2.0 * math.pi * lam / math.sqrt(math.pi * (1.0 - e * e) / 8.0)


def one_run(d: int, phi: float, e: float, n: int, seed: int) -> dict:
    box = hs.PeriodicBox.for_packing(n, phi, None if d == 3 else (1.0, 1.0))
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=seed), box, restitution=e)
    obs = sim.observables
    e0 = sim.engine.kinetic_energy()
    rows = []
    step = max(1, n // 4)  # half a collision per sphere
    while True:
        c = 2.0 * sim.counters["collisions"] / n
        kT = 2.0 * sim.engine.kinetic_energy() / (d * n)
        rows.append((c, sim.time, kT, obs.a2()))
        if c >= C_END:
            break
        sim.run(collisions=step)
    balance = (sim.engine.kinetic_energy() + sim.dissipated) / e0 - 1.0
    return {"rows": np.array(rows), "balance": balance, "side": box.sides[0], "n_density": n / box.volume}


# ---- the driven steady state: white-noise kicks --------------------------------

#: (d, e, N) of the driven rows (packing PHI): no cooling, so no critical length to stay under
DRIVEN = [(3, 0.9, 500), (3, 0.6, 500), (2, 0.9, 400), (2, 0.6, 400)]
DRIVEN_SEEDS = 4
#: collisions per sphere: relaxation, then measurement, sampled every half
C_RELAX, C_MEASURE = 20.0, 200.0
#: the kicks' interval in mean free times (at the predicted temperature)
KICKS_PER_FREE_TIME = 20.0


def a2_white_noise(e: float, d: int) -> float:
    """van Noije and Ernst's first Sonine a_2 of the white-noise driven steady state in d dimensions."""
    denominator = 73.0 + 56.0 * d - 3.0 * e * (35.0 + 8.0 * d) + 30.0 * e * e * (1.0 - e)
    return 16.0 * (1.0 - e) * (1.0 - 2.0 * e * e) / denominator


def driven_strength(d: int, e: float, n: int, n_density: float, kT: float) -> float:
    """The kicks' strength xi_0^2 whose steady state is kT by Enskog's theory with the first Sonine a_2.

    Injection (N - 1) d xi_0^2 / 2 = dissipation (N / 2) nu_E(T) (1 - e^2) T (1 + 3 a_2 / 16),
    nu_E = chi nu_Boltzmann (unit diameter and mass).
    """
    a2 = a2_white_noise(e, d)
    loss = chi(d, PHI) * boltzmann_rate(d, n_density, kT) * (1.0 - e * e) * kT * (1.0 + 3.0 * a2 / 16.0)
    return n * loss / ((n - 1) * d)


def driven_run(d: int, e: float, n: int, seed: int) -> dict:
    """One driven run at the strength whose predicted steady state is kT = 1."""
    from hardspheres.dense import RandomKicks

    box = hs.PeriodicBox.for_packing(n, PHI, None if d == 3 else (1.0, 1.0))
    n_density = n / box.volume
    strength = driven_strength(d, e, n, n_density, 1.0)
    free_time = 1.0 / (chi(d, PHI) * boltzmann_rate(d, n_density, 1.0))
    kicks = RandomKicks(strength, free_time / KICKS_PER_FREE_TIME, seed=1000 + seed)
    sim = hs.Simulation(hs.random_spheres(n, PHI, box, seed=seed), box, restitution=e)
    sim.set_thermostat(kicks)
    obs = sim.observables
    step = max(1, n // 4)
    sim.run(collisions=int(C_RELAX * n / 2))
    obs.reset()
    t0, c0 = sim.time, sim.counters["collisions"]
    rows = []
    while 2.0 * (sim.counters["collisions"] - c0) / n < C_MEASURE:
        sim.run(collisions=step)
        rows.append((obs.temperature(), obs.a2()))
    kts, a2s = np.array(rows).T
    elapsed = sim.time - t0
    return {
        "kT": float(np.mean(kts)),
        "a2": float(np.mean(a2s)),
        "nu": 2.0 * (sim.counters["collisions"] - c0) / n / elapsed,
        "injection": obs.injected() / elapsed,
        "dissipation": obs.dissipated() / elapsed,
        "balance": abs(obs.energy_balance()),
        "expected_injection": kicks.injection_rate(sim.engine.masses, d),
        "n_density": n_density,
        "kicks": kicks.kicks,
    }


def driven_table() -> list[str]:
    """The driven rows: steady kT against Enskog-Sonine theory and against the measured energy balance."""
    out = [
        f"{'d':>2} {'e':>4} {'N':>5} {'kT':>8} {'+-':>7} {'kT theory':>9} {'kT bal':>8} {'+-':>7} "
        f"{'a2':>8} {'+-':>7} {'a2 WN':>8} {'a2 HCS':>8} {'nu/nu_E':>8} {'inj/diss':>9} {'inj/exp':>8} "
        f"{'balance':>9}"
    ]
    for d, e, n in DRIVEN:
        runs = [driven_run(d, e, n, seed) for seed in range(DRIVEN_SEEDS)]
        offset = -2.0 / (d * (n - 1) + 2.0)

        def mean_err(key: str, runs: list = runs) -> tuple[float, float]:
            x = np.array([r[key] for r in runs])
            return float(np.mean(x)), float(np.std(x, ddof=1) / math.sqrt(len(x)))

        kt, kt_err = mean_err("kT")
        a2, a2_err = mean_err("a2")
        a2 -= offset
        # the energy balance with the measured collision rate and a_2: the temperature at which the
        # collisions dissipate (1 - e^2) T (1 + 3 a2/16) / (1 - a2/16) each what the kicks inject
        bal = []
        for r in runs:
            a2r = r["a2"] - offset
            per_t = 0.5 * n * r["nu"] * (1.0 - e * e) * (1.0 + 3.0 * a2r / 16.0) / (1.0 - a2r / 16.0)
            bal.append(r["expected_injection"] / per_t)
        kb, kb_err = float(np.mean(bal)), float(np.std(bal, ddof=1) / math.sqrt(len(bal)))
        nu_e = np.mean(
            [
                r["nu"]
                / (
                    chi(d, PHI)
                    * boltzmann_rate(d, r["n_density"], r["kT"])
                    * (1.0 - a2_white_noise(e, d) / 16.0)
                )
                for r in runs
            ]
        )
        inj = np.mean([r["injection"] / r["dissipation"] for r in runs])
        inj_exp = np.mean([r["injection"] / r["expected_injection"] for r in runs])
        out.append(
            f"{d:>2} {e:>4.1f} {n:>5} {kt:>8.4f} {kt_err:>7.4f} {1.0:>9.4f} {kb:>8.4f} {kb_err:>7.4f} "
            f"{a2:>+8.4f} {a2_err:>7.4f} {a2_white_noise(e, d):>+8.4f} {a2_sonine(e, d):>+8.4f} {nu_e:>8.4f} "
            f"{inj:>9.4f} {inj_exp:>8.4f} {max(r['balance'] for r in runs):>9.1e}"
        )
        print(out[-1], flush=True)
    out.append("")
    out.append(
        f"driven: packing {PHI}, {DRIVEN_SEEDS} seeds per row, kicks every 1/{KICKS_PER_FREE_TIME:g} of the "
        f"mean free time at the strength whose Enskog-Sonine steady state is kT = 1; relaxed for "
        f"{C_RELAX:g} collisions per sphere, measured over {C_MEASURE:g}; kT bal: the temperature at which "
        "the "
        "measured collision rate dissipates what the kicks inject (first Sonine loss with the measured a2); "
        "inj/diss: injected over dissipated energy per unit time; inj/exp: injected over (N-1) d xi0^2 / 2"
    )
    return out


def write(name: str, lines: list[str]) -> None:
    """``lines`` into validation/results/``name``."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", name)
    with atomic_write(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"wrote {path}")


def driven() -> None:
    """The driven steady state's table, into validation/results/granular_driven.txt."""
    t_start = time.perf_counter()
    out = driven_table()
    out[-1] += f"; {time.perf_counter() - t_start:.0f} s"
    write("granular_driven.txt", out)


def hcs() -> None:
    """The homogeneous cooling state's table, into validation/results/granular.txt."""
    out = []
    t_start = time.perf_counter()
    header = (
        f"{'d':>2} {'phi':>4} {'e':>4} {'N':>5} {'seeds':>5} {'L/L_c':>6} {'-dlnT/dC':>10} {'+-':>8} "
        f"{'Haff 1st':>9} {'Sonine':>9} {'dev1 %':>7} {'devS %':>7} {'a2':>8} {'+-':>7} {'a2 vNE':>8} "
        f"{'nu/nu_E':>8} {'+-':>7} {'balance':>9}"
    )
    out.append(header)
    for d, phi, e, n, seeds in CASES:
        slopes, a2s, rates, balances = [], [], [], []
        side = n_density = 0.0
        for seed in range(seeds):
            r = one_run(d, phi, e, n, seed)
            side, n_density = r["side"], r["n_density"]
            rows = r["rows"]
            c, t, kT, a2 = rows.T
            use = c >= C_START
            slopes.append(-np.polyfit(c[use], np.log(kT[use]), 1)[0] if e < 1.0 else 0.0)
            a2s.append(float(np.mean(a2[use])))
            # collisions against Enskog's rate at each interval's mean temperature
            dt = np.diff(t[use])
            kmid = 0.5 * (kT[use][1:] + kT[use][:-1])
            enskog = np.sum(chi(d, phi) * np.array([boltzmann_rate(d, n_density, k) for k in kmid]) * dt)
            rates.append((c[use][-1] - c[use][0]) / enskog)
            balances.append(abs(r["balance"]))
        offset = -2.0 / (d * (n - 1) + 2.0)
        a2 = float(np.mean(a2s)) - offset
        a2_err = float(np.std(a2s, ddof=1) / math.sqrt(seeds))
        theory_a2 = a2_sonine(e, d)
        first = (1.0 - e * e) / d
        sonine = first * (1.0 + 3.0 * theory_a2 / 16.0) / (1.0 - theory_a2 / 16.0)
        s, s_err = float(np.mean(slopes)), float(np.std(slopes, ddof=1) / math.sqrt(seeds))
        nu, nu_err = float(np.mean(rates)), float(np.std(rates, ddof=1) / math.sqrt(seeds))
        nu_theory = 1.0 - theory_a2 / 16.0
        lc = critical_length_enskog(d, e, phi, n_density)
        dev1 = (s / first - 1.0) * 100.0 if e < 1.0 else 0.0
        devs = (s / sonine - 1.0) * 100.0 if e < 1.0 else 0.0
        out.append(
            f"{d:>2} {phi:>4.1f} {e:>4.1f} {n:>5} {seeds:>5} {side / lc:>6.2f} {s:>10.5f} {s_err:>8.5f} "
            f"{first:>9.5f} "
            f"{sonine:>9.5f} {dev1:>+7.2f} {devs:>+7.2f} {a2:>+8.4f} {a2_err:>7.4f} {theory_a2:>+8.4f} "
            f"{nu / nu_theory:>8.4f} {nu_err:>7.4f} {max(balances):>9.1e}"
        )
        print(out[-1], flush=True)
    out.append("")
    out.append(
        f"C = {C_START:g}..{C_END:g} collisions per sphere; L_c with Enskog's collision rate and viscosity; "
        "a2 less the finite-N offset -2/(d(N-1)+2); nu/nu_E: collision rate over Enskog's "
        "(chi: Carnahan-Starling, Henderson) times (1 - a2/16) with van Noije-Ernst's a2; balance: "
        "largest |(E_kin + E_dissipated)/E_0 - 1|; "
        f"{time.perf_counter() - t_start:.0f} s"
    )
    write("granular.txt", out)


# ---- clustering above the critical length ----------------------------------------

#: the clustering runs: disks at this packing and restitution
CLUSTER_PHI, CLUSTER_E = 0.25, 0.6
#: (N, seeds): far above L_c, and below it
CLUSTER_SIZES = [(4096, 4), (32, 40)]
#: collisions per sphere: to the end, and between samples of S(k)
CLUSTER_C_END, CLUSTER_C_STEP = 400.0, 10.0
#: the largest run's frame kept for the pictures: at the end
CLUSTER_FRAME_EVERY = CLUSTER_C_END


def enskog_viscosity_factor(d: int, phi: float) -> float:
    """Enskog's shear viscosity over Boltzmann's at packing ``phi`` (the single-Sonine forms).

    3-D: ``1/chi + 4/5 (4 phi) + 0.7614 (4 phi)^2 chi`` (Chapman and Cowling); 2-D: ``1/chi +
    2 phi + (1 + 8/pi) phi^2 chi`` (Gass, J. Chem. Phys. 54, 1898 (1971)).
    """
    c = chi(d, phi)
    if d == 3:
        b = 4.0 * phi
        return 1.0 / c + 0.8 * b + 0.7614 * b * b * c
    return 1.0 / c + 2.0 * phi + (1.0 + 8.0 / math.pi) * phi * phi * c


def critical_length_enskog(d: int, e: float, phi: float, n_density: float) -> float:
    """L_c with Enskog's collision rate (``chi`` times) and viscosity: ``L_c sqrt(eta_E / (chi eta_0))``."""
    return critical_length(d, e, n_density) * math.sqrt(enskog_viscosity_factor(d, phi) / chi(d, phi))


class ScaledHCS:
    """Every ``interval``, velocities less their mean, scaled to ``kT`` (a thermostat for the HCS).

    In the homogeneous cooling state the thermal speeds fall exponentially in the collisions,
    while the total momentum, conserved, keeps the rounding of the first collisions: after a few
    hundred collisions per sphere at e = 0.6 (a factor 1e-16 in speed) that drift is all that
    moves.  Taking it off and scaling back to ``kT`` is a change of the time unit: the sequence
    of collisions is the HCS's (the TC model's ``tc`` then stays a fixed fraction of the mean
    free time).
    """

    def __init__(self, kT: float, interval: float) -> None:
        self.kT, self.interval = kT, interval
        self.next_time: float | None = None

    def attach(self, sim: hs.Simulation) -> None:
        if self.next_time is None:
            self.next_time = sim.time + self.interval

    def apply(self, sim: hs.Simulation, t: float) -> None:
        eng = sim.engine
        m = np.asarray(eng.masses, float)
        v = eng.velocities - (m @ eng.velocities) / m.sum()
        kt = float(np.sum(m[:, None] * v * v)) / (v.size - v.shape[1])
        v *= math.sqrt(self.kT / kt)
        for i in range(sim.n):
            eng.kick(i, t, v[i])
        self.next_time = t + self.interval

    def state(self) -> str:
        return "{}"


def cluster_run(n: int, seed: int, frames: str | None = None) -> np.ndarray:
    """S(k) at the smallest |k| and the local density's spread every CLUSTER_C_STEP, from C = 0.

    Disks equilibrated elastic for 5 collisions each, then restitution CLUSTER_E with the TC
    model (``tc`` 1e-3 of the mean free time), the drift taken off and the velocities scaled
    to the initial kT every mean free time (:class:`ScaledHCS`).  Rows: (C, S(k_min), the
    standard deviation of the local packing fraction).
    """
    from hardspheres.analysis.granular import LocalDensity, LowKStructureFactor
    from hardspheres.io.trajectory import GSDWriter
    from hardspheres.writers import EveryCollisions

    box = hs.PeriodicBox.for_packing(n, CLUSTER_PHI, (1.0, 1.0))
    sim = hs.Simulation(hs.random_spheres(n, CLUSTER_PHI, box, seed=seed), box)
    sim.run(collisions=5 * n // 2)
    free_time = 1.0 / sim.observables.collision_rate()
    sim.set_restitution(CLUSTER_E, tc=1e-3 * free_time)
    sim.set_thermostat(ScaledHCS(kT=sim.observables.temperature(), interval=free_time))
    writer = None
    if frames is not None:
        writer = GSDWriter(frames, trigger=EveryCollisions(int(CLUSTER_FRAME_EVERY * n / 2)), events=False)
        sim.writers.append(writer)
    c0 = sim.counters["collisions"]
    rows = []
    while True:
        c = 2.0 * (sim.counters["collisions"] - c0) / n
        s = LowKStructureFactor().compute(sim).S[0]
        spread = float(LocalDensity(method="cells").compute(sim).values.std())
        rows.append((c, s, spread))
        if c >= CLUSTER_C_END - 1e-9:
            break
        sim.run(collisions=int(round(CLUSTER_C_STEP * n / 2)))
    if writer is not None:
        writer.close()
    return np.array(rows)


def clusters() -> None:
    """The clustering runs: validation/results/granular_clusters.txt and granular_clusters.gsd."""
    t_start = time.perf_counter()
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")
    curves = {}
    for n, seeds in CLUSTER_SIZES:
        runs = []
        for seed in range(seeds):
            keep = (
                os.path.join(here, "granular_clusters.gsd")
                if (n == CLUSTER_SIZES[0][0] and seed == 0)
                else None
            )
            runs.append(cluster_run(n, seed, keep))
            print(f"N = {n}, seed {seed}: S(k_min) at the end {runs[-1][-1, 1]:.2f}", flush=True)
        curves[n] = np.array(runs)
    n_density = CLUSTER_PHI / (math.pi / 4.0)
    lc = critical_length_enskog(2, CLUSTER_E, CLUSTER_PHI, n_density)
    head = ["C"]
    for n, seeds in CLUSTER_SIZES:
        side = math.sqrt(n / n_density)
        head += [f"S N={n} (L/L_c {side / lc:.2f}, {seeds} seeds)", "+-", "sd(phi_local)"]
    out = ["\t".join(head)]
    c = curves[CLUSTER_SIZES[0][0]][0][:, 0]
    for i, ci in enumerate(c):
        row = [f"{ci:.0f}"]
        for n, seeds in CLUSTER_SIZES:
            r = curves[n][:, i, :]
            err = float(np.std(r[:, 1], ddof=1) / math.sqrt(seeds)) if seeds > 1 else math.nan
            row += [f"{r[:, 1].mean():.4g}", f"{err:.2g}", f"{r[:, 2].mean():.4f}"]
        out.append("\t".join(row))
    out.append("")
    out.append(
        f"disks at packing {CLUSTER_PHI}, e = {CLUSTER_E}, TC model tc = 1e-3 of the mean free time, "
        "velocities less their mean scaled to the initial kT every mean free time; "
        f"L_c = {lc:.2f} (the shear mode, Enskog's collision rate and viscosity); C: collisions per disk; "
        "S: S(k) at the box's smallest |k| = 2 pi / L (mean over seeds); sd(phi_local): the spread of the "
        f"disks' local packing fraction on a grid of cells; {time.perf_counter() - t_start:.0f} s"
    )
    write("granular_clusters.txt", out)


def cluster_pictures() -> None:
    """Reads the clustering results (never runs): docs/images/granular_sk.png and granular_clusters.png."""
    from hardspheres.extras import need
    from hardspheres.io.trajectory import read_trajectory
    from hardspheres.viz.render import render_still

    plt = need("matplotlib.pyplot", "the clustering pictures")
    here = os.path.dirname(os.path.abspath(__file__))
    images = os.path.join(here, "..", "docs", "images")
    lines = open(os.path.join(here, "results", "granular_clusters.txt")).read().splitlines()
    head = lines[0].split("\t")
    table = []
    for line in lines[1:]:
        if not line.strip():
            break
        table.append([float(x) for x in line.split("\t")])
    data = np.array(table)
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for col in range(1, len(head), 3):
        ax.errorbar(
            data[:, 0], data[:, col], yerr=np.nan_to_num(data[:, col + 1]), label=head[col][2:], capsize=2
        )
    ax.set_yscale("log")
    ax.set_xlabel("collisions per disk C")
    ax.set_ylabel("S(k) at the smallest k = 2 pi / L")
    ax.set_title(f"disks, packing {CLUSTER_PHI}, e = {CLUSTER_E}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(images, "granular_sk.png"), dpi=110)
    with warnings.catch_warnings():  # the run was to a collision count: no end time to reach
        warnings.simplefilter("ignore")
        frames = read_trajectory(os.path.join(here, "results", "granular_clusters.gsd"))
    render_still(
        frames,
        os.path.join(images, "granular_clusters.png"),
        color_by="density",
        size=(1280, 720),
        title=f"e = {CLUSTER_E}, C = {CLUSTER_C_END:g}",
    )
    print(f"wrote {images}/granular_sk.png and granular_clusters.png")


# ---- a long run with the TC model: 1e8 collisions ---------------------------------

#: 1000 disks at area fraction 0.5, e = 0.5, tc = 1e-3 of the elastic mean free time
LONG_N, LONG_PHI, LONG_E, LONG_TC = 1000, 0.5, 0.5, 1e-3
LONG_COLLISIONS, LONG_CHUNK = 100_000_000, 2_000_000


def take_off_drift(sim: hs.Simulation) -> float:
    """Every velocity less the mass-weighted mean, now; returns the kinetic energy taken off.

    A periodic box conserves the total momentum to rounding, about 1e-17 of the first speeds.
    Once a cooling gas's thermal speeds fall to that (kinetic energy 1e-34 of the start), the
    gas drifts as a whole: cell crossings per collision grow without bound.
    """
    eng = sim.engine
    m = np.asarray(eng.masses, float)
    v = eng.velocities - (m @ eng.velocities) / m.sum()
    before = eng.kinetic_energy()
    t = sim.time  # (Engine.kick takes its own time as the clock, whatever the rounding)
    for i in range(sim.n):
        eng.kick(i, t, v[i])
    return before - eng.kinetic_energy()


def long_run() -> None:
    """1e8 collisions at e = 0.5 with the TC model; validation/results/granular_long.txt."""
    box = hs.PeriodicBox.for_packing(LONG_N, LONG_PHI, (1.0, 1.0))
    sim = hs.Simulation(hs.random_spheres(LONG_N, LONG_PHI, box, seed=1), box)
    sim.run(collisions=20 * LONG_N)
    free_time = 1.0 / sim.observables.collision_rate()
    sim.set_restitution(LONG_E, tc=LONG_TC * free_time)
    eng = sim.engine
    e0, d0 = eng.kinetic_energy(), sim.dissipated
    removed = 0.0
    out = [f"{'collisions':>11} {'wall s':>8} {'E_kin/E_0':>10} {'crossings/coll':>14} {'balance':>9}"]
    t_start = time.perf_counter()
    c_prev = dict(sim.counters)
    done = 0
    while done < LONG_COLLISIONS:
        sim.run(collisions=LONG_CHUNK)
        done += LONG_CHUNK
        removed += take_off_drift(sim)
        c = sim.counters
        crossings = (c["crossings"] - c_prev["crossings"]) / LONG_CHUNK
        c_prev = dict(c)
        ke = eng.kinetic_energy()
        balance = (ke + sim.dissipated - d0 + removed) / e0 - 1.0
        out.append(
            f"{done:>11.3g} {time.perf_counter() - t_start:>8.1f} {ke / e0:>10.3e} {crossings:>14.2f} "
            f"{balance:>+9.1e}"
        )
        print(out[-1], flush=True)
    out.append("")
    out.append(
        f"{LONG_N} disks, area fraction {LONG_PHI}, equilibrated elastic, then e = {LONG_E} with tc = "
        f"{LONG_TC:g} of the mean free time ({LONG_TC * free_time:.3g}); the drift (total momentum's "
        f"rounding) taken off every {LONG_CHUNK:g} collisions ({removed / e0:.1e} of E_0 in all); balance: "
        "(E_kin + E_dissipated + E_drift taken off) / E_0 - 1"
    )
    write("granular_long.txt", out)


PARTS = {
    "hcs": hcs,
    "driven": driven,
    "clusters": clusters,
    "cluster-pictures": cluster_pictures,
    "long": long_run,
}


def main(argv: list[str]) -> int:
    """Run the parts named in ``argv`` (all but ``long`` without one); 1 on an unknown name."""
    names = argv or [x for x in PARTS if x != "long"]
    unknown = [x for x in names if x not in PARTS]
    if unknown:
        print(f"unknown part {unknown[0]!r}: give some of {', '.join(PARTS)}", file=sys.stderr)
        return 1
    for name in names:
        PARTS[name]()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
