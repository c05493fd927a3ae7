"""validation/ecmc_loop.py: a run saved after every chunk resumes bit for bit (short runs)."""

import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LENGTHS = (20, 160, 8)  # lifts per disk to equilibrate and to measure, chunks


@pytest.fixture(scope="module")
def loop():
    spec = importlib.util.spec_from_file_location("ecmc_loop", ROOT / "validation" / "ecmc_loop.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_an_interrupted_run_resumes_to_the_same_numbers(loop, tmp_path, monkeypatch):
    whole, whole_series = loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS)
    calls = {"n": 0}
    real = loop.psi6

    def dies_at_the_third_chunk(chain):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(chain)

    monkeypatch.setattr(loop, "psi6", dies_at_the_third_chunk)
    with pytest.raises(KeyboardInterrupt):
        loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS, str(tmp_path))
    record = json.loads((tmp_path / "crystal_0.7000_crystal_1.json").read_text())
    assert record["chunk"] == 2 and len(record["series"]) == 2
    monkeypatch.setattr(loop, "psi6", real)
    row, series = loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS, str(tmp_path))
    assert [s["bp"] for s in series] == [s["bp"] for s in whole_series]
    assert [s["psi6"] for s in series] == [s["psi6"] for s in whole_series]
    for key in ("bp", "error_run", "error_chunks", "psi6_mean", "tau_bp"):
        assert row[key] == whole[key], key
    loop.drop_checkpoint(str(tmp_path), "crystal", 0.70, "crystal", 1)
    assert list(tmp_path.iterdir()) == []


def test_a_checkpoint_of_other_lengths_or_damaged_is_refused(loop, tmp_path, monkeypatch):
    monkeypatch.setattr(loop, "psi6", lambda chain: (_ for _ in ()).throw(KeyboardInterrupt))
    with pytest.raises(KeyboardInterrupt):
        loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS, str(tmp_path))
    with pytest.raises(loop.CheckpointProblem, match="lifts per chunk"):
        loop.measure("crystal", 0.70, "crystal", 1, 20, 320, 8, str(tmp_path))
    with pytest.raises(loop.CheckpointProblem, match="lifts per chunk"):
        loop.measure("crystal", 0.70, "crystal", 1, 40, 160, 8, str(tmp_path))
    (tmp_path / "crystal_0.7000_crystal_1.json").write_text("{not json")
    with pytest.raises(loop.CheckpointProblem, match="not a checkpoint of this script"):
        loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS, str(tmp_path))


def test_a_checkpoint_resumes_into_a_shorter_run_of_the_same_chunks(loop, tmp_path, monkeypatch):
    short, short_series = loop.measure("crystal", 0.70, "crystal", 1, 20, 80, 4)
    calls = {"n": 0}
    real = loop.psi6

    def dies_at_the_third_chunk(chain):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(chain)

    monkeypatch.setattr(loop, "psi6", dies_at_the_third_chunk)
    with pytest.raises(KeyboardInterrupt):
        loop.measure("crystal", 0.70, "crystal", 1, *LENGTHS, str(tmp_path))  # 8 chunks of 20
    monkeypatch.setattr(loop, "psi6", real)
    row, series = loop.measure("crystal", 0.70, "crystal", 1, 20, 80, 4, str(tmp_path))  # 4 of 20
    assert [s["bp"] for s in series] == [s["bp"] for s in short_series]
    for key in ("bp", "error_run", "error_chunks", "psi6_mean"):
        assert row[key] == short[key], key


def test_the_plot_draws_both_boxes_and_refuses_a_missing_file(loop, tmp_path, monkeypatch, capsys):
    """``plot`` reads the committed runs into a picture; a CSV that is not there is one line, exit 2."""
    pytest.importorskip("matplotlib")
    rows = loop.read(str(ROOT / "validation" / "results" / "ecmc_loop_870.csv"))
    assert {r["box"] for r in rows} == {"crystal", "square"}
    loop.plot(rows, str(tmp_path / "loop.png"))
    assert (tmp_path / "loop.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    monkeypatch.setattr("sys.argv", ["ecmc_loop.py", "plot", "--csv", str(tmp_path / "none.csv")])
    with pytest.raises(SystemExit) as stop:
        loop.main()
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"ecmc_loop.py: error: --csv {tmp_path / 'none.csv'}: no such file"


def test_states_counts_the_switches_and_averages_the_two_starts(loop):
    """A series that goes low, high, low: two switches, a third above; the starts' mean and its z."""
    ref, ref_err = loop.reference("crystal", 0.718)
    series = [
        {"box": "crystal", "phi": 0.718, "start": start, "seed": 2.0, "bp": bp, "psi6": psi}
        for start in ("liquid", "crystal")
        for bp, psi in ((9.0, 0.75), (9.2, 0.72), (9.0, 0.75))
    ]
    rows = [
        {"box": "crystal", "phi": 0.718, "start": "liquid", "seed": 2.0, "bp": ref - 0.03, "error": 0.03},
        {"box": "crystal", "phi": 0.718, "start": "crystal", "seed": 2.0, "bp": ref + 0.01, "error": 0.04},
    ]
    text = loop.states(rows, series, "crystal", 0.718, 2, 9.1).splitlines()
    assert text[0] == (
        "liquid: 3 chunks, 2 switches, 33% above 9.1; above: beta P d^2 9.200, |Psi6| 0.720; "
        "below: beta P d^2 9.000, |Psi6| 0.750"
    )
    z = -0.01 / (0.025**2 + ref_err**2) ** 0.5
    assert text[2] == f"the two starts' average: {ref - 0.01:.4f} +- 0.0250, z = {z:+.2f}"
    assert loop.states(rows, series, "square", 0.718, 2, 9.1) == "no chunks of square 0.718 seed 2"


def test_the_solid_start_is_the_grown_solid_expanded_to_the_packing(loop, monkeypatch):
    """``solid``: grown to 0.74, chains there, every position scaled into the packing's box, no overlap."""
    monkeypatch.setattr(loop, "SOLID_LIFTS", 20)
    chain = loop.start_chain("square", 0.716, "solid", 1)  # (EventChain refuses an overlap)
    box = loop.make_box("square", 0.716)
    assert chain.container.sides == pytest.approx(box.sides, rel=1e-15)
    radii = chain.state().radii
    assert radii.size == loop.N and radii == pytest.approx(0.5, rel=1e-12)
    assert float(3.141592653589793 * (radii**2).sum() / box.volume) == pytest.approx(0.716, rel=1e-12)
    dense = loop.hs.EventChain.from_simulation(loop.grown("square", 0.74, 1), seed=1, variant="straight")
    dense.run(events=20 * loop.N).run(chains=1)
    ratio = box.sides[0] / dense.container.sides[0]
    assert ratio > 1.01  # the positions of the solid at 0.74, spread over the larger box
    assert (chain.state().positions == dense.state().positions * ratio).all()
    assert loop.size("large") == 128**2 and loop.reference("large", 0.698) == (9.17441, 0.00057)


def test_the_event_dynamics_loop_draws_the_longest_chain_run_of_each_start(tmp_path):
    """validation/disks_loop.py ``plot --ecmc``: one point per packing and start, the longest; no 1 : 1 box."""
    spec = importlib.util.spec_from_file_location("disks_loop", ROOT / "validation" / "disks_loop.py")
    disks = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(disks)
    results = ROOT / "validation" / "results"
    paths = [str(results / f"ecmc_loop_{name}.csv") for name in ("870", "870_long", "16384")]
    points = disks._ecmc_points(paths)
    assert len(points["small"]) == 30 and len(points["large"]) == 3  # 15 packings x 2 starts; 3 at 128^2
    at_718 = sorted(r["length"] for r in points["small"] if abs(r["phi"] - 0.718) < 1e-9)
    assert at_718 == [41_000_000, 41_800_000]  # seed 2's runs, not the shorter ones
