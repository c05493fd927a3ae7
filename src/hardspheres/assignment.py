"""The assignment's simulation and report, given a checked scenario.

Small inputs run the pure-Python reference loop (no numba start-up); larger
ones run the compiled event core.  Both follow the same rules with the same
arithmetic (:mod:`hardspheres.reference`), so their reports are identical;
``HARDSPHERES_ENGINE=reference|compiled`` forces one (the tests do).
"""

import os

from . import reference
from .report import JSONLReport, TextReport
from .scenario import StuckError

#: Up to this many spheres the reference loop runs (its O(N^2) prediction
#: per event costs less than loading the compiled core).
SMALL = 24


def choose_engine(n):
    """``"reference"`` or ``"compiled"`` for ``n`` spheres."""
    forced = os.environ.get("HARDSPHERES_ENGINE", "")
    if forced in ("reference", "compiled"):
        return forced
    return "reference" if n <= SMALL else "compiled"


def write_report(scn, container, end, out, fmt="text"):
    """Simulate ``scn`` in a sphere of radius ``container`` until ``end``, writing the report.

    ``fmt`` is ``"text"`` (the assignment's layout) or ``"jsonl"``.

    Raises:
        StuckError: the run cannot go on (naming the sphere); the events
            before are written.
    """
    try:
        _write_events(scn, container, end, out, fmt)
    except StuckError as e:
        raise e.named(scn.names) from None


def _write_events(scn, container, end, out, fmt):
    rep = (TextReport if fmt == "text" else JSONLReport)(scn.names, scn.masses, scn.radii, out)
    p, v = scn.positions, scn.velocities
    rep.initial(container, end, p, v)
    if choose_engine(len(scn)) == "reference":
        for t, kind, i, j, state in reference.events(scn.masses, scn.radii, p, v,
                                                     container, end):
            rep.event(t, kind, i, j, state(), v)
        return
    from .engine import Engine
    from .warmup import ensure_compiled
    ensure_compiled()  # says so on stderr, once, when the cache is cold
    eng = Engine(scn.masses, scn.radii, p, v, container=container,
                 window=reference.SIMULTANEOUS, rebase=False)
    here = eng.positions_at()
    # the text report shows every sphere; the JSONL one only those involved
    everyone = fmt == "text"
    while True:
        ev = eng.advance(until=end, events=1)
        if len(ev) == 0:
            return
        t, kind, i, j = float(ev["time"][0]), int(ev["kind"][0]), int(ev["i"][0]), int(ev["j"][0])
        rep.event(t, kind, i, j,
                  eng.positions_at(t, here, None if everyone else [i, max(j, i)]), eng.velocities)
