"""Interactive viewer: one self-contained HTML file that opens offline (spheres in 3-D, disks flat).

:func:`write_viewer` writes a page with three.js (vendored in
``hardspheres/viz/_static``, MIT) and the run's frames embedded in it, so the file
can be mailed or opened from disk with no server and no network::

    from hardspheres.viz.viewer import write_viewer
    write_viewer(frames, "run.html", title="2000 spheres, phi = 0.3")

In the page: drag to orbit, wheel to zoom, right-drag to pan; space plays or
pauses, the arrow keys step frames; click a sphere to see its name, mass,
radius and speed; the "cut" slider hides the spheres above a plane ``z = c``
to show the inside of a full container (or beyond ``x = c`` or ``y = c``,
the axis picked beside it: a slab along z seen side-on).  Spheres are drawn at their true radii in perspective,
coloured by speed, by mass or by their Steinhardt bond order q6 (with a
legend; ``color_by="q6"``: crystal-like spheres stand out from a fluid or a
jammed packing); collisions flash red and reflections off the container
flash white as they happen.  Disks (a 2-D box or a circle) are drawn flat,
seen from above with an orthographic camera (drag pans, wheel zooms, no
orbit), and can be coloured by their local hexatic order ``|psi6|``
(``color_by="psi6"``: 1 in a perfect hexagonal crystal).  In a periodic box
``color_by="density"`` colours by the local packing fraction (Voronoi with
freud, else a grid of cells): the clusters of a cooling granular gas.

Positions go in as little-endian Float32 arrays in base64; frames are
subsampled evenly to at most ``max_frames`` (and fewer when the spheres are
so many that positions and speeds would pass ``max_values`` numbers).
In a periodic box each sphere is drawn once, at its centre wrapped into the
box.  The page sets
``window.viewerReady = true`` once it has drawn the first frame and keeps
``window.viewerState = {frame, time, playing}`` current, for tests;
``window.viewerControl`` has ``setPlaying(bool)``, ``setCut(value or null,
axis)`` (``axis`` ``"x"``, ``"y"`` or ``"z"``, default the current one) and
``visible()`` (the indices of the spheres drawn) for scripts (the screenshot
plays the page through it, without clicks).

:func:`hardspheres.viz.screenshot.screenshot` opens such a page in headless
Chromium and saves a PNG.  The page itself (HTML, CSS and the JavaScript that
draws it) is ``hardspheres/viz/_static/viewer.html``, a template whose
``__TITLE__``, ``__JS__`` and ``__DATA__`` this module fills in.
"""

from __future__ import annotations

import base64
import html
import json
import os
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from ..errors import PictureError
from ..events import EventKind
from ..frames import even_indices, frame_indices
from . import cut_axis_index

if TYPE_CHECKING:
    from ..frames import Frames

_STATIC = ("three.core.min.js", "three.module.min.js", "OrbitControls.js")
_CORE_SPECIFIER = '"./three.core.min.js"'


def _b64(array: ArrayLike, dtype: DTypeLike) -> str:
    """Base64 of ``array`` as contiguous little-endian ``dtype``."""
    return base64.b64encode(
        np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<")).tobytes()
    ).decode("ascii")


def _script_json(obj: Any) -> str:
    """JSON safe inside a ``<script>`` element (no ``<`` at all)."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")


def _static(name: str) -> str:
    """Text of the packaged file ``hardspheres/viz/_static/NAME``."""
    return (resources.files("hardspheres.viz") / "_static").joinpath(name).read_text(encoding="utf-8")


def _vendored_js() -> dict[str, str]:
    """The three vendored scripts, keyed ``core``, ``module``, ``orbit``."""
    folder = resources.files("hardspheres.viz") / "_static"
    core, module, orbit = (folder.joinpath(name).read_text(encoding="utf-8") for name in _STATIC)
    if _CORE_SPECIFIER not in module or "from 'three'" not in orbit:
        raise RuntimeError("hardspheres/viz/_static: the vendored three.js files' import specifiers changed")
    return {"core": core, "module": module, "orbit": orbit}


def _round_up(x: float, digits: int = 2) -> float:
    """``x > 0`` rounded up to ``digits`` significant figures (a colour bar's top label)."""
    scale = 10.0 ** (np.floor(np.log10(x)) - (digits - 1))
    return float(f"{np.ceil(x / scale - 1e-9) * scale:.{digits}g}")


#: What the spheres can be coloured by (``color_by``, ``hardspheres view --color``), q6
#: for spheres and psi6 for disks.
COLOR_BY = ("speed", "mass", "q6", "psi6", "density")

#: The colour scale of q6, fixed so that pictures compare, puts a fluid or a jammed
#: packing near its bottom (0.3-0.45), FCC at its top (0.575 at rest).
Q6_RANGE = (0.25, 0.6)


def _q6(frames: Frames, positions: np.ndarray) -> np.ndarray:
    """Steinhardt q6 of each sphere in each frame ``(F, N)``, 12 nearest neighbours (freud).

    ``positions`` are the embedded frames' (wrapped into a periodic box of
    the box's own sides: a rectangular box's images are its own, not a
    cube's of its longest side).  In a spherical container or open space
    the spheres sit in a box wide enough that none sees an image
    (:class:`hardspheres.analysis.structure.BondOrder`).
    """
    from ..analysis.structure import BondOrder

    c = frames.container
    width: float | tuple[float, ...]
    if c is not None and c.periodic:
        width = tuple(float(x) for x in c.sides)  # type: ignore[attr-defined]  # a box's own sides
    else:
        reach = float(np.max(np.abs(positions))) if positions.size else 1.0
        if c is not None:
            reach = max(reach, float(c.bounding_radius))
        width = 4.0 * reach + 4.0 * float(np.max(frames.radii))
    order = BondOrder(num_neighbors=min(12, max(1, positions.shape[1] - 1)))
    return order.compute(positions, box=width).qs


def _psi6(frames: Frames, positions: np.ndarray) -> np.ndarray:
    """``|psi6|`` of each disk in each frame ``(F, N)``, 6 nearest neighbours (freud).

    ``positions`` are the embedded frames' (wrapped into a periodic box);
    in a circle the disks sit in a box wide enough that none sees an image
    (:func:`hardspheres.analysis.structure.local_psi6`).
    """
    from ..analysis.structure import psi6_magnitudes

    return psi6_magnitudes(positions, frames.container)


def local_density(frames: Frames, positions: np.ndarray, what: str) -> tuple[np.ndarray, float, str]:
    """Each sphere's local packing fraction in each frame ``(F, N)``, the scale's top, and its label.

    Voronoi cells if freud is installed, else a grid of cells
    (:class:`hardspheres.analysis.granular.LocalDensity`); in a periodic box
    only.  The scale runs from 0 to the densest packing of equal spheres
    (0.7405) or disks (0.9069), so that pictures compare.
    """
    from ..analysis.granular import LocalDensity

    c = frames.container
    if c is None or not c.periodic:
        raise PictureError(f"{what}: color_by='density' needs a periodic box (the local packing fraction)")
    sides = tuple(float(x) for x in c.sides)  # type: ignore[attr-defined]
    dens = LocalDensity().compute(positions, box=sides, radii=np.asarray(frames.radii, float))
    top = 0.9069 if len(sides) == 2 else 0.7405
    return dens.values, top, f"local packing fraction ({dens.method})"


def _payload(
    frames: Frames,
    title: str | None,
    max_frames: int,
    max_values: int,
    max_events: int,
    color_by: str,
    cut: float | None = None,
    cut_axis: str = "z",
) -> dict[str, Any]:
    """The page's data: frames, sizes, colours and events, checked.

    Longer than 80 lines: one dict the page reads, its checks and its
    scalars (q6, psi6) side by side, so that what the page gets is in one place.
    """
    times = np.asarray(frames.times, dtype=np.float64)
    pos = np.asarray(frames.positions, dtype=np.float64)
    vel = np.asarray(frames.velocities, dtype=np.float64)
    radii = np.asarray(frames.radii, dtype=np.float64).reshape(-1)
    masses = np.asarray(frames.masses, dtype=np.float64).reshape(-1)
    n_frames, n = len(times), len(radii)
    if n_frames == 0:
        raise PictureError("write_viewer: no frames; record at least one")
    d = pos.shape[-1] if pos.ndim == 3 else 3
    if (
        d not in (2, 3)
        or pos.shape != (n_frames, n, d)
        or vel.shape != (n_frames, n, d)
        or masses.shape != (n,)
    ):
        raise PictureError(
            f"write_viewer: inconsistent shapes: times {times.shape}, positions {pos.shape}, "
            f"velocities {vel.shape}, radii {radii.shape}, masses {masses.shape}; "
            "give one frame count and one sphere count"
        )
    if color_by not in COLOR_BY:
        raise PictureError(f"write_viewer: color_by must be one of {', '.join(COLOR_BY)}, got {color_by!r}")
    if color_by == "q6" and n < 2:
        raise PictureError("write_viewer: color_by='q6' needs at least 2 spheres")
    if color_by == "q6" and d == 2:
        raise PictureError("write_viewer: color_by='q6' is for spheres; for disks use 'psi6'")
    if color_by == "psi6" and (d != 2 or n < 2):
        raise PictureError("write_viewer: color_by='psi6' is for disks (a 2-D box or a circle), at least 2")

    keep = frame_indices(n_frames, n, max_frames, max_values)
    t = times[keep]
    p = pos[keep]
    c = frames.container
    sides = [float(x) for x in c.sides] if c is not None and c.periodic else None  # type: ignore[attr-defined]
    box = sides[0] if sides is not None and len(set(sides)) == 1 and d == 3 else None  # the cube's edge
    container = float(c.bounding_radius) if c is not None and not c.periodic else None
    if c is not None:
        p = c.wrap(p)  # periodic: into [-L/2, L/2)
    speeds = np.sqrt(np.einsum("fnk,fnk->fn", vel[keep], vel[keep]))
    extent = frames.extent(p, cover="sphere")

    events = _events(frames, t, n, max_events)
    speed_max = _speed_max(speeds)

    scalar = None
    if color_by == "q6":
        scalar = {
            "name": "q6",
            "label": "bond order q6",
            "values": _b64(_q6(frames, p), np.float32),
            "range": list(Q6_RANGE),
        }
    elif color_by == "psi6":
        scalar = {
            "name": "psi6",
            "label": "hexatic order |psi6|",
            "values": _b64(_psi6(frames, p), np.float32),
            "range": [0.0, 1.0],
        }
    elif color_by == "density":
        values, top, label = local_density(frames, p, "write_viewer")
        scalar = {"name": "density", "label": label, "values": _b64(values, np.float32), "range": [0.0, top]}
    if d == 2:  # the page draws in 3-D coordinates: disks at z = 0
        p = np.concatenate([p, np.zeros(p.shape[:-1] + (1,))], axis=-1)

    names = (
        [str(x) for x in frames.names]
        if (frames.names is not None and len(frames.names) == n and n <= 20000)
        else None
    )
    return {
        "title": title or (f"{n} hard disks" if d == 2 else f"{n} hard spheres"),
        "dimensions": int(d),
        "sides": None if sides is None else (sides + [0.0])[:3],
        "n": n,
        "nframes": int(len(keep)),
        "nframes_total": int(n_frames),
        "container": container,
        "box": box,
        "extent": float(extent),
        "times": t.tolist(),
        "positions": _b64(p, np.float32),
        "speeds": _b64(speeds, np.float32),
        "radii": _b64(radii, np.float32),
        "masses": _b64(masses, np.float32),
        "names": names,
        "speed_range": [0.0, speed_max],
        "mass_range": [float(masses.min()), float(masses.max())] if n else [1.0, 1.0],
        "color_by": color_by,
        "scalar": scalar,
        "cut": None if cut is None else float(cut),
        "cut_axis": cut_axis.lower(),
        "events": events,
    }


def _events(frames: Frames, t: np.ndarray, n: int, max_events: int) -> dict[str, Any]:
    """The page's events: those between the first and last frame shown, in time order, at most ``max_events``."""
    et = np.asarray(frames.event_times, dtype=np.float64).reshape(-1)
    ek = np.asarray(frames.event_kinds).reshape(-1).astype(np.uint8)
    ei = np.asarray(frames.event_i).reshape(-1).astype(np.int32)
    ej = np.asarray(frames.event_j).reshape(-1).astype(np.int32)
    m = min(len(et), len(ek), len(ei), len(ej))
    et, ek, ei, ej = et[:m], ek[:m], ei[:m], ej[:m]
    sel = (et >= t[0]) & (et <= t[-1]) & (ei >= 0) & (ei < n) & (ej < n)
    et, ek, ei, ej = et[sel], ek[sel], ei[sel], ej[sel]
    order = np.argsort(et, kind="stable")
    et, ek, ei, ej = et[order], ek[order], ei[order], ej[order]
    every = frames.events_every  # the recorder kept every this-many-th event of the run
    events_total = int(len(et)) * every
    counts = {
        "collisions": int(np.sum(ek == EventKind.COLLISION)) * every,
        "reflections": int(np.sum(ek == EventKind.REFLECTION)) * every,
    }
    if len(et) > max_events:
        pick = even_indices(len(et), max_events)
        et, ek, ei, ej = et[pick], ek[pick], ei[pick], ej[pick]
    return {
        "n": int(len(et)),
        "total": events_total,
        "counts": counts,
        "times": _b64(et, np.float64),
        "kinds": _b64(ek, np.uint8),
        "i": _b64(ei, np.int32),
        "j": _b64(ej, np.int32),
    }


def _speed_max(speeds: np.ndarray) -> float:
    """The top of the speed colour scale: the 99.5th percentile, rounded up."""
    finite_speeds = speeds[np.isfinite(speeds)]
    speed_max = float(np.percentile(finite_speeds, 99.5)) if finite_speeds.size else 1.0
    if not speed_max > 0:
        speed_max = float(finite_speeds.max()) if finite_speeds.size and finite_speeds.max() > 0 else 1.0
    return _round_up(speed_max)


def write_viewer(
    frames: Frames,
    path: str | os.PathLike[str],
    title: str | None = None,
    max_frames: int = 600,
    *,
    color_by: str = "speed",
    max_values: int = 12_000_000,
    max_events: int = 200_000,
    cut: float | None = None,
    cut_axis: str = "z",
) -> Path:
    """Write an interactive, self-contained HTML viewer of ``frames``.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: the ``.html`` file to write.
        title: shown in the page's corner and tab (default ``"N hard spheres"``).
        max_frames: at most this many frames are embedded, evenly spaced
            (first and last kept).
        color_by: initial colouring, ``"speed"``, ``"mass"``, ``"q6"``,
            ``"psi6"`` (disks) or ``"density"`` (the local packing
            fraction, in a periodic box: :func:`local_density`; switchable
            in the page).  ``"q6"``: each sphere's Steinhardt
            q6 over its 12 nearest neighbours in each embedded frame
            (:class:`hardspheres.analysis.structure.BondOrder`, needs freud), on the
            fixed scale :data:`Q6_RANGE` (0.25 to 0.6): a fluid or a jammed
            packing sits near 0.3-0.45, FCC at 0.575.
        max_values: at most this many numbers (frames x spheres x 4: a
            position and a speed) are embedded, about 4/3 bytes each in the
            file; fewer frames are kept for large N (the default keeps the
            file under about 70 MB).
        max_events: at most this many events are embedded for the flashes
            (evenly spaced in the run's event list when there are more).
        cut: start with the cut-away plane at ``z = cut`` [length]: spheres
            whose centre lies above it are hidden (the page's "cut" slider
            moves it; ``None``: no cut).
        cut_axis: the plane's normal, ``"x"``, ``"y"`` or ``"z"``: with
            ``"x"`` only the spheres with ``x <= cut`` are drawn (a slab
            along z seen side-on); the page's axis menu changes it.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    path = Path(path)
    page = viewer_page(
        frames,
        title,
        max_frames,
        color_by=color_by,
        max_values=max_values,
        max_events=max_events,
        cut=cut,
        cut_axis=cut_axis,
    )
    from ..fileio import atomic_write

    with atomic_write(path, "w", encoding="utf-8") as fh:
        fh.write(page)
    return path


def viewer_page(
    frames: Frames,
    title: str | None = None,
    max_frames: int = 600,
    *,
    color_by: str = "speed",
    max_values: int = 12_000_000,
    max_events: int = 200_000,
    cut: float | None = None,
    cut_axis: str = "z",
) -> str:
    """The viewer's self-contained HTML page of ``frames``, as text (what :func:`write_viewer` writes).

    Arguments as for :func:`write_viewer`.
    """
    if cut is not None and not np.isfinite(cut):
        raise PictureError(f"write_viewer: cut must be a finite number, got {cut!r}")
    cut_axis_index(cut_axis, "write_viewer")
    data = _payload(frames, title, max_frames, max_values, max_events, color_by, cut, cut_axis)
    return (
        _static("viewer.html")
        .replace("__TITLE__", html.escape(data["title"]))
        .replace("__JS__", _script_json(_vendored_js()))
        .replace("__DATA__", _script_json(data))
    )


#: Frames a notebook's inline viewer embeds at most (the page stays a few MB).
NOTEBOOK_FRAMES = 200
#: Numbers (frames x spheres x 4) a notebook's inline viewer embeds at most.
NOTEBOOK_VALUES = 2_000_000


def notebook_html(
    frames: Frames,
    title: str | None = None,
    height: int = 480,
    *,
    max_frames: int = NOTEBOOK_FRAMES,
    color_by: str = "speed",
) -> str:
    """The viewer for a notebook cell: the same self-contained page in an ``<iframe srcdoc>``.

    It needs no server and no network (three.js is inside the page), so it
    works offline and in a notebook saved to HTML.  Jupyter shows it for a
    :class:`~hardspheres.Simulation`, a :class:`~hardspheres.Frames` or a
    trajectory read back (:func:`~hardspheres.read_trajectory`) that ends a
    cell.

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        title: shown in the page's corner.
        height: of the frame in the notebook [CSS pixels].
        max_frames: frames embedded at most (evenly spaced, first and last kept).
        color_by: ``"speed"``, ``"mass"`` or ``"q6"``.

    Returns:
        The HTML text (a ``<div>`` holding the ``<iframe>``).

    Example:
        >>> import numpy as np
        >>> from hardspheres.frames import Frames
        >>> f = Frames([0.0], np.zeros((1, 1, 3)), np.ones((1, 1, 3)), [0.5], [1.0], ["a"], box=4.0)
        >>> notebook_html(f).startswith('<div class="hardspheres-viewer"><iframe')
        True
    """
    page = viewer_page(
        frames, title, max_frames, color_by=color_by, max_values=NOTEBOOK_VALUES, max_events=20_000
    )
    return (
        f'<div class="hardspheres-viewer"><iframe srcdoc="{html.escape(page, quote=True)}" '
        f'style="width: 100%; height: {int(height)}px; border: 1px solid #ccc;" '
        'title="hardspheres viewer" loading="lazy"></iframe></div>'
    )
