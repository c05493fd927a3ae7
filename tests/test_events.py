"""One event record and one set of codes, shared from the core to the files."""

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.core import _core as core
from hardspheres.core import reference
from hardspheres.core.engine import Engine
from hardspheres.events import (
    EVENT_DTYPE,
    EVENT_FIELDS,
    KIND_LABELS,
    EventKind,
    StopReason,
    as_events,
    empty_buffers,
    from_buffers,
    from_columns,
)


def test_core_constants_are_the_enums():
    assert core.REFLECTION == EventKind.REFLECTION and core.COLLISION == EventKind.COLLISION
    assert reference.REFLECTION == EventKind.REFLECTION
    assert reference.COLLISION == EventKind.COLLISION
    # the core's own kinds come after the public ones (they are also the tie order)
    assert {core.CROSSING, core.NONE}.isdisjoint(int(k) for k in EventKind)
    assert [core.STOP_UNTIL, core.STOP_MAX_EVENTS, core.STOP_MAX_COLLISIONS, core.STOP_RECORD_FULL] == [
        StopReason.UNTIL,
        StopReason.MAX_EVENTS,
        StopReason.MAX_COLLISIONS,
        StopReason.RECORD_FULL,
    ]
    assert KIND_LABELS == ("reflection", "collision")


def test_dtype_follows_the_field_list():
    assert EVENT_DTYPE.names == tuple(name for name, _, _ in EVENT_FIELDS)
    bufs = empty_buffers(3)
    assert [b.dtype for b in bufs] == [EVENT_DTYPE[name].base for name in EVENT_DTYPE.names]
    bufs[0][:] = [1.0, 2.0, 3.0]
    bufs[3][:] = -1
    ev = from_buffers(bufs, 2, time_offset=10.0)
    assert ev["time"].tolist() == [11.0, 12.0] and ev["j"].tolist() == [-1, -1]


def test_columns_and_older_records():
    ev = from_columns(time=[1.0], kind=[EventKind.COLLISION], i=[0], j=[1])
    assert ev.dtype == EVENT_DTYPE and ev["impulse"].tolist() == [0.0]
    older = np.zeros(2, [("time", "f8"), ("kind", "i1"), ("i", "i8")])  # no j, no impulse
    got = as_events(older)
    assert got.dtype == EVENT_DTYPE and got["j"].tolist() == [-1, -1]
    with pytest.raises(ValueError, match="unknown event field"):
        from_columns(when=[1.0])
    with pytest.raises(ValueError, match="structured"):
        as_events(np.zeros(3))


def test_engine_returns_records_and_stop_reasons():
    eng = Engine(
        [1.0, 1.0],
        [1.0, 1.0],
        [[-5.0, 0, 0], [5.0, 0, 0]],
        [[1.0, 0, 0], [-1.0, 0, 0]],
        hs.SphericalContainer(100.0),
    )
    ev = eng.advance(until=10.0)
    assert ev.dtype == EVENT_DTYPE
    assert (ev["time"].tolist(), ev["kind"].tolist(), ev["i"].tolist(), ev["j"].tolist()) == (
        [4.0],
        [EventKind.COLLISION],
        [0],
        [1],
    )
    assert ev["impulse"][0] == pytest.approx(2.0)
    assert eng.last_reason is StopReason.UNTIL
    eng.advance(events=1)
    assert eng.last_reason is StopReason.MAX_EVENTS
    assert eng.advance(until=eng.time, record=False).dtype == EVENT_DTYPE


def test_simulation_events_name_their_kind():
    sim = hs.Simulation.from_arrays([1.0], [1.0], [[0, 0, 0]], [[1, 0, 0]], hs.SphericalContainer(3.0))
    (ev,) = list(sim.iter_events(until=2.5))
    assert (ev.time, ev.kind, ev.i, ev.j) == (2.0, "reflection", 0, -1)
    assert ev.impulse == pytest.approx(2.0)


def test_event_kind_equals_the_string_and_the_enum(make_sim):
    """Issue 29 item 3: ``e.kind == EventKind.COLLISION`` was always False
    (a user counting contacts got zero without a word)."""
    import pickle

    from hardspheres.events import EventKind as K

    events = list(make_sim(n=30, packing=0.2).iter_events(events=300))
    by_name = sum(e.kind == "collision" for e in events)
    by_enum = sum(e.kind == K.COLLISION for e in events)
    reflected = sum(K.REFLECTION == e.kind for e in events)
    assert by_name > 0 and by_enum == by_name and reflected == len(events) - by_name
    assert all((e.kind != K.COLLISION) == (e.kind == "reflection") for e in events)
    k = events[0].kind
    assert pickle.loads(pickle.dumps(k)) == k and hash(k) == hash(str(k)) and k.code in K
    assert {e.kind for e in events} <= {"collision", "reflection"}
