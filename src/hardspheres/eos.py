"""Equations of state of the hard-sphere fluid.

Example:
    >>> round(float(carnahan_starling(0.3)), 4)
    3.9738
"""

from __future__ import annotations

import numpy as np


def carnahan_starling(phi):
    """Carnahan-Starling compressibility factor ``Z = (1 + phi + phi^2 - phi^3) / (1 - phi)^3``.

    Args:
        phi: packing fraction(s) (dimensionless); a float or an array.

    Returns:
        ``Z`` (dimensionless), a float for a float, else an array.
    """
    p = np.asarray(phi, dtype=float)
    z = (1.0 + p + p**2 - p**3) / (1.0 - p) ** 3
    return z if z.ndim else float(z)
