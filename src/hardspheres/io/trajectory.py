"""Trajectories: frames when a trigger says, to GSD or extended XYZ, and back.

The writers here are :class:`hardspheres.writers.Writer` s: append one to
``sim.writers`` and every run writes a frame each ``every`` [time] (or when
its ``trigger`` says: :mod:`hardspheres.writers`), starting with the state
at the time it is attached; :meth:`~_FrameWriter.detach` (or the end of a
``with`` block) closes the file.

GSD files use the HOOMD schema in double precision (``gsd``'s default,
single precision, keeps only ~7 digits), so OVITO, HOOMD-blue, freud and
MDAnalysis open them; see ``docs/ovito.md``. Per frame:

* ``configuration/step``: the frame's index; ``configuration/box``: the
  periodic box ``[L, L, L, 0, 0, 0]``, or for the spherical container the
  cube ``2R`` that encloses it (not periodic: switch periodicity off in OVITO);
* ``particles/position``, ``particles/velocity`` (float64);
  ``particles/image`` (periodic box: the exact count of box crossings, so
  ``position + image * L`` is the unwrapped centre; ``log/hardspheres/images``
  in the first frame says the file has them); in the first
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
  float64 array ``log/hardspheres/events``);
* a sheared box (Lees-Edwards): ``log/hardspheres/shear_rate`` [1/time] and
  ``log/hardspheres/shear_offset`` [length], the offset at the frame's time
  (how far along x the images above the box are ahead of it, in
  ``[0, L_x)``; HOOMD's schema has no such field); in XYZ files
  ``shear_rate=`` and ``shear_offset=`` in each frame's comment line.

Example:
    >>> import hardspheres as hs, tempfile, os
    >>> from hardspheres.io.trajectory import GSDWriter, read_trajectory
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
import warnings
from collections.abc import Mapping
from typing import IO, TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from ..containers import Container, PeriodicBox, from_fields
from ..errors import NotAContinuation, TruncatedTrajectory  # noqa: F401 (re-exported)
from ..errors import ArgumentError, TrajectoryError
from ..events import EVENT_DTYPE, empty_events, from_columns
from ..fileio import PathLock
from ..frames import Frames
from ..writers import Periodic, Trigger, as_trigger

if TYPE_CHECKING:
    from typing_extensions import Self

    from ..simulation import Simulation
    from ..state import State
    from ..writers import SimulationView

_GSD_EVENTS = "hardspheres/events"


class _FrameWriter:
    """Frames when its trigger says, from the time it is attached.

    Args:
        every: time between frames [time] (a :class:`~hardspheres.writers.Periodic`
            trigger), or
        trigger: a :class:`~hardspheres.writers.Trigger`.
        events: also keep the events between frames.

    Subclasses write a frame in ``_write_frame(sim, state, events)``, open
    their file ``path``, if any, in ``_open_file()`` (called locked, when
    the writer is first attached; kept in ``_file``, ``_append`` says
    whether to append), and may check the simulation once in ``_start(sim)``.  ``_count`` is the
    index of the next frame in the file; ``_k`` the number of frames this
    writer has written (in an appended file the first, already there, is
    not written again).  ``last_time`` is the time of the last frame in the
    file [time].
    """

    _file: Any = None
    _lock: Any = None
    _append_wanted = False
    _append = False
    _closed = False
    _failed = False
    path: Any = None
    #: The end time [time] recorded in each frame (``log/hardspheres/run_end``):
    #: ``None`` takes each ``run(until=...)``'s; a driver that runs in pieces
    #: (``hardspheres run``) sets its final end here.
    until: float | None = None

    def __init__(
        self, every: float | None = None, events: bool = True, *, trigger: Trigger | None = None
    ) -> None:
        self.trigger = as_trigger(every, trigger)
        self.every = self.trigger.period if isinstance(self.trigger, Periodic) else None
        self.wants_events = bool(events)
        self.last_time: float | None = None
        self._started = False
        self._count = 0
        self._k = 0
        self._events: list[np.ndarray] = []
        self._run_end = (math.inf, math.inf)

    @property
    def next_time(self) -> float:
        """When the next frame is due [time] (``inf`` before it is attached)."""
        return self.trigger.next_time if self._started else math.inf

    @property
    def next_collisions(self) -> float:
        """The collision count at which the next frame is due (``inf`` when not by count)."""
        return self.trigger.next_collisions if self._started else math.inf

    def _open(self) -> None:
        """Lock the file and open it (:meth:`_open_file`), appending if asked and it exists."""
        if self.path is None:
            return
        self._take_lock(self.path)
        self._append = self._append_wanted and os.path.exists(self.path)
        try:
            self._file = self._open_file()
        except BaseException:
            self.close()
            raise

    def _open_file(self) -> Any:
        """Open ``path`` (locked; appending if ``_append``); subclasses that have a file define it."""
        raise NotImplementedError

    def _write_frame(self, sim: SimulationView, state: State, events: np.ndarray) -> None:
        """Write one frame: ``state`` and the ``events`` since the last; subclasses define it."""
        raise NotImplementedError

    def _start(self, sim: SimulationView) -> bool:
        """Get ready for the first frame; returns whether the file continues a run (its last frame is now)."""
        return False

    def _check_open(self) -> None:
        if self._closed:
            raise TrajectoryError(
                f"{type(self).__name__}({self.path or ''!r}) is closed; "
                "open a new writer to write more frames"
            )

    def attach(self, sim: SimulationView) -> None:
        """Start (once): open the file, start the trigger, write a frame if it is due now.

        Raises:
            FileInUseError: another writer holds the file.
            OSError: naming the file.
            NotAContinuation: ``append`` to a file that ends elsewhere.
        """
        self._check_open()
        if not self._started:
            if self._file is None:
                self._open()
            self._started = True
            self.trigger.start(sim.time, sim.counters["collisions"])
            if self._start(sim):
                self._k = 1  # the file's last frame is this one
                self.trigger.fired()
            elif self.trigger.next_time <= sim.time:
                self._frame(sim, sim.time)

    def write(self, sim: SimulationView, t: float) -> None:
        """A frame of ``sim`` at ``t`` (its clock) [time]."""
        self._frame(sim, t)

    def detach(self) -> None:
        """Flush and close the file and release its lock (same as :meth:`close`)."""
        self.close()

    def observe(self, ev: np.ndarray) -> None:
        if len(ev):
            self._events.append(ev)

    def _take_events(self) -> np.ndarray:
        out = np.concatenate(self._events) if self._events else empty_events()
        self._events = []
        return out

    def _frame(self, sim: SimulationView, t: float) -> None:
        self._check_open()
        until = self.until if self.until is not None else sim.run_end
        self.trigger.fired()
        self._run_end = (float(until), self.trigger.next_time)
        try:
            self._write_frame(sim, sim.state(t), self._take_events())
        except OSError as e:
            self._failed = True
            if self.path is not None and e.filename is None:
                raise type(e)(e.errno, e.strerror, self.path) from None
            raise
        self._count += 1
        self._k += 1
        self.last_time = t

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc: object) -> Literal[False]:
        self.close()
        return False

    def close(self) -> None:
        """Flush and close the file and release its lock (further frames are an error).

        Raises:
            OSError: naming the file, if the last data cannot be written
                (not raised again after a failed frame).
        """
        self._closed = True
        try:
            if self._file is not None:
                fh, self._file = self._file, None
                try:
                    fh.close()
                except OSError as e:
                    if not self._failed:
                        if e.filename is None:
                            raise type(e)(e.errno, e.strerror, self.path) from None
                        raise
        finally:
            if self._lock is not None:
                self._lock.release()
                self._lock = None

    def _take_lock(self, path: str) -> None:
        """Lock ``path`` for this writer, or raise (:class:`PathLock`)."""
        self._lock = PathLock(os.fspath(path))


def _continues(path: str, last: dict[str, Any], sim: SimulationView) -> None:
    """Raise unless the frame ``last`` of ``path`` is where ``sim`` is now."""
    same = (
        last["time"] == sim.time
        and last["n"] == sim.n
        and last["names"] == sim.names
        and last["container"] == sim.container
    )
    if not same:
        raise NotAContinuation(
            f"{path} does not end where this simulation is (it ends at t={last['time']!r} "
            f"with {last['n']} spheres; the simulation is at t={sim.time!r} with {sim.n}): "
            "it belongs to another run; write to another file"
        )


class GSDWriter(_FrameWriter):
    """Frames to a GSD file (HOOMD schema, double precision).

    Args:
        path: the file (overwritten, unless ``append``).
        every: time between frames [time], or
        trigger: when to write (:mod:`hardspheres.writers`).
        events: also keep the events between frames (``log/hardspheres/events/...``).
        append: continue an existing file written by an earlier part of the
            same run (checked when the writer is attached); a missing
            file is created.

    The file is opened (and locked) when the writer is first attached to
    a simulation (:meth:`attach`), not when it is made.

    Raises:
        MissingExtraError: ``gsd`` is not installed (``pip install "hardspheres[io]"``).
    """

    def __init__(
        self,
        path: str | os.PathLike,
        every: float | None = None,
        events: bool = True,
        append: bool = False,
        *,
        trigger: Trigger | None = None,
    ) -> None:
        super().__init__(every, events, trigger=trigger)
        from ..extras import need

        self._hoomd = need("gsd.hoomd", "GSDWriter")
        self.path = os.fspath(path)
        self._append_wanted = bool(append)

    def _open_file(self) -> Any:
        try:
            fh = self._hoomd.open(self.path, mode="r+" if self._append else "w", precision="double")
        except (OSError, RuntimeError) as e:
            if isinstance(e, OSError) and e.filename is not None:
                raise
            raise TrajectoryError(f"{self.path}: cannot open as GSD ({e})") from None
        self._count = len(fh) if self._append else 0
        return fh

    def _start(self, sim: SimulationView) -> bool:
        if not self._append or self._count == 0:
            return False
        try:
            last = _gsd_last(self._file)
        except (KeyError, IndexError, ValueError) as e:
            raise TrajectoryError(
                f"{self.path}: not a hardspheres trajectory ({e}); write to another file"
            ) from None
        _continues(self.path, last, sim)
        self.last_time = last["time"]
        return True

    def _write_frame(self, sim: SimulationView, state: State, events: np.ndarray) -> None:
        f = self._hoomd.Frame()
        f.configuration.step = self._count
        c = sim.container
        f.configuration.box = c.gsd_box
        for key, value in c.fields().items():
            f.log[f"hardspheres/{key}"] = np.array([value])
        f.particles.N = state.n
        if getattr(c, "dimensions", 3) == 2:  # as HOOMD writes 2-D: dimensions 2, z = 0, Lz = 0
            f.configuration.dimensions = 2
        f.particles.position = _three(state.positions)
        f.particles.velocity = _three(state.velocities)
        if state.images is not None:
            f.particles.image = _three(state.images).astype(np.int32)
            if self._count == 0:  # marks files that carry images (all zero is not stored)
                f.log["hardspheres/images"] = np.array([1], np.int8)
        if self._count == 0:
            f.particles.types = ["sphere"]
            f.particles.typeid = np.zeros(state.n, dtype=np.uint32)
            f.particles.mass = state.masses
            f.particles.diameter = 2.0 * state.radii
            f.log["hardspheres/names"] = np.frombuffer("\n".join(state.names).encode("utf-8"), dtype=np.uint8)
        f.log["hardspheres/time"] = np.array([state.time])
        f.log["hardspheres/run_end"] = np.array(self._run_end)
        if getattr(c, "shear_rate", 0.0):  # (HOOMD's schema has no Lees-Edwards offset)
            f.log["hardspheres/shear_offset"] = np.array([sim.engine.shear_offset(state.time)])
        if self.wants_events:
            for name in EVENT_DTYPE.names or ():
                f.log[f"{_GSD_EVENTS}/{name}"] = np.ascontiguousarray(events[name])
        self._file.append(f)
        self._file.flush()


class XYZWriter(_FrameWriter):
    """Frames to an extended XYZ file (plain text, every digit kept).

    Each frame is ``N``, a comment line with ``Lattice``, ``Origin``,
    ``pbc``, ``Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1``
    (in a periodic box followed by ``:image:I:3``, the exact counts of box
    crossings, so ``pos + image * L`` is the unwrapped centre, as GSD's
    ``particles/image``), ``Time`` and ``container_radius`` (or
    ``box_length``), then one line per sphere with its numbers as ``%.17g``
    (they read back exactly). Names may not contain whitespace or quotes
    here. Events are not written. Files written before the image columns
    read as well (their frames have no images).

    Args:
        path: the file (overwritten, unless ``append``).
        every: time between frames [time], or
        trigger: when to write (:mod:`hardspheres.writers`).
        append: continue an existing file written by an earlier part of the
            same run (checked when the writer is attached).

    The file is opened (and locked) when the writer is first attached to
    a simulation (:meth:`attach`), not when it is made.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        every: float | None = None,
        append: bool = False,
        *,
        trigger: Trigger | None = None,
    ) -> None:
        super().__init__(every, events=False, trigger=trigger)
        self.path = os.fspath(path)
        self._append_wanted = bool(append)

    def _open_file(self) -> IO[str]:
        return open(self.path, "a" if self._append else "w", encoding="utf-8", newline="\n")

    def _start(self, sim: SimulationView) -> bool:
        from ..messages import quote

        bad = [n for n in sim.names if not n or any(ch.isspace() or ch in "\"'" for ch in n)]
        if bad:
            raise TrajectoryError(
                f"sphere name {quote(bad[0])} cannot be written to XYZ (whitespace or quotes); use GSD"
            )
        if not self._append or os.path.getsize(self.path) == 0:
            return False
        old = _read_xyz(self.path, check_end=False)
        self._count = len(old.times)
        _continues(
            self.path,
            {"time": float(old.times[-1]), "n": old.n, "names": list(old.names), "container": old.container},
            sim,
        )
        self.last_time = float(old.times[-1])
        return True

    def _write_frame(self, sim: SimulationView, state: State, events: np.ndarray) -> None:
        c = sim.container
        x, y, z = c.gsd_box[:3]  # (a spherical container: its enclosing cube)
        pbc = "T T T" if c.periodic else "F F F"
        size = " ".join(f"{k}={v!r}" for k, v in c.fields().items())
        if getattr(c, "shear_rate", 0.0):  # a sheared box: the images' offset at the frame's time
            size += f" shear_offset={sim.engine.shear_offset(state.time)!r}"
        images = state.images
        props = _XYZ_PROPS + (_XYZ_IMAGE if images is not None else "")
        header = (
            f'{state.n}\nLattice="{x!r} 0 0 0 {y!r} 0 0 0 {z!r}" '
            f'Origin="{-x / 2.0!r} {-y / 2.0!r} {-z / 2.0!r}" pbc="{pbc}" Properties={props} '
            f"Time={state.time!r} {size} "
            f'run_end="{self._run_end[0]!r} {self._run_end[1]!r}"\n'
        )
        fh = self._file
        fh.write(header)
        if state.n:
            p3, v3 = _three(state.positions), _three(state.velocities)
            nums = np.column_stack([p3, v3, state.radii, state.masses])
            rows = ("%.17g " * 8).rstrip()
            lines = [f"{name} {rows % tuple(r)}" for name, r in zip(state.names, nums.tolist())]
            if images is not None:
                rows3 = _three(np.asarray(images)).astype(np.int64).tolist()
                lines = [f"{line} {a} {b} {c}" for line, (a, b, c) in zip(lines, rows3)]
            fh.write("\n".join(lines))
            fh.write("\n")
        fh.flush()


#: The XYZ columns after the name: 8 numbers, then (periodic box) 3 image counts.
_XYZ_PROPS = "name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1"
_XYZ_IMAGE = ":image:I:3"


def _gsd_events(log: Mapping[str, Any]) -> np.ndarray | None:
    """A GSD frame's events, or ``None`` if it has none."""
    if f"{_GSD_EVENTS}/time" in log:
        return from_columns(
            **{
                name: log[f"{_GSD_EVENTS}/{name}"]
                for name in EVENT_DTYPE.names or ()
                if f"{_GSD_EVENTS}/{name}" in log
            }
        )
    if _GSD_EVENTS in log:  # files before one array per field: (E, 5) float64
        old = np.asarray(log[_GSD_EVENTS], np.float64).reshape(-1, 5)
        return from_columns(time=old[:, 0], kind=old[:, 1], i=old[:, 2], j=old[:, 3], impulse=old[:, 4])
    return None


def _concat(blocks: list[np.ndarray]) -> np.ndarray:
    return np.concatenate(blocks) if blocks else empty_events()


# ---- reading -------------------------------------------------------------------
def read_trajectory(path: str | os.PathLike) -> Frames:
    """Read a trajectory written by :class:`GSDWriter` or :class:`XYZWriter`.

    Warns :class:`TruncatedTrajectory` (one line: the file, where it ends
    and where its run meant to end) if the file was cut short.

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
    raise TrajectoryError(f"{path}: not a trajectory (use a .gsd or .xyz file)")


#: The shapes of HOOMD-blue's ``particles/type_shapes`` that are spheres (3-D) or disks (2-D).
ROUND_SHAPES = ("Sphere", "Disk")


def _hoomd_radii(path: str, traj: Any) -> np.ndarray:
    """``(N,)`` radii of a HOOMD-blue file's first frame: its spheres' or disks' diameters over 2.

    HPMC's ``particles/type_shapes`` (``{"type": "Sphere", "diameter": d}``
    per type) decide when given: they are the shapes it simulated.  Else
    ``particles/diameter``, which defaults to 1 (as in HOOMD-blue).
    """
    import json

    first = traj[0]
    n = int(first.particles.N)
    shapes = [s if isinstance(s, dict) else json.loads(s) for s in (first.particles.type_shapes or [])]
    types = list(first.particles.types or [])
    for k, shape in enumerate(shapes):
        kind = shape.get("type", "?") if shape else "?"
        if shape and kind not in ROUND_SHAPES:
            name = types[k] if k < len(types) else str(k)
            raise TrajectoryError(
                f"{path}: particles of type {name!r} are a {kind} (particles/type_shapes); "
                "hardspheres reads spheres and disks only"
            )
    typeid = np.asarray(first.particles.typeid, np.int64).reshape(n)
    if shapes and all(s and "diameter" in s for s in shapes) and (n == 0 or typeid.max() < len(shapes)):
        return np.array([float(s["diameter"]) for s in shapes])[typeid] / 2.0
    return np.asarray(first.particles.diameter, np.float64).reshape(n) / 2.0


def read_hoomd(path: str, traj: Any) -> Frames:
    """Frames of a GSD file written by HOOMD-blue (or any writer of its schema), open as ``traj``.

    Read: ``configuration/box`` (a rectangular periodic box),
    ``configuration/dimensions`` (2: disks), ``configuration/step`` (the
    frames' times, in steps; the frame index if they do not increase),
    ``particles/position``, ``velocity`` (0 by default, as HPMC writes
    none: :meth:`hardspheres.Frames.state` then draws them),
    ``image`` (when a frame after the first has it, i.e. the writer
    recorded it per frame: unwrapped positions for the correlators),
    ``mass`` and the radii of :func:`_hoomd_radii` (diameter 1 by default).

    Raises:
        TrajectoryError: what cannot be read, named: a triclinic box (tilt
            factors), non-spherical shapes, a box or a particle count that
            changes between frames.
    """
    first = traj[0]
    n = int(first.particles.N)
    dim = int(first.configuration.dimensions or 3)
    box = np.asarray(first.configuration.box, np.float64).reshape(6)
    if np.any(box[3:] != 0.0):
        raise TrajectoryError(
            f"{path}: a triclinic box (tilt factors xy, xz, yz = {', '.join(f'{x:g}' for x in box[3:])}); "
            "hardspheres reads rectangular boxes only"
        )
    sides = box[:dim]
    if dim not in (2, 3) or not np.all(np.isfinite(sides) & (sides > 0)):
        raise TrajectoryError(f"{path}: configuration/box {box.tolist()} in {dim} dimensions is not a box")
    radii = _hoomd_radii(path, traj)
    # images: a frame without the chunk repeats frame 0's, which HOOMD-blue's writer also does
    # when it does not record them (``dynamic`` without "momentum"): trusted only when a later
    # frame has them (or there is one frame)
    stored = [bool(traj.file.chunk_exists(frame=k, name="particles/image")) for k in range(len(traj))]
    has_images = any(stored[1:]) or stored == [True]
    times, pos, vel, images = [], [], [], []
    for k, f in enumerate(traj):
        if int(f.particles.N) != n or not np.array_equal(np.asarray(f.configuration.box, np.float64), box):
            what = "particle count" if int(f.particles.N) != n else "box"
            raise TrajectoryError(
                f"{path}: the {what} changes at frame {k}; hardspheres reads a fixed box of fixed particles"
            )
        times.append(float(f.configuration.step))
        pos.append(np.asarray(f.particles.position, np.float64).reshape(n, 3)[:, :dim])
        vel.append(np.asarray(f.particles.velocity, np.float64).reshape(n, 3)[:, :dim])
        images.append(np.asarray(f.particles.image, np.int64).reshape(n, 3)[:, :dim])
    t = np.array(times)
    if len(t) > 1 and np.any(np.diff(t) <= 0):
        t = np.arange(len(t), dtype=np.float64)
    return Frames(
        t,
        np.array(pos).reshape(-1, n, dim),
        np.array(vel).reshape(-1, n, dim),
        radii,
        np.asarray(first.particles.mass, np.float64).reshape(n).copy(),
        [f"p{i}" for i in range(n)],
        container=PeriodicBox(tuple(float(s) for s in sides)),
        images=np.array(images).reshape(-1, n, dim) if has_images else None,
    )


def _warn_if_cut(path: str, last_time: float, run_end: Any) -> None:
    """Warn if the run that wrote the last frame had another frame due before its end."""
    try:
        until, due = (float(x) for x in run_end)
    except (TypeError, ValueError):
        return  # not ours to judge
    if due <= until and last_time < until:
        warnings.warn(
            f"{path} ends at t={last_time!r}, but the run writing it was to reach "
            f"t={until!r} (next frame due at t={due!r}): the file was cut short "
            "(disk full, run killed or interrupted)",
            TruncatedTrajectory,
            stacklevel=3,
        )


def _gsd_last(traj: Any) -> dict[str, Any]:
    """What :func:`_continues` compares, from the last frame of an open GSD file."""
    first, last = traj[0], traj[len(traj) - 1]
    n = int(first.particles.N)
    raw = bytes(np.asarray(first.log.get("hardspheres/names", np.zeros(0, np.uint8)), dtype=np.uint8))
    names = raw.decode("utf-8").split("\n") if n else []
    log = last.log
    return {
        "time": float(log["hardspheres/time"][0]),
        "n": int(last.particles.N),
        "names": names,
        "container": from_fields(log),
    }


def _read_gsd(path: str) -> Frames:
    from ..extras import need

    gsd_hoomd = need("gsd.hoomd", f"reading {path}")
    try:
        traj = gsd_hoomd.open(path, mode="r")
    except (OSError, RuntimeError) as e:
        raise TrajectoryError(f"{path}: cannot read as GSD ({e}); give a complete .gsd file") from None
    with traj:
        if len(traj) == 0:
            raise TrajectoryError(f"{path}: no frames; read a trajectory its run wrote frames to")
        first = traj[0]
        log = first.log
        if "hardspheres/time" not in log:
            return read_hoomd(path, traj)
        n = int(first.particles.N)
        raw = bytes(np.asarray(log.get("hardspheres/names", np.zeros(0, np.uint8)), dtype=np.uint8))
        names = raw.decode("utf-8").split("\n") if n else []
        if len(names) != n:
            names = [f"s{i}" for i in range(n)]
        container = from_fields(log)
        times, pos, vel, events, images = [], [], [], [], []
        for f in traj:
            times.append(float(f.log["hardspheres/time"][0]))
            pos.append(np.asarray(f.particles.position, dtype=np.float64).reshape(n, 3))
            vel.append(np.asarray(f.particles.velocity, dtype=np.float64).reshape(n, 3))
            images.append(np.asarray(f.particles.image, dtype=np.int64).reshape(n, 3))
            ev = _gsd_events(f.log)
            if ev is not None:
                events.append(ev)
            run_end = f.log.get("hardspheres/run_end")
        if run_end is not None and len(run_end) == 2:
            _warn_if_cut(path, times[-1], run_end)
        d = getattr(container, "dimensions", 3)
        return Frames(
            np.array(times),
            np.array(pos).reshape(-1, n, 3)[..., :d],
            np.array(vel).reshape(-1, n, 3)[..., :d],
            np.asarray(first.particles.diameter, np.float64) / 2.0,
            np.asarray(first.particles.mass, np.float64).copy(),
            names,
            container=container,
            events=_concat(events),
            images=(
                np.array(images).reshape(-1, n, 3)[..., :d]
                if container.periodic and "hardspheres/images" in log
                else None
            ),
        )


def _xyz_keys(comment: str) -> dict[str, str]:
    import shlex

    out = {}
    for tok in shlex.split(comment):
        if "=" in tok:
            k, v = tok.split("=", 1)
            out[k] = v
    return out


def _read_xyz(path: str, check_end: bool = True) -> Frames:
    times: list[float] = []
    pos: list[np.ndarray] = []
    vel: list[np.ndarray] = []
    images: list[np.ndarray | None] = []
    names: list[str] | None = None
    radii: np.ndarray | None = None
    masses: np.ndarray | None = None
    run_end = None
    container: Container | None = None
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().split("\n")
    k = 0
    try:
        while k < len(lines) and lines[k].strip():
            n = int(lines[k])
            keys = _xyz_keys(lines[k + 1])
            times.append(float(keys["Time"]))
            run_end = keys["run_end"].split() if "run_end" in keys else None
            container = from_fields(keys)
            props = keys.get("Properties", _XYZ_PROPS)
            if props not in (_XYZ_PROPS, _XYZ_PROPS + _XYZ_IMAGE):
                raise TrajectoryError(f"unknown columns Properties={props}")
            cols = 12 if props.endswith(_XYZ_IMAGE) else 9
            rows = [ln.split() for ln in lines[k + 2 : k + 2 + n]]
            if len(rows) != n or any(len(r) != cols for r in rows):
                raise TrajectoryError(
                    f"frame shorter than its atom count, or a line without its {cols} columns"
                )
            nums = np.array([r[1:9] for r in rows], dtype=np.float64).reshape(n, 8)
            pos.append(nums[:, 0:3])
            vel.append(nums[:, 3:6])
            images.append(
                np.array([r[9:] for r in rows], dtype=np.int64).reshape(n, 3) if cols == 12 else None
            )
            if names is None:
                names = [r[0] for r in rows]
                radii, masses = nums[:, 6].copy(), nums[:, 7].copy()
            k += 2 + n
    except (ValueError, KeyError, IndexError) as e:
        raise TrajectoryError(
            f"{path}: not an XYZ trajectory of hardspheres (near line {k + 1}: {e}); "
            "read a file XYZWriter wrote"
        ) from None
    if not times:
        raise TrajectoryError(f"{path}: no frames; read a trajectory its run wrote frames to")
    # set with the first frame
    assert names is not None and radii is not None and masses is not None and container is not None
    if check_end and run_end is not None and len(run_end) == 2:
        _warn_if_cut(path, times[-1], run_end)
    n = len(names)
    has_images = container.periodic and all(im is not None for im in images)
    d = getattr(container, "dimensions", 3)
    return Frames(
        np.array(times),
        np.array(pos).reshape(-1, n, 3)[..., :d],
        np.array(vel).reshape(-1, n, 3)[..., :d],
        radii,
        masses,
        names,
        container=container,
        images=np.array(images).reshape(-1, n, 3)[..., :d] if has_images else None,
    )


def _three(a: ArrayLike) -> np.ndarray:
    """``(N, d)`` rows as ``(N, 3)`` (2-D: z = 0), as GSD and XYZ hold them."""
    a = np.asarray(a)
    if a.ndim == 2 and a.shape[1] == 2:
        return np.column_stack([a, np.zeros(len(a), a.dtype)])
    return a


# ---- in memory -------------------------------------------------------------------
class FrameRecorder(_FrameWriter):
    """Keeps frames in memory; :meth:`frames` returns them as :class:`Frames`.

    Args:
        every, events, trigger: as for the writers (:class:`GSDWriter`).
        max_events: keep at most about twice this many events: past it, every
            other kept event is dropped and then only every ``2**k``-th event
            of the run is kept (evenly thinned; ``Frames.events_every`` says
            which).  ``None``: keep them all (memory grows with the run).

    Example:
        >>> rec = FrameRecorder(1.0, max_events=2)
        >>> rec.observe(np.zeros(5, EVENT_DTYPE)); rec.events_every, rec.events_kept
        (2, 3)
    """

    def __init__(
        self,
        every: float | None = None,
        events: bool = True,
        *,
        trigger: Trigger | None = None,
        max_events: int | None = None,
    ) -> None:
        super().__init__(every, events, trigger=trigger)
        if max_events is not None and not (isinstance(max_events, int) and max_events >= 1):
            raise ArgumentError(
                f"FrameRecorder: max_events must be a whole number >= 1 or None, got {max_events!r}"
            )
        self.max_events = max_events
        #: the events kept are every this-many-th of the run's
        self.events_every = 1
        self._seen = 0  # events observed, kept or not
        self._times: list[float] = []
        self._pos: list[np.ndarray] = []
        self._vel: list[np.ndarray] = []
        self._ev: list[np.ndarray] = []
        self._img: list[np.ndarray | None] = []

    @property
    def events_kept(self) -> int:
        """How many events are kept now."""
        return sum(len(e) for e in self._ev) + sum(len(e) for e in self._events)

    def observe(self, ev: np.ndarray) -> None:
        if self.max_events is None:
            super().observe(ev)
            return
        if not len(ev):
            return
        # the k-th event of the run is kept when k is a multiple of the stride
        first = (-self._seen) % self.events_every
        self._seen += len(ev)
        kept = ev[first :: self.events_every]
        if len(kept):
            self._ev.append(kept.copy())
        while self.events_kept > 2 * self.max_events:
            held = np.concatenate(self._ev)
            self._ev = [held[::2].copy()]  # the kept are run events 0, s, 2s, ...: now 0, 2s, ...
            self.events_every *= 2

    def _start(self, sim: SimulationView) -> bool:
        self._sim = sim
        return False

    def _write_frame(self, sim: SimulationView, state: State, events: np.ndarray) -> None:
        self._times.append(state.time)
        self._pos.append(state.positions)
        self._vel.append(state.velocities)
        if len(events):
            self._ev.append(events)
        self._img.append(state.images)
        self._state = state

    def frames(self) -> Frames:
        """The frames recorded so far."""
        sim, st = self._sim, self._state
        n, d = st.n, getattr(sim.container, "dimensions", 3)
        return Frames(
            np.array(self._times),
            np.array(self._pos).reshape(-1, n, d),
            np.array(self._vel).reshape(-1, n, d),
            st.radii.copy(),
            st.masses.copy(),
            list(st.names),
            container=sim.container,
            events=_concat(self._ev),
            images=(np.array(self._img).reshape(-1, n, d) if sim.container.periodic else None),
            events_every=self.events_every,
        )


def frames_from_simulation(
    sim: Simulation, until: float, every: float, *, max_events: int | None = None
) -> Frames:
    """Run ``sim`` to ``until`` [time], keeping a frame every ``every`` [time].

    Args:
        sim, until, every: the run and its frames.
        max_events: keep at most about twice this many of the run's events,
            evenly thinned (:class:`FrameRecorder`); ``None``: all.

    Returns:
        :class:`hardspheres.frames.Frames` (the first frame is the state at
        the start, the last at ``until``).
    """
    rec = FrameRecorder(every, max_events=max_events)
    sim.writers.append(rec)
    try:
        sim.run(until=until)
    finally:
        sim.writers.remove(rec)
    if until - rec._times[-1] > 1e-9 * every:  # off the grid: end on `until`
        rec.write(sim, sim.time)
    return rec.frames()
