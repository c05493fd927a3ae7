"""Granular gases in the event core: inelastic collisions against the brute-force reference, bit for bit.

The inelastic rule is the core's compile-time variant (``_core``, "the
collision rule"): restitution between spheres and at the wall, the TC model
(Luding and McNamara 1998), the energy dissipated tallied.  The reference
(:mod:`hardspheres.core.reference`) runs the same kernels with the same
arithmetic, so the two agree bit for bit in spheres, circles and periodic
boxes, in 2-D and 3-D, with cells and with neighbour lists, the window on
and off.  Without the TC model an inelastic collapse stops with the
frozen-clock error; with it the run goes on.
"""

import math

import numpy as np
import pytest
from helpers import hs_cmd

import hardspheres as hs

from hardspheres.containers import CircularContainer, PeriodicBox, SphericalContainer
from hardspheres.core import _core as core
from hardspheres.core import checkpoint
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference
from hardspheres.core.scan import Scan
from hardspheres.errors import ArgumentError, StudyError, StuckError
from hardspheres.events import StopReason
from hardspheres.physics import (
    collide,
    collide_inelastic,
    reflect,
    reflect_inelastic,
    scaled_time,
)

from test_engine import CompiledReference, same_events
from test_reference_boxes import _pair

CONTAINERS = {
    "sphere": SphericalContainer(9.0),
    "cube": PeriodicBox(11.0),
    "circle": CircularContainer(10.0),
    "square": PeriodicBox((21.0, 21.0)),
}


def _kinetic(m, v):
    return 0.5 * float(np.sum(np.asarray(m) * np.sum(np.asarray(v, dtype=float) ** 2, axis=1)))


def _run_both(container, m, r, x, v, events, window=0.0, **rule):
    eng = Engine(m, r, x, v, container=container, window=window, rebase=False, reorder=0.0, **rule)
    ref = CompiledReference(
        m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), container=container, window=window, **rule
    )
    return eng, ref, eng.advance(events=events), ref.advance(events=events)


def _assert_same(eng, ref):
    n, d = eng.n, eng.dimensions
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities, dtype=float).reshape(n, d))
    assert np.array_equal(eng.positions_at(), np.asarray(ref.positions_at(), dtype=float).reshape(n, d))
    for key in ("collisions", "reflections"):
        assert eng.counters[key] == ref.counters[key]
    assert (eng.time, eng.wall_impulse, eng.virial) == (ref.time, ref.wall_impulse, ref.virial)
    assert eng.dissipated == ref.dissipated > 0.0


@pytest.fixture(params=["cells", "lists"])
def mode(request, monkeypatch):
    """Cells, or neighbour lists whatever the density."""
    if request.param == "lists":
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
        monkeypatch.setattr(engine_module, "LISTS_FROM_2D", 0.0)
    return request.param


@pytest.mark.parametrize("where", list(CONTAINERS))
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_inelastic_engine_matches_the_reference(where, window, mode):
    """Restitution 0.8 between spheres, 0.9 at the wall: the same events, velocities and tallies."""
    c = CONTAINERS[where]
    m, r, x, v = _pair(c, 200 if c.periodic else 60, 0.25, seed=3, ratio=1.3)
    eng, ref, a, b = _run_both(c, m, r, x, v, 1500, window, restitution=0.8, wall_restitution=0.9)
    assert (eng.scalars[core.F_SHELL] > 0.0) == (mode == "lists")
    assert eng.rule == ((),)
    assert len(a) == len(b) == 1500
    assert same_events(a, b)
    _assert_same(eng, ref)


@pytest.mark.parametrize("where", ["sphere", "square"])
def test_the_tc_model_matches_the_reference(where):
    """With ``tc`` a fifth of a mean free time some collisions are elastic: the same bits, less dissipated."""
    c = CONTAINERS[where]
    m, r, x, v = _pair(c, 60, 0.3, seed=5)
    free = Engine(m, r, x, v, container=c, rebase=False)
    free.advance(events=600)
    tc = 0.2 * free.time * 2.0 * free.n / 600.0  # (a mean free time: 2 N / events per unit time)
    rule = dict(restitution=0.5, wall_restitution=0.5)
    eng, ref, a, b = _run_both(c, m, r, x, v, 1200, tc=tc, **rule)
    assert same_events(a, b)
    _assert_same(eng, ref)
    plain = Engine(m, r, x, v, container=c, rebase=False, **rule)
    plain.advance(events=1200)
    assert plain.dissipated != eng.dissipated  # (the TC model made some collisions elastic)


def test_restitution_one_gives_the_elastic_bits():
    """The inelastic loop at e = 1 (the wall's 0.5 unused in a box) is the elastic one, bit for bit."""
    c = CONTAINERS["cube"]
    m, r, x, v = _pair(c, 80, 0.3, seed=7, ratio=1.5)
    elastic = Engine(m, r, x, v, container=c)
    granular = Engine(m, r, x, v, container=c, restitution=1.0, wall_restitution=0.5, tc=0.01)
    assert elastic.rule == () and granular.rule == ((),)
    assert same_events(elastic.advance(events=3000), granular.advance(events=3000))
    assert np.array_equal(elastic.velocities, granular.velocities)
    assert granular.dissipated == 0.0


@pytest.mark.parametrize("where", list(CONTAINERS))
def test_energy_dissipated_is_accounted_to_rounding(where):
    """Kinetic energy plus the core's tally stays the initial energy; momentum is conserved in a box.

    (In a box the total momentum is set to zero: its kinetic energy cannot be
    dissipated, and a gas cooled down to it flies on as one, crossing the
    box millions of times between its ever rarer collisions.)
    """
    c = CONTAINERS[where]
    m, r, x, v = _pair(c, 100, 0.3, seed=11, ratio=1.2)
    if c.periodic:
        v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)
    eng = Engine(m, r, x, v, container=c, restitution=0.7, wall_restitution=0.9)
    e0 = _kinetic(m, v)
    p0 = np.sum(np.asarray(m)[:, None] * np.asarray(v), axis=0)
    eng.advance(events=20000)
    assert eng.kinetic_energy() < 0.5 * e0
    assert abs(eng.kinetic_energy() + eng.dissipated - e0) <= 1e-12 * e0
    if c.periodic:
        p = np.sum(eng.masses[:, None] * eng.velocities, axis=0)
        assert np.allclose(p, p0, rtol=0, atol=1e-12 * np.sum(np.abs(np.asarray(m)[:, None] * v)))
    assert eng.max_overlap() < 1e-9


def test_sorted_spheres_keep_their_last_collisions():
    """Morton reordering moves each sphere's last collision time with it: the same bits as unsorted."""
    c = CONTAINERS["cube"]
    m, r, x, v = _pair(c, 200, 0.25, seed=9)
    kw = dict(container=c, restitution=0.7, tc=0.05)
    plain, sorted_ = Engine(m, r, x, v, reorder=0.0, **kw), Engine(m, r, x, v, reorder=1.0, **kw)
    assert same_events(plain.advance(events=4000), sorted_.advance(events=4000))
    assert np.array_equal(plain.velocities, sorted_.velocities) and plain.dissipated == sorted_.dissipated
    assert not np.array_equal(sorted_.order, np.arange(200))  # (it did sort)


def test_checkpoint_resumes_bit_for_bit():
    """Rule, last collision times and the dissipated energy survive a checkpoint (with rebases)."""
    c = CONTAINERS["circle"]
    m, r, x, v = _pair(c, 50, 0.3, seed=13)
    kw = dict(container=c, restitution=0.9, wall_restitution=0.8, tc=1e-3)
    a = Engine(m, r, x, v, **kw)
    a.advance(events=5000)
    saved = a.checkpoint()
    assert saved["hit_t"].shape == (50,) and np.all(np.isfinite(saved["hit_t"]))
    b = Engine.restore({k: np.copy(w) for k, w in saved.items()})
    assert (b.restitution, b.wall_restitution, b.tc, b.rule) == (0.9, 0.8, 1e-3, ((),))
    ea, eb = a.advance(events=5000), b.advance(events=5000)
    assert same_events(ea, eb)
    assert np.array_equal(a.velocities, b.velocities) and a.dissipated == b.dissipated


def test_an_older_checkpoint_is_elastic():
    """A version-2 layout (no rule among the scalars, no ``hit_t``) restores as elastic spheres."""
    c = CONTAINERS["sphere"]
    m, r, x, v = _pair(c, 30, 0.2, seed=2)
    a = Engine(m, r, x, v, container=c)
    a.advance(events=500)
    old = {k: np.copy(w) for k, w in a.checkpoint().items() if k != "hit_t"}
    old["scalars"] = old["scalars"][: core.F_RESTITUTION]
    b = Engine.restore(old)
    assert b.rule == () and (b.restitution, b.wall_restitution, b.tc, b.dissipated) == (1.0, 1.0, 0.0, 0.0)
    assert same_events(a.advance(events=500), b.advance(events=500))


def test_damaged_rule_in_a_checkpoint_is_refused():
    c = CONTAINERS["cube"]
    m, r, x, v = _pair(c, 30, 0.2, seed=2)
    saved = Engine(m, r, x, v, container=c, restitution=0.9).checkpoint()
    for damage in ("short", "restitution"):
        bad = {k: np.copy(w) for k, w in saved.items()}
        if damage == "short":
            bad["hit_t"] = bad["hit_t"][:-1]
        else:
            bad["scalars"][core.F_RESTITUTION] = 1.5
        with pytest.raises(checkpoint.CheckpointError, match="damaged checkpoint"):
            Engine.restore(bad)


def _line(n, e, tc=0.0, engine=Engine):
    """``n`` disks in a line, the two ends thrown inwards at unit speed, restitution ``e``."""
    x = [[-12.0 + 2.2 * k, 0.0] for k in range(n)]
    v = [[0.0, 0.0] for _ in range(n)]
    v[0][0], v[-1][0] = 1.0, -1.0
    return engine([1.0] * n, [1.0] * n, x, v, container=CircularContainer(100.0), restitution=e, tc=tc)


@pytest.mark.parametrize("engine", [Engine, CompiledReference], ids=["compiled", "reference"])
def test_inelastic_collapse_stops_with_the_frozen_clock(engine):
    """12 disks in a line at e = 0.5 collapse; the run stops (no hang), naming a sphere and the TC model.

    (Three disks in a line collapse only below e = 7 - 4 sqrt(3) = 0.072:
    McNamara and Young, Phys. Rev. E 50, R28 (1994).)
    """
    sim = _line(12, 0.5, engine=engine)
    sim.advance(until=100.0, record=False)  # the events before the freeze
    assert sim.counters["collisions"] > 100000
    with pytest.raises(StuckError, match="inelastic collapse.*tc") as err:
        sim.advance(until=100.0, record=False)
    assert err.value.reason == "frozen" and 0 <= err.value.sphere < 12 and err.value.time < 100.0
    assert err.value.named([f"d{k}" for k in range(12)]).inelastic


def test_the_tc_model_resolves_the_collapse():
    """With tc = 1e-4 (of a free flight of ~1) the same line runs to the end, dissipating most of its energy."""
    sim = _line(12, 0.5, tc=1e-4)
    sim.advance(until=2000.0, record=False)
    assert sim.last_reason == StopReason.UNTIL and sim.step(until=2000.0) is None  # (to the end)
    assert 0.5 < sim.dissipated < 1.0  # (of the initial 1.0)
    assert abs(sim.kinetic_energy() + sim.dissipated - 1.0) < 1e-12


def test_collapse_same_as_the_reference_until_it_freezes():
    eng, ref = _line(12, 0.5), _line(12, 0.5, engine=CompiledReference)
    eng.advance(until=100.0, record=False)
    ref.advance(until=100.0, record=False)
    assert eng.counters["collisions"] == ref.counters["collisions"]
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities).reshape(12, 2))
    with pytest.raises(StuckError) as a:
        eng.advance(until=100.0)
    with pytest.raises(StuckError) as b:
        ref.advance(until=100.0)
    assert (a.value.time, a.value.sphere) == (b.value.time, b.value.sphere)


@pytest.mark.parametrize("engine", [Engine, CompiledReference], ids=["compiled", "reference"])
def test_an_inelastic_wall_brings_a_disk_to_slide(engine):
    """At wall restitution 0.6 a disk loses its speed off the circle and slides: the sliding error, with the cure."""
    c = CONTAINERS["circle"]
    m, r, x, v = _pair(c, 60, 0.25, seed=3, ratio=1.3)
    sim = engine(m, r, x, v, container=c, restitution=0.8, wall_restitution=0.6)
    sim.advance(events=1500)
    assert sim.counters["reflections"] + sim.counters["collisions"] == 382
    with pytest.raises(StuckError, match="inelastic reflections.*tc") as err:
        sim.advance(events=1)
    assert err.value.reason == "sliding"
    cured = engine(m, r, x, v, container=c, restitution=0.8, wall_restitution=0.6, tc=1e-3)
    assert len(cured.advance(events=1500)) == 1500


def test_scan_learns_the_rule():
    c = SphericalContainer(9.0)
    m, r, x, v = _pair(c, 40, 0.25, seed=4)
    rule = dict(restitution=0.75, wall_restitution=0.5, tc=0.01)
    args = (m.tolist(), r.tolist(), x.tolist(), v.tolist())
    ref, scan = Reference(*args, container=c, **rule), Scan(*args, container=c, **rule)
    assert same_events(ref.advance(events=400), scan.advance(events=400))
    assert ref.dissipated == scan.dissipated > 0.0


@pytest.mark.parametrize(
    "rule,words",
    [
        (dict(restitution=0.0), "restitution must be in"),
        (dict(restitution=1.5), "restitution must be in"),
        (dict(restitution=math.nan), "restitution must be in"),
        (dict(restitution=0.9, wall_restitution=-1.0), "wall restitution must be in"),
        (dict(restitution=0.9, tc=-1.0), "tc must be"),
        (dict(restitution=0.9, tc=math.inf), "tc must be"),
    ],
)
@pytest.mark.parametrize("engine", [Engine, Reference], ids=["compiled", "reference"])
def test_bad_rules_are_refused(engine, rule, words):
    with pytest.raises(ArgumentError, match=words):
        engine([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=10.0, **rule)


@pytest.mark.parametrize("engine", [Engine, Reference], ids=["compiled", "reference"])
def test_no_growth_while_inelastic(engine):
    sim = engine([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=10.0, restitution=0.9)
    with pytest.raises(ArgumentError, match="grow"):
        sim.set_growth(0.1)


def test_kernels_at_e_one_are_the_elastic_ones_and_account_the_energy():
    """``collide_inelastic``/``reflect_inelastic`` at e = 1 give the elastic bits; their ``lost`` is the energy change."""
    rng = np.random.default_rng(0)
    for _ in range(2000):
        m1, m2 = np.exp(rng.uniform(-3, 3, 2))
        d = rng.normal(size=3) * np.exp(rng.uniform(-5, 5))
        dv = rng.normal(size=3) * np.exp(rng.uniform(-5, 5))
        if d @ dv >= 0:
            dv = -dv
        args = (float(m1), float(m2), *map(float, d), *map(float, dv))
        assert collide_inelastic(*args, 1.0)[:2] == collide(*args)
        assert reflect_inelastic(1.0, *map(float, d), *map(float, -dv), 1.0)[0] == reflect(*d, *-dv)
        e = float(rng.uniform(0.05, 1.0))
        k1, k2, lost = collide_inelastic(*args, e)
        v1, v2 = dv - k1 * d, k2 * d  # (v2 = 0 before)
        before = 0.5 * m1 * (dv @ dv)
        after = 0.5 * m1 * (v1 @ v1) + 0.5 * m2 * (v2 @ v2)
        assert abs(before - after - lost) <= 1e-13 * before
        vn = (v1 - v2) @ d / np.linalg.norm(d)
        scale = np.linalg.norm(dv)  # (a grazing pair's vn is a difference of larger numbers)
        assert abs(vn + e * (dv @ d) / np.linalg.norm(d)) <= 1e-12 * scale
        assert np.allclose(m1 * (dv - v1), m2 * v2, rtol=0, atol=1e-12 * m1 * scale)  # momentum


def test_scaled_time_overflows_to_inf():
    """A sphere nearly at rest meets the wall past the largest double: inf, as compiled (was OverflowError)."""
    assert scaled_time(3.0, 2) == 12.0 and scaled_time(1.0, 2000) == math.inf
    ref = Reference([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1e-300, 0.0, 0.0]], container=1e100)
    assert ref.step() is None and ref.idle


# ---- the API, the command and studies ------------------------------------------------------------


def _cooling_sim(n=300, e=0.8, d=3, seed=1):
    box = PeriodicBox.for_packing(n, 0.1, None if d == 3 else (1.0, 1.0))
    return hs.Simulation(hs.random_spheres(n, 0.1, box, seed=seed), box, restitution=e)


def test_simulation_cools_and_resumes_bit_for_bit(tmp_path):
    sim = _cooling_sim()
    obs = sim.observables
    sim.run(collisions=3000)
    assert (sim.restitution, sim.wall_restitution, sim.tc, sim.inelastic) == (0.8, 0.8, 0.0, True)
    assert obs.temperature() < 0.5 and sim.dissipated > 0.0
    assert abs(obs.energy_balance()) < 1e-12
    # per collision, Haff's law to first order (1 - e^2)/d = 0.12, within a few percent
    assert abs(obs.cooling_per_collision() / 0.12 - 1.0) < 0.1
    summary = obs.summary()
    assert "Z" not in summary and "pressure" not in summary  # (they divide by one kT)
    assert {"dissipated", "cooling_rate", "cooling_per_collision", "a2", "energy_balance"} <= set(summary)
    sim.save(tmp_path / "c.npz")
    back = hs.Simulation.load(tmp_path / "c.npz")
    assert (back.restitution, back.inelastic, back.dissipated) == (0.8, True, sim.dissipated)
    sim.run(collisions=2000)
    back.run(collisions=2000)
    assert np.array_equal(sim.state().velocities, back.state().velocities)
    assert sim.dissipated == back.dissipated


def test_simulation_rule_checks_and_set_restitution():
    box = PeriodicBox.for_packing(50, 0.1)
    state = hs.random_spheres(50, 0.1, box, seed=2)
    for bad in (dict(restitution=0.0), dict(restitution="x"), dict(wall_restitution=2.0), dict(tc=-1.0)):
        with pytest.raises(ArgumentError):
            hs.Simulation(state, box, **bad)
    sim = hs.Simulation(state, box)
    assert not sim.inelastic and sim.engine.rule == ()
    sim.run(collisions=200)
    sim.set_restitution(0.7, tc=1e-3)
    assert sim.inelastic and sim.engine.rule == ((),) and sim.tc == 1e-3
    sim.run(collisions=200)
    assert sim.dissipated > 0.0
    with pytest.raises(ArgumentError, match="grow"):
        sim.compress(packing=0.2)


def test_run_command_reports_the_energy_balance(tmp_path):
    (tmp_path / "g.txt").write_text(hs.random_spheres(200, 0.1, box=12.6, seed=3).to_text())
    r = hs_cmd(
        "run", "g.txt", "--box", "12.6", "--until", "5", "--restitution", "0.9",
        "--checkpoint", "g.npz", cwd=tmp_path, check=True,
    )  # fmt: skip
    assert "granular (restitution 0.9)" in r.stdout and "kinetic + dissipated energy drift" in r.stdout
    assert "Haff's law" in r.stdout and "a2 (velocity kurtosis)" in r.stdout
    assert "Z = PV/NkT" not in r.stdout
    again = hs_cmd("run", "--resume", "g.npz", "--until", "6", "--restitution", "0.5", cwd=tmp_path)
    assert again.returncode == 1 and "keeps its collision rule" in again.stderr
    bad = hs_cmd("run", "g.txt", "--box", "12.6", "--until", "5", "--restitution", "1.5", cwd=tmp_path)
    assert bad.returncode == 1 and "(0, 1]" in bad.stderr and "Traceback" not in bad.stderr


def test_a_study_with_restitution():
    from hardspheres.studies import parse_study
    from hardspheres.studies.task import _build, tasks

    plain = tasks(parse_study({"packing": 0.1, "n": 100, "output": "x"}))
    study = parse_study({"packing": 0.1, "n": 100, "output": "x", "restitution": [1.0, 0.9]})
    assert study["measure"] == ["cooling_per_collision", "a2"]
    ts = tasks(study)
    assert [t["restitution"] for t in ts] == [1.0, 0.9]
    assert "restitution" not in plain[0] and plain[0]["key"] not in {t["key"] for t in ts}
    assert _build(ts[1]).restitution == 0.9
    for bad in ({"restitution": 0.0}, {"restitution": 0.9, "measure": ["Z"]}):
        with pytest.raises(StudyError):
            parse_study({"packing": 0.1, "n": 100, **bad})
