"""Trajectories: frames when a trigger says, to GSD or extended XYZ, and back.

The writers here are :class:`hardspheres.writers.Writer` s: append one to
``sim.writers`` and every run writes a frame each ``every`` [time] (or when
its ``trigger`` says: :mod:`hardspheres.writers`), starting with the state
at the time it is attached; the file opens then, and closes on
:meth:`~_FrameWriter.detach` (or at the end of a ``with`` block).

GSD files use the HOOMD schema in double precision (``gsd``'s default,
single precision, keeps only ~7 digits), so OVITO, HOOMD-blue, freud and
MDAnalysis open them; see ``docs/ovito.md``. Per frame:

* ``configuration/step``: the frame's index; ``configuration/box``: the
  periodic box ``[L, L, L, 0, 0, 0]``, or for the spherical container the
  cube ``2R`` that encloses it (not periodic: switch periodicity off in OVITO);
* ``particles/position``, ``particles/velocity`` (float64); in the first
  frame only (readers take later frames' values from it): ``mass``,
  ``diameter`` (twice the radius), one type ``"sphere"``;
* ``log/hardspheres/time`` [time]; ``log/hardspheres/container_radius`` or
  ``log/hardspheres/box_length`` [length]; ``log/hardspheres/names`` (first
  frame: the names, UTF-8, joined by newlines); the events since the
  previous frame, one array per field of
  :data:`~hardspheres.events.EVENT_DTYPE`: ``log/hardspheres/events/time``,
  ``.../kind`` (:class:`~hardspheres.events.EventKind`: 0 reflection,
  1 collision), ``.../i``, ``.../j`` (-1 for a reflection),
  ``.../impulse`` (files written before these read as well: one ``(E, 5)``
  float64 array ``log/hardspheres/events``).

Example:
    >>> import hardspheres as hs, tempfile, os
    >>> from hardspheres.trajectory import GSDWriter, read_trajectory
    >>> sim = hs.Simulation.from_arrays([1.0], [1.0], [[0, 0, 0]], [[1, 0, 0]],
    ...                                 hs.SphericalContainer(3.0))
    >>> path = os.path.join(tempfile.mkdtemp(), "run.gsd")
    >>> with GSDWriter(path, every=1.0) as w:
    ...     sim.writers.append(w)
    ...     _ = sim.run(until=3.0)
    >>> frames = read_trajectory(path)
    >>> frames.times.tolist(), frames.positions[:, 0, 0].tolist()
    ([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 2.0, 1.0])
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from .containers import from_fields
from .events import EVENT_DTYPE, empty_events, from_columns
from .frames import Frames
from .writers import Periodic, Trigger, as_trigger

_GSD_EVENTS = "hardspheres/events"


class _FrameWriter:
    """Frames when its trigger says, from the time it is attached.

    Args:
        every: time between frames [time] (a :class:`~hardspheres.writers.Periodic`
            trigger), or
        trigger: a :class:`~hardspheres.writers.Trigger`.
        events: also keep the events between frames.

    Subclasses write a frame in ``_write_frame(sim, state, events)``, open
    their file and check the simulation once in ``_start(sim)``, and keep
    the open file, if any, in ``_file``.
    """

    _file: Any = None

    def __init__(self, every: float | None = None, events: bool = True, *,
                 trigger: Trigger | None = None) -> None:
        self.trigger = as_trigger(every, trigger)
        self.every = self.trigger.period if isinstance(self.trigger, Periodic) else None
        self.wants_events = bool(events)
        self._started = False
        self._count = 0
        self._events: list[np.ndarray] = []

    @property
    def next_time(self) -> float:
        """When the next frame is due [time] (``inf`` before it is attached)."""
        return self.trigger.next_time if self._started else math.inf

    @property
    def next_collisions(self) -> float:
        """The collision count at which the next frame is due (``inf``: not by count)."""
        return self.trigger.next_collisions if self._started else math.inf

    def _start(self, sim):
        pass

    def attach(self, sim) -> None:
        """Start (once): open the file, start the trigger, write a frame if due now."""
        if not self._started:
            self._start(sim)
            self._started = True
            self.trigger.start(sim.time, sim.counters["collisions"])
            if self.trigger.next_time <= sim.time:
                self.write(sim, sim.time)

    def write(self, sim, t: float) -> None:
        """A frame of ``sim`` at ``t`` (its clock) [time]."""
        self._frame(sim, t)
        self.trigger.fired()

    def detach(self) -> None:
        """Flush and close the file (same as :meth:`close`)."""
        self.close()

    def observe(self, ev):
        if len(ev):
            self._events.append(ev)

    def _take_events(self):
        out = np.concatenate(self._events) if self._events else empty_events()
        self._events = []
        return out

    def _frame(self, sim, t):
        self._write_frame(sim, sim.state(t), self._take_events())
        self._count += 1

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self) -> None:
        """Flush and close the file (further frames are an error)."""
        if self._file is not None:
            self._file.close()
            self._file = None


class GSDWriter(_FrameWriter):
    """Frames to a GSD file (HOOMD schema, double precision).

    Args:
        path: the file (overwritten when the writer is attached).
        every: time between frames [time], or
        trigger: when to write (:mod:`hardspheres.writers`).
        events: also keep the events between frames (``log/hardspheres/events/...``).
    """

    def __init__(self, path: str | os.PathLike, every: float | None = None, events: bool = True,
                 *, trigger: Trigger | None = None) -> None:
        super().__init__(every, events, trigger=trigger)
        import gsd.hoomd  # optional dependency: pip install hardspheres[io]
        self.path = os.fspath(path)
        self._hoomd = gsd.hoomd

    def _start(self, sim):
        self._file = self._hoomd.open(self.path, mode="w", precision="double")

    def _write_frame(self, sim, state, events):
        f = self._hoomd.Frame()
        f.configuration.step = self._count
        c = sim.container
        f.configuration.box = c.gsd_box
        for key, value in c.fields().items():
            f.log[f"hardspheres/{key}"] = np.array([value])
        f.particles.N = state.n
        f.particles.position = state.positions
        f.particles.velocity = state.velocities
        if self._count == 0:
            f.particles.types = ["sphere"]
            f.particles.typeid = np.zeros(state.n, dtype=np.uint32)
            f.particles.mass = state.masses
            f.particles.diameter = 2.0 * state.radii
            f.log["hardspheres/names"] = np.frombuffer(
                "\n".join(state.names).encode("utf-8"), dtype=np.uint8)
        f.log["hardspheres/time"] = np.array([state.time])
        if self.wants_events:
            for name in EVENT_DTYPE.names:
                f.log[f"{_GSD_EVENTS}/{name}"] = np.ascontiguousarray(events[name])
        self._file.append(f)
        self._file.flush()


class XYZWriter(_FrameWriter):
    """Frames to an extended XYZ file (plain text, every digit kept).

    Each frame is ``N``, a comment line with ``Lattice``, ``Origin``,
    ``pbc``, ``Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1``,
    ``Time`` and ``container_radius`` (or ``box_length``), then one line per
    sphere with its numbers as ``%.17g`` (they read back exactly). Names may
    not contain whitespace or quotes here. Events are not written.

    Args:
        path: the file (overwritten when the writer is attached).
        every: time between frames [time], or
        trigger: when to write (:mod:`hardspheres.writers`).
    """

    def __init__(self, path: str | os.PathLike, every: float | None = None, *,
                 trigger: Trigger | None = None) -> None:
        super().__init__(every, events=False, trigger=trigger)
        self.path = os.fspath(path)

    def _start(self, sim):
        bad = [n for n in sim.names if not n or any(ch.isspace() or ch in "\"'" for ch in n)]
        if bad:
            raise ValueError(f"sphere name {bad[0]!r} cannot be written to XYZ "
                             "(whitespace or quotes); use GSD")
        self._file = open(self.path, "w", encoding="utf-8", newline="\n")

    def _write_frame(self, sim, state, events):
        c = sim.container
        side = 2.0 * c.half_width
        pbc = "T T T" if c.periodic else "F F F"
        size = " ".join(f"{k}={v!r}" for k, v in c.fields().items())
        h = side / 2.0
        header = (f'{state.n}\nLattice="{side!r} 0 0 0 {side!r} 0 0 0 {side!r}" '
                  f'Origin="{-h!r} {-h!r} {-h!r}" pbc="{pbc}" '
                  "Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1 "
                  f"Time={state.time!r} {size}\n")
        fh = self._file
        fh.write(header)
        if state.n:
            nums = np.column_stack([state.positions, state.velocities,
                                    state.radii, state.masses])
            rows = ("%.17g " * 8).rstrip()
            fh.write("\n".join(f"{name} {rows % tuple(r)}"
                               for name, r in zip(state.names, nums.tolist())))
            fh.write("\n")
        fh.flush()


def _gsd_events(log):
    """A GSD frame's events, or ``None`` if it has none."""
    if f"{_GSD_EVENTS}/time" in log:
        return from_columns(**{name: log[f"{_GSD_EVENTS}/{name}"] for name in EVENT_DTYPE.names
                               if f"{_GSD_EVENTS}/{name}" in log})
    if _GSD_EVENTS in log:  # files before one array per field: (E, 5) float64
        old = np.asarray(log[_GSD_EVENTS], np.float64).reshape(-1, 5)
        return from_columns(time=old[:, 0], kind=old[:, 1], i=old[:, 2], j=old[:, 3],
                            impulse=old[:, 4])
    return None


def _concat(blocks):
    return np.concatenate(blocks) if blocks else empty_events()


# ---- reading -------------------------------------------------------------------
def read_trajectory(path: str | os.PathLike) -> Frames:
    """Read a trajectory written by :class:`GSDWriter` or :class:`XYZWriter`.

    Returns:
        :class:`hardspheres.frames.Frames`.

    Raises:
        ValueError: the file is not such a trajectory (the message says why).
    """
    path = os.fspath(path)
    if path.endswith(".gsd"):
        return _read_gsd(path)
    if path.endswith((".xyz", ".extxyz")):
        return _read_xyz(path)
    raise ValueError(f"{path}: not a trajectory (use a .gsd or .xyz file)")


def _read_gsd(path):
    import gsd.hoomd
    try:
        traj = gsd.hoomd.open(path, mode="r")
    except (OSError, RuntimeError) as e:
        raise ValueError(f"{path}: cannot read as GSD ({e})") from None
    with traj:
        if len(traj) == 0:
            raise ValueError(f"{path}: no frames")
        first = traj[0]
        log = first.log
        if "hardspheres/time" not in log:
            raise ValueError(f"{path}: not written by hardspheres (no log/hardspheres/time)")
        n = int(first.particles.N)
        raw = bytes(np.asarray(log.get("hardspheres/names", np.zeros(0, np.uint8)),
                               dtype=np.uint8))
        names = raw.decode("utf-8").split("\n") if n else []
        if len(names) != n:
            names = [f"s{i}" for i in range(n)]
        container = from_fields(log)
        times, pos, vel, events = [], [], [], []
        for f in traj:
            times.append(float(f.log["hardspheres/time"][0]))
            pos.append(np.asarray(f.particles.position, dtype=np.float64).reshape(n, 3))
            vel.append(np.asarray(f.particles.velocity, dtype=np.float64).reshape(n, 3))
            ev = _gsd_events(f.log)
            if ev is not None:
                events.append(ev)
        return Frames(np.array(times), np.array(pos).reshape(-1, n, 3),
                      np.array(vel).reshape(-1, n, 3),
                      np.asarray(first.particles.diameter, np.float64) / 2.0,
                      np.asarray(first.particles.mass, np.float64).copy(), names,
                      container=container, events=_concat(events))


def _xyz_keys(comment):
    import shlex
    out = {}
    for tok in shlex.split(comment):
        if "=" in tok:
            k, v = tok.split("=", 1)
            out[k] = v
    return out


def _read_xyz(path):
    times, pos, vel, names, radii, masses = [], [], [], None, None, None
    container = None
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().split("\n")
    k = 0
    try:
        while k < len(lines) and lines[k].strip():
            n = int(lines[k])
            keys = _xyz_keys(lines[k + 1])
            times.append(float(keys["Time"]))
            container = from_fields(keys)
            rows = [ln.split() for ln in lines[k + 2:k + 2 + n]]
            if len(rows) != n or any(len(r) != 9 for r in rows):
                raise ValueError("frame shorter than its atom count")
            nums = np.array([r[1:] for r in rows], dtype=np.float64).reshape(n, 8)
            pos.append(nums[:, 0:3])
            vel.append(nums[:, 3:6])
            if names is None:
                names = [r[0] for r in rows]
                radii, masses = nums[:, 6].copy(), nums[:, 7].copy()
            k += 2 + n
    except (ValueError, KeyError, IndexError) as e:
        raise ValueError(f"{path}: not an XYZ trajectory of hardspheres "
                         f"(near line {k + 1}: {e})") from None
    if not times:
        raise ValueError(f"{path}: no frames")
    n = len(names)
    return Frames(np.array(times), np.array(pos).reshape(-1, n, 3),
                  np.array(vel).reshape(-1, n, 3), radii, masses, names,
                  container=container)


# ---- in memory -------------------------------------------------------------------
class FrameRecorder(_FrameWriter):
    """Keeps frames in memory; :meth:`frames` returns them as :class:`Frames`."""

    def __init__(self, every: float | None = None, events: bool = True, *,
                 trigger: Trigger | None = None) -> None:
        super().__init__(every, events, trigger=trigger)
        self._times: list[float] = []
        self._pos: list[np.ndarray] = []
        self._vel: list[np.ndarray] = []
        self._ev: list[np.ndarray] = []

    def _start(self, sim):
        self._sim = sim

    def _write_frame(self, sim, state, events):
        self._times.append(state.time)
        self._pos.append(state.positions)
        self._vel.append(state.velocities)
        self._ev.append(events)
        self._state = state

    def frames(self):
        """The frames recorded so far."""
        sim, st = self._sim, self._state
        n = st.n
        return Frames(np.array(self._times), np.array(self._pos).reshape(-1, n, 3),
                      np.array(self._vel).reshape(-1, n, 3), st.radii.copy(),
                      st.masses.copy(), list(st.names), container=sim.container,
                      events=_concat(self._ev))


def frames_from_simulation(sim, until: float, every: float) -> Frames:
    """Run ``sim`` to ``until`` [time], keeping a frame every ``every`` [time].

    Returns:
        :class:`hardspheres.frames.Frames` (the first frame is the state at
        the start, the last at ``until``).
    """
    rec = FrameRecorder(every)
    sim.writers.append(rec)
    try:
        sim.run(until=until)
    finally:
        sim.writers.remove(rec)
    if until - rec._times[-1] > 1e-9 * every:  # off the grid: end on `until`
        rec.write(sim, sim.time)
    return rec.frames()
