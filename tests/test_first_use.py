"""Small things a first user met: limits quoted for the right dimension, one-line errors, one rule for
existing outputs, D printed, and a plot that runs no simulation."""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.cli.commands import main
from hardspheres.errors import ContainerError


def test_generate_quotes_the_limit_of_its_dimension(capsys):
    assert main(["generate", "--n", "100", "--box", "10", "10", "--packing", "0.8"]) == 1
    err = capsys.readouterr().err
    assert "0.7405" not in err and "disks" in err, err  # the disks' limits, not the spheres'
    assert main(["generate", "--n", "100", "--box", "10", "--packing", "0.8"]) == 1
    assert "not below 0.7405, the densest packing of equal spheres" in capsys.readouterr().err


@pytest.mark.parametrize("packing", [-0.3, 0, 0.0, float("nan"), 1.5])
def test_for_packing_refuses_a_packing_outside_0_1_in_one_line(packing):
    for cls in (hs.PeriodicBox, hs.SphericalContainer, hs.CircularContainer):
        with pytest.raises(
            ContainerError, match=r"^packing must be a fraction in \(0, 1\), got .*; give e\.g\. 0\.3$"
        ):
            cls.for_packing(100, packing)


def test_a_box_too_small_says_three_times_the_largest_diameter():
    with pytest.raises(hs.BoxShapeError, match="narrower than three times the largest diameter"):
        hs.Simulation.from_arrays(
            [1, 1], [1, 1], [[0, 0, 0], [2.5, 0, 0]], [[0, 0, 0], [1, 0, 0]], hs.PeriodicBox(5.0)
        )
    with pytest.raises(hs.BuildError, match="three times the largest diameter wide"):
        hs.random_spheres(1, 0.3, hs.PeriodicBox(1.5))


def test_a_text_file_given_to_resume_is_not_a_checkpoint(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("hello\n")
    assert main(["run", "--resume", str(tmp_path / "notes.txt"), "--until", "2"]) == 1
    err = capsys.readouterr().err
    assert "not a checkpoint" in err and "pickle" not in err and len(err.strip().splitlines()) == 1


@pytest.fixture
def scenario(tmp_path):
    box = hs.PeriodicBox.for_packing(64, 0.3).length
    (tmp_path / "s.txt").write_text(hs.random_spheres(64, 0.3, box=box, seed=1).to_text())
    return tmp_path, box


@pytest.mark.parametrize(
    "argv",
    [
        ["view", "{s}", "--box", "{box}", "--until", "1", "-o", "{out}.html"],
        ["plot", "speeds", "{s}", "--box", "{box}", "--until", "1", "-o", "{out}.png"],
        ["render", "{s}", "--box", "{box}", "--until", "1", "-o", "{out}.png"],
        ["run", "{s}", "--box", "{box}", "--until", "1", "--trajectory", "{out}.gsd"],
    ],
)
def test_every_command_refuses_an_existing_output_unless_overwrite(scenario, capsys, argv):
    tmp, box = scenario
    args = [a.format(s=tmp / "s.txt", box=box, out=tmp / "out") for a in argv]
    target = next(a for a in args if str(tmp / "out") in a)
    with open(target, "w") as fh:
        fh.write("keep me")
    assert main(args) == 1
    err = capsys.readouterr().err
    assert f"{target} exists; give --overwrite to replace it, or another file name" in err, err
    assert open(target).read() == "keep me"
    assert main([*args, "--overwrite"]) == 0 and open(target, "rb").read(7) != b"keep me"


def test_plot_msd_prints_d_and_the_frames_it_is_from(scenario, capsys):
    tmp, box = scenario
    traj = tmp / "r.gsd"
    assert (
        main(
            [
                "run",
                str(tmp / "s.txt"),
                "--box",
                str(box),
                "--until",
                "20",
                "--equilibrate",
                "20",
                "--trajectory",
                str(traj),
                "--every",
                "0.1",
            ]
        )
        == 0
    )
    capsys.readouterr()
    assert main(["plot", "msd", str(traj), "-o", str(tmp / "m.png")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("D = ") and "+-" in out and "includes its --equilibrate part; --from T" in out
    assert main(["plot", "msd", str(traj), "--from", "5", "-o", str(tmp / "m2.png")]) == 0
    assert "from --from 5" in capsys.readouterr().out


def test_plot_contacts_runs_no_simulation(scenario, monkeypatch, tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("scipy")
    from hardspheres.analysis.collisions import packing_contact_forces
    from hardspheres.viz import plots

    tmp, box = scenario
    sim = hs.Simulation.from_scenario((tmp / "s.txt").read_text(), hs.PeriodicBox(box))
    forces = packing_contact_forces(sim, per_sphere=20)
    assert forces.forces.size > 0 and np.all(forces.forces > 0)

    def no_run(*a, **k):
        raise AssertionError("a picture ran a simulation")

    monkeypatch.setattr(hs.Simulation, "run", no_run)
    assert plots.plot_contacts(sim, tmp_path / "c.png", forces).exists()
