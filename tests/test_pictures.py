"""Movies (hardspheres.viz.render) and plots (hardspheres.viz.plots) from synthetic frames."""

import csv
import io
import shutil
import subprocess
import sys

import numpy as np
import pytest

pytest.importorskip("matplotlib")
from helpers import synthetic_frames  # noqa: E402
from PIL import Image, ImageSequence  # noqa: E402

from hardspheres import maxwell  # noqa: E402
from hardspheres.viz import plots  # noqa: E402
from hardspheres.viz.render import render_movie  # noqa: E402


def assert_not_blank(img, min_colours=20):
    a = np.asarray(img.convert("RGB"))
    colours = len(np.unique(a.reshape(-1, 3), axis=0))
    assert colours >= min_colours, f"image looks blank: {colours} colours"
    assert a.std() > 5.0


def test_movie_gif(tmp_path, capsys):
    frames = synthetic_frames()
    out = render_movie(frames, tmp_path / "run.gif", fps=10, size=(320, 240))
    assert out == tmp_path / "run.gif" and out.stat().st_size > 0
    assert capsys.readouterr().err == ""  # no progress bar: stderr is not a terminal
    with Image.open(out) as im:
        assert im.size == (320, 240)
        images = [f.convert("RGB") for f in ImageSequence.Iterator(im)]
    assert len(images) == len(frames.times)
    for img in (images[0], images[len(images) // 2], images[-1]):
        assert img.size == (320, 240)
        assert_not_blank(img)
    assert np.any(np.asarray(images[0]) != np.asarray(images[-1]))  # the spheres moved


def test_movie_box_by_mass_subsampled(tmp_path):
    frames = synthetic_frames(n=30, n_frames=30, container=None, box=20.0)
    out = render_movie(
        frames,
        tmp_path / "box.gif",
        size=(200, 160),
        max_frames=5,
        color_by="mass",
        title="box",
        progress=False,
    )
    with Image.open(out) as im:
        assert im.size == (200, 160) and im.n_frames == 5
        assert_not_blank(im)


def test_movie_progress_on_a_terminal(tmp_path, monkeypatch):
    class Tty(io.StringIO):
        def isatty(self):
            return True

    err = Tty()
    monkeypatch.setattr(sys, "stderr", err)
    render_movie(synthetic_frames(n=5, n_frames=3), tmp_path / "p.gif", size=(120, 100))
    assert "3/3" in err.getvalue() or "frame" in err.getvalue()


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not installed")
def test_movie_mp4(tmp_path):
    frames = synthetic_frames()
    out = render_movie(frames, tmp_path / "run.mp4", fps=10, size=(320, 240), progress=False)
    assert out.stat().st_size > 0
    probe = subprocess.run(
        [
            "ffprobe",
            "-v",
            "error",
            "-select_streams",
            "v:0",
            "-count_frames",
            "-show_entries",
            "stream=width,height,nb_read_frames",
            "-of",
            "csv=p=0",
            str(out),
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    width, height, count = (int(x) for x in probe.stdout.strip().split(",")[:3])
    assert (width, height, count) == (320, 240, len(frames.times))
    png = tmp_path / "f.png"
    subprocess.run(
        [
            "ffmpeg",
            "-v",
            "error",
            "-y",
            "-i",
            str(out),
            "-vf",
            r"select=eq(n\,5)",
            "-frames:v",
            "1",
            str(png),
        ],
        check=True,
    )
    with Image.open(png) as img:
        assert img.size == (320, 240)
        assert_not_blank(img)


def test_movie_without_ffmpeg_says_so(tmp_path, monkeypatch):
    from matplotlib import animation

    monkeypatch.setattr(animation.FFMpegWriter, "isAvailable", classmethod(lambda cls: False))
    with pytest.raises(RuntimeError, match="ffmpeg"):
        render_movie(synthetic_frames(), tmp_path / "x.mp4")
    with pytest.raises(ValueError, match="format"):
        render_movie(synthetic_frames(), tmp_path / "x.avi2")
    assert not (tmp_path / "x.mp4").exists()


def check_png(path, size=plots.SIZE):
    with Image.open(path) as img:
        assert img.format == "PNG" and img.size == tuple(size)
        assert_not_blank(img, min_colours=50)


@pytest.mark.parametrize("where", ["container", "box"])
def test_plot_conservation(tmp_path, where):
    frames = synthetic_frames(
        container=10.0 if where == "container" else None, box=20.0 if where == "box" else None
    )
    out = plots.plot_conservation(frames, tmp_path / "c.png")
    assert out == tmp_path / "c.png"
    check_png(out)


@pytest.mark.parametrize("equal", [True, False])
def test_plot_speeds(tmp_path, equal):
    frames = synthetic_frames(n=400, n_frames=5, masses=None if equal else (1.0, 3.0))
    check_png(plots.plot_speeds(frames, tmp_path / "s.png"))
    check_png(
        plots.plot_speeds(frames, tmp_path / "s2.png", kT=1.0, start=1, size=(640, 480)), size=(640, 480)
    )


def test_maxwell_densities_are_normalised():
    integrate = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has only trapz
    v = np.linspace(0.0, 30.0, 200001)
    for kT, m in [(1.0, 1.0), (2.5, 0.3)]:
        f = maxwell.speed_density(v, kT, m)
        assert integrate(f, v) == pytest.approx(1.0, abs=1e-6)
        assert integrate(0.5 * m * v**2 * f, v) == pytest.approx(1.5 * kT, rel=1e-6)
    assert integrate(maxwell.reduced_density(v), v) == pytest.approx(1.0, abs=1e-6)


def test_plot_eos(tmp_path):
    phi = np.array([0.1, 0.2, 0.3, 0.4, 0.45])
    z_cs = plots.carnahan_starling(phi)
    z = z_cs * (1 + np.array([0.0, 3e-4, 2.5e-3, 4.4e-3, 3e-4]))
    csv_path = tmp_path / "eos.csv"
    with open(csv_path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["phi", "Z", "Z_err", "Z_CS", "rel_diff", "gamma", "gamma_from_Z", "gamma_rel_diff"])
        for p, zz, zc in zip(phi, z, z_cs):
            g = 6 * (zz - 1) / np.sqrt(np.pi)
            w.writerow([p, zz, 1e-3 * zz, zc, zz / zc - 1, g * 1.001, g, 1e-3])
    out = plots.plot_eos(csv_path, tmp_path / "eos.png")
    check_png(out)
    assert plots.carnahan_starling(0.0) == 1.0

    bad = tmp_path / "bad.csv"
    bad.write_text("phi,Z\n0.1,1.5\n")
    with pytest.raises(ValueError, match="Z_err"):
        plots.plot_eos(bad, tmp_path / "bad.png")
