"""Validation of dense matter: jamming, crystallisation, dense equations of state.

    python validation/compress.py jam N RATE [RATE ...]   # LS jamming density per rate
    python validation/compress.py fluid N PHI [PHI ...]   # metastable fluid Z vs CS/Kolafa
    python validation/compress.py fcc K PHI [PHI ...]     # FCC crystal (4 K^3 spheres) vs Speedy
    python validation/compress.py mix N PHI [PHI ...]     # 50:50 mixture, ratio 1.4, vs BMCSL, HGR, SYH
    python validation/compress.py mixlong N PHI SEED [SEED ...]  # the same, longer, per seed

Everything is in a periodic box with equal masses and kT = 1; results
print as Markdown table rows (docs/validation/dense.md quotes them).  Pressure
error bars are from block averages (20 blocks; sigma of the mean).
"""

import math
import sys
import time

import numpy as np

import hardspheres as hs
from hardspheres import eos
from hardspheres.builders import _fcc, maxwell_boltzmann

# ---- equations of state (sources in docs/validation/dense.md) -----------------------------


def z_cs(eta):
    return float(eos.carnahan_starling(eta))


def z_hg(eta):
    return float(eos.hansen_goos(eta))


def z_klm(eta):
    return float(eos.kolafa(eta))


def z_speedy_crystal(eta):
    """Speedy (1998), FCC: Z = 3/(1-z) - a (z-b)/(z-c), z = eta/eta_cp."""
    z = eta / (math.pi / math.sqrt(18.0))
    a, b, c = 0.5921, 0.7072, 0.601
    return 3.0 / (1.0 - z) - a * (z - b) / (z - c)


def z_bmcsl(eta, diameters, fractions):
    """Boublik (1970); Mansoori, Carnahan, Starling & Leland (1971)."""
    return float(eos.bmcsl(eta, diameters, fractions))


def z_hgr(eta, diameters, fractions):
    """Hansen-Goos & Roth, J. Chem. Phys. 124, 154506 (2006)."""
    return float(eos.hansen_goos_roth(eta, diameters, fractions))


def z_syh(eta, diameters, fractions, pure=eos.kolafa):
    """Santos, Yuste & Lopez de Haro, Mol. Phys. 96, 1 (1999), on KLM by default."""
    return float(eos.santos_yuste_haro(eta, diameters, fractions, pure=pure))


# ---- helpers ----------------------------------------------------------------------


def box_for(n, phi, radius=1.0):
    return (n * 4.0 / 3.0 * math.pi * radius**3 / phi) ** (1.0 / 3.0)


EQUIL = 200  # collisions per sphere after a compression, before measuring


def measure_z(sim, collisions, blocks=20):
    """Z = PV/NkT in blocks of collisions: (mean, sigma of the mean)."""
    zs = []
    for _ in range(blocks):
        sim.observables.reset()
        sim.run(collisions=collisions // blocks)
        zs.append(sim.observables.compressibility())
    zs = np.array(zs)
    return float(zs.mean()), float(zs.std(ddof=1) / math.sqrt(blocks))


def q6(sim):
    """Mean Steinhardt q6 and the fraction of crystal-like spheres."""
    order = hs.BondOrder(num_neighbors=12).compute(sim)
    return order.mean_q, order.crystal_fraction


def fluid(n, phi0, seed=1):
    L = box_for(n, phi0)
    sim = hs.Simulation(hs.random_spheres(n, phi0, box=L, seed=seed), hs.PeriodicBox(L))
    sim.run(collisions=5 * n)
    return sim


# ---- the checks -------------------------------------------------------------------


def jam(n, rates, pressure=1e4, seed=1, trace=None):
    """Compress from a fluid at 0.3 until Z passes ``pressure``, one run per rate.

    ``trace``: a file name pattern with ``{rate}``; each rescale's (phi, Z,
    collisions) is written there as CSV (for phi_J(phi) = phi Z/(Z-3)).
    """
    print(
        "| N | rate gamma | phi at stop | Z at stop | phi_J = phi Z/(Z-3) | q6 | crystal-like |"
        " collisions | wall s |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for rate in rates:
        sim = fluid(n, 0.3, seed=seed)
        rows = []
        t0 = time.perf_counter()
        res = sim.compress(
            packing=0.74,
            rate=rate,
            pressure=pressure,
            progress=lambda phi, z, c, rows=rows: rows.append((phi, z, c)),
        )
        wall = time.perf_counter() - t0
        phij = res.packing * res.pressure / (res.pressure - 3.0)
        q, xtal = q6(sim)
        if trace:
            with open(trace.format(rate=rate), "w") as fh:
                fh.write("phi,Z,collisions\n")
                fh.writelines(f"{a:.8f},{b:.6g},{c}\n" for a, b, c in rows)
        print(
            f"| {n} | {rate:g} | {res.packing:.4f} | {res.pressure:.3g} | {phij:.4f} | "
            f"{q:.3f} | {xtal:.2f} | {res.collisions} | {wall:.0f} |",
            flush=True,
        )


def fluid_eos(n, phis, per_sphere=500, rate=0.005):
    print(
        "| N | phi | Z measured | CS | Hansen-Goos | KLM | (Z - HG)/sigma | (Z - KLM)/sigma |"
        " q6 | crystal-like |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for phi in phis:
        sim = fluid(n, 0.3)
        sim.compress(packing=phi, rate=rate)
        sim.run(collisions=EQUIL * n)
        z, s = measure_z(sim, per_sphere * n)
        q, xtal = q6(sim)
        zh, zk = z_hg(phi), z_klm(phi)
        print(
            f"| {n} | {phi} | {z:.4f} ± {s:.4f} | {z_cs(phi):.4f} | {zh:.4f} | {zk:.4f} | "
            f"{(z - zh) / s:+.1f} | {(z - zk) / s:+.1f} | {q:.3f} | {xtal:.2f} |",
            flush=True,
        )


def fcc_eos(k, phis, per_sphere=500, seed=1):
    n = 4 * k**3
    print("| N | phi | Z measured | Speedy (1998) | (Z - Speedy)/sigma | q6 |")
    print("|---|---|---|---|---|---|")
    for phi in phis:
        L = box_for(n, phi)
        pos = _fcc(k, L / k)
        rng = np.random.default_rng(seed)
        vel = maxwell_boltzmann(rng, np.ones(n))
        sim = hs.Simulation.from_arrays(np.ones(n), np.ones(n), pos, vel, hs.PeriodicBox(L))
        sim.run(collisions=EQUIL * n)
        z, s = measure_z(sim, per_sphere * n)
        q, _ = q6(sim)
        zs = z_speedy_crystal(phi)
        print(f"| {n} | {phi} | {z:.4f} ± {s:.4f} | {zs:.4f} | {(z - zs) / s:+.1f} | {q:.3f} |", flush=True)


def mix_eos(n, phis, ratio=1.4, per_sphere=500, seed=1, equil=EQUIL):
    print(
        "| N | phi | seed | Z measured | BMCSL | (Z - BMCSL)/sigma | Hansen-Goos-Roth |"
        " (Z - HGR)/sigma | SYH on KLM | (Z - SYH)/sigma |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for phi in phis:
        phi0 = 0.2
        L = box_for(n, phi0)
        state = hs.random_spheres(n, phi0, box=L, seed=seed)
        radii = state.radii.copy()
        radii[n // 2 :] /= ratio  # shrinking cannot overlap: 50:50, ratio 1.4
        sim = hs.Simulation.from_arrays(
            state.masses, radii, state.positions, state.velocities, hs.PeriodicBox(L)
        )
        sim.run(collisions=5 * n)
        sim.compress(packing=phi, rate=0.05)
        sim.run(collisions=equil * n)
        z, s = measure_z(sim, per_sphere * n)
        zb, zh = z_bmcsl(phi, [ratio, 1.0], [0.5, 0.5]), z_hgr(phi, [ratio, 1.0], [0.5, 0.5])
        zy = z_syh(phi, [ratio, 1.0], [0.5, 0.5])
        print(
            f"| {n} | {phi} | {seed} | {z:.4f} ± {s:.4f} | {zb:.4f} | {(z - zb) / s:+.1f} | "
            f"{zh:.4f} | {(z - zh) / s:+.1f} | {zy:.4f} | {(z - zy) / s:+.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    what, size, *rest = sys.argv[1:]
    if what == "jam" and rest and rest[-1].endswith(".csv"):  # jam N RATE... TRACE_{rate}.csv
        jam(int(size), [float(x) for x in rest[:-1]], trace=rest[-1])
    elif what == "mixlong":  # mixlong N PHI SEED [SEED ...]: 500 + 2000 collisions per sphere
        for sd in rest[1:]:
            mix_eos(int(size), [float(rest[0])], per_sphere=2000, seed=int(sd), equil=500)
    else:
        vals = [float(x) for x in rest]
        {"jam": jam, "fluid": fluid_eos, "fcc": fcc_eos, "mix": mix_eos}[what](int(size), vals)
