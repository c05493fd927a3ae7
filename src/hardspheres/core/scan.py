"""The reference's rules at O(N) numpy work per event: the assignment's program with no compilation.

:class:`Scan` is :class:`~hardspheres.core.reference.Reference` (same
constructor, methods and results, bit for bit) in a spherical or circular
container without growth, with the search for the next event kept up to
date instead of redone:

* every pair's prediction (from the later of its two spheres' own times,
  the lower index's centre minus the higher's: the reference's arithmetic,
  elementwise in numpy, which rounds each operation as Python floats do)
  is kept in an ``N x N`` table, and every wall's in a vector;
* an event changes only the rows of the one or two spheres it touched, so
  after it those rows are predicted again: O(N) numpy work;
* each row keeps its earliest entry (and the first column holding it); a
  row whose earliest entry was a changed one is scanned again;
* the next event is then read off the rows with the reference's tie order
  and simultaneity window (every prediction before ``clock + window``
  counts as at the clock; among them reflections first, then the lowest
  ``(i, j)``).

A pair whose lengths or speeds fall outside the kernels' safe range (the
rare rescaled path of :func:`~hardspheres.physics.pair_time_within`) is
predicted by the scalar kernel itself.  So the event sequence is the
reference's, and the compiled engine's, to the bit
(tests/test_scan.py).  Memory: ``8 N^2`` bytes (8 MB at ``N = 1000``).

The assignment's program runs it for more than
:data:`~hardspheres.cli.assignment.SMALL` spheres when the compiled core is
not yet in numba's cache: it needs numpy only, and starts in a fraction of
a second where the first compilation takes far longer.

Example:
    >>> scan = Scan([1.0, 1.0], [1.0, 1.0], [[-5.0, 0, 0], [5.0, 0, 0]],
    ...             [[1.0, 0, 0], [-1.0, 0, 0]], container=100.0)
    >>> scan.step(until=10.0)
    (4.0, 1, 0, 1)
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..containers import Container
from ..errors import ArgumentError
from ..physics import INF, LAGRANGE_RATIO, RANGE_HI, RANGE_LO, SQUARES_LO, pair_time, wall_time_grow
from .reference import COLLISION, REFLECTION, Reference

#: The most spheres :class:`Scan` takes (its table is ``8 N^2`` bytes).
MAX_SPHERES = 4096


def _pair_times(
    pi: np.ndarray,
    vi: np.ndarray,
    ti: np.ndarray | float,
    pj: np.ndarray,
    vj: np.ndarray,
    tj: np.ndarray | float,
    sigma: np.ndarray,
    planar: bool,
) -> np.ndarray:
    """Collision times of pairs ``(i, j)``, ``i`` the lower index: the reference's arithmetic, elementwise.

    ``pi, vi, pj, vj`` are ``(k, 3)`` (or ``(3,)``, broadcast), ``ti, tj``
    own times, ``sigma`` the contact distances.  Each operation is the one
    :func:`~hardspheres.core.reference.next_event` and
    :func:`~hardspheres.physics.pair_time_within` make, in their order.
    """
    t0 = np.maximum(ti, tj)
    di = t0 - ti
    dj = t0 - tj
    di = di[:, None] if np.ndim(di) else di
    dj = dj[:, None] if np.ndim(dj) else dj
    d = (pi + vi * di) - (pj + vj * dj)
    dv = vi - vj
    dv = np.broadcast_to(dv, d.shape)
    dx, dy, dz = d[:, 0], d[:, 1], d[:, 2]
    dvx, dvy, dvz = dv[:, 0], dv[:, 1], dv[:, 2]
    if planar:
        b = dx * dvx + dy * dvy
        a = dvx * dvx + dvy * dvy
        r2 = dx * dx + dy * dy
    else:
        b = dx * dvx + dy * dvy + dz * dvz
        a = dvx * dvx + dvy * dvy + dvz * dvz
        r2 = dx * dx + dy * dy + dz * dz
    ar2 = a * r2
    rare = (b <= 0.0) & ~((RANGE_LO <= ar2) & (ar2 <= RANGE_HI) & (a >= SQUARES_LO) & (r2 >= SQUARES_LO))
    c = r2 - sigma * sigma
    s2 = sigma * sigma
    uz = dx * dvy - dy * dvx
    if planar:
        far = a * s2 - uz * uz
    else:
        ux = dy * dvz - dz * dvy
        uy = dz * dvx - dx * dvz
        far = a * s2 - (ux * ux + uy * uy + uz * uz)
    disc = np.where(r2 > LAGRANGE_RATIO * s2, far, b * b - a * c)
    with np.errstate(all="ignore"):
        t = c / (np.sqrt(disc) - b)
    t = np.where(disc <= 0.0, INF, t)
    t = np.where(c <= 0.0, 0.0, t)
    t = np.where(b >= 0.0, INF, t)
    te = t0 + t
    for k in np.flatnonzero(rare):  # the kernel's own rescaled path
        te[k] = t0[k] + pair_time(
            float(dx[k]), float(dy[k]), float(dz[k]), float(dvx[k]), float(dvy[k]), float(dvz[k]),
            float(sigma[k]), planar,
        )  # fmt: skip
    return te


class Scan(Reference):
    """Exact event-driven dynamics in a spherical or circular container, O(N) numpy work per event.

    Arguments, methods and results are :class:`Reference`'s, to the bit;
    periodic boxes and growth are refused (:class:`ArgumentError`).

    Args:
        masses, radii, positions, velocities, container, box, window, time,
        rebase, restitution, wall_restitution, tc: as :class:`Reference`
            (at most :data:`MAX_SPHERES` spheres; the collision rule changes
            velocities only, so the scan's predictions are those of elastic
            spheres' arithmetic, as the reference's).
    """

    def __init__(
        self,
        masses: Sequence[float],
        radii: Sequence[float],
        positions: Sequence[Sequence[float]],
        velocities: Sequence[Sequence[float]],
        container: Container | float | None = None,
        box: float | None = None,
        window: float = 0.0,
        time: float = 0.0,
        rebase: bool = False,
        restitution: float = 1.0,
        wall_restitution: float | None = None,
        tc: float = 0.0,
    ) -> None:
        super().__init__(
            masses, radii, positions, velocities, container, box, window, time, rebase,
            restitution, wall_restitution, tc,
        )  # fmt: skip
        n = self.n
        if self._edges[0]:
            raise ArgumentError("Scan runs in a sphere or a circle; use Engine for a periodic box")
        if n > MAX_SPHERES:
            raise ArgumentError(f"Scan takes at most {MAX_SPHERES} spheres, not {n}; use Engine")
        self._P = np.array(self._p, dtype=float).reshape(n, 3)
        self._V = np.array(self._v, dtype=float).reshape(n, 3)
        self._T = np.array(self._tloc, dtype=float)
        self._R = np.array(self._radii, dtype=float)
        self._walls = np.full(n, INF)
        # the pairs' times (i < j in row i; the rest inf), each row's earliest and its first column
        self._pairs = np.full((n, n), INF)
        for i in range(n - 1):
            self._pairs[i, i + 1 :] = self._row(i, np.arange(i + 1, n))
        for i in range(n):
            self._walls[i] = self._wall_of(i)
        self._first = np.argmin(self._pairs, axis=1) if n else np.zeros(0, dtype=np.intp)
        self._least = self._pairs[np.arange(n), self._first]

    def set_growth(self, rate: float) -> None:
        """Refused: :class:`Scan` has no growth (use :class:`Reference` or the engine)."""
        raise ArgumentError("Scan has no growth; use Engine or Reference")

    def _row(self, i: int, js: np.ndarray) -> np.ndarray:
        """Times of the pairs ``(i, j)`` for ``j`` in ``js`` (all above ``i``)."""
        return _pair_times(
            self._P[i], self._V[i], self._T[i], self._P[js], self._V[js], self._T[js],
            self._R[i] + self._R[js], self.dimensions == 2,
        )  # fmt: skip

    def _column(self, j: int, is_: np.ndarray) -> np.ndarray:
        """Times of the pairs ``(i, j)`` for ``i`` in ``is_`` (all below ``j``)."""
        return _pair_times(
            self._P[is_], self._V[is_], self._T[is_], self._P[j], self._V[j], self._T[j],
            self._R[is_] + self._R[j], self.dimensions == 2,
        )  # fmt: skip

    def _wall_of(self, i: int) -> float:
        """Sphere ``i``'s reflection time (the reference's arithmetic)."""
        pi, vi = self._p[i], self._v[i]
        reach = self._wall - self._radii[i]
        return self._tloc[i] + wall_time_grow(
            pi[0], pi[1], pi[2], vi[0], vi[1], vi[2], reach, 0.0, self.dimensions == 2
        )

    def _touched(self, i: int) -> None:
        """Sphere ``i`` has moved and changed course: its wall and its row and column predicted again."""
        n = self.n
        self._P[i] = self._p[i]
        self._V[i] = self._v[i]
        self._T[i] = self._tloc[i]
        self._walls[i] = self._wall_of(i)
        pairs, least, first = self._pairs, self._least, self._first
        if i + 1 < n:
            pairs[i, i + 1 :] = self._row(i, np.arange(i + 1, n))
            k = int(np.argmin(pairs[i]))
            first[i], least[i] = k, pairs[i, k]
        else:
            least[i] = INF
        if i == 0:
            return
        above = np.arange(i)
        new = self._column(i, above)
        pairs[:i, i] = new
        head, low = first[:i], least[:i]
        # rows whose earliest entry was this one and grew: scanned again
        again = np.flatnonzero((head == i) & (new > low))
        better = (new < low) | ((new == low) & (i < head))
        low[better] = new[better]
        head[better] = i
        if again.size:
            ks = np.argmin(pairs[again], axis=1)
            first[again] = ks
            least[again] = pairs[again, ks]

    def _process(self, until: float) -> tuple[float, int, int, int, float, float, float, float] | None:
        done = super()._process(until)
        if done is not None:
            self._touched(done[2])
            if done[3] >= 0:
                self._touched(done[3])
        return done

    def _next(self) -> tuple[float, int, int, int]:
        """The next event ``(t, kind, i, j)``, as :func:`~hardspheres.core.reference.next_event` finds it."""
        clock = self._clock
        soon = clock + self._window
        walls, least = self._walls, self._least
        if not walls.size:
            return INF, -1, -1, -1
        wi = int(np.argmax(walls < soon))
        if walls[wi] < soon:
            tw = clock
        else:
            wi = int(np.argmin(walls))
            tw = float(walls[wi])
        pi = int(np.argmax(least < soon))
        if least[pi] < soon:
            tp = clock
            pj = int(np.argmax(self._pairs[pi] < soon))
        else:
            pi = int(np.argmin(least))
            tp = float(least[pi])
            pj = int(self._first[pi])
        if tw == INF and tp == INF:
            return INF, -1, -1, -1
        if tw <= tp:
            return tw, REFLECTION, wi, -1
        return tp, COLLISION, pi, pj
