"""Containers own their geometry: every layer takes the object, none asks its type."""

import ast
import math
from pathlib import Path

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.containers import KINDS, Container, ContainerError, as_container, from_fields, from_record
from hardspheres.core.engine import Engine

SRC = Path(hs.__file__).parent
BOTH = [hs.SphericalContainer(3.0), hs.PeriodicBox(4.0)]


@pytest.mark.parametrize("c", BOTH, ids=lambda c: c.kind)
def test_each_container_is_a_container_and_round_trips(c):
    assert isinstance(c, Container)
    assert from_record(c.record()) == c
    assert from_fields(c.fields()) == c
    assert from_fields({f"hardspheres/{k}": [v] for k, v in c.fields().items()}) == c
    assert KINDS[c.kind] is type(c)
    assert len(c.gsd_box) == 6 and c.gsd_box[0] == pytest.approx(2 * c.half_width)
    assert c.bounding_radius >= c.half_width > 0
    right, up = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    assert all(line.shape[1] == 2 for line, _ in c.outline(right, up, cut=0.5))


def test_geometry():
    s, b = BOTH
    assert s.volume == pytest.approx(4 / 3 * math.pi * 27) and s.wall_area == pytest.approx(36 * math.pi)
    assert b.volume == 64.0 and b.wall_area == 0.0
    p = np.array([[2.5, 0, 0], [1.0, 0, 0]])
    assert s.outside(p, np.array([1.0, 1.0])).tolist() == [True, False]
    assert not b.outside(p, np.array([1.0, 1.0])).any()
    assert b.wrap(np.array([[2.5, -2.0, 1.9]])).tolist() == [[-1.5, -2.0, 1.9]]
    assert np.array_equal(s.wrap(p), p)
    assert b.displacement(np.array([1.9, 0, 0]), np.array([-1.9, 0, 0])).tolist() == pytest.approx(
        [-0.2, 0, 0]
    )
    assert s.displacement(np.array([1.9, 0, 0]), np.array([-1.9, 0, 0])).tolist() == [3.8, 0, 0]
    assert (s.degrees_of_freedom(10), b.degrees_of_freedom(10), b.degrees_of_freedom(1)) == (30, 27, 3)
    assert s.check_sphere([2.5, 0, 0], 1.0, [0, 0, 0]).startswith("is not wholly inside")
    assert s.check_sphere([0, 0, 0], 3.0, [1, 0, 0]).startswith("fills the container")
    assert b.check_sphere([9.0, 0, 0], 1.0, [0, 0, 0]) is None


def test_pressure_from_the_cores_totals():
    s, b = BOTH
    assert s.pressure(10, 1.0, 2.0, wall_impulse=36 * math.pi, virial=5.0) == pytest.approx(0.5)
    assert b.pressure(10, 1.0, 2.0, wall_impulse=0.0, virial=6.0) == pytest.approx(11 / 64)


def test_floats_convert_at_the_edge():
    assert as_container(3.0) == hs.SphericalContainer(3.0)
    assert as_container(box=2.0) == hs.PeriodicBox(2.0)
    assert as_container(hs.PeriodicBox(2.0)) == hs.PeriodicBox(2.0)
    with pytest.raises(ContainerError, match="exactly one"):
        as_container(3.0, 2.0)
    with pytest.raises(ValueError, match="finite number > 0"):
        hs.SphericalContainer(-1.0)
    with pytest.raises(ContainerError, match="unknown container"):
        from_record(np.array(["Cylinder", "1.0"]))
    with pytest.raises(ContainerError, match="no container size"):
        from_fields({})


@pytest.mark.parametrize("c", BOTH, ids=lambda c: c.kind)
def test_one_object_through_every_layer(c):
    state = hs.random_spheres(60, 0.2, c, seed=4)
    legacy = (
        hs.random_spheres(60, 0.2, container=c.radius, seed=4)
        if not c.periodic
        else hs.random_spheres(60, 0.2, box=c.length, seed=4)
    )
    assert np.array_equal(state.positions, legacy.positions)
    sim = hs.Simulation(state, c)
    assert sim.container is c
    eng = Engine(state.masses, state.radii, c.wrap(state.positions), state.velocities, c)
    assert eng.container is c
    sim.run(collisions=200)
    assert sim.observables.temperature() > 0
    from hardspheres.io.trajectory import frames_from_simulation

    frames = frames_from_simulation(sim, until=sim.time + 0.5, every=0.25)
    assert frames.container is c and len(frames.events) > 0
    assert frames.extent() == pytest.approx(c.half_width)


def test_no_container_type_branches_above_the_core():
    """No module but containers.py asks whether a container is a sphere or a box."""
    names = {"SphericalContainer", "PeriodicBox"}
    offenders = []
    for path in SRC.glob("*.py"):
        if path.name in ("containers.py", "_core.py"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id == "isinstance"
                and len(node.args) == 2
            ):
                if names & {n.id for n in ast.walk(node.args[1]) if isinstance(n, ast.Name)}:
                    offenders.append(f"{path.name}:{node.lineno}")
    assert offenders == []


@pytest.mark.parametrize("c", BOTH, ids=lambda c: c.kind)
def test_checkpoint_keeps_the_container(c, make_sim, tmp_path, request):
    assert request.node.get_closest_marker("unit") is not None  # conftest's level
    sim = make_sim(n=30, container=c)
    sim.run(collisions=50)
    sim.save(tmp_path / "run.npz")
    back = hs.Simulation.load(tmp_path / "run.npz")
    assert back.container == c and back._engine.container == c
    assert back.state().positions.tolist() == sim.state().positions.tolist()
