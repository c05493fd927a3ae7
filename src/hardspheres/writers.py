"""Writers and triggers: *what* a run writes, and *when*.

A writer (the :class:`Writer` protocol) is appended to
:attr:`Simulation.writers <hardspheres.Simulation.writers>`; as a run goes
the simulation attaches it, stops exactly at the times (or collision counts)
its trigger asks for, calls :meth:`Writer.write`, and hands it the events if
it wants them.  Writers only observe: they never change the state (a
thermostat, which does, has its own slot, :meth:`Simulation.set_thermostat
<hardspheres.Simulation.set_thermostat>`).  One writer serves consecutive
runs, so the simulation never ends it: :meth:`Writer.detach` is the caller's
to call (or the trajectory writers' ``close()`` and ``with`` block) when no
more runs will write.  The trajectory writers (:mod:`hardspheres.io.trajectory`)
are such writers.

Triggers (the :class:`Trigger` protocol) say when, as HOOMD-blue's do:

* :class:`Periodic`: every ``period`` [time] from the time the writer is
  attached (its first write is at that time);
* :class:`LogSpaced`: at ``t0`` and ``t0 + first * factor^k`` (lags spread
  evenly on a log scale, for mean-squared displacements);
* :class:`LogOrigins`: a new time origin every ``every`` [time], and from
  each the lags of :class:`LogSpaced` (the multiple-origin log schedule of
  glass studies: log-spaced lags, many origins, frames ~ log per origin);
* :class:`AtTimes`: at given absolute times;
* :class:`EveryCollisions`: after every ``k`` collisions.

Example:
    >>> trig = LogSpaced(first=0.1, per_decade=2)
    >>> trig.start(time=5.0, collisions=0)
    >>> times = []
    >>> for _ in range(4):
    ...     times.append(round(trig.next_time, 6))
    ...     trig.fired()
    >>> times
    [5.0, 5.1, 5.316228, 6.0]
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import TYPE_CHECKING, Protocol, runtime_checkable

from .errors import ArgumentError

if TYPE_CHECKING:
    import numpy as np

    from .containers import Container
    from .core.engine import Engine
    from .state import State


class SimulationView(Protocol):
    """What writers and observables read of a simulation.

    :class:`hardspheres.Simulation` is one; naming this protocol rather than
    the class keeps the import direction one way (``simulation`` imports
    ``writers``, never the reverse).
    """

    @property
    def container(self) -> Container: ...

    @property
    def engine(self) -> Engine: ...

    @property
    def n(self) -> int: ...

    @property
    def time(self) -> float: ...

    @property
    def counters(self) -> dict[str, int]: ...

    @property
    def names(self) -> list[str]: ...

    @property
    def run_end(self) -> float: ...

    def state(self, time: float | None = None, unwrapped: bool = False) -> State: ...


@runtime_checkable
class Trigger(Protocol):
    """When a writer is next due: a time, a collision count, or both (``inf``: never)."""

    def start(self, time: float, collisions: int) -> None:
        """Begin at ``time`` [time] after ``collisions`` collisions (the writer is attached)."""

    @property
    def next_time(self) -> float:
        """Absolute time it is next due [time] (``inf`` when not by time)."""

    @property
    def next_collisions(self) -> float:
        """Collision count at which it is next due (``inf`` when not by count)."""

    def fired(self) -> None:
        """The writer wrote: move on to the next due point."""


@runtime_checkable
class Writer(Protocol):
    """What :class:`hardspheres.Simulation` calls on the objects in ``sim.writers``.

    Attributes:
        next_time: when it is next due [time] (``inf``: not by time).
        next_collisions: the collision count at which it is next due
            (``inf``: not by count); optional (``inf`` if absent).
        wants_events: whether :meth:`observe` is called.
    """

    wants_events: bool

    @property
    def next_time(self) -> float: ...

    def attach(self, sim: SimulationView) -> None:
        """Called as each run starts (a writer attached before keeps its schedule)."""

    def write(self, sim: SimulationView, t: float) -> None:
        """Write now: the simulation's clock is at ``t`` [time]."""

    def observe(self, events: np.ndarray) -> None:
        """The events of the run since the last call (:data:`~hardspheres.events.EVENT_DTYPE`)."""

    def detach(self) -> None:
        """No more writes: flush and close what it holds."""


def _positive_time(value: float, what: str) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ArgumentError(f"{what} must be a finite time > 0, got {value!r}")
    return value


class _ByTime:
    """Base of the triggers due at times only (never by collision count)."""

    @property
    def next_collisions(self) -> float:
        return math.inf


class Periodic(_ByTime):
    """Due at ``t0, t0 + period, t0 + 2 period, ...`` from the time it starts.

    Args:
        period: time between writes [time], > 0.
    """

    def __init__(self, period: float) -> None:
        self.period = _positive_time(period, "every")
        self._t0 = 0.0
        self._count = 0

    def start(self, time: float, collisions: int) -> None:
        self._t0, self._count = float(time), 0

    @property
    def next_time(self) -> float:
        return self._t0 + self._count * self.period

    def fired(self) -> None:
        self._count += 1


class LogSpaced(_ByTime):
    """Due at ``t0`` and at ``t0 + first * factor^k``, ``k = 0, 1, ...``.

    Args:
        first: the first lag [time], > 0.
        factor: ratio of successive lags, > 1; or
        per_decade: that many lags per factor of ten (``factor = 10^(1/per_decade)``).
        until: no lags beyond this one [time] (default: none).
    """

    def __init__(
        self,
        first: float,
        factor: float | None = None,
        per_decade: int | None = None,
        until: float = math.inf,
    ) -> None:
        self.first = _positive_time(first, "first")
        if (factor is None) == (per_decade is None):
            raise ArgumentError("give exactly one of factor and per_decade")
        self.factor = float(factor if factor is not None else 10.0 ** (1.0 / per_decade))  # type: ignore[operator]
        if not (math.isfinite(self.factor) and self.factor > 1.0):
            raise ArgumentError(f"factor must be a finite number > 1, got {self.factor!r}")
        self.until = float(until)
        self._t0 = 0.0
        self._k = -1  # -1: t0 itself

    def start(self, time: float, collisions: int) -> None:
        self._t0, self._k = float(time), -1

    @property
    def next_time(self) -> float:
        if self._k < 0:
            return self._t0
        lag = self.first * self.factor**self._k
        return self._t0 + lag if lag <= self.until * (1.0 + 1e-12) else math.inf

    def fired(self) -> None:
        self._k += 1


class LogOrigins(_ByTime):
    """Due at ``t0 + m every`` and ``t0 + m every + first * factor^k`` for ``m, k = 0, 1, ...``.

    The multiple-origin log schedule: a :class:`LogSpaced` schedule restarted
    every ``every`` [time], the schedules overlapping when ``until >
    every``.  Correlators (:mod:`hardspheres.analysis.dynamics`) then have
    log-spaced lags from ``first`` to ``until`` and one time origin per
    ``every`` for every lag, with about ``per_decade * decades`` frames per
    origin instead of ``until / first``.  Times due within ``1e-12`` (relative)
    of one another are one write.

    Args:
        first: the first lag [time], > 0.
        every: time between origins [time], > 0.
        factor: ratio of successive lags, > 1; or
        per_decade: that many lags per factor of ten.
        until: the longest lag [time] (default ``every``).

    Example:
        >>> trig = LogOrigins(first=1.0, every=10.0, per_decade=1, until=10.0)
        >>> trig.start(time=0.0, collisions=0)
        >>> times = []
        >>> for _ in range(6):
        ...     times.append(round(trig.next_time, 6))
        ...     trig.fired()
        >>> times
        [0.0, 1.0, 10.0, 11.0, 20.0, 21.0]
    """

    def __init__(
        self,
        first: float,
        every: float,
        factor: float | None = None,
        per_decade: int | None = None,
        until: float | None = None,
    ) -> None:
        self.every = _positive_time(every, "every")
        until = self.every if until is None else _positive_time(until, "until")
        self._log = LogSpaced(first, factor=factor, per_decade=per_decade, until=until)
        self.first, self.factor, self.until = self._log.first, self._log.factor, until
        self._t0 = 0.0
        self._next_origin = 0
        self._active: list[list[float]] = []  # [origin time, k] (k = -1: the origin itself)

    def start(self, time: float, collisions: int) -> None:
        self._t0, self._next_origin, self._active = float(time), 0, []

    def _due(self, origin: float, k: int) -> float:
        if k < 0:
            return origin
        lag = self.first * self.factor**k
        return origin + lag if lag <= self.until * (1.0 + 1e-12) else math.inf

    @property
    def next_time(self) -> float:
        new = self._t0 + self._next_origin * self.every
        return min([new] + [self._due(o, int(k)) for o, k in self._active])

    def fired(self) -> None:
        now = self.next_time
        near = now + 1e-12 * max(abs(now), self.first)
        new = self._t0 + self._next_origin * self.every
        if new <= near:
            self._active.append([new, 0])
            self._next_origin += 1
        for entry in self._active:
            while self._due(entry[0], int(entry[1])) <= near:
                entry[1] += 1
        self._active = [e for e in self._active if self._due(e[0], int(e[1])) < math.inf]


class AtTimes(_ByTime):
    """Due at the given absolute times (those before it starts are skipped).

    Args:
        times: absolute times [time], finite.
    """

    def __init__(self, times: Iterable[float]) -> None:
        self.times = sorted(float(t) for t in times)
        if not all(math.isfinite(t) for t in self.times):
            raise ArgumentError("times must be finite; drop the infinite or NaN ones")
        self._k = 0

    def start(self, time: float, collisions: int) -> None:
        self._k = 0
        while self._k < len(self.times) and self.times[self._k] < time:
            self._k += 1

    @property
    def next_time(self) -> float:
        return self.times[self._k] if self._k < len(self.times) else math.inf

    def fired(self) -> None:
        self._k += 1


class EveryCollisions:
    """Due when it starts and after every ``k`` collisions since.

    Args:
        k: collisions between writes, >= 1.
    """

    def __init__(self, k: int) -> None:
        if int(k) != k or k < 1:
            raise ArgumentError(f"k must be a whole number >= 1, got {k!r}")
        self.k = int(k)
        self._t0 = 0.0
        self._c0 = 0
        self._count = 0

    def start(self, time: float, collisions: int) -> None:
        self._t0, self._c0, self._count = float(time), int(collisions), 0

    @property
    def next_time(self) -> float:
        # the first write is at the start; the later ones by count
        return self._t0 if self._count == 0 else math.inf

    @property
    def next_collisions(self) -> float:
        return math.inf if self._count == 0 else float(self._c0 + self._count * self.k)

    def fired(self) -> None:
        self._count += 1


def as_trigger(every: float | None = None, trigger: Trigger | None = None) -> Trigger:
    """A trigger from ``every`` (a :class:`Periodic` period [time]) or the trigger itself."""
    if (every is None) == (trigger is None):
        raise ArgumentError("give exactly one of every (a time) and trigger")
    if trigger is not None:
        if not isinstance(trigger, Trigger):
            raise ArgumentError(
                "trigger must be a Trigger (Periodic, LogSpaced, LogOrigins, AtTimes, "
                f"EveryCollisions), got {trigger!r}"
            )
        return trigger
    return Periodic(every)  # type: ignore[arg-type]  # not None: checked above
