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
