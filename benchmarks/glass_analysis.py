"""Time the glass and jamming analyses on a 10^4-sphere, 10^3-frame trajectory; measure their memory.

1. Simulates N = 10^4 equal spheres at packing 0.5 in a periodic box and
   keeps F = 10^3 frames (every 0.02, with events), then times each
   analysis on them (wall and CPU seconds): F_s(k, t) at two k
   (isotropic), F_s on lattice shells, F(k, t), alpha_2, G_s(r, t), Q and
   chi_4 (every frame an origin, 10 lags per decade), the free flights,
   recollisions and contact forces of the run's events.
2. Memory: the correlators read a frame at a time; a synthetic source of
   N = 10^4 spheres and F = 10^4 frames (positions made on demand, never
   stored) is analysed (Overlap, origins every 100 frames) under
   tracemalloc: the peak is what the analysis itself holds.

    python3 benchmarks/glass_analysis.py [--n 10000] [--frames 1000]
"""

import argparse
import json
import math
import resource
import time
import tracemalloc

import numpy as np

import hardspheres as hs
from hardspheres.analysis import collisions, dynamics
from hardspheres.io.trajectory import FrameRecorder


def timed(name, fn, out):
    w, c = time.perf_counter(), time.process_time()
    fn()
    out[name] = {"wall_s": round(time.perf_counter() - w, 2), "cpu_s": round(time.process_time() - c, 2)}
    print(name, out[name], flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=10_000)
    ap.add_argument("--frames", type=int, default=1000)
    ap.add_argument("--every", type=float, default=0.02)
    args = ap.parse_args()
    n, phi = args.n, 0.5
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=1), hs.PeriodicBox(box))
    sim.run(collisions=5 * n)
    rec = FrameRecorder(every=args.every)
    ev = collisions.EventRecorder()
    sim.writers += [rec, ev]
    t0 = time.perf_counter()
    sim.run(until=sim.time + args.every * (args.frames - 1) * (1 + 1e-12))
    fr = rec.frames()
    print(
        f"simulated {len(fr.times)} frames of {n} spheres, {ev.collisions} collisions in "
        f"{time.perf_counter() - t0:.1f} s",
        flush=True,
    )
    k = 2 * math.pi
    out = {}
    timed(
        "SelfIntermediate (2 k, isotropic)", lambda: dynamics.SelfIntermediate(k=[k, 2 * k]).compute(fr), out
    )
    timed(
        "SelfIntermediate (lattice, 50 vectors)",
        lambda: dynamics.SelfIntermediate(k=k, shell="lattice").compute(fr),
        out,
    )
    timed(
        "CollectiveIntermediate (100 vectors)", lambda: dynamics.CollectiveIntermediate(k=k).compute(fr), out
    )
    timed("NonGaussian", lambda: dynamics.NonGaussian().compute(fr), out)
    timed("VanHove", lambda: dynamics.VanHove().compute(fr), out)
    timed("Overlap (Q, chi_4)", lambda: dynamics.Overlap().compute(fr), out)
    timed("FreeFlights", lambda: collisions.FreeFlights().compute(ev), out)
    timed("Recollisions", lambda: collisions.Recollisions().compute(ev), out)
    timed("ContactForces", lambda: collisions.ContactForces().compute(ev), out)
    total = sum(v["wall_s"] for v in out.values())
    print(f"all analyses: {total:.1f} s wall", flush=True)

    # memory: N spheres, 10^4 frames made on demand
    frames = 10_000
    rng = np.random.default_rng(0)
    x0, v = rng.uniform(0, box, (n, 3)), rng.normal(size=(n, 3))
    times = np.arange(frames) * 0.01
    src = dynamics._Source(times, np.full(3, box), lambda f: x0 + v * times[f], None, None, n)
    tracemalloc.start()
    w = time.perf_counter()
    ov = dynamics.Overlap(a=0.3, origin_every=1.0).compute(src)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(
        f"Overlap of {n} spheres x {frames} frames (origins every 100 frames, {len(ov.t)} lags): "
        f"tracemalloc peak {peak / 2**20:.1f} MiB, {time.perf_counter() - w:.1f} s; "
        f"process max RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**10:.0f} MiB (with the "
        f"{len(fr.times)}-frame trajectory above in memory)",
        flush=True,
    )
    out["memory_peak_MiB"] = round(peak / 2**20, 1)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
