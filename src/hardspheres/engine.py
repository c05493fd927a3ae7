"""The engine: owns the arrays of the compiled event core and drives it.

:class:`Engine` is the one place that knows the core's array layout; the
public API (:mod:`hardspheres.simulation`), the assignment's program and the
benchmark all go through it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from . import _core as core
from . import events as _events
from .containers import Container, as_container, from_record
from .events import StopReason
from .state import kinetic_energy
from .scenario import StuckError

#: Default number of events the core records per call.
CHUNK = 1 << 14

#: The time origin moves to the clock after this many events per sphere.
REBASE_EVERY = 64


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed (damaged, truncated, foreign); the message says why."""


class Engine:
    """Exact event-driven dynamics of hard spheres, compiled.

    Args:
        masses: ``(N,)`` [mass], > 0.
        radii: ``(N,)`` [length], >= 0.
        positions: ``(N, 3)`` centres at time 0 [length].
        velocities: ``(N, 3)`` [length/time].
        container: the :class:`~hardspheres.containers.Container`, or the
            radius of a spherical container centred at the origin [length].
        box: instead of ``container``, the edge of a periodic cubic box
            centred at the origin [length].
        window: simultaneity window [time]: events less than this after the
            last event happen at its time (the assignment uses 1e-8 s; 0
            means exact times).
        time: the time the positions are given at [time].
        rebase: move the time origin forward now and then, for precision
            in long runs (off: the same arithmetic as the reference loop).

    Example:
        >>> eng = Engine([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]],
        ...              [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0)
        >>> ev = eng.advance(until=10.0)
        >>> ev["time"].tolist(), ev["kind"].tolist()
        ([4.0], [1])
    """

    def __init__(self, masses: ArrayLike, radii: ArrayLike, positions: ArrayLike,
                 velocities: ArrayLike, container: Container | float | None = None,
                 box: float | None = None, window: float = 0.0, time: float = 0.0,
                 rebase: bool = True) -> None:
        self.container: Container = as_container(container, box)
        self.mass = np.ascontiguousarray(masses, dtype=np.float64).reshape(-1)
        n = self.mass.shape[0]
        # one 64-byte row per sphere: x y z vx vy vz t_own radius
        self.S = np.zeros((n, 8))
        self.S[:, 0:3] = np.asarray(positions, dtype=np.float64).reshape(n, 3)
        self.S[:, 3:6] = np.asarray(velocities, dtype=np.float64).reshape(n, 3)
        self.S[:, 7] = np.asarray(radii, dtype=np.float64).reshape(n)
        self.K = np.zeros((n, core.K_COLS), np.int64)
        self.T = np.zeros((n, 2))
        self.nxt = np.zeros(n, np.int64)
        self.prv = np.zeros(n, np.int64)
        self.heap = np.zeros(n, np.int64)
        self.HT = np.zeros(n)
        self.HKEY = np.zeros(n, np.int64)
        self.stack = np.zeros(2 * n + 2, np.int64)
        self.img = np.zeros((n, 3), np.int64)  # periodic images (crossings of the box)
        self.f = np.zeros(core.F_NF)
        self.c = np.zeros(core.C_NC_, np.int64)
        self.offset = float(time)  # absolute time of the core's time origin
        self.f[core.F_OFFSET] = self.offset  # the core's copy (rebase keeps it)
        self.f[core.F_WINDOW] = window
        self._grid(n)
        self._rec = _events.empty_buffers(CHUNK)
        self._since_rebase = 0
        self._rebase_on = rebase
        self.last_reason, self.last_done = StopReason.UNTIL, 0
        self._build()

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self.mass.shape[0]

    @property
    def masses(self) -> np.ndarray:
        """``(N,)`` masses [mass] (a view: do not write)."""
        return self.mass

    @property
    def velocities(self) -> np.ndarray:
        """``(N, 3)`` velocities now [length/time] (a view: do not write)."""
        return self.S[:, 3:6]

    @property
    def radii(self) -> np.ndarray:
        """``(N,)`` radii at the time origin [length] (a view; :meth:`radii_at` for now)."""
        return self.S[:, 7]

    @property
    def box(self) -> float | None:
        """Edge of the periodic box as the core reads it [length], or ``None`` (no box)."""
        box = float(self.f[core.F_BOX])
        return box if box else None

    def _grid(self, n, headroom=1.0):
        sigma = 2.0 * float(self.radii.max()) * headroom if n else 0.0
        params = self.container.core_params()
        span, box = params["span"], params["box"]
        self.f[core.F_CONTAINER] = params["wall_radius"]
        self.f[core.F_BOX] = box
        # cells at least as wide as the largest contact distance, with a
        # small relative margin for rounding; a few cells per sphere at most
        nc = int(span / (sigma * (1.0 + 1e-6))) if sigma > 0.0 else 1
        nc = max(1, min(nc, int(np.ceil(2.0 * max(n, 1) ** (1.0 / 3.0))) + 1, 1 << 10))
        if box and nc < 3:
            if sigma * 3.0 > box:
                raise ValueError(
                    f"periodic box {box:g} is smaller than three largest diameters "
                    f"({sigma:g}); use a larger box")
            nc = 3
        self.c[core.C_NC] = nc
        self.f[core.F_LO] = -0.5 * span
        self.f[core.F_W] = span / nc
        self.head = np.full(nc ** 3, -1, np.int64)

    def _build(self):
        core.build(self.S, self.K, self.T, self.head, self.nxt, self.prv, self.heap,
                   self.HT, self.HKEY, self.f, self.c)
        self.f[core.F_T_KIN] = self.f[core.F_CLOCK]
        core.kinetic_sums(self.S, self.mass, self.f)

    # ---- time -------------------------------------------------------------
    @property
    def time(self) -> float:
        """Time of the last processed event (or the start) [time]."""
        return self.offset + self.f[core.F_CLOCK]

    def _rebase(self):
        self.offset += core.rebase(self.S, self.T, self.HT, self.f)
        self._since_rebase = 0

    @property
    def window(self):
        """The simultaneity window [time]."""
        return float(self.f[core.F_WINDOW])

    # ---- growth and velocities -----------------------------------------------
    @property
    def growth(self):
        """Radii's relative growth rate now: ``dR_i/dt / R_i`` [1/time] (0: off)."""
        g = self.f[core.F_GROW]
        return float(g / (1.0 + g * self.f[core.F_CLOCK])) if g else 0.0

    def set_growth(self, rate):
        """Grow every radius from now at ``dR_i/dt = rate * R_i(now)`` [1/time]; 0 stops.

        Radii then grow linearly in time (each at its own constant speed,
        so mixtures keep their ratios), with the Lubachevsky-Stillinger
        collision rule.  Everything is predicted afresh.
        """
        rate = float(rate)
        if not (rate >= 0.0 and np.isfinite(rate)):
            raise ValueError(f"growth rate must be a finite number >= 0, got {rate}")
        self._rebase()  # radii to the clock
        self.f[core.F_GROW] = rate
        self._regrid()

    def _regrid(self):
        """Cells for the radii now (with room to grow), everything predicted afresh."""
        headroom = 1.05 if self.f[core.F_GROW] else 1.0
        self._grid(self.n, headroom)
        self._build()

    def _grid_limit(self):
        """Absolute time the growing radii outgrow the cells (``inf``: never)."""
        g = self.f[core.F_GROW]
        if not g or self.n == 0:
            return np.inf
        nc = int(self.c[core.C_NC])
        if nc == 1 and self.box is None:
            return np.inf
        rmax = float(self.radii.max())
        if rmax <= 0.0:
            return np.inf
        w = float(self.f[core.F_W]) / (1.0 + 1e-6)
        return self.offset + (w / (2.0 * rmax) - 1.0) / g

    def move_clock(self, t):
        """Move the clock to absolute time ``t`` (no event may be pending before it)."""
        t = float(t) - self.offset
        if self.n and self.HT[0] < t:
            raise ValueError("events are pending before that time: advance first")
        if t > self.f[core.F_CLOCK]:
            self.f[core.F_CLOCK] = t

    def radii_at(self, t=None):
        """``(N,)`` radii at absolute time ``t`` (default: now) [length]."""
        g = self.f[core.F_GROW]
        if not g:
            return self.radii.copy()
        t = self.time if t is None else t
        return self.radii * (1.0 + g * (t - self.offset))

    def rescale_velocities(self, factor):
        """Multiply every velocity by ``factor`` now; everything is predicted afresh."""
        self._rebase()
        f = self.f
        dt = f[core.F_CLOCK] - f[core.F_T_KIN]  # the kinetic integrals up to now
        f[core.F_KIN_INT:core.F_KIN_INT + 6] += f[core.F_KIN_T:core.F_KIN_T + 6] * dt
        f[core.F_HEAT_INT:core.F_HEAT_INT + 3] += f[core.F_HEAT_KIN:core.F_HEAT_KIN + 3] * dt
        f[core.F_T_KIN] = f[core.F_CLOCK]
        self.S[:, 3:6] *= factor
        core.kinetic_sums(self.S, self.mass, f)
        self._build()

    def kick(self, i, t, velocity):
        """Sphere ``i`` takes ``velocity`` at absolute time ``t`` (not before the clock)."""
        t = float(t) - self.offset
        if t < self.f[core.F_CLOCK]:
            raise ValueError("a kick cannot be before the clock")
        vx, vy, vz = (float(x) for x in velocity)
        core.kick(self.S, self.mass, self.K, self.T, self.head, self.nxt, self.heap, self.HT,
                  self.HKEY, self.f, self.c, int(i), t, vx, vy, vz)

    # ---- running ----------------------------------------------------------
    def advance(self, until: float = np.inf, events: int | None = None,
                collisions: int | None = None, record: bool = True) -> np.ndarray:
        """Process events up to time ``until`` or a count limit.

        Args:
            until: absolute time [time]; events after it are left pending.
            events: stop after this many collisions and reflections.
            collisions: stop after this many collisions.
            record: return the events processed (else an empty record).

        Returns:
            The events processed, in order: an array of
            :data:`~hardspheres.events.EVENT_DTYPE` (empty if not ``record``).

        Raises:
            ValueError: ``until`` is NaN.
            StuckError: the next event would repeat without end (a sphere
                sliding along the wall, or a frozen clock).  Events before
                it are returned first, and the call after raises.
        """
        if np.isnan(until):
            raise ValueError("until must be a time, not NaN")
        max_events = np.iinfo(np.int64).max if events is None else int(events)
        max_coll = np.iinfo(np.int64).max if collisions is None else int(collisions)
        chunks = []
        coll0 = int(self.c[core.C_COLL])
        done_total = 0
        rec = self._rec
        while True:
            limit = self._grid_limit()
            if limit < until:
                stop = limit
            else:
                stop = until
            rebase_due = (REBASE_EVERY * max(self.n, 16) if self._rebase_on
                          else np.iinfo(np.int64).max)
            left_ev = min(max_events - done_total, rebase_due - self._since_rebase)
            left_coll = max_coll - (int(self.c[core.C_COLL]) - coll0)
            done, reason = core.run(self.S, self.mass, self.K, self.T, self.head, self.nxt,
                                    self.prv, self.heap, self.HT, self.HKEY, self.f,
                                    self.c, self.stack, self.img,
                                    stop - self.offset, left_ev, left_coll, *rec)
            done_total += done
            self._since_rebase += done
            if record and done:
                chunks.append(_events.from_buffers(rec, done, self.offset))
            if self._since_rebase >= rebase_due:
                self._rebase()
            if reason == StopReason.FROZEN or reason == StopReason.SLIDING:
                if done_total == 0:
                    self.last_reason, self.last_done = StopReason(reason), 0
                    raise StuckError("frozen" if reason == StopReason.FROZEN else "sliding",
                                     float(self.offset + self.HT[0]), int(self.heap[0]))
                break  # the events before it first; the next call raises
            if reason == StopReason.UNTIL and stop < until:
                # growing radii reached the cells' width: move the clock
                # there (nothing happens before), and coarser cells
                if self.f[core.F_CLOCK] < limit - self.offset:
                    self.f[core.F_CLOCK] = limit - self.offset
                self._rebase()
                nc = int(self.c[core.C_NC])
                self._regrid()
                if int(self.c[core.C_NC]) >= nc and self._grid_limit() <= limit:
                    raise ValueError("the spheres have grown too large for the periodic box "
                                     "(three diameters at least)")
                continue
            if reason == StopReason.UNTIL or reason == StopReason.MAX_COLLISIONS:
                break
            if reason == StopReason.MAX_EVENTS and done_total >= max_events:
                break
        self.last_reason = StopReason(reason)
        self.last_done = done_total
        if len(chunks) == 1:
            return chunks[0]
        return np.concatenate(chunks) if chunks else _events.empty_events()

    def step(self, until: float = np.inf) -> tuple[float, int, int, int] | None:
        """Process the next event if it is at or before ``until`` (absolute) [time].

        Returns:
            ``(time, kind, i, j)``, or ``None`` if the next event is after
            ``until``; raises as :meth:`advance` does.
        """
        ev = self.advance(until=until, events=1)
        if len(ev) == 0:
            return None
        return float(ev["time"][0]), int(ev["kind"][0]), int(ev["i"][0]), int(ev["j"][0])

    # ---- checkpoints -------------------------------------------------------
    _SAVED = ("mass", "S", "K", "T", "nxt", "prv", "heap", "HT", "HKEY", "f", "c", "head",
              "img")

    def checkpoint(self) -> dict[str, Any]:
        """Everything needed to resume bit for bit, as a dict of arrays."""
        out = {k: getattr(self, k) for k in self._SAVED}
        # the last two: the core's wall radius and box edge, NaN when absent
        # (files before the container record had only these)
        params = self.container.core_params()
        out["meta"] = np.array([self.offset, float(self._since_rebase),
                                float(self._rebase_on),
                                params["wall_radius"] or np.nan, params["box"] or np.nan])
        out["container"] = self.container.record()
        return out

    @classmethod
    def restore(cls, data: dict[str, np.ndarray]) -> Engine:
        """An engine from :meth:`checkpoint`'s arrays, in exactly the saved state.

        Every array is checked first (:func:`check_arrays`): the compiled
        core trusts its indices, so a damaged file must not reach it.

        Raises:
            CheckpointError: an array is missing or inconsistent.
        """
        check_arrays(data)
        eng = cls.__new__(cls)
        for k in cls._SAVED:
            if k == "img" and k not in data:  # checkpoints from before image counts
                data = dict(data, img=np.zeros((len(data["mass"]), 3), np.int64))
            setattr(eng, k, np.array(data[k]))
        if eng.c.shape[0] < core.C_NC_:  # saved before the last two counters
            eng.c = np.concatenate([eng.c, np.zeros(core.C_NC_ - eng.c.shape[0], np.int64)])
        offset, since, rebase_on, radius, box = data["meta"].tolist()
        eng.offset = offset
        eng._since_rebase = int(since)
        eng._rebase_on = bool(rebase_on)
        if "container" in data:
            try:
                eng.container = from_record(data["container"])
            except (ValueError, TypeError):
                raise CheckpointError("damaged checkpoint: no valid container") from None
            params = eng.container.core_params()
            if (params["wall_radius"] != eng.f[core.F_CONTAINER]
                    or params["box"] != eng.f[core.F_BOX]):
                raise CheckpointError("damaged checkpoint: the container disagrees with the "
                                      "core's")
        else:
            eng.container = as_container(None if np.isnan(radius) else radius,
                                         None if np.isnan(box) else box)
        eng.stack = np.zeros(2 * eng.n + 2, np.int64)
        eng._rec = _events.empty_buffers(CHUNK)
        saved = eng.f.shape[0]
        if saved < core.F_NF:  # checkpoints from before the last scalars
            eng.f = np.concatenate([eng.f, np.zeros(core.F_NF - saved)])
        if saved <= core.F_T_KIN:  # before the transport tallies
            eng.f[core.F_T_KIN] = eng.f[core.F_CLOCK]
            core.kinetic_sums(eng.S, eng.mass, eng.f)
        if saved <= core.F_OFFSET:  # before the frozen-clock streak
            eng.f[core.F_OFFSET] = offset
            eng.f[core.F_STREAK] = eng.f[core.F_CLOCK]
        eng.last_reason, eng.last_done = StopReason.UNTIL, 0
        return eng

    # ---- state ------------------------------------------------------------
    def positions_at(self, t: float | None = None, out: np.ndarray | None = None,
                     spheres=None) -> np.ndarray:
        """Centres of all spheres at absolute time ``t`` (default: now) [length].

        In a periodic box the centres are wrapped into the box.  With
        ``spheres`` (indices), only their rows of ``out`` are filled (the
        same bits), in time independent of the number of spheres.
        """
        t = self.time if t is None else t
        out = np.empty((self.n, 3)) if out is None else out
        if spheres is not None and self.box is None:
            t -= self.offset
            for k in spheres:  # a few: Python floats beat numpy's set-up
                x, y, z, vx, vy, vz, tk = self.S[k, :7].tolist()
                dt = t - tk
                out[k] = (x + vx * dt, y + vy * dt, z + vz * dt)
            return out
        core.positions_at(self.S, t - self.offset, out, self.f[core.F_BOX])
        return out

    def unwrapped_at(self, t=None, out=None):
        """Unwrapped centres at absolute time ``t`` (default: now) [length].

        Periodic box: the centre in the box plus ``images * box``, with
        :attr:`img` the exact count of box crossings of each sphere; in a
        spherical container the same as :meth:`positions_at`.
        """
        t = self.time if t is None else t
        out = np.empty((self.n, 3)) if out is None else out
        core.unwrapped_at(self.S, self.img, t - self.offset, out, self.f[core.F_BOX])
        return out

    @property
    def idle(self):
        """Whether nothing will ever happen again (no spheres, or no event or crossing ahead)."""
        return self.n == 0 or not self.HT[0] < np.inf

    @property
    def counters(self) -> dict[str, int]:
        """Dict of event counts: collisions, reflections, crossings, stale
        (predictions dropped), refreshed (made afresh by the window rule)."""
        c = self.c
        return {"collisions": int(c[core.C_COLL]), "reflections": int(c[core.C_WALL]),
                "crossings": int(c[core.C_CROSS]), "stale": int(c[core.C_STALE]),
                "refreshed": int(c[core.C_REFRESHED])}

    def transport_tallies(self, t=None):
        """The transport tallies at absolute time ``t`` (default: now; periodic box).

        Returns:
            dict of arrays: ``virial`` (6,) the collisional virial tensor
            ``sum r_ij dp_i``; ``kinetic`` (6,) ``int sum m v v dt``;
            ``heat_collisional`` (3,) ``sum r_ij dE_i``; ``heat_kinetic``
            (3,) ``int sum v E dt``.  Tensors in the order xx yy zz xy xz yz;
            all summed since the engine was built.
        """
        f = self.f
        dt = (self.time if t is None else t) - self.offset - f[core.F_T_KIN]
        return {"virial": f[core.F_VIR_T:core.F_VIR_T + 6].copy(),
                "kinetic": (f[core.F_KIN_INT:core.F_KIN_INT + 6]
                            + dt * f[core.F_KIN_T:core.F_KIN_T + 6]),
                "heat_collisional": f[core.F_HEAT_COLL:core.F_HEAT_COLL + 3].copy(),
                "heat_kinetic": (f[core.F_HEAT_INT:core.F_HEAT_INT + 3]
                                 + dt * f[core.F_HEAT_KIN:core.F_HEAT_KIN + 3])}

    @property
    def wall_impulse(self) -> float:
        """Total impulse delivered to the container wall [mass*length/time]."""
        return float(self.f[core.F_WALL_IMPULSE])

    @property
    def virial(self) -> float:
        """Sum over collisions of ``r_ij . dp_i`` [mass*length^2/time]."""
        return float(self.f[core.F_VIRIAL])

    # ---- checks -----------------------------------------------------------
    def max_overlap(self, t: float | None = None) -> float:
        """Largest overlap over all pairs, relative to the pair's contact distance."""
        t = self.time if t is None else t
        x = self.positions_at(t)  # pairs across the box compare by minimum image
        g = self.f[core.F_GROW]
        scale = 1.0 + g * (t - self.offset) if g else 1.0
        return float(core.max_overlap(x, self.S, self.K, self.head, self.nxt,
                                      int(self.c[core.C_NC]),
                                      0.0 if self.box is None else self.box, scale))

    def outside(self, t: float | None = None, tol: float = 1e-9) -> int:
        """Number of spheres poking out of the container by more than ``tol`` of its size."""
        return int(np.sum(self.container.outside(self.positions_at(t), self.radii_at(t), tol)))

    def kinetic_energy(self) -> float:
        """Total kinetic energy [mass*length^2/time^2]."""
        return float(kinetic_energy(self.masses, self.velocities))



# ---- checking a checkpoint ------------------------------------------------------
def _bad(what):
    raise CheckpointError(f"damaged checkpoint: {what}")


def _array(data, key, dtype, shape):
    if key not in data:
        _bad(f"no array {key!r}")
    a = np.asarray(data[key])
    if a.dtype != dtype or a.shape != shape:
        _bad(f"{key!r} is {a.dtype}{list(a.shape)}, expected {np.dtype(dtype)}{list(shape)}")
    return a


def check_arrays(data):
    """Check :meth:`Engine.checkpoint`'s arrays before the compiled core sees them.

    Everything the core indexes with is checked (heap, cell lists, partners,
    cell coordinates, counters), and everything it computes with is finite
    where it must be, so that a damaged or crafted file is refused rather
    than crashing the interpreter or running on NaNs.  O(N).

    Args:
        data: mapping of array name to array, as :meth:`Engine.checkpoint`
            returns it (or as read back from a file).

    Raises:
        CheckpointError: naming the first problem found.
    """
    mass = np.asarray(data.get("mass", np.zeros((0, 0))))
    if mass.ndim != 1:
        _bad("'mass' is not a list of masses")
    n = mass.shape[0]
    _array(data, "mass", np.float64, (n,))
    S = _array(data, "S", np.float64, (n, 8))
    K = _array(data, "K", np.int64, (n, core.K_COLS))
    T = _array(data, "T", np.float64, (n, 2))
    nxt = _array(data, "nxt", np.int64, (n,))
    prv = _array(data, "prv", np.int64, (n,))
    heap = _array(data, "heap", np.int64, (n,))
    HT = _array(data, "HT", np.float64, (n,))
    HKEY = _array(data, "HKEY", np.int64, (n,))
    f = np.asarray(data.get("f", np.zeros(0)))
    if f.dtype != np.float64 or f.ndim != 1 or not core.F_WINDOW < f.shape[0] <= core.F_NF:
        _bad(f"'f' is {f.dtype}{list(f.shape)}, expected float64[{core.F_NF}]")
    if "img" in data:  # periodic image counts, where the core keeps them
        _array(data, "img", np.int64, (n, 3))
    if "c" not in data:
        _bad("no array 'c'")
    c = np.asarray(data["c"])
    if c.dtype != np.int64 or c.ndim != 1 or not core.C_SERIAL < c.shape[0] <= core.C_NC_:
        _bad(f"'c' is {c.dtype}{list(c.shape)}, expected int64[{core.C_NC_}]")
    meta = _array(data, "meta", np.float64, (5,))
    nc = int(c[core.C_NC])
    if not 1 <= nc <= 1 << 10:
        _bad(f"{nc} cells per axis")
    head = _array(data, "head", np.int64, (nc ** 3,))
    # the physical state
    if not np.all(np.isfinite(mass) & (mass > 0)):
        _bad("a mass is not a finite number > 0")
    if not np.all(np.isfinite(S)):
        _bad("a position, velocity, time or radius is not finite")
    if np.any(S[:, core.RAD] < 0):
        _bad("a negative radius")
    if np.any(np.isnan(T)) or np.any(np.isnan(HT)):
        _bad("a predicted time is NaN")
    if not np.all(np.isfinite(f)) or f[core.F_W] <= 0 or f[core.F_WINDOW] < 0:
        _bad("the scalars (clock, grid, window) are not finite and positive where needed")
    if np.any(c < 0):
        _bad("a negative counter")
    offset, since, rebase_on, container, box = meta.tolist()
    if not (np.isfinite(offset) and np.isfinite(since) and since >= 0):
        _bad("the time origin is not finite")
    if np.isnan(container) == np.isnan(box):
        _bad("neither or both of container and box")
    size = box if np.isnan(container) else container
    if not (np.isfinite(size) and size > 0):
        _bad("the container size is not a finite number > 0")
    if (f[core.F_BOX] if np.isnan(container) else f[core.F_CONTAINER]) != size:
        _bad("the container size disagrees with the core's")
    if n == 0:
        if np.any(head != -1):
            _bad("cells hold spheres that do not exist")
        return
    ids = np.arange(n)
    # cells: coordinates in the grid, and each cell's list holds exactly its spheres
    cxyz = K[:, core.CX:core.CZ + 1]
    if np.any((cxyz < 0) | (cxyz >= nc)):
        _bad("a cell coordinate outside the grid")
    if np.any(K[:, core.CELL] != (cxyz[:, 2] * nc + cxyz[:, 1]) * nc + cxyz[:, 0]):
        _bad("a cell index disagrees with its coordinates")
    for name, a in (("head", head), ("nxt", nxt), ("prv", prv)):
        if np.any((a < -1) | (a >= n)):
            _bad(f"{name!r} points outside the spheres")
    seen = np.zeros(n, bool)
    for cell in np.nonzero(head >= 0)[0].tolist():
        j, before = int(head[cell]), -1
        while j >= 0:
            if seen[j] or K[j, core.CELL] != cell or prv[j] != before:
                _bad("the cell lists are inconsistent")
            seen[j] = True
            before, j = j, int(nxt[j])
    if not np.all(seen):
        _bad("a sphere is in no cell list")
    # the calendar: a heap over all spheres, each entry its sphere's earlier event
    if not np.array_equal(np.sort(heap), ids) or np.any(K[heap, core.HPOS] != ids):
        _bad("the event calendar is not a permutation of the spheres")
    kind, partner = K[:, core.EV_KIND], K[:, core.EV_PARTNER]
    coll = kind == core.COLLISION
    if np.any(~np.isin(kind, (core.WALL, core.COLLISION, core.NONE))):
        _bad("an unknown event kind")
    if np.any(coll & ((partner < 0) | (partner >= n) | (partner == ids))):
        _bad("a collision partner outside the spheres")
    lo, hi = np.minimum(ids, partner), np.maximum(ids, partner)
    key = np.where(coll, _key(core.COLLISION, lo, hi, n),
                   np.where(kind == core.WALL, _key(core.WALL, ids, -1, n),
                            _key(core.NONE, n, n - 1, n)))
    if np.any(K[:, core.EV_KEY] != key):
        _bad("an event key disagrees with its event")
    code = K[:, core.CR_CODE]
    if np.any((code < -1) | (code >= 6)) or np.any((code == -1) & (T[:, core.CR_T] < np.inf)):
        _bad("an unknown cell crossing")
    cross_key = _key(core.CROSS, ids, -1, n)
    ev_t, cr_t = T[:, core.EV_T], T[:, core.CR_T]
    first = (cr_t < ev_t) | ((cr_t == ev_t) & (cross_key < key))
    if (np.any(HT[K[:, core.HPOS]] != np.where(first, cr_t, ev_t))
            or np.any(HKEY[K[:, core.HPOS]] != np.where(first, cross_key, key))):
        _bad("the event calendar disagrees with the predictions")
    k = np.arange(1, n)
    p = (k - 1) >> 1
    if np.any((HT[k] < HT[p]) | ((HT[k] == HT[p]) & (HKEY[k] < HKEY[p]))):
        _bad("the event calendar is out of order")


def _key(kind, a, b, n):
    """The core's tie key, on arrays (its Python source, not a second copy)."""
    return core._key.py_func(kind, a, b, n)
