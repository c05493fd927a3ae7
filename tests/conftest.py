"""Shared fixtures (factories for states and simulations) and the test levels.

Every test gets one of three markers, by the module it is in, so the test
files need no decorators (``pytest -m unit`` runs the fast ones; CI runs all):

* ``unit``: one function or class, in process (and the docstrings' examples);
* ``integration``: several layers together (engine, simulation, files);
* ``e2e``: the commands as a user runs them (subprocesses, a browser).

Hypothesis runs derandomized and without its example database (profile
``deterministic``, always loaded): the same examples on every run and every
machine, so that CI never fails on a seed, and no timed health check
(``too_slow`` fails a test on a busy machine).  Every example it ever found is
kept as an explicit ``@example`` or regression test.  To search afresh,
``HYPOTHESIS_PROFILE=seeded pytest --hypothesis-seed=N ...`` (random,
reproducible by ``N``, still no database).
"""

from __future__ import annotations

from pathlib import Path

import os

import pytest
from hypothesis import HealthCheck, settings

# no timing in tests: neither deadlines nor the "too slow" health check,
# which fails a test when the machine is busy (shared CI runners are)
_COMMON = dict(database=None, print_blob=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("deterministic", derandomize=True, **_COMMON)
settings.register_profile("seeded", derandomize=False, **_COMMON)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))

#: Test level by module; a module not listed is ``integration``.
LEVELS = {
    "test_analytic": "unit",
    "test_builders": "unit",
    "test_containers": "unit",
    "test_events": "unit",
    "test_writers": "integration",
    "test_properties": "integration",
    "test_engine": "integration",
    "test_simulation": "integration",
    "test_trajectory": "integration",
    "test_pictures": "integration",
    "test_cli": "e2e",
    "test_commands_pictures": "e2e",
    "test_conformance": "e2e",
    "test_readme": "e2e",
    "test_viewer": "e2e",
}


def level_of(path: Path) -> str:
    """The marker for a test collected from ``path`` (doctests in src/ are unit tests)."""
    if "tests" not in path.parts:
        return "unit"
    return LEVELS.get(path.stem, "integration")


def pytest_collection_modifyitems(config, items):
    for item in items:
        item.add_marker(getattr(pytest.mark, level_of(Path(str(item.path)))))


@pytest.fixture
def make_state():
    """Factory: ``make_state(n=50, packing=0.2, container=None, seed=0, **kw)``.

    A :class:`hardspheres.State` of ``n`` spheres from
    :func:`hardspheres.random_spheres`; ``container`` defaults to a
    spherical container of radius 6.
    """
    import hardspheres as hs

    def make(n=50, packing=0.2, container=None, seed=0, **kw):
        container = hs.SphericalContainer(6.0) if container is None else container
        return hs.random_spheres(n, packing, container, seed=seed, **kw)

    return make


@pytest.fixture
def make_sim(make_state):
    """Factory: ``make_sim(n=50, packing=0.2, container=None, seed=0, window=0.0, **kw)``.

    A :class:`hardspheres.Simulation` of :func:`make_state`'s spheres in the
    same container.
    """
    import hardspheres as hs

    def make(n=50, packing=0.2, container=None, seed=0, window=0.0, **kw):
        container = hs.SphericalContainer(6.0) if container is None else container
        return hs.Simulation(make_state(n, packing, container, seed, **kw), container, window=window)

    return make
