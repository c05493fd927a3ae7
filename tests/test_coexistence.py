"""Direct coexistence: the crystal-fluid slab and its profiles (hardspheres.analysis.coexistence)."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.coexistence import SlabProfile, crystal_fluid_slab, equilibrated_fluid
from hardspheres.core.contacts import closest_ratio
from hardspheres.errors import BuildError


@pytest.mark.parametrize("plane, cells", [("100", (4, 4, 4)), ("111", (6, 6, 6))])
def test_the_slab_holds_a_crystal_beside_a_fluid(plane, cells):
    st, box = crystal_fluid_slab(cells, plane=plane, seed=1)
    n_crystal = 4 * math.prod(cells) if plane == "100" else math.prod(cells)
    assert box.sides[2] > 1.6 * box.sides[0]
    assert (
        closest_ratio(st.positions, st.radii, box.sides) >= 1.0 - 1e-12
    )  # no overlap (fluid pairs at contact)
    sim = hs.Simulation(st, box)
    p = SlabProfile(16).compute(sim)
    like = p.crystal_like
    assert like[:n_crystal].mean() > 0.95 and like[n_crystal:].mean() < 0.2
    lower = p.z < p.z[0] + 0.4 * box.sides[2]
    assert p.crystal[lower].max() == 1.0 and p.crystal[~lower][-4:].max() < 0.5
    assert np.sum(p.packing) * box.volume / 16 == pytest.approx(st.n * math.pi / 6)


def test_at_constant_normal_pressure_only_the_long_side_moves():
    st, box = crystal_fluid_slab((3, 3, 4), plane="100", fluid_packing=0.45, seed=2)
    sim = hs.Simulation(st, box).set_barostat(hs.Barostat(pressure=11.6, kT=1.0, axes="z", seed=1))
    sim.run(until=2.0)
    assert sim.barostat.accepted > 0 and sim.container.sides[:2] == box.sides[:2]


def test_bad_slabs():
    for kwargs in ({"plane": "110"}, {"fluid_packing": 0.6}):
        with pytest.raises(BuildError):
            crystal_fluid_slab((3, 3, 3), **kwargs)
    with pytest.raises(BuildError, match="111"):
        crystal_fluid_slab((4, 3, 4), plane="111")
    with pytest.raises(ValueError):
        SlabProfile(1)


def test_the_fluid_is_compressed_to_its_packing_at_diameter_one():
    sides = (4.0, 4.0, 8.0)
    x = equilibrated_fluid(sides, 0.4917, seed=3)
    assert len(x) == round(0.4917 * 128.0 / (math.pi / 6))  # 120, above what random placement fits here
    assert closest_ratio(x, np.full(len(x), 0.5), np.array(sides)) >= 1.0 - 1e-12
    assert np.all(np.abs(x) <= 0.5 * np.array(sides) + 1e-12)
    assert np.array_equal(x, equilibrated_fluid(sides, 0.4917, seed=3))  # deterministic


def test_filling_makes_up_for_the_spheres_the_faces_take():
    cells = (3, 3, 4)
    target = 0.4917 * (3 * 1.5677) ** 2 * 4 * 1.5677 / (math.pi / 6)  # fluid spheres at 0.4917, about 181
    short, box = crystal_fluid_slab(cells, crystal_packing=0.5433, fluid_packing=0.4917, seed=4, fill=False)
    full, box2 = crystal_fluid_slab(cells, crystal_packing=0.5433, fluid_packing=0.4917, seed=4)
    assert box.sides == box2.sides
    lost = target - (short.n - 144)
    assert lost > 5  # the faces take spheres (about half a layer each)
    assert abs(full.n - 144 - target) < 0.5 * lost
    assert closest_ratio(full.positions, full.radii, np.array(box2.sides)) >= 1.0 - 1e-12


def test_plateaus_leave_out_the_interfaces():
    p = SlabProfile(8)
    p.crystal = np.array([1.0, 1.0, 1.0, 0.5, 0.0, 0.0, 0.0, 0.6])
    p.packing = np.array([0.54, 0.55, 0.54, 0.52, 0.49, 0.48, 0.49, 0.51])
    assert p.plateaus() == (pytest.approx(0.55), pytest.approx(0.48))
    p.crystal = np.zeros(8)
    s, f = p.plateaus()
    assert math.isnan(s) and f == pytest.approx(np.mean(p.packing))
