"""Events: one record for every event, from the compiled core to the files.

An event is a row of :data:`EVENT_DTYPE`, a numpy structured dtype; a run's
events are a 1-D array of it.  The compiled core fills one plain array per
field (:func:`empty_buffers`), the engine hands the rows out
(:meth:`hardspheres.core.engine.Engine.advance`), trajectories store and read
them back (:mod:`hardspheres.io.trajectory`), and :class:`hardspheres.Frames`
keeps them.  Adding a field is one line in :data:`EVENT_FIELDS` (and the
core's code that fills it).

:class:`EventKind` and :class:`StopReason` give the integer codes their
names; the core's constants are the same numbers
(``tests/test_events.py`` checks it).

Example:
    >>> import numpy as np
    >>> from hardspheres.events import EVENT_DTYPE
    >>> ev = np.zeros(2, EVENT_DTYPE)
    >>> ev["kind"] = [EventKind.REFLECTION, EventKind.COLLISION]
    >>> [EventKind(k).label for k in ev["kind"]]
    ['reflection', 'collision']
    >>> ev.dtype.names
    ('time', 'kind', 'i', 'j', 'impulse', 'dp')
"""

from __future__ import annotations

from enum import IntEnum
from typing import TYPE_CHECKING, Any

from .errors import ArgumentError

if TYPE_CHECKING:
    import numpy as np

# numpy loads on first use of the record (the assignment's program uses the
# kinds without numpy)


class EventKind(IntEnum):
    """What happened; the number is also the tie order at equal times.

    ``REFLECTION``: sphere ``i`` bounced off the container wall (``j = -1``);
    ``COLLISION``: spheres ``i < j`` collided (their hard cores touched).
    With a stepped pair potential (square wells; the brute-force reference
    so far): ``CAPTURE``, the pair crossed a step inward; ``RELEASE``, it
    crossed one outward; ``BOUNCE``, its normal kinetic energy did not pay
    for the crossing and it was reflected at the step.  (2 and 3 are the
    core's own: a crossing of the periodic box, no event.)  All pair events
    tie as collisions.
    """

    REFLECTION = 0
    COLLISION = 1
    CAPTURE = 4
    RELEASE = 5
    BOUNCE = 6

    @property
    def label(self) -> str:
        """``"reflection"``, ``"collision"``, ``"capture"``, ``"release"`` or ``"bounce"``."""
        return self.name.lower()


class StopReason(IntEnum):
    """Why the compiled core's :func:`run <hardspheres.core._core.run>` returned.

    ``UNTIL``: the next event is after the requested time (or nothing
    will ever happen); ``MAX_EVENTS``: the event budget is spent;
    ``MAX_COLLISIONS``: the collision budget is spent; ``RECORD_FULL``: the
    event record is full (the engine calls again); ``FROZEN``: the next
    collision or reflection would be one too many in a row with the clock
    not advancing; ``SLIDING``: the next event is a reflection that would
    change nothing (a sphere at the wall moving along it).
    """

    UNTIL = 0
    MAX_EVENTS = 1
    MAX_COLLISIONS = 2
    RECORD_FULL = 3
    FROZEN = 4
    SLIDING = 5


class KindLabel(str):
    """An event kind's name (``"collision"``) that also equals its :class:`EventKind`.

    :attr:`hardspheres.Event.kind` is one of these, so that both
    ``e.kind == "collision"`` and ``e.kind == EventKind.COLLISION`` hold
    (a plain string compared false with the enum, without a word: issue 29).
    It hashes as the string; :attr:`code` is the :class:`EventKind`.

    Example:
        >>> k = KindLabel("collision")
        >>> k == "collision", k == EventKind.COLLISION, EventKind.COLLISION == k
        (True, True, True)
        >>> k == EventKind.REFLECTION, k != EventKind.COLLISION, k.code
        (False, False, <EventKind.COLLISION: 1>)
    """

    __slots__ = ()

    @property
    def code(self) -> EventKind:
        """The :class:`EventKind` of this name."""
        return EventKind[self.upper()]

    def __eq__(self, other: object) -> bool:
        if isinstance(other, EventKind):
            return str.__eq__(self, other.label)
        return str.__eq__(self, other)

    def __ne__(self, other: object) -> bool:
        return not self == other

    __hash__ = str.__hash__

    def __reduce__(self) -> tuple[type[KindLabel], tuple[str]]:
        return (KindLabel, (str(self),))


#: Event kind names by number, ``KIND_LABELS[kind]`` (each a :class:`KindLabel`),
#: for the kinds the compiled core records (the steps' kinds join when it has steps).
KIND_LABELS = tuple(KindLabel(k.label) for k in (EventKind.REFLECTION, EventKind.COLLISION))

#: The fields of an event, in order, as ``(name, numpy dtype, shape)``.
#:
#: * ``time`` [time];
#: * ``kind``: an :class:`EventKind`;
#: * ``i``: the sphere (the lower index of a colliding pair);
#: * ``j``: the other sphere of a collision, ``-1`` for a reflection;
#: * ``impulse``: magnitude of the momentum sphere ``i`` received
#:   [mass*length/time];
#: * ``dp``: ``(3,)`` the momentum sphere ``i`` received (sphere ``j``
#:   received ``-dp``) [mass*length/time].
EVENT_FIELDS: tuple[tuple[str, str, tuple[int, ...]], ...] = (
    ("time", "f8", ()),
    ("kind", "i1", ()),
    ("i", "i8", ()),
    ("j", "i8", ()),
    ("impulse", "f8", ()),
    ("dp", "f8", (3,)),
)

#: One event as a numpy structured dtype (see :data:`EVENT_FIELDS`), made
#: on first use.
EVENT_DTYPE: np.dtype


def __getattr__(name: str) -> Any:
    # EVENT_DTYPE: one event as a numpy structured dtype (see EVENT_FIELDS)
    if name == "EVENT_DTYPE":
        import numpy as np

        global EVENT_DTYPE
        EVENT_DTYPE = np.dtype([(n, dt, shape) for n, dt, shape in EVENT_FIELDS])
        return EVENT_DTYPE
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def empty_events(n: int = 0) -> np.ndarray:
    """``(n,)`` zeroed events of :data:`EVENT_DTYPE`.

    Example:
        >>> empty_events().shape, empty_events(3)["j"].tolist()
        ((0,), [0, 0, 0])
    """
    import numpy as np

    return np.zeros(n, _dtype())


def empty_buffers(n: int) -> tuple[np.ndarray, ...]:
    """One contiguous array per field, ``n`` rows each, as the compiled core fills them.

    Example:
        >>> [b.dtype.name for b in empty_buffers(4)]
        ['float64', 'int8', 'int64', 'int64', 'float64', 'float64']
    """
    import numpy as np

    return tuple(np.zeros((n, *shape), dt) for _, dt, shape in EVENT_FIELDS)


def from_buffers(buffers: tuple[np.ndarray, ...], count: int, time_offset: float = 0.0) -> np.ndarray:
    """The first ``count`` rows of the core's per-field buffers as events.

    Args:
        buffers: as from :func:`empty_buffers`, filled by the core.
        count: rows filled.
        time_offset: added to the times (the engine's time origin) [time].
    """
    import numpy as np

    out = np.empty(count, _dtype())
    for (name, _, _), buf in zip(EVENT_FIELDS, buffers):
        out[name] = buf[:count]
    if time_offset:
        out["time"] += time_offset
    return out


def from_columns(**columns: np.ndarray) -> np.ndarray:
    """Events from one array per field (fields not given are zero; ``j`` is -1).

    Example:
        >>> ev = from_columns(time=[0.5, 1.0], kind=[1, 0], i=[0, 2], j=[1, -1])
        >>> ev["i"].tolist(), ev["impulse"].tolist()
        ([0, 2], [0.0, 0.0])
    """
    import numpy as np

    dtype = _dtype()
    n = max((len(np.asarray(c)) for c in columns.values()), default=0)
    out = np.zeros(n, dtype)
    out["j"] = -1
    names = dtype.names or ()
    for name, col in columns.items():
        if name not in names:
            raise ArgumentError(f"unknown event field {name!r}; the fields are {names}")
        out[name] = np.asarray(col).reshape(out[name].shape)
    return out


def as_events(data: np.ndarray) -> np.ndarray:
    """Events of :data:`EVENT_DTYPE` from a structured array with (some of) its fields.

    Fields present in both are copied by name, so records written before a
    field was added still read (the new field is zero).
    """
    import numpy as np

    data = np.asarray(data)
    dtype = _dtype()
    if data.dtype == dtype:
        return data
    if data.dtype.names is None:
        raise ArgumentError(
            f"events must be a structured array, got dtype {data.dtype}; pass records of EVENT_DTYPE"
        )
    return from_columns(**{k: data[k] for k in data.dtype.names if k in (dtype.names or ())})


def _dtype() -> np.dtype:
    dtype = globals().get("EVENT_DTYPE")
    return dtype if dtype is not None else __getattr__("EVENT_DTYPE")
