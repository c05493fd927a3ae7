"""The assignment's simulation and report, given a checked scenario.

Small inputs run the pure-Python reference loop (no numba start-up); larger
ones run the compiled event core.  Both follow the same rules
(:mod:`hardspheres.reference`).
"""

from . import reference
from .report import TextReport


def write_report(scn, container, end, out):
    """Simulate ``scn`` in a sphere of radius ``container`` until ``end``, writing the report."""
    rep = TextReport(scn.names, scn.masses, scn.radii, out)
    p, v = scn.positions, scn.velocities
    rep.initial(container, end, p, v)
    for t, kind, i, j, state in reference.events(scn.masses, scn.radii, p, v, container, end):
        rep.event(t, kind, i, j, state(), v)
