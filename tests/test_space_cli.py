"""Space above the core: the commands' ``--box LX LY [LZ]``, ``--circle R`` and ``--dimensions``,
disk scenarios (nine fields, ``z = vz = 0``), thermostats and compression in 2-D (issue 24)."""

from __future__ import annotations

import re

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.cli.commands import main
from hardspheres.cli.options import sides_last
from hardspheres.dense import Andersen, VelocityRescale

SQRT3_2 = float(np.sqrt(3.0) / 2.0)


def _lines(text):
    return [line.split() for line in text.splitlines() if line.strip()]


def test_generate_writes_disks_with_z_and_vz_zero(capsys):
    assert main(["generate", "--n", "40", "--box", "10", f"{10 * SQRT3_2}", "--packing", "0.5"]) == 0
    rows = _lines(capsys.readouterr().out)
    assert len(rows) == 40 and all(len(r) == 9 for r in rows)
    assert {r[4] for r in rows} == {"0.0"} and {r[7] for r in rows} == {"0.0"}
    state = hs.State.from_scenario(hs.scenario.parse_scenario("\n".join(" ".join(r) for r in rows)), 2)
    box = hs.PeriodicBox((10.0, 10 * SQRT3_2))
    assert state.positions.shape == (40, 2)
    assert hs.containers.packing_fraction(state.radii, box) == pytest.approx(0.5, rel=1e-12)


@pytest.mark.parametrize(
    "where, size",
    [
        (["--box", "10", "--dimensions", "2"], "periodic box of sides 10 x 10"),
        (["--circle", "10"], "circular container of radius 10"),
        (["--box", "10", "10"], "periodic box of sides 10 x 10"),
    ],
)
def test_run_reads_disks_and_counts_two_degrees_of_freedom(where, size, tmp_path, capsys):
    scn = tmp_path / "d.txt"
    assert main(["generate", "--n", "60", *where, "--packing", "0.4", "--seed", "3"]) == 0
    scn.write_text(capsys.readouterr().out)
    # the scenario after --box's numbers, as users type it: still the scenario
    assert main(["run", *where, str(scn), "--until", "2"]) == 0
    out, err = capsys.readouterr()
    assert f"60 disks, {size}" in out
    kT = float(re.search(r"kT ([0-9.e+-]+)", out).group(1))
    # builders draw kinetic energy (N - 1) kT over 2 degrees of freedom each (no momentum);
    # a box counts 2 N - 2, the circle (whose wall takes up momentum) 2 N
    assert kT == pytest.approx(1.0 if "box" in size else 59 / 60, rel=1e-5)
    assert err == ""


def test_a_flat_layer_of_spheres_is_noted(tmp_path, capsys):
    scn = tmp_path / "d.txt"
    assert main(["generate", "--n", "60", "--box", "10", "10", "--packing", "0.4"]) == 0
    scn.write_text(capsys.readouterr().out)
    assert main(["run", str(scn), "--box", "10", "--until", "1"]) == 0
    out, err = capsys.readouterr()
    assert "60 spheres, periodic box of edge 10" in out
    assert err.count("\n") == 1 and "z = 0 and vz = 0" in err and "--circle R or --box LX LY" in err


def test_three_sides_and_the_cube(capsys):
    assert main(["generate", "--n", "50", "--box", "6", "6", "12", "--packing", "0.3"]) == 0
    rows = _lines(capsys.readouterr().out)
    z = np.array([float(r[4]) for r in rows])
    assert np.ptp(z) > 6.0  # the long side is z
    assert main(["generate", "--n", "50", "--box", "8", "--packing", "0.3"]) == 0
    assert len(_lines(capsys.readouterr().out)) == 50


@pytest.mark.parametrize(
    "argv, words",
    [
        (
            ["generate", "--n", "9", "--box", "1", "2", "3", "4", "--packing", "0.3"],
            ["--box", "1 to 3 sides"],
        ),
        (["generate", "--n", "9", "--box", "0", "5", "--packing", "0.3"], ["--box", "> 0"]),
        (
            ["generate", "--n", "9", "--container", "5", "--dimensions", "2", "--packing", "0.3"],
            ["--container"],
        ),
        (["generate", "--n", "9", "--circle", "5", "--dimensions", "3", "--packing", "0.3"], ["--circle"]),
        (
            ["generate", "--n", "9", "--box", "9", "9", "9", "--dimensions", "2", "--packing", "0.3"],
            ["--box"],
        ),
        (["generate", "--n", "9", "--box", "9", "--circle", "5", "--packing", "0.3"], ["--circle", "--box"]),
        (
            ["generate", "--n", "9", "--box", "9", "9", "--packing", "0.3", "--dimensions", "4"],
            ["--dimensions"],
        ),
        (
            ["bench", "--n", "9", "--packing", "0.3", "--collisions", "5", "--dimensions", "1"],
            ["--dimensions"],
        ),
    ],
)
def test_bad_shapes_are_one_line_naming_the_option(argv, words, capsys):
    try:
        status = main(argv)
    except SystemExit as e:  # argparse's errors (Parser: one line)
        status, err = 1, str(e.code)
    else:
        err = capsys.readouterr().err
    assert status == 1
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    for w in words:
        assert w in err, (w, err)


def test_a_disk_scenario_must_be_flat(tmp_path, capsys):
    scn = tmp_path / "s.txt"
    scn.write_text("1 0.5 0 0 0 1 0 0 a\n1 0.5 2 0 0.25 0 0 0 b\n")
    assert main(["run", str(scn), "--circle", "5", "--until", "1"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("hardspheres run: line 2: z = 0.25") and "\n" not in err
    scn.write_text("1 0.5 0 0 0 1 0 0.5 a\n")
    assert main(["run", str(scn), "--box", "4", "4", "--until", "1"]) == 1
    assert "line 1: z = 0.0, vz = 0.5" in capsys.readouterr().err


def test_resume_keeps_its_container(tmp_path, capsys):
    scn, ck = tmp_path / "s.txt", tmp_path / "c.npz"
    scn.write_text(hs.random_spheres(30, 0.3, container=hs.CircularContainer(6.0), seed=1).to_text())
    assert main(["run", str(scn), "--circle", "6", "--until", "1", "--checkpoint", str(ck)]) == 0
    assert main(["run", "--resume", str(ck), "--until", "2"]) == 0
    assert "30 disks, circular container of radius 6" in capsys.readouterr().out
    assert main(["run", "--resume", str(ck), "--circle", "6", "--until", "3"]) == 1
    assert "--circle" in capsys.readouterr().err


def test_sides_last_moves_only_the_numbers():
    assert sides_last(["run", "--box", "10", "s.txt", "--until", "5"]) == [
        "run",
        "s.txt",
        "--until",
        "5",
        "--box",
        "10",
    ]
    assert sides_last(["run", "--box", "1", "2", "3", "4", "s"]) == ["run", "s", "--box", "1", "2", "3", "4"]
    assert sides_last(["generate", "--box", "x"]) == ["generate", "--box", "x"]
    assert sides_last(["bench", "--box", "--n", "5"]) == ["bench", "--box", "--n", "5"]
    assert sides_last(["run", "--", "--box", "1"]) == ["run", "--", "--box", "1"]


def test_bench_in_two_dimensions(capsys):
    assert (
        main(
            [
                "bench",
                "--n",
                "400",
                "--packing",
                "0.5",
                "--collisions",
                "2000",
                "--warmup",
                "2",
                "--dimensions",
                "2",
                "--box",
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert out.startswith("N=400 disks packing=0.5")
    import json

    res = json.loads(out.strip().splitlines()[-1])
    assert res["dimensions"] == 2 and res["container"] == "box" and res["outside"] == 0
    assert res["enskog_collision_rate"] is None  # the 3-D formula is not quoted for disks


# ---- thermostats and compression in 2-D --------------------------------------------------


def _disks(n=300, phi=0.4, kT=1.0, seed=7):
    box = hs.PeriodicBox((30.0, 30.0 * SQRT3_2))
    return hs.Simulation(hs.random_spheres(n, phi, box, seed=seed, kT=kT), box)


def test_andersen_draws_two_components_and_brings_kT_to_target():
    sim = _disks(kT=4.0)
    sim.set_thermostat(Andersen(kT=1.0, rate=1.0, seed=1))
    sim.run(until=10.0)  # ~3000 resamplings: 10 per disk
    kts = []
    for k in range(10):
        sim.run(until=10.0 + k)
        kts.append(sim.observables.temperature())
    assert sim.state().velocities.shape == (300, 2)
    # kT over 2 degrees of freedom per disk; over 3 it would read 2/3 (DynamO's issue #54)
    assert np.mean(kts) == pytest.approx(1.0, abs=0.06)
    assert sim.thermostat.resampled > 5000


def test_velocity_rescale_in_2d_sets_kT():
    sim = _disks(kT=2.0)
    sim.set_thermostat(VelocityRescale(kT=1.0, interval=0.5))
    sim.run(until=0.5)
    st = sim.state()
    ke = 0.5 * float(np.sum(st.masses[:, None] * st.velocities**2))
    assert ke == pytest.approx(0.5 * 2 * (sim.n - 1) * 1.0, rel=1e-12)


def test_compression_of_disks_passes_the_old_unit_width_and_reaches_its_packing():
    # disks of diameter about 0.6 grown past 1: a 2-D box's cell layer along z was 1 wide,
    # and growth stopped there ("grown too large") before this was fixed
    box = hs.PeriodicBox((20.0, 20.0))
    sim = hs.Simulation(hs.random_spheres(256, 0.2, box, seed=1), box)
    res = sim.compress(packing=0.8, rate=0.01)
    assert res.reason == "packing" and sim.packing == pytest.approx(0.8, rel=1e-9)
    assert sim.engine.max_overlap() <= 1e-9 and 2.0 * sim.state().radii.max() > 1.0


def test_binary_disks_jam_near_084():
    """A 1:1.4 binary mixture of disks, 50:50, jams near packing 0.84.

    O'Hern, Silbert, Liu & Nagel, PRE 68, 011306 (2003): phi_J = 0.842 for
    this mixture (N -> infinity, soft disks quenched); hard disks compressed
    by Lubachevsky-Stillinger jam a little above it at slow rates.
    """
    box = hs.PeriodicBox((14.0, 14.0))
    state = hs.random_spheres(128, 0.3, box, seed=1, binary=(1.4, 0.5))
    sim = hs.Simulation(state, box)
    sim.run(collisions=256)
    res = sim.compress(rate=0.003, pressure=1e4)
    assert res.jammed
    assert 0.83 < res.packing < 0.86, res.packing  # seeds 1, 2, 3: 0.8430, 0.8459, 0.8468
