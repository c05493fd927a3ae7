"""Files written before the layout by families (commit 04aa93d) still load, and resume bit for bit.

tests/data/pre-layout/ was written by that tree: a 32-sphere periodic box run
to t = 2 with a GSD and an XYZ trajectory (a frame every 0.5), then an
Andersen thermostat to t = 2.5 and a checkpoint (``box.npz``); the tree then
ran on to t = 3 and saved the positions and velocities (``box-at-3.npy``).
"""

from pathlib import Path

import numpy as np

import hardspheres as hs

DATA = Path(__file__).resolve().parent / "data" / "pre-layout"


def test_old_checkpoint_resumes_bit_for_bit():
    sim = hs.Simulation.load(DATA / "box.npz")
    assert sim.time == 2.5 and sim.n == 32 and sim.thermostat is not None and sim.writers == []
    sim.run(until=3.0)
    st = sim.state()
    expected = np.load(DATA / "box-at-3.npy")
    assert np.array_equal(np.concatenate([st.positions, st.velocities]), expected)


def test_old_trajectories_read():
    for name in ("run.gsd", "run.xyz"):
        frames = hs.read_trajectory(DATA / name)
        assert frames.n == 32 and np.allclose(frames.times, [0.0, 0.5, 1.0, 1.5, 2.0])
        assert isinstance(frames.container, hs.PeriodicBox) and frames.container.volume == 216.0
