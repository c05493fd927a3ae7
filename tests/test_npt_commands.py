"""Constant pressure at the edges: the package root, ``run --pressure``, the study key, the EOS's inverse."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres import studies
from hardspheres.barostat import Barostat, barostat_from_state
from hardspheres.cli.commands import main as hardspheres
from hardspheres.eos import carnahan_starling, hansen_goos, inverse_compressibility, packing_at_pressure


def test_barostat_at_the_package_root():
    assert hs.Barostat is Barostat and "Barostat" in hs.__all__


def test_packing_at_pressure_inverts_hansen_goos():
    for bp in (0.01, 2.0, 5.0, 10.0, 11.5727):
        phi = packing_at_pressure(bp)
        assert 6.0 * phi * float(hansen_goos(phi)) / math.pi == pytest.approx(bp, rel=1e-13)
    # Fernandez et al. (2012)'s fluid at coexistence, 0.4917(1): Hansen-Goos gives it
    assert packing_at_pressure(11.5727) == pytest.approx(0.4917, abs=2e-4)
    cs = packing_at_pressure(5.0, eos=carnahan_starling)
    assert abs(cs - packing_at_pressure(5.0)) < 2e-3
    for bad in (0.0, -1.0, math.nan, 1e6):
        with pytest.raises(ValueError):
            packing_at_pressure(bad)


def test_inverse_compressibility_is_the_derivative():
    # Carnahan-Starling's d(phi Z)/d phi in closed form: (1 + 4 phi + 4 phi^2 - 4 phi^3 + phi^4) / (1 - phi)^4
    phi = np.array([0.1, 0.3, 0.45])
    exact = (1 + 4 * phi + 4 * phi**2 - 4 * phi**3 + phi**4) / (1 - phi) ** 4
    np.testing.assert_allclose(inverse_compressibility(phi, carnahan_starling), exact, rtol=1e-8)


def test_averages_are_those_of_the_box_after_each_move():
    box = hs.PeriodicBox.for_packing(32, 0.3)
    sim = hs.Simulation(hs.random_spheres(32, 0.3, box=box.length, seed=1), box)
    bar = Barostat(pressure=4.0, every=0.25, seed=3, approach=False)
    sim.set_barostat(bar)
    vols = []
    for k in range(1, 41):
        sim.run(until=0.25 * k)
        vols.append(sim.container.volume)
    solid = sim.packing * sim.container.volume
    assert bar.samples == 40 and bar.accepted > 5
    assert bar.mean_volume == pytest.approx(np.mean(vols), rel=1e-13)
    assert bar.volume_variance == pytest.approx(np.var(vols, ddof=1), rel=1e-9)
    assert bar.mean_packing == pytest.approx(np.mean(solid / np.array(vols)), rel=1e-13)
    again = barostat_from_state(bar.state())
    assert (again.samples, again.mean_volume, again.volume_variance) == (
        bar.samples,
        bar.mean_volume,
        bar.volume_variance,
    )
    assert math.isnan(bar.reset_averages().mean_packing) and bar.samples == 0


@pytest.fixture(scope="module")
def fluid(tmp_path_factory):
    path = tmp_path_factory.mktemp("npt") / "f.txt"
    box = hs.PeriodicBox.for_packing(108, 0.38)
    path.write_text(hs.random_spheres(108, 0.38, box=box.length, seed=2).to_text())
    return path, box.length


def test_run_at_constant_pressure_reports_the_barostat(fluid, capsys):
    path, L = fluid
    assert hardspheres(["run", str(path), "--box", repr(L), "--until", "8", "--pressure", "5"]) == 0
    out = capsys.readouterr().out
    line = [x for x in out.splitlines() if x.startswith("constant pressure 5 ")]
    assert len(line) == 1 and "isotropic" in line[0] and "mean packing 0.3" in line[0], out


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--pressure-axes", "z"], ["--pressure-axes", "--pressure P"]),
        (["--pressure", "5", "--pressure-axes", "w"], ["axes", "'w'"]),
        (["--pressure", "5", "--container", "9"], ["periodic box", "spherical"]),
    ],
)
def test_run_pressure_bad_options_one_line(fluid, capsys, extra, words):
    path, L = fluid
    where = [] if "--container" in extra else ["--box", repr(L)]
    assert hardspheres(["run", str(path), *where, "--until", "2", *extra]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    for w in words:
        assert w in err


def test_run_pressure_not_on_resume(fluid, tmp_path, capsys):
    path, L = fluid
    ck = tmp_path / "c.npz"
    assert (
        hardspheres(
            ["run", str(path), "--box", repr(L), "--until", "2", "--pressure", "5", "--checkpoint", str(ck)]
        )
        == 0
    )
    capsys.readouterr()
    assert hardspheres(["run", "--resume", str(ck), "--until", "3", "--pressure", "6"]) == 1
    assert "resumed run" in capsys.readouterr().err
    assert hardspheres(["run", "--resume", str(ck), "--until", "3"]) == 0
    assert "constant pressure 5 " in capsys.readouterr().out  # the checkpoint kept its barostat


def test_pressure_study_key(tmp_path):
    raw = {
        "pressure": [2.0, 5.0],
        "n": 64,
        "seeds": 1,
        "equilibrate": 20,
        "collisions": 40,
        "blocks": 4,
        "measure": ["mean_packing", "Z"],
        "output": str(tmp_path / "out"),
    }
    spec = studies.parse_study(raw)
    ts = studies.tasks(spec)
    assert [t["betaP"] for t in ts] == [2.0, 5.0]
    assert [t["packing"] for t in ts] == [packing_at_pressure(2.0), packing_at_pressure(5.0)]
    df = studies.sweep(raw, serial=True)
    assert list(df["betaP"]) == [2.0, 5.0]
    for _, r in df.iterrows():
        assert abs(r["mean_packing"] / packing_at_pressure(r["betaP"]) - 1) < 0.05
    # constant-volume studies: no pressure in their tasks (their keys unchanged)
    plain = studies.tasks(studies.parse_study({"packing": 0.3, "n": 64, "output": "x"}))
    assert "betaP" not in plain[0]
    png = tmp_path / "p.png"
    assert (
        hardspheres(
            [
                "plot",
                "sweep",
                str(tmp_path / "out" / "summary.csv"),
                "--x",
                "betaP",
                "--y",
                "mean_packing",
                "-o",
                str(png),
            ]
        )
        == 0
    )
    assert png.stat().st_size > 20000


@pytest.mark.parametrize(
    "data, words",
    [
        ({"pressure": 0.0, "n": 10}, ["pressure = 0.0"]),
        ({"pressure": [1.0, "x"], "n": 10}, ["pressure = 'x'"]),
        ({"pressure": 1.0, "n": 10, "container": "sphere"}, ["pressure", '"box"']),
    ],
)
def test_bad_pressure_study_keys(data, words):
    with pytest.raises(hs.StudyError) as e:
        studies.parse_study(data)
    assert "\n" not in str(e.value)
    for w in words:
        assert w in str(e.value)


def test_the_crystal_and_disk_inverses():
    from hardspheres.eos import kolafa_rottner, speedy_fcc

    for bp in (12.0, 15.0, 20.0):
        phi = packing_at_pressure(bp, speedy_fcc, (0.5, 0.74))
        assert 6.0 * phi * float(speedy_fcc(phi)) / math.pi == pytest.approx(bp, rel=1e-13)
    # at the coexistence packings of Fernandez et al. (2012), both fits give about 11.57
    assert 6 * 0.5433 * float(speedy_fcc(0.5433)) / math.pi == pytest.approx(11.5727, abs=0.02)
    phi = packing_at_pressure(3.0, kolafa_rottner, (0.0, 0.70), dimensions=2)
    assert 4.0 * phi * float(kolafa_rottner(phi)) / math.pi == pytest.approx(3.0, rel=1e-13)
    with pytest.raises(ValueError):
        speedy_fcc(0.44)
