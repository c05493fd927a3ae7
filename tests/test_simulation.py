"""The library API: Simulation, observables, checkpoints, validation, commands."""

import json
import math
import signal
import time
from pathlib import Path

import numpy as np
import pytest
from helpers import hs_cmd, hs_popen, spheres_cmd

import hardspheres as hs
from hardspheres.studies.validate import carnahan_starling, eos_point, ks_distance

ROOT = Path(__file__).resolve().parents[1]


def small_sim(box=False, seed=1, n=300):
    if box:
        return hs.Simulation(hs.random_spheres(n, 0.3, box=12.0, seed=seed), hs.PeriodicBox(12.0))
    return hs.Simulation(hs.random_spheres(n, 0.3, container=8.0, seed=seed), hs.SphericalContainer(8.0))


def test_from_arrays_and_state_at_any_time():
    sim = hs.Simulation.from_arrays(
        [1.0, 3.0],
        [1.0, 1.0],
        [[-5, 0, 0], [5, 0, 0]],
        [[2, 0, 0], [0, 0, 0]],
        hs.SphericalContainer(50.0),
        names=["a", "b"],
    )
    assert list(sim.iter_events(until=3.5)) == []  # gap 8 closing at speed 2
    evs = list(sim.iter_events(until=4.5))
    assert [(e.time, e.kind, e.i, e.j) for e in evs] == [(4.0, "collision", 0, 1)]
    # 1-D elastic: v1' = (m1 - m2)/(m1 + m2) v1 = -1, v2' = 2 m1/(m1 + m2) v1 = 1
    with pytest.raises(ValueError, match="run"):
        sim.state(5.0)  # state() never runs the simulation
    assert sim.time == 4.5
    st = sim.run(until=5.0).state()
    np.testing.assert_allclose(st.velocities[:, 0], [-1.0, 1.0])
    # contact at x = 3 (a) and 5 (b) at t = 4, then one unit apart each
    np.testing.assert_allclose(st.positions[:, 0], [2.0, 6.0])
    assert st.names == ["a", "b"] and st.time == 5.0
    # impulse magnitude on sphere a: m1 |dv| = 3
    assert math.isclose(evs[0].impulse, 3.0)
    with pytest.raises(ValueError, match="past"):
        sim.state(1.0)


def test_from_scenario_file_and_errors(tmp_path):
    path = tmp_path / "s.txt"
    path.write_text("1 1 0 0 0 1 0 0 a\n1 1 5 0 0 0 0 0 b\n")
    sim = hs.Simulation.from_scenario(str(path), hs.SphericalContainer(10.0))
    assert sim.n == 2 and sim.names == ["a", "b"]
    with pytest.raises(hs.ScenarioError, match="line 2"):
        hs.Simulation.from_scenario("1 1 0 0 0 1 0 0 a\n1 1 1 0 0 0 0 0 b\n", hs.SphericalContainer(10.0))
    with pytest.raises(hs.ScenarioError, match="overlap"):
        hs.Simulation.from_arrays(
            [1, 1], [1, 1], [[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)), hs.PeriodicBox(10.0)
        )
    with pytest.raises(ValueError):
        small_sim().run()


def test_periodic_box_conserves_momentum_and_wraps():
    sim = small_sim(box=True)
    p0 = sim.state().momentum()
    sim.run(collisions=20000)
    st = sim.state()
    np.testing.assert_allclose(st.momentum(), p0, atol=1e-10)
    assert np.all(np.abs(st.positions) <= 6.0 + 1e-9)
    assert sim.counters["reflections"] == 0


def test_run_stops_at_limits():
    sim = small_sim()
    sim.run(collisions=1234)
    assert sim.counters["collisions"] == 1234
    evs = list(sim.iter_events(events=100))
    assert len(evs) == 100
    assert all(a.time <= b.time for a, b in zip(evs, evs[1:]))
    sim.run(until=sim.time + 1.0)
    t = sim.time
    assert sim.state().time == t


def test_checkpoint_resumes_bit_for_bit(tmp_path):
    a = small_sim(seed=3)
    b = small_sim(seed=3)
    a.run(collisions=5000)
    b.run(collisions=5000)
    b.save(tmp_path / "ck.npz")
    c = hs.Simulation.load(tmp_path / "ck.npz")
    ea = [tuple(e) for e in a.iter_events(events=30000)]
    ec = [tuple(e) for e in c.iter_events(events=30000)]
    assert ea == ec
    np.testing.assert_array_equal(a.state().positions, c.state().positions)


def test_observables_in_container_and_box():
    sim = small_sim()
    sim.run(collisions=3000)
    obs = sim.observables.reset()
    sim.run(collisions=30000)
    s = obs.summary()
    assert s["elapsed"] > 0 and s["pressure"] > 0
    assert math.isclose(obs.mean_free_time(), 1.0 / obs.collision_rate())
    assert math.isclose(obs.mean_free_path(), obs.mean_speed() / obs.collision_rate())
    # a container's wall pressure at packing 0.3 is of order the bulk one
    assert 2.0 < s["compressibility"] < 6.0
    counts, edges = obs.speed_histogram(bins=20)
    assert counts.sum() == sim.n and len(edges) == 21


def test_validation_short():
    """A short hardspheres validate: Z near Carnahan-Starling, Gamma consistent with Z."""
    row = eos_point(0.3, n=1000, equilibrate=20, collisions=100, blocks=10, seed=2)
    assert abs(row.rel_diff) < 0.03
    assert abs(row.gamma_rel_diff) < 0.02
    assert row.ks_D < 3 * row.ks_D_expected
    assert math.isclose(carnahan_starling(0.3), 3.97376, rel_tol=1e-5)


def test_ks_distance_detects_wrong_temperature():
    rng = np.random.default_rng(0)
    speeds = np.linalg.norm(rng.normal(size=(20000, 3)), axis=1)
    assert ks_distance(speeds, kT=1.0) < 0.015
    assert ks_distance(speeds, kT=1.5) > 0.05


def test_generate_and_run_commands(tmp_path):
    out = hs_cmd("generate", "--n", "300", "--container", "8", "--packing", "0.3", "--seed", "2")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert len(lines) == 300 and len(lines[0].split()) == 9
    scn = tmp_path / "s.txt"
    scn.write_text(out.stdout)
    ck = tmp_path / "ck.npz"
    res = hs_cmd("run", str(scn), "--container", "8", "--until", "2", "--checkpoint", str(ck))
    assert res.returncode == 0, res.stderr
    assert "collisions" in res.stdout and "energy drift" in res.stdout
    assert "events/s" in res.stdout and ck.exists()
    res2 = hs_cmd("run", "--resume", str(ck), "--until", "3")
    assert res2.returncode == 0, res2.stderr
    assert res2.stdout.startswith("time 3")


def test_generate_refuses_impossible_packing():
    out = hs_cmd("generate", "--n", "5", "--container", "1", "--packing", "0.6")
    assert out.returncode == 1
    assert out.stderr.count("\n") == 1 and "lower the packing" in out.stderr


def test_run_interrupted_leaves_checkpoint(tmp_path):
    scn = tmp_path / "s.txt"
    scn.write_text(hs.random_spheres(3000, 0.3, container=20.0, seed=1).to_text())
    ck = tmp_path / "ck.npz"
    proc = hs_popen("run", scn, "--container", "20", "--until", "1e9", "--checkpoint", ck)
    time.sleep(8.0)  # past the start-up (about 4 s of wall time on a loaded 2-core machine)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "interrupted" in out
    assert ck.exists()
    sim = hs.Simulation.load(ck)
    assert sim.counters["collisions"] > 0


def test_spheres_jsonl():
    res = spheres_cmd("--format", "jsonl", "120", "200", input=(ROOT / "examples" / "three.txt").read_text())
    assert res.returncode == 0
    rows = [json.loads(x) for x in res.stdout.splitlines()]
    assert rows[0]["kind"] == "initial" and len(rows[0]["spheres"]) == 3
    assert rows[1]["kind"] == "collision" and rows[1]["spheres"] == ["one", "two"]
    assert f"{rows[1]['time']:g}" == "94.0839"
    text = spheres_cmd("120", "200", input=(ROOT / "examples" / "three.txt").read_text()).stdout
    kinds = [ln.split()[0] for ln in text.splitlines() if ln.startswith(("colliding", "reflecting"))]
    assert [r["kind"][:4] for r in rows[1:]] == [k[:4] for k in kinds]
