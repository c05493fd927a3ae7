"""Dense matter: growth (Lubachevsky-Stillinger) in the event core, compress, thermostats."""

import math

import numpy as np
import pytest
from helpers import spheres_cmd
from hypothesis import given, settings
from hypothesis import strategies as st

import hardspheres as hs
from hardspheres import physics
from hardspheres.core import _core as core
from hardspheres.core.engine import Engine
from hardspheres.dense import Andersen, CompressionError, VelocityRescale

TOL = 1e-9


# ---- kernels against hand-solved cases -------------------------------------------


def test_pair_time_grow_head_on_and_at_rest():
    # closing at 1, contact distance 2 growing at 1: 10 = 2 + 2 t
    assert physics.pair_time_grow(-10.0, 0, 0, 1.0, 0, 0, 2.0, 1.0, math.inf) == 4.0
    # at rest, 3 apart, contact 1 growing at 0.5: 1 + 0.5 t = 3
    assert physics.pair_time_grow(3.0, 0, 0, 0.0, 0, 0, 1.0, 0.5, math.inf) == 4.0
    # receding at 1 while the contact grows at 2: caught up at 5 + t = 1 + 2 t
    assert physics.pair_time_grow(5.0, 0, 0, 1.0, 0, 0, 1.0, 2.0, math.inf) == 4.0
    # receding faster than the growth: never
    assert physics.pair_time_grow(5.0, 0, 0, 3.0, 0, 0, 1.0, 2.0, math.inf) == math.inf


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=6, max_size=6), st.floats(0.1, 1.0), st.floats(0.0, 2.0))
def test_pair_time_grow_is_a_contact(v, s, u):
    dr = np.array(v[:3]) + np.sign(np.array(v[:3]) + 1e-3) * 2.0  # at least 2 apart
    dv = np.array(v[3:])
    t = physics.pair_time_grow(*dr, *dv, s, u, math.inf)
    if t == math.inf:
        # never: the distance stays above the contact at sample times
        for tt in np.linspace(0, 50, 501):
            assert np.linalg.norm(dr + tt * dv) >= (s + u * tt) * (1 - 1e-9)
        return
    gap = np.linalg.norm(dr + t * dv) - (s + u * t)
    assert abs(gap) <= 1e-9 * (np.linalg.norm(dr) + s + (np.linalg.norm(dv) + u) * t)
    for tt in np.linspace(0, t, 50)[:-1]:
        assert np.linalg.norm(dr + tt * dv) >= (s + u * tt) * (1 - 1e-9)


def test_pair_time_grow_without_growth_is_pair_time():
    rng = np.random.default_rng(3)
    for _ in range(500):
        dr = rng.normal(size=3) * 5
        dv = rng.normal(size=3)
        t0 = physics.pair_time(*dr, *dv, 1.0)
        t1 = physics.pair_time_grow(*dr, *dv, 1.0, 0.0, math.inf)
        assert (t0 == t1 == math.inf) or abs(t0 - t1) <= 1e-12 * max(1.0, t0)


@settings(max_examples=400, deadline=None)
@given(
    st.lists(st.floats(-4, 4), min_size=6, max_size=6),
    st.floats(0.05, 1.0),
    st.floats(0.0, 1.0),
    st.integers(-30, 30),
)
def test_pair_time_grow_rejects_only_exact_misses(v, s, u, e):
    """The kernel's sure-miss test (before its discriminant) fires only where the exact one is < 0.

    Near-grazing pairs at scales 2^-30..2^30: a pair it calls a miss has a
    negative discriminant in exact rationals; a pair with a positive one
    that closes within the horizon gets a finite time.
    """
    from fractions import Fraction as F

    k = 2.0**e
    dr = [(x + (2.0 if x >= 0 else -2.0)) * k for x in v[:3]]  # at least 2 apart (times k)
    dv = list(v[3:])
    s, u = s * k, u
    t = physics.pair_time_grow(*dr, *dv, s, u, math.inf)
    R = [F(x) for x in dr]
    V = [F(x) for x in dv]
    a = sum(x * x for x in V) - F(u) ** 2
    b = sum(x * y for x, y in zip(R, V)) - F(s) * F(u)
    c = sum(x * x for x in R) - F(s) ** 2
    disc = b * b - a * c
    bound = (sum(x * x for x in V) + F(u) ** 2) * (sum(x * x for x in R) + F(s) ** 2)
    if a >= 0 and b < 0 and disc > F(1e-12) * bound:
        assert t < math.inf  # they meet: not rejected
    if t == math.inf and a >= 0 and b < 0:
        assert disc <= F(1e-12) * bound


def test_growth_headroom_follows_the_rate():
    """Room to grow: 1 without growth, small for slow growth, at most HEADROOM_MAX for fast."""
    import hardspheres.core.engine as engine_mod

    state = hs.random_spheres(200, 0.3, box=12.0, seed=1)
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, box=12.0)
    assert eng._headroom() == 1.0
    rooms = []
    for rate in (1e-9, 1e-5, 1e-4, 10.0):
        eng.set_growth(rate)
        rooms.append(eng._headroom())
        assert eng.scalars[core.F_HEADROOM] == rooms[-1]
    assert rooms[0] == engine_mod.HEADROOM_MIN and rooms[-1] == engine_mod.HEADROOM_MAX
    assert rooms == sorted(rooms) and rooms[1] < rooms[2] < engine_mod.HEADROOM_MAX


def test_wall_time_grow():
    # at rest at the centre: reach 10 closes at 2 -> 5
    assert physics.wall_time_grow(0, 0, 0, 0, 0, 0, 10.0, 2.0) == 5.0
    # outward at 1, wall closing at 1: 10 - t = t
    assert physics.wall_time_grow(0, 0, 0, 1.0, 0, 0, 10.0, 1.0) == 5.0
    # without growth it is wall_time
    assert physics.wall_time_grow(1.0, 2.0, 0, 0.3, -1.0, 0.5, 9.0, 0.0) == pytest.approx(
        physics.wall_time(1.0, 2.0, 0, 0.3, -1.0, 0.5, 9.0), rel=1e-14
    )


@settings(max_examples=200, deadline=None)
@given(st.floats(0.1, 5), st.floats(0.1, 5), st.floats(-3, 3), st.floats(-3, 3), st.floats(0.0, 2.0))
def test_ls_rule_parts_faster_than_growth(m1, m2, vx, vy, u):
    dr = np.array([-1.0, 0.3, 0.2])
    dr *= 2.0 / np.linalg.norm(dr)
    dv = np.array([vx, vy, 0.5])
    n = dr / np.linalg.norm(dr)
    vn = dv @ n
    k1, k2 = physics.collide_grow(m1, m2, *dr, *dv, u)
    dv2 = dv - (k1 + k2) * dr
    scale = np.linalg.norm(dv) + u
    if vn < u - 1e-12 * scale:  # closing by more than rounding
        assert dv2 @ n > u
        assert dv2 @ n - u == pytest.approx(u - vn, rel=1e-9, abs=1e-12)
    # momentum is conserved
    p1 = m1 * (-k1 * dr) + m2 * (k2 * dr)
    assert np.allclose(p1, 0.0, atol=1e-12)


def test_reflect_grow_inward_faster_than_wall():
    k = physics.reflect_grow(5.0, 0.0, 0.0, 2.0, 1.0, 0.0, 1.0)
    v = np.array([2.0, 1.0, 0.0]) - k * np.array([5.0, 0.0, 0.0])
    assert v[0] == pytest.approx(-4.0) and v[1] == 1.0  # -(2 + 2*1)


# ---- growth in the engine: never an overlap ----------------------------------------


def _grow_and_check(state, box=None, container=None, rate=0.02, chunks=8, per=300):
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, box=box, container=container)
    r0 = eng.radii_at().copy()
    eng.set_growth(rate)
    for _ in range(chunks):
        ev = eng.advance(collisions=per)
        assert eng.max_overlap() <= TOL and eng.outside() == 0
        # and at a time between events
        if len(ev["time"]) > 1:
            tm = 0.5 * (ev["time"][-2] + ev["time"][-1])
            if tm > eng.time:
                assert eng.max_overlap(tm) <= TOL
    r1 = eng.radii_at()
    assert np.all(r1 > r0)
    assert np.allclose(r1 / r0, r1[0] / r0[0], rtol=1e-12)  # in proportion
    return eng


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([1.0, 1.4]), st.floats(0.005, 0.2))
def test_growth_never_overlaps_box(seed, ratio, rate):
    state = hs.random_spheres(60, 0.15, box=8.0, seed=seed, radius_ratio=ratio, mass_ratio=2.0)
    _grow_and_check(state, box=8.0, rate=rate)


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([1.0, 1.4]), st.floats(0.005, 0.2))
def test_growth_never_overlaps_container(seed, ratio, rate):
    state = hs.random_spheres(60, 0.15, container=6.0, seed=seed, radius_ratio=ratio, mass_ratio=2.0)
    _grow_and_check(state, container=6.0, rate=rate)


def test_growth_outgrows_cells_and_regrids():
    state = hs.random_spheres(300, 0.1, box=20.0, seed=1)
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, box=20.0)
    nc0 = int(eng.counts[core.C_CELLS])
    eng.set_growth(0.2)
    eng.advance(collisions=20_000)
    assert int(eng.counts[core.C_CELLS]) < nc0
    assert eng.max_overlap() <= TOL


def test_exact_restart_mid_growth():
    state = hs.random_spheres(100, 0.3, container=6.0, seed=4, radius_ratio=1.4)
    a = Engine(state.masses, state.radii, state.positions, state.velocities, container=6.0)
    a.set_growth(0.05)
    a.advance(collisions=2000)
    b = Engine.restore({k: np.copy(v) for k, v in a.checkpoint().items()})
    ea = a.advance(collisions=3000)
    eb = b.advance(collisions=3000)
    for k in ea.dtype.names:
        assert np.array_equal(ea[k], eb[k])
    assert np.array_equal(a.spheres, b.spheres) and a.time == b.time


# ---- compress ---------------------------------------------------------------------


def test_compress_reaches_packing_and_keeps_kT():
    sim = hs.Simulation(hs.random_spheres(200, 0.3, box=10.0, seed=1), hs.PeriodicBox(10.0))
    kT = sim.observables.temperature()
    seen = []
    res = sim.compress(packing=0.5, rate=0.02, progress=lambda p, z, c: seen.append(p))
    assert res.reason == "packing" and not res.jammed
    assert res.packing == pytest.approx(0.5, rel=1e-12)
    assert sim.packing == pytest.approx(0.5, rel=1e-12)
    assert sim.observables.temperature() == pytest.approx(kT, rel=1e-12)  # rescaled
    assert seen == sorted(seen)
    assert sim._engine.max_overlap() <= TOL
    # the compressed scenario runs as any other (NVE: energy conserved)
    e0 = sim.state().kinetic_energy()
    sim.run(collisions=2000)
    assert sim.state().kinetic_energy() == pytest.approx(e0, rel=1e-12)


def test_compress_mixture_in_container_keeps_ratios():
    state = hs.random_spheres(150, 0.25, container=7.0, seed=2, radius_ratio=1.4)
    sim = hs.Simulation(state, hs.SphericalContainer(7.0))
    res = sim.compress(packing=0.4, rate=0.02)
    assert res.reason == "packing"
    r = sim.state().radii
    assert np.allclose(r / state.radii, r[0] / state.radii[0], rtol=1e-12)
    assert sim._engine.outside() == 0 and sim._engine.max_overlap() <= TOL


def test_fast_compression_jams_and_reports_it():
    sim = hs.Simulation(hs.random_spheres(200, 0.4, box=8.0, seed=3), hs.PeriodicBox(8.0))
    res = sim.compress(packing=0.74, rate=0.1, pressure=300.0)
    assert res.jammed and res.reason == "pressure" and res.pressure >= 300.0
    assert 0.55 < res.packing < 0.66
    assert sim._engine.max_overlap() <= TOL


def test_compress_collision_limit():
    sim = hs.Simulation(hs.random_spheres(100, 0.3, box=8.0, seed=3), hs.PeriodicBox(8.0))
    res = sim.compress(collisions=1000, rate=0.01, pressure=None)
    assert res.reason == "collisions" and 1000 <= res.collisions < 1400


@pytest.mark.parametrize(
    "kw, word",
    [
        ({"packing": 0.75}, "0.7405"),
        ({"packing": 0.2}, "present"),
        ({"packing": 0.5, "rate": 0.0}, "rate"),
        ({"packing": 0.5, "rate": -1.0}, "rate"),
        ({"packing": float("nan")}, "packing"),
        ({"packing": None, "pressure": None}, "give packing"),
    ],
)
def test_compress_bad_input(kw, word):
    sim = hs.Simulation(hs.random_spheres(50, 0.3, box=6.0, seed=1), hs.PeriodicBox(6.0))
    with pytest.raises(CompressionError, match=word):
        sim.compress(**{"rate": 0.01, **kw})


def test_compress_refused_with_window():
    state = hs.random_spheres(20, 0.1, container=5.0, seed=1)
    sim = hs.Simulation(state, hs.SphericalContainer(5.0), window=1e-8)
    with pytest.raises(CompressionError, match="window"):
        sim.compress(packing=0.2, rate=0.01)
    with pytest.raises(ValueError, match="window"):
        sim.set_thermostat(Andersen(1.0, 0.1))


def test_compress_restart_mid_compression_via_engine_checkpoint(tmp_path):
    sim = hs.Simulation(hs.random_spheres(100, 0.3, box=8.0, seed=5), hs.PeriodicBox(8.0))
    sim._engine.set_growth(0.02)
    sim.run(collisions=1500)
    sim.save(tmp_path / "c.npz")
    other = hs.Simulation.load(tmp_path / "c.npz")
    sim.run(collisions=1500)
    other.run(collisions=1500)
    assert np.array_equal(sim._engine.spheres, other._engine.spheres)
    assert sim.packing == other.packing > 0.3


# ---- thermostats ------------------------------------------------------------------


def test_andersen_reproducible_and_resumes_bit_for_bit(tmp_path):
    def make():
        sim = hs.Simulation(hs.random_spheres(100, 0.3, box=8.0, seed=7, kT=3.0), hs.PeriodicBox(8.0))
        return sim.set_thermostat(Andersen(kT=1.0, rate=0.5, seed=11))

    a, b = make(), make()
    a.run(until=2.0)
    b.run(until=2.0)
    assert np.array_equal(a._engine.spheres, b._engine.spheres)
    a.save(tmp_path / "a.npz")
    c = hs.Simulation.load(tmp_path / "a.npz")
    a.run(until=4.0)
    c.run(until=4.0)
    assert np.array_equal(a._engine.spheres, c._engine.spheres)
    assert a.thermostat.resampled == c.thermostat.resampled > 100


def test_andersen_brings_kT_to_target():
    sim = hs.Simulation(hs.random_spheres(300, 0.3, box=11.0, seed=7, kT=4.0), hs.PeriodicBox(11.0))
    sim.set_thermostat(Andersen(kT=1.0, rate=1.0, seed=1))
    sim.run(until=10.0)  # ~3000 resamplings: 10 per sphere
    kts = []
    for k in range(10):
        sim.run(until=10.0 + k)
        kts.append(sim.observables.temperature())
    assert np.mean(kts) == pytest.approx(1.0, abs=0.06)


def test_velocity_rescale_sets_energy():
    sim = hs.Simulation(hs.random_spheres(100, 0.3, box=8.0, seed=7, kT=2.0), hs.PeriodicBox(8.0))
    sim.set_thermostat(VelocityRescale(kT=1.0, interval=0.5))
    sim.run(until=0.5)
    assert sim.observables.temperature() == pytest.approx(1.0, rel=1e-12)
    assert sim._engine.max_overlap() <= TOL


def test_no_thermostat_no_growth_is_nve():
    state = hs.random_spheres(100, 0.3, box=8.0, seed=7)
    a = hs.Simulation(state, hs.PeriodicBox(8.0))
    b = hs.Simulation(state, hs.PeriodicBox(8.0)).set_thermostat(None)
    a.run(collisions=3000)
    b.run(collisions=3000)
    assert np.array_equal(a._engine.spheres, b._engine.spheres)


# ---- the command line and README ------------------------------------------------------


def test_assignment_program_refuses_thermostats():
    res = spheres_cmd("10", "5", "--thermostat", "andersen", input="1 1 0 0 0 1 0 0 a\n")
    assert res.returncode == 1
    assert "--thermostat" in res.stderr and len(res.stderr.strip().splitlines()) == 1


def test_compress_command(tmp_path):
    from hardspheres.cli.commands import main

    scn = tmp_path / "a.txt"
    state = hs.random_spheres(150, 0.3, box=10.0, seed=2)
    scn.write_text(state.to_text())
    out = tmp_path / "d.txt"

    def compress(*args):
        return main(["compress", str(scn), "--box", "10", *map(str, args)])

    assert compress("--packing", 0.45, "--rate", 0.02, "-o", out, "--checkpoint", tmp_path / "c.npz") == 0
    sim = hs.Simulation.from_scenario(str(out), hs.PeriodicBox(10.0))
    assert sim.packing == pytest.approx(0.45, rel=1e-9)
    assert [s.split()[-1] for s in out.read_text().splitlines()] == state.names
    assert hs.Simulation.load(tmp_path / "c.npz").packing == pytest.approx(0.45, rel=1e-9)
    # jammed: reported, not an error
    assert compress("--packing", 0.7, "--rate", 0.3, "--pressure", 200, "-o", out) == 0
    # bad input: one line naming the option, status 1
    assert compress("--packing", 0.75, "--rate", 0.02, "-o", out) == 1
    assert compress("--packing", 0.2, "--rate", 0.02, "-o", out) == 1


def test_generate_method_compress(tmp_path, capsys):
    from hardspheres.cli.commands import main

    assert (
        main(
            [
                "generate",
                "--n",
                "200",
                "--box",
                "10",
                "--packing",
                "0.5",
                "--method",
                "compress",
                "--radius-ratio",
                "1.4",
                "--seed",
                "3",
            ]
        )
        == 0
    )
    text = capsys.readouterr().out
    (tmp_path / "g.txt").write_text(text)
    sim = hs.Simulation.from_scenario(str(tmp_path / "g.txt"), hs.PeriodicBox(10.0))
    assert sim.n == 200 and sim.packing == pytest.approx(0.5, rel=1e-9)


def test_readme_dense_section_runs(tmp_path, monkeypatch):
    import re
    import subprocess
    from pathlib import Path

    # README's Dense matter section moved to the user guide's page
    sec = (Path(__file__).resolve().parents[1] / "docs" / "guide" / "dense.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", sec, re.DOTALL)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    jam = (
        blocks[0]
        .replace("1000, 0.3, box=18.0", "200, 0.3, box=10.5")
        .replace("PeriodicBox(18.0)", "PeriodicBox(10.5)")
    )
    exec(compile(jam, "README.md", "exec"), {})
    xtal = blocks[1].replace("2_000_000", "20_000")
    exec(compile(xtal, "README.md", "exec"), {})
    cmds = re.search(r"```sh\n(.*?)```", sec, re.DOTALL).group(1)
    for line in cmds.strip().splitlines():
        line = line.replace("--n 1000", "--n 200")
        res = subprocess.run(line, shell=True, cwd=tmp_path, capture_output=True, text=True)
        assert res.returncode == 0, (line, res.stderr)


# ---- the engine while growing against a brute-force loop ---------------------------------


def _brute_force_growth(m, r0, x, v, container, h, n_events):
    """All pairs and walls each step, everything at one common time (no cells)."""
    x, v = x.copy(), v.copy()
    n, t, out = len(m), 0.0, []
    for _ in range(n_events):
        best, what = math.inf, None
        for i in range(n):
            reach = container - r0[i] * (1.0 + h * t)
            dt = physics.wall_time_grow(*x[i], *v[i], reach, r0[i] * h)
            if dt < best:
                best, what = dt, (0, i, -1)
            for j in range(i + 1, n):
                s0 = r0[i] + r0[j]
                dt = physics.pair_time_grow(
                    *(x[i] - x[j]), *(v[i] - v[j]), s0 * (1.0 + h * t), s0 * h, math.inf
                )
                if dt < best:
                    best, what = dt, (1, i, j)
        x += v * best
        t += best
        kind, i, j = what
        if kind == 1:
            k1, k2 = physics.collide_grow(m[i], m[j], *(x[i] - x[j]), *(v[i] - v[j]), (r0[i] + r0[j]) * h)
            d = x[i] - x[j]
            v[i] -= k1 * d
            v[j] += k2 * d
        else:
            v[i] -= physics.reflect_grow(*x[i], *v[i], r0[i] * h) * x[i]
        out.append((t, kind, i, j))
    return out


@pytest.mark.parametrize("seed", [1, 2])
def test_growing_engine_matches_brute_force(seed):
    state = hs.random_spheres(16, 0.08, container=5.0, seed=seed, radius_ratio=1.4, mass_ratio=3.0)
    h = 0.08
    eng = Engine(state.masses, state.radii, state.positions, state.velocities, container=5.0)
    eng.set_growth(h)
    ev = eng.advance(events=120)
    ref = _brute_force_growth(state.masses, state.radii, state.positions, state.velocities, 5.0, h, 120)
    assert len(ev["time"]) == 120
    for k, (t, kind, i, j) in enumerate(ref):
        assert (ev["kind"][k], ev["i"][k], ev["j"][k]) == (kind, i, j), k
        assert ev["time"][k] == pytest.approx(t, rel=1e-9), k
    # the radii grew by 1 + h t
    assert np.allclose(eng.radii_at(), state.radii * (1.0 + h * eng.time), rtol=1e-12)


# ---- progress (packing and Z on stderr) ------------------------------------------------


def test_compression_progress_shows_packing_and_Z():
    import io

    from hardspheres.cli.compress import compression_progress

    sim = hs.Simulation(hs.random_spheres(200, 0.3, box=10.0, seed=1), hs.PeriodicBox(10.0))
    buf = io.StringIO()
    bar, show = compression_progress(sim.packing, 0.45, stream=buf, enabled=True)
    sim.compress(packing=0.45, rate=0.02, progress=show)
    bar.close()
    text = buf.getvalue()
    assert "packing 0.45000" in text and "  Z " in text and "100.0%" in text
    assert "collisions/s" in text and text.endswith("\r")  # the line is cleared at the end
    # without a target packing, the bar follows log Z towards the pressure threshold
    buf = io.StringIO()
    bar, show = compression_progress(0.3, None, 1e3, stream=buf, enabled=True)
    show(0.6, 1e3**0.5, 10)
    assert "50.0%" in buf.getvalue()


def test_generate_method_compress_shows_progress(monkeypatch, capsys):
    import io

    from hardspheres.cli import compress
    from hardspheres.cli.commands import main

    buf = io.StringIO()
    real = compress.compression_progress
    monkeypatch.setattr(compress, "compression_progress", lambda *a, **k: real(*a, stream=buf, enabled=True))
    argv = ["generate", "--n", "100", "--box", "8", "--packing", "0.45", "--method", "compress"]
    assert main(argv + ["--rate", "0.05"]) == 0
    assert "packing 0.45000" in buf.getvalue() and "  Z " in buf.getvalue()
    assert len(capsys.readouterr().out.splitlines()) == 100  # the scenario, on stdout only


def test_readme_dense_pictures_are_made_by_make_sh():
    """README's dense picture commands (the viewer coloured by q6) are make.sh's, verbatim."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    sec = (root / "docs" / "guide" / "dense.md").read_text()  # README's section, moved
    blocks = re.findall(r"```sh\n(.*?)```", sec, re.DOTALL)
    pictures = [b for b in blocks if "--color q6" in b]
    assert len(pictures) == 1
    script = (root / "docs" / "images" / "make.sh").read_text()
    marked = script[script.index("# ---- dense picture commands") : script.index("# ---- end of dense")]
    lines = pictures[0].strip().splitlines()
    assert lines == [x for x in marked.splitlines()[1:] if x.strip()]
    for png in ("jammed_q6.png", "crystal_q6.png"):
        assert f"--screenshot {png}" in pictures[0] and f"(../images/{png})" in sec
        assert (root / "docs" / "images" / png).stat().st_size < 320_000


@settings(max_examples=8, deadline=None)
@given(
    st.integers(0, 10_000),
    st.booleans(),
    st.sampled_from([1.0, 1.4]),
    st.sampled_from([1.0, 3.0]),
    st.floats(0.2, 5.0),
    st.floats(0.005, 0.1),
)
def test_energy_after_rescale_is_the_target(seed, periodic, ratio, mass_ratio, kT, rate):
    """compress keeps kT; VelocityRescale sets it: both geometries, mixtures, unequal masses."""
    kw = {"box": 8.0} if periodic else {"container": 6.0}
    state = hs.random_spheres(60, 0.2, seed=seed, radius_ratio=ratio, mass_ratio=mass_ratio, kT=kT, **kw)
    sim = hs.Simulation(state, hs.PeriodicBox(8.0) if periodic else hs.SphericalContainer(6.0))
    kt0 = sim.observables.temperature()
    res = sim.compress(packing=0.3, rate=rate)
    assert res.reason == "packing" and sim.observables.temperature() == pytest.approx(kt0, rel=1e-12)
    assert sim._engine.max_overlap() <= TOL and sim._engine.outside() == 0
    sim.set_thermostat(VelocityRescale(kT=1.0, interval=0.25))
    sim.run(until=sim.time + 0.25)
    assert sim.observables.temperature() == pytest.approx(1.0, rel=1e-12)


def test_compression_resumed_from_a_checkpoint_is_the_same_run(tmp_path):
    """compress in two legs with a checkpoint between: the resumed copy ends bit for bit alike."""
    sim = hs.Simulation(
        hs.random_spheres(120, 0.3, container=7.0, seed=6, radius_ratio=1.4), hs.SphericalContainer(7.0)
    )
    first = sim.compress(collisions=3000, rate=0.02, pressure=None)
    assert first.reason == "collisions"
    sim.save(tmp_path / "mid.npz")
    other = hs.Simulation.load(tmp_path / "mid.npz")
    a = sim.compress(packing=0.45, rate=0.02)
    b = other.compress(packing=0.45, rate=0.02)
    assert a == b and a.reason == "packing"
    assert np.array_equal(sim._engine.spheres, other._engine.spheres) and sim.time == other.time


def test_thermostat_is_not_a_writer_and_acts_before_the_writers():
    """sim.writers only observe; the thermostat has its own slot and acts first at a shared time."""
    import numpy as np

    import hardspheres as hs
    from hardspheres.dense import Thermostat, VelocityRescale

    sim = hs.Simulation(hs.random_spheres(64, 0.2, box=8.0, seed=3), hs.PeriodicBox(8.0))
    th = VelocityRescale(kT=2.0, interval=0.5)
    sim.set_thermostat(th)
    assert sim.writers == [] and sim.thermostat is th and isinstance(th, Thermostat)
    seen = []

    class Probe:
        next_time, wants_events = 0.5, False

        def attach(self, sim):
            pass

        def write(self, sim, t):
            v = sim.engine.velocities
            seen.append(
                float(np.sum(sim.engine.masses[:, None] * v * v)) / (3 * (sim.n - 1))
            )  # 3N - 3 in a box
            self.next_time = np.inf

    sim.writers.append(Probe())
    sim.run(until=0.5)
    assert seen and abs(seen[0] - 2.0) < 1e-9  # the writer at t = 0.5 saw the rescaled velocities


def test_compress_counts_are_whole_numbers(tmp_path):
    from helpers import hs_cmd

    scn = tmp_path / "s.txt"
    scn.write_text("1 0.5 0 0 0 1 0 0 a\n1 0.5 2 0 0 -1 0 0 b\n")
    res = hs_cmd(
        "compress",
        str(scn),
        "--box",
        "6",
        "--rate",
        "0.1",
        "--collisions",
        "2.7",
        "-o",
        str(tmp_path / "o.txt"),
    )
    assert res.returncode == 1 and res.stdout == ""
    assert "--collisions: must be a whole number" in res.stderr and len(res.stderr.splitlines()) == 1
