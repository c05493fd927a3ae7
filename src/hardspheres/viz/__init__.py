"""Pictures: plots, stills and movies, the interactive viewer and its screenshots.

Contract: a picture reads frames, results or tables and writes a file (or
returns matplotlib Axes); it never changes a simulation.  matplotlib, ffmpeg
and the browser are imported or started only when a picture is made.  This
family may import analyses and studies (to plot them) and everything below,
never the commands.

Modules:
    plots: the ``plot`` command's figures (g(r), MSD, equation of state, ...).
    render: stills and movies of frames (matplotlib, ffmpeg).
    viewer: the self-contained three.js page (``_static/`` holds its files).
    screenshot: a viewer page rendered to PNG in headless Chromium.
"""

#: The axes a cut-away plane can be normal to (``cut_axis``).
CUT_AXES = ("x", "y", "z")


def cut_axis_index(cut_axis: str, what: str) -> int:
    """0, 1 or 2 for a cut-away plane normal to x, y or z; :class:`~hardspheres.errors.PictureError` else."""
    from ..errors import PictureError

    if not isinstance(cut_axis, str) or cut_axis.lower() not in CUT_AXES:
        raise PictureError(f"{what}: cut_axis must be 'x', 'y' or 'z' (the plane's normal), got {cut_axis!r}")
    return CUT_AXES.index(cut_axis.lower())
