"""``hardspheres bench``: it times a fluid, and says how it got there (no timed assertions)."""

import json
from pathlib import Path

import pytest
from helpers import hs_cmd

from hardspheres.cli.commands import build_parser
from hardspheres.core import bench as hb

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def fluid():
    return hb.bench(4000, 0.3, 100_000, seed=3, box=True)


def test_warm_up_settles_and_reports_both_rates(fluid):
    r = fluid
    assert r["settled"] is True
    blocks = r["warmup_blocks"]
    assert len(blocks) >= 1 + hb.SETTLE_PAIRS
    assert r["warmup_per_sphere"] == blocks[-1][0] > 0
    # consecutive blocks whose rates agree, as the criterion says
    for (_, a, b), (_, c, d) in zip(blocks[-1 - hb.SETTLE_PAIRS : -1], blocks[-hb.SETTLE_PAIRS :]):
        assert abs(c - a) <= 0.02 * a and abs(d - b) <= 0.05 * b
    for key in ("warmup_collision_rate", "warmup_crossing_rate", "collision_rate", "crossing_rate"):
        assert r[key] > 0
    assert r["crossings"] > 0 and r["collisions"] == 100_000


def test_timed_fluid_collides_at_the_enskog_rate(fluid):
    """Equal hard spheres collide ``4 n sigma^2 g(sigma) sqrt(pi kT / m)`` times per unit time.

    Chapman & Cowling, The Mathematical Theory of Non-uniform Gases, 3rd ed.
    (1970), ch. 16, with g from Carnahan-Starling (good to 0.3% at phi = 0.3):
    24 phi g / sqrt(pi) = 10.067 at phi = 0.3 (sigma = m = kT = 1).
    The lattice it starts from collides at up to 1.6x that rate.
    """
    assert hb.enskog_rate(0.3) == pytest.approx(10.067, abs=1e-3)
    assert fluid["collision_rate"] == pytest.approx(hb.enskog_rate(0.3), rel=0.03)
    assert fluid["warmup_collision_rate"] == pytest.approx(hb.enskog_rate(0.3), rel=0.03)


def test_fixed_warm_up_runs_what_it_is_told():
    r = hb.bench(500, 0.3, 1000, seed=1, warmup=3)
    assert r["warmup_per_sphere"] == 3.0 and r["collisions"] == 1000
    r = hb.bench(500, 0.3, 1000, seed=1, warmup=0)
    assert r["warmup_blocks"] == [] and r["warmup_per_sphere"] == 0.0


def test_settled_compares_within_noise():
    assert hb.settled((10.0, 2.0), (10.05, 2.01), (10**6, 10**5))
    assert not hb.settled((10.0, 2.0), (10.5, 2.0), (10**6, 10**5))
    assert not hb.settled((10.0, 2.0), (10.0, 2.2), (10**6, 10**5))
    assert hb.settled((10.0, 2.0), (10.5, 2.0), (1000, 100))  # 5% is noise for 1000


def test_dense_fluid_crosses_cells_once_warm():
    """From the old contact-spacing lattice, PHI = 0.45 timed no crossing at all."""
    r = hb.bench(3000, 0.45, 50_000, seed=2)
    assert r["settled"] and r["crossings"] > 0 and r["reflections"] > 0
    assert r["max_overlap"] <= 1e-9 and r["outside"] == 0


def test_warmup_option():
    p = build_parser()
    base = ["bench", "--n", "100", "--packing", "0.3", "--collisions", "10"]
    assert p.parse_args(base).warmup is None
    assert p.parse_args(base + ["--warmup", "auto"]).warmup is None
    assert p.parse_args(base + ["--warmup", "2.5"]).warmup == 2.5


def test_command_prints_settle_figures_and_json_last():
    """The last line is the JSON that ../shared/anchor/side_by_side.py reads."""
    out = hs_cmd(
        "bench",
        "--n",
        "400",
        "--packing",
        "0.3",
        "--collisions",
        "2000",
        "--seed",
        "7",
        "--box",
        cwd=ROOT,
        check=True,
    ).stdout
    lines = out.strip().splitlines()
    assert "warm-up:" in out and "settled" in out and "crossings" in out
    r = json.loads(lines[-1])
    for key in (
        "collisions_per_s",
        "max_overlap",
        "outside",
        "energy_rel_drift",
        "warmup_per_sphere",
        "collision_rate",
        "crossing_rate",
        "setup_s",
    ):
        assert key in r
