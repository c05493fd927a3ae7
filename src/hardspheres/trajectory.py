"""Trajectories: frames at fixed time intervals, to GSD or extended XYZ, and back.

Writers follow the :class:`hardspheres.Simulation` writer protocol
(``next_time``, ``attach``, ``write``, ``wants_events``/``observe``): append
one to ``sim.writers`` and every run writes a frame each ``every`` [time],
starting with the state at the time it is attached.

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
  frame: the names, UTF-8, joined by newlines); ``log/hardspheres/events``
  (``(E, 5)``: time, kind (0 reflection, 1 collision), i, j (-1 for a
  reflection), impulse: the events since the previous frame).

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

import math
import os
import warnings

import numpy as np

from .containers import PeriodicBox, SphericalContainer
from .fileio import PathLock
from .frames import Frames

_EMPTY_EVENTS = np.zeros((0, 5))


def _check_every(every):
    every = float(every)
    if not math.isfinite(every) or every <= 0.0:
        raise ValueError(f"every must be a finite time > 0, got {every!r}")
    return every


class TruncatedTrajectory(UserWarning):
    """A trajectory file ends before the run that wrote it meant to (cut short)."""


class NotAContinuation(ValueError):
    """An ``append=True`` writer's file does not end where the simulation is."""


class _FrameWriter:
    """Frames at ``t0, t0 + every, t0 + 2 every, ...`` from the time it is attached.

    Subclasses write a frame in ``_write_frame(sim, state, events)``, may
    check the simulation once in ``_start(sim)``, and keep their open file,
    if any, in ``_file`` (and its lock in ``_lock``).  ``_count`` is the
    index of the next frame in the file; ``_k`` the number of frames this
    writer has written (in an appended file the first, already there, is
    not written again).  ``last_time`` is the time of the last frame in the
    file [time].
    """

    _file = None
    _lock = None
    _closed = False
    _failed = False
    path = None
    #: The end time [time] recorded in each frame (``log/hardspheres/run_end``):
    #: ``None`` takes each ``run(until=...)``'s; a driver that runs in pieces
    #: (``hardspheres run``) sets its final end here.
    until = None

    def __init__(self, every, events=True):
        self.every = _check_every(every)
        self.wants_events = bool(events)
        self.next_time = math.inf
        self.last_time = None
        self._t0 = None
        self._count = 0
        self._k = 0
        self._events = []
        self._run_end = (math.inf, math.inf)

    def _start(self, sim):
        pass

    def _check_open(self):
        if self._closed:
            raise ValueError(f"{type(self).__name__}({self.path or ''!r}) is closed; "
                             "open a new writer to write more frames")

    def attach(self, sim):
        self._check_open()
        if self._t0 is None:
            self._t0 = sim.time
            if self._start(sim) == "continues":
                self._k = 1  # the file's last frame is this one
            else:
                self._frame(sim, sim.time)
        self.next_time = self._t0 + self._k * self.every

    def write(self, sim, t):
        self._frame(sim, t)
        self.next_time = self._t0 + self._k * self.every

    def observe(self, ev):
        if len(ev["t"]):
            self._events.append(np.column_stack(
                [ev["t"], ev["kind"], ev["i"], ev["j"], ev["impulse"]]).astype(np.float64))

    def _take_events(self):
        out = np.concatenate(self._events) if self._events else _EMPTY_EVENTS
        self._events = []
        return out

    def _frame(self, sim, t):
        self._check_open()
        until = self.until if self.until is not None else getattr(sim, "_run_until", math.inf)
        self._run_end = (float(until),
                         self._t0 + (self._k + 1) * self.every)
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

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self):
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

    def _take_lock(self, path):
        """Lock ``path`` for this writer, or raise (:class:`PathLock`)."""
        self.path = os.fspath(path)
        self._lock = PathLock(self.path)


def _continues(path, last, sim):
    """Raise unless the frame ``last`` of ``path`` is where ``sim`` is now."""
    c = sim.container
    size = c.radius if isinstance(c, SphericalContainer) else c.length
    same = (last["time"] == sim.time and last["n"] == sim.n and last["names"] == sim.names
            and last["container"] == (type(c).__name__, size))
    if not same:
        raise NotAContinuation(
            f"{path} does not end where this simulation is (it ends at t={last['time']!r} "
            f"with {last['n']} spheres; the simulation is at t={sim.time!r} with {sim.n}): "
            "it belongs to another run; write to another file")


class GSDWriter(_FrameWriter):
    """Frames to a GSD file (HOOMD schema, double precision).

    Args:
        path: the file (overwritten, unless ``append``).
        every: time between frames [time].
        events: also keep the events between frames (``log/hardspheres/events``).
        append: continue an existing file written by an earlier part of the
            same run (checked when the writer is attached); a missing
            file is created.

    Raises:
        FileInUseError: another writer holds the file.
        OSError: naming the file.
    """

    def __init__(self, path, every, events=True, append=False):
        super().__init__(every, events)
        import gsd.hoomd  # optional dependency: pip install hardspheres[io]
        self._take_lock(path)
        self._append = bool(append) and os.path.exists(self.path)
        try:
            self._file = gsd.hoomd.open(self.path, mode="r+" if self._append else "w",
                                        precision="double")
            self._count = len(self._file) if self._append else 0
        except (OSError, RuntimeError) as e:
            self.close()
            if isinstance(e, OSError) and e.filename is not None:
                raise
            raise ValueError(f"{self.path}: cannot open as GSD ({e})") from None
        self._hoomd = gsd.hoomd

    def _start(self, sim):
        if not self._append or self._count == 0:
            return None
        try:
            last = _gsd_last(self._file)
        except (KeyError, IndexError, ValueError) as e:
            raise ValueError(f"{self.path}: not a hardspheres trajectory ({e}); "
                             "write to another file") from None
        _continues(self.path, last, sim)
        self.last_time = last["time"]
        return "continues"

    def _write_frame(self, sim, state, events):
        f = self._hoomd.Frame()
        f.configuration.step = self._count
        c = sim.container
        if isinstance(c, PeriodicBox):
            f.configuration.box = [c.length, c.length, c.length, 0, 0, 0]
            f.log["hardspheres/box_length"] = np.array([c.length])
        else:
            side = 2.0 * c.radius
            f.configuration.box = [side, side, side, 0, 0, 0]
            f.log["hardspheres/container_radius"] = np.array([c.radius])
        f.particles.N = state.n
        f.particles.position = state.positions
        f.particles.velocity = state.velocities
        if state.images is not None:
            f.particles.image = state.images.astype(np.int32)
            if self._count == 0:  # marks files that carry images (all zero is not stored)
                f.log["hardspheres/images"] = np.array([1], np.int8)
        if self._count == 0:
            f.particles.types = ["sphere"]
            f.particles.typeid = np.zeros(state.n, dtype=np.uint32)
            f.particles.mass = state.masses
            f.particles.diameter = 2.0 * state.radii
            f.log["hardspheres/names"] = np.frombuffer(
                "\n".join(state.names).encode("utf-8"), dtype=np.uint8)
        f.log["hardspheres/time"] = np.array([state.time])
        f.log["hardspheres/run_end"] = np.array(self._run_end)
        if self.wants_events:
            f.log["hardspheres/events"] = events
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
        path: the file (overwritten, unless ``append``).
        every: time between frames [time].
        append: continue an existing file written by an earlier part of the
            same run (checked when the writer is attached).

    Raises:
        FileInUseError: another writer holds the file.
        OSError: naming the file.
    """

    def __init__(self, path, every, append=False):
        super().__init__(every, events=False)
        self._take_lock(path)
        self._append = bool(append) and os.path.exists(self.path)
        try:
            self._file = open(self.path, "a" if self._append else "w", encoding="utf-8",
                              newline="\n")
        except OSError:
            self.close()
            raise

    def _start(self, sim):
        from .messages import quote
        bad = [n for n in sim.names if not n or any(ch.isspace() or ch in "\"'" for ch in n)]
        if bad:
            raise ValueError(f"sphere name {quote(bad[0])} cannot be written to XYZ "
                             "(whitespace or quotes); use GSD")
        if not self._append or os.path.getsize(self.path) == 0:
            return None
        old = _read_xyz(self.path, check_end=False)
        self._count = len(old.times)
        c = ("PeriodicBox", old.box) if old.box is not None else (
            "SphericalContainer", old.container)
        _continues(self.path, {"time": float(old.times[-1]), "n": old.n,
                               "names": list(old.names), "container": c}, sim)
        self.last_time = float(old.times[-1])
        return "continues"

    def _write_frame(self, sim, state, events):
        c = sim.container
        if isinstance(c, PeriodicBox):
            side, pbc, size = c.length, "T T T", f"box_length={c.length!r}"
        else:
            side, pbc, size = 2.0 * c.radius, "F F F", f"container_radius={c.radius!r}"
        h = side / 2.0
        header = (f'{state.n}\nLattice="{side!r} 0 0 0 {side!r} 0 0 0 {side!r}" '
                  f'Origin="{-h!r} {-h!r} {-h!r}" pbc="{pbc}" '
                  "Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1 "
                  f"Time={state.time!r} {size} "
                  f"run_end=\"{self._run_end[0]!r} {self._run_end[1]!r}\"\n")
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


def _event_fields(blocks):
    """:class:`Frames`' event arrays from ``(E, 5)`` blocks (t, kind, i, j, impulse)."""
    ev = np.concatenate(blocks) if blocks else _EMPTY_EVENTS
    return dict(event_times=ev[:, 0], event_kinds=ev[:, 1].astype(np.int8),
                event_i=ev[:, 2].astype(np.int64), event_j=ev[:, 3].astype(np.int64))


# ---- reading -------------------------------------------------------------------
def read_trajectory(path):
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
    raise ValueError(f"{path}: not a trajectory (use a .gsd or .xyz file)")


def _warn_if_cut(path, last_time, run_end):
    """Warn if the run that wrote the last frame had another frame due before its end."""
    try:
        until, due = (float(x) for x in run_end)
    except (TypeError, ValueError):
        return  # not ours to judge
    if due <= until and last_time < until:
        warnings.warn(f"{path} ends at t={last_time!r}, but the run writing it was to reach "
                      f"t={until!r} (next frame due at t={due!r}): the file was cut short "
                      "(disk full, run killed or interrupted)", TruncatedTrajectory,
                      stacklevel=3)


def _gsd_last(traj):
    """What :func:`_continues` compares, from the last frame of an open GSD file."""
    first, last = traj[0], traj[len(traj) - 1]
    n = int(first.particles.N)
    raw = bytes(np.asarray(first.log.get("hardspheres/names", np.zeros(0, np.uint8)),
                           dtype=np.uint8))
    names = raw.decode("utf-8").split("\n") if n else []
    log = last.log
    if "hardspheres/box_length" in log:
        container = ("PeriodicBox", float(log["hardspheres/box_length"][0]))
    else:
        container = ("SphericalContainer", float(log["hardspheres/container_radius"][0]))
    return {"time": float(log["hardspheres/time"][0]), "n": int(last.particles.N),
            "names": names, "container": container}


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
        container = box = None
        if "hardspheres/box_length" in log:
            box = float(log["hardspheres/box_length"][0])
        else:
            container = float(log["hardspheres/container_radius"][0])
        times, pos, vel, events, images = [], [], [], [], []
        for f in traj:
            times.append(float(f.log["hardspheres/time"][0]))
            pos.append(np.asarray(f.particles.position, dtype=np.float64).reshape(n, 3))
            vel.append(np.asarray(f.particles.velocity, dtype=np.float64).reshape(n, 3))
            images.append(np.asarray(f.particles.image, dtype=np.int64).reshape(n, 3))
            if "hardspheres/events" in f.log:
                events.append(np.asarray(f.log["hardspheres/events"], np.float64).reshape(-1, 5))
            run_end = f.log.get("hardspheres/run_end")
        if run_end is not None and len(run_end) == 2:
            _warn_if_cut(path, times[-1], run_end)
        return Frames(np.array(times), np.array(pos).reshape(-1, n, 3),
                      np.array(vel).reshape(-1, n, 3),
                      np.asarray(first.particles.diameter, np.float64) / 2.0,
                      np.asarray(first.particles.mass, np.float64).copy(), names,
                      container=container, box=box,
                      images=(np.array(images).reshape(-1, n, 3)
                              if box is not None and "hardspheres/images" in log else None),
                      **_event_fields(events))


def _xyz_keys(comment):
    import shlex
    out = {}
    for tok in shlex.split(comment):
        if "=" in tok:
            k, v = tok.split("=", 1)
            out[k] = v
    return out


def _read_xyz(path, check_end=True):
    times, pos, vel, names, radii, masses = [], [], [], None, None, None
    run_end = None
    container = box = None
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().split("\n")
    k = 0
    try:
        while k < len(lines) and lines[k].strip():
            n = int(lines[k])
            keys = _xyz_keys(lines[k + 1])
            times.append(float(keys["Time"]))
            run_end = keys["run_end"].split() if "run_end" in keys else None
            if "box_length" in keys:
                box = float(keys["box_length"])
            else:
                container = float(keys["container_radius"])
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
    if check_end and run_end is not None and len(run_end) == 2:
        _warn_if_cut(path, times[-1], run_end)
    n = len(names)
    return Frames(np.array(times), np.array(pos).reshape(-1, n, 3),
                  np.array(vel).reshape(-1, n, 3), radii, masses, names,
                  container=container, box=box)


# ---- in memory -------------------------------------------------------------------
class FrameRecorder(_FrameWriter):
    """Keeps frames in memory; :meth:`frames` returns them as :class:`Frames`."""

    def __init__(self, every, events=True):
        super().__init__(every, events)
        self._times, self._pos, self._vel, self._ev, self._img = [], [], [], [], []

    def _start(self, sim):
        self._sim = sim

    def _write_frame(self, sim, state, events):
        self._times.append(state.time)
        self._pos.append(state.positions)
        self._vel.append(state.velocities)
        self._ev.append(events)
        self._img.append(state.images)
        self._state = state

    def frames(self):
        """The frames recorded so far."""
        sim, st = self._sim, self._state
        n = st.n
        c = sim.container
        return Frames(np.array(self._times), np.array(self._pos).reshape(-1, n, 3),
                      np.array(self._vel).reshape(-1, n, 3), st.radii.copy(),
                      st.masses.copy(), list(st.names),
                      container=c.radius if isinstance(c, SphericalContainer) else None,
                      box=c.length if isinstance(c, PeriodicBox) else None,
                      images=(np.array(self._img).reshape(-1, n, 3)
                              if isinstance(c, PeriodicBox) else None),
                      **_event_fields(self._ev))


def frames_from_simulation(sim, until, every):
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
    if until - rec._times[-1] > 1e-9 * rec.every:  # off the grid: end on `until`
        rec.write(sim, sim.time)
    return rec.frames()
