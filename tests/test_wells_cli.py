"""``hardspheres run --well`` / ``--step``: a square well from the command line.

Checked here: a short run prints the potential, the potential energy per
sphere with its error, the total energy's drift (not the kinetic one) and
the counts of captures, releases and bounces; the checkpoint keeps the
well and a resumed run continues it (a new well refused); bad input is
refused in one line, exit 1, nothing on stdout.
"""

import re

import pytest
from helpers import hs_cmd

import hardspheres as hs

WELL = ("--well", "1.5", "0.5")


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """64 spheres at packing 0.2 in a box of edge 8."""
    folder = tmp_path_factory.mktemp("wells")
    (folder / "s.txt").write_text(hs.random_spheres(64, 0.2, box=8.0, seed=2).to_text())
    return folder


@pytest.fixture(scope="module")
def welled(folder):
    return hs_cmd("run", "s.txt", "--box", "8", "--until", "12", "--equilibrate-time", "2", *WELL,
                  "--checkpoint", "c.npz", cwd=folder, check=True)  # fmt: skip


def test_a_well_run_prints_its_energies_and_step_events(welled):
    out = welled.stdout
    assert "pair potential: square well lambda 1.5, eps 0.5" in out
    drift = re.search(r"total energy \(kinetic \+ potential\) drift (\S+) \(relative", out)
    assert drift is not None and float(drift.group(1)) < 1e-12
    assert "\nenergy drift" not in out
    events = re.search(
        r"(\d+) collisions, \d+ reflections, (\d+) captures, (\d+) releases, (\d+) bounces", out
    )
    assert events is not None and all(int(g) > 0 for g in events.groups())
    u = re.search(r"potential energy per sphere U/N (\S+) \+- (\S+)", out)
    assert u is not None and float(u.group(1)) < 0 and float(u.group(2)) > 0
    assert re.search(r"\(virial\), kT \S+ \(mean; \S+ now\)", out)  # (K changes at every capture)
    assert int(re.search(r"events (\d+):", out).group(1)) == sum(int(g) for g in events.groups()) + int(
        re.search(r"(\d+) reflections", out).group(1)
    )
    assert welled.stderr.count("warning") == 0


def test_the_checkpoint_keeps_the_well_and_a_resumed_run_continues_it(folder, welled):
    sim = hs.Simulation.load(folder / "c.npz")
    assert sim.steps == ((1.5, -0.5),)
    r = hs_cmd("run", "--resume", "c.npz", "--until", "14", "--checkpoint", "c2.npz", cwd=folder,
               check=True)  # fmt: skip
    assert "square well lambda 1.5, eps 0.5" in r.stdout and "captures" in r.stdout
    assert hs.Simulation.load(folder / "c2.npz").steps == ((1.5, -0.5),)
    again = hs_cmd("run", "--resume", "c.npz", "--until", "14", *WELL, cwd=folder)
    assert again.returncode == 1 and again.stdout == "" and "keeps its pair potential" in again.stderr


def test_several_steps(folder):
    r = hs_cmd("run", "s.txt", "--box", "8", "--until", "2", "--step", "1.6", "0.2", "--step", "1.3", "-1",
               cwd=folder, check=True)  # fmt: skip
    assert "pair potential: steps (lambda 1.6, U 0.2), (lambda 1.3, U -1)" in r.stdout


@pytest.mark.parametrize(
    "extra, message",
    [
        (("--restitution", "0.9"), "--well with --restitution below 1: not built yet"),
        (("--shear-rate", "0.5", "--shear-temperature", "1", "--rescale-interval", "0.05"),
         "--well with --shear-rate: not built yet"),
        (("--pressure", "1"), "--well with --pressure: not built yet"),
    ],
)  # fmt: skip
def test_what_a_well_cannot_run_with_is_refused(folder, extra, message):
    r = hs_cmd("run", "s.txt", "--box", "8", "--until", "2", *WELL, *extra, cwd=folder)
    assert r.returncode == 1 and r.stdout == "" and message in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr


@pytest.mark.parametrize(
    "args, message",
    [
        (("--well", "0.9", "1"), "--well 0.9 1: give the width LAMBDA > 1"),
        (("--well", "1.5", "-1"), "the depth EPS > 0"),
        (("--well", "1.5", "x"), "--well: must be a finite number, got 'x'"),
        (("--well", "1.5", "1", "--step", "1.2", "1"), "not both"),
        (("--step", "1.2", "1", "--step", "1.4", "1"), "--step: step (1.4, 1.0)"),
        (("--well", "4.5", "1"), "half the box"),
    ],
)
def test_bad_wells_are_refused_in_one_line(folder, args, message):
    r = hs_cmd("run", "s.txt", "--box", "8", "--until", "2", *args, cwd=folder)
    assert r.returncode == 1 and r.stdout == "" and message in r.stderr, r.stderr
    assert "Traceback" not in r.stderr
