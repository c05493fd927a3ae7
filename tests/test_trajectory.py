"""Trajectories: GSD (double precision) and extended XYZ, read back against the run."""

import numpy as np
import pytest
from helpers import hs_cmd

import hardspheres as hs
from hardspheres.events import EVENT_DTYPE
from hardspheres.io.trajectory import GSDWriter, XYZWriter, frames_from_simulation, read_trajectory

gsd_hoomd = pytest.importorskip("gsd.hoomd")


def _sim(box=False, n=60, seed=3):
    if box:
        state = hs.random_spheres(n, 0.3, box=8.0, seed=seed)
        return hs.Simulation(state, hs.PeriodicBox(8.0))
    state = hs.random_spheres(n, 0.1, container=6.0, seed=seed, radius_ratio=1.5, mass_ratio=5.0)
    state.names = [f"ball-{i}-é" for i in range(n)]  # names are kept, UTF-8 included
    return hs.Simulation(state, hs.SphericalContainer(6.0))


@pytest.mark.parametrize("box", [False, True])
def test_gsd_frames_match_the_run(tmp_path, box):
    path = tmp_path / "run.gsd"
    sim = _sim(box)
    with GSDWriter(path, every=0.25) as w:
        sim.writers.append(w)
        sim.run(until=2.0)
    frames = read_trajectory(str(path))

    ref = _sim(box)
    assert frames.times.tolist() == [0.25 * k for k in range(9)]
    assert frames.names == ref.names
    assert frames.positions.dtype == np.float64
    np.testing.assert_array_equal(frames.radii, ref.state().radii)
    np.testing.assert_array_equal(frames.masses, ref.state().masses)
    if box:
        assert frames.container == hs.PeriodicBox(8.0) and frames.box == 8.0
    else:
        assert frames.container == hs.SphericalContainer(6.0) and frames.box is None
    events = list(ref.iter_events(until=2.0))
    assert len(events) > 50
    assert frames.events.dtype == EVENT_DTYPE
    assert frames.event_kinds.tolist() == [int(e.kind == "collision") for e in events]
    # the impulse is read back, too
    np.testing.assert_allclose(frames.events["impulse"], [e.impulse for e in events], rtol=1e-12)
    assert frames.event_i.tolist() == [e.i for e in events]
    assert frames.event_j.tolist() == [e.j for e in events]
    np.testing.assert_allclose(frames.event_times, [e.time for e in events], rtol=1e-12)

    _assert_replayed(frames, _sim(box))


def test_gsd_is_double_precision_hoomd_schema(tmp_path):
    path = tmp_path / "run.gsd"
    sim = _sim()
    with GSDWriter(path, every=0.5) as w:
        sim.writers.append(w)
        sim.run(until=1.0)
    with gsd_hoomd.open(str(path), "r") as traj:
        assert len(traj) == 3
        f = traj[2]
        assert f.particles.position.dtype == np.float64
        assert f.particles.N == 60
        assert f.configuration.box[:3].tolist() == [12.0, 12.0, 12.0]
        assert f.log["hardspheres/time"][0] == 1.0
        assert f.log["hardspheres/container_radius"][0] == 6.0
        # static data from the first frame
        np.testing.assert_array_equal(f.particles.diameter, 2 * sim.state().radii)


def _assert_replayed(frames, again):
    """Every frame is ``again`` run to its time, to every digit (single precision would miss by ~1e-7)."""
    for t, pos, vel in zip(frames.times, frames.positions, frames.velocities):
        st = again.run(until=t).state()
        np.testing.assert_allclose(pos, st.positions, rtol=0, atol=1e-12)
        np.testing.assert_allclose(vel, st.velocities, rtol=0, atol=1e-12)


@pytest.mark.parametrize("box", [False, True])
def test_xyz_reads_back_exactly(tmp_path, box):
    sim = _sim(box)
    with XYZWriter(tmp_path / "run.xyz", every=0.5) as w:
        sim.writers.append(w)
        sim.run(until=1.5)
    frames = read_trajectory(str(tmp_path / "run.xyz"))
    again = _sim(box)
    assert frames.times.tolist() == [0.0, 0.5, 1.0, 1.5]
    assert frames.names == again.names
    _assert_replayed(frames, again)
    header = (tmp_path / "run.xyz").read_text().split("\n")[1]
    assert "Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1" in header
    assert ('pbc="T T T"' if box else 'pbc="F F F"') in header


def test_xyz_refuses_names_it_cannot_keep(tmp_path):
    sim = hs.Simulation.from_arrays(
        [1.0], [1.0], [[0, 0, 0]], [[1, 0, 0]], hs.SphericalContainer(3.0), names=["a b"]
    )
    sim.writers.append(XYZWriter(tmp_path / "x.xyz", every=1.0))
    with pytest.raises(ValueError, match="use GSD"):
        sim.run(until=1.0)


def test_frames_from_simulation_ends_on_until():
    frames = frames_from_simulation(_sim(), until=1.05, every=0.5)
    assert frames.times.tolist() == [0.0, 0.5, 1.0, 1.05]
    e = frames.energy()
    np.testing.assert_allclose(e, e[0], rtol=1e-12)


def test_writer_survives_several_runs(tmp_path):
    sim = _sim()
    with GSDWriter(tmp_path / "run.gsd", every=0.3) as w:
        sim.writers.append(w)
        sim.run(until=0.5)
        sim.run(until=1.0)
    assert read_trajectory(str(tmp_path / "run.gsd")).times.tolist() == pytest.approx([0.0, 0.3, 0.6, 0.9])


def test_not_a_trajectory(tmp_path):
    p = tmp_path / "bad.gsd"
    p.write_bytes(b"not a gsd file")
    with pytest.raises(ValueError, match="bad.gsd"):
        read_trajectory(str(p))
    q = tmp_path / "bad.xyz"
    q.write_text("3\nno keys here\n")
    with pytest.raises(ValueError, match="bad.xyz"):
        read_trajectory(str(q))
    with pytest.raises(ValueError, match="every"):
        GSDWriter(tmp_path / "x.gsd", every=0.0)


def test_run_command_writes_a_trajectory(tmp_path):
    scn = tmp_path / "scn.txt"
    scn.write_text(hs.random_spheres(40, 0.2, container=5.0, seed=2).to_text())
    out = tmp_path / "out.gsd"
    r = hs_cmd(
        "run", str(scn), "--container", "5", "--until", "2", "--trajectory", str(out), "--every", "0.5"
    )
    assert r.returncode == 0, r.stderr
    assert f"trajectory {out}" in r.stdout
    frames = read_trajectory(str(out))
    assert frames.times.tolist() == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert frames.container == hs.SphericalContainer(5.0) and frames.n == 40


def test_public_names():
    assert hs.GSDWriter is GSDWriter and hs.XYZWriter is XYZWriter
    assert hs.read_trajectory is read_trajectory
