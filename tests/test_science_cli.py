"""`hardspheres plot gr|msd` on a periodic-box trajectory."""

import pytest
from helpers import periodic_gas

import hardspheres as hs
from hardspheres.cli.commands import main
from hardspheres.io.trajectory import GSDWriter

pytest.importorskip("freud")
pytest.importorskip("gsd")


@pytest.fixture(scope="module")
def trajectory(tmp_path_factory):
    path = tmp_path_factory.mktemp("sci") / "t.gsd"
    n, phi = 108, 0.3
    sim = periodic_gas(n, phi, seed=1)
    sim.run(until=2.0)
    with GSDWriter(path, every=0.1) as w:
        sim.writers.append(w)
        sim.run(until=sim.time + 20.0)
    return path


@pytest.mark.parametrize("what", ["gr", "msd"])
def test_plot(trajectory, tmp_path, capsys, what):
    out = tmp_path / f"{what}.png"
    assert main(["plot", what, str(trajectory), "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "wrote" in capsys.readouterr().out


def test_plot_gr_needs_a_periodic_box(tmp_path, capsys):
    path = tmp_path / "c.gsd"
    sim = hs.Simulation(hs.random_spheres(20, 0.1, container=5.0, seed=1), hs.SphericalContainer(5.0))
    with GSDWriter(path, every=0.5) as w:
        sim.writers.append(w)
        sim.run(until=2.0)
    assert main(["plot", "gr", str(path), "-o", str(tmp_path / "g.png")]) == 1
    assert "periodic box" in capsys.readouterr().err


def test_readme_study_runs(tmp_path, monkeypatch):
    """The user guide's study (docs/guide/transport.md, once README's), shortened (N = 108, 30 time units)."""
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "transport.md").read_text()
    block = re.search(r"## A study.*?```python\n(.*?)```", readme, re.S).group(1)
    assert len(block.strip().splitlines()) < 20
    block = block.replace("n, phi = 500, 0.3", "n, phi = 108, 0.3")
    block = block.replace("until=sim.time + 200", "until=sim.time + 30")
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "gr.png").exists()


@pytest.mark.parametrize("what", ["gr", "msd"])
def test_plot_from_skips_early_frames(trajectory, tmp_path, capsys, monkeypatch, what):
    """Issue 29 item 5: plot gr|msd could not skip an equilibration the trajectory holds."""
    from hardspheres.viz import plots

    seen = []
    real = getattr(plots, f"plot_{what}")
    monkeypatch.setattr(
        plots, f"plot_{what}", lambda frames, out, **kw: seen.append(frames) or real(frames, out, **kw)
    )
    out = tmp_path / f"{what}.png"
    assert main(["plot", what, str(trajectory), "-o", str(out), "--from", "12"]) == 0
    assert seen[0].times[0] >= 12.0 and len(seen[0].times) == pytest.approx(101, abs=1)
    assert main(["plot", what, str(trajectory), "-o", str(out), "--from", "1e9", "--overwrite"]) == 1
    assert "no frames from t = 1e+09" in capsys.readouterr().err
