"""Validation against the known hard-sphere equation of state, run as a study.

Equal spheres (diameter ``sigma = 1``, mass 1, ``kT = 1``) in a periodic box
at several packing fractions, each run a task of a study
(:mod:`hardspheres.studies`: every core, or a Dask cluster).  For each, the
compressibility factor ``Z = P V / (N kT)`` from the collision virial is
scored against the accurate equations of state of Hansen-Goos (2016) and
Kolafa-Labik-Malijevsky (2004) (:mod:`hardspheres.eos`) by the z-score
``(Z - Z_ref) / standard error``, and the measured collision rate against
the one that ``Z`` implies through the exact hard-sphere relation

    Gamma = 6 (Z - 1) / sigma * sqrt(kT / (pi m))

(collisions per sphere per unit time).  The speeds are compared with the
Maxwell-Boltzmann distribution by the Kolmogorov-Smirnov distance.
Standard errors come from block averages (20 blocks per run), pooled over
the runs when there are several seeds.
"""

import csv
import math
import os
import tempfile
from dataclasses import asdict, dataclass

import numpy as np

from .eos import carnahan_starling, hansen_goos, kolafa

PACKINGS = (0.1, 0.2, 0.3, 0.4, 0.45, 0.49)
MEASURE = ["Z", "collision_rate", "temperature", "speeds_ks"]
#: Mean of the Kolmogorov distribution, sqrt(pi/2) ln 2: ``sqrt(n) E[D]`` for
#: n independent samples of the right distribution.
KS_MEAN = math.sqrt(math.pi / 2.0) * math.log(2.0)


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
    """One packing fraction's results (dimensionless; rates per unit time)."""

    phi: float
    Z: float
    Z_err: float
    Z_HG: float
    z_HG: float
    Z_KLM: float
    z_KLM: float
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
    seeds: int


def _study(packings, n, equilibrate, collisions, blocks, seeds, folder):
    return {"output": folder, "container": "box", "packing": [float(p) for p in packings],
            "n": int(n), "seeds": list(seeds), "equilibrate": equilibrate,
            "collisions": collisions, "blocks": blocks, "measure": MEASURE}


def _rows(df, n, collisions):
    from .studies import summarize
    rows = []
    for r in summarize(df).to_dict("records"):
        # blocks of all seeds pooled: many more degrees of freedom than the
        # spread of a few seeds' means
        phi, z, z_err = r["packing"], r["Z"], r["Z_err_blocks"]
        hg, klm = float(hansen_goos(phi)), float(kolafa(phi))
        zcs = float(carnahan_starling(phi))
        g_z = 6.0 * (z - 1.0) * math.sqrt(r["temperature"] / math.pi)
        rows.append(Row(
            phi=phi, Z=z, Z_err=z_err, Z_HG=hg, z_HG=(z - hg) / z_err, Z_KLM=klm,
            z_KLM=(z - klm) / z_err, Z_CS=zcs, rel_diff=z / zcs - 1.0,
            gamma=r["collision_rate"], gamma_err=r["collision_rate_err_blocks"], gamma_from_Z=g_z,
            gamma_rel_diff=r["collision_rate"] / g_z - 1.0, ks_D=r["speeds_ks"],
            ks_D_expected=KS_MEAN / math.sqrt(n), n=n,
            collisions=int(collisions * n / 2), seeds=int(r["seeds"])))
    return rows


def measure(phi, n=4000, equilibrate=200, collisions=500, blocks=20, seed=0):
    """Run equal spheres at packing ``phi`` here and measure Z, Gamma and the speeds.

    One task of the validation study, run in this process.

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
    from .studies import sweep
    with tempfile.TemporaryDirectory() as folder:
        df = sweep(_study([phi], n, equilibrate, collisions, blocks, [seed], folder),
                   serial=True)
    return _rows(df, n, collisions)[0]


def validate(packings=PACKINGS, csv_path=None, out=None, n=4000, equilibrate=200,
             collisions=500, blocks=20, seed=0, seeds=1, client=None, serial=False,
             workers=None, folder=None, progress=None):
    """Measure every packing fraction as a study, print the table, write the CSV.

    Args:
        packings: packing fractions.
        csv_path: CSV to write (atomically), or None.
        out: text stream for the table, or None.
        n, equilibrate, collisions, blocks: as :func:`measure`.
        seed, seeds: the runs use seeds ``seed .. seed + seeds - 1`` at
            each packing (errors from all their blocks).
        client, serial, workers: where the runs go, as
            :func:`hardspheres.studies.sweep`.
        folder: keep the study here (a rerun then skips finished runs);
            default: a temporary folder, removed after.
        progress: text stream for the study's progress, or None.

    Returns:
        The list of :class:`Row`.
    """
    from .studies import sweep
    seed_list = range(seed, seed + seeds)
    if folder is None:
        with tempfile.TemporaryDirectory() as tmp:
            df = sweep(_study(packings, n, equilibrate, collisions, blocks, seed_list, tmp),
                       client=client, serial=serial, workers=workers, out=progress)
    else:
        df = sweep(_study(packings, n, equilibrate, collisions, blocks, seed_list,
                          os.path.abspath(folder)),
                   client=client, serial=serial, workers=workers, out=progress)
    rows = _rows(df, n, collisions)
    if out is not None:
        print(f"{'phi':>5} {'Z':>9} {'+-':>7} {'Z_HG':>9} {'z_HG':>6} {'Z_KLM':>9} "
              f"{'z_KLM':>6} {'Gamma':>9} {'Gamma(Z)':>9} {'G/G(Z)-1':>9} {'KS D':>7} "
              f"{'(exp.)':>7}", file=out)
        for r in rows:
            print(f"{r.phi:5.2f} {r.Z:9.4f} {r.Z_err:7.4f} {r.Z_HG:9.4f} {r.z_HG:+6.2f} "
                  f"{r.Z_KLM:9.4f} {r.z_KLM:+6.2f} {r.gamma:9.4f} {r.gamma_from_Z:9.4f} "
                  f"{r.gamma_rel_diff:+9.4%} {r.ks_D:7.4f} {r.ks_D_expected:7.4f}", file=out,
                  flush=True)
    if csv_path is not None:
        from .fileio import atomic_write
        with atomic_write(csv_path, "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(asdict(rows[0])))
            w.writeheader()
            for r in rows:
                w.writerow(asdict(r))
    return rows


def verdict(rows, bar=3.0):
    """Two lines: the largest z-scores and relative errors, and whether every Z passed.

    Z passes when it is within ``bar`` standard errors of both Hansen-Goos
    and KLM.
    """
    worst = max(rows, key=lambda r: max(abs(r.z_HG), abs(r.z_KLM)))
    worst_rel = max(r.Z_err / r.Z for r in rows)
    worst_g = max(abs(r.gamma_rel_diff) for r in rows)
    bad = [r.phi for r in rows if max(abs(r.z_HG), abs(r.z_KLM)) > bar]
    return [(f"largest |z| of Z: {abs(worst.z_HG):.2f} against Hansen-Goos, "
             f"{abs(worst.z_KLM):.2f} against KLM (packing {worst.phi:g}); "
             f"largest relative standard error of Z {worst_rel:.3%}; "
             f"largest |Gamma/Gamma(Z) - 1| = {worst_g:.3%}"),
            f"Z within {bar:g} standard errors of both at every packing" if not bad else
            f"Z more than {bar:g} standard errors from Hansen-Goos or KLM at packing "
            f"{', '.join(f'{p:g}' for p in bad)}"]
