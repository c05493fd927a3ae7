"""Containers: where the spheres live.

* :class:`SphericalContainer`: the assignment's hard spherical wall centred
  on the origin; spheres reflect off it.
* :class:`PeriodicBox`: a cube centred on the origin with periodic
  boundaries and minimum-image collisions, for bulk matter (no walls).
"""

import math
from dataclasses import dataclass


class PeriodicBoxRequired(ValueError):
    """Images, unwrapped positions and transport need a :class:`PeriodicBox`."""


def require_periodic(container, what):
    """The box edge of ``container``; :class:`PeriodicBoxRequired` if it is not a periodic box."""
    if not isinstance(container, PeriodicBox):
        raise PeriodicBoxRequired(
            f"{what} need a periodic box (a container's wall bounds the motion and makes "
            "the fluid non-uniform); simulate in hs.PeriodicBox(L)")
    return container.length


@dataclass(frozen=True)
class SphericalContainer:
    """A hard spherical wall of radius ``radius`` [length] centred on the origin.

    Example:
        >>> round(SphericalContainer(1.0).volume, 6)
        4.18879
    """

    radius: float

    def __post_init__(self):
        if not (math.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"container radius must be a finite number > 0, got {self.radius}")

    @property
    def volume(self):
        """Volume enclosed [length^3]."""
        return 4.0 / 3.0 * math.pi * self.radius ** 3

    @property
    def area(self):
        """Area of the wall [length^2]."""
        return 4.0 * math.pi * self.radius ** 2

    def engine_args(self):
        return {"container": self.radius}


@dataclass(frozen=True)
class PeriodicBox:
    """A periodic cube of edge ``length`` [length] centred on the origin.

    Example:
        >>> PeriodicBox(2.0).volume
        8.0
    """

    length: float

    def __post_init__(self):
        if not (math.isfinite(self.length) and self.length > 0):
            raise ValueError(f"box length must be a finite number > 0, got {self.length}")

    @property
    def volume(self):
        """Volume of the box [length^3]."""
        return self.length ** 3

    def engine_args(self):
        return {"box": self.length}
