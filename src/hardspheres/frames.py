"""Frames: a run sampled at fixed times, the common currency of writers and pictures.

Trajectory readers (:mod:`hardspheres.trajectory`) produce :class:`Frames`;
the viewer, renderer and plots (:mod:`hardspheres.viewer`,
:mod:`hardspheres.render`, :mod:`hardspheres.plots`) consume them, picking
the frames they draw with :func:`frame_indices`.
"""

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Frames:
    """Snapshots of all spheres at increasing times.

    Attributes:
        times: ``(F,)`` frame times [time].
        positions: ``(F, N, 3)`` centres [length].
        velocities: ``(F, N, 3)`` [length/time].
        radii: ``(N,)`` [length].
        masses: ``(N,)`` [mass].
        names: ``N`` sphere names.
        container: radius of the spherical container [length], or ``None``.
        box: edge of the periodic cubic box [length] (centred on the
            origin), or ``None``.
        event_times: ``(E,)`` times of events [time] (may be empty).
        event_kinds: ``(E,)`` 0 = reflection off the container, 1 = collision.
        event_i, event_j: ``(E,)`` spheres involved (``j = -1`` for reflections).
        images: ``(F, N, 3)`` int64 periodic images (periodic box), or ``None``.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    radii: np.ndarray
    masses: np.ndarray
    names: list
    container: float | None = None
    box: float | None = None
    event_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    event_kinds: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int8))
    event_i: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    event_j: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    images: np.ndarray | None = None

    @property
    def n(self):
        """Number of spheres."""
        return len(self.radii)

    def __repr__(self):
        times = np.asarray(self.times)
        span = f", t={times[0]:.6g}..{times[-1]:.6g}" if len(times) else ""
        where = (f", container={self.container:g}" if self.container is not None else
                 f", box={self.box:g}" if self.box is not None else "")
        return (f"Frames(n={self.n}, frames={len(times)}{span}{where}, "
                f"events={len(self.event_times)})")

    def unwrapped(self):
        """``(F, N, 3)`` unwrapped centres ``positions + images * box`` [length].

        Raises:
            PeriodicBoxRequired: not a periodic box, or a file without images.
        """
        from .containers import PeriodicBoxRequired
        if self.box is None or self.images is None:
            raise PeriodicBoxRequired(
                "unwrapped positions need image counts: a periodic-box run recorded "
                "with GSDWriter or frames_from_simulation (XYZ files carry none)")
        return self.positions + self.images * self.box

    def energy(self):
        """``(F,)`` kinetic energy of each frame [mass*length^2/time^2]."""
        return 0.5 * np.einsum("n,fnk,fnk->f", self.masses, self.velocities, self.velocities)

    def momentum(self):
        """``(F, 3)`` total momentum of each frame [mass*length/time]."""
        return np.einsum("n,fnk->fk", self.masses, self.velocities)


def frame_indices(n_frames, n_spheres, max_frames=600, max_values=12_000_000):
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
    cap = max(cap, min(2, n_frames))
    if n_frames <= cap:
        return np.arange(n_frames)
    return np.unique(np.round(np.linspace(0, n_frames - 1, cap)).astype(np.int64))
