"""Mixture equations of state (hardspheres.eos): BMCSL and Hansen-Goos & Roth."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hardspheres import eos

D, X = [1.4, 1.0], [0.5, 0.5]  # the 50:50 mixture of docs/validation/dense.md


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


# ---- Santos, Yuste & Lopez de Haro (1999): a mixture built on a one-component Z ------


def _virial_route(eta, diameters, fractions, contact):
    """Z = 1 + (4 eta / M3) sum_ij x_i x_j sigma_ij^3 g_ij, by the explicit double sum.

    ``contact(eta, z)`` gives g_ij from z_ij = (sigma_i sigma_j / sigma_ij) M2 / M3
    (Hansen & McDonald, Theory of Simple Liquids, the virial pressure of a
    hard-sphere mixture).
    """
    d, x = np.asarray(diameters, float), np.asarray(fractions, float)
    m2, m3 = float(np.sum(x * d**2)), float(np.sum(x * d**3))
    total = 0.0
    for i in range(d.size):
        for j in range(d.size):
            sij = 0.5 * (d[i] + d[j])
            z = d[i] * d[j] / sij * m2 / m3
            total += x[i] * x[j] * sij**3 * contact(eta, z)
    return 1.0 + 4.0 * eta / m3 * total


def _boublik(eta, z):
    """Boublik's (1970) contact values, BMCSL's (as in Chapman et al. 1990, Eq. 25)."""
    return 1 / (1 - eta) + 1.5 * eta * z / (1 - eta) ** 2 + 0.5 * (eta * z) ** 2 / (1 - eta) ** 3


def _py_contact(eta, z):
    """Percus-Yevick contact values of an additive mixture (Lebowitz, Phys. Rev. 133, A895, 1964)."""
    return 1 / (1 - eta) + 1.5 * eta * z / (1 - eta) ** 2


def _py_virial_one(eta):
    """Percus-Yevick one-component Z by the virial route: (1 + 2 eta + 3 eta^2)/(1 - eta)^2."""
    return (1 + 2 * eta + 3 * eta**2) / (1 - eta) ** 2


MIXTURES = [
    (D, X),
    ([1.0, 3.0], [0.9, 0.1]),
    ([0.5, 1.0, 2.5], [0.2, 0.5, 0.3]),
    ([1.0, 1.1, 1.2, 5.0], [0.25, 0.25, 0.25, 0.25]),
]


@pytest.mark.parametrize("d, x", MIXTURES)
def test_virial_route_helper_gives_bmcsl_from_boublik_contact_values(d, x):
    """The helper's sums and z_ij are right: Boublik's contact values give BMCSL."""
    for eta in (0.1, 0.3, 0.5):
        assert _virial_route(eta, d, x, _boublik) == pytest.approx(float(eos.bmcsl(eta, d, x)), rel=1e-13)


@pytest.mark.parametrize("d, x", MIXTURES)
@pytest.mark.parametrize("pure", [eos.kolafa, eos.hansen_goos, eos.carnahan_starling])
def test_syh_is_the_virial_route_of_contact_values_linear_in_z(d, x, pure):
    """The closed form is the recipe: g_ij = 1/(1-eta) + [g_s - 1/(1-eta)] z_ij."""
    for eta in (0.05, 0.3, 0.45, 0.55):
        g_s = (float(pure(eta)) - 1) / (4 * eta)

        def linear(e, z, g_s=g_s):
            return 1 / (1 - e) + (g_s - 1 / (1 - e)) * z

        assert float(eos.santos_yuste_haro(eta, d, x, pure=pure)) == pytest.approx(
            _virial_route(eta, d, x, linear), rel=1e-13
        )


@pytest.mark.parametrize("d, x", MIXTURES)
def test_syh_on_percus_yevick_is_the_percus_yevick_mixture(d, x):
    """PY's contact values are linear in z_ij, so the recipe reproduces PY's virial route."""
    for eta in (0.1, 0.3, 0.5):
        assert float(eos.santos_yuste_haro(eta, d, x, pure=_py_virial_one)) == pytest.approx(
            _virial_route(eta, d, x, _py_contact), rel=1e-13
        )


@pytest.mark.parametrize("pure", [eos.kolafa, eos.hansen_goos, eos.carnahan_starling])
def test_syh_one_component_and_equal_sizes_give_the_pure_fluid(pure):
    phi = np.linspace(0.01, 0.55, 12)
    zs = pure(phi)
    assert np.allclose(eos.santos_yuste_haro(phi, [2.0], [1.0], pure=pure), zs, rtol=1e-14)
    assert np.allclose(
        eos.santos_yuste_haro(phi, [1.3, 1.3, 1.3], [0.2, 0.3, 0.5], pure=pure), zs, rtol=1e-14
    )


@pytest.mark.parametrize("d, x", MIXTURES)
@pytest.mark.parametrize("pure", [eos.kolafa, eos.hansen_goos, eos.carnahan_starling])
def test_syh_exact_second_and_third_virial_coefficients(d, x, pure):
    """BMCSL is exact through B3; so is the recipe when Z_s = 1 + 4 eta + 10 eta^2 + ...

    The difference from BMCSL starts at eta^3 (doubling eta multiplies it by 8).
    """
    diff = [float(eos.santos_yuste_haro(p, d, x, pure=pure) - eos.bmcsl(p, d, x)) for p in (1e-3, 2e-3)]
    assert abs(diff[0]) < 1e-7
    assert diff[1] / diff[0] == pytest.approx(8.0, rel=2e-2)


def test_syh_second_virial_coefficient_with_a_wrong_third():
    """With a Z_s wrong at eta^2 (Z_s = 1 + 4 eta) the mixture's B2 stays exact."""

    def pure(eta):
        return 1 + 4 * np.asarray(eta, float)

    for d, x in MIXTURES:
        eta = np.array([1e-4, 2e-4])
        diff = eos.santos_yuste_haro(eta, d, x, pure=pure) - eos.bmcsl(eta, d, x)
        assert diff[1] / diff[0] == pytest.approx(4.0, rel=1e-2)  # starts at eta^2


def test_syh_scale_free_and_above_bmcsl_on_carnahan_starling():
    phi = np.array([0.2, 0.3, 0.4, 0.5])
    z = eos.santos_yuste_haro(phi, D, X)
    assert np.allclose(eos.santos_yuste_haro(phi, [1.4e-9, 1.0e-9], X), z, rtol=1e-14)
    assert np.allclose(eos.santos_yuste_haro(phi, [1.0, 1.4], X[::-1]), z, rtol=1e-14)
    # Built on Carnahan-Starling it lies above BMCSL (the paper: nearer to simulation)
    cs = eos.santos_yuste_haro(phi, D, X, pure=eos.carnahan_starling)
    assert np.all(cs > eos.bmcsl(phi, D, X))
    # and on KLM above that again by about KLM/CS - 1 (0.2-0.3% here)
    rel = z / cs - 1
    assert np.all((rel > 0.001) & (rel < 0.004))


@pytest.mark.parametrize(
    "d, x",
    [([1.0, 2.0], [0.5]), ([1.0, -1.0], [0.5, 0.5]), ([1.0, 2.0], [0.4, 0.4]), ([], [])],
)
def test_syh_bad_input(d, x):
    with pytest.raises(ValueError):
        eos.santos_yuste_haro(0.3, d, x)
    with pytest.raises(ValueError):
        eos.santos_yuste_haro(1.0, D, X)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.05, 20.0), min_size=1, max_size=5),
    st.lists(st.floats(0.01, 1.0), min_size=5, max_size=5),
    st.floats(1e-3, 0.55),
)
def test_syh_closed_form_property(diameters, weights, eta):
    """Any mixture of up to 5 components: the closed form equals the double sum, Z > 1.

    Up to packing 0.55, KLM's range (it turns over at 0.57 and is negative by 0.6).
    """
    x = np.array(weights[: len(diameters)])
    x = x / x.sum()
    g_s = (float(eos.kolafa(eta)) - 1) / (4 * eta)

    def linear(e, z):
        return 1 / (1 - e) + (g_s - 1 / (1 - e)) * z

    z = float(eos.santos_yuste_haro(eta, diameters, x))
    assert z == pytest.approx(_virial_route(eta, diameters, x, linear), rel=1e-12)
    assert z > 1.0


@pytest.mark.parametrize("d, x", MIXTURES)
@pytest.mark.parametrize("pure", [eos.kolafa, eos.hansen_goos, eos.carnahan_starling])
def test_syh_is_the_2005_virial_coefficient_form(d, x, pure):
    """Santos and co-workers' later form, as thermopack writes it (saftvrmie_hardsphere.f90):

    Z - 1 = (b3 B2 - b2 B3)/(b3 - b2) phi/(1 - phi) + (B3 - B2)/(b3 - b2) (Z_s - 1),
    b2, b3 = 4, 10, with the mixture's reduced B2, B3 read off BMCSL's series
    (exact through B3): B2 = 1 + 3A, B3 = 1 + 6A + 3B.
    """
    dd, xx = np.asarray(d, float), np.asarray(x, float)
    m1, m2, m3 = (float(np.sum(xx * dd**k)) for k in (1, 2, 3))
    a, b = m1 * m2 / m3, m2**3 / m3**2
    # B2, B3 from BMCSL's own low-density slope and curvature (not from a, b):
    h = 1e-4
    z1, z2 = float(eos.bmcsl(h, d, x)), float(eos.bmcsl(2 * h, d, x))
    b2_mix = (4 * z1 - z2 - 3) / (2 * h)  # Richardson: error O(h^2)
    assert b2_mix == pytest.approx(1 + 3 * a, rel=1e-6)
    b2_mix = 1 + 3 * a
    f1, f2 = (z1 - 1 - b2_mix * h) / h**2, (z2 - 1 - 2 * b2_mix * h) / (2 * h) ** 2
    assert 2 * f1 - f2 == pytest.approx(1 + 6 * a + 3 * b, rel=1e-5)  # Richardson
    b3_mix = 1 + 6 * a + 3 * b
    for eta in (0.1, 0.3, 0.5):
        z_2005 = (
            1
            + (10 * b2_mix - 4 * b3_mix) / 6 * eta / (1 - eta)
            + (b3_mix - b2_mix) / 6 * (float(pure(eta)) - 1)
        )
        assert float(eos.santos_yuste_haro(eta, d, x, pure=pure)) == pytest.approx(z_2005, rel=1e-13)
