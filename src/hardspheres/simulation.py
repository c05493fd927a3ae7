"""Simulation: the object physicists script.

A :class:`Simulation` holds spheres in a container, runs them exactly
(compiled event core, :mod:`hardspheres.core.engine`), hands out the state at its
clock, calls writers when their triggers say (:mod:`hardspheres.writers`),
and accumulates observables.

Example:
    >>> import hardspheres as hs
    >>> sim = hs.Simulation.from_arrays(
    ...     masses=[1.0, 1.0], radii=[1.0, 1.0],
    ...     positions=[[-5, 0, 0], [5, 0, 0]], velocities=[[1, 0, 0], [-1, 0, 0]],
    ...     container=hs.SphericalContainer(100.0))
    >>> [(e.time, e.kind, e.i, e.j) for e in sim.iter_events(until=10.0)]
    [(4.0, 'collision', 0, 1)]
    >>> sim.time, sim.state().positions[:, 0].tolist()
    (10.0, [-7.0, 7.0])
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, cast

import numpy as np
from numpy.typing import ArrayLike

from .containers import Container, as_container, require_periodic
from .core import checkpoint
from .core.engine import CheckpointError, Engine
from .core.warmup import ensure_compiled
from .errors import ArgumentError, BoxShapeError, ShearError
from .events import KIND_LABELS, KindLabel, StopReason
from .fileio import atomic_write
from .messages import quote
from .observables import Observables
from .scenario import TOUCH_TOL, ScenarioError, check_scenario, parse_scenario
from .state import State
from .writers import Writer

if TYPE_CHECKING:
    from .barostat import Barostat
    from .dense import CompressResult, Thermostat

    class _Acting(Protocol):
        """A thermostat or barostat once attached: its next_time is a time, no longer None."""

        next_time: float

        def attach(self, sim: Simulation) -> None: ...

        def apply(self, sim: Simulation, t: float) -> None: ...


#: Event kind names by number (:class:`~hardspheres.events.EventKind`).
KINDS = KIND_LABELS

#: What :meth:`Simulation.save` writes in its ``format`` array, and the
#: version of the layout; :meth:`Simulation.load` refuses anything else.


class Event(NamedTuple):
    """One event of a run.

    Attributes:
        time: [time].
        kind: ``"collision"`` or ``"reflection"``, a
            :class:`~hardspheres.events.KindLabel`: it equals its
            :class:`~hardspheres.events.EventKind` too.
        i: the sphere (the lower index of a colliding pair).
        j: the other sphere of a collision, ``-1`` for a reflection.
        impulse: magnitude of the momentum sphere ``i`` received
            [mass*length/time].
        dp: the momentum sphere ``i`` received, ``(dpx, dpy, dpz)``
            [mass*length/time] (sphere ``j`` received minus this).
    """

    time: float
    kind: KindLabel
    i: int
    j: int
    impulse: float
    dp: tuple = (0.0, 0.0, 0.0)


class Simulation:
    """Spheres in a container, simulated exactly.

    Args:
        state: the spheres at the start (:class:`hardspheres.State`).
        container: a :class:`~hardspheres.containers.Container`
            (:class:`SphericalContainer`, :class:`PeriodicBox`), or the
            radius of a spherical container [length].
        window: simultaneity window [time]: events less than this after
            the previous one happen at its time (the assignment's program
            uses 1e-8 s; 0, the default, keeps exact times).
        restitution: normal restitution coefficient ``e`` of every
            collision, ``0 < e <= 1``: 1 (the default) is elastic hard
            spheres; below 1 a granular gas, which cools
            (docs/guide/granular.md).
        wall_restitution: the container wall's coefficient (default:
            ``restitution``; unused in a periodic box).
        tc: the TC model's duration [time] (Luding and McNamara 1998): a
            collision within ``tc`` of either sphere's previous one is
            elastic, which resolves inelastic collapse; 0 (the default) is
            off.  A small fraction of the mean free time, e.g. 1e-3 of it.
        steps: a stepped pair potential ``[(lambda_k, U_k), ...]``,
            outermost first: a square well of width ``lambda`` and depth
            ``eps`` is ``[(lambda, -eps)]``; each pair ``(i, j)`` has the
            energy ``U_k`` inside ``lambda_k (R_i + R_j)`` and outside the
            next edge, 0 outside every edge (docs/numerics.md, "Steps:
            wells and shoulders").  Default: none (hard spheres).  Per
            pair of species: ``{(s, t): [(lambda_k, U_k), ...]}`` (each
            unordered pair once; left out: hard spheres), with ``species``.
        species: ``(N,)`` each sphere's species ``0..3``, in input order
            (with steps per pair of species).

    Attributes:
        container: the :class:`SphericalContainer` or :class:`PeriodicBox`.
        names: the spheres' names, in input order.
        observables: :class:`hardspheres.Observables`, time averages since
            its last ``reset()`` (pressure, ``Z``, collision rate, ...).
        writers: objects called as the simulation runs (e.g.
            :class:`hardspheres.GSDWriter`); append to this list.

    Raises:
        ScenarioError: a mass, radius, position or velocity that is not a
            finite number (masses > 0, radii >= 0), repeated names, spheres
            outside the container or overlapping.
        ValueError: a window that is not a finite number >= 0, a
            restitution coefficient outside (0, 1], a negative ``tc``.
    """

    #: Set (e.g. from a signal handler) to end the current run at its next
    #: chunk of events; :meth:`request_stop` sets it.  Runs stop at once until
    #: it is set back to ``False``.
    stop_requested: bool = False
    #: Thermostat holding kT (:mod:`hardspheres.dense`), or ``None`` (NVE);
    #: :meth:`set_thermostat` sets it.
    thermostat: Thermostat | None = None
    #: Barostat holding the pressure (:mod:`hardspheres.barostat`), or
    #: ``None`` (constant volume); :meth:`set_barostat` sets it.
    barostat: Barostat | None = None

    def __init__(
        self,
        state: State,
        container: Container | float,
        window: float = 0.0,
        restitution: float = 1.0,
        wall_restitution: float | None = None,
        tc: float = 0.0,
        steps: Any = None,
        species: ArrayLike | None = None,
    ) -> None:
        container = as_container(container)
        state.check()
        window = _number(window, "window", "a finite number >= 0 [time]", minimum=0.0)
        restitution, wall_restitution, tc = _rule(restitution, wall_restitution, tc)
        self.container: Container = container
        self.names = list(state.names)
        #: Writers called as runs go (:class:`hardspheres.writers.Writer`).
        self.writers: list[Writer] = []
        self.stop_requested = False
        self.thermostat = None
        self.barostat = None
        self._run_until = math.inf
        _check_inside(state, container)
        if container.periodic and state.n:
            narrowest = min(container.sides)  # type: ignore[attr-defined]  # a box's
            widest = 2.0 * float(np.max(state.radii))
            if 3.0 * widest > narrowest:  # the engine's cells: three a side at least
                raise BoxShapeError(
                    f"periodic box side {narrowest:g} is narrower than three times the largest diameter "
                    f"({widest:g}); every side must be at least {3.0 * widest:g}"
                )
        # the unwrapped centres (positions + images * L) are kept in a periodic box
        images = container.image_counts(state.positions)
        if state.images is not None:
            images += np.asarray(state.images, dtype=np.int64).reshape(images.shape)
        sheared = bool(getattr(container, "shear_rate", 0.0))
        _compiled(
            container.dimensions,
            inelastic=restitution < 1.0 or (wall_restitution or 1.0) < 1.0,
            sheared=sheared,
            stepped=bool(steps),
        )
        self._engine = Engine(
            state.masses,
            state.radii,
            container.wrap(state.positions),
            state.velocities,
            container,
            window=window,
            time=state.time,
            restitution=restitution,
            wall_restitution=wall_restitution,
            tc=tc,
            steps=steps,
            species=species,
        )
        self._engine.images = images
        if state.n > 1:
            worst = self._engine.max_overlap()
            if worst > TOUCH_TOL:
                raise ScenarioError(
                    f"spheres overlap by up to {worst:.3g} of their contact distance; move them apart"
                )
        self._clock = float(state.time)
        self.observables = Observables(self)

    # ---- construction ------------------------------------------------------
    @classmethod
    def from_arrays(
        cls,
        masses: ArrayLike,
        radii: ArrayLike,
        positions: ArrayLike,
        velocities: ArrayLike,
        container: Container | float,
        names: Sequence[str] | None = None,
        time: float = 0.0,
        window: float = 0.0,
        restitution: float = 1.0,
        wall_restitution: float | None = None,
        tc: float = 0.0,
        steps: Sequence[Sequence[float]] | None = None,
    ) -> Simulation:
        """Build from arrays: ``masses (N,)`` [mass], ``radii (N,)`` [length],
        ``positions (N, 3)`` [length], ``velocities (N, 3)`` [length/time]
        (the other arguments as the constructor's)."""
        state = State.from_arrays(masses, radii, positions, velocities, names, time)
        return cls(state, container, window, restitution, wall_restitution, tc, steps)

    @classmethod
    def from_scenario(
        cls, source: str | bytes | os.PathLike, container: Container | float, window: float = 0.0
    ) -> Simulation:
        """Build from a scenario in the assignment's input format.

        Args:
            source: a path, or the scenario text itself (``str`` with a
                newline, or ``bytes``).
            container: the container (a 2-D one reads disks: every
                line's ``z`` and ``vz`` 0, as :meth:`State.to_text` writes them).
        """
        if isinstance(source, (bytes, str)) and (isinstance(source, bytes) or "\n" in source):
            data = source
        else:
            with open(source, "rb") as fh:
                data = fh.read()
        scn = parse_scenario(data)
        check_scenario(scn, container)
        # disks (a 2-D container): the same nine fields, z = 0 and vz = 0 on every line
        dims = getattr(container, "dimensions", 3)
        return cls(State.from_scenario(scn, dimensions=dims), container, window=window)

    # ---- running -------------------------------------------------------------
    @property
    def time(self) -> float:
        """The simulation's clock [time], where the last run stopped."""
        return float(max(self._engine.time, self._clock))

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self._engine.n

    @property
    def run_end(self) -> float:
        """Where the current (or last) run was asked to end [time] (``inf`` when it ends by a count).

        Trajectory writers record it, so that a file cut short shows.
        """
        return self._run_until

    @property
    def engine(self) -> Engine:
        """The compiled engine, with its running tallies and velocities (read, do not change)."""
        return self._engine

    @property
    def counters(self) -> dict[str, int]:
        """Events processed so far (collisions, reflections, crossings, stale)."""
        return self._engine.counters

    # ---- the collision rule (granular gases) ----------------------------------
    @property
    def restitution(self) -> float:
        """Normal restitution coefficient between spheres (1 for elastic collisions)."""
        return self._engine.restitution

    @property
    def wall_restitution(self) -> float:
        """Normal restitution coefficient at the container's wall (1 for elastic reflections)."""
        return self._engine.wall_restitution

    @property
    def tc(self) -> float:
        """The TC model's duration [time] (0 when the model is off)."""
        return self._engine.tc

    @property
    def inelastic(self) -> bool:
        """Whether events change the kinetic energy (a restitution coefficient below 1, or a thermal wall)."""
        return self._engine.inelastic

    @property
    def steps(self) -> tuple[tuple[float, float], ...]:
        """The stepped pair potential ``((lambda_k, U_k), ...)``, outermost first; empty for hard spheres."""
        return self._engine.steps

    def potential_energy(self) -> float:
        """The stepped potential's energy now [energy] (0: hard spheres): exact, from the count per step."""
        return self._engine.potential_energy()

    def total_energy(self) -> float:
        """Kinetic plus potential energy now [energy]: conserved to rounding by elastic spheres with steps."""
        return self._engine.kinetic_energy() + self._engine.potential_energy()

    @property
    def wall_temperature(self) -> float:
        """The thermal wall's temperature ``kT_w`` [energy]; 0 when the wall reflects."""
        return self._engine.wall_temperature

    @property
    def wall_heat(self) -> float:
        """Kinetic energy the thermal wall gave the spheres since the start [energy]; negative if it took."""
        return self._engine.wall_heat

    def set_wall_temperature(self, kt: float, seed: int = 0) -> Simulation:
        """Make the container's wall a thermal wall at ``kt`` from now (0: it reflects again); returns self.

        A sphere meeting a thermal wall leaves it with a velocity drawn at
        the wall's temperature: the normal speed from the flux-weighted
        distribution, the tangential velocity from the Maxwellian
        (:func:`hardspheres.physics.thermal_wall`; docs/numerics.md, "The
        thermal wall").  Elastic spheres relax to ``kt``; a granular gas
        reaches a steady state where the wall's heat balances what the
        collisions dissipate (:attr:`wall_heat`, :attr:`dissipated`).  The
        draws are reproducible from ``seed`` and resume bit for bit from a
        checkpoint.

        Args:
            kt: the wall's temperature [energy], finite, ``>= 0``.
            seed: the wall's generator seed, ``0 <= seed < 2^32``.

        Raises:
            ValueError: ``kt`` negative or not finite, a seed out of range,
                or a periodic box (no wall).

        Example:
            >>> import hardspheres as hs
            >>> box = hs.SphericalContainer(12.0)
            >>> sim = hs.Simulation(hs.random_spheres(50, 0.1, box, seed=1), box)
            >>> sim.set_wall_temperature(2.0, seed=3).run(until=20.0).wall_temperature
            2.0
        """
        kt = _number(kt, "wall temperature", "a finite energy >= 0 (0: off)", minimum=0.0)
        _compiled(self.container.dimensions, inelastic=kt > 0.0 or self._engine.inelastic)
        self._engine.set_wall_temperature(kt, seed)
        return self

    @property
    def dissipated(self) -> float:
        """Kinetic energy dissipated by inelastic collisions and reflections since the start [energy].

        Kinetic plus dissipated energy is conserved to rounding
        (docs/numerics.md, "Inelastic collisions").
        """
        return self._engine.dissipated

    def set_restitution(
        self, restitution: float = 1.0, wall_restitution: float | None = None, tc: float = 0.0
    ) -> Simulation:
        """Change the collision rule from now on (the arguments as the constructor's); returns self.

        E.g. equilibrate elastic spheres, then let them cool.  Checkpoints
        keep the rule.

        Example:
            >>> import hardspheres as hs
            >>> sim = hs.Simulation(hs.random_spheres(100, 0.1, box=20.0, seed=1), hs.PeriodicBox(20.0))
            >>> sim.set_restitution(0.9).restitution
            0.9
        """
        restitution, wall_restitution, tc = _rule(restitution, wall_restitution, tc)
        _compiled(
            self.container.dimensions,
            inelastic=restitution < 1.0 or (wall_restitution or 1.0) < 1.0,
            sheared=bool(getattr(self.container, "shear_rate", 0.0)),
        )
        self._engine.set_restitution(restitution, wall_restitution, tc)
        return self

    def run(
        self, until: float | None = None, collisions: int | None = None, events: int | None = None
    ) -> Simulation:
        """Run until time ``until`` or until so many collisions or events, whichever first.

        Writers in :attr:`writers` (:class:`hardspheres.writers.Writer`)
        are called on the way: ``attach(sim)`` as each run starts,
        ``write(sim, t)`` when the clock reaches their ``next_time`` [time]
        or the collision count their ``next_collisions``, and, if their
        ``wants_events`` is true, ``observe(events)`` with each batch of
        events as :meth:`advance <hardspheres.core.engine.Engine.advance>`
        returns them.

        Returns:
            self
        """
        for _ in self._chunks(until, collisions, events, record=False):
            pass
        return self

    def iter_events(
        self, until: float | None = None, collisions: int | None = None, events: int | None = None
    ) -> Iterator[Event]:
        """Run as :meth:`run` does, yielding each :class:`Event` in order."""
        for ev in self._chunks(until, collisions, events, record=True):
            for t, k, i, j, imp, dp in zip(
                ev["time"].tolist(),
                ev["kind"].tolist(),
                ev["i"].tolist(),
                ev["j"].tolist(),
                ev["impulse"].tolist(),
                ev["dp"].tolist(),
            ):
                yield Event(t, KINDS[k], i, j, imp, tuple(dp))

    def _chunks(
        self, until: float | None, collisions: int | None, events: int | None, record: bool
    ) -> Iterator[np.ndarray]:
        if until is None and collisions is None and events is None:
            raise ArgumentError("give until, collisions or events: the run never ends otherwise")
        if until is None:
            until = np.inf
        else:
            until = _number(until, "until", f"a finite time >= the clock ({self.time!r})")
            if until < self.time:
                raise ArgumentError(
                    f"until={until!r} is before the simulation's clock ({self.time!r}); give a later time"
                )
        coll_left = np.inf if collisions is None else _count(collisions, "collisions")
        ev_left = np.inf if events is None else _count(events, "events")
        eng = self._engine
        self._run_until = until
        th = cast("_Acting | None", self.thermostat)  # attached below
        if th is not None:
            th.attach(self)
        bs = cast("_Acting | None", self.barostat)
        if bs is not None:
            bs.attach(self)
        for w in self.writers:
            w.attach(self)
        listeners = [w for w in self.writers if getattr(w, "wants_events", False)]
        yield_events = record  # the caller iterates over the events
        record = record or bool(listeners)
        # the writers with a collision-count trigger (their next_collisions)
        by_count: list[Any] = [w for w in self.writers if getattr(w, "next_collisions", np.inf) < np.inf]
        obs = self.observables
        while coll_left > 0 and ev_left > 0 and not self.stop_requested:
            stop = until if th is None else min(until, th.next_time)
            if bs is not None:
                stop = min(stop, bs.next_time)
            for w in self.writers:
                stop = min(stop, w.next_time)
            # the observables sample their tallies (for error bars) on a time grid
            sampling = obs.next_sample <= stop and not eng.idle
            if sampling:
                stop = obs.next_sample
            step = cast(int, min(ev_left, 1 << 16))  # ev_left is a count or inf
            c0 = eng.counters["collisions"]
            budget = coll_left
            for w in by_count:
                budget = min(budget, max(w.next_collisions - c0, 0))
            ev = eng.advance(
                until=stop, events=step, collisions=None if budget == np.inf else int(budget), record=record
            )
            c1 = eng.counters["collisions"]
            coll_left -= c1 - c0
            ev_left -= eng.last_done
            for w in listeners:
                w.observe(ev)
            if yield_events:
                yield ev
            for w in by_count:
                if w.next_collisions <= c1:
                    w.write(self, self.time)
            if eng.last_reason == StopReason.UNTIL:  # reached `stop`
                if stop < np.inf:
                    self._clock = max(self._clock, stop)
                if sampling:
                    obs.sample()
                if th is not None and th.next_time <= stop:
                    th.apply(self, th.next_time)
                if bs is not None and bs.next_time <= stop:
                    bs.apply(self, bs.next_time)
                for w in self.writers:
                    if w.next_time <= stop:
                        w.write(self, w.next_time)
                if stop >= until:
                    break

    def request_stop(self) -> None:
        """End the current run early, at its next chunk of events (safe from a signal handler).

        Runs stop at once until :attr:`stop_requested` is set back to ``False``.
        """
        self.stop_requested = True

    # ---- dense matter ----------------------------------------------------------
    def compress(
        self,
        packing: float | None = None,
        rate: float = 1e-3,
        pressure: float = 1e3,
        collisions: int | None = None,
        progress: Callable[[float, float, int], None] | None = None,
    ) -> CompressResult:
        """Compress by growing every radius in proportion (Lubachevsky-Stillinger).

        Radii grow linearly in time; colliding spheres part faster than
        their contact distance grows, and velocities are rescaled every few
        collisions per sphere to keep ``kT`` at its value at the start.

        Args:
            packing: stop at this packing fraction (must be above the
                present one and below what the geometry allows: 0.7405 for
                equal spheres).
            rate: growth speed of the largest diameter in units of the
                thermal speed ``sqrt(kT/m)``; > 0 (the ``growthrate`` g of
                Skoge et al.'s program is ``2 sqrt(3) g``: see
                :mod:`hardspheres.dense`).
            pressure: stop when the reduced pressure ``Z = PV/(NkT)``
                passes this (jammed; ``None``: no threshold).
            collisions: stop after this many collisions.
            progress: called as ``progress(packing, Z, collisions)`` at
                each velocity rescale.

        Returns:
            :class:`hardspheres.dense.CompressResult` (``jammed`` says
            whether it stopped on the pressure: not an error).

        Raises:
            CompressionError: a bad option (the message names it).

        Example:
            >>> import hardspheres as hs
            >>> sim = hs.Simulation(hs.random_spheres(200, 0.3, box=10.0, seed=1),
            ...                     hs.PeriodicBox(10.0))
            >>> res = sim.compress(packing=0.45, rate=0.01)
            >>> res.reason, round(res.packing, 6)
            ('packing', 0.45)
        """
        from .dense import compress

        try:
            return compress(
                self, packing=packing, rate=rate, pressure=pressure, collisions=collisions, progress=progress
            )
        finally:  # the clock moves with the spheres, even when the compression was stopped
            self._clock = max(self._clock, self._engine.time)

    @property
    def packing(self) -> float:
        """Packing fraction now, the volume of the spheres over the container's."""
        from .dense import packing_fraction

        return packing_fraction(self._engine.radii_at(), self.container)

    def set_thermostat(self, thermostat: Thermostat | None) -> Simulation:
        """Hold the temperature with a thermostat (``None``: NVE, the default).

        ``thermostat`` is a :class:`hardspheres.dense.Andersen`,
        :class:`hardspheres.dense.VelocityRescale` or
        :class:`hardspheres.dense.RandomKicks` (white-noise driving of a
        granular gas); checkpoints keep it.
        """
        if (
            thermostat is not None
            and bool(getattr(self.container, "shear_rate", 0.0))
            and type(thermostat).__name__ not in ("PeculiarRescale", "PeculiarAndersen")
        ):
            raise ShearError(
                f"thermostat: {type(thermostat).__name__} would act on the flow of a sheared box; "
                "use hardspheres.dense.PeculiarRescale or PeculiarAndersen (on the peculiar velocities)"
            )
        if thermostat is not None and self._engine.window > 0.0:
            raise ArgumentError(
                f"thermostat: not with a simultaneity window (window={self._engine.window:g}); "
                "build the Simulation with window=0"
            )
        old, self.thermostat = self.thermostat, thermostat  # its own slot: it acts before the writers observe
        self.observables.thermostat_changed(old)  # a driving thermostat's injected energy counts from now
        return self

    def set_barostat(self, barostat: Barostat | None) -> Simulation:
        """Hold the pressure with a barostat (``None``: constant volume, the default).

        ``barostat`` is a :class:`hardspheres.barostat.Barostat` (Monte
        Carlo volume moves between event-driven stretches); it acts after
        the thermostat and before the writers; checkpoints keep it.

        Raises:
            BarostatError: not a periodic box, or a simultaneity window.
        """
        if barostat is not None:
            barostat.check(self)
        self.barostat = barostat
        return self

    # ---- state -----------------------------------------------------------------
    def state(self, time: float | None = None, unwrapped: bool = False) -> State:
        """The spheres at ``time`` (default: the clock) as a :class:`State`.

        Positions are advanced exactly along each sphere's line from its
        last event; in a periodic box they are wrapped into the box, and
        ``State.images`` holds each sphere's exact count of box crossings.
        It never runs the simulation: for a later time, :meth:`run` to it first.

        Args:
            unwrapped: positions not wrapped into the box (periodic box
                only): where each sphere would be had the box no edges,
                for displacements and diffusion.

        Raises:
            PeriodicBoxRequired: ``unwrapped`` in a spherical container.
        """
        if unwrapped:
            require_periodic(self.container, "unwrapped positions")
        t = self.time if time is None else _number(time, "time", "a finite time [time]")
        if t > self.time:
            raise ArgumentError(
                f"time {t} is after the simulation's clock ({self.time}); run(until={t!r}) first"
            )
        if t < self.time:
            raise ArgumentError(
                f"time {t} is before the simulation's clock ({self.time}); "
                "the past is not kept: ask for states as you run"
            )
        eng = self._engine
        periodic = self.container.periodic
        if periodic:
            # the images of the stored centres, then of the ones wrapped into the box
            raw = eng.unwrapped_at(t)
            pos = eng.positions_at(t)
            images = np.rint((raw - pos) / eng.sides).astype(np.int64)
            if unwrapped:
                pos = raw
        else:
            pos, images = eng.positions_at(t), None
        return State(
            eng.masses.copy(), eng.radii_at(t), pos, eng.velocities.copy(), list(self.names), t, images
        )

    # ---- checkpoints ---------------------------------------------------------
    def save(self, path: str | os.PathLike, lock: bool = True) -> None:
        """Write a checkpoint; :meth:`load` resumes it bit for bit.

        The file (an ``.npz`` with a ``format`` name and ``version``) is
        written through :func:`hardspheres.fileio.atomic_write`: a unique
        temporary in the same folder, fsync-ed and renamed, under a lock, so
        an interrupted save leaves the old checkpoint, and two saves to one
        file never mix.

        Args:
            path: the checkpoint file (``.npz``).
            lock: take the file's lock while writing; ``False`` when the
                caller already holds it (the ``run`` command locks its
                checkpoint for the whole run).

        Raises:
            FileInUseError: another writer holds ``path``.
            OSError: naming ``path``.
        """
        th = self.thermostat
        arrays: dict[str, np.ndarray] = {
            "format": np.array(checkpoint.FORMAT),
            "version": np.array(checkpoint.VERSION),
            "names": np.array(self.names, dtype=str).reshape(-1),
            **self.observables.checkpoint(),
            "clock": np.array(self._clock),
        }
        if th is not None:
            arrays["thermostat"] = np.array(th.state())
        if self.barostat is not None:
            arrays["barostat"] = np.array(self.barostat.state())
        arrays.update(self._engine.checkpoint())  # the container's record is the engine's
        with atomic_write(path, "wb", lock=lock) as fh:
            np.savez(fh, **arrays)  # type: ignore[arg-type]

    @classmethod
    def load(cls, path: str | os.PathLike) -> Simulation:
        """Resume a checkpoint written by :meth:`save`.

        Every array is checked before the compiled core sees it.

        Raises:
            CheckpointError: the file is not a checkpoint of this format and
                version, is truncated or damaged (one line says which).
            OSError: the file cannot be read.
        """
        data = checkpoint.read(path)
        if "container" not in data:
            raise CheckpointError(f"{path}: damaged checkpoint: no valid container")
        sim = cls.__new__(cls)
        names = data.pop("names", None)
        obs_arrays: dict[str, np.ndarray] = {
            k: data.pop(k) for k in ("obs", "obs_samples", "obs_every") if k in data
        }
        mark = obs_arrays.get("obs")
        clock = data.pop("clock", None)
        th = data.pop("thermostat", None)
        bs = data.pop("barostat", None)
        try:
            sim._engine = Engine.restore(data, before_core=_compiled)  # it reads and checks the container
        except CheckpointError as e:
            raise CheckpointError(f"{path}: {e}") from None
        sim.container = sim._engine.container
        sheared = bool(getattr(sim.container, "shear_rate", 0.0))
        stepped = bool(sim._engine.steps)
        if (
            sim._engine.inelastic or sheared or stepped
        ):  # (these variants of the core are compiled on their own)
            _compiled(
                sim.container.dimensions, inelastic=sim._engine.inelastic, sheared=sheared, stepped=stepped
            )
        n = sim._engine.n
        if names is None or names.dtype.kind != "U" or names.shape != (n,) or len(set(names.tolist())) != n:
            raise CheckpointError(f"{path}: damaged checkpoint: not {n} distinct names")
        if mark is None or mark.dtype != np.float64 or mark.ndim != 1 or not np.all(np.isfinite(mark)):
            raise CheckpointError(f"{path}: damaged checkpoint: bad observables mark")
        if clock is None or clock.shape != () or not np.isfinite(clock):
            raise CheckpointError(f"{path}: damaged checkpoint: bad clock")
        eng = sim._engine
        sim.names = [str(x) for x in names]
        sim.writers = []
        sim.stop_requested = False
        sim._run_until = math.inf
        sim._clock = float(clock)
        sim.observables = Observables(sim)
        sim.observables.restore(obs_arrays)  # an older layout's mark: averages start afresh
        if n:
            worst = eng.max_overlap()
            if not worst <= 1e-6 or eng.outside(tol=1e-6):
                raise CheckpointError(f"{path}: damaged checkpoint: spheres overlap or leave the container")
        sim.thermostat = None
        if th is not None:
            from .dense import thermostat_from_state

            _restore_slot(path, "thermostat", lambda: sim.set_thermostat(thermostat_from_state(str(th))))
        sim.barostat = None
        if bs is not None:
            from .barostat import barostat_from_state

            _restore_slot(path, "barostat", lambda: sim.set_barostat(barostat_from_state(str(bs))))
        return sim


_WARM: set[tuple[int, bool, bool, bool]] = set()


def _compiled(
    dimensions: int = 3, inelastic: bool = False, sheared: bool = False, stepped: bool = False
) -> None:
    """Compile the event core for ``dimensions`` now if numba's cache is cold (once per process).

    :func:`~hardspheres.core.warmup.ensure_compiled` says so on stderr first,
    which a notebook shows under the cell, so the first simulation of a fresh
    install is not a silent wait of half a minute.  ``inelastic``: the
    core's inelastic variant (granular gases), compiled on its own.
    """
    if (dimensions, inelastic, sheared, stepped) not in _WARM:
        _WARM.add((dimensions, inelastic, sheared, stepped))
        ensure_compiled(dimensions=dimensions, inelastic=inelastic, sheared=sheared, stepped=stepped)


def _rule(restitution: float, wall: float | None, tc: float) -> tuple[float, float | None, float]:
    """The collision rule's arguments as floats, or a ValueError naming the one that is wrong."""
    e = _number(restitution, "restitution", "a number in (0, 1] (1: elastic)", minimum=0.0)
    ew = None if wall is None else _number(wall, "wall_restitution", "a number in (0, 1] (1: elastic)", 0.0)
    for name, value in (("restitution", e), ("wall_restitution", ew)):
        if value is not None and not 0.0 < value <= 1.0:
            raise ArgumentError(f"{name} must be a number in (0, 1] (1: elastic), got {value!r}")
    return e, ew, _number(tc, "tc", "a finite time >= 0 (0: no TC model) [time]", minimum=0.0)


def _restore_slot(path: str | os.PathLike, what: str, restore: Callable[[], object]) -> None:
    """Run ``restore()`` (a checkpoint's thermostat or barostat back in its slot); refuse a bad one."""
    try:
        restore()
    except (ValueError, KeyError, TypeError) as e:
        raise CheckpointError(f"{path}: damaged checkpoint: bad {what} ({e})") from None


def _number(x: float, what: str, expected: str, minimum: float = -math.inf) -> float:
    """``x`` as a float, or a ValueError saying what was expected."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        v = math.nan
    if not (math.isfinite(v) and v >= minimum):
        raise ArgumentError(f"{what} must be {expected}, got {x!r}")
    return v


def _count(x: float, what: str) -> int:
    """``x`` as an int >= 0, or a ValueError."""
    try:
        v = int(x)
        ok = v == x and v >= 0
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ArgumentError(f"{what} must be a whole number >= 0, got {x!r}")
    return v


def _check_inside(state: State, container: Container) -> None:
    bad = np.nonzero(container.outside(state.positions, state.radii, TOUCH_TOL))[0]
    if len(bad):
        i = int(bad[0])
        problem = (
            container.check_sphere(state.positions[i].tolist(), float(state.radii[i]), [0.0, 0.0, 0.0])
            or "is not wholly inside the container"
        )
        raise ScenarioError(f"sphere {quote(state.names[i])} {problem}")
