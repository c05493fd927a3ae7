"""docs/glass.md's examples run (smaller and shorter)."""

import re
import subprocess
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")
pytest.importorskip("scipy")

PAGE = (Path(__file__).resolve().parents[1] / "docs" / "glass.md").read_text()
BLOCKS = re.findall(r"```python\n(.*?)```", PAGE, re.S)


def run(block, changes):
    import matplotlib

    matplotlib.use("Agg")
    for old, new in changes:
        assert old in block, old
        block = block.replace(old, new)
    scope: dict = {}
    exec(compile(block, "docs/glass.md", "exec"), scope)
    return scope


def test_the_glass_former_example_runs():
    s = run(
        BLOCKS[0],
        [
            ("n, phi = 500, 0.56", "n, phi = 100, 0.45"),
            ("10_000 * n", "20 * n"),
            ("every=10, per_decade=8, until=1000", "every=2, per_decade=8, until=10"),
            ("sim.time + 1000", "sim.time + 10"),
            ("origin_every=10", "origin_every=2"),
        ],
    )
    assert 0 < s["tau"] < 10 and s["chi4_peak"] > 0 and len(s["alpha2"]) == len(s["fs"].t)


def test_the_jammed_packing_example_runs():
    s = run(
        BLOCKS[1],
        [
            ("1000, 0.3", "128, 0.3"),
            ("(1e-3, 1e5), (1e-4, 1e6)", "(1e-3, 1e6)"),
            ("2000 * sim.n", "100 * sim.n"),
            ("f_max=0.1, contacts_only", "f_max=0.5, contacts_only"),
        ],
    )
    c = s["c"]
    assert abs(c.z - c.z_isostatic) < 0.02 * c.z_isostatic
    assert 0 < s["gamma"] < 1
    cut = s["cut"]  # cut where the non-rattlers' network is isostatic
    kept = int((~cut.rattler).sum())
    assert int(cut.contacts[~cut.rattler].sum()) // 2 >= 3 * (kept - 1) + 1
    assert -1 < s["theta"] < 2


def test_the_readme_glass_commands_run(tmp_path):
    """README's 'Glasses and jamming' commands, 128 spheres: compress prints z, rattlers and phi_J; plots written."""
    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    cmds = re.search(r"## Glasses and jamming\n.*?```sh\n(.*?)```", readme, re.S).group(1)
    out = ""
    for line in cmds.strip().splitlines():
        line = line.replace("--n 1000 --box 12", "--n 128 --box 6").replace("--box 12", "--box 6")
        # --until as README has it: the frames' spacing is what is tested (128 spheres: a second)
        res = subprocess.run(line, shell=True, cwd=tmp_path, capture_output=True, text=True)
        assert res.returncode == 0, (line, res.stderr)
        assert "warning" not in res.stderr, (line, res.stderr)  # tau_alpha and the peak resolved
        out += res.stdout
    assert re.search(r"jamming: z = \d\.\d+ to \d\.\d+ after removing .* rattlers .* phi_J = 0\.\d+", out)
    for png in ("contacts.png", "fs.png", "chi4.png"):
        assert (tmp_path / png).stat().st_size > 1000
