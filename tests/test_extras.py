"""Optional packages: a missing one is a one-line error naming the extra that installs it.

Each test hides a package as an uninstalled one does (``sys.modules[name] = None`` makes
``import name`` raise ModuleNotFoundError) and checks what the user sees.
"""

import re
import sys

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.errors import MissingExtraError

PYPROJECT_EXTRA = re.compile(
    r'pip install "hardspheres\[(\w+)\]" \(from a checkout: pip install "\.\[\1\]"\)'
)


def _hide(monkeypatch, *names):
    for name in names:
        for loaded in [m for m in sys.modules if m == name or m.startswith(name + ".")]:
            monkeypatch.delitem(sys.modules, loaded)
        monkeypatch.setitem(sys.modules, name, None)


def _extra(err):
    text = str(err)
    assert "\n" not in text
    m = PYPROJECT_EXTRA.search(text)
    assert m, text
    return m.group(1)


def test_every_optional_package_maps_to_an_extra_of_pyproject():
    import tomllib
    from pathlib import Path

    from hardspheres.extras import EXTRAS

    extras = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    for module, extra in EXTRAS.items():
        wanted = {"freud": "freud-analysis", "distributed": "dask"}.get(module, module)  # dask[distributed]
        assert any(r.split(">")[0].split("[")[0].split(";")[0].strip() == wanted for r in extras[extra]), (
            module,
            extra,
        )


def _box_frames(tmp_path):
    box = hs.PeriodicBox.for_packing(64, 0.3)
    sim = hs.Simulation(hs.random_spheres(64, 0.3, box, seed=1), box)
    from hardspheres.io.trajectory import frames_from_simulation

    return sim, frames_from_simulation(sim, until=2.0, every=0.02)


def test_msd_needs_no_freud(monkeypatch, tmp_path):
    """README's first block runs with what Getting started installs (io, plot): MSD is numpy's."""
    sim, frames = _box_frames(tmp_path)
    _hide(monkeypatch, "freud")
    msd = hs.MSD(blocks=2).compute(frames)
    x = frames.unwrapped()
    brute = [np.mean(np.sum((x[k:] - x[: len(x) - k]) ** 2, axis=2)) for k in range(len(x))]
    np.testing.assert_allclose(msd.msd, brute, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_msd_equals_the_sum_over_origins(dim):
    rng = np.random.default_rng(3)
    x = np.cumsum(rng.normal(size=(200, 7, dim)), axis=0) + 1e4  # far from the origin: rounding
    got = hs.MSD._msd(x)
    brute = [np.mean(np.sum((x[k:] - x[: len(x) - k]) ** 2, axis=2)) for k in range(len(x))]
    np.testing.assert_allclose(got, brute, rtol=1e-9, atol=1e-9)


def test_structure_without_freud_names_the_analysis_extra(monkeypatch, tmp_path):
    _, frames = _box_frames(tmp_path)
    _hide(monkeypatch, "freud")
    with pytest.raises(MissingExtraError) as e:
        hs.RDF(r_max=2.0).compute(frames)
    assert _extra(e.value) == "analysis" and "freud" in str(e.value)
    assert isinstance(e.value, ImportError)


def test_contacts_without_scipy_names_the_analysis_extra(monkeypatch, tmp_path):
    sim, _ = _box_frames(tmp_path)
    _hide(monkeypatch, "scipy")
    with pytest.raises(MissingExtraError) as e:
        hs.Contacts().compute(sim)
    assert _extra(e.value) == "analysis" and "scipy" in str(e.value)


def test_gsd_without_gsd_names_the_io_extra(monkeypatch, tmp_path):
    _hide(monkeypatch, "gsd")
    with pytest.raises(MissingExtraError) as e:
        hs.GSDWriter(tmp_path / "a.gsd", every=1.0)
    assert _extra(e.value) == "io"
    (tmp_path / "b.gsd").write_bytes(b"x")
    with pytest.raises(MissingExtraError) as e:
        hs.read_trajectory(tmp_path / "b.gsd")
    assert _extra(e.value) == "io"
    with pytest.raises(MissingExtraError) as e:
        hs.SelfIntermediate(k=6.0).compute(str(tmp_path / "b.gsd"))
    assert _extra(e.value) == "io"


def test_plots_without_matplotlib_name_the_plot_extra(monkeypatch, tmp_path):
    sim, frames = _box_frames(tmp_path)
    msd = hs.MSD(blocks=2).compute(frames)
    _hide(monkeypatch, "matplotlib")
    with pytest.raises(MissingExtraError) as e:
        msd.plot()
    assert _extra(e.value) == "plot"
    from hardspheres.viz import plots

    with pytest.raises(MissingExtraError) as e:
        plots.plot_msd(frames, tmp_path / "m.png")
    assert _extra(e.value) == "plot"
    from hardspheres.viz.render import render_still

    with pytest.raises(MissingExtraError) as e:
        render_still(frames, tmp_path / "s.png")
    assert _extra(e.value) == "plot"


def test_sweep_without_dask_names_the_sweep_extra(monkeypatch, tmp_path):
    _hide(monkeypatch, "distributed")
    with pytest.raises(MissingExtraError) as e:
        hs.sweep({"n": 8, "packing": 0.1, "collisions": 10, "output": str(tmp_path / "s")})
    assert _extra(e.value) == "sweep"


def test_a_command_without_its_extra_exits_1_with_one_line(monkeypatch, tmp_path, capsys):
    from hardspheres.cli.commands import main

    scn = tmp_path / "s.txt"
    scn.write_text("1 0.5 1 1 1 1 0 0 a\n1 0.5 4 1 1 -1 0 0 b\n")
    _hide(monkeypatch, "matplotlib")
    status = main(["plot", "gr", str(scn), "--box", "8", "-o", str(tmp_path / "r.png")])
    err = capsys.readouterr().err
    assert status == 1 and len(err.strip().splitlines()) == 1 and "hardspheres[plot]" in err, err
