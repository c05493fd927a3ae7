"""The commands as a working physicist uses them (issue 15), end to end through the CLI.

One test (or a few) per item: the compile note, trajectory size, honest run
summaries, numbers as typed, degenerate requests, small systems, file
formats, progress, pictures of many spheres, and the small things.
"""

import io
import pathlib
import re

import numpy as np
import pytest
from helpers import ROOT, hs_cmd, spheres_cmd

import hardspheres as hs
from hardspheres.cli import commands
from hardspheres.cli import run as runner
from hardspheres.progress import Progress


def assert_one_line(res, *words):
    """Exit 1, nothing on stdout, one line on stderr holding ``words``, no traceback."""
    assert res.returncode == 1, (res.stdout, res.stderr)
    assert res.stdout == ""
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr, res.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])


@pytest.fixture(scope="module")
def scn(tmp_path_factory):
    """A directory with s.txt: 200 spheres in a container of radius 10."""
    d = tmp_path_factory.mktemp("ux")
    (d / "s.txt").write_text(hs.random_spheres(200, 0.2, container=10.0, seed=3).to_text())
    (d / "b.txt").write_text(hs.random_spheres(200, 0.2, box=15.0, seed=3).to_text())
    from hardspheres.core.warmup import ensure_compiled

    ensure_compiled(quiet=True)
    return d


# ---- 1. the first compilation is announced and kept out of the rates ------------------


@pytest.mark.slow
def test_cold_cache_is_announced_once_and_not_timed(scn, tmp_path):
    env = {"NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    first = hs_cmd("run", "s.txt", "--container", 10, "--until", 0.5, cwd=scn, env=env)
    assert first.returncode == 0, first.stderr
    assert (
        "compiling the event core for 3-D (once per dimension and collision rule, then cached; typically"
        in first.stderr
    )
    assert first.stderr.count("compiling") == 1
    assert "(compilation excluded)" in first.stdout
    again = hs_cmd("run", "s.txt", "--container", 10, "--until", 0.5, cwd=scn, env=env)
    assert again.returncode == 0 and again.stderr == "", again.stderr


def test_spheres_says_it_compiles_when_the_cache_is_cold(monkeypatch, capsys):
    """The assignment's program (compiled engine) gives the same note, on stderr only."""
    from hardspheres.cli import run_spheres
    from hardspheres.core import warmup

    monkeypatch.setenv("HARDSPHERES_ENGINE", "compiled")
    monkeypatch.setattr(
        warmup, "is_cold", lambda dimensions=3, inelastic=False, sheared=False, stepped=False: True
    )
    out = io.StringIO()
    data = (ROOT / "examples" / "three.txt").read_bytes()
    assert run_spheres(["120", "105"], io.BytesIO(data), out) == 0
    err = capsys.readouterr().err
    assert err.startswith("compiling the event core for 3-D (once per dimension") and err.endswith(" s\n")
    assert "colliding one two" in out.getvalue() and "compiling" not in out.getvalue()


def test_cold_cache_detection(tmp_path, monkeypatch):
    from hardspheres.core import warmup

    assert warmup.ensure_compiled(quiet=True) >= 0.0
    assert not warmup.is_cold()
    paths = warmup._index_paths()
    assert paths and all(p.endswith(".nbi") for p in paths)
    monkeypatch.setattr(warmup, "_index_paths", lambda: [str(tmp_path / "missing.nbi")])
    assert warmup.is_cold()


def test_cold_cache_detection_per_dimension(tmp_path, monkeypatch):
    """2-D and 3-D have machine code of their own: each is cold until its marker is there."""
    from hardspheres.core import warmup

    for d in (2, 3):
        assert warmup.ensure_compiled(quiet=True, dimensions=d) >= 0.0
        assert not warmup.is_cold(d) and pathlib.Path(warmup._marker(d)).exists()
    monkeypatch.setattr(
        warmup,
        "_marker",
        lambda d, inelastic=False, sheared=False, stepped=False: str(
            tmp_path / f"compiled-{d}d{'-inelastic' * inelastic}{'-sheared' * sheared}{'-stepped' * stepped}"
        ),
    )
    assert warmup.is_cold(2) and warmup.is_cold(3)
    (tmp_path / "compiled-2d").write_text("compiled\n")
    assert not warmup.is_cold(2) and warmup.is_cold(3)


# ---- 2. trajectories: events opt-in, size estimated -------------------------------------


def test_events_are_opt_in(scn):
    gsd = pytest.importorskip("gsd.hoomd")
    for name, extra in (("plain.gsd", []), ("events.gsd", ["--events"])):
        res = hs_cmd(
            "run",
            "s.txt",
            "--container",
            10,
            "--until",
            1,
            "--trajectory",
            name,
            "--every",
            0.5,
            *extra,
            cwd=scn,
        )
        assert res.returncode == 0, res.stderr
    with gsd.open(scn / "plain.gsd") as f:
        assert not any(k.startswith("hardspheres/events") for k in f[1].log)
    with gsd.open(scn / "events.gsd") as f:  # one array per event field
        assert len(f[1].log["hardspheres/events/time"]) > 0
    assert_one_line(
        hs_cmd("run", "s.txt", "--container", 10, "--until", 1, "--trajectory", "t.xyz", "--events", cwd=scn),
        "--events",
        ".gsd",
    )


def test_large_trajectory_is_warned(scn, monkeypatch, capsys):
    frames = 33 * (20000 * 48 + 200)  # positions and velocities in float64
    assert runner.estimate_trajectory_bytes(20000, 33, 1e5, 32.0, False) == frames
    assert runner.estimate_trajectory_bytes(20000, 33, 1e5, 32.0, True) == frames + 1e5 * 32 * 40
    monkeypatch.setattr(runner, "LARGE_TRAJECTORY", 1000.0)
    monkeypatch.chdir(scn)
    status = commands.main(
        ["run", "s.txt", "--container", "10", "--until", "1", "--trajectory", "w.gsd", "--every", "0.1"]
    )
    err = capsys.readouterr().err
    assert status == 0
    m = re.search(r"warning: w.gsd will grow to about ([\d.]+) kB \(11 frames\)", err)
    assert m, err
    assert 0.5 < (scn / "w.gsd").stat().st_size / (1e3 * float(m.group(1))) < 2.0


# ---- 3. run summaries -------------------------------------------------------------------


def test_equilibrate_and_labelled_pressures(scn):
    res = hs_cmd("run", "s.txt", "--container", 10, "--until", 3, "--equilibrate", 5, cwd=scn)
    assert res.returncode == 0, res.stderr
    out = res.stdout
    assert "after equilibrating: 5 collisions per sphere, to t = " in out
    m = re.search(r"averages over t = ([\d.e+-]+) \.\. 3", out)
    assert m and 0 < float(m.group(1)) < 3
    assert "wall pressure" in out and "surface term" in out and "Z = PV/NkT" not in out
    box = hs_cmd("run", "b.txt", "--box", 15, "--until", 2, "--equilibrate-time", 0.5, cwd=scn)
    assert box.returncode == 0, box.stderr
    assert "Z = PV/NkT" in box.stdout and "(virial)" in box.stdout
    assert "after equilibrating: 0.5 time units, to t = 0.5" in box.stdout
    plain = hs_cmd("run", "s.txt", "--container", 10, "--until", 1, cwd=scn)
    assert "from the start" in plain.stdout and "--equilibrate" in plain.stdout
    assert_one_line(
        hs_cmd("run", "s.txt", "--container", 10, "--until", 1, "--equilibrate-time", 2, cwd=scn),
        "--equilibrate-time",
        "--until",
    )
    assert_one_line(
        hs_cmd("run", "s.txt", "--container", 10, "--until", 0.01, "--equilibrate", 1000, cwd=scn),
        "--equilibrate",
        "--until",
    )


def test_summary_shows_errors_when_the_observables_give_them():
    s = {
        "pressure": 1.234567,
        "pressure_error": 0.0123,
        "pressure_converged": True,
        "compressibility": 2.0,
        "compressibility_error": float("nan"),
        "collision_rate": 3.0,
        "collision_rate_error": 0.1,
        "collision_rate_converged": False,
        "mean_free_path": 0.5,
    }
    assert runner._value(s, "pressure") == "1.23457 +- 0.012"
    assert "error unknown" in runner._value(s, "compressibility")
    assert "lower bound" in runner._value(s, "collision_rate")
    assert runner._value(s, "mean_free_path") == "0.5"


# ---- 4. numbers as physicists type them; every message names the option ----------------


def test_integral_floats_are_counts():
    args = commands.build_parser().parse_args(
        ["bench", "--n", "1e4", "--packing", "0.3", "--collisions", "2e6", "--seed", "7.0"]
    )
    assert (args.n, args.collisions, args.seed) == (10000, 2000000, 7)
    assert isinstance(args.collisions, int)


@pytest.mark.parametrize(
    "args, words",
    [
        (["bench", "--n", "100", "--packing", "0.3", "--collisions", "1.5"], ["--collisions", "whole"]),
        (["validate", "--packings", "abc"], ["--packings", "packing fractions"]),
        (
            ["generate", "--n", "5", "--container", "9", "--packing", "0.3", "--seed", "-1"],
            ["--seed", ">= 0"],
        ),
        (["generate", "--n", "5", "--container", "abc", "--packing", "0.3"], ["--container", "> 0"]),
        (["render", "x.gsd", "-o", "m.bmp"], ["-o", ".gif"]),
        (["render", "x.gsd", "--size", "big"], ["--size", "WIDTHxHEIGHT"]),
    ],
)
def test_bad_options_are_named(args, words, tmp_path):
    res = hs_cmd(*args, cwd=tmp_path)
    assert_one_line(res, f"hardspheres {args[0]}:", *words)


# ---- 5. degenerate requests refused, before any work --------------------------------------


@pytest.mark.parametrize(
    "args, words",
    [
        (["generate", "--n", "0", "--container", "9", "--packing", "0.3"], ["--n", ">= 1"]),
        (["bench", "--n", "0", "--packing", "0.3", "--collisions", "10"], ["--n"]),
        (["bench", "--n", "100", "--packing", "0.3", "--collisions", "0"], ["--collisions"]),
        (["validate", "--collisions", "0"], ["--collisions"]),
        (["validate", "--packings", "0.3,nan"], ["--packings", "'nan'"]),
        (["validate", "--packings", "0.3,0.8"], ["--packings", "'0.8'"]),
        (["render", "s.txt", "--container", "10", "--until", "1", "--fps", "0"], ["--fps"]),
        (["render", "s.txt", "--container", "10", "--until", "1", "--fps", "-3"], ["--fps"]),
    ],
)
def test_degenerate_requests_refused(args, words, scn):
    res = hs_cmd(*args, cwd=scn)
    assert_one_line(res, *words)
    assert not (scn / "validation.csv").exists() and not (scn / "movie.gif").exists()


# ---- 6. small systems ------------------------------------------------------------------------


@pytest.mark.parametrize("n, radius", [(1, 10), (8, 10), (10, 10), (10, 5)])
def test_small_systems_generate_and_run(n, radius, tmp_path):
    res = hs_cmd("generate", "--n", n, "--container", radius, "--packing", 0.3, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    (tmp_path / "s.txt").write_text(res.stdout)
    state = hs.Simulation.from_scenario(str(tmp_path / "s.txt"), hs.SphericalContainer(radius)).state()
    assert state.n == n
    phi = float(np.sum(state.radii**3) / radius**3)
    assert abs(phi - 0.3) < 1e-9
    run = hs_cmd("run", "s.txt", "--container", radius, "--until", 1, cwd=tmp_path)
    assert run.returncode == 0, run.stderr


def test_box_too_small_for_the_engine_is_refused_by_generate(tmp_path):
    assert_one_line(
        hs_cmd("generate", "--n", 1, "--box", 10, "--packing", 0.3, cwd=tmp_path),
        "three times the largest diameter",
    )


# ---- 7. formats ------------------------------------------------------------------------------


def test_plot_and_still_formats(scn):
    pytest.importorskip("matplotlib")
    scen = ["--container", 10, "--until", 0.5]
    for name, magic in (("p.pdf", b"%PDF"), ("p.svg", b"<?xml"), ("p.png", b"\x89PNG")):
        res = hs_cmd("plot", "speeds", "s.txt", *scen, "-o", name, cwd=scn)
        assert res.returncode == 0, res.stderr
        assert (scn / name).read_bytes().startswith(magic), name
    res = hs_cmd("render", "s.txt", *scen, "-o", "still.svg", cwd=scn)
    assert res.returncode == 0 and b"<svg" in (scn / "still.svg").read_bytes()[:2000]
    assert_one_line(hs_cmd("plot", "speeds", "s.txt", *scen, "-o", "p.jpg", cwd=scn), "-o", ".pdf")
    assert_one_line(hs_cmd("view", "s.txt", *scen, "-o", "v.png", cwd=scn), "-o", ".html")
    assert not (scn / "v.png").exists() and not (scn / "p.jpg").exists()


# ---- 8. progress --------------------------------------------------------------------------------


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_rate_eta_and_no_stale_characters():
    term = _Terminal()
    bar = Progress(10.0, stream=term)
    bar.update(5.0, 1000, "t=105.123456")
    bar.update(10.0, 2000, "t=10")
    first, second = term.getvalue().split("\r")[1:3]
    assert "events/s" in first and "left" in first and "50.0%" in first
    assert len(second) >= len(first) and second.rstrip().endswith("done")
    bar.close()
    assert term.getvalue().endswith("\r" + " " * len(second) + "\r")
    quiet = io.StringIO()  # not a terminal: nothing
    bar = Progress(10.0, stream=quiet)
    bar.update(5.0, events=1000)
    bar.close()
    assert quiet.getvalue() == ""


def test_progress_bar_with_a_label_only_and_notes():
    """``sweep`` gives a label and no count (once a TypeError on a terminal)."""
    term = _Terminal()
    bar = Progress(1.0, stream=term)
    bar.update(0.5, label="packing 0.40000  Z 5.1  collisions 100")
    assert "packing 0.40000" in term.getvalue() and "/s" not in term.getvalue()
    bar.note("a line of its own")
    assert "\ra line of its own\n" in term.getvalue()
    assert "packing 0.40000" in term.getvalue().rsplit("\n", 1)[1]  # the bar drawn again
    bar.close()
    assert term.getvalue().endswith("\r")


def test_progress_is_a_writer_redrawn_by_its_trigger():
    """The bar of ``hardspheres run`` rides on one ``sim.run``, as a writer with a trigger."""
    import hardspheres as hs
    from hardspheres.writers import Writer

    sim = hs.Simulation(hs.random_spheres(20, 0.1, container=8.0, seed=1), 8.0)
    term = _Terminal()
    seen = []
    bar = runner.ProgressWriter(
        Progress(2.0, stream=term),
        0.0,
        steps=20,
        first=lambda events, elapsed: seen.append((events, elapsed)),
    )
    assert isinstance(bar, Writer)
    sim.writers.append(bar)
    sim.run(until=2.0)
    redraws = term.getvalue().split("\r")[1:]
    assert 19 <= len(redraws) <= 20 and "t=0.1 " in redraws[0] and "t=1.9 " in redraws[18]
    assert seen and seen[0][1] == pytest.approx(0.1)
    sim.writers.remove(bar)
    bar.detach()
    assert term.getvalue().endswith("\r")


def test_run_is_silent_on_stderr_when_not_a_terminal(scn):
    res = hs_cmd("run", "s.txt", "--container", 10, "--until", 1, cwd=scn)
    assert res.returncode == 0 and res.stderr == "", res.stderr


# ---- 9. pictures of many spheres ------------------------------------------------------------


def test_render_slice_caption_and_size(scn):
    pytest.importorskip("matplotlib")
    from PIL import Image

    scen = ["s.txt", "--container", 10, "--until", 0.5]
    assert hs_cmd("render", *scen, "-o", "all.png", cwd=scn).returncode == 0
    res = hs_cmd("render", *scen, "-o", "cut.png", "--slice", 0, "--size", "800x450", cwd=scn)
    assert res.returncode == 0, res.stderr
    with Image.open(scn / "all.png") as a, Image.open(scn / "cut.png") as c:
        assert a.size == (1280, 720) and c.size == (800, 450)
        c = np.asarray(c.convert("RGB").resize(a.size))
        a = np.asarray(a.convert("RGB"))
    # the top of the picture (z > 0) is emptier with the cut: more white
    white = lambda img: np.mean(np.all(img[120:300, 400:880] > 245, axis=2))  # noqa: E731
    assert white(c) > white(a) + 0.2
    from hardspheres.viz.render import packing_fraction

    frames = hs.read_trajectory  # noqa: F841 (the caption's phi comes from packing_fraction)
    f = hs.Frames(
        np.zeros(1), np.zeros((1, 1, 3)), np.zeros((1, 1, 3)), np.ones(1), np.ones(1), ["a"], container=2.0
    )
    assert abs(packing_fraction(f) - 1 / 8) < 1e-12


def test_view_slice_is_in_the_page(scn):
    res = hs_cmd(
        "view", "s.txt", "--container", 10, "--until", 0.5, "--slice", -2.5, "-o", "cut.html", cwd=scn
    )
    assert res.returncode == 0, res.stderr
    page = (scn / "cut.html").read_text()
    assert '"cut":-2.5' in page and 'id="cut"' in page


@pytest.mark.slow
def test_screenshot_of_20000_spheres(tmp_path):
    """The page of 20000 spheres renders, plays and is saved, with no click to time out."""
    from hardspheres.viz.screenshot import find_chromium, screenshot
    from hardspheres.viz.viewer import write_viewer

    pytest.importorskip("playwright.sync_api")
    if find_chromium() is None:
        pytest.skip("needs chromium")
    from PIL import Image

    state = hs.random_spheres(20000, 0.3, container=40.0, seed=1)
    t = np.array([0.0, 0.1])
    pos = np.stack([state.positions, state.positions + 0.1 * state.velocities])
    frames = hs.Frames(
        t, pos, np.stack([state.velocities] * 2), state.radii, state.masses, state.names, container=40.0
    )
    write_viewer(frames, tmp_path / "big.html", cut=0.0)
    screenshot(tmp_path / "big.html", tmp_path / "big.png", timeout=240)
    with Image.open(tmp_path / "big.png") as im:
        a = np.asarray(im.convert("RGB"))
    assert im.size == (960, 640) and len(np.unique(a.reshape(-1, 3), axis=0)) > 200


# ---- 10. small things -------------------------------------------------------------------------


def test_refused_or_kept_options_of_run(scn):
    ck = scn / "ck.npz"
    assert (
        hs_cmd("run", "s.txt", "--container", 10, "--until", 1, "--checkpoint", ck, cwd=scn).returncode == 0
    )
    assert_one_line(
        hs_cmd("run", "--resume", ck, "--container", 10, "--until", 2, cwd=scn), "--container", "checkpoint"
    )
    assert_one_line(
        hs_cmd("run", "s.txt", "--container", 10, "--until", 1, "--every", 0.1, cwd=scn),
        "--every",
        "--trajectory",
    )
    assert_one_line(
        hs_cmd(
            "run", "s.txt", "--container", 10, "--until", 1, "--trajectory", "t.gsd", "--every", 5, cwd=scn
        ),
        "--every",
        "longer",
    )
    res = hs_cmd("run", "--resume", ck, "--until", 2, cwd=scn)  # keeps checkpointing
    assert res.returncode == 0 and f"checkpoint {ck}" in res.stdout
    assert hs.Simulation.load(ck).time == 2.0


def test_help_and_version_of_both_programs(tmp_path):
    for argv in (["--help"], ["-h"]):
        res = spheres_cmd(*argv)
        assert res.returncode == 0 and res.stdout.startswith("usage: spheres"), res
    res = spheres_cmd("--version")
    assert res.returncode == 0 and res.stdout.strip() == f"spheres (hardspheres {hs.__version__})"
    res = hs_cmd("--version", cwd=tmp_path)
    assert res.returncode == 0 and res.stdout.strip() == f"hardspheres {hs.__version__}"
    res = hs_cmd("run", "--help", cwd=tmp_path)
    assert res.returncode == 0 and "--equilibrate" in res.stdout and "--events" in res.stdout
    # the assignment's arguments are untouched
    res = spheres_cmd("120", "105", input=(ROOT / "examples" / "three.txt").read_text())
    assert res.returncode == 0 and "colliding one two" in res.stdout


def test_reprs_are_summaries_and_help_lists_attributes():
    state = hs.random_spheres(1000, 0.3, container=20.0, seed=1)
    assert repr(state) == "State(n=1000, time=0, names=[s0, s1, s2, ...])"
    f = hs.Frames(
        np.array([0.0, 1.0]),
        np.zeros((2, 1000, 3)),
        np.zeros((2, 1000, 3)),
        state.radii,
        state.masses,
        state.names,
        container=20.0,
    )
    assert repr(f) == "Frames(n=1000, frames=2, t=0..1, container=20, events=0)"
    doc = hs.Simulation.__doc__
    for name in ("observables", "writers", "container"):
        assert f"{name}:" in doc


def test_viewer_colour_bar_top_is_round():
    from hardspheres.viz.viewer import _payload, _round_up

    assert _round_up(3.6388) == 3.7 and _round_up(0.012345) == 0.013 and _round_up(2.0) == 2.0
    rng = np.random.default_rng(0)
    v = rng.normal(size=(2, 50, 3))
    f = hs.Frames(
        np.array([0.0, 1.0]),
        np.zeros((2, 50, 3)),
        v,
        np.ones(50),
        np.ones(50),
        [f"s{i}" for i in range(50)],
        container=20.0,
    )
    top = _payload(f, None, 600, 10**7, 1000, "speed")["speed_range"][1]
    assert top == float(f"{top:.2g}")


def test_empty_scenario_is_refused(tmp_path):
    (tmp_path / "empty.txt").write_text("")
    for args in (
        ["run", "empty.txt", "--container", 10, "--until", 1],
        ["view", "empty.txt", "--container", 10, "--until", 1, "-o", "e.html"],
    ):
        assert_one_line(hs_cmd(*args, cwd=tmp_path), "empty.txt", "no spheres")
    assert not (tmp_path / "e.html").exists()


def test_one_sphere_alone_gets_no_advice_that_cannot_help(tmp_path):
    """Issue 29 item 8: "mean free path inf (error unknown: run longer)" for a
    sphere alone in a box, which can never collide."""
    (tmp_path / "a.txt").write_text("1 0.5 0 0 0 1 0.3 0.2 a\n")
    done = hs_cmd("run", "a.txt", "--box", 4, "--until", 100, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    text = done.stdout + done.stderr
    assert "run longer" not in text and "one sphere: it never collides" in text
    assert not re.search(r"\+- 0(\s|$)", text), text  # no spread is no error bar, not "+- 0"


def test_summaries_say_only_what_happened(tmp_path):
    """Issue 29 item 5: every run without --equilibrate said its averages
    "include the melting of a lattice start", also after --resume."""
    (tmp_path / "s.txt").write_text(
        "".join(
            f"1 0.3 {x} {y} 0 {0.1 * x} {-0.1 * y} 0.5 s{x}{y}\n" for x in range(-2, 3) for y in range(-2, 3)
        )
    )
    first = hs_cmd("run", "s.txt", "--box", 6, "--until", 5, "--checkpoint", "c.npz", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    out = first.stdout + first.stderr
    assert "melting" not in out and "not equilibrated in this run" in out
    again = hs_cmd("run", "--resume", "c.npz", "--until", 10, cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    out = again.stdout + again.stderr
    assert "from the resumed checkpoint on" in out and "lattice" not in out
    traj = hs_cmd(
        "run", "s.txt", "--box", 6, "--until", 50, "--equilibrate", 5, "--trajectory", "t.gsd", cwd=tmp_path
    )
    assert traj.returncode == 0, traj.stderr
    assert "they include the equilibration" in traj.stdout + traj.stderr


def test_hopeless_trajectory_is_refused_before_the_first_frame(tmp_path):
    """Issue 29 item 8: --until 1e6 --every 1e-9 poured out frames with no warning
    (the size estimate waited for the first progress step, 1/200 of the run)."""
    (tmp_path / "s.txt").write_text("1 0.5 0 0 0 1 0.3 0.2 a\n1 0.5 2 0 0 -1 0.3 0.2 b\n")
    done = hs_cmd(
        "run",
        "s.txt",
        "--box",
        10,
        "--until",
        "1e6",
        "--every",
        "1e-9",
        "--trajectory",
        "t.gsd",
        cwd=tmp_path,
    )
    assert done.returncode == 1 and done.stderr.count("\n") == 1 and "larger --every" in done.stderr
    assert not (tmp_path / "t.gsd").exists()
