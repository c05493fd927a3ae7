"""Newtonian and forward event chains (EventChain(variant=...)): exact lifts, no overlap, the cells
against brute force bit for bit, the lifting rules, bit-for-bit resume and the pressure.

Scenarios as in tests/test_mc.py (random_spheres, equal and polydisperse radii, square and
rectangular boxes, 2-D and 3-D, scales 1e-6 to 1e6): every tolerance is relative.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres.eos import hansen_goos, kolafa_rottner
from hardspheres.errors import ArgumentError, BoxShapeError
from hardspheres.mc import _core as core
from hardspheres.mc.chain import VARIANTS, EventChain

ROUND = 1e-12
FREE = ["newtonian", "forward"]


def _worst_overlap(state, box):
    p, r = state.positions, state.radii
    dr = box.displacement(p[:, None, :], p[None, :, :])
    dist = np.sqrt(np.sum(dr * dr, axis=-1))
    sigma = r[:, None] + r[None, :]
    np.fill_diagonal(dist, np.inf)
    return float(np.max((sigma - dist) / sigma))


scenarios = st.tuples(
    st.sampled_from(FREE),
    st.sampled_from([2, 3]),
    st.integers(24, 150),
    st.floats(0.05, 0.55),
    st.sampled_from([1.0, 1.5, 3.0]),
    st.sampled_from([1e-6, 1.0, 1e6]),
    st.sampled_from([(1.0, 1.0, 1.0), (1.0, 0.8660254037844386, 1.3), (2.0, 1.0, 1.0)]),
    st.integers(0, 2**16),
)


@settings(max_examples=30, deadline=None)
@given(scenarios)
def test_no_overlap_ever_and_the_cells_equal_brute_force(args):
    variant, d, n, packing, ratio, scale, aspect, seed = args
    if d == 2:
        packing = min(packing * 1.3, 0.7)
    sides = tuple(scale * x for x in aspect[:d])
    try:
        box = hs.PeriodicBox.for_packing(n, packing, sides)
        state = hs.random_spheres(n, packing, box, seed=seed)
        state.radii = state.radii * np.random.default_rng(seed).uniform(1.0 / ratio, 1.0, n)
        cells = EventChain(state, box, seed=seed, variant=variant)
    except (hs.BuildError, BoxShapeError):
        return  # too few spheres for three cells across, or no room: not a case
    brute = EventChain(state, box, seed=seed, variant=variant)
    for _ in range(3):
        cells.run(chains=10)
        brute.run(chains=10, brute=True)
        assert _worst_overlap(cells.state(), box) <= ROUND
        assert np.array_equal(cells.state().positions, brute.state().positions)
        assert np.array_equal(cells.totals(), brute.totals())
    cells.run(events=7)
    brute.run(events=7, brute=True)
    assert np.array_equal(cells._pos, brute._pos) and np.array_equal(cells._images, brute._images)
    assert np.array_equal(cells._vel, brute._vel) and np.array_equal(cells._ints, brute._ints)


@pytest.mark.parametrize("variant", FREE)
@pytest.mark.parametrize("d", [2, 3])
def test_dense_polydisperse_runs_touch_but_never_overlap_and_equal_brute_force(variant, d):
    n, packing, aspect = (120, 0.66, (1.0, 0.9)) if d == 2 else (108, 0.45, None)
    box = hs.PeriodicBox.for_packing(n, packing, aspect)
    state = hs.random_spheres(n, packing, box, seed=3, uniform_radius_ratio=1.2)
    chain = EventChain(state, box, seed=3, variant=variant)
    brute = EventChain(state, box, seed=3, variant=variant)
    worst = []
    for _ in range(10):
        chain.run(events=997)  # stops mid-chain: a lifted pair is touching
        brute.run(events=997, brute=True)
        worst.append(_worst_overlap(chain.state(), box))
    assert max(worst) <= ROUND
    assert max(worst) > -1e-9  # at contact, within rounding: the lifts are exact
    assert np.array_equal(chain._pos, brute._pos) and np.array_equal(chain._tally, brute._tally)
    assert chain._ints[core.I_STEPS] > 0  # steps at the cells' edges happened (and changed nothing)


def _pair(variant, vel, length=10.0):
    """Disks of radius 2.5 at (-2.5, 0) and (5.5, 3) in a box of 16 (3 cells across), disk 0 active with ``vel``."""
    state = hs.State.from_arrays([1.0, 1.0], [2.5, 2.5], [[-2.5, 0.0], [5.5, 3.0]], np.zeros((2, 2)))
    chain = EventChain(state, hs.PeriodicBox((16.0, 16.0)), chain_length=length, variant=variant)
    chain._ints[core.I_ACTIVE] = 0
    chain._floats[core.F_LEFT] = length
    chain._vel[0] = vel
    chain._stamp[:] = 0  # both velocities drawn for this chain
    return chain


def test_a_newtonian_lift_by_hand_swaps_the_normal_components():
    # disk 0 moves along +x at speed 2 toward disk 1, (8, 3) ahead: contact after 4 (|(4, 3)| = 5),
    # within its cell (no step first)
    chain = _pair("newtonian", [2.0, 0.0])
    chain._vel[1] = [0.5, -1.0]
    chain.run(events=1)
    assert chain.state().positions.tolist() == [[1.5, 0.0], [5.5, 3.0]]
    assert chain._floats[core.F_LEFT] == 8.0  # the chain's time: 2 of 10 spent
    e = np.array([0.8, 0.6])
    v0, v1 = np.array([2.0, 0.0]), np.array([0.5, -1.0])
    dot = (v1 - v0) @ e
    assert np.allclose(chain._vel[0], v0 + dot * e, rtol=0, atol=1e-15)
    assert np.allclose(chain._vel[1], v1 - dot * e, rtol=0, atol=1e-15)
    assert chain._vel[1] @ e == pytest.approx(v0 @ e, rel=1e-15)  # j leaves along the normal as i came
    assert chain._ints[core.I_ACTIVE] == 1
    # the tallies: the lift's (r_j - r_i)_a v_a, the step's t v_a^2
    assert chain.totals().tolist() == [1.0, 0.0, 8.0, 0.0, 8.0, 0.0]


def test_a_forward_lift_keeps_the_side_and_leaves_along_the_normal():
    chain = _pair("forward", [1.0, 0.0])
    chain.run(events=1)
    e = np.array([0.8, 0.6])
    v = chain._vel[1]
    assert v @ v == pytest.approx(1.0, rel=1e-15)
    assert v @ e > 0  # away from disk 0
    across = np.array([-0.6, 0.8])  # the old direction (1, 0) has -0.6 across e: the side is kept
    assert v @ across < 0


@pytest.mark.parametrize("d", [2, 3])
def test_the_forward_rule_draws_the_normal_part_with_the_flux_weight(d):
    # the part along e has density c (1 - c^2)^((d-3)/2): in 2-D the part across is uniform on (0, 1],
    # in 3-D c^2 is
    rng = np.array([12345], dtype=np.uint64)
    vel = np.zeros((2, d))
    vel[0, :2] = [0.6, 0.8]
    e = (1.0, 0.0, 0.0)
    draws = []
    for _ in range(20000):
        core.lift_forward(0, 1, *e, vel, rng, ((),) * d)
        draws.append(vel[1, 0])
    c = np.array(draws)
    assert np.all(c > 0)
    x = np.sqrt(1 - c**2) if d == 2 else c**2
    assert abs(x.mean() - 0.5) < 4 * math.sqrt(1 / 12 / x.size)
    assert abs(np.mean(x < 0.25) - 0.25) < 4 * math.sqrt(0.25 * 0.75 / x.size)


@pytest.mark.parametrize("variant", FREE)
def test_resume_is_bit_for_bit(tmp_path, variant):
    box = hs.PeriodicBox((14.0, 12.0))
    state = hs.random_spheres(100, 0.6, box, seed=2)
    whole = EventChain(state, box, seed=4, variant=variant)
    whole.run(chains=30).run(events=555).run(chains=40)
    part = EventChain(state, box, seed=4, variant=variant)
    part.run(chains=30).run(events=555)  # mid-chain
    part.save(tmp_path / "c.npz")
    resumed = EventChain.load(tmp_path / "c.npz")
    assert resumed.variant == variant
    resumed.run(chains=40)
    assert np.array_equal(resumed._pos, whole._pos) and np.array_equal(resumed._images, whole._images)
    assert np.array_equal(resumed.totals(), whole.totals()) and resumed._rng[0] == whole._rng[0]
    assert np.array_equal(resumed._vel, whole._vel)


def test_a_checkpoint_from_before_the_variants_loads_as_straight(tmp_path):
    box = hs.PeriodicBox((10.0, 10.0))
    chain = EventChain(hs.random_spheres(20, 0.3, box, seed=1), box)
    chain.run(chains=5)
    chain.save(tmp_path / "c.npz")
    data = dict(np.load(tmp_path / "c.npz"))
    for key in ("variant", "velocities", "stamps"):
        del data[key]
    data["ints"] = data["ints"][:3]
    np.savez(tmp_path / "old.npz", **data)
    old = EventChain.load(tmp_path / "old.npz")
    assert old.variant == "straight" and old.counters == chain.counters
    assert np.array_equal(old.run(chains=5)._pos, chain.run(chains=5)._pos)


def test_an_unknown_variant_is_refused_in_one_line():
    box = hs.PeriodicBox((10.0, 10.0))
    with pytest.raises(ArgumentError, match="straight, newtonian, forward") as e:
        EventChain(hs.random_spheres(20, 0.3, box, seed=1), box, variant="reflective")
    assert "\n" not in str(e.value)
    assert list(VARIANTS) == ["straight", "newtonian", "forward"]


@pytest.mark.parametrize("variant", FREE)
@pytest.mark.parametrize(
    "d, packing, n, reference", [(2, 0.5, 400, kolafa_rottner), (3, 0.35, 500, hansen_goos)]
)
def test_the_pressure_matches_the_equation_of_state(variant, d, packing, n, reference):
    box = hs.PeriodicBox.for_packing(n, packing, (1.0,) * d)
    chain = EventChain(hs.random_spheres(n, packing, box, seed=11), box, seed=11, variant=variant)
    chain.run(events=500 * n).observables.reset()
    chain.run(events=(6000 if d == 2 else 3000) * n)
    z = chain.observables.estimate("Z")
    # the canonical ensemble's 1/N term (docs/numerics.md): Z_N = Z - phi K' / (2 N K), K = d(phi Z)/d phi
    h = 1e-4

    def k(p):
        return ((p + h) * float(reference(p + h)) - (p - h) * float(reference(p - h))) / (2 * h)

    expected = float(reference(packing)) - packing * (k(packing + h) - k(packing - h)) / (2 * h) / (
        2 * n * k(packing)
    )
    assert z.converged and z.sem > 0
    assert abs(z.mean - expected) <= 3 * z.sem
    s = chain.observables.summary()
    assert abs(s["pressure_xx"] - s["pressure_yy"]) <= 3 * math.hypot(
        s["pressure_xx_error"], s["pressure_yy_error"]
    )


def test_the_sample_command_takes_a_variant_and_resumes_it(tmp_path, capsys):
    from hardspheres.cli.commands import main

    box = hs.PeriodicBox((20.0, 20.0))
    scn = tmp_path / "d.txt"
    scn.write_text(hs.random_spheres(200, 0.5, box, seed=1).to_text())
    ck = str(tmp_path / "s.npz")
    argv = ["sample", str(scn), "--box", "20", "20", "--chains", "200", "--variant", "forward"]
    assert main([*argv, "--checkpoint", ck]) == 0
    assert "Z = beta P V / N" in capsys.readouterr().out
    assert EventChain.load(ck).variant == "forward"
    assert main(["sample", "--resume", ck, "--chains", "10", "--variant", "newtonian"]) == 1
    err = capsys.readouterr().err.strip()
    assert "leave out --variant" in err and "\n" not in err
