"""Validation against the known hard-sphere equation of state.

Equal spheres (diameter ``sigma = 1``, mass 1, ``kT = 1``) in a periodic box
at several packing fractions.  For each, the compressibility factor
``Z = P V / (N kT)`` from the collision virial is compared with
Carnahan-Starling, and the measured collision rate with the one that ``Z``
implies through the exact hard-sphere relation

    Gamma = 6 (Z - 1) / sigma * sqrt(kT / (pi m))

(collisions per sphere per unit time).  The speeds are compared with the
Maxwell-Boltzmann distribution by the Kolmogorov-Smirnov distance.
Statistical errors come from block averages.
"""

import csv
import math
from dataclasses import asdict, dataclass

import numpy as np

from .builders import random_spheres
from .containers import PeriodicBox
from .simulation import Simulation

PACKINGS = (0.1, 0.2, 0.3, 0.4, 0.45)


def carnahan_starling(phi):
    """Carnahan-Starling compressibility factor at packing fraction ``phi``."""
    return (1.0 + phi + phi * phi - phi ** 3) / (1.0 - phi) ** 3


def maxwell_cdf(v, kT=1.0, m=1.0):
    """Cumulative Maxwell-Boltzmann distribution of speeds ``v`` [length/time]."""
    a = math.sqrt(kT / m)
    x = np.asarray(v) / a
    erf = np.vectorize(math.erf)
    return erf(x / math.sqrt(2.0)) - np.sqrt(2.0 / math.pi) * x * np.exp(-0.5 * x * x)


def ks_distance(speeds, kT=1.0, m=1.0):
    """Largest gap between the speeds' empirical CDF and Maxwell-Boltzmann's."""
    s = np.sort(np.asarray(speeds))
    n = len(s)
    cdf = maxwell_cdf(s, kT, m)
    hi = np.arange(1, n + 1) / n - cdf
    lo = cdf - np.arange(0, n) / n
    return float(max(hi.max(), lo.max()))


@dataclass
class Row:
    """One packing fraction's results."""

    phi: float
    Z: float
    Z_err: float
    Z_CS: float
    rel_diff: float
    gamma: float
    gamma_err: float
    gamma_from_Z: float
    gamma_rel_diff: float
    ks_D: float
    ks_D_expected: float
    n: int
    collisions: int


def measure(phi, n=4000, equilibrate=50, collisions=500, blocks=20, seed=0):
    """Run equal spheres at packing ``phi`` and measure Z, Gamma and the speeds.

    Args:
        phi: packing fraction.
        n: number of spheres.
        equilibrate: collisions per sphere before measuring (the FCC start
            melts within a few).
        collisions: collisions per sphere measured.
        blocks: blocks for the statistical errors.
        seed: random seed.

    Returns:
        A :class:`Row`.
    """
    sigma, kT, m = 1.0, 1.0, 1.0
    box = (n * math.pi * sigma ** 3 / (6.0 * phi)) ** (1.0 / 3.0)
    state = random_spheres(n, phi, box=box, seed=seed, kT=kT)
    sim = Simulation(state, PeriodicBox(box))
    sim.run(collisions=equilibrate * n // 2)
    per_block = max(1, collisions * n // (2 * blocks))
    zs, gammas, speeds = [], [], []
    for _ in range(blocks):
        obs = sim.observables.reset()
        sim.run(collisions=per_block)
        zs.append(obs.compressibility())
        gammas.append(obs.collision_rate())
        speeds.append(np.linalg.norm(sim.state().velocities, axis=1))
    kT_meas = sim.observables.temperature()
    zs, gammas = np.array(zs), np.array(gammas)
    z, z_err = zs.mean(), zs.std(ddof=1) / math.sqrt(blocks)
    g, g_err = gammas.mean(), gammas.std(ddof=1) / math.sqrt(blocks)
    g_z = 6.0 * (z - 1.0) / sigma * math.sqrt(kT_meas / (math.pi * m))
    zcs = carnahan_starling(phi)
    all_speeds = np.concatenate(speeds)
    return Row(phi=phi, Z=z, Z_err=z_err, Z_CS=zcs, rel_diff=z / zcs - 1.0,
               gamma=g, gamma_err=g_err, gamma_from_Z=g_z, gamma_rel_diff=g / g_z - 1.0,
               ks_D=ks_distance(all_speeds, kT_meas, m),
               ks_D_expected=1.36 / math.sqrt(len(all_speeds)),
               n=n, collisions=per_block * blocks)


def validate(packings=PACKINGS, csv_path=None, out=None, **kw):
    """Measure every packing fraction, print the table, write the CSV.

    Returns:
        The list of :class:`Row`.
    """
    rows = []
    header = (f"{'phi':>5} {'Z':>9} {'+-':>7} {'Z_CS':>8} {'Z/Z_CS-1':>9} "
              f"{'Gamma':>9} {'Gamma(Z)':>9} {'G/G(Z)-1':>9} {'KS D':>7} {'(95%)':>7}")
    if out is not None:
        print(header, file=out, flush=True)
    for phi in packings:
        r = measure(phi, **kw)
        rows.append(r)
        if out is not None:
            print(f"{r.phi:5.2f} {r.Z:9.4f} {r.Z_err:7.4f} {r.Z_CS:8.4f} {r.rel_diff:+9.4%} "
                  f"{r.gamma:9.4f} {r.gamma_from_Z:9.4f} {r.gamma_rel_diff:+9.4%} "
                  f"{r.ks_D:7.4f} {r.ks_D_expected:7.4f}", file=out, flush=True)
    if csv_path is not None:
        from .fileio import atomic_write
        with atomic_write(csv_path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(asdict(rows[0])))
            w.writeheader()
            for r in rows:
                w.writerow(asdict(r))
    return rows
