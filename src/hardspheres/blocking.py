"""Error bars of time averages: Flyvbjerg-Petersen blocking.

A time series from a simulation is correlated, so the naive standard error
``std / sqrt(n)`` is too small.  Blocking (H. Flyvbjerg and H. G. Petersen,
J. Chem. Phys. 91, 461 (1989)) averages neighbouring pairs again and again;
once the blocks are longer than the correlation time the estimate of the
standard error of the mean stops growing (a plateau) and that value is the
error bar.  If it never stops growing, the run is too short for an error
bar: :func:`blocking` says so (``converged`` false) instead of reporting the
still-rising estimate as if it were one.

Example:
    >>> import numpy as np
    >>> x = np.random.default_rng(1).normal(size=4096)
    >>> b = blocking(x)
    >>> b.converged, round(b.sem / (1 / 64), 1)  # white noise: std / sqrt(n)
    (True, 1.0)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .errors import ArgumentError

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: Fewest blocks a level may have to be used for the error bar.
MIN_BLOCKS = 16


class Blocking(NamedTuple):
    """The result of :func:`blocking`.

    Attributes:
        mean: mean of the series.
        sem: standard error of the mean: the plateau value (the larger of
            the plateau's first two levels), or, without a plateau, the
            largest estimate over the usable levels.
        level: the blocking level chosen (blocks of ``2**level`` samples).
        n_blocks: number of blocks at that level.
        converged: whether the estimates reached a plateau (the correlation
            check).  If not, ``sem`` is a lower bound: run longer.
        sems: ``(levels,)`` the estimate at each level.
        sem_errors: ``(levels,)`` the statistical error of each estimate,
            ``sem / sqrt(2 (n - 1))``.
    """

    mean: float
    sem: float
    level: int
    n_blocks: int
    converged: bool
    sems: np.ndarray
    sem_errors: np.ndarray

    def plot(self, ax: Axes | None = None) -> Axes:
        """The estimate against the blocking level, with the chosen one marked; returns Axes."""
        from .extras import need

        plt = need("matplotlib.pyplot", "plot")

        ax = plt.figure().add_subplot() if ax is None else ax
        lv = np.arange(len(self.sems))
        ax.errorbar(lv, self.sems, yerr=self.sem_errors, fmt="o-", ms=3)
        ax.axhline(self.sem, ls="--", color="grey")
        ax.set_xlabel("blocking level (blocks of 2^level samples)")
        ax.set_ylabel("standard error of the mean")
        ax.set_title("plateau" if self.converged else "no plateau: run longer")
        return ax


def blocking(x: ArrayLike, min_blocks: int = MIN_BLOCKS) -> Blocking:
    """Mean and standard error of a correlated series by Flyvbjerg-Petersen blocking.

    At level ``k`` the series has been pair-averaged ``k`` times (an odd last
    sample is dropped); the estimate is ``s_k = std_k / sqrt(n_k - 1)`` with
    error ``s_k / sqrt(2 (n_k - 1))``.  The plateau is the first level whose
    estimate is not exceeded by the next two levels' by more than their
    joint error (so growth has stopped) and by no usable later level's by
    more than twice their joint error; levels with fewer than
    ``min_blocks`` blocks are not trusted to decide.

    Args:
        x: ``(n,)`` samples, equally spaced in time.
        min_blocks: fewest blocks a level needs to be used.

    Raises:
        ValueError: fewer than two samples.
    """
    x = np.asarray(x, dtype=np.float64).reshape(-1)
    if x.size < 2:
        raise ArgumentError(f"{x.size} samples: an error bar needs at least two; run longer")
    mean = float(np.mean(x))
    sem_list: list[float] = []
    err_list: list[float] = []
    count_list: list[int] = []
    y = x
    while y.size >= 2:
        n = y.size
        s = float(np.sqrt(np.var(y) / (n - 1)))
        sem_list.append(s)
        err_list.append(s / np.sqrt(2.0 * (n - 1)))
        count_list.append(n)
        m = n // 2
        y = 0.5 * (y[0 : 2 * m : 2] + y[1 : 2 * m : 2])
    sems, errs, counts = np.array(sem_list), np.array(err_list), np.array(count_list)
    usable = np.nonzero(counts >= min(min_blocks, counts[0]))[0]
    last = int(usable[-1])
    level, converged = None, False
    for k in range(last - 1):
        rise1 = sems[k + 1] - sems[k]
        rise2 = sems[k + 2] - sems[k]
        later = sems[k + 1 : last + 1] - sems[k]
        if (
            rise1 <= np.hypot(errs[k], errs[k + 1])
            and rise2 <= np.hypot(errs[k], errs[k + 2])
            and np.all(later <= 2.0 * np.hypot(errs[k], errs[k + 1 : last + 1]))
        ):
            level, converged = k, True
            break
    if level is None:
        level = int(np.argmax(sems[: last + 1]))
        sem = sems[level]
    else:
        # the plateau's first level still underestimates a little when the
        # correlation time is long: the larger of it and the next level
        # (AR(1) series, correlation time 200 samples, 2^14 samples: mean
        # sem/true 0.96 this way, 0.90 from the first level alone)
        sem = max(sems[level], sems[level + 1])
    return Blocking(mean, float(sem), level, int(counts[level]), converged, sems, errs)
