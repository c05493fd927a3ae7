"""Transport validation: the published tables, the scoring, and the command (short)."""

import csv
import math

import pytest
from helpers import hs_cmd

from hardspheres.studies.validate import (
    DYNAMO_RHO05,
    HEYES_CASS_D,
    PIEPRZYK_2019_D,
    TransportRow,
    published_diffusion,
    score_transport,
)

RHO05 = 0.5 * math.pi / 6.0


def test_published_tables_agree_with_each_other():
    """Two independent MD sets: within 3% of each other over the fluid (0.1 to 0.45)."""
    for phi in (0.1, 0.2, 0.3, 0.4, 0.45):
        (p, _, _), (h, _, _) = published_diffusion(phi)
        assert abs(p / h - 1) < 0.03, phi


def test_interpolation_hits_tabulated_points_and_is_smooth():
    for rho, d in PIEPRZYK_2019_D:
        assert published_diffusion(rho * math.pi / 6)[0][0] == pytest.approx(d, rel=1e-12)
    for phi, d in HEYES_CASS_D[1:]:
        assert published_diffusion(phi)[-1][0] == pytest.approx(d, rel=1e-12)
    d, err, _ = published_diffusion(0.3)[0]
    lo, hi = PIEPRZYK_2019_D[9][1], PIEPRZYK_2019_D[10][1]  # rho 0.55, 0.60 around 0.573
    assert hi < d < lo and err < 1e-3 * d


def test_lue_plus_yeh_hummer_gives_pieprzyk():
    """DynamO's finite-N D at rho 0.5 plus the Yeh-Hummer correction = the N -> inf table."""
    from hardspheres.analysis.transport import yeh_hummer

    L = (DYNAMO_RHO05["n"] / DYNAMO_RHO05["rho"]) ** (1 / 3)
    d_inf = yeh_hummer(DYNAMO_RHO05["D"][0], L, DYNAMO_RHO05["eta"][0])
    assert d_inf == pytest.approx(dict(PIEPRZYK_2019_D)[0.5], rel=0.005)


def _row(phi, n, D_inf, D_inf_err, **kw):
    base = dict(
        phi=phi,
        n=n,
        L=10.0,
        Z=3.0,
        Z_err=0.01,
        mean_free_time=0.13,
        mean_free_time_err=1e-4,
        D=0.2,
        D_err=0.01,
        D_inf=D_inf,
        D_inf_err=D_inf_err,
        eta=0.6,
        eta_err=0.03,
        lam=2.3,
        lam_err=0.1,
        time=1.0,
        collisions=1,
        seconds=1.0,
    )
    base.update(kw)
    return TransportRow(**base)


def test_scores_use_combined_errors_and_the_largest_n():
    rows = [_row(0.3, 256, 0.1, 0.001), _row(0.3, 1372, 0.2061, 0.003)]
    s = score_transport(rows)
    assert [x.n for x in s] == [1372, 1372]  # only the largest N is extrapolated
    p = s[0]
    assert p.z == pytest.approx((0.2061 - p.reference) / math.hypot(0.003, p.reference_error))
    assert p.passed  # 1.5% off: within 2%
    far = score_transport([_row(0.3, 1372, 0.25, 0.001)])
    assert not any(x.passed for x in far)


def test_dynamo_system_is_scored_on_all_four():
    r = _row(
        RHO05,
        1372,
        0.265,
        0.003,
        D=0.247,
        D_err=0.003,
        mean_free_time=0.1303,
        mean_free_time_err=1e-4,
        eta=0.55,
        eta_err=0.03,
        lam=2.2,
        lam_err=0.1,
    )
    q = {x.quantity for x in score_transport([r])}
    assert q == {"D_inf", "D", "mean_free_time", "eta", "lambda"}


def test_validate_transport_quick_and_plot(tmp_path):
    out = tmp_path / "t.csv"
    r = hs_cmd("validate", "--transport", "--quick", "--csv", str(out), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "| D_inf | 0.3000 | 256 |" in r.stdout and f"wrote {out}" in r.stdout
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert {x["quantity"] for x in rows} == {"D_inf"} and len(rows) == 2
    # 30 time units of 256 spheres: D_inf within 15% of the published value
    assert all(abs(float(x["rel_diff"])) < 0.15 for x in rows)
    png = tmp_path / "t.png"
    r = hs_cmd("plot", "transport", str(out), "-o", str(png))
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 10000


def test_transport_refuses_options_it_does_not_take(tmp_path):
    r = hs_cmd("validate", "--transport", "--seeds", "3", cwd=tmp_path)
    assert r.returncode == 1 and "--seeds does not apply to --transport" in r.stderr
    assert "Traceback" not in r.stderr and not list(tmp_path.iterdir())
    r = hs_cmd("validate", "--time", "5", cwd=tmp_path)
    assert r.returncode == 1 and "--time applies to --transport only" in r.stderr
    assert len(r.stderr.strip().splitlines()) <= 2 and not list(tmp_path.iterdir())


def test_transport_before_anything_was_measured_says_what_to_do():
    """Issue 11, item 7: one-line ValueErrors that say what to do."""
    import hardspheres as hs
    from hardspheres.analysis.transport import MSD, VACF, ShearViscosity, ThermalConductivity
    from hardspheres.io.trajectory import frames_from_simulation
    from hardspheres.observables import NoMeasurementError

    L = 7.0
    sim = hs.Simulation(hs.random_spheres(64, 0.2, box=L, seed=2), hs.PeriodicBox(L))
    for compute, words in (
        (lambda: ShearViscosity().compute(sim), "run longer"),
        (lambda: ThermalConductivity().compute(sim), "run longer"),
        (lambda: sim.observables.estimate("compressibility"), "run"),
        (lambda: MSD().compute(frames_from_simulation(sim, 0.1, 0.1)), "record at least three"),
        (lambda: VACF().diffusion(), "compute"),
    ):
        with pytest.raises(ValueError) as exc:
            compute()
        msg = str(exc.value)
        assert "\n" not in msg and words in msg, msg
        if words == "run":
            assert isinstance(exc.value, NoMeasurementError)


def test_line_extrapolation_recovers_an_exact_yeh_hummer_series():
    from hardspheres.analysis.transport import yeh_hummer
    from hardspheres.studies.validate import line_extrapolations

    rows = []
    for n in (500, 1372, 2744):
        L = (n * math.pi / 1.8) ** (1 / 3)
        d = 0.2 - (yeh_hummer(0.0, L, 0.73))  # D(L) = D_inf - xi kT / (6 pi eta L)
        rows.append(_row(0.3, n, 0.2, 0.001, L=L, D=d, D_err=0.001, eta=0.73))
    (line,) = line_extrapolations(rows)
    assert "D_inf = 0.2000 +-" in line and "slope -0.206" in line and "Yeh-Hummer's -0.206" in line
    assert line_extrapolations(rows[:1]) == []


def test_plot_transport_refuses_another_csv(tmp_path):
    bad = tmp_path / "eos.csv"
    bad.write_text("phi,Z,Z_err\n0.3,3.98,0.01\n")
    r = hs_cmd("plot", "transport", str(bad), "-o", str(tmp_path / "t.png"))
    assert r.returncode == 1 and "missing column(s) quantity" in r.stderr
    assert "validate --transport" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "t.png").exists()


def test_mean_free_time_is_scored_against_the_equation_of_state():
    """Issue 29 item 7: scored against Lue's 0.13031 +- 0.000005, an error no
    source gives; now sqrt(pi)/(6 (Z - 1)) with KLM (0.130170), error t/N."""
    r = _row(RHO05, 1372, 0.265, 0.003, mean_free_time=0.13019, mean_free_time_err=1e-4)
    (s,) = [x for x in score_transport([r]) if x.quantity == "mean_free_time"]
    assert round(s.reference, 6) == 0.13017 and s.reference_error == pytest.approx(0.13017 / 1372, rel=1e-4)
    assert "Kolafa" in s.source and "1372" not in s.source and s.passed
    (d,) = [x for x in score_transport([r]) if x.quantity == "D"]
    assert d.reference_error == pytest.approx(0.06 * 0.247) and "no published error" in d.source
