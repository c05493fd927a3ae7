"""Frames: a run sampled at fixed times, the common currency of writers and pictures.

Trajectory readers (:mod:`hardspheres.io.trajectory`) produce :class:`Frames`;
the viewer, renderer and plots (:mod:`hardspheres.viz.viewer`,
:mod:`hardspheres.viz.render`, :mod:`hardspheres.viz.plots`) consume them, picking
the frames they draw with :func:`frame_indices` (and the viewer the events
it embeds with :func:`even_indices`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .containers import Container, as_container
from .errors import ArgumentError
from .events import as_events, empty_events, from_columns
from .state import kinetic_energy

if TYPE_CHECKING:
    from .state import State


class Frames:
    """Snapshots of all spheres at increasing times.

    Args:
        times: ``(F,)`` frame times [time].
        positions: ``(F, N, 3)`` centres [length].
        velocities: ``(F, N, 3)`` [length/time].
        radii: ``(N,)`` [length].
        masses: ``(N,)`` [mass].
        names: ``N`` sphere names.
        container: the :class:`~hardspheres.containers.Container`, a radius
            of a spherical container [length], or ``None`` (open space).
        box: instead of ``container``, the edge of a periodic cubic box
            centred on the origin [length].
        events: the events of the run (:data:`~hardspheres.events.EVENT_DTYPE`;
            may be empty).
        event_times, event_kinds, event_i, event_j: instead of ``events``,
            its columns.
        images: ``(F, N, 3)`` int64 periodic images (periodic box), or ``None``.
        events_every: ``events`` holds every this-many-th event of the run
            (1: all of them; more when a recorder thinned them to bound its
            memory, :class:`~hardspheres.io.trajectory.FrameRecorder`).

    Attributes:
        container: the container, or ``None``.
        events: ``(E,)`` the events.

    Example:
        >>> f = Frames([0.0], np.zeros((1, 1, 3)), np.ones((1, 1, 3)), [0.5], [2.0], ["a"],
        ...            container=3.0)
        >>> f.container, f.energy().tolist(), f.box
        (SphericalContainer(radius=3.0), [3.0], None)
    """

    def __init__(
        self,
        times: ArrayLike,
        positions: ArrayLike,
        velocities: ArrayLike,
        radii: ArrayLike,
        masses: ArrayLike,
        names: Sequence[str],
        container: Container | float | None = None,
        box: float | None = None,
        events: np.ndarray | None = None,
        *,
        event_times: ArrayLike | None = None,
        event_kinds: ArrayLike | None = None,
        event_i: ArrayLike | None = None,
        event_j: ArrayLike | None = None,
        images: np.ndarray | None = None,
        events_every: int = 1,
    ) -> None:
        self.times = np.asarray(times, dtype=np.float64)
        self.positions = np.asarray(positions, dtype=np.float64)
        self.velocities = np.asarray(velocities, dtype=np.float64)
        self.radii = np.asarray(radii, dtype=np.float64)
        self.masses = np.asarray(masses, dtype=np.float64)
        self.names = list(names)
        self.container: Container | None = (
            None if container is None and box is None else as_container(container, box)
        )
        columns: dict[str, Any] = {
            k: v
            for k, v in (("time", event_times), ("kind", event_kinds), ("i", event_i), ("j", event_j))
            if v is not None
        }
        if events is not None:
            self.events = as_events(events)
        elif columns:
            self.events = from_columns(**columns)
        else:
            self.events = empty_events()
        self.images = None if images is None else np.asarray(images, dtype=np.int64)
        self.events_every = int(events_every)
        if self.events_every < 1:
            raise ArgumentError(f"Frames: events_every must be a whole number >= 1, got {events_every!r}")

    def __repr__(self) -> str:
        times = np.asarray(self.times)
        span = f", t={times[0]:.6g}..{times[-1]:.6g}" if len(times) else ""
        c = self.container
        where = "" if c is None else f", {'box' if c.periodic else 'container'}={c.size:g}"
        return f"Frames(n={self.n}, frames={len(times)}{span}{where}, events={len(self.events)})"

    def state(self, frame: int = -1, kT: float = 1.0, seed: int = 0) -> State:
        """The spheres of one frame as a :class:`~hardspheres.State`, to start a simulation from.

        A frame whose velocities are all zero (a Monte Carlo trajectory:
        HOOMD-blue's HPMC writes none) gets velocities drawn from
        Maxwell-Boltzmann at ``kT`` (zero total momentum).

        Args:
            frame: the frame's index (default the last).
            kT: temperature of drawn velocities [energy].
            seed: seed of the draw.

        Example:
            >>> import hardspheres as hs
            >>> f = Frames([0.0], [[[0, 0, 0], [2, 0, 0]]], np.zeros((1, 2, 3)), [0.5, 0.5], [1.0, 1.0],
            ...            ["a", "b"], box=5.0)
            >>> sim = hs.Simulation(f.state(), f.container)
            >>> round(sim.state().kinetic_energy(), 6)  # (d/2) (N - 1) kT
            1.5
        """
        from .maxwell import maxwell_boltzmann
        from .state import State

        try:
            k = range(len(self.times))[frame]
        except IndexError:
            raise ArgumentError(f"frame {frame} of {len(self.times)} frames; give -F .. F-1") from None
        x = self.positions[k].copy()
        v = self.velocities[k].copy()
        if not np.any(v):
            v = maxwell_boltzmann(np.random.default_rng(seed), self.masses, kT, dimensions=x.shape[1])
        if self.container is not None and self.container.periodic:
            x = self.container.wrap(x)
        return State.from_arrays(self.masses, self.radii, x, v, self.names, time=float(self.times[k]))

    def since(self, t: float) -> Frames:
        """The frames (and events) at times ``>= t``: e.g. to leave out an equilibration.

        Example:
            >>> f = Frames([0.0, 1.0, 2.0], np.zeros((3, 1, 3)), np.zeros((3, 1, 3)), [1.0], [1.0], ["a"])
            >>> f.since(1.0).times.tolist()
            [1.0, 2.0]
        """
        keep = self.times >= t
        if not keep.any():
            raise ArgumentError(
                f"no frames from t = {t:g} on (the last is at t = {self.times[-1]:g}); give an earlier t"
            )
        return self.replace(
            times=self.times[keep],
            positions=self.positions[keep],
            velocities=self.velocities[keep],
            events=self.events[self.events["time"] >= t],
            images=None if self.images is None else self.images[keep],
        )

    def replace(self, **changes: Any) -> Frames:
        """A copy with some attributes replaced (as ``dataclasses.replace`` did).

        Example:
            >>> f = Frames([0.0, 1.0], np.zeros((2, 1, 3)), np.zeros((2, 1, 3)), [1.0], [1.0], ["a"])
            >>> f.replace(times=f.times[::2], positions=f.positions[::2],
            ...           velocities=f.velocities[::2]).times.tolist()
            [0.0]
        """
        args: dict[str, Any] = dict(
            times=self.times,
            positions=self.positions,
            velocities=self.velocities,
            radii=self.radii,
            masses=self.masses,
            names=self.names,
            container=self.container,
            events=self.events,
            images=self.images,
            events_every=self.events_every,
        )
        unknown = set(changes) - set(args)
        if unknown:
            raise ArgumentError(
                f"Frames has no attribute {sorted(unknown)[0]!r} to replace; "
                f"name one of its fields ({', '.join(args)})"
            )
        args.update(changes)
        return Frames(**args)

    @property
    def n(self) -> int:
        """Number of spheres."""
        return len(self.radii)

    @property
    def box(self) -> float | np.ndarray | None:
        """Edge of the periodic cube, or ``(3,)`` sides of a rectangular box [length]; else ``None``."""
        c = self.container
        if c is None or not c.periodic:
            return None
        return c.length if c.cube else np.array(c.sides)  # type: ignore[attr-defined]

    def unwrapped(self) -> np.ndarray:
        """``(F, N, 3)`` unwrapped centres ``positions + images * box`` [length].

        Raises:
            PeriodicBoxRequired: not a periodic box, or a file without images.
        """
        from .containers import PeriodicBoxRequired

        box = self.box
        if box is None or self.images is None:
            raise PeriodicBoxRequired(
                "unwrapped positions need image counts: a periodic-box run recorded "
                "with GSDWriter or frames_from_simulation (XYZ files carry none)"
            )
        return self.positions + self.images * box

    # the events' columns by their older names
    @property
    def event_times(self) -> np.ndarray:
        """``(E,)`` times of the events [time]."""
        return self.events["time"]

    @property
    def event_kinds(self) -> np.ndarray:
        """``(E,)`` :class:`~hardspheres.events.EventKind` of the events."""
        return self.events["kind"]

    @property
    def event_i(self) -> np.ndarray:
        """``(E,)`` the sphere of each event (the lower index of a pair)."""
        return self.events["i"]

    @property
    def event_j(self) -> np.ndarray:
        """``(E,)`` the other sphere of a collision, ``-1`` for a reflection."""
        return self.events["j"]

    def energy(self) -> np.ndarray:
        """``(F,)`` kinetic energy of each frame [mass*length^2/time^2]."""
        return kinetic_energy(self.masses, self.velocities)

    def momentum(self) -> np.ndarray:
        """``(F, 3)`` total momentum of each frame [mass*length/time]."""
        return np.einsum("n,fnk->fk", self.masses, self.velocities)

    def wrapped_positions(self, keep: slice | int | np.ndarray = slice(None)) -> np.ndarray:
        """Positions of the frames ``keep``, wrapped into a periodic box [length]."""
        pos = self.positions[keep]
        return pos if self.container is None else self.container.wrap(pos)

    def extent(self, positions: np.ndarray | None = None, *, cover: str = "cube") -> float:
        """How far from the origin a picture must reach [length].

        The container's ``half_width`` (``cover="cube"``) or
        ``bounding_radius`` (``cover="sphere"``); in open space, the
        farthest sphere's edge in ``positions`` (default: all frames).
        """
        c = self.container
        if c is not None:
            e = c.half_width if cover == "cube" else c.bounding_radius
        else:
            pos = self.positions if positions is None else positions
            r = float(np.max(self.radii)) if len(self.radii) else 0.0
            if not np.size(pos):
                e = 1.0
            elif cover == "cube":
                e = float(np.max(np.abs(pos))) + r
            else:
                e = float(np.max(np.linalg.norm(pos, axis=-1))) + r
        return e if np.isfinite(e) and e > 0 else 1.0


def frame_indices(
    n_frames: int, n_spheres: int, max_frames: int = 600, max_values: int = 12_000_000
) -> np.ndarray:
    """Indices of the frames the viewer keeps: evenly spaced, first and last kept.

    At most ``max_frames`` frames, and at most ``max_values`` embedded numbers
    (``frames * spheres * 4``: a position and a speed, 4 bytes each), but never
    fewer than two frames when there are two.

    >>> frame_indices(5, 10).tolist()
    [0, 1, 2, 3, 4]
    >>> frame_indices(1001, 10, max_frames=3).tolist()
    [0, 500, 1000]
    """
    if n_frames <= 0:
        return np.zeros(0, np.int64)
    cap = min(int(max_frames), int(max_values) // max(1, 4 * n_spheres))
    return even_indices(n_frames, max(cap, min(2, n_frames)))


def even_indices(n: int, most: int) -> np.ndarray:
    """Indices of at most ``most`` of ``n`` items, evenly spaced: all of them if
    ``n <= most``, else the first, the last and evenly between (rounded).

    >>> even_indices(3, 5).tolist(), even_indices(11, 3).tolist()
    ([0, 1, 2], [0, 5, 10])
    """
    if n <= most:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, most)).astype(np.int64))
