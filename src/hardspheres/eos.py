"""Equations of state of the hard-sphere fluid: ``Z(phi) = P V / (N kT)``.

One home for the reference curves the library compares with (``validate``,
``plot eos``, ``plot sweep``).  ``phi`` is the packing fraction (dimensionless,
``pi/6 rho sigma^3``); every function takes a float or an array and returns
the same shape.

* :func:`carnahan_starling`: the classic closed form, good to a few 0.1%
  at liquid densities (it is low by 0.2-0.3% at phi 0.3-0.45).
* :func:`kolafa`: Kolafa, Labik & Malijevsky (KLM, 2004), a fit to
  molecular dynamics with relative errors below 4e-5 (95%) that reproduces
  the virial coefficients B2 to B6.
* :func:`hansen_goos`: Hansen-Goos (2016), a fit of similar accuracy over
  the whole fluid range.

The two accurate ones agree with each other to about 1e-4 for
``phi <= 0.5``, far better than either agrees with Carnahan-Starling:

    >>> round(float(kolafa(0.45) / carnahan_starling(0.45) - 1), 4)
    0.0021
    >>> abs(float(hansen_goos(0.45) / kolafa(0.45) - 1)) < 2e-4
    True
"""

import numpy as np

# Hansen-Goos (2016), Table I: coefficients of the polynomial in phi, highest
# power (7) first, and the prefactor of the logarithm.
_HG_A = 8.0
_HG_B = (-0.096495, 0.248245, 0.041212, -1.265575, -2.635232, 47.0 / 3.0, -19.0, 9.0)

# Kolafa, Labik & Malijevsky (2004): Z = 1 + sum c_k x^k with x = phi/(1-phi).
_KLM = ((1, 4.0), (2, 6.0), (3, 2.3647684), (4, -0.8698551), (5, 1.1062803),
        (6, -1.1014221), (7, 0.66605866), (8, -0.03633431), (10, -0.20965164),
        (14, 0.10555569), (22, -0.00872380))


def _phi(phi):
    phi = np.asarray(phi, dtype=float)
    if np.any((phi < 0.0) | (phi >= 1.0)):
        raise ValueError("packing fraction phi must be in [0, 1)")
    return phi


def carnahan_starling(phi):
    """Carnahan-Starling ``Z = (1 + phi + phi^2 - phi^3) / (1 - phi)^3``.

    N. F. Carnahan and K. E. Starling, J. Chem. Phys. 51, 635 (1969).

    Args:
        phi: packing fraction(s), dimensionless, in [0, 1).

    Returns:
        Z, dimensionless (float array of ``phi``'s shape).

    Example:
        >>> round(float(carnahan_starling(0.3)), 4)
        3.9738
    """
    phi = _phi(phi)
    return (1.0 + phi + phi * phi - phi ** 3) / (1.0 - phi) ** 3


def hansen_goos(phi):
    """Hansen-Goos equation of state of the hard-sphere fluid.

    H. Hansen-Goos, "Communication: Non-linear fits to the hard-sphere
    equation of state", J. Chem. Phys. 144, 164506 (2016), Eq. (6) with the
    coefficients of its Table I::

        Z = a ln(1 - phi) / phi + sum_k b_k phi^k / (1 - phi)^3

    with ``a = 8`` and ``b_0..b_7 = 9, -19, 47/3, -2.635232, -1.265575,
    0.041212, 0.248245, -0.096495``.  At ``phi -> 0`` it tends to 1.

    Args:
        phi: packing fraction(s), dimensionless, in [0, 1).

    Returns:
        Z, dimensionless.

    Example:
        Allen & Tildesley (Computer Simulation of Liquids, 2nd ed., 2017,
        examples) print ``P = 1.6347`` from this equation at number
        density ``rho = 0.5`` (``sigma = kT = 1``):

        >>> import math
        >>> round(0.5 * float(hansen_goos(math.pi * 0.5 / 6)), 4)
        1.6347
    """
    phi = _phi(phi)
    small = phi < 1e-6
    safe = np.where(small, 0.5, phi)
    z = _HG_A * np.log1p(-safe) / safe + np.polyval(_HG_B, safe) / (1.0 - safe) ** 3
    # series near 0: Z = 1 + 4 phi + O(phi^2)
    return np.where(small, 1.0 + 4.0 * phi, z)


def kolafa(phi):
    """Kolafa-Labik-Malijevsky (KLM) equation of state of the hard-sphere fluid.

    J. Kolafa, S. Labik and A. Malijevsky, "Accurate equation of state of
    the hard sphere fluid in stable and metastable regions", Phys. Chem.
    Chem. Phys. 6, 2335 (2004): a power series in ``x = phi / (1 - phi)``::

        Z = 1 + 4x + 6x^2 + 2.3647684x^3 - 0.8698551x^4 + 1.1062803x^5
              - 1.1014221x^6 + 0.66605866x^7 - 0.03633431x^8
              - 0.20965164x^10 + 0.10555569x^14 - 0.00872380x^22

    (the same coefficients as DynamO's hard-sphere pair-correlation
    closure).  The first terms are Carnahan-Starling's ``1 + 4x + 6x^2 +
    2x^3``; the rest make the virial coefficients B4 to B6 exact.

    Args:
        phi: packing fraction(s), dimensionless, in [0, 1).

    Returns:
        Z, dimensionless.

    Example:
        The fourth virial coefficient, ``B4 / b^3 = 18.3648`` with
        ``b = 2 pi sigma^3 / 3``, from the series' low-density slope:

        >>> p = 1e-3
        >>> z3 = (kolafa(p) - 1 - 4 * p - 10 * p * p) / p ** 3
        >>> round(float(z3), 1)
        18.4
    """
    phi = _phi(phi)
    x = phi / (1.0 - phi)
    z = np.ones_like(x)
    for k, c in _KLM:
        z = z + c * x ** k
    return z


#: Reference equations of state by name (as ``plot`` and ``validate`` use them).
REFERENCES = {"Carnahan-Starling": carnahan_starling, "Hansen-Goos": hansen_goos,
              "KLM": kolafa}
