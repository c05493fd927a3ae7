"""Image counts and unwrapped positions in the periodic box."""

import numpy as np
import pytest
from helpers import periodic_gas

import hardspheres as hs
from hardspheres.containers import PeriodicBoxRequired
from hardspheres.io.trajectory import GSDWriter, XYZWriter, frames_from_simulation, read_trajectory


def gas(n=64, phi=0.2, seed=3, kT=4.0):
    sim = periodic_gas(n, phi, seed, kT=kT)
    return sim, sim.container.length


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
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[0.0, 0.0, 0.0]], [[3.0, -7.0, 0.25]], hs.PeriodicBox(box))
    st = sim.run(until=100.0).state(unwrapped=True)  # state() never runs the simulation
    np.testing.assert_allclose(st.positions[0], [300.0, -700.0, 25.0], rtol=1e-12)
    # 300 = 30 boxes, -700 = -70 boxes, 25 = 3 boxes - 5 (the box is [-L/2, L/2))
    np.testing.assert_array_equal(st.images[0], [30, -70, 3])


def test_input_outside_the_box_keeps_its_unwrapped_centre():
    box = 10.0
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[23.0, -14.0, 1.0]], [[0, 0, 0]], hs.PeriodicBox(box))
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
    np.testing.assert_array_equal(back.state(unwrapped=True).positions, sim.state(unwrapped=True).positions)


def test_xyz_keeps_images_as_gsd_does(tmp_path):
    """Extended XYZ carries the image counts as three integer columns: same unwrapping as GSD."""
    pytest.importorskip("gsd")
    sim, box = gas(n=32)
    with GSDWriter(tmp_path / "t.gsd", every=0.5) as g, XYZWriter(tmp_path / "t.xyz", every=0.5) as x:
        sim.writers.extend([g, x])
        sim.run(until=3.0)
    fg, fx = read_trajectory(tmp_path / "t.gsd"), read_trajectory(tmp_path / "t.xyz")
    assert np.abs(fx.images).sum() > 0  # spheres crossed the box: the test can fail
    np.testing.assert_array_equal(fx.images, fg.images)
    np.testing.assert_array_equal(fx.images[-1], sim.state().images)
    np.testing.assert_array_equal(fx.unwrapped(), fg.unwrapped())
    np.testing.assert_array_equal(fx.unwrapped()[-1], sim.state(unwrapped=True).positions)
    header = (tmp_path / "t.xyz").read_text().split("\n")[1]
    assert "Properties=name:S:1:pos:R:3:velo:R:3:radius:R:1:mass:R:1:image:I:3 " in header


def test_xyz_continued_after_a_checkpoint_keeps_counting(tmp_path):
    """An XYZ file appended to after a resume: the images go on from the checkpoint's."""
    sim, box = gas(n=32)
    with XYZWriter(tmp_path / "t.xyz", every=0.5) as x:
        sim.writers.append(x)
        sim.run(until=2.0)
    sim.writers.clear()
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    with XYZWriter(tmp_path / "t.xyz", every=0.5, append=True) as x:
        back.writers.append(x)
        back.run(until=4.0)
    fr = read_trajectory(tmp_path / "t.xyz")
    assert fr.times.tolist() == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0]
    np.testing.assert_array_equal(fr.images[-1], back.state().images)
    np.testing.assert_array_equal(fr.unwrapped()[-1], back.state(unwrapped=True).positions)
    # the same run without the break: the same unwrapped trajectory, frame by frame
    once, _ = gas(n=32)
    with XYZWriter(tmp_path / "once.xyz", every=0.5) as x:
        once.writers.append(x)
        once.run(until=4.0)
    ref = read_trajectory(tmp_path / "once.xyz")
    np.testing.assert_array_equal(fr.images, ref.images)
    np.testing.assert_allclose(fr.unwrapped(), ref.unwrapped(), rtol=0, atol=1e-9 * box)


def test_xyz_from_before_images_reads_without_them(tmp_path):
    """An XYZ file without the image columns (older writer) reads; unwrapping says why not."""
    sim, box = gas(n=32)
    with XYZWriter(tmp_path / "t.xyz", every=0.5) as x:
        sim.writers.append(x)
        sim.run(until=1.0)
    new = read_trajectory(tmp_path / "t.xyz")
    lines = (tmp_path / "t.xyz").read_text().split("\n")
    old = []
    for line in lines:
        if "Properties=" in line:
            old.append(line.replace(":image:I:3", ""))
        elif len(line.split()) == 12:
            old.append(" ".join(line.split()[:9]))
        else:
            old.append(line)
    (tmp_path / "old.xyz").write_text("\n".join(old))
    fr = read_trajectory(tmp_path / "old.xyz")
    assert fr.images is None
    np.testing.assert_array_equal(fr.positions, new.positions)
    np.testing.assert_array_equal(fr.velocities, new.velocities)
    with pytest.raises(PeriodicBoxRequired, match="image counts"):
        fr.unwrapped()


def test_xyz_with_unknown_columns_is_refused(tmp_path):
    p = tmp_path / "odd.xyz"
    p.write_text(
        '1\nLattice="10 0 0 0 10 0 0 0 10" Properties=species:S:1:pos:R:3 Time=0.0 box_length=10.0\na 0 0 0\n'
    )
    with pytest.raises(ValueError, match="odd.xyz.*Properties"):
        read_trajectory(p)


def test_images_in_a_spherical_container_raise():
    sim = hs.Simulation.from_arrays([1.0], [0.5], [[0, 0, 0]], [[1, 0, 0]], hs.SphericalContainer(5.0))
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
