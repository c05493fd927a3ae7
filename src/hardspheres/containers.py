"""Containers: where the spheres live, and everything that depends on it.

* :class:`SphericalContainer`: the assignment's hard spherical wall centred
  on the origin; spheres reflect off it.
* :class:`PeriodicBox`: a cube centred on the origin with periodic
  boundaries and minimum-image collisions, for bulk matter (no walls).
* :class:`CircularContainer`: the 2-D round wall; it and
  :class:`SphericalContainer` share their base, :class:`RoundWall`.

A container is one object that every layer passes along (engine,
simulation, observables, trajectories, frames, pictures); it owns the
geometry, so nothing above the compiled core asks which container it is:

* geometry: :meth:`~Container.wrap`, :meth:`~Container.displacement`
  (minimum image), :meth:`~Container.outside` (spheres not wholly inside),
  :attr:`~Container.volume`, :attr:`~Container.wall_area`,
  :attr:`~Container.half_width` and :attr:`~Container.bounding_radius`
  (pictures), :meth:`~Container.outline` (lines to draw);
* thermodynamics: :meth:`~Container.degrees_of_freedom` and
  :meth:`~Container.pressure` from the core's running totals;
* files: :meth:`~Container.fields` (GSD log and XYZ header),
  :attr:`~Container.gsd_box`, :meth:`~Container.record` (checkpoints),
  read back by :func:`from_fields` and :func:`from_record`;
* the core: :meth:`~Container.core_params`, the numbers the compiled event
  loop reads (a wall radius and a periodic edge, 0 when absent).

A third geometry (a slab, a cylinder) is one new class here, registered in
:data:`KINDS`, and one branch in the core (:mod:`hardspheres.core._core`: its
wall time and reflection, and its cell grid's edges).

Example:
    >>> import numpy as np
    >>> c = SphericalContainer(2.0)
    >>> round(c.volume, 4), c.degrees_of_freedom(10), c.fields()
    (33.5103, 30, {'container_radius': 2.0})
    >>> b = PeriodicBox(2.0)
    >>> b.wrap(np.array([[1.5, -1.2, 0.0]])).tolist()
    [[-0.5, 0.8, 0.0]]
    >>> from_record(b.record()) == b
    True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Protocol, runtime_checkable

from .errors import BoxShapeError, ContainerError, PeriodicBoxRequired, ShearError  # noqa: F401 (re-exported)

if TYPE_CHECKING:
    from typing import TypeVar

    import numpy as np
    from numpy.typing import ArrayLike

    #: A tally or a time: one number, or an array of them (the observables' blocks).
    _Tally = TypeVar("_Tally", float, np.ndarray)

#: Relative tolerance for "touching within rounding", so two spheres overlap only
#: if their distance is below ``(1 - TOUCH_TOL)`` times the sum of their
#: radii; a sphere is outside only if it pokes out by more than ``TOUCH_TOL``
#: times the container radius.
TOUCH_TOL = 1e-9

# numpy is imported where it is used: the assignment's program checks its
# scenario against a container without loading numpy.


@runtime_checkable
class Container(Protocol):
    """What every container provides (see the module docstring)."""

    periodic: ClassVar[bool]

    @property
    def label(self) -> str: ...

    @property
    def size(self) -> float: ...

    @property
    def description(self) -> str: ...

    @property
    def dimensions(self) -> int: ...

    @property
    def volume(self) -> float: ...

    @property
    def wall_area(self) -> float: ...

    @property
    def half_width(self) -> float: ...

    @property
    def bounding_radius(self) -> float: ...

    @property
    def gsd_box(self) -> list[float]: ...

    def wrap(self, positions: np.ndarray) -> np.ndarray: ...

    def image_counts(self, positions: np.ndarray) -> np.ndarray: ...

    def displacement(self, a: np.ndarray, b: np.ndarray) -> np.ndarray: ...

    def outside(self, positions: np.ndarray, radii: np.ndarray, tol: float = TOUCH_TOL) -> np.ndarray: ...

    def degrees_of_freedom(self, n: int) -> int: ...

    def pressure(
        self, n: int, kT: float, elapsed: _Tally, wall_impulse: _Tally, virial: _Tally
    ) -> _Tally: ...

    def fields(self) -> dict[str, float]: ...

    def record(self) -> np.ndarray: ...

    def core_params(self) -> dict: ...

    def check_sphere(self, p: list[float], r: float, v: list[float]) -> str | None: ...

    def outline(
        self, right: np.ndarray, up: np.ndarray, cut: float | None = None, axis: int = 2
    ) -> list[tuple[np.ndarray, bool]]: ...


def _positive(value: float, what: str) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ContainerError(f"{what} must be a number, got {value!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise ContainerError(f"{what} must be a finite number > 0, got {value}")
    return value


def require_periodic(container: Container | None, what: str) -> float:
    """The box's x side (a cube's edge); :class:`PeriodicBoxRequired` if it is not periodic."""
    if container is None or not container.periodic:
        raise PeriodicBoxRequired(
            f"{what} need a periodic box (spheres in a container do not diffuse freely); "
            "simulate in hs.PeriodicBox(L)"
        )
    return float(container.sides[0])  # type: ignore[attr-defined]  # a box's


def _shear_rate(value: Any) -> float:  # anything a user gives: checked here
    """``value`` as a shear rate [1/time]; :class:`ShearError` if it is not a finite number."""
    if isinstance(value, (bool, str, bytes)):
        raise ShearError(f"shear_rate {value!r}: give a finite number [1/time] (0: no shear)")
    try:
        rate = float(value)
    except (TypeError, ValueError):
        raise ShearError(f"shear_rate {value!r}: give a finite number [1/time] (0: no shear)") from None
    if not math.isfinite(rate):
        raise ShearError(f"shear_rate {value!r}: give a finite number [1/time] (0: no shear)")
    return rate + 0.0  # (-0.0 is no shear: +0.0)


@dataclass(frozen=True)
class RoundWall:
    """A hard round wall of radius ``radius`` [length] centred on the origin, in ``dimensions`` (2 or 3).

    What :class:`SphericalContainer` (3-D) and :class:`CircularContainer`
    (2-D) share: no periodic images, plain differences, the wall's reach,
    ``d N`` degrees of freedom, the pressure on the wall, the files' fields.
    Each subclass adds what its dimension sets: volume, wall area, the
    GSD box, the core's numbers, the start check and the outline.
    """

    radius: float
    periodic: ClassVar[bool] = False
    #: The name in files (:meth:`record`) and its size's field (:meth:`fields`).
    kind: ClassVar[str]
    size_field: ClassVar[str]
    dimensions: ClassVar[int]
    #: The shape's adjective in words (:attr:`label`, :attr:`description`).
    shape: ClassVar[str]

    @property
    def size(self) -> float:
        """The one number that sets the container, its radius [length]."""
        return self.radius

    @property
    def label(self) -> str:
        """A short description for titles."""
        return f"{self.shape} container R = {self.radius:g}"

    @property
    def description(self) -> str:
        """It in words, for messages and summaries."""
        return f"{self.shape} container of radius {self.radius:g}"

    @property
    def half_width(self) -> float:
        """Half the side of the cube (a square in 2-D) that encloses it [length]."""
        return self.radius

    @property
    def bounding_radius(self) -> float:
        """Radius of the sphere (a circle in 2-D) that encloses it [length]."""
        return self.radius

    def wrap(self, positions: np.ndarray) -> np.ndarray:
        """Positions as they are (no periodic images) [length]."""
        import numpy as np

        return np.asarray(positions, dtype=np.float64)

    def image_counts(self, positions: np.ndarray) -> np.ndarray:
        """``(N, d)`` zeros: no periodic images."""
        import numpy as np

        return np.zeros(np.asarray(positions).reshape(-1, self.dimensions).shape, np.int64)

    def displacement(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """``a - b`` [length]."""
        import numpy as np

        return np.asarray(a, dtype=np.float64) - b

    def outside(self, positions: np.ndarray, radii: np.ndarray, tol: float = TOUCH_TOL) -> np.ndarray:
        """``(N,)`` True for spheres (disks) poking out of the wall by more than ``tol`` of its radius."""
        import numpy as np

        pos = np.asarray(positions, dtype=np.float64).reshape(-1, self.dimensions)
        reach = np.linalg.norm(pos, axis=1) + radii
        return reach > self.radius * (1.0 + tol)

    def degrees_of_freedom(self, n: int) -> int:
        """``d N``: the wall takes up momentum, so none is conserved."""
        return self.dimensions * n

    def pressure(self, n: int, kT: float, elapsed: _Tally, wall_impulse: _Tally, virial: _Tally) -> _Tally:
        """Momentum delivered to the wall per unit area (2-D: length) and time [energy/length^d]."""
        return wall_impulse / (self.wall_area * elapsed)

    @property
    def wall_area(self) -> float:
        """Area of the wall (its length in 2-D) [length^(d-1)], each subclass's own."""
        raise NotImplementedError

    def fields(self) -> dict[str, float]:
        """Its numbers by name, for GSD logs and XYZ headers."""
        return {self.size_field: self.radius}

    def record(self) -> np.ndarray:
        """``[kind, repr(size)]`` for checkpoints (:func:`from_record`)."""
        import numpy as np

        return np.array([self.kind, repr(self.radius)])


@dataclass(frozen=True)
class SphericalContainer(RoundWall):
    """A hard spherical wall of radius ``radius`` [length] centred on the origin.

    Spheres reflect off the wall; the pressure is the momentum the wall
    receives per unit area and time.

    Example:
        >>> round(SphericalContainer(1.0).volume, 6)
        4.18879
    """

    kind: ClassVar[str] = "SphericalContainer"
    size_field: ClassVar[str] = "container_radius"
    dimensions: ClassVar[int] = 3
    shape: ClassVar[str] = "spherical"

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "container radius"))

    @classmethod
    def for_packing(cls, n: int, packing: float) -> SphericalContainer:
        """The container ``n`` spheres of diameter 1 fill to the fraction ``packing``.

        Example:
            >>> round(SphericalContainer.for_packing(1000, 0.125).radius, 6)
            10.0
        """
        n, packing = _n_and_packing(n, packing)
        return cls((n / (8.0 * packing)) ** (1.0 / 3.0))

    @property
    def volume(self) -> float:
        """Volume enclosed [length^3]."""
        return 4.0 / 3.0 * math.pi * self.radius**3

    @property
    def wall_area(self) -> float:
        """Area of the wall [length^2]."""
        return 4.0 * math.pi * self.radius**2

    area = wall_area

    @property
    def gsd_box(self) -> list[float]:
        """GSD's ``configuration/box``, the enclosing cube (not periodic)."""
        side = 2.0 * self.radius
        return [side, side, side, 0.0, 0.0, 0.0]

    def core_params(self) -> dict:
        """What the compiled core reads: wall radius, periodic edge (0: none), grid span (per axis too)."""
        span = 2.0 * self.radius
        return {
            "wall_radius": self.radius,
            "box": 0.0,
            "span": span,
            "edges": (0.0, 0.0, 0.0),
            "spans": (span, span, span),
        }

    def check_sphere(self, p: list[float], r: float, v: list[float]) -> str | None:
        """Why a sphere at ``p`` of radius ``r`` moving at ``v`` cannot start here, or ``None``."""
        reach = math.sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) + r
        if reach > self.radius + TOUCH_TOL * self.radius:
            return f"is not wholly inside the container: |p| + R = {reach:g} > {self.radius:g}"
        if r >= self.radius and (v[0] or v[1] or v[2]):
            return "fills the container and cannot move; give it zero velocity or a smaller radius"
        from .physics import reflect, wall_time

        px, py, pz, vx, vy, vz = p[0], p[1], p[2], v[0], v[1], v[2]
        if wall_time(px, py, pz, vx, vy, vz, self.radius - r) == 0.0 and (
            reflect(px, py, pz, vx, vy, vz) == 0.0
        ):
            return (
                "touches the container wall and moves along it (velocity perpendicular to its "
                "position): it would slide along the wall, which point reflections cannot "
                "model; give it a velocity component off the wall or move it inward"
            )
        return None

    def outline(
        self, right: np.ndarray, up: np.ndarray, cut: float | None = None, axis: int = 2
    ) -> list[tuple[np.ndarray, bool]]:
        """Its outline seen along ``right x up``: ``(line (k, 2), dashed)`` pairs [length].

        The silhouette circle, and where a cut-away plane meets the wall
        (dashed): the plane normal to axis ``axis`` (0, 1, 2: x, y, z) at
        that coordinate ``cut``.
        """
        import numpy as np

        r = self.radius
        u = np.linspace(0, 2 * np.pi, 181)
        out = [(np.column_stack([r * np.cos(u), r * np.sin(u)]), False)]
        if cut is not None and abs(cut) < r:
            rho = np.sqrt(r * r - cut * cut)
            ring = np.empty((len(u), 3))
            a, b = (k for k in range(3) if k != axis)
            ring[:, a], ring[:, b], ring[:, axis] = rho * np.cos(u), rho * np.sin(u), cut
            out.append((np.column_stack([ring @ right, ring @ up]), True))
        return out


def _box_sides(length: Any) -> float | tuple[float, ...]:  # anything a user gives: checked here
    """``length`` as a cube's edge (a float) or a box's sides (a tuple); :class:`BoxShapeError` if neither."""
    allowed = "give one number (a cube's edge), three (Lx, Ly, Lz) or two (Lx, Ly: 2-D), each finite and > 0"
    if isinstance(length, (str, bytes)):
        raise BoxShapeError(f"box sides {length!r}: {allowed}")
    try:
        sides = tuple(length)
    except TypeError:
        try:
            return _positive(length, "box length")
        except ContainerError:
            raise BoxShapeError(f"box length {length!r}: {allowed}") from None
    if len(sides) not in (2, 3):
        raise BoxShapeError(f"a box of {len(sides)} sides {sides!r} (dimension {len(sides)}): {allowed}")
    out = []
    for a, x in zip("xyz", sides):
        try:
            out.append(_positive(x, f"box side L{a}"))
        except ContainerError:
            raise BoxShapeError(f"box side L{a} = {x!r}: {allowed}") from None
    if len(out) == 3 and out[0] == out[1] == out[2]:
        return out[0]  # the cube: one number, the same arithmetic
    return tuple(out)


@dataclass(frozen=True)
class PeriodicBox:
    """A periodic box centred on the origin: a cube of edge ``length``, or sides ``(Lx, Ly, Lz)`` [length].

    Pairs collide with their nearest image; total momentum is conserved; the
    pressure comes from the collision virial.  ``length`` is a float for a
    cube (three equal sides are the cube) and a tuple for a rectangular
    box; :attr:`sides` is always the tuple.

    ``shear_rate`` ``g`` [1/time] shears it by Lees-Edwards boundaries
    (flow along x, gradient along y, streaming velocity ``g y`` along x):
    the images across the y faces slide along x at ``+-g L_y``, a sphere
    crossing a y face gains or loses ``g L_y`` in ``v_x``; total momentum
    along y and z is conserved, along x it is not.  0 (the default) is
    the plain periodic box.  For now only the brute-force reference
    (:class:`hardspheres.core.reference.Reference`) runs a sheared box: the
    compiled event core refuses it (:meth:`core_params`).

    Example:
        >>> PeriodicBox(2.0).volume, PeriodicBox((1.0, 2.0, 3.0)).volume
        (8.0, 6.0)
        >>> PeriodicBox((2.0, 2.0, 2.0))
        PeriodicBox(length=2.0)
        >>> PeriodicBox((4.0, 3.0), shear_rate=0.5).boundary_speed
        1.5
    """

    length: float | tuple[float, ...]
    shear_rate: float = 0.0
    periodic: ClassVar[bool] = True
    kind: ClassVar[str] = "PeriodicBox"
    size_field: ClassVar[str] = "box_length"
    #: the fields of a rectangular box's sides (:meth:`fields`)
    side_fields: ClassVar[tuple[str, ...]] = ("box_length_x", "box_length_y", "box_length_z")

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _box_sides(self.length))
        object.__setattr__(self, "shear_rate", _shear_rate(self.shear_rate))

    def __repr__(self) -> str:
        if self.shear_rate:
            return f"PeriodicBox(length={self.length!r}, shear_rate={self.shear_rate!r})"
        return f"PeriodicBox(length={self.length!r})"

    @property
    def sheared(self) -> bool:
        """Whether it is sheared (a shear rate other than 0)."""
        return self.shear_rate != 0.0

    @property
    def boundary_speed(self) -> float:
        """The speed ``g L_y`` of the images across the y faces along x [length/time], 0 if not sheared."""
        return self.shear_rate * self.sides[1]

    def sheared_by(self, shear_rate: float) -> PeriodicBox:
        """The same box sheared at ``shear_rate`` [1/time] (0: not sheared).

        Example:
            >>> PeriodicBox(3.0).sheared_by(0.1)
            PeriodicBox(length=3.0, shear_rate=0.1)
        """
        return PeriodicBox(self.length, shear_rate)

    @classmethod
    def for_packing(cls, n: int, packing: float, aspect: tuple[float, ...] | None = None) -> PeriodicBox:
        """The box ``n`` spheres of diameter 1 fill to the fraction ``packing``.

        ``aspect``: the sides' proportions (default: a cube); two of them
        make a 2-D box that ``n`` disks of diameter 1 fill to the area
        fraction ``packing``.

        Example:
            >>> round(PeriodicBox.for_packing(500, 0.3).length, 6)
            9.556139
            >>> [round(x, 6) for x in PeriodicBox.for_packing(500, 0.3, (1, 1, 2)).sides]
            [7.584713, 7.584713, 15.169425]
            >>> [round(x, 6) for x in PeriodicBox.for_packing(400, 0.7, (1, 3**0.5 / 2)).sides]
            [22.76463, 19.714748]
        """
        n, packing = _n_and_packing(n, packing)
        if aspect is None:
            return cls((n * math.pi / (6.0 * packing)) ** (1.0 / 3.0))
        a = [float(x) for x in aspect]
        if len(a) not in (2, 3) or not all(math.isfinite(x) and x > 0 for x in a):
            raise BoxShapeError(f"aspect {aspect!r}: give three (or, for disks, two) finite numbers > 0")
        d = len(a)
        volume = n * math.pi / ((6.0 if d == 3 else 4.0) * packing)
        unit = (volume / math.prod(a)) ** (1.0 / d)
        return cls(tuple(unit * x for x in a))

    @property
    def cube(self) -> bool:
        """Whether it is a cube (three equal sides)."""
        return not isinstance(self.length, tuple)

    @property
    def sides(self) -> tuple[float, ...]:
        """The sides ``(Lx, Ly, Lz)`` [length]."""
        if isinstance(self.length, tuple):
            return self.length
        return (self.length,) * 3

    @property
    def dimensions(self) -> int:
        """The dimension of space, 3, or 2 for ``(Lx, Ly)``."""
        return len(self.sides)

    @property
    def size(self) -> float:
        """The one number that sets a cube, its edge; a box's longest side [length]."""
        return max(self.sides)

    @property
    def _sides_text(self) -> str:
        return " x ".join(f"{x:g}" for x in self.sides)

    @property
    def label(self) -> str:
        """A short description for titles."""
        shear = f", shear rate {self.shear_rate:g}" if self.shear_rate else ""
        if self.cube:
            return f"periodic box L = {self.size:g}{shear}"
        return f"periodic box {self._sides_text}{shear}"

    @property
    def description(self) -> str:
        """It in words, for messages and summaries."""
        shear = f", sheared at rate {self.shear_rate:g} (Lees-Edwards)" if self.shear_rate else ""
        if self.cube:
            return f"periodic box of edge {self.size:g}{shear}"
        return f"periodic box of sides {self._sides_text}{shear}"

    @property
    def volume(self) -> float:
        """Volume of the box [length^3] (in 2-D its area [length^2])."""
        if self.cube:
            return self.size**3
        return math.prod(self.sides)

    @property
    def wall_area(self) -> float:
        """No walls, so 0 [length^2]."""
        return 0.0

    @property
    def half_width(self) -> float:
        """Half the longest side (the enclosing cube's) [length]."""
        return 0.5 * self.size

    @property
    def bounding_radius(self) -> float:
        """Half the box's diagonal [length]."""
        if self.cube:
            return 0.5 * self.size * math.sqrt(3.0)
        return 0.5 * math.sqrt(sum(x * x for x in self.sides))

    @property
    def gsd_box(self) -> list[float]:
        """GSD's ``configuration/box`` (periodic; in 2-D ``Lz = 0``, as HOOMD writes it)."""
        return [*self.sides, 0.0, 0.0, 0.0] if self.dimensions == 3 else [*self.sides, 0.0, 0.0, 0.0, 0.0]

    def _edges(self) -> float | tuple[float, ...] | np.ndarray:
        import numpy as np

        return self.length if self.cube else np.array(self.sides)

    def wrap(self, positions: np.ndarray) -> np.ndarray:
        """Positions moved by whole sides into ``[-L/2, L/2)`` per axis [length]."""
        import numpy as np

        p = np.asarray(positions, dtype=np.float64)
        L = self._edges()
        return p - L * np.floor(p / L + 0.5)

    def image_counts(self, positions: np.ndarray) -> np.ndarray:
        """``(N, 3)`` whole sides :meth:`wrap` takes off each position (its periodic image)."""
        import numpy as np

        p = np.asarray(positions, dtype=np.float64).reshape(-1, self.dimensions)
        return np.floor(p / self._edges() + 0.5).astype(np.int64)

    def displacement(self, a: np.ndarray, b: np.ndarray, offset: float = 0.0) -> np.ndarray:
        """``a - b`` to the nearest image [length].

        ``offset``: a sheared box's Lees-Edwards offset now [length] (the
        images across the y faces shifted along x by it: the engine's
        ``shear_offset()``); 0 is the plain box, with its arithmetic.
        """
        import numpy as np

        d = np.asarray(a, dtype=np.float64) - b
        L = self._edges()
        if offset:
            lx, ly = self.sides[0], self.sides[1]
            d = d.copy()
            ky = np.round(d[..., 1] / ly)
            d[..., 1] -= ly * ky
            d[..., 0] -= ky * offset
            d[..., 0] -= lx * np.round(d[..., 0] / lx)
            if self.dimensions == 3:
                d[..., 2] -= self.sides[2] * np.round(d[..., 2] / self.sides[2])
            return d
        return d - L * np.round(d / L)

    def outside(self, positions: np.ndarray, radii: np.ndarray, tol: float = TOUCH_TOL) -> np.ndarray:
        """``(N,)`` all False: nothing is outside a periodic box."""
        import numpy as np

        return np.zeros(np.asarray(positions).reshape(-1, self.dimensions).shape[0], dtype=bool)

    def degrees_of_freedom(self, n: int) -> int:
        """``d N - d``: total momentum is conserved (``d N`` for one sphere)."""
        d = self.dimensions
        return d * n - d if n > 1 else d * n

    def pressure(self, n: int, kT: float, elapsed: _Tally, wall_impulse: _Tally, virial: _Tally) -> _Tally:
        """``(N kT + W / (d t)) / V`` with ``W`` the collision virial [energy/length^d]."""
        return (n * kT + virial / (self.dimensions * elapsed)) / self.volume

    def fields(self) -> dict[str, float]:
        """Its numbers by name, for GSD logs and XYZ headers (``box_length`` or the sides; ``shear_rate``)."""
        out = {self.size_field: self.size} if self.cube else dict(zip(self.side_fields, self.sides))
        if self.shear_rate:
            out["shear_rate"] = self.shear_rate
        return out  # (2-D: x and y)

    def record(self) -> np.ndarray:
        """``[kind, size]`` for checkpoints (:func:`from_record`): ``repr`` of the edge, or the sides.

        A sheared box adds a third entry, ``repr`` of its shear rate.
        """
        import numpy as np

        size = repr(self.length) if self.cube else " ".join(repr(x) for x in self.sides)
        if self.shear_rate:
            return np.array([self.kind, size, repr(self.shear_rate)])
        return np.array([self.kind, size])

    def core_params(self, shear: bool = False) -> dict:
        """What the compiled core reads: wall radius (0: none), periodic edge, grid span.

        ``box`` and ``span`` are the x side's; ``edges`` and ``spans`` per axis.

        Raises:
            ShearError: the box is sheared and ``shear`` is not set: the
                caller has no Lees-Edwards boundaries (an engine that runs
                them, the event core or the brute-force reference, passes
                ``shear=True``; event chains, for one, do not).
        """
        if self.shear_rate and not shear:
            raise ShearError(
                f"a sheared box (shear_rate {self.shear_rate:g}) runs on the event-driven engine "
                "(hardspheres.Simulation), not here; give shear_rate=0"
            )
        x = self.sides[0]
        if self.dimensions == 2:  # one layer of cells, not periodic along z (the core never reads z)
            # that layer as wide as the widest side: the cells' narrowest width, which
            # bounds growing radii, is then in the plane (a width of 1 stopped growth at diameter 1)
            sides = self.sides
            spans = (*sides, max(sides))
            return {"wall_radius": 0.0, "box": x, "span": x, "edges": (*sides, 0.0), "spans": spans}
        return {"wall_radius": 0.0, "box": x, "span": x, "edges": self.sides, "spans": self.sides}

    def check_sphere(self, p: list[float], r: float, v: list[float]) -> str | None:
        """``None``: any sphere fits (the engine checks that the box holds three diameters)."""
        return None

    def outline(
        self, right: np.ndarray, up: np.ndarray, cut: float | None = None, axis: int = 2
    ) -> list[tuple[np.ndarray, bool]]:
        """Its 12 edges (4 in 2-D) seen along ``right x up``: ``(line (2, 2), dashed)`` pairs [length]."""
        import numpy as np

        if self.dimensions == 2:
            hx, hy = (0.5 * x for x in self.sides)
            ring = np.array([[-hx, -hy, 0.0], [hx, -hy, 0.0], [hx, hy, 0.0], [-hx, hy, 0.0]])
            return [
                (np.column_stack([edge @ right[:3], edge @ up[:3]]), False)
                for edge in (ring[[k, (k + 1) % 4]] for k in range(4))
            ]
        hx, hy, hz = (0.5 * x for x in self.sides)
        corners = np.array([[x, y, z] for x in (-hx, hx) for y in (-hy, hy) for z in (-hz, hz)])
        return [
            (np.column_stack([corners[[a, b]] @ right, corners[[a, b]] @ up]), False)
            for a in range(8)
            for b in range(a + 1, 8)
            if np.sum(corners[a] != corners[b]) == 1
        ]


@dataclass(frozen=True)
class CircularContainer(RoundWall):
    """A hard circular wall of radius ``radius`` [length] centred on the origin: 2-D.

    The 2-D analogue of :class:`SphericalContainer`: disks reflect off the
    wall.  Its "volume" is the area ``pi R^2``, its "wall area" the
    perimeter ``2 pi R``, and the pressure the momentum the wall receives
    per unit length and time [energy/length^2].  That wall pressure is not
    the bulk pressure: a curved hard wall carries a line tension (the
    wall's surface excess), so it differs from the bulk's by a term of
    order ``1 / R`` (``p_wall = p_bulk + gamma / R``, gamma the line
    tension; e.g. Urrutia, J. Chem. Phys. 133, 104503 (2010), for hard
    disks in a circle): compare with bulk equations of state in large
    circles only, or use a :class:`PeriodicBox`.

    Example:
        >>> c = CircularContainer(2.0)
        >>> round(c.volume, 4), c.degrees_of_freedom(10), c.dimensions
        (12.5664, 20, 2)
    """

    kind: ClassVar[str] = "CircularContainer"
    size_field: ClassVar[str] = "circle_radius"
    dimensions: ClassVar[int] = 2
    shape: ClassVar[str] = "circular"

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "circle radius"))

    @classmethod
    def for_packing(cls, n: int, packing: float) -> CircularContainer:
        """The circle ``n`` disks of diameter 1 fill to the area fraction ``packing``."""
        n, packing = _n_and_packing(n, packing)
        return cls(math.sqrt(n / (4.0 * packing)))

    @property
    def volume(self) -> float:
        """Area enclosed [length^2]."""
        return math.pi * self.radius**2

    @property
    def wall_area(self) -> float:
        """Length of the wall [length]."""
        return 2.0 * math.pi * self.radius

    area = wall_area

    @property
    def gsd_box(self) -> list[float]:
        """GSD's ``configuration/box``, the enclosing square with ``Lz = 0`` (2-D; not periodic)."""
        side = 2.0 * self.radius
        return [side, side, 0.0, 0.0, 0.0, 0.0]

    def core_params(self) -> dict:
        """What the compiled core reads: the wall, no box, the grid (one layer of cells: 2-D)."""
        span = 2.0 * self.radius
        return {
            "wall_radius": self.radius,
            "box": 0.0,
            "span": span,
            "edges": (0.0, 0.0, 0.0),
            "spans": (span, span, span),  # one layer along z, as wide as the circle (see PeriodicBox)
        }

    def check_sphere(self, p: list[float], r: float, v: list[float]) -> str | None:
        """Why a disk at ``p`` of radius ``r`` moving at ``v`` cannot start here, or ``None``."""
        reach = math.sqrt(p[0] * p[0] + p[1] * p[1]) + r
        if reach > self.radius + TOUCH_TOL * self.radius:
            return f"is not wholly inside the container: |p| + R = {reach:g} > {self.radius:g}"
        if r >= self.radius and (v[0] or v[1]):
            return "fills the container and cannot move; give it zero velocity or a smaller radius"
        return None

    def outline(
        self, right: np.ndarray, up: np.ndarray, cut: float | None = None, axis: int = 2
    ) -> list[tuple[np.ndarray, bool]]:
        """The circle, seen along ``right x up`` [length]."""
        import numpy as np

        u = np.linspace(0, 2 * np.pi, 181)
        ring = np.column_stack([self.radius * np.cos(u), self.radius * np.sin(u), np.zeros_like(u)])
        return [(np.column_stack([ring @ right[:3], ring @ up[:3]]), False)]


#: The containers by :attr:`kind` (files name them so).
KINDS: dict[str, type[SphericalContainer] | type[PeriodicBox] | type[CircularContainer]] = {
    c.kind: c for c in (SphericalContainer, PeriodicBox, CircularContainer)
}


def as_container(
    container: Container | float | None = None, box: float | tuple[float, ...] | None = None
) -> Container:
    """A container from the object, or from the older floats: a radius or a box edge.

    Example:
        >>> as_container(3.0), as_container(box=2.0)
        (SphericalContainer(radius=3.0), PeriodicBox(length=2.0))
    """
    if (container is None) == (box is None):
        raise ContainerError("give exactly one of container (a container or a radius) and box")
    if box is not None:
        return PeriodicBox(box)
    if isinstance(container, Container):
        return container
    return SphericalContainer(container)  # type: ignore[arg-type]  # not None: checked above


def from_record(record: np.ndarray) -> Container:
    """The container :meth:`Container.record` describes."""
    import numpy as np

    entries = [str(x) for x in np.asarray(record).tolist()]
    if len(entries) not in (2, 3):
        raise ContainerError(f"a container record of {len(entries)} entries; expected 2 or 3")
    kind, size = entries[:2]
    if kind not in KINDS:
        raise ContainerError(f"unknown container {kind!r}; known: {', '.join(KINDS)}")
    numbers = [float(x) for x in size.split()]
    if len(entries) == 3:  # a sheared box
        if kind != PeriodicBox.kind:
            raise ContainerError(f"a {kind} is not sheared, but its record has a third entry")
        return PeriodicBox(numbers[0] if len(numbers) == 1 else tuple(numbers), float(entries[2]))
    if len(numbers) == 1:
        return KINDS[kind](numbers[0])
    if kind != PeriodicBox.kind:
        raise ContainerError(f"a {kind} has one size, not {size!r}")
    return PeriodicBox(tuple(numbers))


def _n_and_packing(n: int, packing: float) -> tuple[int, float]:
    """``for_packing``'s arguments checked: ``n`` a whole number >= 1, ``packing`` in (0, 1).

    Raises:
        ContainerError: either is out of range (the message names it).

    Example:
        >>> PeriodicBox.for_packing(100, 0)
        Traceback (most recent call last):
        ...
        hardspheres.errors.ContainerError: packing must be a fraction in (0, 1), got 0; give e.g. 0.3
    """
    try:
        count, phi = int(n), float(packing)
    except (TypeError, ValueError, OverflowError):
        count, phi = -1, math.nan
    if isinstance(n, bool) or count != n or count < 1:
        raise ContainerError(f"n must be a whole number >= 1 (the spheres), got {n!r}")
    if isinstance(packing, bool) or not (0.0 < phi < 1.0):  # NaN fails too
        raise ContainerError(f"packing must be a fraction in (0, 1), got {packing!r}; give e.g. 0.3")
    return count, phi


def from_fields(fields: dict) -> Container:
    """The container whose :meth:`Container.fields` are among ``fields`` (a GSD log, an XYZ header)."""
    import numpy as np

    def number(key: str) -> float:
        return float(np.asarray(fields[key], dtype=np.float64).reshape(-1)[0])

    shear = 0.0
    for key in ("shear_rate", "hardspheres/shear_rate"):
        if key in fields:
            shear = number(key)
    for prefix in ("", "hardspheres/"):
        for d in (3, 2):
            keys = [prefix + k for k in PeriodicBox.side_fields[:d]]
            if all(k in fields for k in keys):
                return PeriodicBox(tuple(number(k) for k in keys), shear)
    for cls in KINDS.values():
        for key in (cls.size_field, f"hardspheres/{cls.size_field}"):
            if key in fields:
                size = float(np.asarray(fields[key], dtype=np.float64).reshape(-1)[0])
                return PeriodicBox(size, shear) if cls is PeriodicBox else cls(size)
    raise ContainerError(
        "no container size found (container_radius, circle_radius, box_length or box_length_x/y[/z])"
    )


#: The densest packing of equal spheres, ``pi / sqrt(18) = 0.74048`` (FCC and
#: HCP; Kepler's conjecture, proved by Hales, Ann. Math. 162, 1065 (2005)).
#: The one home of this constant: every check of a packing fraction uses it.
MAX_PACKING = math.pi / math.sqrt(18.0)

#: The densest packing of equal disks, the triangular lattice's ``pi / (2 sqrt 3) = 0.9069``
#: (Thue; Fejes Toth 1940).  The one home of the 2-D constant.
MAX_PACKING_2D = math.pi / (2.0 * math.sqrt(3.0))


def packing_fraction(radii: ArrayLike, container: Container) -> float:
    """Fraction of the container's volume the spheres of ``radii`` fill.

    Example:
        >>> round(packing_fraction([1.0], PeriodicBox(4.0)), 6)
        0.06545
    """
    import numpy as np

    r = np.asarray(radii, dtype=np.float64)
    if getattr(container, "dimensions", 3) == 2:  # disks: the area fraction
        return float(math.pi * np.sum(r**2) / container.volume)
    return float(4.0 / 3.0 * math.pi * np.sum(r**3) / container.volume)
