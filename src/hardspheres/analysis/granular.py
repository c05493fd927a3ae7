"""Clustering of granular gases: S(k) at the box's smallest wave vectors and the local density.

A cooling granular gas larger than the critical length of the homogeneous
cooling state (docs/guide/granular.md, "Clusters") forms clusters: density
fluctuations at the longest wavelengths grow.  Two measures see it:

* :class:`LowKStructureFactor`: ``S(k) = |sum_j exp(i k . r_j)|^2 / N`` at
  the periodic box's smallest wave vectors, ``k = 2 pi n / L`` with the
  integer vectors ``n`` of the first shells (``|n| = 1``, then ``sqrt 2``,
  ...), for each configuration: a time series that grows as clusters form
  and otherwise stays at the fluid's value (below 1: the compressibility's
  limit ``S(k -> 0)``).  The same definition as
  :class:`~hardspheres.analysis.structure.StructureFactor` (freud's direct
  method), with numpy alone: at so few wave vectors the direct sum is cheap.
* :class:`LocalDensity`: each sphere's local packing fraction, its own
  volume over its Voronoi cell's (freud) or its cell's packing fraction on a
  grid of cells (numpy), and their histogram.

Both need a periodic box.

Example:
    >>> import hardspheres as hs
    >>> box = hs.PeriodicBox.for_packing(400, 0.1, (1.0, 1.0))
    >>> sim = hs.Simulation(hs.random_spheres(400, 0.1, box, seed=1), box)
    >>> s = LowKStructureFactor(shells=1).compute(sim)
    >>> s.k.round(4).tolist(), bool(0.3 < s.S[0] < 3.0)
    ([0.1121], True)
    >>> dens = LocalDensity(method="cells").compute(sim)
    >>> dens.values.shape, int(dens.counts.sum())
    ((1, 400), 400)
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..containers import PeriodicBox
from ..errors import AnalysisInputError
from .compute import Compute
from .structure import _freud_box, _wrap, configurations

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from .structure import Edge, Source

#: The ways :class:`LocalDensity` measures it.
METHODS = ("auto", "voronoi", "cells")


def _times(source: object, frames: int) -> np.ndarray:
    """The configurations' times (a Frames' or a Simulation's), else ``nan``."""
    from ..frames import Frames
    from ..simulation import Simulation

    if isinstance(source, Frames):
        return np.asarray(source.times, float).reshape(-1)[:frames].copy()
    if isinstance(source, Simulation):
        return np.array([source.time])
    return np.full(frames, math.nan)


def shell_vectors(sides: tuple[float, ...], shells: int) -> tuple[np.ndarray, np.ndarray]:
    """The wave vectors of the box's first ``shells`` shells, one of each ``+-k`` pair.

    Args:
        sides: the box's sides [length] (2 or 3 of them).
        shells: how many of the smallest distinct ``|k|`` to take (>= 1).

    Returns:
        ``(kvectors (M, d), shell (M,))``: the vectors [1/length] and the
        index of the shell each belongs to, shells in increasing ``|k|``.
    """
    d = len(sides)
    reach = shells + 1
    grid = np.array(np.meshgrid(*[np.arange(-reach, reach + 1)] * d, indexing="ij")).reshape(d, -1).T
    # one of each pair: the first non-zero component positive
    first = np.array([row[np.nonzero(row)[0][0]] if np.any(row) else 0 for row in grid])
    grid = grid[first > 0]
    k = 2.0 * np.pi * grid / np.asarray(sides, float)
    mag = np.round(np.linalg.norm(k, axis=1), 10)
    levels = np.unique(mag)[:shells]
    keep = np.isin(mag, levels)
    return k[keep], np.searchsorted(levels, mag[keep])


class LowKStructureFactor(Compute):
    """S(k) at the box's smallest wave vectors, per configuration: clustering's growth.

    Args:
        shells: how many of the smallest ``|k|`` to measure (1: ``2 pi / L``
            for a cube or square).

    After :meth:`compute`: ``k``, ``(shells,)`` the shells' ``|k|``
    [1/length]; ``S``, ``(shells,)`` S(k) averaged over the configurations
    and each shell's vectors; ``S_frames``, ``(F, shells)`` the same per
    configuration; ``times``, ``(F,)`` the configurations' times (``nan``
    for bare positions).
    """

    _results = ("k", "S", "S_frames", "times")

    def __init__(self, shells: int = 1) -> None:
        if not (isinstance(shells, int) and shells >= 1):
            raise AnalysisInputError(f"shells must be a whole number >= 1, got {shells!r}")
        self.shells = shells

    def compute(self, source: Source, box: Edge | None = None) -> LowKStructureFactor:
        """S(k) of each of ``source``'s configurations (a periodic box); returns self."""
        L, pos, _ = configurations(source, box)
        sides = PeriodicBox(L).sides
        d = len(sides)
        if pos.shape[-1] != d or pos.shape[1] == 0:
            raise AnalysisInputError(f"positions of shape {pos.shape} in a {d}-D box: give (F, N, {d})")
        kvec, shell = shell_vectors(tuple(sides), self.shells)
        n = pos.shape[1]
        per = np.empty((len(pos), self.shells))
        for f, x in enumerate(pos):
            phase = x @ kvec.T  # (N, M)
            rho2 = np.cos(phase).sum(axis=0) ** 2 + np.sin(phase).sum(axis=0) ** 2
            per[f] = np.bincount(shell, weights=rho2 / n, minlength=self.shells) / np.bincount(shell)
        self.k = np.unique(np.round(np.linalg.norm(kvec, axis=1), 10))[: self.shells]
        self.S_frames = per
        self.S = per.mean(axis=0)
        self.times = _times(source, len(pos))
        self._computed = True
        return self

    def plot(self, ax: Axes | None = None) -> Axes:
        """S at the smallest ``|k|`` against time (or configuration); returns the Axes."""
        ax = self._axes(ax)
        x = self.times if np.all(np.isfinite(self.times)) else np.arange(len(self.S_frames))
        ax.plot(x, self.S_frames[:, 0])
        ax.set_xlabel("t" if x is self.times else "configuration")
        ax.set_ylabel(f"S(k = {self.k[0]:.3g})")
        return ax


class LocalDensity(Compute):
    """Each sphere's local packing fraction and its histogram.

    Args:
        method: ``"voronoi"``: the sphere's volume over its Voronoi cell's
            (freud: ``pip install hardspheres[analysis]``); ``"cells"``: the
            packing fraction of the grid cell that holds its centre (numpy;
            spheres counted whole in the cell of their centre);
            ``"auto"``: Voronoi if freud is installed, else cells.
        cell: the cells' smallest side [length], for ``"cells"``; default:
            the side that holds 8 spheres at the mean density, at least two
            diameters.
        bins: histogram bins between 0 and the densest packing (equal
            spheres: 0.7405, disks: 0.9069) [1].

    After :meth:`compute`: ``values``, ``(F, N)`` each sphere's local
    packing fraction [1]; ``counts`` and ``edges`` (``bins + 1`` of them),
    the histogram of ``values`` over all configurations; ``method``, the
    method used (``"voronoi"`` or ``"cells"``).
    """

    _results = ("values", "counts", "edges")

    def __init__(self, method: str = "auto", cell: float | None = None, bins: int = 40) -> None:
        if method not in METHODS:
            raise AnalysisInputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        if cell is not None and not (math.isfinite(cell) and cell > 0):
            raise AnalysisInputError(f"cell must be a length > 0, got {cell!r}")
        if not (isinstance(bins, int) and bins >= 1):
            raise AnalysisInputError(f"bins must be a whole number >= 1, got {bins!r}")
        self.requested, self.cell, self.bins = method, cell, bins
        self.method = method

    def compute(
        self, source: Source, box: Edge | None = None, radii: np.ndarray | None = None
    ) -> LocalDensity:
        """The local packing fraction of every sphere of every configuration; returns self.

        ``radii`` [length]: for bare positions, which carry none.
        """
        L, pos, known = configurations(source, box)
        radii = known if known is not None else radii
        sides = np.asarray(PeriodicBox(L).sides, float)
        d = len(sides)
        n = pos.shape[1]
        if radii is None or len(radii) != n:
            raise AnalysisInputError("sphere radii unknown: give a Simulation, Frames or State, or radii")
        radii = np.asarray(radii, float)
        if n == 0:
            raise AnalysisInputError("no spheres: nothing to measure")
        own = (np.pi * radii**2) if d == 2 else (4.0 / 3.0 * np.pi * radii**3)
        method = self.requested
        if method == "auto":
            from ..errors import MissingExtraError
            from ..extras import need

            try:
                need("freud", "the Voronoi local density")
                method = "voronoi"
            except MissingExtraError:
                method = "cells"
        values = np.empty((len(pos), n))
        if method == "voronoi":
            values[:] = self._voronoi(L, pos, own)
        else:
            values[:] = self._cells(sides, pos, own)
        self.method = method
        self.values = values
        top = 0.9069 if d == 2 else 0.7405
        self.counts, self.edges = np.histogram(
            values, bins=self.bins, range=(0.0, max(top, float(values.max())))
        )
        self._computed = True
        return self

    @staticmethod
    def _voronoi(L: Edge, pos: np.ndarray, own: np.ndarray) -> np.ndarray:
        from ..extras import need

        freud = need("freud", "the Voronoi local density (method='voronoi')")
        fbox = _freud_box(freud, L)
        vor = freud.locality.Voronoi()
        out = np.empty(pos.shape[:2])
        for f, x in enumerate(pos):
            vor.compute((fbox, _wrap(x, L)))
            out[f] = own / np.asarray(vor.volumes, float)
        return out

    def _cells(self, sides: np.ndarray, pos: np.ndarray, own: np.ndarray) -> np.ndarray:
        d, n = len(sides), pos.shape[1]
        volume = float(np.prod(sides))
        diameter = 2.0 * float((own.mean() / (np.pi if d == 2 else 4.0 / 3.0 * np.pi)) ** (1.0 / d))
        side = self.cell or max(2.0 * diameter, (8.0 * volume / n) ** (1.0 / d))
        m = np.maximum(1, np.floor(sides / side)).astype(np.int64)
        cell_volume = volume / float(np.prod(m))
        box = PeriodicBox(tuple(float(x) for x in sides))
        out = np.empty(pos.shape[:2])
        for f, x in enumerate(pos):
            w = box.wrap(x) + sides / 2.0  # into [0, L)
            idx = np.minimum((w / sides * m).astype(np.int64), m - 1)
            flat = np.ravel_multi_index(tuple(idx.T), tuple(m))
            filled = np.bincount(flat, weights=own, minlength=int(np.prod(m))) / cell_volume
            out[f] = filled[flat]
        return out

    def plot(self, ax: Axes | None = None) -> Axes:
        """The histogram of the local packing fraction (a density); returns the Axes."""
        ax = self._axes(ax)
        widths = np.diff(self.edges)
        total = self.counts.sum()
        ax.stairs(self.counts / (total * widths) if total else self.counts, self.edges)
        ax.set_xlabel(f"local packing fraction ({self.method})")
        ax.set_ylabel("probability density")
        return ax
