"""State: the spheres as a plain dataclass of numpy arrays."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from .scenario import Scenario


def kinetic_energy(masses: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Total kinetic energy ``sum m |v|^2 / 2`` [mass*length^2/time^2].

    Args:
        masses: ``(N,)`` [mass].
        velocities: ``(N, 3)``, or ``(F, N, 3)`` for ``F`` frames [length/time].

    Returns:
        A scalar, or ``(F,)``.

    Example:
        >>> float(kinetic_energy(np.array([2.0]), np.array([[1.0, 0.0, 0.0]])))
        1.0
    """
    v = np.asarray(velocities, dtype=np.float64)
    return 0.5 * np.sum(np.asarray(masses) * np.sum(v * v, axis=-1), axis=-1)


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
    names: list[str] = field(default_factory=list)
    time: float = 0.0
    images: np.ndarray | None = None

    @property
    def dimensions(self) -> int:
        """The dimension of space ``d``, the positions' columns (2 for disks, else 3)."""
        p = np.asarray(self.positions)
        return 2 if p.ndim == 2 and p.shape[1] == 2 else 3

    @classmethod
    def from_arrays(
        cls,
        masses: ArrayLike,
        radii: ArrayLike,
        positions: ArrayLike,
        velocities: ArrayLike,
        names: Sequence[str] | None = None,
        time: float = 0.0,
    ) -> State:
        """Build a state from array-likes, naming spheres ``s0, s1, ...`` if unnamed.

        Raises:
            ScenarioError: arrays of the wrong shape, or numbers that
                :meth:`check` refuses.
        """
        from .scenario import ScenarioError

        try:
            masses = np.asarray(masses, dtype=np.float64).reshape(-1)
            n = masses.shape[0]
            arrays = [
                np.asarray(radii, dtype=np.float64),
                np.asarray(positions, np.float64),
                np.asarray(velocities, dtype=np.float64),
            ]
        except (TypeError, ValueError) as e:
            raise ScenarioError(
                f"masses, radii, positions and velocities must be numbers ({_first_line(e)})"
            ) from None
        # the dimension from the positions' columns: 3, or 2 for disks
        d = 2 if arrays[1].ndim == 2 and arrays[1].shape[1] == 2 and arrays[1].shape[0] == n else 3
        for what, a, shape in zip(("radii", "positions", "velocities"), arrays, ((n,), (n, d), (n, d))):
            if a.size != int(np.prod(shape)):
                raise ScenarioError(f"{what} has shape {list(a.shape)} for {n} masses; give {list(shape)}")
        names = [f"s{i}" for i in range(n)] if names is None else [str(x) for x in names]
        if len(names) != n:
            raise ScenarioError(f"{len(names)} names for {n} spheres; give one per sphere")
        state = cls(
            masses,
            arrays[0].reshape(n),
            arrays[1].reshape(n, d).copy(),
            arrays[2].reshape(n, d).copy(),
            names,
            time,
        )
        state.check()
        state.time = float(state.time)
        return state

    def check(self) -> None:
        """Check that the state can be simulated.

        Raises:
            ScenarioError: saying which sphere and what is wrong: a mass
                that is not a finite number > 0, a radius that is not a
                finite number >= 0, a position or velocity that is not
                finite, a repeated name, mismatched lengths, or a time that
                is not finite.
        """
        from .messages import quote
        from .scenario import ScenarioError

        n = len(self.masses)
        for what, a, shape in (
            ("masses", self.masses, (n,)),
            ("radii", self.radii, (n,)),
            ("positions", self.positions, (n, self.dimensions)),
            ("velocities", self.velocities, (n, self.dimensions)),
        ):
            if np.shape(a) != shape:
                raise ScenarioError(f"{what} has shape {list(np.shape(a))}, expected {list(shape)}")
        if len(self.names) != n:
            raise ScenarioError(f"{len(self.names)} names for {n} spheres; give one per sphere")

        def refuse(values: np.ndarray, ok: np.ndarray, what: str) -> None:
            bad = np.nonzero(~ok)[0]
            if len(bad):
                i = int(bad[0])
                raise ScenarioError(
                    f"sphere {i} ({quote(self.names[i])}): {what}, got {np.asarray(values)[i].tolist()!r}"
                )

        m, r = self.masses, self.radii
        refuse(m, np.isfinite(m) & (m > 0), "mass must be a finite number > 0")
        refuse(r, np.isfinite(r) & (r >= 0), "radius must be a finite number >= 0")
        refuse(self.positions, np.all(np.isfinite(self.positions), axis=1), "position must be finite")
        refuse(self.velocities, np.all(np.isfinite(self.velocities), axis=1), "velocity must be finite")
        seen: dict[str, int] = {}
        for i, name in enumerate(self.names):
            if name in seen:
                raise ScenarioError(
                    f"sphere {i}: name {quote(name)} is already sphere {seen[name]}'s; names are IDs"
                )
            seen[name] = i
        try:
            ok = np.isfinite(float(self.time))
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ScenarioError(f"time must be a finite number, got {self.time!r}")

    @classmethod
    def from_scenario(cls, scn: Scenario, dimensions: int = 3) -> State:
        """From a parsed :class:`hardspheres.scenario.Scenario`.

        ``dimensions = 2``: disks, read from the same nine fields with
        ``z = 0`` and ``vz = 0`` on every line (as :meth:`to_text` writes
        them); the state's arrays are ``(N, 2)``.

        Raises:
            ScenarioError: in 2-D, a line whose ``z`` or ``vz`` is not 0 (named).

        Example:
            >>> from hardspheres.scenario import parse_scenario
            >>> State.from_scenario(parse_scenario("1 0.5 1 2 0 3 4 0 a"), dimensions=2).positions
            array([[1., 2.]])
        """
        from .errors import ScenarioError

        positions = scn.positions or np.zeros((0, 3))
        velocities = scn.velocities or np.zeros((0, 3))
        if dimensions == 2:
            for p, v, line in zip(scn.positions, scn.velocities, scn.lines):
                if p[2] != 0.0 or v[2] != 0.0:
                    raise ScenarioError(
                        f"z = {p[2]!r}, vz = {v[2]!r}: disks (a circle or a 2-D box) have z = 0 and vz = 0",
                        line,
                    )
            positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)[:, :2]
            velocities = np.asarray(velocities, dtype=np.float64).reshape(-1, 3)[:, :2]
        elif dimensions != 3:
            raise ScenarioError(f"dimensions must be 2 or 3, got {dimensions!r}")
        return cls.from_arrays(scn.masses, scn.radii, positions, velocities, scn.names)

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self.masses.shape[0]

    def __repr__(self) -> str:
        names = ", ".join(self.names[:3]) + (", ..." if self.n > 3 else "")
        return f"State(n={self.n}, time={self.time:.6g}, names=[{names}])"

    def kinetic_energy(self) -> float:
        """Total kinetic energy [mass*length^2/time^2]."""
        return float(kinetic_energy(self.masses, self.velocities))

    def momentum(self) -> np.ndarray:
        """``(3,)`` total momentum [mass*length/time]."""
        return self.masses @ self.velocities

    def to_text(self) -> str:
        """The assignment's input format, with every digit kept (``%.17g``); disks with ``z = vz = 0``."""
        flat = self.dimensions == 2
        rows = [
            f"{m!r} {r!r} {p[0]!r} {p[1]!r} {0.0 if flat else p[2]!r} "
            f"{v[0]!r} {v[1]!r} {0.0 if flat else v[2]!r} {nm}\n"
            for m, r, p, v, nm in zip(
                self.masses.tolist(),
                self.radii.tolist(),
                self.positions.tolist(),
                self.velocities.tolist(),
                self.names,
            )
        ]
        return "".join(rows)


def _first_line(err: BaseException) -> str:
    text = (str(err).splitlines() or [type(err).__name__])[0]
    return text if len(text) <= 80 else text[:77] + "..."
