"""The brute-force reference engine: simple, obviously right, O(N^2) per event.

:class:`Reference` speaks the compiled :class:`~hardspheres.core.engine.Engine`'s
interface (as DynamO keeps its brute-force scheduler behind the same
interface as its fast ones): the same constructor, :meth:`~Reference.step`,
:meth:`~Reference.advance`, :meth:`~Reference.positions_at`, ``velocities``,
``counters``, so the assignment's program has one loop for both and the
tests run one test on either.  After every event it predicts every wall and
every pair afresh, takes the earliest, and processes it.  It is the
definition the engine is tested against, and it runs the assignment's
program for small inputs, where it is faster than loading the compiled core.

Arithmetic shared with the engine, so that both give bit-identical results
(from time 0, engine built with ``rebase=False``):

* each sphere is kept as its centre ``p`` at its own time ``tloc`` (the time
  of its last event); its centre at ``t`` is ``p + v * (t - tloc)``;
* a pair is predicted from the later of its two spheres' times, a wall from
  the sphere's own time, so a prediction does not depend on when it is made.

Rules of the assignment (``tests/data/assignment/README.md``):

* an event less than the window (the program's :data:`SIMULTANEOUS`) after
  the last event (the clock) happens now, at the clock;
* among events at the same time, reflections go before collisions, lower
  input index first, pairs ``(i, j)`` with ``i < j`` in input order;
* events at times ``<= until`` are processed, none after.

And two of the model's own (both engines stop the same way, with
:class:`~hardspheres.scenario.StuckError`, before the event):

* a reflection that would not change the velocity (a sphere at the wall
  moving along it) is not an event: it would come again at once, forever;
* more than :func:`~hardspheres.physics.frozen_limit` collisions and
  reflections in a row with the clock not advancing: it is stuck.

Pure Python floats throughout (no numpy, which the assignment's program does
not load for small inputs; only :meth:`Reference.advance`'s event record and
:meth:`Reference.kinetic_energy` load it).  The loop's steps are module
functions (:func:`next_event`, :func:`move_sphere`, :func:`apply_event`) on
sequences of ``[x, y, z]``: lists here, numpy arrays where the tests compile
the same functions with numba to check the engine at larger ``N``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..containers import Container, as_container
from ..errors import BoxShapeError
from ..events import EventKind, StopReason
from ..physics import (
    FROZEN_RELATIVE,
    INF,
    collide,
    frozen_limit,
    pair_time,
    reflect,
    wall_time,
)
from ..scenario import StuckError

if TYPE_CHECKING:
    import numpy as np

#: The assignment's simultaneity window: events closer than this to the
#: current time happen now [time].
SIMULTANEOUS = 1e-8

#: Event kinds (:class:`~hardspheres.events.EventKind`'s numbers, as plain
#: ints for the loop's speed).
REFLECTION = int(EventKind.REFLECTION)
COLLISION = int(EventKind.COLLISION)

_NEVER = 1 << 62  # no count limit


def next_event(
    p: list[list[float]],
    v: list[list[float]],
    tloc: list[float],
    radii: list[float],
    wall: float,
    clock: float,
    window: float,
) -> tuple[float, int, int, int]:
    """Earliest event as ``(t, kind, i, j)`` (``j = -1`` for walls).

    Args:
        p, v: ``N`` centres (at each sphere's own time) and velocities.
        tloc: ``N`` times of the spheres' last events [time].
        radii: ``N`` radii [length].
        wall: the container's radius [length].
        clock: the time of the last event [time].
        window: events before ``clock + window`` are put at ``clock`` [time].

    Returns:
        ``(t, kind, i, j)``, or ``(inf, -1, -1, -1)`` when nothing will ever
        happen.
    """
    n = len(p)
    soon = clock + window
    best = INF
    best_kind, best_i, best_j = -1, -1, -1
    for i in range(n):
        pi, vi = p[i], v[i]
        te = tloc[i] + wall_time(pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], wall - radii[i])
        if te < soon:
            te = clock
        if te < best:
            best, best_kind, best_i, best_j = te, REFLECTION, i, -1
    for i in range(n):
        pi, vi, ri, ti = p[i], v[i], radii[i], tloc[i]
        for j in range(i + 1, n):
            pj, vj, tj = p[j], v[j], tloc[j]
            t0 = ti if ti > tj else tj
            di, dj = t0 - ti, t0 - tj
            te = t0 + pair_time(
                (pi[0] + vi[0] * di) - (pj[0] + vj[0] * dj),
                (pi[1] + vi[1] * di) - (pj[1] + vj[1] * dj),
                (pi[2] + vi[2] * di) - (pj[2] + vj[2] * dj),
                vi[0] - vj[0],
                vi[1] - vj[1],
                vi[2] - vj[2],
                ri + radii[j],
            )
            if te < soon:
                te = clock
            if te < best:
                best, best_kind, best_i, best_j = te, COLLISION, i, j
    return best, best_kind, best_i, best_j


def move_sphere(p: list[list[float]], v: list[list[float]], tloc: list[float], i: int, t: float) -> None:
    """Move sphere ``i`` along its line to time ``t`` (its centre and own time change)."""
    pi, vi = p[i], v[i]
    dt = t - tloc[i]
    pi[0] += vi[0] * dt
    pi[1] += vi[1] * dt
    pi[2] += vi[2] * dt
    tloc[i] = t


def apply_event(
    kind: int, i: int, j: int, p: list[list[float]], v: list[list[float]], masses: list[float]
) -> tuple[float, float, float, float, float]:
    """Change the velocities for one event (its spheres moved to its time).

    Returns:
        ``(impulse, dpx, dpy, dpz, virial)``: the magnitude and the vector of
        the momentum sphere ``i`` receives [mass*length/time], and for a
        collision ``r_ij . dp_i`` [mass*length^2/time] (0 for a reflection),
        with the core's arithmetic.
    """
    if kind == REFLECTION:
        pi, vi = p[i], v[i]
        px, py, pz = pi[0], pi[1], pi[2]
        k = reflect(px, py, pz, vi[0], vi[1], vi[2])
        vi[0] -= k * px
        vi[1] -= k * py
        vi[2] -= k * pz
        mi = masses[i]
        imp = mi * k * math.sqrt(px * px + py * py + pz * pz)
        return imp, -mi * k * px, -mi * k * py, -mi * k * pz, 0.0
    pi, pj, vi, vj = p[i], p[j], v[i], v[j]
    dx, dy, dz = pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]
    k1, k2 = collide(masses[i], masses[j], dx, dy, dz, vi[0] - vj[0], vi[1] - vj[1], vi[2] - vj[2])
    vi[0] -= k1 * dx
    vi[1] -= k1 * dy
    vi[2] -= k1 * dz
    vj[0] += k2 * dx
    vj[1] += k2 * dy
    vj[2] += k2 * dz
    mi = masses[i]
    d2 = dx * dx + dy * dy + dz * dz
    return -mi * k1 * math.sqrt(d2), -mi * k1 * dx, -mi * k1 * dy, -mi * k1 * dz, -mi * k1 * d2


def _row(row: Sequence[float], d: int, what: str) -> list[float]:
    """A centre or velocity as ``[x, y, z]`` floats (``z = 0`` in 2-D); ValueError if not ``d`` numbers."""
    out = [float(x) for x in row]
    if len(out) != d:
        raise BoxShapeError(f"{what} have {len(out)} components but the container is {d}-D; give {d}")
    return out + [0.0] if d == 2 else out


class Reference:
    """Exact event-driven dynamics of hard spheres, by brute force, in pure Python.

    The arguments, and the methods that run and read, are
    :class:`~hardspheres.core.engine.Engine`'s (not its cells, time origin,
    growth, kicks, checkpoints or overlap checks); arrays come back as lists.

    Args:
        masses: ``N`` [mass], > 0.
        radii: ``N`` [length], >= 0.
        positions: ``N`` centres ``[x, y, z]`` at time ``time`` [length] (copied).
        velocities: ``N`` velocities ``[vx, vy, vz]`` [length/time] (copied).
        container: a spherical :class:`~hardspheres.containers.Container`,
            or its radius [length].
        box: (the engine's) a periodic box: refused here.
        window: simultaneity window [time] (the assignment's program uses
            :data:`SIMULTANEOUS`; 0 means exact times).
        time: the time the positions are given at [time].
        rebase: ignored (the engine's option; this loop keeps absolute times).

    Raises:
        ValueError: a periodic box (the reference has a spherical wall only).

    Example:
        >>> ref = Reference([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]],
        ...                 [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0)
        >>> ref.step(until=10.0)
        (4.0, 1, 0, 1)
        >>> ref.velocities, ref.step(until=10.0)
        ([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], None)
    """

    def __init__(
        self,
        masses: Sequence[float],
        radii: Sequence[float],
        positions: Sequence[Sequence[float]],
        velocities: Sequence[Sequence[float]],
        container: Container | float | None = None,
        box: float | None = None,
        window: float = 0.0,
        time: float = 0.0,
        rebase: bool = False,
    ) -> None:
        where = as_container(container, box)
        if where.periodic:
            raise ValueError(
                "the reference loop has a spherical wall only; use the engine for a periodic box"
            )
        self.container: Container = where
        self._wall = where.core_params()["wall_radius"]
        #: the dimension of space (the container's); in 2-D each centre and
        #: velocity is kept as ``[x, y, 0.0]``: the same kernels, z terms exactly 0
        self.dimensions = d = int(getattr(where, "dimensions", 3))
        self.masses = [float(m) for m in masses]
        self._radii = [float(r) for r in radii]
        self._p = [_row(row, d, "positions") for row in positions]
        self._v = [_row(row, d, "velocities") for row in velocities]
        n = len(self.masses)
        if not len(self._radii) == len(self._p) == len(self._v) == n:
            raise ValueError(
                f"{n} masses but {len(self._radii)} radii, {len(self._p)} positions "
                f"and {len(self._v)} velocities; give one of each per sphere"
            )
        self._window = float(window)
        self._tloc = [float(time)] * n
        self._clock = float(time)
        self._limit = frozen_limit(n)
        self._frozen = 0  # collisions and reflections in a row with the clock not advancing
        self._streak = self._clock  # time of the first of them
        self._coll = self._refl = 0
        self._wall_impulse = self._virial = 0.0
        self.last_reason, self.last_done = StopReason.UNTIL, 0

    # ---- what the engine also tells ---------------------------------------------
    @property
    def n(self) -> int:
        """Number of spheres."""
        return len(self.masses)

    @property
    def velocities(self) -> list[list[float]]:
        """``N`` velocities now [length/time] (in 3-D the loop's own lists: do not write)."""
        if self.dimensions == 2:
            return [v[:2] for v in self._v]
        return self._v

    @property
    def time(self) -> float:
        """Time of the last processed event (or the start) [time]."""
        return self._clock

    @property
    def window(self) -> float:
        """The simultaneity window [time]."""
        return self._window

    @property
    def counters(self) -> dict[str, int]:
        """Events so far: collisions, reflections (crossings, stale, refreshed: 0, no cells)."""
        return {
            "collisions": self._coll,
            "reflections": self._refl,
            "crossings": 0,
            "stale": 0,
            "refreshed": 0,
        }

    @property
    def wall_impulse(self) -> float:
        """Total impulse delivered to the container wall [mass*length/time]."""
        return self._wall_impulse

    @property
    def virial(self) -> float:
        """Sum over collisions of ``r_ij . dp_i`` [mass*length^2/time]."""
        return self._virial

    @property
    def idle(self) -> bool:
        """Whether nothing will ever happen again."""
        return self._next()[1] < 0

    def radii_at(self, t: float | None = None) -> list[float]:
        """``N`` radii [length] (they do not grow here)."""
        return list(self._radii)

    def positions_at(
        self, t: float | None = None, out: Any = None, spheres: Sequence[int] | None = None
    ) -> Any:
        """Centres of all spheres at time ``t`` (default: now) [length].

        Into ``out`` (a list of ``N`` rows, or an ``(N, 3)`` array) if given;
        with ``spheres`` (indices), only their rows.
        """
        t = self._clock if t is None else t
        p, v, tloc = self._p, self._v, self._tloc
        if out is None:
            out = [None] * len(p)
        for k in range(len(p)) if spheres is None else spheres:
            pk, vk = p[k], v[k]
            dt = t - tloc[k]
            if self.dimensions == 2:
                out[k] = [pk[0] + vk[0] * dt, pk[1] + vk[1] * dt]
            else:
                out[k] = [pk[0] + vk[0] * dt, pk[1] + vk[1] * dt, pk[2] + vk[2] * dt]
        return out

    def kinetic_energy(self) -> float:
        """Total kinetic energy [mass*length^2/time^2]."""
        import numpy as np

        from ..state import kinetic_energy

        return float(kinetic_energy(np.asarray(self.masses), np.asarray(self._v)))

    # ---- running ------------------------------------------------------------------
    # the loop's steps (the tests swap in the same functions compiled)
    _next_event = staticmethod(next_event)
    _move_sphere = staticmethod(move_sphere)
    _apply_event = staticmethod(apply_event)

    def _next(self) -> tuple[float, int, int, int]:
        return self._next_event(
            self._p, self._v, self._tloc, self._radii, self._wall, self._clock, self._window
        )

    def _process(self, until: float) -> tuple[float, int, int, int, float, float, float, float] | None:
        """The next event up to ``until``, processed: ``(t, kind, i, j, impulse, dp..., virial)``.

        ``None`` if it is after ``until`` (or there is none).

        Raises:
            StuckError: it would be the reflection of a sphere sliding along
                the wall, or one too many in a row with the clock frozen.
        """
        t, kind, i, j = self._next()
        if kind < 0 or not t <= until:
            return None
        if t - self._streak <= FROZEN_RELATIVE * abs(t):
            if self._frozen >= self._limit:
                raise StuckError("frozen", t, i)
        else:
            self._frozen = 0
            self._streak = t
        p, v, tloc = self._p, self._v, self._tloc
        if kind == REFLECTION:
            pi, vi = p[i], v[i]
            dt = t - tloc[i]
            if (
                reflect(pi[0] + vi[0] * dt, pi[1] + vi[1] * dt, pi[2] + vi[2] * dt, vi[0], vi[1], vi[2])
                == 0.0
            ):
                raise StuckError("sliding", t, i)
        self._frozen += 1
        self._clock = t
        self._move_sphere(p, v, tloc, i, t)
        if j >= 0:
            self._move_sphere(p, v, tloc, j, t)
        imp, dpx, dpy, dpz, vir = self._apply_event(kind, i, j, p, v, self.masses)
        if kind == REFLECTION:
            self._refl += 1
            self._wall_impulse += imp
        else:
            self._coll += 1
            self._virial += vir
        return t, kind, i, j, imp, dpx, dpy, dpz

    def step(self, until: float = INF) -> tuple[float, int, int, int] | None:
        """Process the next event if it is at or before ``until`` [time].

        Returns:
            ``(time, kind, i, j)`` of the event (``kind`` an
            :class:`~hardspheres.events.EventKind` number, ``j = -1`` for a
            reflection), or ``None`` if the next one is after ``until``.

        Raises:
            StuckError: the next event would repeat without end (a sphere
                sliding along the wall, or a frozen clock).
        """
        done = self._process(until)
        return None if done is None else done[:4]

    def advance(
        self,
        until: float = INF,
        events: int | None = None,
        collisions: int | None = None,
        record: bool = True,
    ) -> np.ndarray:
        """Process events up to time ``until`` or a count limit, as the engine's ``advance``.

        Returns:
            The events processed, in order: an array of
            :data:`~hardspheres.events.EVENT_DTYPE` (empty if not ``record``).

        Raises:
            ValueError: ``until`` is NaN.
            StuckError: as :meth:`step`; events before it are returned first,
                and the call after raises.
        """
        import numpy as np

        from ..events import EVENT_DTYPE

        if until != until:
            raise ValueError("until must be a time, not NaN")
        max_events = _NEVER if events is None else int(events)
        max_coll = _NEVER if collisions is None else int(collisions)
        rows = []
        done = coll = 0
        reason = StopReason.UNTIL
        while True:
            if done >= max_events:
                reason = StopReason.MAX_EVENTS
                break
            if coll >= max_coll:
                reason = StopReason.MAX_COLLISIONS
                break
            try:
                ev = self._process(until)
            except StuckError as e:
                if done == 0:
                    self.last_reason = StopReason.FROZEN if e.reason == "frozen" else StopReason.SLIDING
                    self.last_done = 0
                    raise
                reason = StopReason.FROZEN if e.reason == "frozen" else StopReason.SLIDING
                break
            if ev is None:
                break
            done += 1
            coll += ev[1] == COLLISION
            if record:
                rows.append((*ev[:5], ev[5:8]))
        self.last_reason, self.last_done = reason, done
        return np.array(rows, dtype=EVENT_DTYPE)
