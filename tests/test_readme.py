"""README's claims, run: its Python example and its commands."""

import re
import subprocess
from pathlib import Path

from helpers import spheres_cmd

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys):
    """It runs with what Getting started installs (io, plot): no freud, no scipy (the analysis extra)."""
    import sys

    for name in ("freud", "scipy"):
        for loaded in [m for m in sys.modules if m == name or m.startswith(name + ".")]:
            monkeypatch.delitem(sys.modules, loaded)
        monkeypatch.setitem(sys.modules, name, None)
    block = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    assert len(block.strip().splitlines()) <= 16  # the "15-line example"
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    assert (tmp_path / "run.npz").exists() and (tmp_path / "run.gsd").exists()
    assert re.search(r"Z = \d\.\d{3} \+- 0\.\d{3}; Hansen-Goos: 3\.984", capsys.readouterr().out)


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


def test_readme_is_a_front_page():
    """At most about 200 lines; the venv step; links that resolve; nothing from outside the repository."""
    assert len(README.splitlines()) <= 200
    assert "python3 -m venv .venv" in README.split("```sh", 1)[1].split("```", 1)[0]
    assert "../shared" not in README  # a user's clone has no ../shared
    assert "FSmallenburg/EDMD" in README  # where the anchor's sources are
    links = re.findall(r"\]\(([^)#]+)\)", README)
    local = [link for link in links if "://" not in link]
    assert len(local) >= 20
    missing = [link for link in local if not (ROOT / link).exists()]
    assert missing == [], missing
    layout = re.search(r"## Layout\n(.*?)(\n## |\Z)", README, re.S).group(1)
    assert "docs/architecture.md" in layout and (ROOT / "docs" / "architecture.md").exists()


def test_readme_speed_figures_are_recorded_runs():
    """Every ratio README's Speed section quotes is in benchmarks/README.md's tables of that run."""
    speed = re.search(r"## Speed\n(.*?)\n## ", README, re.S).group(1)
    bench = (ROOT / "benchmarks" / "README.md").read_text()
    run = re.search(r"## Speed, quiet: .*?\n(.*?)\n## ", bench, re.S)
    assert run, "benchmarks/README.md lost the runs README quotes"
    text = run.group(1)
    assert "2026-12-06" in speed and "2026-12-06" in bench[run.start() : run.start() + 200]
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| 1e+0") and len(cells) == 9:
            rows[(cells[0], cells[1])] = cells[6]
    quoted = {("1e+04", "0.1"): "0.86", ("1e+04", "0.3"): "1.07", ("1e+04", "0.45"): "0.83",
              ("1e+05", "0.1"): "0.95", ("1e+05", "0.3"): "1.25", ("1e+05", "0.45"): "0.79",
              ("1e+06", "0.1"): "0.90", ("1e+06", "0.3"): "0.95", ("1e+06", "0.45"): "0.60"}  # fmt: skip
    for key, ratio in quoted.items():
        assert ratio in speed
        assert rows[key] == ratio, (key, rows[key], ratio)


def test_readme_hard_disk_study_prints_what_readme_quotes(tmp_path, monkeypatch, capsys):
    """README's "Hard disks" block, run as it stands: its printed line is the one README quotes."""
    section = re.search(r"## Hard disks\n(.*?)\n## ", README, re.S).group(1)
    block = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    printed = capsys.readouterr().out.strip()
    assert f"prints `{printed}`" in section.replace("\n", " "), printed
    assert (tmp_path / "disks.png").stat().st_size > 10_000


def test_readme_constant_pressure_block_prints_what_readme_quotes(tmp_path, monkeypatch, capsys):
    """README's "Constant pressure and coexistence" block, run as it stands: the lines README quotes."""
    import hardspheres as hs
    from hardspheres.analysis.coexistence import SlabProfile, crystal_fluid_slab
    from hardspheres.eos import packing_at_pressure

    section = re.search(r"## Constant pressure and coexistence\n(.*?)\n## ", README, re.S).group(1)
    block = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    printed = capsys.readouterr().out.strip().splitlines()
    text = section.replace("\n", " ")
    assert len(printed) == 2 and all(f"`{line}`" in text for line in printed), printed
    assert f"(Hansen-Goos: {packing_at_pressure(5.0):.3f})" in text
    start = hs.Simulation(*crystal_fluid_slab((3, 3, 6), plane="100", seed=1))
    assert f"{SlabProfile(bins=20).compute(start).crystal_fraction:.2f} at the start" in text


def test_readme_quotes_what_its_example_prints(tmp_path, monkeypatch, capsys):
    """The line README says its first simulation prints is the line it prints."""
    block = re.search(r"```python\n(.*?)```", README, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    printed = capsys.readouterr().out.strip().splitlines()[-1]
    quoted = re.search(r"```\n\nIt prints `([^`]+)`", README)
    assert quoted, "README does not quote what its first simulation prints"
    assert quoted.group(1) == printed
