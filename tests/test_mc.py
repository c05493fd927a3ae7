"""Event-chain Monte Carlo (hardspheres.mc): exact lifts, no overlap, the cells against brute force,
bit-for-bit resume, the pressure against the equations of state and the event core, files and commands.

Scenarios are random_spheres states (equal and polydisperse radii, square and
rectangular boxes, 2-D and 3-D) at scales from 1e-6 to 1e6: every tolerance is
relative (scale-free).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres.eos import hansen_goos, kolafa_rottner
from hardspheres.errors import BoxShapeError, CheckpointError, PeriodicBoxRequired, ScenarioError
from hardspheres.mc import _core as core
from hardspheres.mc.chain import CHAIN_FRACTION, EventChain

#: Overlap allowed after a run, relative to the contact distance: rounding only.
ROUND = 1e-12


def _pair(a, b, sides=(40.0, 40.0), length=10.0):
    """Two spheres of radius 2.5 at ``a`` and ``b`` in a box, sphere 0 about to move along +x."""
    d = len(sides)
    state = hs.State.from_arrays([1.0, 1.0], [2.5, 2.5], [a, b], np.zeros((2, d)))
    chain = EventChain(state, hs.PeriodicBox(tuple(sides)), chain_length=length)
    chain._ints[core.I_ACTIVE] = 0  # the chain in progress: sphere 0, all of it left
    chain._floats[core.F_LEFT] = length
    return chain


def test_two_disks_by_hand():
    # dr = (8, 3), sigma = 5: perp 3, sqrt(25 - 9) = 4, so the lift is 8 - 4 = 4
    chain = _pair([0.0, 0.0], [8.0, 3.0])
    chain.run(events=1)
    assert chain.state().positions.tolist() == [[4.0, 0.0], [8.0, 3.0]]
    assert chain.counters == {"events": 1, "chains": 0, "collisions": 1}
    assert chain._ints[core.I_ACTIVE] == 1 and chain._floats[core.F_LEFT] == 6.0
    # the rest of the chain (6) moves sphere 1 on: 0 lies behind it, its image 36 ahead
    chain.run(chains=1)
    assert chain.state().positions.tolist() == [[4.0, 0.0], [14.0, 3.0]]
    assert chain.totals().tolist() == [1.0, 1.0, 4.0, 0.0, 10.0, 0.0]
    # Z_x = 1 + 4 / 10 (Li et al. Eq. 20), over N / V = 2 / 1600
    assert chain.observables.estimate("pressure_xx").mean == pytest.approx(2 / 1600 * 1.4, rel=1e-15)


def test_a_chain_longer_than_the_box_wraps_and_counts_images():
    # from x = 8, sphere 1 meets sphere 0's image ahead after 32 (lead 36, minus 4): a chain of 30 does not
    chain = _pair([4.0, 0.0], [8.0, 3.0], length=30.0)
    chain._ints[core.I_ACTIVE] = 1
    chain.run(chains=1)
    st_ = chain.state()
    assert st_.positions.tolist() == [[4.0, 0.0], [-2.0, 3.0]]
    assert st_.images.tolist() == [[0, 0], [1, 0]]
    assert chain.state(unwrapped=True).positions.tolist() == [[4.0, 0.0], [38.0, 3.0]]
    # ... and a chain of 40 does: a lift at 32, then sphere 0 goes on 8
    chain = _pair([4.0, 0.0], [8.0, 3.0], length=40.0)
    chain._ints[core.I_ACTIVE] = 1
    chain.run(chains=1)
    assert chain.state(unwrapped=True).positions.tolist() == [[12.0, 0.0], [40.0, 3.0]]
    assert chain.counters["events"] == 1


def test_a_graze_is_no_contact_and_the_lift_is_the_kernels_root():
    # perp = sigma exactly: they graze, no lift
    chain = _pair([0.0, 0.0], [8.0, 5.0])
    chain.run(chains=1)
    assert chain.counters["events"] == 0
    assert chain.state().positions[0].tolist() == [10.0, 0.0]
    # the lift is physics.pair_time_within with v_i - v_j = e_x, bit for bit
    from hardspheres import physics

    dr, perp = 7.3, 1.9
    chain = _pair([0.0, 0.0], [dr, perp])
    chain.run(events=1)
    assert chain.state().positions[0, 0] == physics.pair_time(
        -dr, -perp, 0.0, 1.0, 0.0, 0.0, 5.0, planar=True
    )


def test_three_d_by_hand_and_the_axes_alternate():
    # along +x first: dr = (8, 0, 3), sigma 5: lift 4; the next chain runs along +y
    state = hs.State.from_arrays([1.0, 1.0], [2.5, 2.5], [[0, 0, 0], [8.0, 0.0, 3.0]], np.zeros((2, 3)))
    chain = EventChain(state, hs.PeriodicBox(40.0), chain_length=10.0)
    chain._ints[core.I_ACTIVE] = 0
    chain._floats[core.F_LEFT] = 10.0
    chain.run(chains=1)
    assert chain.state().positions.tolist() == [[4.0, 0.0, 0.0], [14.0, 0.0, 3.0]]
    before = chain.state().positions
    chain.run(chains=1)  # the second chain: along y only
    moved = np.nonzero(np.any(chain.state().positions != before, axis=0))[0].tolist()
    assert moved == [1]
    chain.run(chains=1)
    assert chain.totals()[2 + 3 + 2] > 0  # the third along z


def _scenario(d, n, packing, ratio, scale, aspect, seed):
    """Equal spheres from the builder, then each shrunk by a factor in ``[1/ratio, 1]`` (polydisperse)."""
    sides = tuple(scale * x for x in aspect[:d])
    box = hs.PeriodicBox.for_packing(n, packing, sides)
    state = hs.random_spheres(n, packing, box, seed=seed)
    state.radii = state.radii * np.random.default_rng(seed).uniform(1.0 / ratio, 1.0, n)
    return state, box


def _worst_overlap(state, box):
    p, r = state.positions, state.radii
    dr = box.displacement(p[:, None, :], p[None, :, :])
    dist = np.sqrt(np.sum(dr * dr, axis=-1))
    sigma = r[:, None] + r[None, :]
    np.fill_diagonal(dist, np.inf)
    return float(np.max((sigma - dist) / sigma))


scenarios = st.tuples(
    st.sampled_from([2, 3]),
    st.integers(24, 150),
    st.floats(0.05, 0.55),
    st.sampled_from([1.0, 1.5, 3.0]),
    st.sampled_from([1e-6, 1.0, 1e6]),
    st.sampled_from([(1.0, 1.0, 1.0), (1.0, 0.8660254037844386, 1.3), (2.0, 1.0, 1.0)]),
    st.integers(0, 2**16),
)


@settings(max_examples=30)
@given(scenarios)
def test_no_overlap_ever_and_the_cells_equal_brute_force(args):
    d, n, packing, ratio, scale, aspect, seed = args
    if d == 2:
        packing = min(packing * 1.3, 0.7)
    try:
        state, box = _scenario(d, n, packing, ratio, scale, aspect, seed)
        cells = EventChain(state, box, seed=seed)
    except (hs.BuildError, BoxShapeError):
        return  # too few spheres for three cells across, or no room: not a case
    brute = EventChain(state, box, seed=seed)
    for _ in range(3):
        cells.run(chains=10)
        brute.run(chains=10, brute=True)
        assert _worst_overlap(cells.state(), box) <= ROUND
        assert np.array_equal(cells.state().positions, brute.state().positions)
        assert np.array_equal(cells.totals(), brute.totals())
    cells.run(events=7)
    brute.run(events=7, brute=True)
    assert np.array_equal(cells._pos, brute._pos) and np.array_equal(cells._images, brute._images)


@pytest.mark.parametrize("d", [2, 3])
def test_dense_polydisperse_runs_touch_but_never_overlap(d):
    n, packing, aspect = (120, 0.62, (1.0, 0.9)) if d == 2 else (108, 0.45, None)
    box = hs.PeriodicBox.for_packing(n, packing, aspect)
    state = hs.random_spheres(n, packing, box, seed=3, uniform_radius_ratio=1.2)
    chain = EventChain(state, box, seed=3)
    worst = []
    for _ in range(20):
        chain.run(events=997)  # stops mid-chain: a lifted pair is touching
        worst.append(_worst_overlap(chain.state(), box))
    assert max(worst) <= ROUND
    assert max(worst) > -1e-9  # at contact, within rounding: the lifts are exact


@pytest.mark.parametrize("d", [2, 3])
def test_the_brute_force_search_equals_the_cells_in_a_dense_binary_mixture(d):
    n, packing, aspect = (300, 0.65, (1.0, 0.866)) if d == 2 else (256, 0.40, None)
    box = hs.PeriodicBox.for_packing(n, packing, aspect)
    state = hs.random_spheres(n, packing, box, seed=5, binary=(1.4, 0.5))
    a, b = EventChain(state, box, seed=9), EventChain(state, box, seed=9)
    a.run(chains=60)
    b.run(chains=60, brute=True)
    assert a.counters == b.counters and a.counters["events"] > 500
    assert np.array_equal(a._pos, b._pos) and np.array_equal(a._tally, b._tally)


def test_resume_is_bit_for_bit(tmp_path):
    box = hs.PeriodicBox((14.0, 12.0))
    state = hs.random_spheres(100, 0.6, box, seed=2)
    whole = EventChain(state, box, seed=4)
    whole.run(chains=30).run(events=555).run(chains=40)
    part = EventChain(state, box, seed=4)
    part.run(chains=30).run(events=555)  # mid-chain
    part.save(tmp_path / "c.npz")
    resumed = EventChain.load(tmp_path / "c.npz")
    resumed.run(chains=40)
    assert np.array_equal(resumed._pos, whole._pos) and np.array_equal(resumed._images, whole._images)
    assert np.array_equal(resumed.totals(), whole.totals()) and resumed._rng[0] == whole._rng[0]
    assert resumed.observables.estimate("Z").mean == whole.observables.estimate("Z").mean
    assert np.array_equal(resumed.observables.blocks("Z"), whole.observables.blocks("Z"))


def test_a_damaged_or_foreign_checkpoint_is_refused_in_one_line(tmp_path):
    box = hs.PeriodicBox((10.0, 10.0))
    chain = EventChain(hs.random_spheres(20, 0.3, box, seed=1), box)
    chain.save(tmp_path / "c.npz")
    data = dict(np.load(tmp_path / "c.npz"))
    data["positions"] = data["positions"][:, :1]
    np.savez(tmp_path / "bad.npz", **data)
    with pytest.raises(CheckpointError, match="positions") as e:
        EventChain.load(tmp_path / "bad.npz")
    assert "\n" not in str(e.value)
    np.savez(tmp_path / "s.npz", format=np.array("hardspheres-checkpoint"), version=np.array(2))
    with pytest.raises(CheckpointError, match="not an event-chain checkpoint"):
        EventChain.load(tmp_path / "s.npz")


@pytest.mark.parametrize(
    "d, packing, n, reference",
    [
        (2, 0.3, 400, kolafa_rottner),
        (2, 0.5, 400, kolafa_rottner),
        (3, 0.2, 500, hansen_goos),
        (3, 0.35, 500, hansen_goos),
    ],
)
def test_the_pressure_matches_the_equation_of_state(d, packing, n, reference):
    # (at N = 64 the pressure of disks at 0.3 is 0.6% low: the finite-size correction of
    # order 1/N, 0.2% at N = 256 and none seen at 1024; the event core's is the same)
    box = hs.PeriodicBox.for_packing(n, packing, (1.0,) * d)
    chain = EventChain(hs.random_spheres(n, packing, box, seed=11), box, seed=11)
    chain.run(chains=300 * d).observables.reset()
    chain.run(chains=20000 if d == 2 else 100000)
    z = chain.observables.estimate("Z")
    assert z.converged and z.sem > 0
    assert abs(z.mean - float(reference(packing))) <= 3 * z.sem
    # the axes agree with each other (equal in equilibrium)
    s = chain.observables.summary()
    assert abs(s["pressure_xx"] - s["pressure_yy"]) <= 3 * math.hypot(
        s["pressure_xx_error"], s["pressure_yy_error"]
    )


def test_the_pressure_matches_the_event_cores():
    box = hs.PeriodicBox((9.0, 9.0))
    state = hs.random_spheres(64, 0.5, box, seed=21)
    chain = EventChain(state, box, seed=21)
    chain.run(chains=300).observables.reset()
    ecmc = chain.run(chains=6000).observables.estimate("Z")
    sim = hs.Simulation(state, box)
    sim.run(collisions=20000)
    sim.observables.reset()
    edmd = sim.run(collisions=200000).observables.estimate("Z")
    assert abs(ecmc.mean - edmd.mean) <= 3 * math.hypot(ecmc.sem, edmd.sem)


def test_refusals_are_one_line():
    state = hs.random_spheres(10, 0.2, hs.SphericalContainer(6.0), seed=1)
    with pytest.raises(PeriodicBoxRequired, match="periodic box") as e:
        EventChain(state, hs.SphericalContainer(6.0))
    assert "\n" not in str(e.value)
    disks = hs.random_spheres(10, 0.2, hs.CircularContainer(6.0), seed=1)
    with pytest.raises(PeriodicBoxRequired):
        EventChain(disks, hs.CircularContainer(6.0))
    two = hs.State.from_arrays([1, 1], [1.0, 1.0], [[0, 0], [1.5, 0]], np.zeros((2, 2)))
    with pytest.raises(ScenarioError, match="overlap"):
        EventChain(two, hs.PeriodicBox((10.0, 10.0)))
    with pytest.raises(BoxShapeError, match="three times the largest diameter"):
        EventChain(two, hs.PeriodicBox((5.0, 10.0)))
    with pytest.raises(ScenarioError, match="2-D positions in a 3-D box"):
        EventChain(two, hs.PeriodicBox(10.0))
    ok = hs.State.from_arrays([1, 1], [1.0, 1.0], [[0, 0], [3.0, 0]], np.zeros((2, 2)))
    with pytest.raises(ValueError, match="chain_length"):
        EventChain(ok, hs.PeriodicBox((10.0, 10.0)), chain_length=-1.0)
    with pytest.raises(ValueError, match="give chains or events"):
        EventChain(ok, hs.PeriodicBox((10.0, 10.0))).run()


def test_the_default_chain_length_is_li_et_al_s():
    box = hs.PeriodicBox((30.0, 20.0))
    chain = EventChain(hs.random_spheres(50, 0.3, box, seed=1), box)
    assert chain.chain_length == CHAIN_FRACTION * math.sqrt(600.0)
    assert CHAIN_FRACTION == pytest.approx(3.125 * 0.0768)


def test_one_call_to_the_event_core_and_back():
    box = hs.PeriodicBox((12.0, 12.0))
    chain = EventChain(hs.random_spheres(64, 0.5, box, seed=1), box, kT=2.0)
    chain.run(chains=50)
    sim = chain.to_simulation(seed=3)
    assert np.array_equal(sim.state().positions, chain.state().positions)
    assert np.array_equal(sim.state().images, chain.state().images)
    assert sim.observables.temperature() == pytest.approx(2.0, rel=1e-12)
    assert np.allclose(sim.state().momentum(), 0.0, atol=1e-12)
    sim.run(collisions=1000)
    back = EventChain.from_simulation(sim, seed=5)
    assert back.kT == pytest.approx(2.0, rel=1e-9)
    assert np.array_equal(back.state(unwrapped=True).positions, sim.state(unwrapped=True).positions)
    back.run(chains=10)


@pytest.mark.parametrize("suffix", [".gsd", ".xyz"])
def test_frames_at_chain_ends_through_the_trajectory_writers(tmp_path, suffix):
    pytest.importorskip("gsd")
    box = hs.PeriodicBox((12.0, 12.0))
    chain = EventChain(hs.random_spheres(64, 0.5, box, seed=1), box)
    path = tmp_path / f"t{suffix}"
    writer = hs.GSDWriter(path, every=10) if suffix == ".gsd" else hs.XYZWriter(path, every=10)
    with writer:
        chain.writers.append(writer)
        chain.run(events=333)  # mid-chain: the next frame waits for a chain's end
        chain.run(chains=45)
    frames = hs.read_trajectory(path)
    k = int(chain.time // 10) + 1
    assert chain.time > 50 and frames.times.tolist() == [10.0 * m for m in range(k)]
    assert frames.positions.shape == (k, 64, 2)
    assert np.array_equal(frames.positions[-1], chain.state().positions) == (chain.time % 10 == 0)
    pytest.importorskip("freud")
    rdf = hs.RDF().compute(frames)
    assert np.all(np.isfinite(rdf.g)) and rdf.g.max() > 1.0


def test_the_sample_command_runs_resumes_and_refuses_in_one_line(tmp_path, capsys):
    from hardspheres.cli.commands import main

    box = hs.PeriodicBox((20.0, 20.0))
    scn = tmp_path / "d.txt"
    scn.write_text(hs.random_spheres(200, 0.5, box, seed=1).to_text())
    gsd, ck = str(tmp_path / "s.gsd"), str(tmp_path / "s.npz")
    pytest.importorskip("gsd")
    argv = ["sample", str(scn), "--box", "20", "20", "--chains", "600", "--equilibrate", "100"]
    assert main([*argv, "--trajectory", gsd, "--every", "100", "--checkpoint", ck]) == 0
    out = capsys.readouterr().out
    assert "chains 700" in out and "Z = beta P V / N" in out and "pressure_yy" in out
    assert main(["sample", "--resume", ck, "--chains", "300", "--trajectory", gsd, "--every", "100"]) == 0
    assert "chains 1000" in capsys.readouterr().out
    frames = hs.read_trajectory(gsd)
    assert frames.times.tolist() == [100.0 * k for k in range(11)]
    # the same run in one go ends with the same bits
    one = EventChain(hs.State.from_scenario(hs.parse_scenario(scn.read_text()), dimensions=2), box)
    one.run(chains=1000)
    assert np.array_equal(EventChain.load(ck).state().positions, one.state().positions)
    assert main(["sample", str(scn), "--circle", "20", "--chains", "5"]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("hardspheres sample: --container/--circle") and "\n" not in err


def test_a_study_with_method_ecmc_runs_and_refuses_what_chains_cannot_do(tmp_path):
    pytest.importorskip("pandas")
    from hardspheres.errors import StudyError
    from hardspheres.studies.spec import parse_study
    from hardspheres.studies.task import run_task, tasks

    keys = {"packing": 0.3, "n": 100, "dimensions": 2, "collisions": 300, "equilibrate": 30, "blocks": 4}
    study = parse_study({**keys, "method": "ecmc", "output": str(tmp_path / "s")})
    (task,) = tasks(study)
    assert task["method"] == "ecmc"
    row = run_task(task)
    assert row["method"] == "ecmc" and row["Z_err"] > 0
    assert abs(row["Z"] - float(kolafa_rottner(0.3))) < 0.05  # (100 disks: finite-size 0.4% low)
    # EDMD tasks keep their keys (no method entry)
    (edmd,) = tasks(parse_study({**keys, "output": str(tmp_path / "e")}))
    assert "method" not in edmd
    for bad, what in (
        ({"container": "circle"}, 'container = "box"'),
        ({"pressure": 5.0}, "constant volume"),
        ({"measure": ["collision_rate"]}, "not measured by"),
        ({"method": "mc"}, 'give "edmd" or "ecmc"'),
    ):
        with pytest.raises(StudyError, match=what) as e:
            parse_study({**keys, "method": "ecmc", **bad})
        assert "\n" not in str(e.value)


def test_the_event_core_names_an_event_chain_checkpoint_for_what_it_is(tmp_path):
    box = hs.PeriodicBox((10.0, 10.0))
    EventChain(hs.random_spheres(20, 0.3, box, seed=1), box).save(tmp_path / "c.npz")
    with pytest.raises(
        CheckpointError, match="an event-chain checkpoint; resume it with hardspheres sample"
    ) as e:
        hs.Simulation.load(tmp_path / "c.npz")
    assert "\n" not in str(e.value)
