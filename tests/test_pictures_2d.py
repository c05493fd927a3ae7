"""Pictures and transport of disks: the flat viewer (orthographic, colour by psi6), render, plot,
and D in 2-D (issue 24)."""

from __future__ import annotations

import base64
import os

import numpy as np
import pytest
from helpers import embedded_data

import hardspheres as hs
from hardspheres.analysis.transport import MSD, VACF
from hardspheres.builders import hexagonal
from hardspheres.cli.commands import main
from hardspheres.io.trajectory import frames_from_simulation
from hardspheres.maxwell import ks_distance, maxwell_boltzmann, reduced_density, speed_cdf, speed_density
from hardspheres.viz.render import render_still
from hardspheres.viz.screenshot import CHROMIUM_ARGS
from hardspheres.viz.viewer import write_viewer

CHROMIUM = "/usr/bin/chromium"


@pytest.fixture(scope="module")
def crystal_frames():
    """A hexagonal crystal of 64 disks at packing 0.75 in its sqrt(3)/2 box, run a little."""
    state, box = hexagonal((8, 8), 0.75, seed=2)
    sim = hs.Simulation(state, box)
    return frames_from_simulation(sim, until=0.5, every=0.05)


@pytest.fixture(scope="module")
def circle_frames():
    circle = hs.CircularContainer(8.0)
    sim = hs.Simulation(hs.random_spheres(60, 0.4, circle, seed=4), circle)
    return frames_from_simulation(sim, until=1.0, every=0.1)


def _floats(b64, shape):
    return np.frombuffer(base64.b64decode(b64), "<f4").reshape(shape)


def test_viewer_page_of_disks_is_flat_and_colours_by_psi6(crystal_frames, tmp_path):
    pytest.importorskip("freud")
    data = embedded_data(write_viewer(crystal_frames, tmp_path / "d.html", color_by="psi6").read_text())
    f, n = data["nframes"], data["n"]
    assert data["dimensions"] == 2 and data["title"] == "64 hard disks"
    sides = crystal_frames.container.sides
    assert data["sides"] == pytest.approx([sides[0], sides[1], 0.0]) and data["box"] is None
    pos = _floats(data["positions"], (f, n, 3))
    assert np.all(pos[..., 2] == 0.0)  # disks at z = 0, drawn in the plane
    assert np.all(np.abs(pos[..., :2]) <= np.array(sides) / 2 + 1e-5)
    sc = data["scalar"]
    assert sc["name"] == "psi6" and sc["range"] == [0.0, 1.0]
    psi = _floats(sc["values"], (f, n))
    assert psi[0].min() > 0.999  # the perfect crystal at t = 0
    assert 0.5 < psi[-1].mean() <= 1.0  # still ordered after a few collisions per disk


def test_viewer_of_disks_in_a_circle_and_bad_colours(circle_frames, tmp_path):
    pytest.importorskip("freud")
    data = embedded_data(write_viewer(circle_frames, tmp_path / "c.html", color_by="psi6").read_text())
    assert data["container"] == 8.0 and data["sides"] is None and data["dimensions"] == 2
    psi = _floats(data["scalar"]["values"], (data["nframes"], data["n"]))
    assert np.all((psi >= 0) & (psi <= 1 + 1e-6))
    with pytest.raises(ValueError, match="q6' is for spheres"):
        write_viewer(circle_frames, tmp_path / "x.html", color_by="q6")
    spheres = frames_from_simulation(
        hs.Simulation(hs.random_spheres(20, 0.2, container=6.0, seed=1), hs.SphericalContainer(6.0)),
        until=0.2,
        every=0.1,
    )
    with pytest.raises(ValueError, match="psi6' is for disks"):
        write_viewer(spheres, tmp_path / "y.html", color_by="psi6")


def test_disk_page_in_chromium(crystal_frames, tmp_path):
    pytest.importorskip("freud")
    if not os.path.exists(CHROMIUM):
        pytest.skip(f"{CHROMIUM} is missing (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="Python playwright is missing")
    from PIL import Image

    path = write_viewer(crystal_frames, tmp_path / "d.html", color_by="psi6")
    errors = []
    with sync_api.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_page(viewport={"width": 800, "height": 600})
            page.on("pageerror", lambda exc: errors.append(f"page error: {exc}"))
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.goto(path.as_uri())
            page.wait_for_function("window.viewerReady === true", timeout=30_000)
            page.wait_for_timeout(300)
            assert "64 disks · periodic box, sides" in page.locator("#facts").inner_text()
            assert "|psi6|" in page.locator("#legend").inner_text()
            assert page.locator("#colorby option").all_inner_texts() == ["speed", "mass", "psi6"]
            assert page.locator("#cut").is_hidden()  # a plane has no cut-away
            shot = tmp_path / "shot.png"
            page.screenshot(path=str(shot))
            img = np.asarray(Image.open(shot).convert("RGB")).astype(int)
            box = page.locator("#view canvas").bounding_box()
            x0, y0, w, h = (int(box[k]) for k in ("x", "y", "width", "height"))
            region = img[y0 : y0 + h, x0 : x0 + w]
            # seen from above, the crystal is a patch of yellow (|psi6| = 1, viridis' top)
            # in the middle of the canvas, not a perspective view with the dark background there
            centre = region[h // 2 - 20 : h // 2 + 20, w // 2 - 20 : w // 2 + 20].reshape(-1, 3)
            yellow = (centre[:, 0] > 180) & (centre[:, 1] > 180) & (centre[:, 2] < 120)
            assert yellow.mean() > 0.4, yellow.mean()
            page.select_option("#colorby", "speed")
            assert "speed" in page.locator("#legend").inner_text()
        finally:
            browser.close()
    assert not errors, errors


def test_render_still_of_disks(crystal_frames, circle_frames, tmp_path):
    from PIL import Image

    for frames, name in ((crystal_frames, "box.png"), (circle_frames, "circle.png")):
        out = render_still(frames, tmp_path / name, size=(640, 360))
        img = np.asarray(Image.open(out).convert("RGB"))
        assert img.shape == (360, 640, 3) and len(np.unique(img.reshape(-1, 3), axis=0)) > 50
    with pytest.raises(ValueError, match="cut is for spheres"):
        render_still(circle_frames, tmp_path / "cut.png", cut=0.0)
    pytest.importorskip("freud")
    out = render_still(crystal_frames, tmp_path / "psi6.png", size=(640, 360), color_by="psi6", time=0.0)
    img = np.asarray(Image.open(out).convert("RGB")).astype(int)
    yellow = (img[..., 0] > 200) & (img[..., 1] > 200) & (img[..., 2] < 100)  # |psi6| = 1: viridis' top
    assert yellow.sum() > 2000


def test_commands_draw_disks(tmp_path, capsys):
    pytest.importorskip("freud")
    scn = tmp_path / "d.txt"
    assert main(["generate", "--n", "60", "--box", "12", f"{12 * np.sqrt(3) / 2}", "--packing", "0.5"]) == 0
    scn.write_text(capsys.readouterr().out)
    where = [str(scn), "--box", "12", f"{12 * np.sqrt(3) / 2}", "--until", "0.5"]
    assert main(["view", *where, "--color", "psi6", "-o", str(tmp_path / "v.html")]) == 0
    assert "(60 disks, " in capsys.readouterr().out
    assert main(["render", *where, "--color", "psi6", "-o", str(tmp_path / "r.png")]) == 0
    assert main(["plot", "speeds", *where, "-o", str(tmp_path / "s.png")]) == 0
    assert main(["plot", "gr", *where, "-o", str(tmp_path / "g.png")]) == 0
    assert main(["plot", "conservation", *where, "-o", str(tmp_path / "c.png")]) == 0
    # in a circle: L is Lz alone (numpy's cross product of 2-vectors is not used)
    circle = tmp_path / "c.txt"
    circle.write_text(hs.random_spheres(40, 0.4, hs.CircularContainer(7.0), seed=1).to_text())
    assert (
        main(
            [
                "plot",
                "conservation",
                str(circle),
                "--circle",
                "7",
                "--until",
                "1",
                "-o",
                str(tmp_path / "l.png"),
            ]
        )
        == 0
    )
    for name in ("v.html", "r.png", "s.png", "g.png", "c.png", "l.png"):
        assert (tmp_path / name).stat().st_size > 1000


def test_maxwell_in_two_dimensions():
    v = np.linspace(0.0, 12.0, 24001)
    for d in (2, 3):
        f = speed_density(v, 1.5, 2.0, dimensions=d)
        assert np.trapezoid(f, v) == pytest.approx(1.0, abs=1e-6)
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(v))])
        assert np.max(np.abs(cdf - speed_cdf(v, 1.5, 2.0, dimensions=d))) < 1e-7
        assert np.trapezoid(reduced_density(v, dimensions=d), v) == pytest.approx(1.0, abs=1e-6)
    # speeds of a 2-D draw follow the Rayleigh law, not the 3-D one
    vel = maxwell_boltzmann(np.random.default_rng(0), np.ones(20000), kT=1.0, dimensions=2)
    speeds = np.linalg.norm(vel, axis=1)
    assert ks_distance(speeds, dimensions=2) < 0.015 < ks_distance(speeds, dimensions=3)


def test_diffusion_of_disks_uses_two_dimensions():
    """MSD = 4 D t and D = 1/2 int C dt: the two agree for a dilute disk fluid."""
    box = hs.PeriodicBox((20.0, 20.0))
    sim = hs.Simulation(hs.random_spheres(200, 0.1, box, seed=5), box)
    sim.run(collisions=2000)
    frames = frames_from_simulation(sim, until=sim.time + 60.0, every=0.02)
    msd = MSD().compute(frames)
    vacf = VACF().compute(frames)
    d_msd, e_msd = msd.diffusion()
    d_vacf, e_vacf = vacf.diffusion()
    assert d_vacf == pytest.approx(d_msd, rel=0.15), (d_msd, e_msd, d_vacf, e_vacf)
    # C(0) = <v.v> = 2 kT/m over two components (kT = 1)
    assert vacf.c[0] == pytest.approx(2.0 * (sim.n - 1) / sim.n, rel=1e-6)
