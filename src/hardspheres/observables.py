"""Observables: time averages of a run from the event core's running tallies."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .simulation import Simulation


class Observables:
    """Averages over the run since the last :meth:`reset`, from the event core's tallies.

    The core adds a few numbers per event (impulse on the wall, collision
    virial), so keeping these costs the event loop almost nothing.

    Example:
        >>> import hardspheres as hs
        >>> state = hs.random_spheres(500, 0.2, box=20.0, seed=1)
        >>> sim = hs.Simulation(state, hs.PeriodicBox(20.0))
        >>> obs = sim.run(collisions=5000).observables.reset()
        >>> z = sim.run(collisions=20000).observables.compressibility()
        >>> abs(z / 2.406 - 1.0) < 0.05  # Carnahan-Starling at packing 0.2
        True
    """

    def __init__(self, sim: Simulation) -> None:
        self._sim = sim
        self.reset()

    def _now(self):
        eng = self._sim.engine
        c = eng.counters
        return (float(self._sim.time), float(c["collisions"]), float(c["reflections"]),
                eng.wall_impulse, eng.virial)

    def reset(self) -> Observables:
        """Start averaging afresh from now; returns self."""
        self._mark = self._now()
        return self

    def _delta(self):
        now = self._now()
        return tuple(a - b for a, b in zip(now, self._mark))

    @property
    def elapsed(self) -> float:
        """Time averaged over [time]."""
        return self._delta()[0]

    def _dof(self):
        return self._sim.container.degrees_of_freedom(self._sim.n)

    def temperature(self) -> float:
        """Kinetic temperature ``kT`` now [energy]: ``2 E_kin / degrees of freedom``.

        In a periodic box total momentum is conserved, so three degrees of
        freedom are not thermal.
        """
        return 2.0 * self._sim.engine.kinetic_energy() / max(self._dof(), 1)

    def pressure(self) -> float:
        """Pressure [energy/length^3] averaged since :meth:`reset`.

        Spherical container: momentum delivered to the wall per unit area
        and time.  Periodic box: ``(N kT + W / (3 t)) / V`` with ``W`` the
        collision virial ``sum r_ij . dp_i``.
        """
        dt, _, _, wall, virial = self._delta()
        if dt <= 0:
            raise ValueError("no time has passed since reset(); run first")
        return self._sim.container.pressure(self._sim.n, self.temperature(), dt, wall, virial)

    def compressibility(self) -> float:
        """``Z = P V / (N kT)`` since :meth:`reset`."""
        n, kT = self._sim.n, self.temperature()
        return self.pressure() * self._sim.container.volume / (n * kT)

    def collision_rate(self) -> float:
        """Collisions per sphere per unit time [1/time] (each collision counts for both)."""
        dt, coll, _, _, _ = self._delta()
        return 2.0 * coll / (self._sim.n * dt)

    def mean_free_time(self) -> float:
        """Mean time between collisions of a sphere [time] (``inf`` without any)."""
        rate = self.collision_rate()
        return 1.0 / rate if rate > 0 else np.inf

    def mean_speed(self) -> float:
        """Mean speed of the spheres now [length/time]."""
        return float(np.mean(np.linalg.norm(self._sim.engine.vel, axis=1)))

    def mean_free_path(self) -> float:
        """Mean distance a sphere travels between collisions [length]."""
        return self.mean_speed() * self.mean_free_time()

    def speed_histogram(self, bins: int = 50, range: tuple[float, float] | None = None,
                        ) -> tuple[np.ndarray, np.ndarray]:
        """Histogram of the speeds now: ``(counts, edges)`` [edges: length/time]."""
        speeds = np.linalg.norm(self._sim.engine.vel, axis=1)
        return np.histogram(speeds, bins=bins, range=range)

    def summary(self) -> dict[str, float]:
        """Dict of the observables (pressure and rates over the time since reset)."""
        out = {"time": self._sim.time, "elapsed": self.elapsed,
               "temperature": self.temperature()}
        if self.elapsed > 0:
            out.update(pressure=self.pressure(), compressibility=self.compressibility(),
                       collision_rate=self.collision_rate(),
                       mean_free_time=self.mean_free_time(),
                       mean_free_path=self.mean_free_path())
        return out
