"""The assignment's text report (``shared/conformance/README.md``'s layout).

Numbers print with ``:g``; the container radius and end time print as
``str(float(x))``.  Writers take positions and velocities as sequences of
``[x, y, z]`` (lists, or numpy arrays, which are converted once per block).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import IO, TYPE_CHECKING

from ..events import KIND_LABELS, EventKind

if TYPE_CHECKING:
    import numpy as np

_REFLECTION = int(EventKind.REFLECTION)

PROMPT = (
    "Please enter the mass, radius, x/y/z position, x/y/z velocity\n"
    "and name of each sphere\n"
    "When complete, use EOF / Ctrl-D to stop entering\n"
)

_VECS = "%g,%g,%g) v=(%g,%g,%g)\n"


class TextReport:
    """Writes the assignment's report to a text stream.

    Args:
        names, masses, radii: the spheres, in input order.
        out: a text stream (``write`` is called with large chunks).

    Example:
        >>> import io
        >>> out = io.StringIO()
        >>> rep = TextReport(["a"], [2.0], [1.0], out)
        >>> rep.initial(10.0, 5.0, [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]])
        >>> print(out.getvalue(), end="")
        <BLANKLINE>
        Here are the initial conditions.
        universe radius 10.0
        end simulation 5.0
        a m=2 R=1 p=(0,0,0) v=(1,0,0)
        energy: 1
        momentum: (2,0,0)
        <BLANKLINE>
        Here are the events.
    """

    def __init__(
        self,
        names: Sequence[str],
        masses: Sequence[float] | np.ndarray,
        radii: Sequence[float] | np.ndarray,
        out: IO[str],
    ) -> None:
        self.names = list(names)
        self.masses = [float(m) for m in masses]
        self.out = out
        self._prefix = [f"{nm} m={m:g} R={r:g} p=(" for nm, m, r in zip(self.names, self.masses, radii)]
        self._fmt: str | None = None

    def _block(
        self,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> str:
        if hasattr(positions, "shape"):
            return self._block_arrays(positions, velocities)
        parts = []
        e = px = py = pz = 0.0
        for pre, m, p, v in zip(self._prefix, self.masses, positions, velocities):
            parts.append(pre)
            parts.append(_VECS % (p[0], p[1], p[2], v[0], v[1], v[2]))
            vx, vy, vz = v
            e += 0.5 * m * (vx * vx + vy * vy + vz * vz)
            px += m * vx
            py += m * vy
            pz += m * vz
        parts.append(f"energy: {e:g}\nmomentum: ({px:g},{py:g},{pz:g})\n")
        return "".join(parts)

    def _block_arrays(
        self,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> str:
        """The same block from numpy arrays, one formatting call for all lines.

        Sums accumulate in input order (``cumsum`` is sequential), so the
        totals are bit-identical to the list path's.
        """
        import numpy as np

        if self._fmt is None:
            self._fmt = "".join(pre.replace("%", "%%") + _VECS for pre in self._prefix)
            self._m = np.array(self.masses)
        n = len(self.masses)
        if n == 0:
            return "energy: 0\nmomentum: (0,0,0)\n"
        both = np.empty((n, 6))
        both[:, :3] = positions
        both[:, 3:] = velocities
        m = self._m
        vx, vy, vz = both[:, 3], both[:, 4], both[:, 5]
        e = float(np.cumsum(0.5 * m * (vx * vx + vy * vy + vz * vz))[-1])
        px = float(np.cumsum(m * vx)[-1])
        py = float(np.cumsum(m * vy)[-1])
        pz = float(np.cumsum(m * vz)[-1])
        return self._fmt % tuple(both.ravel().tolist()) + f"energy: {e:g}\nmomentum: ({px:g},{py:g},{pz:g})\n"

    def initial(
        self,
        container: float,
        end: float,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> None:
        """The initial conditions, through ``Here are the events.``"""
        self.out.write(
            f"\nHere are the initial conditions.\nuniverse radius {float(container)}\n"
            f"end simulation {float(end)}\n" + self._block(positions, velocities) + "\nHere are the events.\n"
        )

    def event(
        self,
        t: float,
        kind: int,
        i: int,
        j: int,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> None:
        """One event: an :class:`~hardspheres.events.EventKind` of ``i`` (and ``j``)."""
        what = (
            f"reflecting {self.names[i]}"
            if kind == _REFLECTION
            else f"colliding {self.names[i]} {self.names[j]}"
        )
        self.out.write(f"\ntime of event: {t:g}\n{what}\n" + self._block(positions, velocities))


class JSONLReport:
    r"""The same run as one JSON object per line, every digit kept.

    The first line describes the start (``"kind": "initial"``, container
    radius, end time, every sphere); then one line per event with its time,
    kind (``"collision"`` or ``"reflection"``), the names of the spheres
    involved, and their positions and velocities just after it.

    Example:
        >>> import io
        >>> out = io.StringIO()
        >>> rep = JSONLReport(["a"], [2.0], [1.0], out)
        >>> rep.event(1.5, 0, 0, -1, [[9.0, 0.0, 0.0]], [[-1.0, 0.0, 0.0]])
        >>> out.getvalue()
        '{"time": 1.5, "kind": "reflection", "spheres": ["a"], "p": [[9.0, 0.0, 0.0]], "v": [[-1.0, 0.0, 0.0]]}\n'
    """

    def __init__(
        self,
        names: Sequence[str],
        masses: Sequence[float] | np.ndarray,
        radii: Sequence[float] | np.ndarray,
        out: IO[str],
    ) -> None:
        import json

        self._dumps = json.dumps
        self.names = list(names)
        self.masses = [float(m) for m in masses]
        self.radii = [float(r) for r in radii]
        self.out = out

    def initial(
        self,
        container: float,
        end: float,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> None:
        spheres = [
            {"name": nm, "m": m, "R": r, "p": list(map(float, p)), "v": list(map(float, v))}
            for nm, m, r, p, v in zip(self.names, self.masses, self.radii, positions, velocities)
        ]
        self.out.write(
            self._dumps(
                {"kind": "initial", "radius": float(container), "end": float(end), "spheres": spheres}
            )
            + "\n"
        )

    def event(
        self,
        t: float,
        kind: int,
        i: int,
        j: int,
        positions: Sequence[Sequence[float]] | np.ndarray,
        velocities: Sequence[Sequence[float]] | np.ndarray,
    ) -> None:
        who = [i] if kind == _REFLECTION else [i, j]
        self.out.write(
            self._dumps(
                {
                    "time": float(t),
                    "kind": KIND_LABELS[kind],
                    "spheres": [self.names[k] for k in who],
                    "p": [list(map(float, positions[k])) for k in who],
                    "v": [list(map(float, velocities[k])) for k in who],
                }
            )
            + "\n"
        )
