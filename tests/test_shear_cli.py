"""``hardspheres run --shear-rate``: a sheared box from the command line, its summary and its GSD frames.

Checked here: a short thermostatted sheared run prints the rate, the
viscosity with its error, the normal stress differences and the peculiar
kT; the checkpoint keeps the shear and a resumed run continues it (a new
rate refused); a sheared granular gas needs no thermostat; bad input is
refused in one line with nothing on stdout; the GSD frames carry the
Lees-Edwards offset and the rate.
"""

import argparse
import math
import re

import numpy as np
import pytest
from helpers import hs_cmd

import hardspheres as hs

SHEAR = ("--shear-rate", "0.5")
HELD = ("--shear-temperature", "1", "--rescale-interval", "0.05")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """100 spheres at packing 0.3 in a box of edge 5.6 (a mean free time about 0.1 at kT = 1)."""
    folder = tmp_path_factory.mktemp("shear")
    (folder / "s.txt").write_text(hs.random_spheres(100, 0.3, box=5.6, seed=3).to_text())
    return folder


@pytest.fixture(scope="module")
def sheared(folder):
    """A thermostatted sheared run to t = 12 with a checkpoint and a GSD trajectory (frames every 3)."""
    return hs_cmd("run", "s.txt", "--box", "5.6", "--until", "12", "--equilibrate-time", "2", *SHEAR, *HELD,
                  "--checkpoint", "c.npz", "--trajectory", "t.gsd", "--every", "3", cwd=folder,
                  check=True)  # fmt: skip


def test_a_sheared_run_prints_its_rheology_with_error_bars(sheared):
    out = sheared.stdout
    assert "periodic box of edge 5.6, sheared at rate 0.5 (Lees-Edwards)" in out
    assert "energy drift" not in out  # (not conserved: the shear works, the thermostat takes heat out)
    assert "peculiar kT held at 1 by rescaling every 0.05" in out
    kT = float(re.search(r"peculiar kT (\S+) \(mean; ", out).group(1))
    assert 1.0 < kT < 1.05  # (it heats between rescalings: the mean sits above the target)
    eta = re.search(r"viscosity eta = -P_xy/g (\S+) \+- (\S+)", out)
    assert eta is not None and float(eta.group(1)) > 0 and float(eta.group(2)) > 0
    assert re.search(r"N1 = P_xx - P_yy \S+ \+- ", out) and re.search(r"N2 = P_yy - P_zz \S+ \+- ", out)
    assert "warning" not in sheared.stderr


def test_the_checkpoint_keeps_the_shear_and_a_resumed_run_continues_it(folder, sheared):
    from hardspheres.dense import PeculiarRescale

    sim = hs.Simulation.load(folder / "c.npz")
    assert sim.container.shear_rate == 0.5 and isinstance(sim.thermostat, PeculiarRescale)
    assert sim.thermostat.kT == 1.0 and sim.thermostat.interval == 0.05
    r = hs_cmd("run", "--resume", "c.npz", "--until", "14", "--checkpoint", "c2.npz", cwd=folder,
               check=True)  # fmt: skip
    assert "sheared at rate 0.5" in r.stdout and "viscosity eta" in r.stdout
    assert hs.Simulation.load(folder / "c2.npz").container.shear_rate == 0.5
    again = hs_cmd("run", "--resume", "c.npz", "--until", "14", *SHEAR, cwd=folder)
    assert again.returncode == 1 and again.stdout == "" and "keeps its shear" in again.stderr


def test_gsd_frames_carry_the_shear_offset_and_rate(folder, sheared):
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    from hardspheres.io.trajectory import read_trajectory

    sim = hs.Simulation.load(folder / "c.npz")
    lx, ly = sim.container.sides[:2]
    with gsd_hoomd.open(str(folder / "t.gsd"), "r") as f:
        frames = list(f)
    assert len(frames) == 5  # t = 0, 3, ..., 12
    for frame in frames:
        t = float(frame.log["hardspheres/time"][0])
        assert float(frame.log["hardspheres/shear_rate"][0]) == 0.5
        offset = float(frame.log["hardspheres/shear_offset"][0])
        assert 0.0 <= offset < lx
        assert offset == pytest.approx(math.fmod(0.5 * ly * t, lx), abs=1e-9)  # (from 0 at t = 0)
    assert float(frames[-1].log["hardspheres/shear_offset"][0]) == sim.engine.shear_offset(12.0)
    assert np.allclose(read_trajectory(folder / "t.gsd").times, [0, 3, 6, 9, 12])


def test_a_sheared_granular_gas_needs_no_thermostat(folder):
    r = hs_cmd("run", "s.txt", "--box", "5.6", "--until", "8", "--equilibrate-time", "3", *SHEAR,
               "--restitution", "0.9", cwd=folder, check=True)  # fmt: skip
    assert "granular (restitution 0.9), sheared: dissipated" in r.stdout
    assert "granular temperature (peculiar) kT" in r.stdout and "heated by the shear" in r.stdout
    assert "viscosity eta = -P_xy/g" in r.stdout and "Haff" not in r.stdout


def test_a_long_rescale_interval_is_warned_of(folder):
    r = hs_cmd("run", "s.txt", "--box", "5.6", "--until", "6", *SHEAR, "--shear-temperature", "1",
               "--rescale-interval", "1.5", cwd=folder, check=True)  # fmt: skip
    assert "warning: the fluid heats by" in r.stderr and "--rescale-interval" in r.stderr


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (SHEAR, ["heats without end", "--shear-temperature"]),
        (("--shear-rate", "0", *HELD), ["--shear-rate", "other than 0"]),
        (("--shear-rate", "inf", *HELD), ["--shear-rate", "finite"]),
        ((*SHEAR, "--shear-temperature", "1"), ["needs --rescale-interval"]),
        ((*SHEAR, "--rescale-interval", "0.1"), ["--rescale-interval", "give --shear-temperature"]),
        (HELD, ["--shear-temperature", "give --shear-rate"]),
        ((*SHEAR, *HELD, "--restitution", "0.9"), ["--restitution below 1", "leave out"]),
        ((*SHEAR, *HELD, "--pressure", "2"), ["--shear-rate with --pressure"]),
        ((*SHEAR, "--restitution", "0.9", "--kicks", "1", "--kick-interval", "0.1"),
         ["--shear-rate with --kicks"]),
        ((*SHEAR, "--shear-temperature", "-1", "--rescale-interval", "0.1"),
         ["--shear-temperature", "> 0"]),
    ],
)  # fmt: skip
def test_bad_shear_options_are_refused_in_one_line(folder, args, words):
    r = hs_cmd("run", "s.txt", "--box", "5.6", "--until", "1", *args, cwd=folder)
    assert r.returncode == 1 and r.stdout == "" and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr


def test_shear_needs_a_periodic_box(folder):
    r = hs_cmd("run", "s.txt", "--container", "6", "--until", "1", *SHEAR, *HELD, cwd=folder)
    assert r.returncode == 1 and r.stdout == "" and "give --box" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_xyz_frames_carry_the_shear_offset_and_read_back(folder, sheared):
    from hardspheres.io.trajectory import read_trajectory

    r = hs_cmd("run", "--resume", "c.npz", "--until", "13", "--checkpoint", "c3.npz", "--trajectory", "t.xyz",
               "--every", "0.5", cwd=folder, check=True)  # fmt: skip
    assert "sheared at rate 0.5" in r.stdout
    sim = hs.Simulation.load(folder / "c3.npz")
    lx, ly = sim.container.sides[:2]
    headers = [line for line in (folder / "t.xyz").read_text().splitlines() if line.startswith("Lattice=")]
    assert len(headers) == 3  # t = 12, 12.5, 13
    for line in headers:
        t = float(re.search(r"Time=(\S+)", line).group(1))
        offset = float(re.search(r"shear_offset=(\S+)", line).group(1))
        assert "shear_rate=0.5" in line
        assert offset == pytest.approx(math.fmod(0.5 * ly * t, lx), abs=1e-9)
    frames = read_trajectory(folder / "t.xyz")
    assert np.allclose(frames.times, [12, 12.5, 13]) and frames.container.shear_rate == 0.5


@pytest.mark.parametrize(
    ("where", "extra", "variant"),
    [
        (["--box", "5.6", "5.6"], {"shear_rate": 0.5}, (2, False, True)),
        (["--box", "5.6"], {"restitution": 0.9, "shear_rate": 0.5}, (3, True, True)),
        (["--box", "5.6"], {}, (3, False, False)),
    ],
)
def test_a_run_compiles_first_the_variant_it_needs_not_the_plain_one(
    folder, monkeypatch, where, extra, variant
):
    """A sheared (or 2-D, or granular) run compiled the plain 3-D core first, then its own: twice the wait."""
    from hardspheres.cli import source
    from hardspheres.core import warmup

    asked = []
    monkeypatch.setattr(
        warmup, "ensure_compiled", lambda dimensions=3, inelastic=False, sheared=False, **k: asked.append(
            (dimensions, inelastic, sheared)) or 0.0
    )  # fmt: skip
    scenario = folder / ("d.txt" if where.count("5.6") == 2 else "s.txt")
    if not scenario.exists():
        scenario.write_text(hs.random_spheres(40, 0.3, box=(5.6, 5.6), seed=3).to_text())
    args = argparse.Namespace(
        resume=None, scenario=str(scenario), container=None, circle=None, box=where[1:], dimensions=None,
        restitution=extra.get("restitution"), wall_restitution=None, tc=None, shear_rate=extra.get("shear_rate"),
    )  # fmt: skip
    sim = source.starting_simulation(args)
    assert asked[0] == variant
    assert sim.container.dimensions == variant[0] and bool(sim.container.shear_rate) == variant[2]
