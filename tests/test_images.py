"""Image counts and unwrapped positions in the periodic box."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.containers import PeriodicBoxRequired
from hardspheres.trajectory import GSDWriter, frames_from_simulation, read_trajectory


def gas(n=64, phi=0.2, seed=3, kT=4.0):
    box = (n * math.pi / (6.0 * phi)) ** (1.0 / 3.0)
    st = hs.random_spheres(n, phi, box=box, seed=seed, kT=kT)
    return hs.Simulation(st, hs.PeriodicBox(box)), box


def brute_unwrap(pos, box):
    """Unwrap a fine-grained trajectory by summing minimum-image steps between frames."""
    step = np.diff(pos, axis=0)
    step -= box * np.rint(step / box)
    return pos[0] + np.concatenate([np.zeros((1,) + pos.shape[1:]), np.cumsum(step, axis=0)])


def test_images_match_brute_force_unwrapping():
    sim, box = gas()
    vmax = np.abs(sim.state().velocities).max()
    # frames close enough that no sphere moves half a box between them (checked below)
    dt = 0.1 * box / (4 * vmax)
    fr = frames_from_simulation(sim, until=400 * dt, every=dt)
    assert np.abs(fr.velocities).max() * dt < 0.5 * box
    ref = brute_unwrap(fr.positions, box)
    # most spheres crossed the box, some many times: the test can fail
    crossed = np.abs(fr.images[-1]).sum(axis=1)
    assert np.mean(crossed > 0) > 0.8 and crossed.max() >= 3
    np.testing.assert_array_equal(np.rint((ref - fr.positions) / box), fr.images)
    np.testing.assert_allclose(fr.unwrapped(), ref, rtol=0, atol=1e-9 * box)
    end = sim.state(unwrapped=True)
    np.testing.assert_allclose(end.positions, ref[-1], rtol=0, atol=1e-9 * box)
    np.testing.assert_array_equal(end.images, fr.images[-1])


def test_free_flight_is_exact():
    """A lone sphere crosses the box at known times: images are the integer part."""
    box = 10.0
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[0.0, 0.0, 0.0]], [[3.0, -7.0, 0.25]],
                                    hs.PeriodicBox(box))
    st = sim.run(until=100.0).state(unwrapped=True)  # state() never runs the simulation
    np.testing.assert_allclose(st.positions[0], [300.0, -700.0, 25.0], rtol=1e-12)
    # 300 = 30 boxes, -700 = -70 boxes, 25 = 3 boxes - 5 (the box is [-L/2, L/2))
    np.testing.assert_array_equal(st.images[0], [30, -70, 3])


def test_input_outside_the_box_keeps_its_unwrapped_centre():
    box = 10.0
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[23.0, -14.0, 1.0]], [[0, 0, 0]],
                                    hs.PeriodicBox(box))
    st = sim.state()
    np.testing.assert_array_equal(st.images, [[2, -1, 0]])
    np.testing.assert_allclose(sim.state(unwrapped=True).positions, [[23.0, -14.0, 1.0]])
    # a state with images round-trips through a new simulation
    again = hs.Simulation(st, hs.PeriodicBox(box)).state(unwrapped=True)
    np.testing.assert_allclose(again.positions, [[23.0, -14.0, 1.0]])


def test_checkpoint_and_gsd_keep_images(tmp_path):
    pytest.importorskip("gsd")
    sim, _ = gas(n=32)
    with GSDWriter(tmp_path / "t.gsd", every=0.5) as w:
        sim.writers.append(w)
        sim.run(until=3.0)
    fr = read_trajectory(tmp_path / "t.gsd")
    assert np.abs(fr.images).sum() > 0
    np.testing.assert_array_equal(fr.images[-1], sim.state().images)
    sim.writers.clear()
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    sim.run(until=6.0)
    back.run(until=6.0)
    np.testing.assert_array_equal(back.state(unwrapped=True).positions,
                                  sim.state(unwrapped=True).positions)


def test_images_in_a_spherical_container_raise():
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[0, 0, 0]], [[1, 0, 0]],
                                    hs.SphericalContainer(5.0))
    assert sim.state().images is None
    with pytest.raises(PeriodicBoxRequired, match="periodic box"):
        sim.state(unwrapped=True)


def test_gsd_without_images_is_not_taken_as_zero_images(tmp_path):
    """A file from before image counts: no marker, so no images (not silently zero)."""
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    path = tmp_path / "old.gsd"
    with gsd_hoomd.open(path, mode="w") as f:
        fr = gsd_hoomd.Frame()
        fr.particles.N = 1
        fr.particles.position = np.zeros((1, 3))
        fr.configuration.box = [10, 10, 10, 0, 0, 0]
        fr.log["hardspheres/time"] = np.array([0.0])
        fr.log["hardspheres/box_length"] = np.array([10.0])
        f.append(fr)
    frames = read_trajectory(path)
    assert frames.images is None
    with pytest.raises(PeriodicBoxRequired, match="image counts"):
        frames.unwrapped()


def test_checkpoint_from_before_images_and_tallies_loads(tmp_path):
    """An older checkpoint (no images, short scalars, 5-column observables) resumes; averages restart."""
    sim, _ = gas(n=32)
    sim.run(until=1.0)
    sim.save(tmp_path / "new.npz")
    with np.load(tmp_path / "new.npz") as z:
        data = {k: z[k] for k in z.files}
    del data["images"], data["obs_samples"], data["obs_every"]
    data["scalars"] = data["scalars"][:9]
    data["obs"] = data["obs"][:5]
    np.savez(tmp_path / "old.npz", **data)
    old = hs.Simulation.load(tmp_path / "old.npz")
    old.run(until=3.0)
    sim.run(until=3.0)
    np.testing.assert_array_equal(old.state().positions, sim.state().positions)
    assert old.observables.elapsed == pytest.approx(2.0)
    assert old.observables.pressure_tensor().shape == (3, 3)
