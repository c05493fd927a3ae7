"""The thermal wall (a heated container) in the event core, against the brute-force reference, bit for bit.

A sphere meeting a thermal wall leaves it with a velocity drawn at the
wall's temperature (:func:`hardspheres.physics.thermal_wall`): the normal
speed from the flux-weighted distribution, the tangential velocity from the
Maxwellian.  The draws come from a counter-based generator, so the engine
and the reference (pure Python or compiled) draw the same numbers, and a
checkpoint resumes the sequence.  Compiled in the core's inelastic variant.
"""

import math

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.containers import CircularContainer, PeriodicBox, SphericalContainer
from hardspheres.core import _core as core
from hardspheres.core import checkpoint
from hardspheres.core import engine as engine_module
from hardspheres.core.engine import Engine
from hardspheres.core.reference import Reference
from hardspheres.errors import ArgumentError
from hardspheres.physics import mix32, thermal_wall, uniform_draw

from test_engine import CompiledReference, same_events
from test_reference_boxes import _pair

WALLS = {"sphere": SphericalContainer(9.0), "circle": CircularContainer(10.0)}
RULES = {
    "elastic spheres": dict(wall_temperature=2.0, wall_seed=5),
    "granular": dict(restitution=0.8, wall_temperature=0.5, wall_seed=9, tc=1e-3),
}


def _kinetic(m, v):
    return 0.5 * float(np.sum(np.asarray(m) * np.sum(np.asarray(v, dtype=float) ** 2, axis=1)))


@pytest.fixture(params=["cells", "lists"])
def mode(request, monkeypatch):
    """Cells, or neighbour lists whatever the density."""
    if request.param == "lists":
        monkeypatch.setattr(engine_module, "LISTS_FROM", 0.0)
        monkeypatch.setattr(engine_module, "LISTS_FROM_2D", 0.0)
    return request.param


@pytest.mark.parametrize("where", list(WALLS))
@pytest.mark.parametrize("rule", list(RULES))
@pytest.mark.parametrize("window", [0.0, 1e-8])
def test_thermal_wall_matches_the_reference(where, rule, window, mode):
    c = WALLS[where]
    m, r, x, v = _pair(c, 60, 0.25, seed=3, ratio=1.3)
    kw = dict(container=c, window=window, **RULES[rule])
    eng = Engine(m, r, x, v, rebase=False, reorder=0.0, **kw)
    ref = CompiledReference(m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), **kw)
    a, b = eng.advance(events=1500), ref.advance(events=1500)
    assert eng.rule == ((),) and (eng.scalars[core.F_SHELL] > 0.0) == (mode == "lists")
    assert same_events(a, b)
    n, d = eng.n, eng.dimensions
    assert np.array_equal(eng.velocities, np.asarray(ref.velocities, dtype=float).reshape(n, d))
    assert (eng.wall_heat, eng.dissipated, eng.wall_impulse) == (
        ref.wall_heat,
        ref.dissipated,
        ref.wall_impulse,
    )
    assert eng.counters["reflections"] == ref.counters["reflections"] == eng.counts[core.C_WALL_DRAWS] > 100


@pytest.mark.parametrize("where", list(WALLS))
def test_the_pure_python_reference_draws_the_same_bits(where):
    """The reference in Python (math's log, cos and sin) and the compiled core agree bit for bit."""
    c = WALLS[where]
    m, r, x, v = _pair(c, 20, 0.2, seed=4)
    kw = dict(container=c, wall_temperature=1.5, wall_seed=123)
    eng = Engine(m, r, x, v, rebase=False, reorder=0.0, **kw)
    ref = Reference(m, r, np.asarray(x).tolist(), np.asarray(v).tolist(), **kw)
    assert same_events(eng.advance(events=400), ref.advance(events=400))
    assert eng.wall_heat == ref.wall_heat != 0.0


def test_kernel_compiled_equals_python_and_draws_the_wall_distribution():
    """The compiled kernel's bits are Python's; the emitted speeds have the wall's moments.

    Normal speed ``c`` (density ``c / s^2 exp(-c^2 / 2 s^2)``): ``<c> = s sqrt(pi / 2)``,
    ``<c^2> = 2 s^2``; each tangential component: mean 0, variance ``s^2``.
    """
    kt, m = 2.0, 0.5
    s = math.sqrt(kt / m)
    rng = np.random.default_rng(1)
    normal, tangent = [], []
    for draw in range(20000):
        p = rng.normal(size=3)
        p *= 4.0 / np.linalg.norm(p)
        v = rng.normal(size=3)
        args = (m, *p, *v, kt, 77, draw)
        w = thermal_wall(*args)
        assert w == core.thermal_wall(*args)
        n = p / 4.0
        wv = np.array(w[:3])
        normal.append(-wv @ n)
        t = wv - (wv @ n) * n
        tangent.append(t @ np.cross(n, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(n, [0.0, 0.0, 1.0])))
        assert w[3] == pytest.approx(m * (v @ n + normal[-1]), rel=1e-12)
        assert w[4] == pytest.approx(0.5 * m * (wv @ wv - v @ v), rel=1e-9, abs=1e-12)
    c, t = np.array(normal), np.array(tangent)
    assert np.all(c > 0.0)
    err = 4.0 / math.sqrt(len(c))  # (four standard errors, in units of the moments' spread)
    assert abs(c.mean() / (s * math.sqrt(math.pi / 2)) - 1.0) < err * 0.53
    assert abs(np.mean(c**2) / (2 * s * s) - 1.0) < err * 1.0
    assert abs(t.mean() / s) < err and abs(np.var(t) / (s * s) - 1.0) < err * 1.42


def test_uniform_draws_are_open_and_mixed():
    assert mix32(0) == 0 and 0 <= mix32(2**32 - 1) < 2**32
    u = np.array([[uniform_draw(7, d, k) for k in range(5)] for d in range(4000)])
    assert np.all((u > 0.0) & (u < 1.0))
    assert abs(u.mean() - 0.5) < 4 * 0.289 / math.sqrt(u.size)
    assert np.max(np.abs(np.corrcoef(u.T) - np.eye(5))) < 4 / math.sqrt(4000)
    assert uniform_draw(7, 2**40 + 3, 0) != uniform_draw(7, 3, 0)  # (the high word counts)
    assert uniform_draw(8, 3, 0) != uniform_draw(7, 3, 0)


@pytest.mark.parametrize("where", list(WALLS))
def test_energy_is_accounted_to_rounding(where):
    """Kinetic energy = initial - dissipated + the wall's heat, to rounding."""
    c = WALLS[where]
    m, r, x, v = _pair(c, 100, 0.3, seed=11, ratio=1.2)
    eng = Engine(m, r, x, v, container=c, restitution=0.7, wall_temperature=0.3, wall_seed=1)
    e0 = _kinetic(m, v)
    eng.advance(events=20000)
    assert eng.wall_heat > 0.0 and eng.dissipated > 0.0
    scale = e0 + eng.dissipated
    assert abs(eng.kinetic_energy() - (e0 - eng.dissipated + eng.wall_heat)) <= 1e-12 * scale
    assert eng.max_overlap() < 1e-9


@pytest.mark.parametrize("where", list(WALLS))
def test_elastic_spheres_relax_to_the_wall_temperature(where):
    """Elastic spheres between thermal walls: the kinetic temperature is the wall's (seed fixed).

    From kT = 0.25 towards kT_w = 1: over the second half of the run the
    mean kT is within 3% of 1 (its block error here is under 1%).
    """
    c = WALLS[where]
    m, r, x, v = _pair(c, 80, 0.05, seed=2)
    v = 0.5 * np.asarray(v) / math.sqrt(2.0 * _kinetic(m, v) / (len(m) * c.dimensions))
    sim = hs.Simulation.from_arrays(m, r, x, v, c).set_wall_temperature(1.0, seed=4)
    temps = []
    for k in range(200):
        sim.run(events=400)
        if k >= 100:
            temps.append(2.0 * sim.engine.kinetic_energy() / (sim.engine.n * c.dimensions))
    assert abs(np.mean(temps) - 1.0) < 0.03
    assert sim.observables.summary()["energy_balance"] == pytest.approx(0.0, abs=1e-12)


def test_zero_wall_temperature_keeps_the_elastic_bits():
    c = WALLS["sphere"]
    m, r, x, v = _pair(c, 60, 0.3, seed=7)
    plain, off = (
        Engine(m, r, x, v, container=c),
        Engine(m, r, x, v, container=c, wall_temperature=0.0, wall_seed=3),
    )
    assert plain.rule == off.rule == () and not off.inelastic
    assert same_events(plain.advance(events=2000), off.advance(events=2000))


def test_checkpoint_resumes_the_draws_bit_for_bit(tmp_path):
    c = WALLS["circle"]
    m, r, x, v = _pair(c, 50, 0.3, seed=13)
    a = Engine(m, r, x, v, container=c, restitution=0.9, wall_temperature=1.5, wall_seed=77)
    a.advance(events=3000)
    b = Engine.restore({k: np.copy(w) for k, w in a.checkpoint().items()})
    assert (b.wall_temperature, b.counts[core.C_WALL_SEED], b.rule) == (1.5, 77, ((),))
    assert same_events(a.advance(events=3000), b.advance(events=3000))
    assert np.array_equal(a.velocities, b.velocities) and a.wall_heat == b.wall_heat
    # through a Simulation's file
    sim = hs.Simulation.from_arrays(m, r, x, v, c).set_wall_temperature(0.7, seed=5)
    sim.run(events=1000)
    sim.save(tmp_path / "c.npz")
    again = hs.Simulation.load(tmp_path / "c.npz")
    assert again.wall_temperature == 0.7 and again.wall_heat == sim.wall_heat
    sim.run(events=1000)
    again.run(events=1000)
    assert np.array_equal(sim.engine.velocities, again.engine.velocities)


def test_an_older_checkpoint_has_no_thermal_wall():
    """A version-3 layout (no wall temperature, no generator) restores without a thermal wall."""
    c = WALLS["sphere"]
    m, r, x, v = _pair(c, 30, 0.2, seed=2)
    a = Engine(m, r, x, v, container=c, restitution=0.9)
    a.advance(events=500)
    old = {k: np.copy(w) for k, w in a.checkpoint().items()}
    old["scalars"], old["counts"] = old["scalars"][: core.F_WALL_KT], old["counts"][: core.C_WALL_SEED]
    b = Engine.restore(old)
    assert (b.wall_temperature, b.wall_heat, b.restitution) == (0.0, 0.0, 0.9)
    assert same_events(a.advance(events=500), b.advance(events=500))


@pytest.mark.parametrize("damage", ["temperature", "seed", "draws"])
def test_a_damaged_thermal_wall_in_a_checkpoint_is_refused(damage):
    c = WALLS["sphere"]
    m, r, x, v = _pair(c, 30, 0.2, seed=2)
    bad = {
        k: np.copy(w) for k, w in Engine(m, r, x, v, container=c, wall_temperature=1.0).checkpoint().items()
    }
    if damage == "temperature":
        bad["scalars"][core.F_WALL_KT] = -1.0
    elif damage == "seed":
        bad["counts"][core.C_WALL_SEED] = 2**32
    else:
        bad["counts"][core.C_WALL_DRAWS] = -1
    with pytest.raises(checkpoint.CheckpointError, match="damaged checkpoint"):
        Engine.restore(bad)


@pytest.mark.parametrize("engine", [Engine, Reference], ids=["compiled", "reference"])
@pytest.mark.parametrize(
    "rule, words",
    [
        (dict(wall_temperature=-1.0), "wall temperature must be"),
        (dict(wall_temperature=math.inf), "wall temperature must be"),
        (dict(wall_temperature=1.0, wall_seed=2**32), "wall seed must be"),
        (dict(wall_temperature=1.0, wall_seed=-1), "wall seed must be"),
    ],
)
def test_bad_thermal_walls_are_refused(engine, rule, words):
    with pytest.raises(ArgumentError, match=words):
        engine([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], container=10.0, **rule)


@pytest.mark.parametrize("engine", [Engine, Reference], ids=["compiled", "reference"])
def test_a_box_has_no_wall_to_heat(engine):
    with pytest.raises(ArgumentError, match="needs a wall"):
        engine([1.0], [1.0], [[0.0, 0.0, 0.0]], [[1.0, 0.0, 0.0]], box=10.0, wall_temperature=1.0)


def test_simulation_refuses_bad_input_and_growth():
    box = SphericalContainer(12.0)
    sim = hs.Simulation(hs.random_spheres(20, 0.05, box, seed=1), box)
    with pytest.raises(ValueError, match="wall temperature must be"):
        sim.set_wall_temperature(-2.0)
    with pytest.raises(ValueError, match="wall seed must be"):
        sim.set_wall_temperature(1.0, seed=-3)
    sim.set_wall_temperature(1.0)
    with pytest.raises(ArgumentError, match="grow"):
        sim.engine.set_growth(0.1)
    periodic = hs.Simulation(hs.random_spheres(20, 0.05, PeriodicBox(20.0), seed=1), PeriodicBox(20.0))
    with pytest.raises(ValueError, match="needs a wall"):
        periodic.set_wall_temperature(1.0)


def test_run_command_heats_the_wall_and_resumes(tmp_path):
    from helpers import hs_cmd

    box = SphericalContainer(10.0)
    (tmp_path / "g.txt").write_text(hs.random_spheres(100, 0.1, box, seed=3, kT=0.25).to_text())
    args = ("run", "g.txt", "--container", "10", "--until", "20", "--restitution", "0.9")
    r = hs_cmd(*args, "--wall-temperature", "1", "--checkpoint", "g.npz", cwd=tmp_path, check=True)
    assert "thermal wall kT_w 1" in r.stdout and "kinetic + dissipated - injected energy drift" in r.stdout
    assert "heated by a thermal wall at kT_w 1" in r.stdout and "a2" not in r.stdout
    again = hs_cmd("run", "--resume", "g.npz", "--until", "30", cwd=tmp_path, check=True)
    assert "heated by a thermal wall at kT_w 1" in again.stdout
    for extra, words in [
        (("--wall-seed", "4294967296", "--wall-temperature", "1"), "--wall-seed 4294967296"),
        (("--wall-seed", "3"), "give --wall-temperature"),
        (("--wall-temperature", "0"), "--wall-temperature"),
        (("--wall-temperature", "1", "--wall-restitution", "0.5"), "leave out --wall-restitution"),
    ]:
        bad = hs_cmd(*args, *extra, cwd=tmp_path)
        assert bad.returncode == 1 and words in bad.stderr and "Traceback" not in bad.stderr, extra
        assert bad.stdout == ""
    boxed = hs_cmd("run", "g.txt", "--box", "40", "--until", "5", "--wall-temperature", "1", cwd=tmp_path)
    assert boxed.returncode == 1 and "a periodic box has none" in boxed.stderr
    resumed = hs_cmd("run", "--resume", "g.npz", "--until", "40", "--wall-temperature", "2", cwd=tmp_path)
    assert resumed.returncode == 1 and "keeps its" in resumed.stderr
