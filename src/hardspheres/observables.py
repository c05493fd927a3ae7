"""Observables: time averages of a run from the event core's running tallies.

Sheared runs (Lees-Edwards boundaries, :class:`ShearFlow`) have their own
averages: the shear stress, the viscosity, the normal stress differences,
the temperature of the peculiar velocities and the streaming profile.

Error bars: the tallies are also sampled on a grid of equally spaced times
(one *block* between neighbouring samples), and the standard error of each
average comes from Flyvbjerg-Petersen blocking of the per-block values
(:mod:`hardspheres.blocking`).

Granular gases (restitution below 1) cool: the temperature is no longer
constant, so the time averages that divide by ``kT`` (pressure, ``Z``) are
left out of :meth:`Observables.summary` for them, and the granular
observables take their place: the energy dissipated (the core's tally), the
cooling rate, the cooling per collision (Haff's law) and the kurtosis
``a_2`` of the velocity distribution.  The grid starts fine and coarsens by two
(neighbouring blocks merge) whenever :attr:`Observables.MAX_SAMPLES` is
reached, so memory stays bounded however long the run, and, on the
automatic grid, while blocks hold fewer than :attr:`Observables.MIN_EVENTS`
events, so sampling stays cheap in small systems.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .blocking import Blocking, blocking
from .containers import require_periodic
from .errors import NoMeasurementError  # noqa: F401 (re-exported)
from .errors import ArgumentError, DriftWarning, ShearError
from .writers import SimulationView

# columns of a tally sample (the transport tallies follow in a periodic box)
_T, _COLL, _REFL, _WALL, _VIRIAL = range(5)
_VIR_T = slice(5, 11)  # collisional virial tensor (xx yy zz xy xz yz)
_KIN_T = slice(11, 17)  # time integral of the kinetic tensor
_HEAT_C = slice(17, 20)  # heat Helfand moment: collisional part
_HEAT_K = slice(20, 23)  # heat Helfand moment: free flight
# a stepped run's samples end with two snapshots (not tallies): the kinetic and potential energy then
_K_NOW, _U_NOW = -2, -1
_TENSOR = ("xx", "yy", "zz", "xy", "xz", "yz")
_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


class Observables:
    """Averages over the run since the last :meth:`reset`, from the event core's tallies.

    The core adds a few numbers per event (impulse on the wall, collision
    virial), so keeping these costs the event loop almost nothing.

    Example:
        >>> import hardspheres as hs
        >>> state = hs.random_spheres(500, 0.2, box=20.0, seed=1)
        >>> sim = hs.Simulation(state, hs.PeriodicBox(20.0))
        >>> obs = sim.run(collisions=5000).observables.reset()
        >>> z = sim.run(collisions=20000).observables.Z()
        >>> abs(z / 2.406 - 1.0) < 0.05  # Carnahan-Starling at packing 0.2
        True
    """

    #: Samples kept before neighbouring blocks merge (the interval doubles):
    #: 2^16, so that the transport fits keep lags of about a mean free time
    #: in runs of 10^4 mean free times or more (a sample is 23 numbers in a
    #: periodic box, about 0.8 kB as kept: 50 MB at the cap).  Set it per
    #: run with ``reset(max_samples=...)``; :attr:`merges` counts the
    #: doublings the cap caused.
    MAX_SAMPLES = 65536
    #: With the automatic interval, blocks merge (the interval doubles) while
    #: they hold fewer events than this: a sample costs about as much as a
    #: hundred events, so small systems would otherwise pay for sampling.
    MIN_EVENTS = 500

    def __init__(self, sim: SimulationView, every: float | None = None) -> None:
        self._sim = sim
        #: a sheared box's rate [1/time] (0: not sheared): temperature and stress then peculiar
        self._shear_rate = float(getattr(sim.container, "shear_rate", 0.0))
        #: the pair potential's steps (empty: hard spheres): the potential energy is sampled then
        self._stepped = bool(getattr(sim, "steps", ()))
        self.reset(every)

    def _now(self) -> tuple[float, ...]:
        eng = self._sim.engine
        c = eng.counters
        t = float(self._sim.time)
        now: tuple[float, ...] = (
            t,
            float(c["collisions"]),
            float(c["reflections"]),
            eng.wall_impulse,
            eng.virial,
        )
        if self._sim.container.periodic:  # the transport tallies
            tt = eng.transport_tallies(t)
            if self._shear_rate:  # a sheared box: the kinetic tensor of the peculiar velocities
                tt["kinetic"] = eng.stress_tallies(t)["kinetic"]
            now += tuple(
                np.concatenate(
                    [tt["virial"], tt["kinetic"], tt["heat_collisional"], tt["heat_kinetic"]]
                ).tolist()
            )
        if self._stepped:  # snapshots, not tallies: the last two columns (K, U now)
            now += (eng.kinetic_energy(), eng.potential_energy())
        return now

    def reset(self, every: float | None = None, max_samples: int | None = None) -> Observables:
        """Start averaging afresh from now; returns self.

        Args:
            max_samples: samples kept before neighbouring blocks merge
                (default :attr:`MAX_SAMPLES`, at least 16).
            every: first interval between tally samples (blocks) [time];
                default: a tenth of the time a sphere of rms speed takes to
                cross the mean spacing ``(V/N)^(1/3)`` (about a mean free
                time in a dense fluid), doubled while a block holds fewer
                than :attr:`MIN_EVENTS` events.  It doubles whenever
                :attr:`MAX_SAMPLES` is reached.
        """
        if max_samples is not None:
            if not (isinstance(max_samples, int) and max_samples >= 16):
                raise ArgumentError(f"max_samples must be an integer >= 16, got {max_samples!r}")
            self.MAX_SAMPLES = max_samples
        self.merges = 0
        eng = self._sim.engine
        self._granular_mark = (eng.kinetic_energy(), eng.dissipated)  # (energy now and dissipated)
        #: the total energy K + U at reset (the drift check of a stepped run)
        self._energy_mark = eng.kinetic_energy() + (eng.potential_energy() if self._stepped else 0.0)
        # a driving thermostat's tally now, and what thermostats replaced since injected
        self._injected_mark = (self._injected_total(), 0.0)
        self._mark = self._now()
        self._samples = [self._mark]
        self._auto = every is None
        self.every = float(every) if every is not None else self._auto_every()
        if not self.every > 0:
            raise ArgumentError(f"every must be a time > 0, got {every}")
        self.next_sample = self._mark[_T] + self.every
        return self

    def _auto_every(self) -> float:
        sim = self._sim
        n = sim.n
        v2 = float(np.mean(np.sum(sim.engine.velocities**2, axis=1))) if n else 0.0
        if v2 <= 0.0:
            return math.inf
        # a tenth of the spacing (V/N)^(1/d) at the mean speed
        return 0.1 * (sim.container.volume / n) ** (1.0 / sim.container.dimensions) / math.sqrt(v2)

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The arrays :meth:`restore` takes back: the mark, the samples, the schedule.

        :meth:`hardspheres.Simulation.save` stores them in its checkpoint, so
        a resumed run averages over the same blocks as the run it continues.
        """
        return {
            "obs": np.array(self._mark, dtype=np.float64),
            "obs_samples": np.array(self._samples, dtype=np.float64),
            "obs_every": np.array([self.every, self.next_sample]),
        }

    def restore(self, arrays: dict[str, np.ndarray]) -> bool:
        """Take back what :meth:`checkpoint` gave, checked first; returns whether it was taken.

        A mark of another length (an older checkpoint's layout) or damaged
        arrays leave the averages starting afresh from now (``False``).
        """
        mark = arrays.get("obs")
        samples = arrays.get("obs_samples")
        every = arrays.get("obs_every")
        if mark is None or mark.ndim != 1 or len(mark) != len(self._mark):
            return False
        self._mark = tuple(mark.tolist())
        self._samples = [self._mark]
        if (
            samples is not None
            and every is not None
            and samples.ndim == 2
            and samples.shape[1] == len(mark)
            and samples.shape[0] >= 1
            and np.all(np.isfinite(samples))
            and every.shape == (2,)
            and every[0] > 0
        ):
            self._samples = [tuple(r) for r in samples.tolist()]
            self.every, self.next_sample = every.tolist()
        return True

    def sample(self) -> None:
        """Record the tallies now (the simulation calls this at :attr:`next_sample`)."""
        now = self._now()
        last = self._samples[-1]
        sparse = (
            self._auto
            and len(self._samples) > 2
            and now[_COLL] + now[_REFL] - last[_COLL] - last[_REFL] < self.MIN_EVENTS
        )
        self._samples.append(now)
        full = len(self._samples) > self.MAX_SAMPLES
        if full or sparse:
            self.merges += full
            # merge neighbouring blocks: keep every other sample from the mark
            # (an odd last block waits for its partner)
            if len(self._samples) % 2 == 0:
                self._samples.pop()
            self._samples = self._samples[::2]
            self.every *= 2.0
        self.next_sample = self._samples[-1][_T] + self.every

    @property
    def n_blocks(self) -> int:
        """Number of complete blocks sampled since :meth:`reset`."""
        return len(self._samples) - 1

    def _delta(self) -> tuple[float, ...]:
        now = self._now()
        return tuple(a - b for a, b in zip(now, self._mark))

    @property
    def elapsed(self) -> float:
        """Time averaged over [time]."""
        return self._delta()[0]

    def _dof(self) -> int:
        return self._sim.container.degrees_of_freedom(self._sim.n)

    def temperature(self) -> float:
        """Kinetic temperature ``kT`` now [energy]: ``2 E_kin / degrees of freedom``.

        ``d`` degrees of freedom per sphere (``d = 2`` for disks); in a
        periodic box total momentum is conserved, so ``d`` of them are not
        thermal (:meth:`Container.degrees_of_freedom
        <hardspheres.containers.Container.degrees_of_freedom>`).
        """
        if self._shear_rate:  # the peculiar velocities' (the flow's kinetic energy is not heat)
            eng = self._sim.engine
            c = peculiar_velocities(eng.positions_at(), eng.velocities, self._shear_rate)
            return float(np.sum(eng.masses[:, None] * c * c)) / max(self._dof(), 1)
        return 2.0 * self._sim.engine.kinetic_energy() / max(self._dof(), 1)

    # ---- granular gases: the temperature is not conserved -----------------------
    def dissipated(self) -> float:
        """Kinetic energy dissipated by inelastic collisions and reflections since :meth:`reset` [energy].

        The event core's tally (``Simulation.dissipated`` since the start):
        kinetic plus dissipated energy is conserved to rounding.
        """
        return self._sim.engine.dissipated - self._granular_mark[1]

    def _injected_total(self) -> float:
        """The driving thermostat's tally of injected energy, plus the thermal wall's heat [energy]."""
        thermostat = float(getattr(getattr(self._sim, "thermostat", None), "injected", 0.0))
        return thermostat + self._sim.engine.wall_heat

    def injected(self) -> float:
        """Kinetic energy a driving thermostat or a thermal wall injected since :meth:`reset` [energy].

        The tally of :class:`hardspheres.dense.RandomKicks` plus the heat of
        a thermal wall (:meth:`hardspheres.Simulation.set_wall_temperature`;
        0 without either).  In a driven steady state it matches
        :meth:`dissipated` over a long run.
        """
        base, before = self._injected_mark
        return before + self._injected_total() - base

    def thermostat_changed(self, old: object) -> None:
        """The simulation calls this as its thermostat changes (``old`` the one replaced, or ``None``).

        What ``old`` injected since :meth:`reset` stays counted; the new
        one's tally counts from now.
        """
        base, before = self._injected_mark
        before += float(getattr(old, "injected", 0.0)) + self._sim.engine.wall_heat - base
        self._injected_mark = (self._injected_total(), before)

    def energy_balance(self) -> float:
        """``(E_kin + E_dissipated - E_injected) / E_kin(reset) - 1``: zero to rounding [1].

        The energy check of a granular gas, driven or not (for elastic
        spheres without a driving thermostat the plain energy drift).

        Raises:
            NoMeasurementError: no kinetic energy at :meth:`reset`.
        """
        e0 = self._granular_mark[0]
        if not e0 > 0:
            raise NoMeasurementError("no kinetic energy at reset(): nothing to balance")
        return (self._sim.engine.kinetic_energy() + self.dissipated() - self.injected()) / e0 - 1.0

    def _cooling(self) -> tuple[float, float, float]:
        """``(ln(T_reset / T_now), elapsed time, collisions per sphere)`` since :meth:`reset`."""
        e0, e1 = self._granular_mark[0], self._sim.engine.kinetic_energy()
        d = self._delta()
        if not d[_T] > 0 or not d[_COLL] > 0:
            raise NoMeasurementError("no collision since reset(): run first")
        if not (e0 > 0 and e1 > 0):
            raise NoMeasurementError("no kinetic energy at reset() or now: no temperature to compare")
        return math.log(e0 / e1), d[_T], 2.0 * d[_COLL] / self._sim.n

    def cooling_rate(self) -> float:
        """Mean cooling rate since :meth:`reset`: ``ln(T_reset / T_now) / elapsed`` [1/time].

        The time average of ``zeta = -d ln T / dt``.  In the homogeneous
        cooling state ``zeta`` falls as the gas cools (Haff's law:
        ``T = T_0 / (1 + t / t_0)^2``); per collision it is constant
        (:meth:`cooling_per_collision`).

        Raises:
            NoMeasurementError: no collision or no kinetic energy since reset.
        """
        drop, dt, _ = self._cooling()
        return drop / dt

    def cooling_per_collision(self) -> float:
        """``-d ln T / dC`` since :meth:`reset`, ``C`` collisions per sphere (each counts for both) [1].

        Haff's law to first order: ``(1 - e^2) / d`` for a Maxwellian gas
        of equal spheres; the first Sonine correction multiplies it by
        ``(1 + 3 a_2 / 16) / (1 - a_2 / 16)`` (docs/guide/granular.md).
        The Enskog factor cancels: it speeds up collisions and cooling alike.

        Raises:
            NoMeasurementError: no collision or no kinetic energy since reset.
        """
        drop, _, c = self._cooling()
        return drop / c

    def a2(self) -> float:
        """Kurtosis coefficient of the velocity distribution now: ``<v^4> / (<v^2>^2 (1 + 2/d)) - 1`` [1].

        0 for a Maxwell-Boltzmann distribution; the homogeneous cooling
        state's is small and negative at ``e`` near 1 (van Noije and
        Ernst's first Sonine approximation: -0.0146 in 3-D and -0.0269 in
        2-D at ``e = 0.9``; docs/guide/granular.md).  In a periodic box of
        the velocities relative to their mean (the total momentum is
        conserved).  One snapshot's statistical error is of order
        ``1 / sqrt(N)``: average it over many.

        Raises:
            NoMeasurementError: no spheres, or all at rest.
        """
        v = np.asarray(self._sim.engine.velocities, dtype=float)
        if self._sim.container.periodic and len(v):
            v = v - v.mean(axis=0)
        v2 = np.sum(v * v, axis=1) if len(v) else np.zeros(0)
        m2 = float(np.mean(v2)) if len(v2) else 0.0
        if not m2 > 0:
            raise NoMeasurementError("no moving sphere: no velocity distribution")
        d = self._sim.container.dimensions
        return float(np.mean(v2 * v2)) / (m2 * m2 * (1.0 + 2.0 / d)) - 1.0

    # ---- stepped potentials (square wells): the potential energy ---------------------
    def _potential_snapshots(self) -> np.ndarray:
        """A stepped run's potential energy at the end of each block since :meth:`reset` [energy]."""
        if not self._stepped:
            raise NoMeasurementError(
                "no potential energy: hard spheres have none (give steps=[(lambda, -eps)] for a well)"
            )
        if self.n_blocks < 1:
            raise NoMeasurementError("no block sampled since reset(): run first")
        return np.array([r[_U_NOW] for r in self._samples[1:]])

    def potential_energy(self) -> Blocking:
        """The potential energy averaged since :meth:`reset`, with its blocking error [energy].

        A stepped run's (``Simulation(..., steps=...)``): the exact energy
        (``U_k`` times the pairs in step ``k``, summed) sampled at the end of
        each block, on the grid the tallies are sampled on; the mean of the
        samples estimates the time average, and Flyvbjerg-Petersen blocking
        of them gives its error (``nan`` with fewer than two blocks).

        Raises:
            NoMeasurementError: hard spheres (no steps), or no block sampled yet.

        Example:
            >>> import hardspheres as hs
            >>> s = hs.random_spheres(64, 0.2, box=8.0, seed=2)
            >>> sim = hs.Simulation(s, hs.PeriodicBox(8.0), steps=[(1.5, -1.0)])
            >>> obs = sim.run(until=1.0).observables.reset()
            >>> u = sim.run(until=6.0).observables.potential_energy()
            >>> u.mean < 0, u.sem > 0
            (True, True)
        """
        u = self._potential_snapshots()
        if u.size < 2:
            return _unknown_error(float(u.mean()))
        return blocking(u)

    def energy_drift(self) -> float:
        """``(K + U now - (K + U) at reset) / K at reset``: zero to rounding for a stepped run [1].

        The energy check of elastic spheres with steps, as
        :meth:`energy_balance` is hard spheres' (``U = 0`` without steps).
        Relative to the kinetic energy, which is positive, since ``K + U``
        may be near zero or negative in a deep well.

        Raises:
            NoMeasurementError: no kinetic energy at :meth:`reset`.
        """
        k0 = self._granular_mark[0]
        if not k0 > 0:
            raise NoMeasurementError("no kinetic energy at reset(): nothing to compare the drift with")
        eng = self._sim.engine
        u = eng.potential_energy() if self._stepped else 0.0
        return (eng.kinetic_energy() + u - self._energy_mark) / k0

    def heat_capacity(self) -> Blocking:
        """Heat capacity at constant volume per sphere, ``C_V / (N k_B)`` [1], from the fluctuations.

        At constant ``N``, ``V`` and ``E`` the kinetic energy fluctuates as
        ``U`` does (``K + U = E``), and Lebowitz, Percus and Verlet's
        relation (Phys. Rev. 153, 250 (1967)) gives the heat capacity:
        ``<dK^2> = (f/2) kT^2 (1 - f k_B / (2 C_V))``, so
        ``C_V / k_B = (f/2) / (1 - 2 <dK^2> / (f kT^2))``, ``f`` the
        degrees of freedom and ``kT = 2 <K> / f``.  Hard spheres' is
        ``f / 2`` exactly (``3/2`` per sphere in 3-D); a well adds to it.
        The variance comes from the samples at the block ends; its error
        from blocking the squared deviations (the mean's error neglected).

        Raises:
            NoMeasurementError: hard spheres, fewer than
                :data:`MIN_FLUCTUATION_BLOCKS` blocks, a run whose energy is
                not conserved (a thermostat, a barostat, a thermal wall), or
                fluctuations too large for the relation (not constant energy).
        """
        u = self._potential_snapshots()
        if u.size < MIN_FLUCTUATION_BLOCKS:
            raise NoMeasurementError(
                f"{u.size} blocks sampled: the heat capacity from fluctuations needs "
                f"{MIN_FLUCTUATION_BLOCKS}; run longer"
            )
        sim = self._sim
        if (
            getattr(sim, "thermostat", None) is not None
            or getattr(sim, "barostat", None) is not None
            or sim.engine.wall_temperature > 0
        ):
            raise NoMeasurementError(
                "the heat capacity from fluctuations holds at constant energy: a thermostat, a barostat "
                "or a thermal wall changes it; run without them"
            )
        f = max(self._dof(), 1)
        k = np.array([r[_K_NOW] for r in self._samples[1:]])
        kT = 2.0 * float(k.mean()) / f
        dev2 = (k - k.mean()) ** 2
        var = float(dev2.mean())
        x = 2.0 * var / (f * kT * kT) if kT > 0 else math.inf
        if not x < 1.0:
            raise NoMeasurementError(
                f"the kinetic energy fluctuates more than constant energy allows (2 <dK^2> / (f kT^2) = "
                f"{x:.3g}, not below 1): is the run conserving energy? check energy_drift()"
            )
        b = blocking(dev2)
        cv = 0.5 * f / (1.0 - x) / sim.n
        scale = 0.5 * f / (1.0 - x) ** 2 * 2.0 / (f * kT * kT) / sim.n  # d C_V / d <dK^2>
        return b._replace(mean=cv, sem=scale * b.sem, sems=scale * b.sems, sem_errors=scale * b.sem_errors)

    def mean_temperature(self) -> float:
        """A stepped run's ``kT`` averaged since :meth:`reset` [energy] (``2 <K> / f``).

        A periodic box's from the kinetic tensor's time integral (exact); a
        container's from the kinetic energy sampled at the block ends and now.
        Hard spheres keep ``kT`` constant: :meth:`temperature`.

        Raises:
            NoMeasurementError: no time has passed since :meth:`reset`.
        """
        if not self._stepped:
            return self.temperature()
        now = np.array(self._now())
        if not now[_T] > self._mark[_T]:
            raise NoMeasurementError("no time has passed since reset(); run first")
        if self._sim.container.periodic:
            return float(self._mean_kT(np.array([self._mark, now]))[0])
        k = np.array([r[_K_NOW] for r in self._samples] + [now[_K_NOW]])
        return 2.0 * float(np.mean(k)) / max(self._dof(), 1)

    def _mean_kT(self, s: np.ndarray) -> np.ndarray:
        """A stepped run's mean ``kT`` over each block between the rows of samples ``s`` [energy].

        The kinetic energy changes at every capture and release: a periodic
        box's from the kinetic tensor's time integral (exact), a
        container's from the snapshots at the block's ends (trapezoid).
        """
        dof = max(self._dof(), 1)
        if self._sim.container.periodic:
            d = np.diff(s, axis=0)
            with np.errstate(divide="ignore", invalid="ignore"):
                return d[:, _KIN_T][:, :3].sum(axis=1) / (d[:, _T] * dof)
        k = s[:, _K_NOW]
        return (k[1:] + k[:-1]) / dof

    def _measured(self, d: np.ndarray, kT: float | np.ndarray | None = None) -> dict[str, np.ndarray]:
        """The observables from tally differences ``d`` (columns as a sample; rows: blocks).

        ``kT``: the temperature of each block (default: now, which a hard-sphere run keeps).
        """
        dt = d[..., _T]
        cont = self._sim.container
        n = self._sim.n
        kT = self.temperature() if kT is None else kT
        with np.errstate(divide="ignore", invalid="ignore"):
            p = cont.pressure(n, kT, dt, d[..., _WALL], d[..., _VIRIAL])  # type: ignore[arg-type]
            z = p * cont.volume / (n * kT)
            rate = 2.0 * d[..., _COLL] / (n * dt)
            out = {"pressure": p, "Z": z, "collision_rate": rate}
            if d.shape[-1] > _HEAT_K.stop - 1:
                ptensor = (d[..., _VIR_T] + d[..., _KIN_T]) / (dt[..., None] * cont.volume)
                for q, name in enumerate(_TENSOR):
                    out[f"pressure_{name}"] = ptensor[..., q]
                if self._shear_rate:  # eta = -P_xy / g; N1 = P_xx - P_yy, N2 = P_yy - P_zz
                    out["viscosity"] = -ptensor[..., 3] / self._shear_rate
                    out["normal_stress_1"] = ptensor[..., 0] - ptensor[..., 1]
                    if cont.dimensions == 3:
                        out["normal_stress_2"] = ptensor[..., 1] - ptensor[..., 2]
        return out

    def _whole(self, name: str) -> float:
        name = ALIASES.get(name, name)
        d = np.array(self._delta())
        if not d[_T] > 0:
            raise NoMeasurementError("no time has passed since reset(); run first")
        kT = np.array([self.mean_temperature()]) if self._stepped else None
        values = self._measured(d, kT)
        if name not in values:
            raise ArgumentError(f"no time average {name!r} here: choose one of {', '.join(values)}")
        return float(np.asarray(values[name]).reshape(-1)[0])

    def blocks(self, name: str) -> np.ndarray:
        """``(n_blocks,)`` the values of ``name`` over each block of equal length.

        ``name`` is one of ``"pressure"``, ``"Z"`` (alias
        ``"compressibility"``),
        ``"collision_rate"``, and in a periodic box ``"pressure_xx"``
        ... ``"pressure_yz"`` (the components of :meth:`pressure_tensor`).
        """
        s = np.array(self._samples)
        values = self._measured(np.diff(s, axis=0), self._mean_kT(s) if self._stepped else None)
        name = ALIASES.get(name, name)
        if name not in values:
            raise ArgumentError(f"no time average {name!r} here: choose one of {', '.join(values)}")
        return values[name]

    def estimate(self, name: str) -> Blocking:
        """Mean over the whole time since :meth:`reset` and its blocking error.

        Returns:
            A :class:`hardspheres.blocking.Blocking` whose ``mean`` is the
            average over all the time since reset (the blocks, and the part
            after the last one) and whose ``sem`` is the standard error from
            Flyvbjerg-Petersen blocking of :meth:`blocks` (``nan`` with fewer
            than two blocks).

        Raises:
            NoMeasurementError: nothing was measured yet.
        """
        mean = self._whole(name)
        x = self.blocks(name)
        if x.size < 2:
            return _unknown_error(mean)
        return blocking(x)._replace(mean=mean)

    def error(self, name: str) -> float:
        """Standard error of ``name``'s average (``nan`` with fewer than two blocks)."""
        return self.estimate(name).sem

    def pressure(self) -> float:
        """Pressure [energy/length^3] averaged since :meth:`reset`.

        Spherical container: momentum delivered to the wall per unit area
        and time.  Periodic box: ``(N kT + W / (3 t)) / V`` with ``W`` the
        collision virial ``sum r_ij . dp_i``.  Error bar: :meth:`error`.
        """
        return self._whole("pressure")

    def pressure_tensor(self) -> np.ndarray:
        """``(d, d)`` pressure tensor [energy/length^d] averaged since :meth:`reset` (periodic box).

        In 2-D (disks) the ``xx``, ``yy`` and ``xy`` components: its trace
        over two is the mechanical pressure ``(E_kin + W / 2t) / A``.

        ``P = (int sum m v v dt + sum r_ij dp_i) / (t V)``: the kinetic part
        integrated exactly between collisions and the collisional virial
        tensor, both accumulated by the event core.  Its trace over three
        is the mechanical pressure, ``(2 E_kin / 3 + W / 3t) / V``, which
        differs from :meth:`pressure` (``N kT`` with ``kT`` from ``3N - 3``
        degrees of freedom) by ``kT / V``.  Errors: ``error("pressure_xy")``.

        Raises:
            PeriodicBoxRequired: in a spherical container (the wall's
                pressure is :meth:`pressure`).
        """
        require_periodic(self._sim.container, "the pressure tensor and transport")
        p = np.empty((3, 3))
        for q, name in enumerate(_TENSOR):
            a, b = _PAIRS[q]
            p[a, b] = p[b, a] = self._whole(f"pressure_{name}")
        d = getattr(self._sim.container, "dimensions", 3)
        return p[:d, :d].copy() if d != 3 else p

    def helfand_moments(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """Sampled Helfand moments since :meth:`reset` (periodic box), for Einstein-Helfand.

        Args:
            kind: ``"momentum"``: ``(S, 3)`` the xy, xz, yz components of
                ``int_0^t V P_ab dt'`` (``sum m x_a v_b`` in its periodic
                form) [mass*length^2/time]; ``"energy"``: ``(S, 3)``
                ``sum x E`` in its periodic form [energy*length].

        Returns:
            ``(t, moments)``: the sample times since reset ``(S,)`` [time]
            and the moments there, relative to their value at reset.

        Raises:
            NoMeasurementError: ``"energy"`` in a run with steps (its
                potential energy is not in the moment yet).
        """
        require_periodic(self._sim.container, "the pressure tensor and transport")
        s = np.array(self._samples)
        s = s - s[0]
        if kind == "momentum":
            m = s[:, _VIR_T][:, 3:] + s[:, _KIN_T][:, 3:]
        elif kind == "energy":
            if self._stepped:
                raise NoMeasurementError(
                    "the energy moment of a run with steps lacks the potential energy's share (half of "
                    "each bond's U at each sphere): the thermal conductivity is not built for steps yet"
                )
            m = s[:, _HEAT_C] + s[:, _HEAT_K]
        else:
            raise ArgumentError(f"kind {kind!r}: use 'momentum' or 'energy'")
        return s[:, _T], m

    def Z(self) -> float:  # noqa: N802 (the physicists' name)
        """``Z = P V / (N kT)`` since :meth:`reset` (periodic box: from the virial).

        In a spherical container it is the *wall's* ``P V / (N kT)``, which
        includes a surface term (not the bulk Z): :meth:`summary` marks it.
        """
        return self._whole("Z")

    def compressibility(self) -> float:
        """The old name of :meth:`Z` (the compressibility *factor*, not kappa_T)."""
        return self.Z()

    def collision_rate(self) -> float:
        """Collisions per sphere per unit time [1/time] (each collision counts for both)."""
        return self._whole("collision_rate")

    def mean_free_time(self) -> float:
        """Mean time between collisions of a sphere [time] (``inf`` without any)."""
        rate = self.collision_rate()
        return 1.0 / rate if rate > 0 else np.inf

    def mean_speed(self) -> float:
        """Mean speed of the spheres now [length/time]."""
        return float(np.mean(np.linalg.norm(self._sim.engine.velocities, axis=1)))

    def mean_free_path(self) -> float:
        """Mean distance a sphere travels between collisions [length]."""
        return self.mean_speed() * self.mean_free_time()

    def speed_histogram(
        self,
        bins: int = 50,
        range: tuple[float, float] | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Histogram of the speeds now: ``(counts, edges)`` [edges: length/time]."""
        speeds = np.linalg.norm(self._sim.engine.velocities, axis=1)
        return np.histogram(speeds, bins=bins, range=range)

    def summary(self) -> dict[str, Any]:
        """Dict of the observables (averages over the time since reset).

        Each time average ``x`` comes with ``x_error``, its standard error
        from blocking (``nan`` if fewer than two blocks were sampled), and
        ``x_converged``, whether the blocking reached a plateau (if not,
        the error is a lower bound: run longer).  ``Z`` (also under its old
        name ``compressibility``) comes with ``Z_route``: ``"virial"`` in a
        periodic box (the bulk Z), ``"wall"`` in a spherical container,
        where it is the wall's ``P V / (N kT)`` and ``Z_note`` says that it
        includes a surface term.

        A stepped run (square wells) adds ``potential_energy`` (with its
        error; :meth:`potential_energy`), ``energy_drift``
        (:meth:`energy_drift`; left out with a thermostat, a barostat or a
        thermal wall) and, from :data:`MIN_FLUCTUATION_BLOCKS` blocks on,
        ``heat_capacity`` per sphere (:meth:`heat_capacity`).  Its ``Z``
        divides by ``mean_temperature``, the mean ``kT`` over the run
        (``temperature`` is ``kT`` now, which changes at every capture and
        release).
        """
        out: dict[str, Any] = {
            "time": self._sim.time,
            "elapsed": self.elapsed,
            "temperature": self.temperature(),
            "blocks": self.n_blocks,
            "sample_interval": self.every,
        }
        if self._sim.engine.inelastic:
            # a cooling gas: no average that divides by one kT
            out["dissipated"] = self.dissipated()
            if self._injected_total():
                out["injected"] = self.injected()
            if self._granular_mark[0] > 0:
                out["energy_balance"] = self.energy_balance()
            try:
                out.update(
                    cooling_rate=self.cooling_rate(), cooling_per_collision=self.cooling_per_collision()
                )
            except NoMeasurementError:
                pass
            if self._sim.n >= 2 and self.temperature() > 0:
                out["a2"] = self.a2()
            return out
        if self.elapsed > 0:
            for name in ("pressure", "Z", "collision_rate"):
                est = self.estimate(name)
                out[name] = est.mean
                out[f"{name}_error"] = est.sem
                out[f"{name}_converged"] = est.converged
            wall = self._sim.container.wall_area > 0
            out["Z_route"] = "wall" if wall else "virial"
            if wall:
                out["Z_note"] = (
                    "wall pressure of a finite sphere: it includes a surface term, so it is not the bulk Z"
                )
            for key in ("", "_error", "_converged"):  # the old name, kept
                out[f"compressibility{key}"] = out[f"Z{key}"]
            if self._shear_rate:
                out["shear_rate"] = self._shear_rate
                names = ["viscosity", "normal_stress_1"] + (
                    ["normal_stress_2"] if self._sim.container.dimensions == 3 else []
                )
                for name in names:
                    est = self.estimate(name)
                    out[name], out[f"{name}_error"], out[f"{name}_converged"] = (
                        est.mean,
                        est.sem,
                        est.converged,
                    )
            rate, rate_err = out["collision_rate"], out["collision_rate_error"]
            out.update(mean_free_time=self.mean_free_time(), mean_free_path=self.mean_free_path())
            rel = rate_err / rate if rate > 0 else np.nan
            out["mean_free_time_error"] = out["mean_free_time"] * rel
            out["mean_free_path_error"] = out["mean_free_path"] * rel
        if self._stepped:
            out.update(self._stepped_summary())
        return out

    def _stepped_summary(self) -> dict[str, Any]:
        """A stepped run's keys: the potential energy, the energy drift, the heat capacity if measurable."""
        out: dict[str, Any] = {}
        if self.elapsed > 0:
            out["mean_temperature"] = self.mean_temperature()
        if self.n_blocks >= 1:
            est = self.potential_energy()
            out["potential_energy"], out["potential_energy_error"] = est.mean, est.sem
            out["potential_energy_converged"] = est.converged
        sim = self._sim
        if (
            getattr(sim, "thermostat", None) is None
            and getattr(sim, "barostat", None) is None
            and not sim.engine.wall_temperature > 0
            and self._granular_mark[0] > 0
        ):
            out["energy_drift"] = self.energy_drift()
        try:
            est = self.heat_capacity()
        except NoMeasurementError:  # (too few blocks, or not at constant energy: no number)
            return out
        out["heat_capacity"], out["heat_capacity_error"] = est.mean, est.sem
        out["heat_capacity_converged"] = est.converged
        return out


#: Old names of the time averages (``estimate("compressibility")`` is ``estimate("Z")``).
ALIASES = {"compressibility": "Z"}


def _unknown_error(mean: float) -> Blocking:
    return Blocking(mean, math.nan, 0, 0, False, np.zeros(0), np.zeros(0))


# ---- sheared runs (Lees-Edwards) ---------------------------------------------------


def peculiar_velocities(positions: np.ndarray, velocities: np.ndarray, shear_rate: float) -> np.ndarray:
    """``(N, d)`` velocities relative to the streaming profile: ``c = v - g y e_x`` [length/time].

    ``positions`` in the sheared box (y from its centre, where the flow is
    at rest), ``shear_rate`` ``g`` [1/time].

    Example:
        >>> peculiar_velocities(np.array([[0.0, 2.0]]), np.array([[1.5, 0.5]]), 0.25).tolist()
        [[1.0, 0.5]]
    """
    c = np.array(velocities, dtype=np.float64)
    c[:, 0] -= shear_rate * np.asarray(positions, dtype=np.float64)[:, 1]
    return c


class ShearFlow:
    """Run a sheared box and average its rheology: stress, viscosity, normal stresses, profile.

    Reads what the engine exposes (``stress_tallies``, ``positions_at``,
    ``velocities``, ``masses``, ``container``, ``shear_rate``, ``advance``,
    ``kick``): for now :class:`hardspheres.core.reference.Reference`, which
    runs Lees-Edwards boundaries (the compiled core does not yet).  It
    drives the engine (:meth:`run`), applies a thermostat at its times
    (:class:`hardspheres.dense.PeculiarRescale`,
    :class:`hardspheres.dense.PeculiarAndersen`) and samples the tallies on
    a grid of equal blocks, from which:

    * the pressure tensor ``P = (int sum m c c dt + sum r_ij dp_i) / (t V)``
      with peculiar velocities ``c = v - g y e_x`` (docs/numerics.md,
      "Lees-Edwards shear"), per block;
    * the viscosity ``eta = -P_xy / g``, the normal stress differences
      ``N_1 = P_xx - P_yy`` and ``N_2 = P_yy - P_zz`` (3-D), and the
      kinetic temperature of the peculiar velocities, each with a
      Flyvbjerg-Petersen error bar over the blocks (:meth:`estimate`);
    * the streaming profile ``<v_x>(y)`` in layers across y (:meth:`profile`).

    Averages over a run whose temperature drifts (an elastic fluid heats
    up under shear) warn (:class:`~hardspheres.errors.DriftWarning`): use a
    thermostat, or inelastic collisions.

    Args:
        engine: the engine running a sheared box.
        thermostat: one acting on the peculiar velocities, or ``None``.
        every: the time between samples (a block) [time]; default a tenth
            of the time a sphere of rms peculiar speed crosses the mean
            spacing ``(V/N)^(1/d)``.
        layers: the layers across y for the profile.

    Example:
        >>> import hardspheres as hs
        >>> from hardspheres.core.reference import Reference
        >>> box = hs.PeriodicBox((12.0, 12.0), shear_rate=0.05)
        >>> s = hs.random_spheres(40, 0.3, container=box, seed=1)
        >>> flow = ShearFlow(Reference(s.masses, s.radii, s.positions, s.velocities, container=box))
        >>> flow.run(20.0).time, flow.n_blocks >= 16
        (20.0, True)
    """

    def __init__(
        self, engine: Any, thermostat: Any = None, every: float | None = None, layers: int = 8
    ) -> None:
        self.engine = engine
        self.container = engine.container
        self.shear_rate = float(getattr(engine, "shear_rate", 0.0))
        if not self.shear_rate:
            raise ShearError(
                "ShearFlow needs a sheared box: give hs.PeriodicBox(..., shear_rate=g) with g != 0"
            )
        if not (isinstance(layers, int) and layers >= 1):
            raise ArgumentError(f"layers must be a whole number >= 1, got {layers!r}")
        self.layers = layers
        self.thermostat = thermostat
        self.reset(every)

    # the view a thermostat reads (hardspheres.dense.ObservedSimulation's names)
    @property
    def n(self) -> int:
        """Number of spheres."""
        return int(self.engine.n)

    @property
    def time(self) -> float:
        """The time reached [time] (the last sample, or the engine's last event or kick if later)."""
        return max(self._t, float(self.engine.time))

    def reset(self, every: float | None = None) -> ShearFlow:
        """Start averaging afresh from now; returns self."""
        self._t = float(self.engine.time)
        self.every = float(every) if every is not None else self._auto_every()
        if not (self.every > 0 and math.isfinite(self.every)):
            raise ArgumentError(f"every must be a finite time > 0, got {every!r}")
        self._samples: list[np.ndarray] = [self._tallies(self._t)]
        self._profiles: list[np.ndarray] = []
        return self

    def _auto_every(self) -> float:
        c = self._peculiar(self._t)
        v2 = float(np.mean(np.sum(c * c, axis=1))) if self.n else 0.0
        if not v2 > 0:
            raise NoMeasurementError("every sphere at rest in the flow: give every=")
        box = self.container
        return 0.1 * (box.volume / self.n) ** (1.0 / box.dimensions) / math.sqrt(v2)

    def _peculiar(self, t: float) -> np.ndarray:
        x = np.asarray(self.engine.positions_at(t), dtype=np.float64).reshape(self.n, -1)
        v = np.asarray(self.engine.velocities, dtype=np.float64).reshape(self.n, -1)
        return peculiar_velocities(x, v, self.shear_rate)

    def _tallies(self, t: float) -> np.ndarray:
        tal = self.engine.stress_tallies(t)
        return np.concatenate([[t], tal["kinetic"], tal["virial"]])

    def run(self, duration: float) -> ShearFlow:
        """Run the engine for ``duration`` [time], sampling every :attr:`every`; returns self.

        The thermostat, if any, acts at its times (before a sample due at
        the same instant).  The run ends exactly at ``time + duration``.
        """
        if not (duration >= 0 and math.isfinite(duration)):
            raise ArgumentError(f"duration must be a finite time >= 0, got {duration!r}")
        end = self._t + float(duration)
        th = self.thermostat
        if th is not None:
            th.attach(self)
        next_sample = self._samples[-1][0] + self.every
        while True:
            due = min(end, next_sample)
            if th is not None and th.next_time is not None and th.next_time < due:
                self.engine.advance(until=th.next_time)
                self._t = th.next_time
                th.apply(self, th.next_time)
                continue
            self.engine.advance(until=due)
            self.engine.move_clock(due)
            self._t = due
            if due == next_sample:
                self._sample(due)
                next_sample = due + self.every
            if due == end:
                return self

    def _sample(self, t: float) -> None:
        self._samples.append(self._tallies(t))
        ly = self.container.sides[1]
        x = np.asarray(self.engine.positions_at(t), dtype=np.float64).reshape(self.n, -1)
        v = np.asarray(self.engine.velocities, dtype=np.float64).reshape(self.n, -1)
        k = np.clip(np.floor((x[:, 1] / ly + 0.5) * self.layers).astype(int), 0, self.layers - 1)
        counts = np.bincount(k, minlength=self.layers)
        sums = np.bincount(k, weights=v[:, 0], minlength=self.layers)
        with np.errstate(invalid="ignore", divide="ignore"):
            self._profiles.append(sums / counts)

    # ---- averages ---------------------------------------------------------------------
    @property
    def n_blocks(self) -> int:
        """Blocks sampled since the reset."""
        return len(self._samples) - 1

    @property
    def elapsed(self) -> float:
        """Time sampled since the reset, in whole blocks [time]."""
        return float(self._samples[-1][0] - self._samples[0][0])

    def _per_block(self, d: np.ndarray) -> dict[str, np.ndarray]:
        """Every average per row of tally differences ``d`` (columns: t, kinetic 6, virial 6)."""
        dt = d[..., 0]
        box = self.container
        dof = box.degrees_of_freedom(self.n)
        with np.errstate(invalid="ignore", divide="ignore"):
            p = (d[..., 1:7] + d[..., 7:13]) / (dt[..., None] * box.volume)
            kin = d[..., 1:7] / dt[..., None]
            out = {f"pressure_{q}": p[..., k] for k, q in enumerate(("xx", "yy", "zz", "xy", "xz", "yz"))}
            out["viscosity"] = -p[..., 3] / self.shear_rate
            out["n1"] = p[..., 0] - p[..., 1]
            if box.dimensions == 3:
                out["n2"] = p[..., 1] - p[..., 2]
            out["temperature"] = (kin[..., 0] + kin[..., 1] + kin[..., 2]) / dof
        return out

    def blocks(self, name: str) -> np.ndarray:
        """``(n_blocks,)`` the values of ``name`` over each block: ``viscosity``, ``n1``, ``n2`` (3-D),
        ``temperature``, ``pressure_xx`` ... ``pressure_yz``."""
        values = self._per_block(np.diff(np.array(self._samples), axis=0))
        if name not in values:
            raise ArgumentError(f"no average {name!r} here: choose one of {', '.join(values)}")
        return values[name]

    def estimate(self, name: str) -> Blocking:
        """Mean of ``name`` over the blocks and its blocking error (names as :meth:`blocks`).

        Raises:
            NoMeasurementError: fewer than 16 blocks (no error bar to trust): run longer.

        Warns:
            DriftWarning: the temperature drifts over the blocks.
        """
        if self.n_blocks < MIN_SHEAR_BLOCKS:
            raise NoMeasurementError(
                f"{self.n_blocks} blocks sampled: an error bar needs {MIN_SHEAR_BLOCKS}; run longer"
            )
        x = self.blocks(name)
        self._warn_if_drifting()
        return blocking(x)

    def viscosity(self) -> Blocking:
        """``eta = -<P_xy> / g`` [mass/(length^(d-2) time)], with its blocking error."""
        return self.estimate("viscosity")

    def normal_stress_differences(self) -> tuple[Blocking, ...]:
        """``N_1 = P_xx - P_yy`` and, in 3-D, ``N_2 = P_yy - P_zz`` [energy/length^d], with errors."""
        names = ("n1", "n2") if self.container.dimensions == 3 else ("n1",)
        return tuple(self.estimate(q) for q in names)

    def pressure_tensor(self) -> np.ndarray:
        """``(d, d)`` pressure tensor averaged over the blocks, peculiar kinetic part [energy/length^d]."""
        if self.n_blocks < 1:
            raise NoMeasurementError("no block sampled yet: run first")
        d = self._samples[-1] - self._samples[0]
        values = self._per_block(d)
        p = np.empty((3, 3))
        for k, (a, b) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
            name = ("xx", "yy", "zz", "xy", "xz", "yz")[k]
            p[a, b] = p[b, a] = float(values[f"pressure_{name}"])
        dim = self.container.dimensions
        return p[:dim, :dim].copy()

    def temperature(self) -> float:
        """Kinetic temperature of the peculiar velocities now: ``sum m c^2 / (d N - d)`` [energy]."""
        c = self._peculiar(self.time)
        m = np.asarray(self.engine.masses, dtype=np.float64)
        return float(np.sum(m[:, None] * c * c)) / max(self.container.degrees_of_freedom(self.n), 1)

    def profile(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The streaming profile: ``(y, <v_x>, error)`` per layer across y [length, length/time].

        Averaged over the samples (each layer's mean ``v_x`` at each
        sample); the error is blocking's (a layer empty at a sample is left
        out of it).  Linear with slope ``g`` for a sheared fluid in a steady state.

        Raises:
            NoMeasurementError: fewer than 16 samples: run longer.
        """
        if len(self._profiles) < MIN_SHEAR_BLOCKS:
            raise NoMeasurementError(
                f"{len(self._profiles)} samples: a profile needs {MIN_SHEAR_BLOCKS}; run longer"
            )
        ly = self.container.sides[1]
        y = ((np.arange(self.layers) + 0.5) / self.layers - 0.5) * ly
        a = np.array(self._profiles)
        mean = np.full(self.layers, np.nan)
        err = np.full(self.layers, np.nan)
        for k in range(self.layers):
            col = a[:, k][np.isfinite(a[:, k])]
            if col.size >= 2:
                b = blocking(col)
                mean[k], err[k] = b.mean, b.sem
        return y, mean, err

    def plot_profile(self, ax: Any = None) -> Any:
        """The streaming profile with its error bars and the line ``g y`` it should follow; returns Axes."""
        from .extras import need

        plt = need("matplotlib.pyplot", "plot")
        y, u, err = self.profile()
        ax = plt.figure().add_subplot() if ax is None else ax
        ax.errorbar(y, u, yerr=err, fmt="o", ms=4, label="measured")
        ly = self.container.sides[1]
        line = np.array([-0.5 * ly, 0.5 * ly])
        ax.plot(
            line, self.shear_rate * line + float(np.nanmean(u - self.shear_rate * y)), "--", label="slope g"
        )
        ax.set_xlabel("y [length]")
        ax.set_ylabel("<v_x> [length/time]")
        ax.set_title(f"streaming profile, g = {self.shear_rate:g}, {self.n_blocks} samples")
        ax.legend()
        return ax

    def _warn_if_drifting(self) -> None:
        """:class:`DriftWarning` if the temperature's trend over the blocks is over 4 errors and 2%."""
        import warnings

        kt = self.blocks("temperature")
        n = kt.size
        t = np.arange(n, dtype=np.float64) - 0.5 * (n - 1)
        slope = float(np.dot(t, kt - kt.mean()) / np.dot(t, t))
        resid = kt - kt.mean() - slope * t
        se = math.sqrt(float(np.dot(resid, resid)) / max(n - 2, 1) / float(np.dot(t, t)))
        change, err, mean = slope * (n - 1), se * (n - 1), float(kt.mean())
        if abs(change) > 4.0 * err and abs(change) > DRIFT_TOLERANCE * mean:
            warnings.warn(
                f"the temperature drifts by {change / mean:+.1%} over the averaged blocks (viscous "
                "heating): the averages mix temperatures; hold it with a thermostat on the peculiar "
                "velocities (hardspheres.dense.PeculiarRescale) or use inelastic collisions",
                DriftWarning,
                stacklevel=3,
            )


#: Fewest blocks :meth:`Observables.heat_capacity` gives a variance from.
MIN_FLUCTUATION_BLOCKS = 32
#: Fewest blocks :meth:`ShearFlow.estimate` gives an error bar from (blocking's own minimum).
MIN_SHEAR_BLOCKS = 16
#: A temperature trend below this fraction of the mean is not a drift (:class:`ShearFlow`).
DRIFT_TOLERANCE = 0.02
