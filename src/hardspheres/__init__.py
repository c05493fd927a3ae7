"""hardspheres: exact event-driven simulation of perfectly elastic spheres.

Example:
    >>> import hardspheres as hs
    >>> container = hs.SphericalContainer(10.0)
    >>> state = hs.random_spheres(200, 0.3, container, seed=1)
    >>> sim = hs.Simulation(state, container)
    >>> sim.run(until=1.0).time
    1.0
"""

import importlib

from .containers import Container, PeriodicBox, PeriodicBoxRequired, SphericalContainer
from .events import EventKind, StopReason
from .scenario import Scenario, ScenarioError, parse_scenario


# numpy and numba load on first use, so that the assignment's program
# (hardspheres.cli) starts without them
_LAZY = {
    "BuildError": "builders",
    "maxwell_boltzmann": "maxwell",
    "random_spheres": "builders",
    "Event": "simulation",
    "Observables": "observables",
    "Simulation": "simulation",
    "State": "state",
    "GSDWriter": "io.trajectory",
    "XYZWriter": "io.trajectory",
    "read_trajectory": "io.trajectory",
    "Frames": "frames",
    "sweep": "studies",
    "StudyError": "studies",
    "CheckpointError": "core.engine",
    "FileInUseError": "fileio",
    "TruncatedTrajectory": "io.trajectory",
    "RDF": "analysis.structure",
    "StructureFactor": "analysis.structure",
    "BondOrder": "analysis.structure",
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


def __getattr__(name):
    if name == "__version__":  # looked up on first use: the program starts faster
        from .version import package_version

        return package_version()
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "BondOrder",
    "BuildError",
    "CheckpointError",
    "CollectiveIntermediate",
    "ContactForces",
    "Contacts",
    "Container",
    "Event",
    "EventKind",
    "EventRecorder",
    "FileInUseError",
    "Frames",
    "FreeFlights",
    "GSDWriter",
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
    "enskog",
    "maxwell_boltzmann",
    "parse_scenario",
    "random_spheres",
    "read_trajectory",
    "sweep",
    "yeh_hummer",
]
