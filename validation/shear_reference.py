"""Shear flow on the brute-force reference: a small flow curve eta(g) against the equilibrium viscosity.

The compiled event core does not shear yet; the brute-force reference does
(every pair predicted after every event, its steps compiled here by numba
as the tests compile them).  For N = 108 equal spheres at packing 0.3
(sigma = m = kT = 1), held at kT = 1 by isokinetic rescaling of the peculiar
velocities (``PeculiarRescale``, every 0.05), it measures eta = -<P_xy>/g
at a few shear rates (``ShearFlow``, blocking errors) and compares the
smallest rates with the equilibrium Einstein-Helfand viscosity of the same
system from the compiled core (``ShearViscosity``), and with Enskog's.

usage:
    python3 validation/shear_reference.py                  # about 10 minutes on a loaded core
    python3 validation/shear_reference.py --scale 0.2      # a quick look
    python3 validation/shear_reference.py --profile docs/images/shear_profile.png   # 4 minutes

``--profile``: instead, 120 disks at area fraction 0.3 sheared at g = 0.05
(kT = 1, isokinetic every 0.5) for 600 time units, and the picture of
their streaming profile (the guide's, "Shear flow").

Units: sigma = m = kT = 1 (rates in sqrt(kT/m)/sigma).
"""

import argparse
import math
import time
import types
from collections.abc import Callable
from typing import Any

import numpy as np
from numba import njit

import hardspheres as hs
from hardspheres.analysis.transport import ShearViscosity, enskog
from hardspheres.core import _core, reference
from hardspheres.core.reference import Reference
from hardspheres.dense import PeculiarRescale
from hardspheres.observables import ShearFlow

N, PHI = 108, 0.3
RATES = (0.1, 0.2, 0.5, 1.0)


def _compiled(fn: Callable) -> Callable:
    """A step of the reference's loop compiled by numba, its kernels the core's (the same bits)."""
    glob = dict(fn.__globals__, pair_time=_core.pair_time, collide=_core.collide)
    for name in ("box_exit", "_earlier", "shear_offset"):
        if name in fn.__code__.co_names:
            glob[name] = _compiled(getattr(reference, name))
    return njit(types.FunctionType(fn.__code__, glob, fn.__name__, fn.__defaults__))


class FastReference(Reference):
    """The reference with its search and its collision compiled, on arrays."""

    _next_event_sheared = staticmethod(_compiled(reference.next_event_sheared))
    _next_event_periodic = staticmethod(_compiled(reference.next_event_periodic))

    def __init__(self, *args: Any, **kw: Any) -> None:
        super().__init__(*args, **kw)
        self.masses = np.array(self.masses)
        self._radii = np.array(self._radii)
        self._p = np.array(self._p).reshape(self.n, 3)
        self._v = np.array(self._v).reshape(self.n, 3)
        self._tloc = np.array(self._tloc)


def start(seed: int) -> tuple[hs.PeriodicBox, Any, np.ndarray]:
    """108 unit spheres on an FCC lattice at packing 0.3, Maxwell velocities at kT = 1, no drift."""
    box = hs.PeriodicBox.for_packing(N, PHI)
    s = hs.random_spheres(N, PHI, container=box, seed=seed)
    v = s.velocities - s.velocities.mean(axis=0)
    v *= math.sqrt(1.0 / (np.sum(v * v) / (3 * N - 3)))
    return box, s, v


def equilibrium(duration: float, seed: int) -> tuple[float, float]:
    box, s, v = start(seed)
    s.velocities[:] = v
    sim = hs.Simulation(s, box)
    sim.run(until=20.0)
    sim.observables.reset(every=0.1)
    sim.run(until=20.0 + duration)
    return ShearViscosity().compute(sim).value()


def sheared(rate: float, duration: float, seed: int) -> tuple[Any, Any, Any, Any, int]:
    box, s, v = start(seed)
    v[:, 0] += rate * s.positions[:, 1]
    eng = FastReference(s.masses, s.radii, s.positions, v, container=box.sheared_by(rate))
    flow = ShearFlow(eng, thermostat=PeculiarRescale(1.0, 0.05), every=0.5)
    flow.run(20.0)  # to the steady state
    flow.reset(every=0.5)
    flow.run(duration)
    eta = flow.viscosity()
    n1, n2 = flow.normal_stress_differences()
    kt = flow.estimate("temperature")
    return eta, n1, n2, kt, eng.counters["collisions"]


def profile_picture(path: str) -> None:
    """The guide's picture: the streaming profile of 120 sheared disks."""
    import matplotlib

    matplotlib.use("Agg")
    rate = 0.05
    box = hs.PeriodicBox((20.0, 20.0), shear_rate=rate)
    s = hs.random_spheres(120, 0.3, container=box, seed=1)
    v = s.velocities - s.velocities.mean(axis=0)
    v *= math.sqrt(1.0 / (np.sum(v * v) / (2 * 120 - 2)))
    v[:, 0] += rate * s.positions[:, 1]
    flow = ShearFlow(
        FastReference(s.masses, s.radii, s.positions, v, container=box),
        thermostat=PeculiarRescale(1.0, 0.5),
        layers=8,
    )
    flow.run(20.0)
    flow.reset()
    flow.run(600.0)
    y, u, _ = flow.profile()
    eta = flow.viscosity()
    print(f"slope {np.polyfit(y, u, 1)[0]:.4f} (g = {rate}), eta = {eta.mean:.4f} +- {eta.sem:.4f}")
    ax = flow.plot_profile()
    ax.set_title("120 disks, area fraction 0.3, g = 0.05, kT = 1: 600 time units")
    ax.figure.savefig(path, dpi=100)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scale", type=float, default=1.0, help="run lengths times this")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--profile", metavar="PNG", help="the streaming profile's picture instead")
    args = ap.parse_args()
    if args.profile:
        profile_picture(args.profile)
        return
    t0 = time.time()
    e_eq, e_err = equilibrium(2000.0 * args.scale, args.seed)
    print(f"N = {N}, packing {PHI}: Enskog eta = {enskog(PHI)['eta']:.4f}")
    took = time.time() - t0
    print(f"equilibrium (Einstein-Helfand, compiled core): eta = {e_eq:.4f} +- {e_err:.4f}  ({took:.0f} s)")
    print(" g      eta            N1             N2             kT        collisions  s")
    for g in RATES:
        t1 = time.time()
        eta, n1, n2, kt, coll = sheared(g, 300.0 * args.scale, args.seed)
        z = (eta.mean - e_eq) / math.hypot(eta.sem, e_err)
        print(
            f"{g:4.2f}  {eta.mean:.4f} +- {eta.sem:.4f}  {n1.mean:+.4f} +- {n1.sem:.4f}  "
            f"{n2.mean:+.4f} +- {n2.sem:.4f}  {kt.mean:.4f}  {coll:9d}  {time.time() - t1:4.0f}"
            f"   z vs equilibrium {z:+.2f}{'' if eta.converged else '  (blocking not converged)'}",
            flush=True,
        )


if __name__ == "__main__":
    main()
