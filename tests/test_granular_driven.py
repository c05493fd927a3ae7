"""Driven granular gases: the random-kick (white-noise) thermostat and its energy tally.

:class:`hardspheres.dense.RandomKicks` gives every sphere a Gaussian velocity
kick of variance ``strength * interval`` per component every ``interval``,
less the mass-weighted mean kick.  Checked here: the mean injection rate
``(N - 1) d m strength / 2`` (elastic collisions conserve energy, so the
kinetic energy grows by it on average), the tally (kinetic plus dissipated
less injected energy conserved to rounding), the momentum, checkpoints
resuming bit for bit, and bad input.
"""

import math
import re

import numpy as np
import pytest
from helpers import hs_cmd

import hardspheres as hs
from hardspheres.dense import RandomKicks, thermostat_from_state
from hardspheres.errors import ArgumentError


def _gas(n, phi, dims, seed=1, restitution=1.0, kT=1.0):
    box = hs.PeriodicBox.for_packing(n, phi, (1.0, 1.0) if dims == 2 else None)
    state = hs.random_spheres(n, phi, box, seed=seed, kT=kT)
    return hs.Simulation(state, box, restitution=restitution)


@pytest.mark.parametrize("dims", [2, 3])
def test_kicks_inject_the_analytic_rate(dims):
    """d<E_kin>/dt = (N - 1) d m strength / 2: kinetic energy from nearly at rest, 400 spheres."""
    n, strength, interval, t = 400, 2.0, 0.01, 1.0
    sim = _gas(n, 0.05, dims, kT=1e-6)
    kicks = RandomKicks(strength, interval, seed=3)
    sim.set_thermostat(kicks)
    e0 = sim.engine.kinetic_energy()
    sim.run(until=t + interval / 2)
    assert kicks.kicks == 100
    expected = kicks.injection_rate(sim.engine.masses, dims) * t
    assert expected == pytest.approx((n - 1) * dims * strength / 2 * t)
    gained = sim.engine.kinetic_energy() - e0
    # the final kinetic energy is a sum of d N squares of normals: relative sd sqrt(2 / (d N))
    sd = math.sqrt(2.0 / (dims * n))
    assert abs(gained / expected - 1.0) < 4 * sd
    assert kicks.injected == pytest.approx(gained, rel=1e-12)
    assert sim.observables.injected() == pytest.approx(gained, rel=1e-12)
    assert sim.engine.max_overlap() <= 1e-9


def test_driven_granular_gas_balances_energy_and_momentum():
    """Inelastic disks, kicked: kinetic + dissipated - injected is the initial energy to rounding."""
    sim = _gas(200, 0.1, 2, restitution=0.8)
    p0 = (sim.engine.masses[:, None] * sim.engine.velocities).sum(axis=0)
    sim.set_thermostat(RandomKicks(strength=1.0, interval=0.05, seed=2))
    sim.observables.reset()
    sim.run(until=20.0)
    obs = sim.observables
    assert obs.injected() > 2 * sim.engine.kinetic_energy() > 0
    assert obs.dissipated() > 0
    assert abs(obs.energy_balance()) < 1e-12
    p1 = (sim.engine.masses[:, None] * sim.engine.velocities).sum(axis=0)
    assert np.allclose(p1, p0, atol=1e-12)
    summary = obs.summary()
    assert summary["injected"] == obs.injected()
    assert abs(summary["energy_balance"]) < 1e-12


def test_injected_counts_from_when_the_thermostat_is_set():
    sim = _gas(100, 0.1, 2, restitution=0.9)
    sim.run(until=1.0)  # cools, no driving
    kicks = RandomKicks(strength=1.0, interval=0.1, seed=1)
    sim.set_thermostat(kicks)
    sim.run(until=3.0)
    assert sim.observables.injected() == kicks.injected > 0
    assert abs(sim.observables.energy_balance()) < 1e-12
    sim.set_thermostat(None)  # what it injected stays counted
    sim.run(until=4.0)
    assert sim.observables.injected() == kicks.injected
    assert abs(sim.observables.energy_balance()) < 1e-12


def test_kicks_are_reproducible_and_resume_bit_for_bit(tmp_path):
    def make():
        return _gas(150, 0.1, 2, seed=4, restitution=0.7).set_thermostat(RandomKicks(0.5, 0.03, seed=9))

    a, b = make(), make()
    a.run(until=2.0)
    b.run(until=2.0)
    assert np.array_equal(a.engine.velocities, b.engine.velocities)
    a.save(tmp_path / "a.npz")
    c = hs.Simulation.load(tmp_path / "a.npz")
    assert isinstance(c.thermostat, RandomKicks)
    a.run(until=4.0)
    c.run(until=4.0)
    assert np.array_equal(a.engine.velocities, c.engine.velocities)
    assert a.thermostat.kicks == c.thermostat.kicks > 100
    assert a.thermostat.injected == c.thermostat.injected
    again = thermostat_from_state(a.thermostat.state())
    assert again.state() == a.thermostat.state()


@pytest.mark.parametrize(
    ("args", "word"),
    [
        ((0.0, 0.1), "strength"),
        ((-1.0, 0.1), "strength"),
        ((1.0, 0.0), "interval"),
        ((math.nan, 1.0), "strength"),
    ],
)
def test_bad_kicks_are_refused(args, word):
    with pytest.raises(ArgumentError, match=word):
        RandomKicks(*args)


# ---- the kicks on the command line and in studies -------------------------------------------


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    """200 spheres at packing 0.1 in a box of edge 12.6 (the mean free time about 0.6 at kT = 1)."""
    folder = tmp_path_factory.mktemp("kicks")
    (folder / "g.txt").write_text(hs.random_spheres(200, 0.1, box=12.6, seed=3).to_text())
    return folder


def test_run_command_drives_with_kicks_and_resumes_them(scenario):
    run = ("run", "g.txt", "--box", "12.6", "--restitution", "0.8", "--kicks", "1.0")
    r = hs_cmd(*run, "--until", "3.01", "--kick-interval", "0.02", "--kick-seed", "2", "--checkpoint",
               "k.npz", cwd=scenario, check=True)  # fmt: skip
    assert "granular (restitution 0.8), driven: injected" in r.stdout
    assert "kinetic + dissipated - injected energy drift" in r.stdout
    assert "driven by white-noise kicks (strength 1, every 0.02)" in r.stdout
    assert "Haff's law" not in r.stdout and "warning" not in r.stderr
    drift = float(re.search(r"injected energy drift (\S+)", r.stdout).group(1))
    assert drift < 1e-12
    sim = hs.Simulation.load(scenario / "k.npz")
    assert isinstance(sim.thermostat, RandomKicks) and sim.thermostat.seed == 2
    assert sim.thermostat.kicks == 150  # every 0.02 up to t = 3.01
    again = hs_cmd("run", "--resume", "k.npz", "--until", "3.51", cwd=scenario, check=True)
    assert "driven by white-noise kicks (strength 1, every 0.02)" in again.stdout
    assert hs.Simulation.load(scenario / "k.npz").thermostat.kicks == 175


def test_run_command_warns_of_a_long_kick_interval(scenario):
    r = hs_cmd("run", "g.txt", "--box", "12.6", "--restitution", "0.8", "--kicks", "1.0",
               "--kick-interval", "1.0", "--until", "4", cwd=scenario, check=True)  # fmt: skip
    assert "warning: the kicks come every" in r.stderr and "--kick-interval" in r.stderr


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (("--kicks", "1"), ["--kicks needs --kick-interval"]),
        (("--kick-interval", "0.1", "--restitution", "0.9"), ["--kick-interval", "give --kicks"]),
        (("--kick-seed", "3", "--restitution", "0.9"), ["--kick-seed", "give --kicks"]),
        (("--kicks", "1", "--kick-interval", "0.1"), ["--kicks", "--restitution below 1"]),
        (("--kicks", "0", "--kick-interval", "0.1", "--restitution", "0.9"), ["--kicks", "> 0"]),
        (("--kicks", "1", "--kick-interval", "-1", "--restitution", "0.9"), ["--kick-interval", "> 0"]),
        (("--kicks", "1", "--kick-interval", "0.1", "--kick-seed", "1.5", "--restitution", "0.9"),
         ["--kick-seed", "whole number"]),
        (("--kicks", "1", "--kick-interval", "0.1", "--restitution", "0.9", "--pressure", "2"),
         ["--kicks with --pressure"]),
        (("--kicks", "1", "--kick-interval", "0.1", "--restitution", "0.9", "--wall-temperature", "1"),
         ["--kicks with --wall-temperature"]),
    ],
)  # fmt: skip
def test_run_command_refuses_bad_kicks(scenario, args, words):
    r = hs_cmd("run", "g.txt", "--box", "12.6", "--until", "1", *args, cwd=scenario)
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    for w in words:
        assert w in r.stderr, r.stderr


def test_run_command_refuses_new_kicks_on_resume(scenario):
    (scenario / "plain.txt").write_text(hs.random_spheres(20, 0.1, box=6.0, seed=1).to_text())
    hs_cmd("run", "plain.txt", "--box", "6", "--until", "0.5", "--restitution", "0.9", "--checkpoint",
           "p.npz", cwd=scenario, check=True)  # fmt: skip
    r = hs_cmd("run", "--resume", "p.npz", "--until", "1", "--kicks", "1", "--kick-interval", "0.1",
               cwd=scenario)  # fmt: skip
    assert r.returncode == 1 and "keeps its driving" in r.stderr and "Traceback" not in r.stderr


def test_a_study_with_kicks():
    from hardspheres.studies import parse_study
    from hardspheres.studies.task import _build, kick_seed, tasks

    base = {"packing": 0.1, "n": 100, "output": "x", "restitution": 0.8}
    plain = tasks(parse_study(base))
    study = parse_study({**base, "kicks": [0.5, 1.0], "kick_interval": 0.05, "seeds": 2})
    assert study["measure"] == ["temperature", "a2"]
    ts = tasks(study)
    assert [(t["kicks"], t["kick_interval"], t["seed"]) for t in ts] == [
        (0.5, 0.05, 0), (0.5, 0.05, 1), (1.0, 0.05, 0), (1.0, 0.05, 1)
    ]  # fmt: skip
    assert "kicks" not in plain[0] and plain[0]["key"] not in {t["key"] for t in ts}
    assert len({t["key"] for t in ts}) == 4
    kicks = _build(ts[3]).thermostat
    assert isinstance(kicks, RandomKicks)
    assert (kicks.strength, kicks.interval, kicks.seed) == (1.0, 0.05, kick_seed(1))
    assert kick_seed(1) not in (0, 1) and kick_seed(0) != kick_seed(1)


@pytest.mark.parametrize(
    ("keys", "words"),
    [
        ({"kicks": 1.0}, ["kicks needs kick_interval"]),
        ({"kick_interval": 0.1}, ["kick_interval is for the kicks"]),
        ({"kicks": 0.0, "kick_interval": 0.1}, ["kicks = 0.0"]),
        ({"kicks": 1.0, "kick_interval": [0.1, -1]}, ["kick_interval = -1"]),
        ({"kicks": 1.0, "kick_interval": 0.1, "restitution": [0.8, 1.0]}, ["restitution below 1"]),
        ({"kicks": 1.0, "kick_interval": 0.1, "restitution": None}, ["restitution below 1"]),
        ({"kicks": 1.0, "kick_interval": 0.1, "measure": ["Z"]}, ["measure: Z", "driven by kicks"]),
        ({"kicks": 1.0, "kick_interval": 0.1, "measure": ["cooling_rate"]}, ["cooling_rate"]),
    ],
)
def test_bad_kicks_in_a_study_are_refused(keys, words):
    from hardspheres.errors import StudyError
    from hardspheres.studies import parse_study

    data = {"packing": 0.1, "n": 100, "output": "x", "restitution": 0.8, **keys}
    data = {k: v for k, v in data.items() if v is not None}
    with pytest.raises(StudyError) as e:
        parse_study(data, source="s.toml")
    assert str(e.value).startswith("s.toml: ") and "\n" not in str(e.value)
    for w in words:
        assert w in str(e.value)


def test_a_driven_task_resumes_to_the_same_row(tmp_path, monkeypatch):
    """A driven task cut after a checkpoint ends with the uninterrupted one's row (the kicks' state saved)."""
    from hardspheres import studies
    from hardspheres.studies import measures as study_measures
    from hardspheres.studies import task as study_task

    monkeypatch.setattr(study_task, "STEP", 40)
    spec = studies.parse_study(
        {"packing": 0.1, "n": 64, "restitution": 0.8, "kicks": 1.0, "kick_interval": 0.05,
         "equilibrate": 4, "collisions": 20, "blocks": 3, "checkpoint_seconds": 0, "output": "x"}
    )  # fmt: skip
    whole = dict(studies.tasks(spec)[0], folder=str(tmp_path / "whole"))
    cut = dict(whole, folder=str(tmp_path / "cut"))
    ref = studies.run_task(whole)
    assert ref["kicks"] == 1.0 and ref["kick_interval"] == 0.05 and ref["temperature"] > 0

    class Stop(Exception):
        pass

    calls = {"k": 0}
    real = study_measures.block_value

    def flaky(name, sim, obs):  # dies in block 2, after checkpoints were written
        calls["k"] += 1
        if calls["k"] == 3:
            raise Stop
        return real(name, sim, obs)

    monkeypatch.setattr(study_task, "block_value", flaky)
    with pytest.raises(Stop):
        studies.run_task(cut)
    monkeypatch.setattr(study_task, "block_value", real)
    assert studies.run_task(cut) == ref


def test_run_command_balances_a_resumed_thermal_wall(tmp_path):
    """A checkpoint with a heated wall, resumed by ``run``: its heat counts in the energy line."""
    box = hs.SphericalContainer(8.0)
    sim = hs.Simulation(hs.random_spheres(60, 0.1, box, seed=2), box, restitution=0.9)
    sim.set_wall_temperature(2.0, seed=1).run(until=1.0)
    sim.save(tmp_path / "w.npz")
    r = hs_cmd("run", "--resume", "w.npz", "--until", "6", cwd=tmp_path, check=True)
    assert "driven: injected" in r.stdout, r.stdout
    drift = float(re.search(r"injected energy drift (\S+)", r.stdout).group(1))
    assert drift < 1e-12
