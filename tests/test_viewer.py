"""The HTML viewer in a real headless Chromium: it starts, draws, plays.

Needs Debian's ``chromium`` (``/usr/bin/chromium``) and the Python
``playwright`` package (its own browser downloads are not used); skipped with
the reason when either is missing.  The screenshot is kept in
``test-artifacts/viewer.png`` for a person to look at.
"""

import base64
import json
import os
import re
from pathlib import Path

import helpers  # its synthetic_frames, with this module's defaults below
import numpy as np
import pytest
from helpers import embedded_data

from hardspheres.events import empty_events
from hardspheres.frames import Frames, frame_indices
from hardspheres.viz.screenshot import CHROMIUM_ARGS
from hardspheres.viz.viewer import write_viewer

CHROMIUM = "/usr/bin/chromium"
ARTIFACTS = Path(__file__).resolve().parent.parent / "test-artifacts"


def synthetic_frames(n=80, n_frames=40, container=10.0, box=None, seed=3):
    """Spheres on straight lines inside a container (or box), with 300 fake events."""
    return helpers.synthetic_frames(
        n, n_frames, container, box, seed, masses=(1.0, 2.0, 4.0), duration=2.0, ball=True, events=300
    )


def test_frame_indices_subsample():
    assert frame_indices(10, 5, max_frames=600).tolist() == list(range(10))
    idx = frame_indices(5000, 5, max_frames=600)
    assert len(idx) == 600 and idx[0] == 0 and idx[-1] == 4999 and np.all(np.diff(idx) > 0)
    # Many spheres: the value budget keeps fewer frames, never fewer than two.
    assert len(frame_indices(600, 1_000_000, max_frames=600, max_values=12_000_000)) == 3
    assert len(frame_indices(600, 10**9)) == 2
    assert frame_indices(1, 10**9).tolist() == [0]


def test_html_is_self_contained(tmp_path):
    frames = synthetic_frames(n=7, n_frames=1000, container=None, box=20.0)
    path = write_viewer(frames, tmp_path / "v.html", title="a <b> & c", max_frames=50)
    html = path.read_text(encoding="utf-8")
    # Nothing fetched from anywhere: no http(s) URL in src/href, scripts inline.
    assert not re.search(r'(src|href)\s*=\s*"(https?:)?//', html)
    assert "a &lt;b&gt; &amp; c" in html
    data = embedded_data(html)
    assert data["nframes"] == 50 and data["nframes_total"] == 1000 and data["n"] == 7
    pos = np.frombuffer(base64.b64decode(data["positions"]), "<f4").reshape(50, 7, 3)
    keep = frame_indices(1000, 7, 50)
    wrapped = frames.positions[keep] - 20.0 * np.floor(frames.positions[keep] / 20.0 + 0.5)
    assert np.allclose(pos, wrapped, atol=1e-5)
    assert np.all(np.abs(pos) <= 10.0 + 1e-5)
    assert data["events"]["n"] == 300 and data["box"] == 20.0 and data["container"] is None


def _launch():
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is missing (apt-get install chromium)")
    sync_api = pytest.importorskip(
        "playwright.sync_api", reason="Python playwright is missing (pip install playwright)"
    )
    return sync_api


def _watched(page, errors):
    """``page``, its console errors, page errors and failed requests appended to ``errors``."""
    page.on(
        "console",
        lambda msg: errors.append(f"console {msg.type}: {msg.text}") if msg.type == "error" else None,
    )
    page.on("pageerror", lambda exc: errors.append(f"page error: {exc}"))
    page.on("requestfailed", lambda req: errors.append(f"request failed: {req.url}"))
    return page


def test_viewer_in_chromium(tmp_path):
    sync_api = _launch()
    from PIL import Image

    frames = synthetic_frames()
    path = write_viewer(frames, tmp_path / "viewer.html", title="synthetic spheres")
    errors = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = _watched(browser.new_page(viewport={"width": 1000, "height": 700}), errors)
            page.goto(path.as_uri())
            page.wait_for_function("window.viewerReady === true", timeout=30_000)
            page.wait_for_timeout(300)
            assert page.locator("#view canvas").count() == 1
            assert page.locator("#message").is_hidden()

            shot = tmp_path / "shot.png"
            page.screenshot(path=str(shot))
            img = np.asarray(Image.open(shot).convert("RGB"))
            assert img.shape == (700, 1000, 3)
            canvas_box = page.locator("#view canvas").bounding_box()
            x0, y0 = int(canvas_box["x"]), int(canvas_box["y"])
            region = img[y0 : y0 + int(canvas_box["height"]), x0 : x0 + int(canvas_box["width"])]
            colours = np.unique(region.reshape(-1, 3), axis=0)
            assert len(colours) > 200, f"canvas looks blank: {len(colours)} colours"
            assert region.std() > 5

            state0 = page.evaluate("({...window.viewerState})")
            time0 = page.locator("#time").inner_text()
            assert state0["playing"] is False and state0["frame"] == 0
            page.click("#play")
            page.wait_for_function(
                f"document.getElementById('time').textContent !== {json.dumps(time0)}", timeout=10_000
            )
            page.wait_for_timeout(700)
            state1 = page.evaluate("({...window.viewerState})")
            assert state1["playing"] is True and state1["time"] > state0["time"]
            assert page.locator("#time").inner_text() != time0
            page.click("#play")
            assert page.evaluate("window.viewerState.playing") is False

            # The slider moves time; the colour switch redraws the legend.
            page.locator("#slider").fill("20")
            page.wait_for_function("window.viewerState.frame === 20", timeout=5_000)
            assert abs(page.evaluate("window.viewerState.time") - frames.times[20]) < 1e-9
            page.select_option("#colorby", "mass")
            assert "mass" in page.locator("#legend").inner_text()
            page.select_option("#colorby", "speed")
            page.wait_for_timeout(200)
            ARTIFACTS.mkdir(exist_ok=True)
            page.screenshot(path=str(ARTIFACTS / "viewer.png"))

            # A single frame of three equal spheres in a box, no events: still draws, play is inert.
            one = synthetic_frames(n=3, n_frames=1, container=None, box=6.0)
            one.masses = np.ones(3)
            one.events = empty_events()
            page2 = _watched(browser.new_page(viewport={"width": 600, "height": 400}), errors)
            page2.goto(write_viewer(one, tmp_path / "one.html").as_uri())
            page2.wait_for_function("window.viewerReady === true", timeout=30_000)
            page2.click("#play")
            page2.wait_for_timeout(200)
            assert page2.evaluate("({...window.viewerState})") == {"frame": 0, "time": 0.0, "playing": False}
            page2.select_option("#colorby", "mass")
            assert "all equal" in page2.locator("#legend").inner_text()
        finally:
            browser.close()
    assert not errors, errors


def test_page_is_a_packaged_file_and_render_does_not_import_the_viewer():
    """The page lives in viz/_static/viewer.html (package data), not in a Python string."""
    import subprocess
    import sys
    from importlib import resources

    page = (resources.files("hardspheres.viz") / "_static" / "viewer.html").read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>") and "__DATA__" in page and "__JS__" in page
    viewer_src = (resources.files("hardspheres.viz") / "viewer.py").read_text(encoding="utf-8")
    assert "<!DOCTYPE" not in viewer_src
    code = "import sys, hardspheres.viz.render; print('hardspheres.viz.viewer' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def _fcc_frames(k=3, a=2.0, n_frames=3, jitter=0.0, seed=1):
    """A perfect (or jittered) FCC lattice of 4 k^3 unit-diameter spheres in a periodic box."""
    rng = np.random.default_rng(seed)
    base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    cells = np.array([[i, j, m] for i in range(k) for j in range(k) for m in range(k)])
    pos = ((cells[:, None, :] + base[None]) * a).reshape(-1, 3) - 0.5 * k * a
    n = len(pos)
    positions = np.stack([pos + jitter * rng.normal(size=pos.shape) for _ in range(n_frames)])
    return Frames(
        times=np.arange(n_frames, dtype=float),
        positions=positions,
        velocities=rng.normal(size=(n_frames, n, 3)),
        radii=np.full(n, 0.7),
        masses=np.ones(n),
        names=[f"s{i}" for i in range(n)],
        box=k * a,
    )


def test_viewer_colours_by_q6(tmp_path):
    pytest.importorskip("freud")
    frames = _fcc_frames(jitter=0.0)
    data = embedded_data(write_viewer(frames, tmp_path / "q.html", color_by="q6").read_text())
    sc = data["scalar"]
    assert data["color_by"] == "q6" and sc["name"] == "q6"
    q6 = np.frombuffer(base64.b64decode(sc["values"]), "<f4").reshape(data["nframes"], data["n"])
    assert np.allclose(q6, 0.5745, atol=1e-3)  # FCC, 12 neighbours (Steinhardt q6 = 0.5745)
    assert sc["range"] == [0.25, 0.6]  # fixed, so that pictures compare
    # a liquid-like (strongly jittered) lattice: lower q6 than the crystal
    liquid = embedded_data(
        write_viewer(_fcc_frames(jitter=0.4), tmp_path / "l.html", color_by="q6").read_text()
    )
    ql = np.frombuffer(base64.b64decode(liquid["scalar"]["values"]), "<f4")
    assert ql.mean() < 0.5
    # speed and mass colouring carry no scalar; a bad colour names the choices
    assert embedded_data(write_viewer(frames, tmp_path / "s.html").read_text())["scalar"] is None
    with pytest.raises(ValueError, match="speed, mass, q6"):
        write_viewer(frames, tmp_path / "x.html", color_by="q7")


def test_viewer_q6_in_a_spherical_container(tmp_path):
    pytest.importorskip("freud")
    frames = synthetic_frames(n=40, n_frames=5)
    data = embedded_data(write_viewer(frames, tmp_path / "c.html", color_by="q6").read_text())
    q6 = np.frombuffer(base64.b64decode(data["scalar"]["values"]), "<f4")
    assert q6.shape == (5 * 40,) and np.all((q6 >= 0) & (q6 <= 1))


def test_q6_page_in_chromium(tmp_path):
    pytest.importorskip("freud")
    sync_api = _launch()
    path = write_viewer(_fcc_frames(jitter=0.1), tmp_path / "q.html", color_by="q6")
    errors = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = _watched(browser.new_page(viewport={"width": 800, "height": 500}), errors)
            page.goto(path.as_uri())
            page.wait_for_function("window.viewerReady === true", timeout=30_000)
            assert "bond order q6" in page.locator("#legend").inner_text()
            assert page.locator("#colorby option").all_inner_texts() == ["speed", "mass", "q6"]
            page.select_option("#colorby", "speed")
            assert "speed" in page.locator("#legend").inner_text()
        finally:
            browser.close()
    assert not errors, errors


@pytest.mark.parametrize("size", [(960, 640), (600, 400)])
def test_the_control_bar_fits_the_window(tmp_path, size):
    """At the screenshot's default size (960 x 640) the bar's last control ("view") was cut off at
    the right edge; the bar now wraps, and the view takes what it leaves."""
    import inspect

    from hardspheres.viz.screenshot import screenshot

    assert inspect.signature(screenshot).parameters["size"].default == (960, 640)
    sync_api = _launch()
    path = write_viewer(synthetic_frames(), tmp_path / "viewer.html", title="synthetic spheres")
    errors = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = _watched(browser.new_page(viewport={"width": size[0], "height": size[1]}), errors)
            page.goto(path.as_uri())
            page.wait_for_function("window.viewerReady === true", timeout=30_000)
            boxes = page.evaluate(
                "[...document.querySelectorAll('#bar > *')].map(e => {"
                " const r = e.getBoundingClientRect(); return [e.id || e.textContent.trim(), r.left, r.top, r.right, r.bottom]; })"
            )
            view = page.locator("#view").bounding_box()
            bar = page.locator("#bar").bounding_box()
        finally:
            browser.close()
    assert not errors, errors
    for name, left, top, right, bottom in boxes:
        assert 0 <= left and right <= size[0] and 0 <= top and bottom <= size[1], (
            name,
            left,
            top,
            right,
            bottom,
        )
    assert view["y"] + view["height"] <= bar["y"] + 0.5 and view["height"] > size[1] / 2
