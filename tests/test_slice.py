"""The cut-away plane along any axis: ``--slice [AXIS=]VALUE``, ``cut_axis`` of the stills and the viewer.

A plain number is still the plane ``z = VALUE``; ``x=VALUE`` and ``y=VALUE``
keep the spheres whose centre has that coordinate ``<= VALUE`` (a slab along
z seen side-on).  Checked: the parsing and its one-line errors, which
spheres a still draws (by where they appear in the picture), which the
viewer's page draws (in headless Chromium, when present), and the bad
axes.
"""

import argparse
import os

import numpy as np
import pytest
from helpers import embedded_data, hs_cmd

from hardspheres.cli.options import cut_of, slice_plane
from hardspheres.errors import PictureError
from hardspheres.frames import Frames
from hardspheres.viz import cut_axis_index
from hardspheres.viz.viewer import write_viewer

CHROMIUM = "/usr/bin/chromium"


@pytest.mark.parametrize(
    "text, plane",
    [
        ("10.5", ("z", 10.5)),
        ("-2.5", ("z", -2.5)),
        ("x=5", ("x", 5.0)),
        ("Y=-1e-1", ("y", -0.1)),
        (" z = 3 ", ("z", 3.0)),
    ],
)
def test_slice_parses_a_number_or_axis_and_value(text, plane):
    assert slice_plane(text) == plane


@pytest.mark.parametrize("text", ["w=3", "x=", "=2", "x=abc", "xy=1", "x=1_0", "", "x==1"])
def test_a_bad_slice_says_what_is_allowed(text):
    with pytest.raises(argparse.ArgumentTypeError, match="AXIS=VALUE with AXIS x, y or z"):
        slice_plane(text)


def test_a_slice_at_infinity_is_refused():
    with pytest.raises(argparse.ArgumentTypeError, match="finite"):
        slice_plane("x=inf")


def test_cut_of_gives_the_picture_keywords():
    assert cut_of(None) == (None, "z")
    assert cut_of(("x", 2.0)) == (2.0, "x")


def test_cut_axis_index_names_the_axes():
    assert [cut_axis_index(a, "t") for a in ("x", "y", "z", "X")] == [0, 1, 2, 0]
    for bad in ("w", "", None, 2):
        with pytest.raises(PictureError, match="cut_axis must be 'x', 'y' or 'z'"):
            cut_axis_index(bad, "t")  # type: ignore[arg-type]


def _pair(axis, which=(0, 1)):
    """Spheres at -3 (0) and +3 (1) along ``axis`` (0, 1, 2) in a periodic box of 10, one frame."""
    p = np.zeros((1, len(which), 3))
    for k, i in enumerate(which):
        p[0, k, axis] = (-3.0, 3.0)[i]
    n = len(which)
    return Frames(
        np.zeros(1), p, np.zeros((1, n, 3)), np.ones(n), np.ones(n), [str(i) for i in range(n)], box=10.0
    )


def _ink(path):
    """Where the picture is not white (the caption's corner left out)."""
    from PIL import Image

    with Image.open(path) as im:
        a = np.asarray(im.convert("RGB")).astype(int)
    ink = np.any(a < 235, axis=2)
    ink[: a.shape[0] // 4, : int(a.shape[1] * 0.45)] = False  # the caption: N, packing, the cut
    return ink


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_the_still_draws_only_the_spheres_below_the_cut(tmp_path, axis):
    pytest.importorskip("matplotlib")
    from hardspheres.viz.render import render_still

    k = "xyz".index(axis)

    def draw(name, frames, cut):
        return _ink(render_still(frames, tmp_path / name, size=(400, 300), cut=cut, cut_axis=axis))

    cut = draw("cut.png", _pair(k), 0.0)  # the pair, cut at 0: the low sphere only
    low = draw("low.png", _pair(k, (0,)), 5.0)  # one sphere each, nothing cut (the same camera)
    high = draw("high.png", _pair(k, (1,)), 5.0)
    empty = draw("empty.png", _pair(k), -4.0)  # both cut away: the box's edges only
    assert (low & ~empty).sum() > 300 and (high & ~empty).sum() > 300
    assert np.mean(cut != low) < 0.002, np.mean(cut != low)
    assert np.mean(cut != high) > 10 * max(np.mean(cut != low), 1e-4)


def test_the_still_captions_the_cut(tmp_path):
    from hardspheres.viz.render import _caption

    assert _caption(_pair(0), 2, 1.5, None, "x")[1].endswith("cut-away: x <= 1.5")


def test_a_bad_cut_axis_is_refused_by_stills_and_the_viewer(tmp_path):
    pytest.importorskip("matplotlib")
    from hardspheres.viz.render import render_still

    with pytest.raises(PictureError, match="render: cut_axis must be"):
        render_still(_pair(0), tmp_path / "s.png", cut=0.0, cut_axis="w")
    with pytest.raises(PictureError, match="write_viewer: cut_axis must be"):
        write_viewer(_pair(0), tmp_path / "v.html", cut=0.0, cut_axis="r")


def test_the_page_carries_the_cut_axis(tmp_path):
    data = embedded_data(write_viewer(_pair(0), tmp_path / "v.html", cut=1.0, cut_axis="x").read_text())
    assert data["cut"] == 1.0 and data["cut_axis"] == "x"
    assert embedded_data(write_viewer(_pair(0), tmp_path / "w.html").read_text())["cut_axis"] == "z"


def test_view_and_render_take_an_axis_and_refuse_a_bad_one(tmp_path):
    pytest.importorskip("matplotlib")
    scn = hs_cmd("generate", "--n", 30, "--box", 8, "--packing", 0.2, "--seed", 1, cwd=tmp_path, check=True)
    (tmp_path / "s.txt").write_text(scn.stdout)
    common = ["s.txt", "--box", 8, "--until", 0.2]
    hs_cmd("view", *common, "--slice", "y=1.5", "-o", "v.html", cwd=tmp_path, check=True)
    data = embedded_data((tmp_path / "v.html").read_text())
    assert data["cut"] == 1.5 and data["cut_axis"] == "y"
    hs_cmd("view", *common, "--slice", "-1", "-o", "z.html", cwd=tmp_path, check=True)
    data = embedded_data((tmp_path / "z.html").read_text())
    assert data["cut"] == -1.0 and data["cut_axis"] == "z"  # a plain number: still z
    hs_cmd("render", *common, "--slice", "x=0", "--color", "q6", "-o", "s.png", cwd=tmp_path, check=True)
    assert (tmp_path / "s.png").stat().st_size > 1000
    for command, out in (("view", "b.html"), ("render", "b.png")):
        res = hs_cmd(command, *common, "--slice", "w=1", "-o", out, cwd=tmp_path)
        lines = res.stderr.strip().splitlines()
        assert res.returncode == 1 and len(lines) == 1, res.stderr
        assert lines[0].startswith(f"hardspheres {command}: ") and "AXIS x, y or z" in lines[0], lines[0]


def test_the_page_draws_only_the_spheres_below_the_cut_in_chromium(tmp_path):
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is missing (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="Python playwright is missing")
    from hardspheres.viz.screenshot import CHROMIUM_ARGS

    rng = np.random.default_rng(1)
    p = rng.uniform(-4.5, 4.5, size=(1, 50, 3))
    frames = Frames(
        np.zeros(1),
        p,
        np.zeros((1, 50, 3)),
        np.full(50, 0.2),
        np.ones(50),
        [str(i) for i in range(50)],
        box=10.0,
    )
    path = write_viewer(frames, tmp_path / "v.html", cut=0.5, cut_axis="x")
    stored = p[0].astype(np.float32)  # the page's positions are float32
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(viewport={"width": 500, "height": 400})
            page.goto(path.as_uri())
            page.wait_for_function("window.viewerReady === true", timeout=30_000)
            assert (
                page.evaluate("window.viewerControl.visible()")
                == np.flatnonzero(stored[:, 0] <= 0.5).tolist()
            )
            assert page.locator("#cutaxis").input_value() == "x"
            page.evaluate("window.viewerControl.setCut(-1, 'y')")
            assert (
                page.evaluate("window.viewerControl.visible()") == np.flatnonzero(stored[:, 1] <= -1).tolist()
            )
            assert page.locator("#cutaxis").input_value() == "y"
            page.select_option("#cutaxis", "z")  # the menu keeps the plane's value, on the new axis
            assert (
                page.evaluate("window.viewerControl.visible()") == np.flatnonzero(stored[:, 2] <= -1).tolist()
            )
            page.evaluate("window.viewerControl.setCut(null)")
            assert page.evaluate("window.viewerControl.visible()") == list(range(50))
        finally:
            browser.close()


def test_q6_in_a_rectangular_box_uses_its_own_sides():
    """A perfect FCC crystal in an elongated box: every sphere crystal-like, those at the faces too.

    (The viewer's and the stills' q6 took a cube of the longest side, so the
    spheres near the short sides missed their images and looked fluid.)
    """
    pytest.importorskip("freud")
    from hardspheres.builders import crystal
    from hardspheres.viz.viewer import _q6

    state, box = crystal("fcc", (3, 3, 8), 0.55)
    p = np.asarray(state.positions)[None]
    frames = Frames(np.zeros(1), p, np.zeros_like(p), state.radii, state.masses, state.names, container=box)
    q6 = _q6(frames, box.wrap(p))
    assert q6.shape == (1, state.n) and q6.min() > 0.55
