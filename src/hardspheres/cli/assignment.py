"""The assignment's simulation and report, given a checked scenario.

Small inputs run the pure-Python reference engine (no numba or numpy
start-up); larger ones run the compiled event core, or, while numba's
cache does not hold it yet, the numpy engine :class:`~hardspheres.core.scan.Scan`
(O(N) per event, no compilation).  All three speak one interface and follow
the same rules with the same arithmetic (:mod:`hardspheres.core.reference`),
so one loop writes the report and the reports are identical;
``HARDSPHERES_ENGINE=reference|scan|compiled`` forces one (the tests do).
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


def _found(name: str) -> bool:
    """Whether module ``name`` can be imported (looked up, not imported)."""
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


def compiled_available() -> bool:
    """Whether numpy and numba can be imported (looked up, not imported)."""
    return _found("numpy") and _found("numba")


def choose_engine(n: int) -> str:
    """``"reference"``, ``"scan"`` or ``"compiled"`` for ``n`` spheres.

    All three write the same bytes.  Up to :data:`SMALL` spheres the
    reference loop (pure Python, O(N^2) per event: no numpy to load).  Above,
    the compiled core when numba's cache holds it; while it does not (the
    first compilation takes far longer than a short run), :class:`Scan`
    (numpy, O(N) per event) for up to :data:`~hardspheres.core.scan.MAX_SPHERES`
    spheres.  Without numba, :class:`Scan`; without numpy, the reference.
    ``HARDSPHERES_ENGINE=reference|scan|compiled`` forces one.
    """
    forced = os.environ.get("HARDSPHERES_ENGINE", "")
    if forced in ("reference", "scan", "compiled"):
        return forced
    if n <= SMALL or not _found("numpy"):
        return "reference"
    from ..core.scan import MAX_SPHERES

    if not _found("numba"):
        return "scan" if n <= MAX_SPHERES else "reference"
    if n > MAX_SPHERES:
        return "compiled"
    from ..core.warmup import is_cold

    return "scan" if is_cold(3) else "compiled"


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
    choice = choose_engine(len(scn))
    if choice == "reference":
        engine = Reference
    elif choice == "scan":
        from ..core.scan import Scan

        engine = Scan
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
