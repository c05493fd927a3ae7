"""Equations of state of the hard-sphere and hard-disk fluids: ``Z(phi) = P V / (N kT)``.

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

Hard disks (2-D; ``phi = pi/4 rho sigma^2`` the area fraction):
:func:`kolafa_rottner`, a fit to molecular dynamics extrapolated to infinite
N, up to the liquid-hexatic transition (``phi <= 0.7069``).

Mixtures: :func:`bmcsl` and :func:`hansen_goos_roth` (both built on
Carnahan-Starling) and :func:`santos_yuste_haro` (built on any of the
one-component curves above, KLM by default).

The two accurate ones agree with each other to about 1e-4 for
``phi <= 0.5``, far better than either agrees with Carnahan-Starling:

    >>> round(float(kolafa(0.45) / carnahan_starling(0.45) - 1), 4)
    0.0021
    >>> abs(float(hansen_goos(0.45) / kolafa(0.45) - 1)) < 2e-4
    True
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from .errors import ArgumentError

# Hansen-Goos (2016), Table I: coefficients of the polynomial in phi, highest
# power (7) first, and the prefactor of the logarithm.
_HG_A = 8.0
_HG_B = (-0.096495, 0.248245, 0.041212, -1.265575, -2.635232, 47.0 / 3.0, -19.0, 9.0)

# Kolafa, Labik & Malijevsky (2004): Z = 1 + sum c_k x^k with x = phi/(1-phi).
_KLM = (
    (1, 4.0),
    (2, 6.0),
    (3, 2.3647684),
    (4, -0.8698551),
    (5, 1.1062803),
    (6, -1.1014221),
    (7, 0.66605866),
    (8, -0.03633431),
    (10, -0.20965164),
    (14, 0.10555569),
    (22, -0.00872380),
)

# Kolafa & Rottner (2006), the hard-disk fluid, Eq. (7) of Sec. 3.2 with the
# coefficients of its rho_max = 0.90 fit (p. 3439): Z = sum c_k x^k, x = phi/(1-phi).
# As typed from the paper (doi:10.1080/00268970600967963) in two independent
# public programs, which agree digit for digit (a polydisperse free-volume code
# citing the paper with "rho_max = 0.9", and a script that also types the
# paper's Table 1, the data the test checks the fit against).
_KR_DISKS = (
    (1, 2.0),
    (2, 1.12801775),
    (3, 0.00181895291),
    (4, -0.0526134737),
    (5, 0.0504960168),
    (6, -0.0325537792),
    (7, 0.0134578632),
    (8, 0.00140888182),
    (9, -0.00834273601),
    (10, 0.00694127367),
    (11, -0.00262254723),
    (12, 0.000355746352),
    (22, -5.24672938e-9),
    (57, 5.88054639e-23),
)
#: The largest area fraction Kolafa & Rottner's fit covers, ``pi/4 * 0.90``.
KOLAFA_ROTTNER_MAX = math.pi * 0.90 / 4.0


def _phi(phi: ArrayLike) -> np.ndarray:
    phi = np.asarray(phi, dtype=float)
    if np.any((phi < 0.0) | (phi >= 1.0)):
        raise ArgumentError("packing fraction phi must be in [0, 1)")
    return phi


def carnahan_starling(phi: ArrayLike) -> np.ndarray:
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
    return (1.0 + phi + phi * phi - phi**3) / (1.0 - phi) ** 3


def carnahan_starling_contact(phi: ArrayLike) -> np.ndarray:
    """Carnahan-Starling contact value ``g(sigma+) = (1 - phi/2) / (1 - phi)^3``.

    The radial distribution at contact that makes the virial route give
    :func:`carnahan_starling`: ``Z = 1 + 4 phi g``.

    Example:
        >>> round(float(carnahan_starling_contact(0.3)), 4)
        2.4781
    """
    phi = _phi(phi)
    return (1.0 - 0.5 * phi) / (1.0 - phi) ** 3


def collision_rate_from_z(z: float, sigma: float = 1.0, kT: float = 1.0, mass: float = 1.0) -> float:
    """Collisions per sphere per unit time of equal hard spheres with pressure ``Z``.

    ``nu = 6 (Z - 1) sqrt(kT / (pi m)) / sigma``: exact for hard spheres, since
    both ``Z - 1 = 4 phi g(sigma+)`` (the virial) and the collision frequency
    ``nu = 4 n sigma^2 g(sigma+) sqrt(pi kT / m)`` are set by the contact value
    (Chapman and Cowling, *The Mathematical Theory of Non-uniform Gases*, 3rd
    ed., 1970, ch. 16).  The mean free time is ``1 / nu``.

    Example:
        >>> round(collision_rate_from_z(float(carnahan_starling(0.3))), 3)
        10.067
    """
    return 6.0 * (z - 1.0) * math.sqrt(kT / (math.pi * mass)) / sigma


def hansen_goos(phi: ArrayLike) -> np.ndarray:
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


def kolafa(phi: ArrayLike) -> np.ndarray:
    """Kolafa-Labik-Malijevsky (KLM) equation of state of the hard-sphere fluid.

    J. Kolafa, S. Labik and A. Malijevsky, "Accurate equation of state of
    the hard sphere fluid in stable and metastable regions", Phys. Chem.
    Chem. Phys. 6, 2335 (2004): a power series in ``x = phi / (1 - phi)``::

        Z = 1 + 4x + 6x^2 + 2.3647684x^3 - 0.8698551x^4 + 1.1062803x^5
              - 1.1014221x^6 + 0.66605866x^7 - 0.03633431x^8
              - 0.20965164x^10 + 0.10555569x^14 - 0.00872380x^22

    (the same coefficients as DynamO's hard-sphere pair-correlation
    closure).  The first terms are Carnahan-Starling's ``1 + 4x + 6x^2 +
    2x^3``; the rest make the virial coefficients B4 to B6 exact.  It is a
    fit to the stable and metastable fluid: use it up to packing about
    0.55; beyond, the high powers take over (it peaks near 0.57, 20.3, and
    is negative at 0.6), where :func:`hansen_goos` still rises.

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
        z = z + c * x**k
    return z


def kolafa_rottner(phi: ArrayLike) -> np.ndarray:
    """Kolafa & Rottner's equation of state of the hard-disk fluid (2-D).

    J. Kolafa and M. Rottner, "Simulation-based equation of state of the
    hard disk fluid and prediction of higher-order virial coefficients",
    Mol. Phys. 104, 3435 (2006) (arXiv:cond-mat/0608356), Eq. (7), the fit
    with ``rho_max = 0.90`` (their Sec. 3.2, p. 3439), a power series in
    ``x = phi / (1 - phi)``::

        Z = 1 + 2x + 1.12801775x^2 + 0.00181895291x^3 - 0.0526134737x^4
              + 0.0504960168x^5 - 0.0325537792x^6 + 0.0134578632x^7
              + 0.00140888182x^8 - 0.00834273601x^9 + 0.00694127367x^10
              - 0.00262254723x^11 + 0.000355746352x^12
              - 5.24672938e-9 x^22 + 5.88054639e-23 x^57

    ``phi = pi rho sigma^2 / 4`` is the area fraction.  The series has the
    exact virial coefficients B2 to B4 (``Z = 1 + 2 phi + 3.12801775 phi^2
    + 4.25785 phi^3 + ...``) and is fitted to their molecular dynamics
    extrapolated to infinite N (standard errors of Z 2e-6 to 1e-4
    relative).  Its range is ``phi <= 0.7069`` (reduced density 0.90); the
    paper warns that densities 0.89-0.90 (phi 0.699-0.707) "may be affected
    by finite-size effects".  Beyond 0.7069 the x^57 term takes over:
    values there are refused.

    Where the coefficients come from: as two independent public programs
    type them from the paper, agreeing digit for digit on this fit; tests/test_disks_eos.py checks it
    against the paper's Table 1 (their Z at reduced densities 0.40-0.90,
    as the second program types it) and against the exact B2-B4.

    Args:
        phi: area fraction(s), dimensionless, in [0, :data:`KOLAFA_ROTTNER_MAX`].

    Returns:
        Z = PA/(NkT), dimensionless.

    Raises:
        ValueError: ``phi`` outside the fit's range.

    Example:
        Their Table 1, reduced density 0.70: ``Z = 5.082362(19)``:

        >>> import math
        >>> round(float(kolafa_rottner(math.pi * 0.70 / 4)), 5)
        5.08237
    """
    phi = np.asarray(phi, dtype=float)
    if np.any((phi < 0.0) | (phi > KOLAFA_ROTTNER_MAX)):
        raise ArgumentError(
            f"area fraction phi must be in [0, {KOLAFA_ROTTNER_MAX:.4f}] for Kolafa & Rottner's "
            "hard-disk fit (reduced density 0.90); denser is the hexatic or the solid"
        )
    x = phi / (1.0 - phi)
    z = np.ones_like(x)
    for k, c in _KR_DISKS:
        z = z + c * x**k
    return z


# ---- mixtures ----------------------------------------------------------------------


def _measures(
    phi: ArrayLike, diameters: ArrayLike, fractions: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The bulk fundamental measures ``n0..n3`` of a mixture at packing ``phi``.

    ``n0 = rho``, ``n1 = rho <R>``, ``n2 = 4 pi rho <R^2>``, ``n3 = phi``
    (``R`` the radii, ``<.>`` the average over mole fractions).
    """
    phi = _phi(phi)
    d = np.asarray(diameters, dtype=float)
    x = np.asarray(fractions, dtype=float)
    if d.ndim != 1 or d.shape != x.shape or d.size == 0:
        raise ArgumentError("diameters and fractions must be 1-d arrays of the same length")
    if np.any(d <= 0) or np.any(x < 0) or not np.isclose(x.sum(), 1.0):
        raise ArgumentError("diameters must be > 0 and the mole fractions >= 0, summing to 1")
    r = 0.5 * d
    rho = phi / (4.0 * np.pi / 3.0 * np.sum(x * r**3))
    return rho, rho * np.sum(x * r), 4.0 * np.pi * rho * np.sum(x * r**2), phi


def bmcsl(phi: ArrayLike, diameters: ArrayLike, fractions: ArrayLike) -> np.ndarray:
    """Boublik-Mansoori-Carnahan-Starling-Leland (BMCSL) Z of a hard-sphere mixture.

    T. Boublik, J. Chem. Phys. 53, 471 (1970); G. A. Mansoori, N. F.
    Carnahan, K. E. Starling and T. W. Leland, J. Chem. Phys. 54, 1523
    (1971).  In the fundamental measures ``n0..n3`` (:func:`hansen_goos_roth`)::

        Z rho = n0/(1-n3) + n1 n2/(1-n3)^2 + n2^3 (3 - n3) / (36 pi (1-n3)^3)

    Exact through the third virial coefficient; Carnahan-Starling for one
    component.  It is known to fall slightly below simulations of
    size-asymmetric mixtures (D. M. Heyes and A. Santos, "Chemical potential
    of a test hard sphere of variable size in hard-sphere fluid mixtures",
    abstract).

    Args:
        phi: total packing fraction(s) in [0, 1).
        diameters: ``(K,)`` diameters of the K components (any unit).
        fractions: ``(K,)`` their mole (number) fractions, summing to 1.

    Returns:
        Z = PV/(NkT), dimensionless.

    Example:
        >>> round(float(bmcsl(0.3, [1.0], [1.0])), 4) == round(float(carnahan_starling(0.3)), 4)
        True
    """
    n0, n1, n2, n3 = _measures(phi, diameters, fractions)
    g = 1.0 - n3
    return (n0 / g + n1 * n2 / g**2 + n2**3 * (3.0 - n3) / (36.0 * np.pi * g**3)) / n0


def hansen_goos_roth(phi: ArrayLike, diameters: ArrayLike, fractions: ArrayLike) -> np.ndarray:
    """Hansen-Goos & Roth's Z of a hard-sphere mixture (a "CS" generalization).

    H. Hansen-Goos and R. Roth, J. Chem. Phys. 124, 154506 (2006): a
    generalization of Carnahan-Starling to additive mixtures, as the bulk
    limit of their White Bear mark II density functional (J. Phys.:
    Condens. Matter 18, 8413 (2006))::

        Z rho = n0/(1-n3) + n1 n2 (1 + n3^2/3)/(1-n3)^2
                + n2^3 (1 - 2 n3/3 + n3^2/3) / (12 pi (1-n3)^3)

    with ``n0 = rho``, ``n1 = rho <R>``, ``n2 = 4 pi rho <R^2>``, ``n3 =
    phi``.  This form is checked (tests/test_eos_mixture.py) against the
    pressure ``n0 + sum_a n_a dPhi/dn_a - Phi`` of the White Bear II free
    energy density ``Phi`` as thermotools/SurfPack implements it
    (``surfpack/FMT.py``, ``WhiteBearMarkII``): they agree to rounding.
    For one component it is Carnahan-Starling exactly, and it has BMCSL's
    (exact) second and third virial coefficients; it lies above BMCSL for
    unequal sizes.

    Args:
        phi: total packing fraction(s) in [0, 1).
        diameters: ``(K,)`` diameters of the K components.
        fractions: ``(K,)`` their mole fractions, summing to 1.

    Returns:
        Z = PV/(NkT), dimensionless.

    Example:
        The 50:50 mixture of radius ratio 1.4 at packing 0.4 lies above
        BMCSL:

        >>> z = hansen_goos_roth(0.4, [1.4, 1.0], [0.5, 0.5])
        >>> round(float(z / bmcsl(0.4, [1.4, 1.0], [0.5, 0.5]) - 1), 4)
        0.0006
    """
    n0, n1, n2, n3 = _measures(phi, diameters, fractions)
    g = 1.0 - n3
    return (
        n0 / g
        + n1 * n2 * (1.0 + n3**2 / 3.0) / g**2
        + n2**3 * (1.0 - 2.0 * n3 / 3.0 + n3**2 / 3.0) / (12.0 * np.pi * g**3)
    ) / n0


def santos_yuste_haro(
    phi: ArrayLike,
    diameters: ArrayLike,
    fractions: ArrayLike,
    pure: Callable[[ArrayLike], np.ndarray] = kolafa,
) -> np.ndarray:
    """Santos, Yuste & Lopez de Haro's Z of a hard-sphere mixture from a one-component Z.

    A. Santos, S. B. Yuste and M. Lopez de Haro, "Equation of state of a
    multicomponent d-dimensional hard-sphere fluid", Mol. Phys. 96, 1 (1999)
    (the "e1" recipe; listed as arXiv cond-mat/0204246 on tomesphere.com).  The recipe, as its abstract
    states it: the contact values ``g_ij`` of the mixture's pair
    distributions depend on the sizes only through ``z_ij = (sigma_i
    sigma_j / sigma_ij) M2 / M3`` (``M_n = <sigma^n>`` over mole fractions,
    ``sigma_ij = (sigma_i + sigma_j)/2``) and are linear in it, as in the
    Percus-Yevick solution (Lebowitz 1964), with the coefficients fixed by
    the exact point-particle limit ``g(z = 0) = 1/(1 - phi)`` and the
    one-component limit ``g(z = 1) = g_s(phi) = (Z_s - 1)/(4 phi)``::

        g_ij = 1/(1 - phi) + [g_s(phi) - 1/(1 - phi)] z_ij

    The virial route, ``Z = 1 + (4 phi/M3) sum_ij x_i x_j sigma_ij^3
    g_ij``, then gives (the sums done in closed form)::

        Z = 1 + phi/(1 - phi) (1 + A - 2 B) + (Z_s - 1) (A + B)/2,
        A = M1 M2 / M3,  B = M2^3 / M3^2.

    This closed form is derived from the recipe above (as the paper's
    abstract states it).
    It is the same equation as the later form of Santos and co-workers
    (2005, for nonadditive mixtures) that thermopack implements
    (thermotools/thermopack, ``src/saftvrmie_hardsphere.f90``,
    ``calc_hardsphere_helmholtzenergy_santos``: excess free energy
    ``F12 (-ln(1 - phi)) + F22 a_s(phi)`` with ``F12 = (b3 B2 - b2 B3)/(b3 -
    b2)``, ``F22 = (B3 - B2)/(b3 - b2)``, ``b2, b3 = 4, 10`` the
    one-component and ``B2, B3`` the mixture's reduced virial
    coefficients): for additive spheres ``B2 = 1 + 3A`` and ``B3 = 1 + 6A +
    3B`` (exact, BMCSL's), so ``F12 = 1 + A - 2B`` and ``F22 = (A + B)/2``.
    Checked in tests/test_eos_mixture.py: it is ``Z_s`` for one component
    and for equal sizes, it has the exact second virial coefficient for any
    ``Z_s`` with ``B2`` right and BMCSL's exact third for any ``Z_s`` with
    ``B3`` right (``Z_s = 1 + 4 phi + 10 phi^2 + ...``), and with the
    Percus-Yevick (virial) ``Z_s`` it is the Percus-Yevick virial mixture
    equation.  With Carnahan-Starling as ``Z_s`` it lies above BMCSL for
    unequal sizes (the paper reports it closer to simulation than BMCSL).
    Unlike BMCSL and Hansen-Goos & Roth it inherits the accuracy of
    ``pure``: the default is :func:`kolafa`.

    Args:
        phi: total packing fraction(s) in [0, 1).
        diameters: ``(K,)`` diameters of the K components.
        fractions: ``(K,)`` their mole fractions, summing to 1.
        pure: the one-component ``Z_s(phi)`` (:func:`kolafa`, up to packing
            about 0.55, :func:`hansen_goos` or :func:`carnahan_starling`).

    Returns:
        Z = PV/(NkT), dimensionless.

    Example:
        One component gives ``pure`` back; the 50:50 mixture of radius
        ratio 1.4 at packing 0.4, built on KLM, lies 0.4% above BMCSL:

        >>> float(santos_yuste_haro(0.4, [2.0], [1.0])) == float(kolafa(0.4))
        True
        >>> z = santos_yuste_haro(0.4, [1.4, 1.0], [0.5, 0.5])
        >>> round(float(z), 4), round(float(z / bmcsl(0.4, [1.4, 1.0], [0.5, 0.5]) - 1), 4)
        (6.636, 0.0038)
    """
    _measures(phi, diameters, fractions)  # validates the arguments
    phi = _phi(phi)
    d = np.asarray(diameters, dtype=float)
    x = np.asarray(fractions, dtype=float)
    d = d / np.max(d)  # scale-free: only ratios of moments enter
    m1, m2, m3 = (float(np.sum(x * d**k)) for k in (1, 2, 3))
    a = m1 * m2 / m3
    b = m2**3 / m3**2
    return 1.0 + phi / (1.0 - phi) * (1.0 + a - 2.0 * b) + (pure(phi) - 1.0) * (0.5 * (a + b))


def speedy_fcc(phi: ArrayLike) -> np.ndarray:
    """Speedy's equation of state of the hard-sphere FCC crystal.

    R. J. Speedy, "Pressure and entropy of hard-sphere crystals", J. Phys.:
    Condens. Matter 10, 4387 (1998), Eq. (2) with the FCC row of its
    Table 1::

        Z = 3 / (1 - z) - A (z - b) / (z - c),   z = rho sigma^3 / sqrt(2)

    (``z`` the density over close packing's, ``z = phi / (pi sqrt(2) /
    6)``), ``A = 0.5921``, ``b = 0.7072``, ``c = 0.601``: a fit to
    simulations of the crystal between melting (``phi`` about 0.545) and
    close packing (Table 1's coefficients as SklogWiki's page "Equations of
    state for crystals of hard spheres" quotes them).  It gives the coexistence pressure at the solid's
    coexistence packing, 0.5433 (Fernandez et al. 2012): ``beta P sigma^3
    = 11.57``, below.

    Args:
        phi: packing fraction(s) of the crystal, in (0.4451, 0.7405): above
            the fit's pole ``z = c`` (``phi = 0.4451``), below close packing.

    Returns:
        Z, dimensionless.

    Example:
        >>> phi = 0.5433
        >>> round(float(6 * phi * speedy_fcc(phi) / math.pi), 2)
        11.57
    """
    phi = np.asarray(phi, dtype=float)
    close = math.pi * math.sqrt(2.0) / 6.0
    z = phi / close
    if np.any((z <= _SPEEDY_FCC[2]) | (z >= 1.0)):
        raise ArgumentError(f"Speedy's crystal fit needs phi in ({_SPEEDY_FCC[2] * close:.4f}, {close:.4f})")
    a, b, c = _SPEEDY_FCC
    return 3.0 / (1.0 - z) - a * (z - b) / (z - c)


#: Speedy (1998), Table 1, FCC: ``A, b, c``.
_SPEEDY_FCC = (0.5921, 0.7072, 0.601)


def packing_at_pressure(
    pressure: float,
    eos: Callable[[ArrayLike], np.ndarray] | None = None,
    bounds: tuple[float, float] = (0.0, 0.6),
    dimensions: int = 3,
) -> float:
    """The packing fraction at reduced pressure ``beta P sigma^d``: the inverse of ``eos``.

    Solves ``phi Z(phi) / v_d = beta P sigma^d`` (``rho sigma^d = phi /
    v_d``, ``v_3 = pi / 6``, ``v_2 = pi / 4``: disks' area fraction) by
    bisection on ``bounds`` to the last bit (``phi Z`` is increasing there);
    ``eos`` is :func:`hansen_goos` by default (:func:`speedy_fcc` for the
    crystal with ``bounds=(0.5, 0.74)``, :func:`kolafa_rottner` for disks
    with ``dimensions=2``).  What a constant-pressure run should find on
    average (in the thermodynamic limit).

    Args:
        pressure: ``beta P sigma^d``, > 0, between ``eos``'s at the bounds.
        eos: ``Z(phi)``, with ``phi Z`` increasing on ``bounds``.
        bounds: the packings searched.
        dimensions: 3, or 2 for disks.

    Example:
        >>> phi = packing_at_pressure(5.0)
        >>> round(phi, 6), round(float(6 * phi * hansen_goos(phi) / math.pi), 12)
        (0.392914, 5.0)
    """
    f = hansen_goos if eos is None else eos
    vd = math.pi / 6.0 if dimensions == 3 else math.pi / 4.0
    p = float(pressure)
    if not (math.isfinite(p) and p > 0.0):
        raise ArgumentError(f"pressure must be a finite number > 0, got {pressure!r}")

    def bp(phi: float) -> float:
        return phi * float(f(phi)) / vd if phi > 0.0 else 0.0

    lo, hi = (float(x) for x in bounds)
    if not bp(lo) <= p < bp(hi):
        raise ArgumentError(
            f"pressure {p:g} is outside the equation of state's {bp(lo):.6g} to {bp(hi):.6g} "
            f"(packings {lo:g} to {hi:g}); give a pressure in that range"
        )
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return hi if bp(hi) - p < p - bp(lo) else lo
        if bp(mid) < p:
            lo = mid
        else:
            hi = mid


def inverse_compressibility(
    phi: ArrayLike, eos: Callable[[ArrayLike], np.ndarray] | None = None
) -> np.ndarray:
    """``d(beta P) / d rho = d(phi Z) / d phi``: the inverse of ``rho kT kappa_T``, dimensionless.

    At constant pressure it sets the volume's fluctuations, ``<dV^2> /
    <V>^2 = 1 / (N d(phi Z)/d phi)`` (the fluctuation formula ``<dV^2> =
    kT V kappa_T``; e.g. Allen & Tildesley, *Computer Simulation of Liquids*,
    2nd ed. 2017, section 2.5; in 2-D the same with the area).  A central difference of ``phi Z(phi)``
    with step ``1e-5`` (``eos``'s error is far larger than the step's
    ``1e-10``); ``eos`` is :func:`hansen_goos` by default.

    Example:
        >>> round(float(inverse_compressibility(1e-3)), 4)  # 1 + 8 phi + ... at low density
        1.008
    """
    f = hansen_goos if eos is None else eos
    x = _phi(phi)
    h = 1e-5
    lo = np.maximum(x - h, 0.0)
    return ((x + h) * f(x + h) - lo * f(lo)) / (x + h - lo)


#: Reference equations of state by name (as ``plot`` and ``validate`` use them).
REFERENCES = {"Carnahan-Starling": carnahan_starling, "Hansen-Goos": hansen_goos, "KLM": kolafa}
