"""Headless movies of a run: matplotlib (Agg) 3-D scatter to GIF or MP4.

::

    from hardspheres.render import render_movie
    render_movie(frames, "run.gif", fps=20, size=(640, 480))
    render_movie(frames, "run.mp4")            # needs ffmpeg on PATH
    render_still(frames, "last.png")           # one frame (the last, or time=T)

Spheres are drawn as markers whose size follows their radii (orthographic
projection, so the scale is the same everywhere), coloured by speed (or by
mass) with a colour bar, inside a wireframe of the spherical container (or
the edges of the periodic box), with the time written in the corner.  No
display is needed: the figure is drawn by Agg and never shown.
"""

import shutil
import sys
import time as _time
from pathlib import Path

import numpy as np

from .viewer import frame_indices


class _Progress:
    """Progress on stderr, only when stderr is a terminal (tqdm if installed)."""

    def __init__(self, total, enabled, label="rendering"):
        self.total, self.n, self.bar, self.text = total, 0, None, False
        if not enabled or not _isatty(sys.stderr):
            return
        try:
            from tqdm import tqdm
        except ImportError:
            self.text, self.label, self.start, self.shown = True, label, _time.monotonic(), 0.0
            self._show()
        else:
            self.bar = tqdm(total=total, desc=label, unit="frame", file=sys.stderr, leave=False)

    def _show(self):
        done = self.n / self.total if self.total else 1.0
        width = 30
        fill = int(round(done * width))
        sys.stderr.write(f"\r{self.label} [{'#' * fill}{'.' * (width - fill)}] {self.n}/{self.total}")
        sys.stderr.flush()

    def update(self):
        self.n += 1
        if self.bar is not None:
            self.bar.update(1)
        elif self.text:
            now = _time.monotonic()
            if now - self.shown > 0.1 or self.n == self.total:
                self.shown = now
                self._show()

    def close(self):
        if self.bar is not None:
            self.bar.close()
        elif self.text:
            sys.stderr.write("\r" + " " * (len(self.label) + 45) + "\r")
            sys.stderr.flush()


def _isatty(stream):
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def _writer(path, fps, dpi):
    from matplotlib import animation

    suffix = path.suffix.lower()
    if suffix == ".gif":
        return animation.PillowWriter(fps=fps)
    if suffix in (".mp4", ".m4v", ".mov", ".mkv", ".webm"):
        if not animation.FFMpegWriter.isAvailable():
            raise RuntimeError(
                f"render_movie: writing {suffix} needs the ffmpeg program, which was not found "
                f"(looked for {shutil.which('ffmpeg') or 'ffmpeg'!r} on PATH); install ffmpeg "
                "(e.g. apt-get install ffmpeg) or write a .gif, which needs only Pillow")
        codec = "libvpx-vp9" if suffix == ".webm" else "libx264"
        extra = ["-pix_fmt", "yuv420p"] if codec == "libx264" else None
        return animation.FFMpegWriter(fps=fps, codec=codec, extra_args=extra)
    raise ValueError(f"render_movie: unknown movie format {path.suffix!r} (use .gif or .mp4)")


def _extent(frames, pos):
    if frames.container is not None:
        return float(frames.container)
    if frames.box is not None:
        return 0.5 * float(frames.box)
    r = float(np.max(frames.radii)) if len(frames.radii) else 0.0
    e = float(np.max(np.abs(pos))) + r if pos.size else 1.0
    return e if np.isfinite(e) and e > 0 else 1.0


def _draw_container(ax, frames):
    style = dict(color="0.45", linewidth=0.5, alpha=0.35)
    if frames.container is not None:
        r = float(frames.container)
        u = np.linspace(0, 2 * np.pi, 25)
        v = np.linspace(0, np.pi, 13)
        ax.plot_wireframe(r * np.outer(np.cos(u), np.sin(v)), r * np.outer(np.sin(u), np.sin(v)),
                          r * np.outer(np.ones_like(u), np.cos(v)), rstride=2, cstride=2, **style)
    elif frames.box is not None:
        h = 0.5 * float(frames.box)
        corners = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)])
        for a in range(8):
            for b in range(a + 1, 8):
                if np.sum(corners[a] != corners[b]) == 1:
                    ax.plot(*corners[[a, b]].T, **style)


def _pixels_per_unit(fig, ax):
    """Screen pixels per data length unit of the (orthographic, isotropic) 3-D axes."""
    from mpl_toolkits.mplot3d import proj3d

    fig.canvas.draw()
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    x, y, _ = proj3d.proj_transform(pts[:, 0], pts[:, 1], pts[:, 2], ax.get_proj())
    disp = ax.transData.transform(np.column_stack([x, y]))
    a = (disp[1:] - disp[0]).T  # 2 x 3: screen images of the unit vectors
    return float(np.mean(np.linalg.svd(a, compute_uv=False)))


def _scene(frames, size, keep, color_by, title, dpi):
    """The figure a movie or a still draws, and ``show(f)`` that puts frame ``keep[f]`` on it."""
    from matplotlib import colors
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    width, height = (int(s) for s in size)
    pos = np.asarray(frames.positions, float)[keep]
    vel = np.asarray(frames.velocities, float)[keep]
    times = np.asarray(frames.times, float)[keep]
    radii = np.asarray(frames.radii, float)
    masses = np.asarray(frames.masses, float)
    if frames.box is not None:
        box = float(frames.box)
        pos = pos - box * np.floor(pos / box + 0.5)
    speeds = np.linalg.norm(vel, axis=2)
    extent = _extent(frames, pos)

    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes([0.0, 0.0, 0.84, 1.0], projection="3d")
    ax.set_proj_type("ortho")
    lim = extent if frames.box is not None else 1.02 * extent
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(-lim, lim)
    # The axes' own cube is the box; a sphere's outline is smaller, so zoom in.
    ax.set_box_aspect((1, 1, 1), zoom=1.0 if frames.box is not None else 1.2)
    ax.set_axis_off()
    _draw_container(ax, frames)

    if color_by == "speed":
        finite = speeds[np.isfinite(speeds)]
        hi = float(np.percentile(finite, 99.5)) if finite.size else 1.0
        norm = colors.Normalize(0.0, hi if hi > 0 else 1.0)
        values = speeds
        label = "speed"
    else:
        lo, hi = (float(masses.min()), float(masses.max())) if masses.size else (0.0, 1.0)
        norm = colors.Normalize(lo, hi if hi > lo else lo + 1.0)
        values = np.broadcast_to(masses, speeds.shape)
        label = "mass"

    scale = _pixels_per_unit(fig, ax)
    diameter_pt = 2.0 * radii * scale * 72.0 / dpi
    sc = ax.scatter(pos[0, :, 0], pos[0, :, 1], pos[0, :, 2], s=np.maximum(diameter_pt, 0.5) ** 2,
                    c=values[0], cmap="viridis", norm=norm, edgecolors="0.15", linewidths=0.3,
                    depthshade=True, alpha=1.0)
    cax = fig.add_axes([0.87, 0.2, 0.025, 0.6])
    fig.colorbar(sc, cax=cax, label=label)
    header = f"{title}\n" if title else ""
    label_t = fig.text(0.02, 0.97, "", va="top", ha="left", family="monospace", fontsize=10)

    def show(f):
        sc._offsets3d = (pos[f, :, 0], pos[f, :, 1], pos[f, :, 2])
        sc.set_array(values[f])
        label_t.set_text(f"{header}t = {times[f]:.6g}")

    return fig, show


def _check(size, color_by, what):
    width, height = (int(s) for s in size)
    if width <= 0 or height <= 0:
        raise ValueError(f"{what}: bad size {size}")
    if color_by not in ("speed", "mass"):
        raise ValueError(f"{what}: color_by must be 'speed' or 'mass'")


def render_movie(frames, path, fps=20, size=(640, 480), progress=True, *, max_frames=None,
                 color_by="speed", title=None, dpi=100):
    """Render ``frames`` to a movie file and return ``path``.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: ``.gif`` (Pillow) or ``.mp4`` (ffmpeg; a :class:`RuntimeError`
            says so when ffmpeg is missing; ``.mov``, ``.mkv``, ``.webm``
            also go through ffmpeg).
        fps: frames per second of the movie.
        size: ``(width, height)`` in pixels (even numbers for mp4).
        progress: show a progress bar on stderr when it is a terminal.
        max_frames: render at most this many frames, evenly spaced (default:
            all).
        color_by: ``"speed"`` or ``"mass"``.
        title: text above the time label.
        dpi: resolution used to lay out the figure (the pixel size is
            ``size`` whatever it is).

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    _check(size, color_by, "render_movie")
    width, height = (int(s) for s in size)
    if path.suffix.lower() != ".gif" and (width % 2 or height % 2):
        raise ValueError(f"render_movie: {path.suffix} needs an even width and height, not {size}")
    writer = _writer(path, fps, dpi)

    n_frames = len(frames.times)
    if n_frames == 0:
        raise ValueError("render_movie: no frames")
    keep = frame_indices(n_frames, 0, max_frames or n_frames)
    fig, show = _scene(frames, size, keep, color_by, title, dpi)

    bar = _Progress(len(keep), progress)
    try:
        from .fileio import atomic_path
        with atomic_path(path) as tmp, writer.saving(fig, tmp, dpi):
            for f in range(len(keep)):
                show(f)
                writer.grab_frame()
                bar.update()
    finally:
        bar.close()
    return path


def render_still(frames, path, time=None, size=(640, 480), *, color_by="speed", title=None,
                 dpi=100):
    """Draw one frame of ``frames``, as :func:`render_movie` draws it, to a PNG.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: the ``.png`` to write.
        time: draw the frame nearest this time [time] (default: the last).
        size: ``(width, height)`` in pixels.
        color_by: ``"speed"`` or ``"mass"``.
        title: text above the time label.
        dpi: resolution used to lay out the figure.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    _check(size, color_by, "render_still")
    if path.suffix.lower() != ".png":
        raise ValueError(f"render_still: writes a .png, not {path.suffix or path.name!r}")
    times = np.asarray(frames.times, float)
    if len(times) == 0:
        raise ValueError("render_still: no frames")
    if time is None:
        k = len(times) - 1
    elif not np.isfinite(time):
        raise ValueError(f"render_still: time must be a finite number, got {time!r}")
    else:
        k = int(np.argmin(np.abs(times - float(time))))
    fig, show = _scene(frames, size, np.array([k]), color_by, title, dpi)
    show(0)
    from .fileio import atomic_write
    with atomic_write(path, "wb") as fh:
        fig.savefig(fh, dpi=dpi, format="png")
    return path
