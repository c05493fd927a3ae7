"""Headless movies and stills of a run: shaded spheres drawn by matplotlib (Agg).

::

    from hardspheres.viz.render import render_movie, render_still
    render_movie(frames, "run.gif", fps=20, size=(960, 540))
    render_movie(frames, "run.mp4")            # needs ffmpeg on PATH
    render_still(frames, "last.png")           # one frame (the last, or time=T)
    render_still(frames, "inside.png", cut=0.0)  # only spheres with z <= 0
    render_still(frames, "side.png", cut=0.0, cut_axis="x", color_by="q6")  # x <= 0: a slab side-on

Spheres are shaded disks at their true radii (orthographic projection, so
the scale is the same everywhere; nearer spheres hide farther ones),
coloured by speed, by mass, by the local packing fraction (``"density"``: clusters of a granular
gas, in a periodic box) or by their bond order q6 (freud) with a colour bar, inside the outline of the
spherical container (or the edges of the periodic box), captioned with N,
the packing fraction and the time.  Disks (a 2-D box or a circle) are drawn
flat, as seen from above (x right, y up), with a thin dark rim and no
highlight, inside the circle or the box's four edges.  The default sizes
suit 16:9 slides.  No display is needed: the figure is drawn by Agg and
never shown.
"""

from __future__ import annotations

import os
import shutil
import time as _time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import PictureError
from ..frames import frame_indices
from ..progress import Progress, duration
from . import cut_axis_index

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..frames import Frames


def _writer(path: Path, fps: int, dpi: int) -> Any:
    from ..extras import need

    animation = need("matplotlib.animation", "a movie")

    suffix = path.suffix.lower()
    if suffix == ".gif":
        return animation.PillowWriter(fps=fps)
    if suffix in (".mp4", ".m4v", ".mov", ".mkv", ".webm"):
        if not animation.FFMpegWriter.isAvailable():
            raise RuntimeError(
                f"render_movie: writing {suffix} needs the ffmpeg program, which was not found "
                f"(looked for {shutil.which('ffmpeg') or 'ffmpeg'!r} on PATH); install ffmpeg "
                "(e.g. apt-get install ffmpeg) or write a .gif, which needs only Pillow"
            )
        codec = "libvpx-vp9" if suffix == ".webm" else "libx264"
        extra = ["-pix_fmt", "yuv420p"] if codec == "libx264" else None
        return animation.FFMpegWriter(fps=fps, codec=codec, extra_args=extra)
    raise PictureError(f"render_movie: unknown movie format {path.suffix!r} (use .gif or .mp4)")


#: The viewing direction, azimuth and elevation [degrees] of the camera (z up).
AZIMUTH, ELEVATION = -60.0, 22.0
#: The camera's azimuth [degrees] with a cut normal to x, y, z, looking at the cut's face
#: (from +x, from +y, from above), most squarely at a cut along x or y.
CUT_AZIMUTH = (-30.0, 60.0, AZIMUTH)


def _camera(
    azimuth: float = AZIMUTH, elevation: float = ELEVATION
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit vectors ``(right, up, towards_camera)`` of an orthographic view, z up."""
    a, e = np.radians(azimuth), np.radians(elevation)
    d = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.cross([0.0, 0.0, 1.0], d)
    right /= np.linalg.norm(right)
    return right, np.cross(d, right), d


def packing_fraction(frames: Frames) -> float | None:
    """Volume fraction the spheres fill in the container or box (``None`` in open space)."""
    if frames.container is None:
        return None
    from ..containers import packing_fraction as of_radii

    return of_radii(frames.radii, frames.container)


def _draw_container(
    ax: Axes, frames: Frames, right: np.ndarray, up: np.ndarray, cut: float | None, axis: int
) -> None:
    if frames.container is None:
        return
    style: dict[str, Any] = dict(color="0.45", linewidth=0.8, alpha=0.6)
    for line, dashed in frames.container.outline(right, up, cut, axis):
        ax.plot(line[:, 0], line[:, 1], **(dict(style, linestyle="--") if dashed else style))


def _scene(
    frames: Frames,
    size: tuple[int, int],
    keep: np.ndarray,
    color_by: str,
    title: str | None,
    dpi: int,
    cut: float | None = None,
    cut_axis: str = "z",
) -> tuple[Figure, Callable[[int], None]]:
    """The figure a movie or a still draws, and ``show(f)`` that puts frame ``keep[f]`` on it.

    Spheres are shaded disks (a dark rim, the body, a highlight towards the
    light at the upper left) drawn far to near in an orthographic view, so
    nearer spheres hide farther ones.  ``cut`` keeps only the spheres whose
    centre has ``z <= cut`` (a cut-away that shows the inside), or ``x`` or
    ``y`` with ``cut_axis``; the camera then looks at the cut's face
    (:data:`CUT_AZIMUTH`).

    Longer than 80 lines: the figure and the ``show`` closure that draws on
    it share their arrays and artists, and its annotated signature takes a
    line per parameter.
    """
    from ..extras import need

    need("matplotlib", "a picture")
    from matplotlib import cm, colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    width, height = (int(s) for s in size)
    vel = np.asarray(frames.velocities, float)[keep]
    times = np.asarray(frames.times, float)[keep]
    radii = np.asarray(frames.radii, float)
    masses = np.asarray(frames.masses, float)
    n = len(radii)
    pos = frames.wrapped_positions(keep)
    speeds = np.linalg.norm(vel, axis=2)
    flat = pos.shape[-1] == 2
    axis = cut_axis_index(cut_axis, "render")
    if flat and cut is not None:
        raise PictureError("render: cut is for spheres; disks lie in the plane z = 0 (leave cut out)")
    if flat and color_by == "q6":
        raise PictureError("render: color_by='q6' is for spheres; for disks use 'psi6'")
    if flat:  # disks, seen from above: the plane's own axes, z = 0
        pos = np.concatenate([pos, np.zeros(pos.shape[:-1] + (1,))], axis=-1)
        right, up, towards = np.eye(3)
        extent = 1.04 * frames.extent(pos[..., :2], cover="cube")
    else:
        right, up, towards = _camera() if cut is None else _camera(CUT_AZIMUTH[axis])
        extent = 1.04 * frames.extent(pos, cover="sphere")

    fig = Figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor="white")
    FigureCanvasAgg(fig)
    side = 0.94 * min(height, 0.8 * width)  # the square drawing area [pixels]
    x0 = max(0.0, 0.5 * (width - side) - 0.04 * width)
    ax = fig.add_axes((x0 / width, 0.5 * (1 - side / height), side / width, side / height))
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal", adjustable="box")
    ax.set_axis_off()
    _draw_container(ax, frames, right, up, cut, axis)

    if color_by == "psi6":  # disks: the local hexatic order, on the fixed scale 0 to 1
        from matplotlib import colors

        from ..analysis.structure import psi6_magnitudes

        if not flat:
            raise PictureError("render: color_by='psi6' is for disks (a 2-D box or a circle)")
        norm, values, label = (
            colors.Normalize(0.0, 1.0),
            psi6_magnitudes(pos[..., :2], frames.container),
            "|psi6|",
        )
    elif color_by == "q6":  # spheres: Steinhardt q6 over 12 neighbours, the viewer's fixed scale
        from matplotlib import colors

        from .viewer import Q6_RANGE, _q6

        norm, values, label = colors.Normalize(*Q6_RANGE), _q6(frames, pos), "bond order q6"
    elif color_by == "density":  # the local packing fraction (clusters), 0 to the densest packing
        from matplotlib import colors

        from .viewer import local_density

        values, top, label = local_density(frames, pos[..., :2] if flat else pos, "render")
        norm = colors.Normalize(0.0, top)
    else:
        norm, values, label = _colour_scale(color_by, speeds, masses)
    cmap = colormaps["viridis"]

    points_per_unit = side * 72.0 / dpi / (2.0 * extent)
    diameter = np.maximum(2.0 * radii * points_per_unit, 0.6)  # [points]
    # three markers per sphere, drawn in this order: rim, body, highlight, each
    # shifted towards the light (upper left) by this many radii, this wide;
    # a disk is flat: a thin rim and its body, no highlight (drawn again as body)
    shift, scale = ((0.0, 0.0, 0.0), (1.0, 0.9, 0.9)) if flat else ((0.0, 0.08, 0.3), (1.0, 0.8, 0.3))
    sc = ax.scatter(np.zeros(0), np.zeros(0), linewidths=0)
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    cax = fig.add_axes(((x0 + side) / width + 0.03, 0.2, 0.018, 0.6))
    fig.colorbar(sm, cax=cax, label=label)
    header, caption = _caption(frames, n, cut, title, "xyz"[axis])
    label_t = fig.text(
        0.015, 0.975, "", va="top", ha="left", family="monospace", fontsize=max(9, round(height / 48))
    )

    def show(f: int) -> None:
        p = pos[f]
        visible = np.ones(n, bool) if cut is None else p[:, axis] <= cut
        order = np.nonzero(visible)[0]
        order = order[np.argsort(p[order] @ towards, kind="stable")]  # far to near
        x, y = p @ right, p @ up
        base = cmap(norm(values[f]))[:, :3]
        k = len(order)
        xy = np.empty((3 * k, 2))
        rgba = np.ones((3 * k, 4))
        r = radii[order]
        for layer in range(3):
            xy[layer::3, 0] = x[order] - shift[layer] * r
            xy[layer::3, 1] = y[order] + shift[layer] * r
        rgba[0::3, :3] = 0.45 * base[order]
        rgba[1::3, :3] = base[order]
        rgba[2::3, :3] = base[order] if flat else 0.45 * base[order] + 0.55
        rgba[2::3, 3] = 1.0 if flat else 0.75
        sc.set_offsets(xy)
        sc.set_facecolors(rgba)  # type: ignore[attr-defined]  # an alias the stubs leave out
        sizes = np.empty(3 * k)
        for layer in range(3):
            sizes[layer::3] = (scale[layer] * diameter[order]) ** 2
        sc.set_sizes(sizes)
        label_t.set_text(f"{header}{caption}\nt = {times[f]:.6g}")

    return fig, show


def _caption(
    frames: Frames, n: int, cut: float | None, title: str | None, axis: str = "z"
) -> tuple[str, str]:
    """``(header, caption)`` of a picture: the title, then N, the packing fraction and the cut."""
    phi = packing_fraction(frames)
    caption = f"N = {n}" + (f", phi = {phi:.3g}" if phi is not None else "")
    if cut is not None:
        caption += f"\ncut-away: {axis} <= {cut:.4g}"
    return (f"{title}\n" if title else ""), caption


def _colour_scale(color_by: str, speeds: np.ndarray, masses: np.ndarray) -> tuple[Any, np.ndarray, str]:
    """``(norm, values, label)``: the spheres' colours by speed (to its 99.5th percentile) or by mass."""
    from matplotlib import colors

    if color_by == "speed":
        finite = speeds[np.isfinite(speeds)]
        hi = float(np.percentile(finite, 99.5)) if finite.size else 1.0
        return colors.Normalize(0.0, hi if hi > 0 else 1.0), speeds, "speed"
    lo, hi = (float(masses.min()), float(masses.max())) if masses.size else (0.0, 1.0)
    return colors.Normalize(lo, hi if hi > lo else lo + 1.0), np.broadcast_to(masses, speeds.shape), "mass"


def _check(size: tuple[int, int], color_by: str, what: str) -> None:
    width, height = (int(s) for s in size)
    if width <= 0 or height <= 0:
        raise PictureError(f"{what}: bad size {size}; give (width, height) in pixels, both > 0")
    if color_by not in ("speed", "mass", "q6", "psi6", "density"):
        raise PictureError(
            f"{what}: color_by must be 'speed', 'mass', 'density', (spheres) 'q6' or (disks) 'psi6', "
            f"got {color_by!r}"
        )


def _check_movie(path: Path, fps: int, size: tuple[int, int], color_by: str) -> None:
    """Refuse a movie's arguments before any work (one line naming the argument)."""
    _check(size, color_by, "render_movie")
    width, height = (int(s) for s in size)
    if path.suffix.lower() != ".gif" and (width % 2 or height % 2):
        raise PictureError(f"render_movie: {path.suffix} needs an even width and height, not {size}")
    if int(fps) != fps or not 1 <= fps <= 100:
        raise PictureError(f"render_movie: fps must be a whole number from 1 to 100, got {fps!r}")


def render_movie(
    frames: Frames,
    path: str | os.PathLike[str],
    fps: int = 20,
    size: tuple[int, int] = (960, 540),
    progress: bool = True,
    *,
    max_frames: int | None = None,
    color_by: str = "speed",
    title: str | None = None,
    dpi: int = 100,
    cut: float | None = None,
    cut_axis: str = "z",
    on_estimate: Callable[[int, float], None] | None = None,
) -> Path:
    """Render ``frames`` to a movie file and return ``path``.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: ``.gif`` (Pillow) or ``.mp4`` (ffmpeg; a :class:`RuntimeError`
            says so when ffmpeg is missing; ``.mov``, ``.mkv``, ``.webm``
            also go through ffmpeg).
        fps: frames per second of the movie (1 to 100).
        size: ``(width, height)`` in pixels (even numbers for mp4); the
            default suits a 16:9 slide.
        progress: when stderr is a terminal, say there how long the movie
            will take (after the first frames) and show a progress bar.
        max_frames: render at most this many frames, evenly spaced (default:
            all).
        color_by: ``"speed"``, ``"mass"``, ``"q6"`` (spheres: bond order, the viewer's scale;
            freud) or ``"psi6"`` (disks: the local hexatic order, 0 to 1; freud).
        title: text above the caption (N, packing fraction, time).
        dpi: resolution used to lay out the figure (the pixel size is
            ``size`` whatever it is).
        cut: draw only the spheres whose centre has ``z <= cut`` [length] (a cut-away).
        cut_axis: the cut's normal, ``"x"``, ``"y"`` or ``"z"`` (``"x"``: only ``x <= cut``,
            a slab along z seen side-on); the camera turns to the cut's face.
        on_estimate: called once, after the first frames, with the number
            of frames and the expected total time [s] (terminal or not).

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    _check_movie(path, fps, size, color_by)
    writer = _writer(path, int(fps), dpi)

    n_frames = len(frames.times)
    if n_frames == 0:
        raise PictureError("render_movie: no frames; record at least one")
    keep = frame_indices(n_frames, 0, max_frames or n_frames)
    fig, show = _scene(frames, size, keep, color_by, title, dpi, cut, cut_axis)

    bar = Progress(len(keep), enabled=None if progress else False, unit="frames", every=0.1)
    start = _time.monotonic()
    first_done = start  # when the first frame is done (set then)
    try:
        from ..fileio import atomic_path

        with atomic_path(path) as tmp, writer.saving(fig, tmp, dpi):
            for f in range(len(keep)):
                show(f)
                writer.grab_frame()
                now = _time.monotonic()
                if f == 0:
                    first_done = now  # the first frame also pays for the set-up
                # the estimate: from the pace of frames 2 and 3 (or of frame 1 alone)
                if f == min(2, len(keep) - 1) and len(keep) > 1:
                    per_frame = (now - first_done) / f if f > 0 else now - start
                    total = now - start + per_frame * (len(keep) - 1 - f)
                    if on_estimate is not None:
                        bar.clear()  # the caller's words go on a line of their own
                        on_estimate(len(keep), total)
                        bar.redraw()
                    elif bar.on:
                        bar.note(f"rendering {len(keep)} frames to {path.name}, about {duration(total)}")
                bar.update(f + 1, f + 1, f"rendering {f + 1}/{len(keep)}")
    finally:
        bar.close()
    return path


#: Still pictures' formats, by extension.
STILLS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}


def render_still(
    frames: Frames,
    path: str | os.PathLike[str],
    time: float | None = None,
    size: tuple[int, int] = (1280, 720),
    *,
    color_by: str = "speed",
    title: str | None = None,
    dpi: int = 100,
    cut: float | None = None,
    cut_axis: str = "z",
) -> Path:
    """Draw one frame of ``frames``, as :func:`render_movie` draws it, to a picture.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: the ``.png`` (or ``.pdf``, ``.svg``) to write.
        time: draw the frame nearest this time [time] (default: the last).
        size: ``(width, height)`` in pixels; the default suits a 16:9 slide.
        color_by: ``"speed"``, ``"mass"``, ``"q6"`` (spheres) or ``"psi6"`` (disks), as for
            :func:`render_movie`.
        title: text above the caption (N, packing fraction, time).
        dpi: resolution used to lay out the figure.
        cut: draw only the spheres whose centre has ``z <= cut`` [length].
        cut_axis: the cut plane's normal, ``"x"``, ``"y"`` or ``"z"``, as for :func:`render_movie`.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    _check(size, color_by, "render_still")
    fmt = STILLS.get(path.suffix.lower())
    if fmt is None:
        raise PictureError(f"render_still: writes .png, .pdf or .svg, not {path.suffix or path.name!r}")
    times = np.asarray(frames.times, float)
    if len(times) == 0:
        raise PictureError("render_still: no frames; record at least one")
    if time is None:
        k = len(times) - 1
    elif not np.isfinite(time):
        raise PictureError(f"render_still: time must be a finite number, got {time!r}")
    else:
        k = int(np.argmin(np.abs(times - float(time))))
    fig, show = _scene(frames, size, np.array([k]), color_by, title, dpi, cut, cut_axis)
    show(0)
    from ..fileio import atomic_write

    with atomic_write(path, "wb") as fh:
        fig.savefig(fh, dpi=dpi, format=fmt)
    return path
