"""hardspheres: exact event-driven simulation of perfectly elastic spheres."""

from .scenario import Scenario, ScenarioError, parse_scenario

__all__ = ["Scenario", "ScenarioError", "parse_scenario"]
__version__ = "0.1.0"
