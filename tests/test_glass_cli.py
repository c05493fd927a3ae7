"""The glass and jamming commands: plot fs|chi4|contacts, compress's jamming line, their bad input."""

import re

import numpy as np

import pytest

import hardspheres as hs
from hardspheres.cli.commands import main

pytest.importorskip("matplotlib")
pytest.importorskip("scipy")


@pytest.fixture(scope="module")
def fluid(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("glass")
    box = hs.PeriodicBox.for_packing(108, 0.4).length
    (tmp / "f.txt").write_text(hs.random_spheres(108, 0.4, box=box, seed=1).to_text())
    return tmp, box


@pytest.mark.parametrize("what", ["fs", "chi4"])
def test_plot_fs_and_chi4(fluid, what, capsys):
    tmp, box = fluid
    out = tmp / f"{what}.png"
    assert main(["plot", what, str(tmp / "f.txt"), "--box", str(box), "--until", "5", "-o", str(out)]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG" and f"wrote {out}" in capsys.readouterr().out


def test_compress_reports_z_rattlers_and_phi_j_then_plot_contacts(fluid, capsys):
    tmp, box = fluid
    out = tmp / "jammed.txt"
    argv = ["compress", str(tmp / "f.txt"), "--box", str(box), "--rate", "0.01", "--pressure", "1e4"]
    assert main([*argv, "-o", str(out)]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 2 and lines[0].startswith("jammed at packing")
    m = re.fullmatch(
        r"jamming: z = ([\d.]+) to ([\d.]+) after removing [\d.]+% to [\d.]+% rattlers \(contacts: gaps below "
        r"30/Z to 100/Z of the contact distance; isostatic ([\d.]+)\); phi_J = ([\d.]+) \+- \S+ "
        r"\(Z = d phi_J / \(phi_J - phi\) fitted to \d+ points\)",
        lines[1],
    )
    assert m, lines[1]
    z_lo, z_hi, z_iso, phi_j = map(float, m.groups())
    assert z_lo <= z_hi and 5.0 < z_iso < 6.0
    packing = float(lines[0].split()[3].rstrip(":"))
    assert packing < phi_j < packing + 0.01
    pic = tmp / "contacts.png"
    assert main(["plot", "contacts", str(out), "--box", str(box), "-o", str(pic)]) == 0
    assert pic.read_bytes()[:4] == b"\x89PNG"


def test_a_fluid_compression_has_no_jamming_line(fluid, capsys):
    tmp, box = fluid
    argv = ["compress", str(tmp / "f.txt"), "--box", str(box), "--rate", "0.01", "--packing", "0.45"]
    assert main([*argv, "-o", str(tmp / "g.txt")]) == 0
    assert len(capsys.readouterr().out.strip().splitlines()) == 1


def test_bad_input_is_one_line(fluid, capsys):
    tmp, box = fluid
    assert main(["plot", "contacts", str(tmp / "f.txt"), "-o", str(tmp / "c.png")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "hardspheres plot: plot contacts: give a packing's scenario file (as compress writes) and --box L"
    ]
    argv = [
        "plot",
        "fs",
        str(tmp / "f.txt"),
        "--box",
        str(box),
        "--until",
        "2",
        "--k",
        "0.1",
        "-o",
        str(tmp / "x.png"),
    ]
    assert main(argv) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "k = 0.1 is below 2 pi / L" in err[0]


def test_readme_glass_frames_resolve_tau_alpha_and_the_chi4_peak(fluid, capsys):
    """run --log-frames: log-spaced lags from many origins; plot fs and chi4 mark tau_alpha and the peak
    without a warning, while equally spaced frames far apart are refused with one (no "0.5 +- 0")."""
    tmp, box = fluid
    log = tmp / "log.gsd"
    argv = ["run", str(tmp / "f.txt"), "--box", str(box), "--until", "10", "--trajectory"]
    assert main([*argv, str(log), "--log-frames", "0.01", "--every", "1"]) == 0
    t = hs.read_trajectory(log).times
    np.testing.assert_allclose(t[:4], [0.0, 0.01, 0.01 * 10**0.1, 0.01 * 10**0.2])
    assert len(t) == 10 * 21 + 1  # 10 origins of 21 frames (lags 0.01 .. 1 at 10 per decade), and 10
    capsys.readouterr()
    for what in ("fs", "chi4"):
        assert main(["plot", what, str(log), "-o", str(tmp / f"{what}_log.png")]) == 0
        assert capsys.readouterr().err == ""
    even = tmp / "even.gsd"
    assert main([*argv, str(even), "--every", "0.5"]) == 0
    capsys.readouterr()
    for what, said in (("fs", "no tau_alpha marked"), ("chi4", "no peak marked")):
        assert main(["plot", what, str(even), "-o", str(tmp / f"{what}_even.png")]) == 0
        err = capsys.readouterr().err
        assert err.startswith(f"hardspheres plot: warning: {said}") and "first lag t = 0.5" in err, err


def test_log_frames_need_a_trajectory_and_a_first_lag_below_every(fluid, capsys):
    tmp, box = fluid
    argv = ["run", str(tmp / "f.txt"), "--box", str(box), "--until", "10"]
    assert main([*argv, "--log-frames", "0.01"]) == 1
    assert "--log-frames is for the trajectory" in capsys.readouterr().err
    assert main([*argv, "--log-frames", "2", "--every", "1", "--trajectory", str(tmp / "x.gsd")]) == 1
    assert "--log-frames 2 is not shorter" in capsys.readouterr().err


def test_a_compression_short_of_isostatic_is_not_called_jammed(fluid, capsys):
    """Too fast (--rate 0.03 here): z after rattler removal below isostatic at both tolerances; the
    report says stopped, not jammed, and a warning suggests a slower rate."""
    tmp, box = fluid
    argv = ["compress", str(tmp / "f.txt"), "--box", str(box), "--rate", "0.03", "--pressure", "1e6"]
    assert main([*argv, "-o", str(tmp / "fast.txt")]) == 0
    out, err = capsys.readouterr()
    first, jam = out.strip().splitlines()
    assert first.startswith("stopped at packing") and "(not jammed: short of isostatic)" in first
    z_hi, z_iso = (float(x) for x in re.search(r"to ([\d.]+) after .* isostatic ([\d.]+)\)", jam).groups())
    assert z_hi < z_iso
    assert len(err.strip().splitlines()) == 1 and err.startswith("hardspheres compress: warning: z = ")
    assert "short of isostatic" in err and "compress more slowly (--rate 0.003)" in err


def test_compress_rate_defaults_to_the_library_and_a_missing_file_is_named(fluid, capsys, tmp_path):
    from hardspheres.cli.compress import add_parser
    from hardspheres.dense import compress
    import argparse
    import inspect

    sub = argparse.ArgumentParser().add_subparsers()
    assert add_parser(sub).parse_args(["x.txt", "--box", "5", "-o", "y.txt"]).rate == (
        inspect.signature(compress).parameters["rate"].default
    )
    missing = tmp_path / "missing.txt"
    assert (
        main(["compress", str(missing), "--box", "5", "--pressure", "1e3", "-o", str(tmp_path / "o.txt")])
        == 1
    )
    err = capsys.readouterr().err
    assert f"{missing}: No such file or directory" in err and "--rate" not in err
    assert main(["compress", "--box", "5", "--pressure", "1e3", "-o", str(tmp_path / "o.txt")]) == 1
    assert "give a scenario file" in capsys.readouterr().err
