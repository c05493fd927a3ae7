"""Mean free time from the event record against the exact one from Z (docs/validation/glass-jamming.md).

N = 1000 equal spheres (sigma = m = kT = 1) in a periodic box, 5 collisions
per sphere to equilibrate, then 200 recorded with an EventRecorder: the
mean free time 1 / Gamma (FreeFlights) against sigma sqrt(pi m / kT) /
(6 (Z - 1)) with Z from the same run's virial (Observables).

    python3 validation/free_flights.py
"""

import math

import hardspheres as hs
from hardspheres.analysis.collisions import EventRecorder, FreeFlights, Recollisions, mean_free_time_from_z

for phi in (0.05, 0.3, 0.45):
    n = 1000
    box = hs.PeriodicBox.for_packing(n, phi).length
    sim = hs.Simulation(hs.random_spheres(n, phi, box=box, seed=1), hs.PeriodicBox(box))
    sim.run(collisions=5 * n)
    sim.observables.reset()
    rec = EventRecorder()
    sim.writers.append(rec)
    sim.run(collisions=200 * n)
    obs = sim.observables
    z, z_err, kT = obs.compressibility(), obs.error("compressibility"), obs.temperature()
    ff = FreeFlights().compute(rec)
    exact = mean_free_time_from_z(z, kT=kT)
    err = math.hypot(ff.mean_error, exact * z_err / (z - 1))
    rc = Recollisions().compute(rec)
    print(
        f"phi {phi}: Z = {z:.4f} +- {z_err:.4f}; mean free time {ff.mean:.6f} (record) vs {exact:.6f} (from Z): "
        f"{(ff.mean / exact - 1) * 100:+.3f}% = {(ff.mean - exact) / err:+.2f} sigma; complete flights' mean "
        f"{ff.flight_mean:.6f}; collisions per sphere {ff.per_sphere.mean():.1f} (min {ff.per_sphere.min()}); "
        f"pairs recolliding within one mean free time: {rc.within(ff.mean):.3f} of collisions"
    )
