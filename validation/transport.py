"""Transport validation: D, eta, lambda of the hard-sphere fluid against published MD.

Runs :func:`hardspheres.studies.validate.validate_transport`: at packing 0.2618
(rho sigma^3 = 0.5, DynamO's test system of 1372 spheres), 0.3 and 0.45,
with N = 500 and 1372, prints the measurements (with the Enskog ratios) and
the z-scores against the published values (sources in
``hardspheres.studies.validate`` and docs/validation/transport.md), and writes the scores to
docs/validation-transport.csv (``hardspheres plot transport`` draws it).

usage:
    python3 validation/transport.py                     # 33 M collisions: 325 s on 2 loaded cores
    python3 validation/transport.py --sizes 256 --scale 0.1 --csv /tmp/t.csv   # a minute
    python3 validation/transport.py --vacf              # the VACF's long-time tail at 0.45

Units: sigma = m = kT = 1.
"""

import argparse
import math
import sys
import time

import numpy as np

from hardspheres.studies.validate import TRANSPORT_PACKINGS, validate_transport

RHO05 = 0.5 * math.pi / 6.0
#: production runs [sigma sqrt(m/kT)]: about 15000 mean free times at rho = 0.5
#: (eta and lambda against DynamO), 10000 at 0.3 and 0.45
DURATIONS = {RHO05: 2000.0, 0.3: 990.0, 0.45: 352.0}


class _Velocities:
    """A writer keeping only the velocities (the VACF needs nothing else): a long run at
    frames a tenth of a mean free time apart fits in memory."""

    def __init__(self, every):
        self.every = every
        self.t, self.v = [], []

    def make(self, sim):
        from hardspheres.io.trajectory import FrameRecorder

        class Rec(FrameRecorder):
            def _write_frame(rec, sim, state, events):
                self.t.append(state.time)
                self.v.append(state.velocities.copy())
                rec._state = state

        return Rec(self.every, events=False)

    def frames(self, sim):
        from hardspheres.frames import Frames

        v = np.array(self.v)
        zeros = np.broadcast_to(np.zeros(1), v.shape)  # positions: not needed, not stored
        return Frames(
            np.array(self.t),
            zeros,
            v,
            sim.state().radii,
            sim.state().masses,
            sim.names,
            container=sim.container,
            images=np.broadcast_to(np.zeros(1, np.int64), v.shape),
        )


def vacf_tail(n=500, phi=0.45, mft_total=2000.0, seed=3):
    """C(t) at packing ``phi`` over ``mft_total`` mean free times: D from its integral to
    several cuts against the MSD's D (same run), and the tail against t^-3/2."""
    import hardspheres as hs
    from hardspheres.io.trajectory import FrameRecorder
    from hardspheres.analysis.transport import MSD, VACF

    L = (n * math.pi / (6.0 * phi)) ** (1.0 / 3.0)
    sim = hs.Simulation(hs.random_spheres(n, phi, box=L, seed=seed), hs.PeriodicBox(L))
    sim.run(collisions=50 * n)
    obs = sim.observables.reset()
    sim.run(collisions=5 * n)
    mft = obs.mean_free_time()
    vel = _Velocities(0.1 * mft)
    w_v = vel.make(sim)
    w_x = FrameRecorder(10 * mft, events=False)  # positions for the MSD, coarser
    sim.writers.extend([w_v, w_x])
    sim.run(until=sim.time + mft_total * mft)
    sim.writers.clear()
    v = VACF(blocks=5).compute(vel.frames(sim))
    D_msd, D_msd_err = MSD().compute(w_x.frames()).diffusion()
    print(
        f"packing {phi}, N = {n}, L = {L:.3f}, mean free time {mft:.5f}, "
        f"{mft_total:g} mean free times; D (MSD) = {D_msd:.5f} +- {D_msd_err:.5f}"
    )
    print("| cut [mean free times] | D (VACF) | D (VACF) / D (MSD) - 1 |")
    print("|---|---|---|")
    seg = v.t[len(v.t) // v.blocks - 1]
    for cut in (10, 25, 50, 100, 150, 200, 250, 300):
        if cut * mft > seg:
            break
        d, e = v.diffusion(t_max=cut * mft)
        print(f"| {cut} | {d:.5f} +- {e:.5f} | {d / D_msd - 1:+.2%} |")
    c = v.c / v.c[0]
    for lo, hi in ((5, 10), (10, 20), (20, 40), (40, 80), (80, 160), (160, 250), (250, 400)):
        sel = (v.t >= lo * mft) & (v.t < hi * mft)
        print(
            f"C(t)/C(0) over {lo}-{hi} mean free times: mean {np.mean(c[sel]):+.2e}, "
            f"times (t/mft)^1.5: {np.mean(c[sel] * (v.t[sel] / mft) ** 1.5):+.4f}"
        )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--packings", type=float, nargs="+", default=list(TRANSPORT_PACKINGS))
    ap.add_argument("--sizes", type=int, nargs="+", default=[500, 1372])
    ap.add_argument("--scale", type=float, default=1.0, help="multiply the run lengths")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--csv", default="docs/validation-transport.csv")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument(
        "--vacf",
        action="store_true",
        help="only the VACF tail study "
        "(at the first of --packings if given, else 0.45; N = the first of "
        "--sizes if given, else 500; --scale multiplies its 2000 mean free times)",
    )
    args = ap.parse_args(argv)
    if args.vacf:
        vacf_tail(
            n=args.sizes[0] if args.sizes != [500, 1372] else 500,
            phi=args.packings[0] if args.packings != list(TRANSPORT_PACKINGS) else 0.45,
            mft_total=2000.0 * args.scale,
            seed=3,
        )
        return 0
    dur = {p: args.scale * DURATIONS.get(p, 7000.0 * 0.1) for p in args.packings}
    t0 = time.perf_counter()
    rows, scores = validate_transport(
        packings=args.packings,
        sizes=args.sizes,
        duration=dur,
        seed=args.seed,
        out=sys.stdout,
        csv_path=args.csv,
        workers=args.workers,
    )
    print(
        f"\nwrote {args.csv}; {sum(r.collisions for r in rows)} collisions measured, "
        f"{time.perf_counter() - t0:.0f} s"
    )
    for r in rows:
        print(f"<!-- phi {r.phi:.4f} N {r.n}: {r.collisions} collisions, {r.seconds:.0f} s -->")
    return 0


if __name__ == "__main__":
    sys.exit(main())
