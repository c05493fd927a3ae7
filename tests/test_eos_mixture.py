"""Mixture equations of state (hardspheres.eos): BMCSL and Hansen-Goos & Roth."""

import math

import numpy as np
import pytest

from hardspheres import eos

D, X = [1.4, 1.0], [0.5, 0.5]  # the 50:50 mixture of docs/validation.md


def _bmcsl_xi(eta, diameters, fractions):
    """BMCSL in Mansoori et al.'s (1971) xi_k = pi/6 rho <d^k> form."""
    d, x = np.asarray(diameters, float), np.asarray(fractions, float)
    m = [float(np.sum(x * d**k)) for k in range(4)]
    rho = eta / (math.pi / 6.0 * m[3])
    xi = [math.pi / 6.0 * rho * mk for mk in m]
    e = xi[3]
    p = (6.0 / math.pi) * (
        xi[0] / (1 - e) + 3 * xi[1] * xi[2] / (1 - e) ** 2 + (3 - e) * xi[2] ** 3 / (1 - e) ** 3
    )
    return p / rho


@pytest.mark.parametrize("phi", [0.05, 0.3, 0.4, 0.5])
def test_bmcsl_is_mansoori_et_al(phi):
    assert float(eos.bmcsl(phi, D, X)) == pytest.approx(_bmcsl_xi(phi, D, X), rel=1e-13)


@pytest.mark.parametrize("f", [eos.bmcsl, eos.hansen_goos_roth])
def test_one_component_is_carnahan_starling(f):
    phi = np.linspace(0.01, 0.55, 12)
    cs = eos.carnahan_starling(phi)
    assert np.allclose(f(phi, [2.0], [1.0]), cs, rtol=1e-13)
    assert np.allclose(f(phi, [1.0, 1.0], [0.3, 0.7]), cs, rtol=1e-13)  # equal sizes
    # a published value: Carnahan & Starling (1969), Z = 3.9738 at packing 0.3
    assert round(float(f(0.3, [1.0], [1.0])), 4) == 3.9738


def test_hansen_goos_roth_is_the_white_bear_ii_bulk_pressure():
    """beta p = n0 + sum_a n_a dPhi/dn_a - Phi with Phi the White Bear II free energy density.

    Phi of H. Hansen-Goos and R. Roth, J. Phys.: Condens. Matter 18, 8413
    (2006), bulk (vector densities zero); derivatives by central differences.
    """

    def phi_wb2(n):
        n0, n1, n2, n3 = n
        lg = math.log1p(-n3)
        f2 = (2 * n3 - n3**2 + 2 * (1 - n3) * lg) / n3
        f3 = (2 * n3 - 3 * n3**2 + 2 * n3**3 + 2 * (1 - n3) ** 2 * lg) / n3**2
        return (
            -n0 * lg
            + n1 * n2 * (1 + f2 / 3) / (1 - n3)
            + n2**3 * (1 - f3 / 3) / (24 * math.pi * (1 - n3) ** 2)
        )

    for phi in (0.2, 0.4, 0.5):
        n = np.array(eos._measures(phi, D, X), dtype=float)
        grad = []
        for a in range(4):
            h = 1e-6 * n[a]
            up, dn = n.copy(), n.copy()
            up[a] += h
            dn[a] -= h
            grad.append((phi_wb2(up) - phi_wb2(dn)) / (2 * h))
        beta_p = n[0] + float(np.dot(n, grad)) - phi_wb2(n)
        assert beta_p / n[0] == pytest.approx(float(eos.hansen_goos_roth(phi, D, X)), rel=1e-8)


def test_same_second_and_third_virial_coefficients_as_bmcsl():
    """Both are exact through B3 for additive mixtures: they part at order phi^3."""
    d1 = [float(eos.hansen_goos_roth(p, D, X) - eos.bmcsl(p, D, X)) for p in (1e-3, 2e-3)]
    assert d1[1] / d1[0] == pytest.approx(8.0, rel=1e-2)
    assert abs(d1[0]) < 1e-8


def test_hansen_goos_roth_above_bmcsl_for_unequal_sizes():
    phi = np.array([0.2, 0.3, 0.4, 0.5])
    assert np.all(eos.hansen_goos_roth(phi, D, X) > eos.bmcsl(phi, D, X))


@pytest.mark.parametrize(
    "d, x",
    [([1.0, 2.0], [0.5]), ([1.0, -1.0], [0.5, 0.5]), ([1.0, 2.0], [0.4, 0.4]), ([], [])],
)
def test_bad_mixture_input(d, x):
    with pytest.raises(ValueError):
        eos.bmcsl(0.3, d, x)
    with pytest.raises(ValueError):
        eos.hansen_goos_roth(0.3, d, x)
