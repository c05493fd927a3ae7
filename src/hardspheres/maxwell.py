"""Maxwell-Boltzmann: the equilibrium distribution of velocities, drawn and evaluated.

One home for the distribution: :func:`maxwell_boltzmann` draws velocities
(the builders use it), :func:`speed_density` and :func:`reduced_density`
are its densities of speeds (the plots draw them), :func:`speed_cdf` its
cumulative distribution (validation's Kolmogorov-Smirnov distance).  Each
takes ``dimensions``: 3, or 2 for disks, whose speeds follow the Rayleigh
distribution ``(m v / kT) exp(-m v^2 / (2 kT))``.

Example:
    >>> import numpy as np
    >>> v = maxwell_boltzmann(np.random.default_rng(0), np.ones(1000), kT=2.0)
    >>> round(float(0.5 * np.sum(v * v)) / (1.5 * 999), 12)
    2.0
    >>> round(float(speed_cdf(1e9)), 6), round(float(speed_density(0.0, 1.0, 1.0)), 6)
    (1.0, 0.0)
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from .state import kinetic_energy


def maxwell_boltzmann(
    rng: np.random.Generator, masses: np.ndarray, kT: float = 1.0, dimensions: int = 3
) -> np.ndarray:
    """Velocities drawn at temperature ``kT`` [energy], total momentum zero.

    The draw is rescaled so that the kinetic energy is exactly
    ``d/2 (N - 1) kT`` (zero momentum removes ``d`` degrees of freedom).

    Args:
        rng: a numpy random generator.
        masses: ``(N,)`` [mass].
        kT: temperature [energy].

        dimensions: ``d``, 3 or 2 (disks).

    Returns:
        ``(N, d)`` velocities [length/time] (kinetic energy ``d/2 (N - 1) kT``).

    Raises:
        BuildError: ``kT`` is not a finite number >= 0.
    """
    if not (np.isfinite(kT) and kT >= 0):
        from .errors import BuildError

        raise BuildError(f"kT must be a finite number >= 0 [energy], got {kT!r}")
    n = len(masses)
    d = int(dimensions)
    v = rng.normal(size=(n, d)) * np.sqrt(kT / masses)[:, None]
    if n > 1:
        v -= (masses @ v) / masses.sum()
        ke = kinetic_energy(masses, v)
        if ke > 0:
            v *= np.sqrt(0.5 * d * (n - 1) * kT / ke)
    else:
        v[:] = 0.0
    return v


def speed_density(v: ArrayLike, kT: float, m: float, dimensions: int = 3) -> np.ndarray:
    """Density of speeds ``v`` [length/time] for mass ``m`` at ``kT`` [time/length].

    ``f(v) = 4 pi v^2 (m / (2 pi kT))^{3/2} exp(-m v^2 / (2 kT))``; in 2-D
    ``f(v) = (m v / kT) exp(-m v^2 / (2 kT))``.
    """
    v = np.asarray(v, dtype=float)
    if dimensions == 2:
        return m * v / kT * np.exp(-m * v**2 / (2.0 * kT))
    return 4.0 * np.pi * v**2 * (m / (2.0 * np.pi * kT)) ** 1.5 * np.exp(-m * v**2 / (2.0 * kT))


def reduced_density(x: ArrayLike, dimensions: int = 3) -> np.ndarray:
    """Density of ``x = v sqrt(m / kT)`` (dimensionless), any masses: ``sqrt(2/pi) x^2 exp(-x^2 / 2)``
    (2-D: ``x exp(-x^2 / 2)``)."""
    x = np.asarray(x, dtype=float)
    if dimensions == 2:
        return x * np.exp(-0.5 * x**2)
    return math.sqrt(2.0 / math.pi) * x**2 * np.exp(-0.5 * x**2)


def speed_cdf(v: ArrayLike, kT: float = 1.0, m: float = 1.0, dimensions: int = 3) -> np.ndarray:
    """Cumulative distribution of speeds ``v`` [length/time] for mass ``m`` at ``kT`` (``d`` = 3 or 2).

    Example:
        >>> round(float(speed_cdf(1.0, dimensions=2)), 6)  # 1 - exp(-1/2)
        0.393469
    """
    a = math.sqrt(kT / m)
    x = np.asarray(v) / a
    if dimensions == 2:
        return -np.expm1(-0.5 * x * x)
    erf = np.vectorize(math.erf)
    return erf(x / math.sqrt(2.0)) - np.sqrt(2.0 / math.pi) * x * np.exp(-0.5 * x * x)


#: Mean of the Kolmogorov distribution, sqrt(pi/2) ln 2, which is ``sqrt(n) E[D]``
#: for n independent samples of the right distribution.
KS_MEAN = math.sqrt(math.pi / 2.0) * math.log(2.0)


def ks_distance(speeds: ArrayLike, kT: float = 1.0, m: float = 1.0, dimensions: int = 3) -> float:
    """Largest gap between the speeds' empirical CDF and Maxwell-Boltzmann's (in ``d`` dimensions)."""
    s = np.sort(np.asarray(speeds))
    n = len(s)
    cdf = speed_cdf(s, kT, m, dimensions)
    hi = np.arange(1, n + 1) / n - cdf
    lo = cdf - np.arange(0, n) / n
    return float(max(hi.max(), lo.max()))
