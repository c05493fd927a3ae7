"""Direct coexistence: the crystal-fluid slab and its profiles (hardspheres.analysis.coexistence)."""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.analysis.coexistence import SlabProfile, crystal_fluid_slab
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
