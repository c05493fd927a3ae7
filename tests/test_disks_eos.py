"""The hard-disk equation of state (Kolafa & Rottner 2006) and our disks' Z against it."""

import math

import pytest

import hardspheres as hs
from hardspheres import eos

# Kolafa & Rottner, Mol. Phys. 104, 3435 (2006), Table 1 (p. 3436): reduced
# density rho* = N sigma^2 / A, Z and its standard error, from molecular
# dynamics extrapolated to infinite N (rho* 0.89 and 0.90 by Z(1/N)
# extrapolation; 0.90 "may be affected by finite-size effects").  As typed
# from the paper in a public program of the code index (stored file id
# 70488689747, its KR_TABLE1).
TABLE_1 = [
    (0.40, 2.1514393, 0.0000052),
    (0.50, 2.7601235, 0.0000079),
    (0.60, 3.663691, 0.000012),
    (0.70, 5.082362, 0.000019),
    (0.80, 7.476491, 0.000036),
    (0.85, 9.245785, 0.000072),
    (0.88, 10.2309, 0.0003),
    (0.90, 10.2059, 0.0011),
]


@pytest.mark.parametrize(("rho", "z", "err"), TABLE_1)
def test_kolafa_rottner_reproduces_its_own_simulations(rho, z, err):
    # the fit's residuals over these points are 0.05-1.2 standard errors (s = 0.927)
    assert abs(float(eos.kolafa_rottner(math.pi * rho / 4.0)) - z) < 2.0 * err


def test_kolafa_rottner_has_the_exact_virial_coefficients():
    # hard disks in powers of phi: Z = 1 + 2 phi + 4 b3 phi^2 + 8 b4 phi^3 + ...
    # with the closed forms b3 = B3/B2^2 = 4/3 - sqrt(3)/pi and
    # b4 = B4/B2^3 = 2 - 9 sqrt(3)/(2 pi) + 10/pi^2; the x-series gives
    # 2 + c2 (phi^2) and 2 + 2 c2 + c3 (phi^3)
    c = {2: 1.12801775, 3: 0.00181895291}  # as in eos.kolafa_rottner's docstring
    assert 2.0 + c[2] == pytest.approx(4.0 * (4.0 / 3.0 - math.sqrt(3.0) / math.pi), rel=1e-9)
    b4 = 2.0 - 9.0 * math.sqrt(3.0) / (2.0 * math.pi) + 10.0 / math.pi**2
    assert 2.0 + 2.0 * c[2] + c[3] == pytest.approx(8.0 * b4, rel=1e-8)
    p = 1e-4
    series = 1.0 + 2.0 * p + (2.0 + c[2]) * p**2 + (2.0 + 2.0 * c[2] + c[3]) * p**3
    assert float(eos.kolafa_rottner(p)) == pytest.approx(series, rel=1e-14)
    assert float(eos.kolafa_rottner(0.0)) == 1.0


def test_kolafa_rottner_refuses_the_hexatic():
    assert float(eos.kolafa_rottner(eos.KOLAFA_ROTTNER_MAX)) == pytest.approx(10.2058, abs=1e-3)
    for bad in (0.71, 0.75, -0.1):
        with pytest.raises(ValueError, match="0.7069"):
            eos.kolafa_rottner(bad)


def test_a_disk_fluid_has_kolafa_rottners_z():
    # the short version of validation/disks_eos.py: 2000 disks at area
    # fraction 0.5, 10^6 collisions; Henderson's (1 + phi^2/8)/(1 - phi)^2
    # is 0.45% higher here, several standard errors away
    phi, n = 0.5, 2000
    side = math.sqrt(n * math.pi / (4.0 * phi))
    box = hs.PeriodicBox((side, side))
    sim = hs.Simulation(hs.random_spheres(n, phi, box, seed=5), box)
    sim.run(collisions=100 * n)
    obs = sim.observables.reset()
    sim.run(collisions=1_000_000)
    z, err, ref = obs.Z(), obs.error("Z"), float(eos.kolafa_rottner(phi))
    assert err / z < 0.0012
    assert abs(z - ref) < 3.5 * err
    assert abs(z - (1 + phi**2 / 8) / (1 - phi) ** 2) > 3.5 * err


def test_disks_compress_to_the_packing_asked():
    # the growth time to a target packing scales the radii by (phi/phi0)^(1/d):
    # with 1/3 in 2-D, disks stopped at 0.6725 when asked for 0.712
    from hardspheres.builders import hexagonal

    _, box = hexagonal((10, 10), 0.712)
    sim = hs.Simulation(hs.random_spheres(100, 0.6, box, seed=1), box)
    res = sim.compress(packing=0.712, rate=1e-2, pressure=None)
    assert res.reason == "packing"
    assert sim.packing == pytest.approx(0.712, rel=1e-9)
