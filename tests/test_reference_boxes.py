"""The engine against the brute-force reference in periodic boxes and with growth, bit for bit.

Cube, rectangular box and 2-D box; cells and neighbour lists; the
simultaneity window on and off; radii growing (as the compression grows
them) and not.  Fixed seeds: every run is the same every time.
"""

import numpy as np
import pytest

from hardspheres.builders import random_spheres
from hardspheres.containers import CircularContainer, PeriodicBox, SphericalContainer
from hardspheres.core import _core as core
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference

from test_engine import CompiledReference, same_events
from test_planar import disks


def _pair(container, n, phi, seed, ratio=1.0):
    """Masses, radii, centres and velocities of ``n`` spheres or disks at packing ``phi`` in ``container``."""
    if container.dimensions == 2:
        return disks(n, phi, container, seed, ratio)
    s = random_spheres(n, phi, container=container, seed=seed, radius_ratio=ratio)
    return s.masses, s.radii, s.positions, s.velocities


def _both(container, m, r, x, v, window, events, grow=0.0, reference=CompiledReference, before=0):
    """The engine's and the reference's events (``before`` events, growth ``grow`` from then, ``events`` more)."""
    eng = Engine(m, r, x, v, container=container, window=window, rebase=False, reorder=0.0)
    eng.mode = "lists" if eng.scalars[core.F_SHELL] > 0.0 else "cells"  # (as built)
    ref = reference(m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), container=container, window=window)
    out = []
    for sim in (eng, ref):
        first = sim.advance(events=before)
        if grow:
            sim.set_growth(grow)
        out.append(np.concatenate([first, sim.advance(events=events)]))
    return eng, ref, out[0], out[1]


def _same_state(eng, ref):
    n, d = eng.n, eng.dimensions
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities, dtype=float).reshape(n, d))
    assert np.array_equal(eng.positions_at(), np.asarray(ref.positions_at(), dtype=float).reshape(n, d))
    for key in ("collisions", "reflections"):
        assert eng.counters[key] == ref.counters[key]
    assert (eng.time, eng.wall_impulse, eng.virial) == (ref.time, ref.wall_impulse, ref.virial)
    assert np.array_equal(eng.radii_at(), np.asarray(ref.radii_at()))


BOXES = {
    "cube": PeriodicBox(11.0),
    "rectangle": PeriodicBox((9.0, 11.0, 14.0)),
    "square": PeriodicBox((21.0, 21.0)),
    "rectangle-2d": PeriodicBox((17.0, 26.0)),
}


@pytest.fixture(params=["cells", "lists"])
def mode(request, monkeypatch):
    """The core predicts against cells, or against neighbour lists whatever the density."""
    if request.param == "lists":
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
        monkeypatch.setattr(engine_module, "LISTS_FROM_2D", 0.0)
    return request.param


def _check_mode(eng, mode):
    assert eng.mode == mode


@pytest.mark.parametrize("name", list(BOXES))
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_engine_matches_the_reference_in_periodic_boxes(mode, name, window):
    box = BOXES[name]
    phi = 0.3 if box.dimensions == 3 else 0.45
    m, r, x, v = _pair(box, 150, phi, seed=len(name), ratio=1.2)
    eng, ref, a, b = _both(box, m, r, x, v, window, 3000)
    _check_mode(eng, mode)
    assert len(a) == 3000 and same_events(a, b)
    _same_state(eng, ref)
    assert np.array_equal(eng.images, np.asarray(ref.images))
    assert eng.counters["crossings"] > 0


@pytest.mark.parametrize("name", ["cube", "rectangle-2d"])
def test_engine_matches_the_pure_python_reference_in_periodic_boxes(mode, name):
    box = BOXES[name]
    m, r, x, v = _pair(box, 12, 0.05 if box.dimensions == 3 else 0.1, seed=3)
    eng, ref, a, b = _both(box, m, r, x, v, 1e-8, 200, reference=Reference)
    assert same_events(a, b)
    _same_state(eng, ref)


@pytest.mark.parametrize(
    "container",
    [
        BOXES["cube"],
        BOXES["rectangle"],
        BOXES["rectangle-2d"],
        SphericalContainer(7.0),
        CircularContainer(11.0),
    ],
    ids=["cube", "rectangle", "rectangle-2d", "sphere", "circle"],
)
def test_engine_matches_the_reference_while_growing(mode, container):
    """Radii growing after a first stretch (the compression's way), past rebuilds of the cells or lists."""
    phi = 0.25 if container.dimensions == 3 else 0.4
    m, r, x, v = _pair(container, 120, phi, seed=9, ratio=1.3)
    eng, ref, a, b = _both(container, m, r, x, v, 1e-8, 3000, grow=0.01, before=500)
    _check_mode(eng, mode)
    assert same_events(a, b)
    _same_state(eng, ref)
    assert eng.growth == ref.growth and eng.max_overlap() < 1e-9
    assert eng._packing(eng.radii_at()) > 1.1 * phi  # grown, past rebuilds of the cells or lists
