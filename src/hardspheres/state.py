"""State: the spheres as a plain dataclass of numpy arrays."""

from dataclasses import dataclass, field

import numpy as np


@dataclass
class State:
    """Spheres at one time.

    Attributes:
        masses: ``(N,)`` [mass].
        radii: ``(N,)`` [length].
        positions: ``(N, 3)`` centres [length].
        velocities: ``(N, 3)`` [length/time].
        names: ``N`` unique names (IDs).
        time: the time of this state [time].
        images: ``(N, 3)`` int64 periodic images (periodic box only, else
            ``None``): the unwrapped centre is ``positions + images * L``.

    Example:
        >>> s = State.from_arrays([1.0], [0.5], [[0, 0, 0]], [[1, 0, 0]])
        >>> s.names, s.kinetic_energy()
        (['s0'], 0.5)
    """

    masses: np.ndarray
    radii: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    names: list = field(default_factory=list)
    time: float = 0.0
    images: np.ndarray | None = None

    @classmethod
    def from_arrays(cls, masses, radii, positions, velocities, names=None, time=0.0):
        """Build a state from array-likes, naming spheres ``s0, s1, ...`` if unnamed."""
        masses = np.asarray(masses, dtype=np.float64).reshape(-1)
        n = masses.shape[0]
        names = [f"s{i}" for i in range(n)] if names is None else [str(x) for x in names]
        if len(names) != n:
            raise ValueError(f"{len(names)} names for {n} spheres")
        return cls(masses, np.asarray(radii, dtype=np.float64).reshape(n),
                   np.asarray(positions, dtype=np.float64).reshape(n, 3).copy(),
                   np.asarray(velocities, dtype=np.float64).reshape(n, 3).copy(),
                   names, float(time))

    @classmethod
    def from_scenario(cls, scn):
        """From a parsed :class:`hardspheres.scenario.Scenario`."""
        return cls.from_arrays(scn.masses, scn.radii, scn.positions or np.zeros((0, 3)),
                               scn.velocities or np.zeros((0, 3)), scn.names)

    @property
    def n(self):
        """Number of spheres."""
        return self.masses.shape[0]

    def kinetic_energy(self):
        """Total kinetic energy [mass*length^2/time^2]."""
        return float(0.5 * np.sum(self.masses * np.sum(self.velocities ** 2, axis=1)))

    def momentum(self):
        """``(3,)`` total momentum [mass*length/time]."""
        return self.masses @ self.velocities

    def to_text(self):
        """The assignment's input format, with every digit kept (``%.17g``)."""
        rows = [f"{m!r} {r!r} {p[0]!r} {p[1]!r} {p[2]!r} {v[0]!r} {v[1]!r} {v[2]!r} {nm}\n"
                for m, r, p, v, nm in zip(self.masses.tolist(), self.radii.tolist(),
                                          self.positions.tolist(), self.velocities.tolist(),
                                          self.names)]
        return "".join(rows)
