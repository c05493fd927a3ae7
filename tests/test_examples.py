"""Every file in examples/ runs: the scripts at a reduced size (``--quick``), the scenarios
through the ``spheres`` program, the study file through ``hs.sweep`` at a reduced size."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

from helpers import PACKAGE_ROOT, spheres_cmd

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
SCRIPTS = sorted(p.name for p in EXAMPLES.glob("*.py") if p.name != "study.py")
# scenario -> (container radius, end time) and a line its report must hold
SCENARIOS = {
    "three.txt": ("120", "105", "time of event: 94.0839\ncolliding one two\n"),
    "newtons_cradle.txt": ("20", "12", "time of event: 8\ncolliding d e\n"),
    "heavy_and_light.txt": ("15", "20", "reflecting light\n"),
}
NEEDS = {
    "equation_of_state.py": ["matplotlib"],
    "trajectory_pictures.py": ["matplotlib", "gsd"],
    "jammed_packing.py": ["freud"],
    "crystal.py": ["freud"],
    "transport.py": ["freud"],
}


def test_every_example_is_tested_and_listed():
    tested = set(SCRIPTS) | set(SCENARIOS) | {"study.py", "eos.toml", "README.md"}
    present = {p.name for p in EXAMPLES.iterdir() if p.is_file()}
    assert present == tested, "an example this test does not run (or runs but is gone)"
    listing = (EXAMPLES / "README.md").read_text()
    assert all(f"`{name}`" in listing for name in present - {"README.md"})
    assert len(present - {"README.md"}) >= 8


def _env():
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join([str(PACKAGE_ROOT), env.get("PYTHONPATH", "")])
    return env


@pytest.mark.parametrize("script", SCRIPTS)
def test_script_runs_quick(script, tmp_path):
    for module in NEEDS.get(script, []):
        pytest.importorskip(module)
    res = subprocess.run(
        [sys.executable, str(EXAMPLES / script), "--quick"],
        cwd=tmp_path,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 0, res.stderr[-3000:]
    assert res.stdout.strip(), "printed nothing"


@pytest.mark.parametrize("name", sorted(SCENARIOS))
def test_scenario_runs_in_the_assignment_program(name):
    radius, end, expected = SCENARIOS[name]
    with open(EXAMPLES / name) as fh:
        out = spheres_cmd(radius, end, stdin=fh, check=True).stdout
    assert expected in out


def test_study_file_and_script_run_reduced(tmp_path):
    pytest.importorskip("distributed")
    pytest.importorskip("pyarrow")
    study = tomllib.loads((EXAMPLES / "eos.toml").read_text())
    assert study["packing"] and study["n"]  # the file parses as a study
    small = dict(study, packing=study["packing"][:2], n=64, seeds=2, equilibrate=5, collisions=20)
    lines = [f"{k} = {v!r}".replace("'", '"') for k, v in small.items()]
    (tmp_path / "small.toml").write_text("\n".join(lines) + "\n")
    res = subprocess.run(
        [sys.executable, str(EXAMPLES / "study.py"), str(tmp_path / "small.toml"), "--serial"],
        cwd=tmp_path,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode == 0, res.stderr[-3000:]
    assert res.stdout.count("Hansen-Goos") == 2
    assert (tmp_path / "eos" / "results.parquet").exists()
