"""The assignment's simulation and report, given a checked scenario.

Small inputs run the pure-Python reference engine (no numba or numpy
start-up); larger ones run the compiled event core (or, on a Python
without numpy or numba, the reference engine too).  Both speak one interface
and follow the same rules with the same arithmetic
(:mod:`hardspheres.core.reference`), so one loop writes the report and the
reports are identical;
``HARDSPHERES_ENGINE=reference|compiled`` forces one (the tests do).
"""

from __future__ import annotations

import importlib.util
import os
from typing import IO, TYPE_CHECKING

from ..core.reference import SIMULTANEOUS, Reference
from ..io.report import JSONLReport, TextReport
from ..scenario import StuckError

if TYPE_CHECKING:
    from ..core.engine import Engine
    from ..scenario import Scenario

#: Up to this many spheres the reference loop runs (its O(N^2) prediction
#: per event costs less than loading the compiled core).
SMALL = 24


def compiled_available() -> bool:
    """Whether numpy and numba can be imported (looked up, not imported)."""
    for name in ("numpy", "numba"):
        try:
            if importlib.util.find_spec(name) is None:
                return False
        except (ImportError, ValueError):
            return False
    return True


def choose_engine(n: int) -> str:
    """``"reference"`` or ``"compiled"`` for ``n`` spheres.

    The compiled core for more than :data:`SMALL` spheres, if numpy and
    numba are installed; else the reference loop, which needs neither and
    writes the same bytes (only slower: O(N^2) per event).
    """
    forced = os.environ.get("HARDSPHERES_ENGINE", "")
    if forced in ("reference", "compiled"):
        return forced
    return "reference" if n <= SMALL or not compiled_available() else "compiled"


def write_report(scn: Scenario, container: float, end: float, out: IO[str], fmt: str = "text") -> None:
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


def _write_events(scn: Scenario, container: float, end: float, out: IO[str], fmt: str) -> None:
    rep = (TextReport if fmt == "text" else JSONLReport)(scn.names, scn.masses, scn.radii, out)
    rep.initial(container, end, scn.positions, scn.velocities)
    engine: type[Reference] | type[Engine]
    if choose_engine(len(scn)) == "reference":
        engine = Reference
    else:
        from ..core.engine import Engine
        from ..core.warmup import ensure_compiled

        engine = Engine

        ensure_compiled()  # says so on stderr, once, when the cache is cold
    eng = engine(
        scn.masses,
        scn.radii,
        scn.positions,
        scn.velocities,
        container=container,
        window=SIMULTANEOUS,
        rebase=False,
    )
    here = eng.positions_at()
    # the text report shows every sphere; the JSONL one only those involved
    everyone = fmt == "text"
    while (ev := eng.step(until=end)) is not None:
        t, kind, i, j = ev
        rep.event(
            t, kind, i, j, eng.positions_at(t, here, None if everyone else (i, max(j, i))), eng.velocities
        )
