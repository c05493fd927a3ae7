"""hardspheres: exact event-driven simulation of perfectly elastic spheres.

Example:
    >>> import hardspheres as hs
    >>> container = hs.SphericalContainer(10.0)
    >>> state = hs.random_spheres(200, 0.3, container, seed=1)
    >>> sim = hs.Simulation(state, container)
    >>> sim.run(until=1.0).time
    1.0
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from .containers import (
    BoxShapeError,
    CircularContainer,
    Container,
    PeriodicBox,
    PeriodicBoxRequired,
    SphericalContainer,
)
from .errors import BuildError, CheckpointError, FileInUseError, StudyError, TruncatedTrajectory
from .events import EventKind, StopReason
from .scenario import Scenario, ScenarioError, parse_scenario

if TYPE_CHECKING:  # the lazy names, for type checkers and IDEs (tests/test_layout.py keeps both lists equal)
    from .analysis.collisions import ContactForces, EventRecorder, FreeFlights, Recollisions
    from .analysis.dynamics import CollectiveIntermediate, NonGaussian, Overlap, SelfIntermediate, VanHove
    from .analysis.jamming import Contacts, JammingPoint
    from .analysis.structure import RDF, BondOrder, Hexatic, StructureFactor
    from .analysis.transport import MSD, VACF, ShearViscosity, ThermalConductivity, enskog, yeh_hummer
    from .barostat import Barostat
    from .builders import crystal, hexagonal, random_spheres
    from .frames import Frames
    from .mc.chain import EventChain
    from .io.trajectory import GSDWriter, XYZWriter, read_trajectory
    from .maxwell import maxwell_boltzmann
    from .observables import Observables
    from .simulation import Event, Simulation
    from .state import State
    from .studies import sweep

# numpy and numba load on first use, so that the assignment's program
# (hardspheres.cli) starts without them
_LAZY = {
    "Barostat": "barostat",
    "maxwell_boltzmann": "maxwell",
    "random_spheres": "builders",
    "crystal": "builders",
    "hexagonal": "builders",
    "Event": "simulation",
    "EventChain": "mc.chain",
    "Observables": "observables",
    "Simulation": "simulation",
    "State": "state",
    "GSDWriter": "io.trajectory",
    "XYZWriter": "io.trajectory",
    "read_trajectory": "io.trajectory",
    "Frames": "frames",
    "sweep": "studies",
    "RDF": "analysis.structure",
    "StructureFactor": "analysis.structure",
    "BondOrder": "analysis.structure",
    "Hexatic": "analysis.structure",
    "MSD": "analysis.transport",
    "VACF": "analysis.transport",
    "ShearViscosity": "analysis.transport",
    "ThermalConductivity": "analysis.transport",
    "yeh_hummer": "analysis.transport",
    "SelfIntermediate": "analysis.dynamics",
    "CollectiveIntermediate": "analysis.dynamics",
    "NonGaussian": "analysis.dynamics",
    "VanHove": "analysis.dynamics",
    "Overlap": "analysis.dynamics",
    "EventRecorder": "analysis.collisions",
    "FreeFlights": "analysis.collisions",
    "Recollisions": "analysis.collisions",
    "ContactForces": "analysis.collisions",
    "Contacts": "analysis.jamming",
    "JammingPoint": "analysis.jamming",
    "enskog": "analysis.transport",
}


def _frames_html(frames: Frames) -> str:
    from .viz.viewer import notebook_html

    return notebook_html(frames)


def _simulation_html(sim: Simulation) -> str:
    """A simulation as the viewer shows it: its spheres now, one frame."""
    from .frames import Frames
    from .viz.viewer import notebook_html

    st = sim.state()
    frames = Frames(
        [st.time],
        st.positions[None],
        st.velocities[None],
        st.radii,
        st.masses,
        st.names,
        container=sim.container,
    )
    title = f"{sim.n} spheres, t = {st.time:.6g}"
    return notebook_html(frames, title=title)


def _quietly(to_html: Callable[[Any], str]) -> Callable[[object], str | None]:
    """A display formatter that falls back to the plain repr instead of raising."""

    def html(obj: object) -> str | None:
        try:
            return to_html(obj)
        except Exception:  # a picture is never worth a traceback in the cell
            return None

    return html


def _register_notebook_display(shell: Any = None) -> None:
    """Show Simulation, Frames and trajectories as the interactive viewer in Jupyter.

    Called on import: when IPython is running, its ``text/html`` formatter
    is told (by name, importing nothing) how to draw
    :class:`~hardspheres.Simulation` and :class:`~hardspheres.Frames` (what
    :func:`~hardspheres.read_trajectory` returns), so that one ending a cell
    shows :func:`hardspheres.viz.viewer.notebook_html`: the self-contained
    viewer page, offline.  The classes stay below the pictures' family
    (tests/test_layout.py); this, at the package root, joins them.
    """
    if shell is None:
        ipython = sys.modules.get("IPython")
        shell = ipython.get_ipython() if ipython is not None else None
    if shell is None:
        return
    html = shell.display_formatter.formatters["text/html"]
    html.for_type_by_name("hardspheres.frames", "Frames", _quietly(_frames_html))
    html.for_type_by_name("hardspheres.simulation", "Simulation", _quietly(_simulation_html))


_register_notebook_display()


def __getattr__(name: str) -> Any:
    if name == "__version__":  # looked up on first use: the program starts faster
        from .version import package_version

        return package_version()
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    """Every public name, loaded or not (``dir(hs)``, ``help(hs)`` and tab completion see them)."""
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "Barostat",
    "BondOrder",
    "BoxShapeError",
    "BuildError",
    "CircularContainer",
    "CheckpointError",
    "CollectiveIntermediate",
    "ContactForces",
    "Contacts",
    "Container",
    "Event",
    "EventChain",
    "EventKind",
    "EventRecorder",
    "FileInUseError",
    "Frames",
    "FreeFlights",
    "GSDWriter",
    "Hexatic",
    "JammingPoint",
    "MSD",
    "NonGaussian",
    "Observables",
    "Overlap",
    "PeriodicBox",
    "PeriodicBoxRequired",
    "RDF",
    "Recollisions",
    "Scenario",
    "ScenarioError",
    "SelfIntermediate",
    "ShearViscosity",
    "Simulation",
    "SphericalContainer",
    "State",
    "StopReason",
    "StructureFactor",
    "StudyError",
    "ThermalConductivity",
    "TruncatedTrajectory",
    "VACF",
    "VanHove",
    "XYZWriter",
    "crystal",
    "enskog",
    "hexagonal",
    "maxwell_boltzmann",
    "parse_scenario",
    "random_spheres",
    "read_trajectory",
    "sweep",
    "yeh_hummer",
]
