"""Writers and triggers: when a run writes is separate from what it writes."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.io.trajectory import FrameRecorder, GSDWriter, XYZWriter
from hardspheres.writers import AtTimes, EveryCollisions, LogSpaced, Periodic, Trigger, Writer, as_trigger


def _due_times(trigger, start=0.0, n=5):
    trigger.start(start, 0)
    out = []
    for _ in range(n):
        out.append(trigger.next_time)
        trigger.fired()
    return out


def test_time_triggers():
    assert _due_times(Periodic(0.5), start=1.0) == [1.0, 1.5, 2.0, 2.5, 3.0]
    got = _due_times(LogSpaced(first=1.0, factor=10.0), start=2.0)
    assert got == [2.0, 3.0, 12.0, 102.0, 1002.0]
    got = _due_times(LogSpaced(first=1.0, factor=2.0, until=4.0), n=6)
    assert got == [0.0, 1.0, 2.0, 4.0, math.inf, math.inf]
    assert _due_times(AtTimes([3.0, 0.5, 2.0]), start=1.0, n=3) == [2.0, 3.0, math.inf]
    for trig in (Periodic(1.0), LogSpaced(1.0, per_decade=3), AtTimes([]), EveryCollisions(5)):
        assert isinstance(trig, Trigger)


def test_count_trigger():
    trig = EveryCollisions(100)
    trig.start(7.0, 40)
    assert (trig.next_time, trig.next_collisions) == (7.0, math.inf)  # first: at the start
    trig.fired()
    assert (trig.next_time, trig.next_collisions) == (math.inf, 140)
    trig.fired()
    assert trig.next_collisions == 240


def test_bad_triggers():
    with pytest.raises(ValueError, match="every"):
        Periodic(0.0)
    with pytest.raises(ValueError, match="exactly one"):
        LogSpaced(1.0)
    with pytest.raises(ValueError, match="factor"):
        LogSpaced(1.0, factor=1.0)
    with pytest.raises(ValueError, match="whole number"):
        EveryCollisions(0)
    with pytest.raises(ValueError, match="exactly one"):
        as_trigger(1.0, Periodic(1.0))
    with pytest.raises(ValueError, match="Trigger"):
        as_trigger(trigger=3.0)


def test_recorder_on_log_spaced_times(make_sim):
    sim = make_sim(n=40)
    rec = FrameRecorder(trigger=LogSpaced(first=0.01, factor=10.0))
    assert isinstance(rec, Writer)
    sim.writers.append(rec)
    sim.run(until=5.0)
    frames = rec.frames()
    np.testing.assert_allclose(frames.times, [0.0, 0.01, 0.1, 1.0], rtol=1e-12)
    # each frame is the state at its time, not at the end of the run
    again = make_sim(n=40)
    for t, pos in zip(frames.times, frames.positions):
        np.testing.assert_allclose(pos, again.run(until=t).state().positions, atol=1e-12)


def test_recorder_every_k_collisions(make_sim):
    sim = make_sim(n=40)
    rec = FrameRecorder(trigger=EveryCollisions(50))
    sim.writers.append(rec)
    sim.run(collisions=175)
    assert sim.counters["collisions"] == 175
    frames = rec.frames()
    assert len(frames.times) == 4  # at the start, then after 50, 100, 150 collisions
    kinds = frames.events["kind"]
    colls = np.cumsum(kinds == hs.EventKind.COLLISION)
    # the frame at 50 collisions is at the 50th collision's time
    assert frames.times[1] == frames.events["time"][np.searchsorted(colls, 50)]
    assert frames.times[3] == frames.events["time"][np.searchsorted(colls, 150)]


def test_file_writers_take_triggers(tmp_path, make_sim):
    pytest.importorskip("gsd.hoomd")
    for cls, name in ((GSDWriter, "a.gsd"), (XYZWriter, "a.xyz")):
        sim = make_sim(n=20)
        with cls(tmp_path / name, trigger=AtTimes([0.25, 1.0])) as w:
            sim.writers.append(w)
            sim.run(until=1.0)
        frames = hs.read_trajectory(tmp_path / name)
        assert frames.times.tolist() == [0.25, 1.0]


def test_state_does_not_run(make_sim):
    sim = make_sim(n=20)
    with pytest.raises(ValueError, match=r"run\(until=1.0\) first"):
        sim.state(1.0)
    assert sim.time == 0.0 and sim.counters["collisions"] == 0
    sim.request_stop()
    sim.run(until=1.0)
    assert sim.time == 0.0  # stopped before any event
    sim.stop_requested = False
    assert sim.run(until=1.0).time == 1.0
