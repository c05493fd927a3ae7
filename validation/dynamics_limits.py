"""The exact limits of F_s and alpha_2 (docs/validation/glass-jamming.md, "Dynamics: exact limits").

1. Short times in a dilute gas (packing 1e-3, N = 4000, t up to 1/20 of the
   mean free time): F_s(k, t) = exp(-k^2 kT t^2 / (2 m)) and alpha_2 = 0
   (Maxwell-Boltzmann velocities, free flight), scored in units of the
   spheres' sampling error.
2. Long times in a fluid (packing 0.2 and 0.4, N = 1000): -d ln F_s / dt =
   k^2 D at k = 2 pi / L, D from the MSD (freud) of the same run.

    python3 validation/dynamics_limits.py
"""

import math

import numpy as np

import hardspheres as hs
from hardspheres.analysis.dynamics import NonGaussian, SelfIntermediate
from hardspheres.io.trajectory import frames_from_simulation


def short_times(n=4000, seed=11):
    box = hs.PeriodicBox.for_packing(n, 1e-3).length
    sim = hs.Simulation(hs.random_spheres(n, 1e-3, box=box, seed=seed), hs.PeriodicBox(box))
    v = sim.state().velocities.copy()
    mft = 1 / (4 * math.sqrt(math.pi) * n / box**3)  # dilute: sigma = m = kT = 1, g = 1
    fr = frames_from_simulation(sim, until=mft / 20, every=mft / 400)
    kT = float(np.mean(v**2))
    fs = SelfIntermediate(k=[2 * math.pi, 10.0, 20.0]).compute(fr)
    exact = np.exp(-np.outer(fs.t**2, fs.k**2) * kT / 2)
    score = np.abs(fs.F - exact) / fs.particle_error
    ng = NonGaussian().compute(fr)
    a2 = np.abs(ng.alpha2) / ng.alpha2_particle_error
    print(
        f"short times: N = {n}, packing 1e-3, {sim.counters['collisions']} collisions, "
        f"t = {fs.t[0]:.3g}..{fs.t[-1]:.3g} (mean free time {mft:.4g}), F_s from {fs.F.min():.3g} to 1"
    )
    print(
        f"  max |F_s - exp(-k^2 kT t^2/2m)| = {np.max(np.abs(fs.F - exact)):.2e}, "
        f"max in sampling errors {score.max():.2f}"
    )
    print(
        f"  alpha_2 from {ng.alpha2.min():+.4f} to {ng.alpha2.max():+.4f}, max |alpha_2| in errors {a2.max():.2f}"
    )


def long_times(phi, n=1000, seed=5, length=80.0):
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=seed), hs.PeriodicBox(box))
    sim.run(collisions=10 * n)
    fr = frames_from_simulation(sim, until=sim.time + length, every=0.25)
    msd = hs.MSD(blocks=4).compute(fr)
    D, D_err = msd.diffusion(t_min=5.0, t_max=15.0)
    k = 2 * math.pi / box
    fs = SelfIntermediate(k=k, lags=[5.0, 10.0, 15.0, 20.0], blocks=4).compute(fr)
    F, e = fs.F[:, 0], fs.error[:, 0]
    slope, cov = np.polyfit(fs.t, np.log(F), 1, w=F / e, cov="unscaled")
    Dk, Dk_err = -slope[0] / k**2, math.sqrt(cov[0, 0]) / k**2
    print(
        f"long times: packing {phi}, N = {n}, {length:g} time units, k = 2 pi / L = {k:.4f}: "
        f"-d ln F_s/dt / k^2 = {Dk:.5f} +- {Dk_err:.5f}, D (MSD, 5-15) = {D:.5f} +- {D_err:.5f}, "
        f"difference {(Dk - D) / math.hypot(Dk_err, D_err):+.2f} sigma; F_s {F[0]:.3f} to {F[-1]:.3f}"
    )


if __name__ == "__main__":
    short_times()
    long_times(0.2)
    long_times(0.4)
