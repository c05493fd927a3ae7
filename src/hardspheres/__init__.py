"""hardspheres: exact event-driven simulation of perfectly elastic spheres.

Example:
    >>> import hardspheres as hs
    >>> state = hs.random_spheres(200, 0.3, container=10.0, seed=1)
    >>> sim = hs.Simulation(state, hs.SphericalContainer(10.0))
    >>> sim.run(until=1.0).time
    1.0
"""

import importlib

from .containers import PeriodicBox, PeriodicBoxRequired, SphericalContainer
from .scenario import Scenario, ScenarioError, parse_scenario

# numpy and numba load on first use, so that the assignment's program
# (hardspheres.cli) starts without them
_LAZY = {"BuildError": "builders", "maxwell_boltzmann": "builders",
         "random_spheres": "builders", "Event": "simulation", "Observables": "observables",
         "Simulation": "simulation", "State": "state", "GSDWriter": "trajectory",
         "XYZWriter": "trajectory", "read_trajectory": "trajectory", "Frames": "frames",
         "sweep": "studies", "StudyError": "studies",
         "CheckpointError": "engine", "FileInUseError": "fileio",
         "TruncatedTrajectory": "trajectory",
         "RDF": "structure", "StructureFactor": "structure", "BondOrder": "structure",
         "MSD": "transport", "VACF": "transport", "ShearViscosity": "transport",
         "ThermalConductivity": "transport", "yeh_hummer": "transport", "enskog": "transport"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["BuildError", "CheckpointError", "Event", "FileInUseError", "Frames", "GSDWriter",
           "Observables", "PeriodicBox", "Scenario", "ScenarioError", "Simulation",
           "SphericalContainer", "State", "StudyError", "TruncatedTrajectory",
           "maxwell_boltzmann", "parse_scenario", "random_spheres", "read_trajectory", "sweep",
           "XYZWriter",
           "BondOrder", "MSD", "PeriodicBoxRequired", "RDF", "ShearViscosity", "StructureFactor",
           "ThermalConductivity", "VACF", "enskog", "yeh_hummer"]
__version__ = "0.1.0"
