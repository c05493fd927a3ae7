"""Simulation: the object physicists script.

A :class:`Simulation` holds spheres in a container, runs them exactly
(compiled event core, :mod:`hardspheres.engine`), hands out the state at any
time, calls writers at fixed time intervals, and accumulates observables.

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

import os
from collections.abc import Iterator, Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .containers import Container, as_container, from_record
from .engine import Engine
from .events import EventKind, StopReason
from .observables import Observables
from .scenario import TOUCH_TOL, ScenarioError, check_scenario, parse_scenario
from .state import State
from .writers import Writer

#: Event kind names by number (:class:`~hardspheres.events.EventKind`).
KINDS = tuple(k.label for k in EventKind)


class Event(NamedTuple):
    """One event of a run.

    Attributes:
        time: [time].
        kind: ``"collision"`` or ``"reflection"``.
        i: the sphere (the lower index of a colliding pair).
        j: the other sphere of a collision, ``-1`` for a reflection.
        impulse: magnitude of the momentum sphere ``i`` received
            [mass*length/time].
    """

    time: float
    kind: str
    i: int
    j: int
    impulse: float


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

    Raises:
        ScenarioError: spheres outside the container or overlapping.
    """

    def __init__(self, state: State, container: Container | float, window: float = 0.0):
        container = as_container(container)
        self.container: Container = container
        self.names = list(state.names)
        #: Writers called as runs go (:class:`hardspheres.writers.Writer`).
        self.writers: list[Writer] = []
        #: Set (e.g. from a signal handler) to end the run at the next chunk
        #: of events; :meth:`request_stop` sets it.
        self.stop_requested = False
        _check_inside(state, container)
        self._engine = Engine(state.masses, state.radii, container.wrap(state.positions),
                              state.velocities, container, window=window, time=state.time)
        if state.n > 1:
            worst = self._engine.max_overlap()
            if worst > TOUCH_TOL:
                raise ScenarioError(
                    f"spheres overlap by up to {worst:.3g} of their contact distance; "
                    "move them apart")
        self._clock = float(state.time)
        self.observables = Observables(self)

    # ---- construction ------------------------------------------------------
    @classmethod
    def from_arrays(cls, masses: ArrayLike, radii: ArrayLike, positions: ArrayLike,
                    velocities: ArrayLike, container: Container | float,
                    names: Sequence[str] | None = None,
                    time: float = 0.0, window: float = 0.0) -> Simulation:
        """Build from arrays: ``masses (N,)`` [mass], ``radii (N,)`` [length],
        ``positions (N, 3)`` [length], ``velocities (N, 3)`` [length/time]."""
        return cls(State.from_arrays(masses, radii, positions, velocities, names, time),
                   container, window=window)

    @classmethod
    def from_scenario(cls, source: str | bytes | os.PathLike, container: Container | float,
                      window: float = 0.0) -> Simulation:
        """Build from a scenario in the assignment's input format.

        Args:
            source: a path, or the scenario text itself (``str`` with a
                newline, or ``bytes``).
            container: the container.
        """
        if isinstance(source, (bytes, str)) and (
                isinstance(source, bytes) or "\n" in source):
            data = source
        else:
            with open(source, "rb") as fh:
                data = fh.read()
        scn = parse_scenario(data)
        check_scenario(scn, container)
        return cls(State.from_scenario(scn), container, window=window)

    # ---- running -------------------------------------------------------------
    @property
    def time(self) -> float:
        """The simulation's clock [time]: where the last run stopped."""
        return float(max(self._engine.time, self._clock))

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self._engine.n

    @property
    def engine(self) -> Engine:
        """The compiled engine: its running tallies and velocities (read, do not change)."""
        return self._engine

    @property
    def counters(self) -> dict[str, int]:
        """Events processed so far: collisions, reflections, crossings, stale."""
        return self._engine.counters

    def run(self, until: float | None = None, collisions: int | None = None,
            events: int | None = None) -> Simulation:
        """Run until time ``until`` or until so many collisions or events, whichever first.

        Writers in :attr:`writers` (:class:`hardspheres.writers.Writer`)
        are called on the way: ``attach(sim)`` as each run starts,
        ``write(sim, t)`` when the clock reaches their ``next_time`` [time]
        or the collision count their ``next_collisions``, and, if their
        ``wants_events`` is true, ``observe(events)`` with each batch of
        events as :meth:`advance <hardspheres.engine.Engine.advance>`
        returns them.

        Returns:
            self
        """
        for _ in self._chunks(until, collisions, events, record=False):
            pass
        return self

    def iter_events(self, until: float | None = None, collisions: int | None = None,
                    events: int | None = None) -> Iterator[Event]:
        """Run as :meth:`run` does, yielding each :class:`Event` in order."""
        for ev in self._chunks(until, collisions, events, record=True):
            for t, k, i, j, imp in zip(ev["time"].tolist(), ev["kind"].tolist(),
                                       ev["i"].tolist(), ev["j"].tolist(),
                                       ev["impulse"].tolist()):
                yield Event(t, KINDS[k], i, j, imp)

    def _chunks(self, until, collisions, events, record):
        if until is None and collisions is None and events is None:
            raise ValueError("give until, collisions or events: the run never ends otherwise")
        until = np.inf if until is None else float(until)
        coll_left = np.inf if collisions is None else int(collisions)
        ev_left = np.inf if events is None else int(events)
        eng = self._engine
        for w in self.writers:
            w.attach(self)
        listeners = [w for w in self.writers if getattr(w, "wants_events", False)]
        keep = record
        record = record or bool(listeners)
        by_count = [w for w in self.writers if getattr(w, "next_collisions", np.inf) < np.inf]
        while coll_left > 0 and ev_left > 0 and not self.stop_requested:
            stop = until
            for w in self.writers:
                stop = min(stop, w.next_time)
            step = min(ev_left, 1 << 16)
            c0 = eng.counters["collisions"]
            budget = coll_left
            for w in by_count:
                budget = min(budget, max(w.next_collisions - c0, 0))
            ev = eng.advance(until=stop, events=step,
                             collisions=None if budget == np.inf else int(budget),
                             record=record)
            c1 = eng.counters["collisions"]
            coll_left -= c1 - c0
            ev_left -= eng.last_done
            for w in listeners:
                w.observe(ev)
            if keep:
                yield ev
            for w in by_count:
                if w.next_collisions <= c1:
                    w.write(self, self.time)
            if eng.last_reason == StopReason.UNTIL:  # reached `stop`
                if stop < np.inf:
                    self._clock = max(self._clock, stop)
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

    # ---- state -----------------------------------------------------------------
    def state(self, time: float | None = None) -> State:
        """The spheres at ``time`` (default: the clock) as a :class:`State`.

        Positions are advanced exactly along each sphere's line from its
        last event; in a periodic box they are wrapped into the box.  It
        never runs the simulation: for a later time, :meth:`run` to it first.
        """
        t = self.time if time is None else float(time)
        if t > self.time:
            raise ValueError(f"time {t} is after the simulation's clock ({self.time}); "
                             f"run(until={t!r}) first")
        if t < self.time:
            raise ValueError(f"time {t} is before the simulation's clock ({self.time}); "
                             "the past is not kept: ask for states as you run")
        eng = self._engine
        return State(eng.mass.copy(), eng.rad.copy(), eng.positions_at(t), eng.vel.copy(),
                     list(self.names), t)

    # ---- checkpoints ---------------------------------------------------------
    def save(self, path: str | os.PathLike) -> None:
        """Write a checkpoint; :meth:`load` resumes it bit for bit.

        The file is written to a temporary name and renamed, so an
        interrupted save never leaves a broken checkpoint.
        """
        tmp = f"{path}.tmp"
        with open(tmp, "wb") as fh:
            np.savez(fh, names=np.array(self.names, dtype=str).reshape(-1),
                     obs=np.array(self.observables._mark, dtype=np.float64),
                     clock=np.array(self._clock),
                     **self._engine.checkpoint())
        os.replace(tmp, path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> Simulation:
        """Resume a checkpoint written by :meth:`save`."""
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        sim = cls.__new__(cls)
        sim.container = from_record(data["container"])
        sim.names = [str(x) for x in data.pop("names")]
        sim.writers = []
        sim.stop_requested = False
        mark = data.pop("obs")
        sim._clock = float(data.pop("clock"))
        sim._engine = Engine.restore(data)
        sim.observables = Observables(sim)
        sim.observables._mark = tuple(mark.tolist())
        return sim


def _check_inside(state, container):
    bad = np.nonzero(container.outside(state.positions, state.radii, TOUCH_TOL))[0]
    if len(bad):
        i = int(bad[0])
        problem = container.check_sphere(state.positions[i].tolist(), float(state.radii[i]),
                                         [0.0, 0.0, 0.0]) or "is not wholly inside the container"
        raise ScenarioError(f"sphere {state.names[i]!r} {problem}")
