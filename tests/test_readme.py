"""README's claims, run: its Python example and its commands."""

import re
import subprocess
from pathlib import Path

from helpers import spheres_cmd

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_readme_python_example_runs(tmp_path, monkeypatch):
    block = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "run.npz").exists()


def test_readme_first_command_output():
    """`spheres 120 105 < examples/three.txt` prints the assignment text's example events."""
    with open(ROOT / "examples" / "three.txt") as fh:
        out = spheres_cmd("120", "105", stdin=fh, check=True).stdout
    assert "time of event: 94.0839\ncolliding one two\n" in out
    assert "time of event: 102.539\nreflecting two\n" in out
    assert out.rstrip().endswith("momentum: (0,-0.217836,12.8993)")


def test_readme_commands_run(tmp_path):
    cmds = re.search(r"## Commands\n\n```sh\n(.*?)```", README, re.S).group(1)
    for line in cmds.strip().splitlines():
        line = line.replace("--collisions 2000000", "--collisions 20000")
        line = line.replace("--collisions 2e6", "--collisions 2e4")
        line = line.replace(
            "hardspheres validate --csv validation.csv",
            "hardspheres validate --n 500 --collisions 20 --equilibrate 5 "
            "--packings 0.2 --csv validation.csv",
        )
        res = subprocess.run(line, shell=True, cwd=tmp_path, capture_output=True, text=True)
        assert res.returncode == 0, (line, res.stderr)


def test_architecture_names_every_module():
    """docs/architecture.md names each module of src/hardspheres, and only modules that exist."""
    layout = (ROOT / "docs" / "architecture.md").read_text().split("## Every module", 1)[1]
    named = {m for m in re.findall(r"`(?:\w+/)?_?\w+\.py`", layout) if m not in ("`__init__.py`",)}
    named = {m for m in named if not m.startswith("`tests/")}
    src = ROOT / "src" / "hardspheres"
    modules = {
        f"`{p.relative_to(src).as_posix()}`"
        for p in src.rglob("*.py")
        if p.name != "__main__.py"
        and (p.name != "__init__.py" or p.parent.name in ("studies", "cli"))
        and "_static" not in p.parts
    }
    assert modules - named == set(), "modules docs/architecture.md does not name"
    assert named - modules == set(), "docs/architecture.md names modules that do not exist"
