"""The closest pair of a periodic box, relative to contact: one compiled kernel.

:func:`closest_ratio` is what a constant-pressure volume move
(:mod:`hardspheres.barostat`) asks before it squeezes the box: the least
``d_ij / (R_i + R_j)`` over all pairs, with ``d_ij`` the minimum-image
distance.  A move that scales every centre with the box creates no overlap
exactly when that ratio, in the scaled box, is at least 1.

Cells of at least the largest contact distance per axis (at most about
``2 N^(1/3)`` per axis) (all cells along an
axis with fewer than three), so each pair is seen once or, in a small box,
a few times (harmless for a minimum).  ``O(N)`` for a box of many cells.

Example:
    >>> import numpy as np
    >>> x = np.array([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0], [-3.0, 2.0, 0.0]])
    >>> float(closest_ratio(x, np.full(3, 0.5), np.array([8.0, 8.0, 8.0])))
    1.5
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


@numba.njit(cache=True, nogil=True)
def _closest(
    x: np.ndarray, radii: np.ndarray, sides: np.ndarray, sigma_max: float
) -> float:  # pragma: no cover (compiled)
    n = x.shape[0]
    nc = np.empty(3, np.int64)
    most = int(np.ceil(2.0 * n ** (1.0 / 3.0))) + 1  # about 8 cells per sphere at most
    for a in range(3):
        k = int(sides[a] / sigma_max) if sigma_max > 0.0 else 1
        nc[a] = max(1, min(k, most))
    ncell = nc[0] * nc[1] * nc[2]
    head = np.full(ncell, -1, np.int64)
    nxt = np.full(n, -1, np.int64)
    cell = np.empty((n, 3), np.int64)
    for i in range(n):
        for a in range(3):
            u = x[i, a] / sides[a] + 0.5
            u -= np.floor(u)
            c = int(u * nc[a])
            if c >= nc[a]:
                c = nc[a] - 1
            if c < 0:
                c = 0
            cell[i, a] = c
        flat = (cell[i, 2] * nc[1] + cell[i, 1]) * nc[0] + cell[i, 0]
        nxt[i] = head[flat]
        head[flat] = i
    best = np.inf
    span = np.empty(3, np.int64)
    for a in range(3):
        span[a] = 3 if nc[a] >= 3 else nc[a]
    for i in range(n):
        for oz in range(span[2]):
            cz = (cell[i, 2] + oz - 1) % nc[2] if nc[2] >= 3 else oz
            for oy in range(span[1]):
                cy = (cell[i, 1] + oy - 1) % nc[1] if nc[1] >= 3 else oy
                for ox in range(span[0]):
                    cx = (cell[i, 0] + ox - 1) % nc[0] if nc[0] >= 3 else ox
                    j = head[(cz * nc[1] + cy) * nc[0] + cx]
                    while j >= 0:
                        if j > i:
                            d2 = 0.0
                            for a in range(3):
                                d = x[i, a] - x[j, a]
                                d -= sides[a] * np.round(d / sides[a])
                                d2 += d * d
                            s = radii[i] + radii[j]
                            if s > 0.0:
                                r = np.sqrt(d2) / s
                                if r < best:
                                    best = r
                        j = nxt[j]
    return best


def closest_ratio(positions: ArrayLike, radii: ArrayLike, sides: ArrayLike) -> float:
    """Least ``d_ij / (R_i + R_j)`` over pairs in a periodic box of ``sides`` (``inf``: none near).

    Args:
        positions: ``(N, 3)`` centres [length] (any image), or ``(N, 2)``
            with two ``sides`` (disks).
        radii: ``(N,)`` [length].
        sides: ``(3,)`` the box's sides [length], each at least three
            largest diameters (the engine's own bound), or ``(2,)`` in 2-D.

    Returns:
        The ratio for the closest pair among those nearer than the largest
        contact distance; ``inf`` if no pair is that near.
    """
    r = np.ascontiguousarray(radii, dtype=np.float64).reshape(-1)
    L = np.asarray(sides, dtype=np.float64).reshape(-1)
    sigma_max = 2.0 * float(r.max()) if r.size else 0.0
    if L.size == 2:  # disks: z = 0 in one layer of cells (a side too short for two)
        x = np.zeros((r.size, 3))
        x[:, :2] = np.asarray(positions, dtype=np.float64).reshape(-1, 2)
        L = np.array([L[0], L[1], 1.5 * sigma_max if sigma_max > 0.0 else 1.0])
    else:
        x = np.ascontiguousarray(positions, dtype=np.float64).reshape(-1, 3)
        L = np.ascontiguousarray(L).reshape(3)
    if x.shape[0] < 2:
        return np.inf
    return float(_closest(x, r, L, sigma_max))
