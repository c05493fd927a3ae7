"""Diagnostic plots (PNG, PDF or SVG by the extension; matplotlib Agg, no display needed).

::

    from hardspheres import plots
    plots.plot_conservation(frames, "conservation.png")  # energy, momentum
    plots.plot_speeds(frames, "speeds.png")              # against Maxwell-Boltzmann
    plots.plot_eos("docs/validation.csv", "eos.png")     # Z against Carnahan-Starling
    plots.plot_transport("docs/validation-transport.csv", "transport.png")  # D, eta, lambda
    plots.plot_sweep("study/results.parquet", "Z.png")   # a study, Z against Hansen-Goos
    plots.plot_flow("study/results.parquet", "flow.png") # a sheared study: eta against g
    plots.plot_gr(frames, "gr.png")                      # g(r), periodic box
    plots.plot_msd(frames, "msd.png")                    # MSD and D, periodic box

Each function writes a PNG of ``size`` pixels (default 960 x 720), or a PDF or
SVG of the same proportions, as the file name's extension says, and returns
its path.
"""

from __future__ import annotations

import csv
import math
import os
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..eos import carnahan_starling, hansen_goos, packing_at_pressure
from ..errors import AnalysisInputError, PictureError, ResolutionWarning, StudyError
from ..maxwell import reduced_density, speed_density
from ..messages import plus_minus

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.collisions import ContactForces
    from ..analysis.transport import MSD
    from ..frames import Frames
    from ..simulation import Simulation

SIZE = (960, 720)


def _figure(size: tuple[int, int], dpi: int) -> Figure:
    from ..extras import need

    need("matplotlib", "a plot")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


#: File formats the plots write, by extension (matplotlib's backends).
FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}


def _save(fig: Figure, path: str | os.PathLike[str], dpi: int) -> Path:
    """Save in the format the extension names (PNG, or PDF and SVG for papers)."""
    from ..fileio import atomic_write

    path = Path(path)
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise PictureError(
            f"{path.name}: plots are written as {', '.join(FORMATS)}, "
            f"not {path.suffix or 'a name without extension'}"
        )
    with atomic_write(path, "wb") as fh:
        fig.savefig(fh, dpi=dpi, format=fmt)
    return path


def plot_conservation(
    frames: Frames, path: str | os.PathLike[str], *, size: tuple[int, int] = SIZE, dpi: int = 100
) -> Path:
    """Energy and momentum over time, and their deviations from the first frame.

    Top: kinetic energy ``E(t)`` and ``(E - E0) / E0``.  Bottom: the total
    momentum's components and the deviation of the conserved vector,
    relative to its natural scale: the linear momentum ``P`` in a periodic
    box or open space (scale ``sum m |v|``), the angular momentum ``L``
    about the centre in a spherical container (scale ``sum m |r| |v|``),
    where the walls change ``P`` but exert no torque.  Disks: the two
    components of ``P``, and in a circle the one of ``L``, ``Lz``.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    times = np.asarray(frames.times, float)
    if len(times) == 0:
        raise PictureError("plot_conservation: no frames; record at least one")
    masses = np.asarray(frames.masses, float)
    pos = np.asarray(frames.positions, float)
    vel = np.asarray(frames.velocities, float)
    energy = np.asarray(frames.energy(), float)
    momentum = np.asarray(frames.momentum(), float)
    e0 = energy[0]
    rel_e = (energy - e0) / e0 if e0 != 0 else energy - e0

    # walls change P but exert no torque about the centre: then L is conserved
    in_container = frames.container is not None and frames.container.wall_area > 0
    d = pos.shape[-1]  # 3, or 2 for disks
    axes_names = "xyz"[:d]
    if in_container and d == 2:  # L = Lz = x vy - y vx
        vector = np.einsum("n,fn->f", masses, pos[..., 0] * vel[..., 1] - pos[..., 1] * vel[..., 0])[:, None]
    elif in_container:
        vector = np.einsum("n,fnk->fk", masses, np.cross(pos, vel))
    if in_container:
        scale = float(np.sum(masses * np.linalg.norm(pos[0], axis=1) * np.linalg.norm(vel[0], axis=1)))
        name, symbol = "L about centre", "L"
    else:
        vector = momentum
        scale = float(np.sum(masses * np.linalg.norm(vel[0], axis=1)))
        name, symbol = "momentum P", "P"
    scale = scale if scale > 0 else 1.0
    dev = (vector - vector[0]) / scale

    fig = _figure(size, dpi)
    axes = fig.subplots(2, 2, sharex=True)
    ax = axes[0, 0]
    ax.plot(times, energy, color="C3", marker="." if len(times) < 60 else None)
    ax.set_ylabel("kinetic energy E")
    ax.set_title("energy")
    ax.ticklabel_format(axis="y", useOffset=False)
    # Conserved to rounding: show E on a scale of 1% of E0, not of its last digits.
    e_lo, e_hi = float(np.min(energy)), float(np.max(energy))
    pad = max(e_hi - e_lo, 0.01 * max(abs(e_lo), abs(e_hi)))
    if np.isfinite(pad) and pad > 0:
        ax.set_ylim(e_lo - pad, e_hi + pad)
    ax = axes[0, 1]
    ax.plot(times, rel_e, color="C3")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_ylabel("(E - E0) / E0" if e0 != 0 else "E - E0")
    ax.set_title(f"energy: max |dev| = {np.max(np.abs(rel_e)):.1e}", loc="right")
    ax = axes[1, 0]
    for k, c in enumerate(axes_names):
        ax.plot(times, momentum[:, k], label=f"P{c}", color=f"C{k}")
    ax.legend(loc="best", fontsize="small")
    ax.set_ylabel("total momentum P")
    ax.set_title("momentum" + (" (changed by the wall)" if in_container else ""))
    ax.set_xlabel("time")
    ax = axes[1, 1]
    for k, c in enumerate("z" if vector.shape[1] == 1 else axes_names):  # disks in a circle: Lz alone
        ax.plot(times, dev[:, k], label=f"{symbol}{c}", color=f"C{'xyz'.index(c)}")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.legend(loc="best", fontsize="small")
    ax.set_ylabel(f"({symbol} - {symbol}0) / {'sum m|r||v|' if in_container else 'sum m|v|'}")
    ax.set_title(f"{name}: max |dev| = {np.max(np.abs(dev)):.1e}", loc="right")
    ax.set_xlabel("time")
    where = frames.container.label if frames.container is not None else "open space"
    fig.suptitle(f"Conservation: {frames.n} {'disks' if d == 2 else 'spheres'}, {where}, {len(times)} frames")
    return _save(fig, path, dpi)


def plot_speeds(
    frames: Frames,
    path: str | os.PathLike[str],
    kT: float | None = None,
    *,
    start: int = 0,
    bins: int | None = None,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """Histogram of the speeds over all frames against Maxwell-Boltzmann.

    Equal masses ``m``: the density of ``v`` against
    ``f(v) = 4 pi v^2 (m/(2 pi kT))^{3/2} exp(-m v^2/(2 kT))``.  Unequal
    masses: the density of ``x = v sqrt(m/kT)`` against
    ``sqrt(2/pi) x^2 exp(-x^2/2)``, which every species shares.  Disks
    (2-D frames): the same in two dimensions, ``f(v) = (m v / kT)
    exp(-m v^2/(2 kT))`` and ``x exp(-x^2/2)`` (:mod:`hardspheres.maxwell`).

    Longer than 80 lines with this docstring (about 60 of code: one figure).

    Args:
        frames: a :class:`hardspheres.frames.Frames`.
        path: the PNG to write.
        kT: temperature [energy]; default ``2/d`` of the mean kinetic
            energy per sphere over the frames used (``d`` = 3, or 2 for disks).
        start: first frame used (to leave out an equilibration).
        bins: histogram bins (default from the sample size).

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    masses = np.asarray(frames.masses, float)
    vel = np.asarray(frames.velocities, float)[start:]
    if vel.shape[0] == 0 or vel.shape[1] == 0:
        raise PictureError("plot_speeds: no speeds to plot; record frames of at least one sphere")
    speeds = np.linalg.norm(vel, axis=2)  # (F, N)
    d = vel.shape[2]  # 3, or 2 for disks
    kinetic = 0.5 * masses[None, :] * speeds**2
    measured_kT = float(2.0 / d * kinetic.mean())
    if kT is None:
        kT = measured_kT
    if not kT > 0:
        raise PictureError(
            "plot_speeds: kT must be positive (all spheres at rest?); give kT or frames of moving spheres"
        )
    equal = bool(np.allclose(masses, masses[0], rtol=1e-12, atol=0.0))
    count = speeds.size
    bins = bins or int(np.clip(2.0 * count ** (1 / 3), 10, 120))

    fig = _figure(size, dpi)
    ax = fig.subplots()
    if equal:
        m = float(masses[0])
        sample = speeds.ravel()
        scale = math.sqrt(kT / m)
        top = max(float(np.percentile(sample, 99.9)), 4.2 * scale)
        grid = np.linspace(0.0, top, 400)
        curve = speed_density(grid, kT, m, dimensions=d)
        xlabel = "speed v"
        curve_label = f"Maxwell-Boltzmann, m = {m:g}, kT = {kT:.4g}"
    else:
        sample = (speeds * np.sqrt(masses / kT)[None, :]).ravel()
        top = max(float(np.percentile(sample, 99.9)), 4.2)
        grid = np.linspace(0.0, top, 400)
        curve = reduced_density(grid, dimensions=d)
        xlabel = "v sqrt(m / kT)"
        curve_label = f"Maxwell-Boltzmann, reduced (kT = {kT:.4g})"
    ax.hist(
        sample,
        bins=bins,
        range=(0.0, top),
        density=True,
        color="C0",
        alpha=0.6,
        edgecolor="C0",
        label=f"{count} speeds ({vel.shape[0]} frames x {vel.shape[1]} spheres)",
    )
    ax.plot(grid, curve, color="C3", lw=2, label=curve_label)
    ax.set_xlim(0.0, top)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("probability density")
    ax.legend(loc="upper right")
    note = "kT from the mean kinetic energy" if kT == measured_kT else f"kT given; measured {measured_kT:.4g}"
    kinds = "equal masses" if equal else f"{len(np.unique(masses))} masses"
    ax.set_title(f"Speed distribution: {frames.n} {'disks' if d == 2 else 'spheres'}, {kinds}; {note}")
    return _save(fig, path, dpi)


def _csv_rows(csv_path: str | os.PathLike[str], need: Sequence[str], hint: str = "") -> list[dict[str, str]]:
    """The rows of a CSV table (dicts keyed by its header).

    Raises:
        ValueError: one line naming the file: not UTF-8 text, no rows, or
            a column of ``need`` missing (then ``hint`` follows).
    """
    try:
        with open(csv_path, newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    except UnicodeDecodeError:
        raise StudyError(f"{csv_path}: not a CSV text file (not UTF-8)") from None
    if not rows:
        raise StudyError(f"{csv_path}: no rows; give a table with a row per measurement")
    missing = [c for c in need if c not in rows[0]]
    if missing:
        raise StudyError(f"{csv_path}: missing column(s) {', '.join(missing)}{hint}")
    return rows


def read_eos_csv(csv_path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """Columns of an equation-of-state CSV as float arrays, keyed by header."""
    rows = _csv_rows(csv_path, ("phi", "Z", "Z_err"))
    out = {}
    for key in rows[0]:
        try:
            out[key] = np.array([float(r[key]) for r in rows])
        except (TypeError, ValueError):
            continue
    order = np.argsort(out["phi"], kind="stable")
    return {k: v[order] for k, v in out.items()}


def plot_transport(
    csv_path: str | os.PathLike[str],
    path: str | os.PathLike[str],
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """Transport coefficients against published values, from ``validate --transport``'s CSV.

    One point per comparison (columns ``quantity,phi,n,value,error,reference,
    reference_error,z,source``): the relative deviation ``value / reference
    - 1`` in percent with its combined error bar, the band of +-2% shaded.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    need = ("quantity", "phi", "value", "error", "reference", "reference_error", "source")
    rows = _csv_rows(csv_path, need, hint=" (write it with hardspheres validate --transport)")
    try:
        num = {k: np.array([float(r[k]) for r in rows]) for k in need[1:-1]}
    except ValueError as e:
        raise StudyError(f"{csv_path}: not a number ({e}); fix that cell") from None
    dev = 100.0 * (num["value"] / num["reference"] - 1.0)
    err = 100.0 * np.hypot(num["error"], num["reference_error"]) / num["reference"]
    labels = [f"{r['quantity']}, phi {float(r['phi']):.3f}, N {r.get('n', '?')}" for r in rows]
    sources = list(dict.fromkeys(r["source"].split(",")[0] for r in rows))
    fig = _figure(size, dpi)
    ax = fig.subplots()
    y = np.arange(len(rows))[::-1]
    ax.axvspan(-2.0, 2.0, color="0.9", label="+-2%")
    ax.axvline(0.0, color="0.5", lw=0.8)
    for k, src in enumerate(sources):
        sel = np.array([r["source"].split(",")[0] == src for r in rows])
        ax.errorbar(dev[sel], y[sel], xerr=err[sel], fmt="o", color=f"C{k}", capsize=3, label=src)
    ax.set_yticks(y, labels)
    ax.set_ylim(-1, len(rows))
    ax.set_xlabel("measured / published - 1 [%] (error bar: combined standard error)")
    ax.set_title("Transport coefficients against published molecular dynamics")
    ax.legend(loc="best", fontsize="small")
    ax.grid(alpha=0.3, axis="x")
    return _save(fig, path, dpi)


def plot_eos(
    csv_path: str | os.PathLike[str],
    path: str | os.PathLike[str],
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """Compressibility factor ``Z`` against Carnahan-Starling, from a CSV.

    The CSV has the columns ``phi,Z,Z_err,Z_CS,rel_diff,gamma,gamma_from_Z,
    gamma_rel_diff`` (as ``hardspheres validate --csv`` writes; only
    ``phi,Z,Z_err`` are required).  Left: ``Z`` with error bars and the
    curve ``Z = (1 + phi + phi^2 - phi^3) / (1 - phi)^3``.  Right: the
    relative deviations ``Z / Z_CS - 1`` and, when present,
    ``Gamma / Gamma(Z) - 1``, in percent.

    Returns:
        ``path`` as a :class:`pathlib.Path`.
    """
    d = read_eos_csv(csv_path)
    phi, z, z_err = d["phi"], d["Z"], d["Z_err"]
    z_cs = carnahan_starling(phi)

    fig = _figure(size, dpi)
    ax, dx = fig.subplots(1, 2, width_ratios=[3, 2])
    grid = np.linspace(0.0, min(0.6, max(float(phi.max()) * 1.08, 0.05)), 300)
    ax.plot(grid, carnahan_starling(grid), color="C3", lw=1.5, label="Carnahan-Starling")
    ax.errorbar(phi, z, yerr=z_err, fmt="o", color="C0", ms=5, capsize=3, label="simulation")
    ax.set_xlabel("packing fraction phi")
    ax.set_ylabel("Z = PV / (N kT)")
    ax.set_xlim(0.0, grid[-1])
    ax.set_ylim(bottom=0.9)
    ax.legend(loc="upper left")
    ax.set_title("Equation of state")
    ax.grid(alpha=0.3)

    dx.axhline(0.0, color="0.5", lw=0.8)
    dx.errorbar(
        phi,
        100.0 * (z / z_cs - 1.0),
        yerr=100.0 * z_err / z_cs,
        fmt="o",
        color="C0",
        capsize=3,
        label="Z / Z_CS - 1",
    )
    if "gamma" in d and "gamma_from_Z" in d:
        g, gz = d["gamma"], d["gamma_from_Z"]
        gerr = 100.0 * d["gamma_err"] / gz if "gamma_err" in d else None
        dx.errorbar(
            phi + 0.004,
            100.0 * (g / gz - 1.0),
            yerr=gerr,
            fmt="s",
            color="C2",
            ms=4,
            capsize=3,
            label="Gamma / Gamma(Z) - 1",
        )
    dx.set_xlabel("packing fraction phi")
    dx.set_ylabel("relative deviation [%]")
    dx.legend(loc="best", fontsize="small")
    dx.set_title("Deviations")
    dx.grid(alpha=0.3)
    return _save(fig, path, dpi)


def read_table(path: str | os.PathLike[str]) -> Any:
    """A study's results or summary (``.parquet`` or ``.csv``) as a DataFrame."""
    import pandas as pd

    path = str(path)
    try:
        df = pd.read_csv(path) if path.endswith(".csv") else pd.read_parquet(path)
    except (OSError, ValueError) as e:
        if isinstance(e, FileNotFoundError):
            raise OSError(f"{path}: no such file") from None
        reason = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise StudyError(f"{path}: not a study's results table (.parquet or .csv): {reason}") from None
    return _grid_defaults(df)


def _grid_defaults(df: Any) -> Any:
    """``df`` with the grid's defaults where a column is missing a value.

    A CSV reads a 3-D study's empty ``aspect`` (the cube) back as NaN, and
    rows with NaN in a grid column drop out of the averages over seeds.
    """
    from ..studies import GRID_DEFAULTS

    for k, v in GRID_DEFAULTS.items():
        if k in df.columns and df[k].isna().any():
            df = df.assign(**{k: df[k].astype(object).where(df[k].notna(), v)})
    return df


def plot_sweep(
    table: Any,
    path: str | os.PathLike[str],
    x: str = "packing",
    y: str = "Z",
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """A study's observable ``y`` against the parameter ``x``, with error bars.

    ``table`` is a study's ``results.parquet`` (one row per run: averaged
    here over seeds, :func:`hardspheres.studies.summarize`) or its
    ``summary.parquet`` (or either as ``.csv``).  Points are the means, error
    bars one standard error; one series per value of the other parameters
    that vary (N, ratios, container).  For ``Z`` against ``packing`` of
    equal spheres in a periodic box, the Hansen-Goos (2016) curve is drawn,
    with Carnahan-Starling dashed, and a lower panel shows ``Z / Z_HG - 1``.

    Args:
        table: path of the results or summary table.
        path: the PNG to write.
        x: a grid parameter (column), e.g. ``packing`` or ``n``.
        y: a measured observable, e.g. ``Z``.

    Returns:
        ``path`` as a :class:`pathlib.Path`.

    Raises:
        ValueError: a column missing (the message lists those present).

    Longer than 80 lines: the table's checks, the series and the reference
    curves share one figure's axes, and the annotated signature takes a line
    per parameter.
    """
    from ..studies import GRID, measured, summarize

    df = read_table(table) if not hasattr(table, "columns") else _grid_defaults(table)
    if "seed" in df.columns:
        df = summarize(df)
    params = [c for c in GRID if c in df.columns and c != "seed"]
    if x not in params:
        raise StudyError(f"--x {x!r} is not a parameter of {table} (parameters: {', '.join(params)})")
    obs = measured(df)
    if y not in obs:
        raise StudyError(f"--y {y!r} is not measured in {table} (measured: {', '.join(obs)})")
    df = df.sort_values(x, kind="stable")
    # (at constant pressure "packing" is where each run started: not a series of its own)
    others = [c for c in params if c != x and df[c].nunique() > 1 and not (x == "betaP" and c == "packing")]
    groups = list(df.groupby(others, sort=True)) if others else [((), df)]
    pure_box = bool((df["container"] == "box").all() and (df["radius_ratio"] == 1).all())
    # constant pressure: the mean packing against the inverse of Hansen-Goos
    npt = y == "mean_packing" and x == "betaP" and pure_box
    reference = npt or (y in ("Z", "compressibility") and x == "packing" and pure_box)

    def curve(xs: np.ndarray) -> np.ndarray:
        return np.array([packing_at_pressure(p) for p in xs]) if npt else hansen_goos(xs)

    fig = _figure(size, dpi)
    if reference:
        ax, dx = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1.3])
    else:
        ax, dx = fig.subplots(), None
    if npt:
        grid = np.linspace(0.05, float(df[x].max()) * 1.05, 200)
        ax.plot(grid, curve(grid), color="C3", lw=1.5, label="Hansen-Goos (2016), inverted")
        dx.axhline(0.0, color="C3", lw=1)
    elif reference:
        _eos_reference(ax, dx, float(df[x].max()))
    colors = ["C0", "C1", "C2", "C4", "C5", "C6", "C7", "C8", "C9"]  # C3 is the reference
    for k, (key, g) in enumerate(groups):
        key = key if isinstance(key, tuple) else (key,)
        color = colors[k % len(colors)]
        label = ", ".join(f"{c} = {v}" for c, v in zip(others, key)) or "simulation"
        ax.errorbar(g[x], g[y], yerr=g[f"{y}_err"], fmt="o", ms=4, capsize=3, color=color, label=label)
        if dx is not None:
            ref = curve(g[x].to_numpy(float))
            dx.errorbar(
                g[x],
                100.0 * (g[y] / ref - 1.0),
                yerr=100.0 * g[f"{y}_err"] / ref,
                fmt="o",
                ms=4,
                capsize=3,
                color=color,
            )
    ax.set_ylabel(y)
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize="small")
    ax.set_title(f"{y} against {x}: mean ± standard error{_seeds_note(df)}")
    last = dx if dx is not None else ax
    if dx is not None:
        dx.set_ylabel(f"{y} / {'phi' if npt else 'Z'}_HG - 1 [%]")
        dx.grid(alpha=0.3)
    last.set_xlabel(x)
    return _save(fig, path, dpi)


def plot_flow(
    table: Any, path: str | os.PathLike[str], *, size: tuple[int, int] = SIZE, dpi: int = 100
) -> Path:
    """A study's flow curve: the viscosity ``eta = -P_xy/g`` against the shear rate ``g``, with error bars.

    ``table`` is a sheared study's ``results.parquet`` (averaged here over
    seeds, :func:`hardspheres.studies.summarize`) or its ``summary.parquet``
    (or either as ``.csv``), with the columns ``shear_rate``, ``viscosity``
    and ``viscosity_err``; rows without a shear rate are left out.  Points
    are the means, error bars one standard error; one series per value of
    the other parameters that vary (packing, N, ...).  Rates of both signs
    are drawn at ``|g|`` (the viscosity is even in ``g``).  When the rates
    span a decade or more the rate's axis is logarithmic, and the
    viscosity's when its means (all above 0) span a decade.

    Args:
        table: path of the results or summary table (or a DataFrame).
        path: the picture to write (.png, .pdf, .svg).

    Returns:
        ``path`` as a :class:`pathlib.Path`.

    Raises:
        StudyError: no sheared row, or no viscosity measured (the message
            says what to give).

    Example:
        >>> import pandas as pd, tempfile, os
        >>> rows = pd.DataFrame({"container": "box", "packing": 0.3, "n": 64, "radius_ratio": 1.0,
        ...     "shear_rate": [0.1, 1.0], "viscosity": [0.8, 0.7], "viscosity_err": [0.05, 0.02]})
        >>> plot_flow(rows, os.path.join(tempfile.mkdtemp(), "flow.png")).name
        'flow.png'
    """
    from ..studies import GRID, measured, summarize

    df = read_table(table) if not hasattr(table, "columns") else _grid_defaults(table)
    name = table if isinstance(table, (str, os.PathLike)) else "the table"
    if "shear_rate" not in df.columns:
        raise StudyError(f"{name}: no shear_rate column: a flow curve is drawn from a sheared study")
    if "seed" in df.columns:
        df = summarize(df)
    if "viscosity" not in measured(df):
        raise StudyError(
            f"{name}: viscosity is not measured (measured: {', '.join(measured(df)) or 'nothing'}); "
            "measure viscosity"
        )
    df = df[np.isfinite(df["shear_rate"].to_numpy(float)) & (df["shear_rate"] != 0)].copy()
    if df.empty:
        raise StudyError(f"{name}: no sheared row (shear_rate other than 0)")
    both = bool((df["shear_rate"] < 0).any() and (df["shear_rate"] > 0).any())
    df["rate"] = df["shear_rate"].abs()
    df = df.sort_values("rate", kind="stable")
    params = [c for c in GRID if c in df.columns and c not in ("seed", "shear_rate")]
    others = [c for c in params if df[c].nunique() > 1]
    groups = list(df.groupby(others, sort=True)) if others else [((), df)]
    fig = _figure(size, dpi)
    ax = fig.subplots()
    for k, (key, g) in enumerate(groups):
        key = key if isinstance(key, tuple) else (key,)
        label = ", ".join(f"{c} = {v}" for c, v in zip(others, key)) or "simulation"
        ax.errorbar(g["rate"], g["viscosity"], yerr=g["viscosity_err"], fmt="o-", ms=4, capsize=3,
                    lw=0.8, color=f"C{k % 10}", label=label)  # fmt: skip
    rates, eta = df["rate"].to_numpy(float), df["viscosity"].to_numpy(float)
    if rates.max() >= 10.0 * rates.min():
        ax.set_xscale("log")
    if (eta > 0).all() and eta.max() >= 10.0 * eta.min():  # (strong thinning: a log scale too)
        ax.set_yscale("log")
    ax.set_xlabel("|shear rate| |g|" if both else "shear rate g")
    ax.set_ylabel("viscosity eta = -P_xy / g")
    ax.grid(alpha=0.3, which="both")
    ax.legend(loc="best", fontsize="small")
    ax.set_title(f"flow curve: mean ± standard error{_seeds_note(df)}")
    return _save(fig, path, dpi)


def _eos_reference(ax: Axes, dx: Axes, top: float) -> None:
    """Hansen-Goos (solid) and Carnahan-Starling (dashed) up to ``top``, and CS / HG - 1 on ``dx``."""
    grid = np.linspace(0.0, min(0.55, top * 1.05 + 0.01), 300)
    ax.plot(grid, hansen_goos(grid), color="C3", lw=1.5, label="Hansen-Goos (2016)")
    ax.plot(grid, carnahan_starling(grid), color="0.4", lw=1, ls="--", label="Carnahan-Starling")
    dx.axhline(0.0, color="C3", lw=1)
    dx.plot(
        grid[1:],
        100.0 * (carnahan_starling(grid[1:]) / hansen_goos(grid[1:]) - 1.0),
        color="0.4",
        lw=1,
        ls="--",
    )


def _seeds_note(df: Any) -> str:
    """``, K seeds per point`` (or a range) for a summary table's title."""
    seeds = df["seeds"] if "seeds" in df.columns else None
    if seeds is None:
        return ""
    if seeds.min() != seeds.max():
        return f", {int(seeds.min())}-{int(seeds.max())} seeds per point"
    return f", {int(seeds.iloc[0])} seeds per point"


def plot_gr(
    frames: Frames, path: str | os.PathLike[str], *, size: tuple[int, int] = SIZE, dpi: int = 100
) -> Path:
    """g(r) of a periodic-box trajectory, averaged over its frames, with g(sigma) and Z.

    Uses :class:`hardspheres.analysis.structure.RDF` (freud).  Returns ``path``.
    """
    from ..analysis.structure import RDF

    rdf = RDF().compute(frames)
    fig = _figure(size, dpi)
    ax = rdf.plot(fig.add_subplot())
    try:
        g, err = rdf.contact_value()
        z, z_err = rdf.Z()
        ax.plot(
            [1.0],
            [g],
            "o",
            label=f"g(sigma+) = {plus_minus(g, err)}: Z = 1 + {2 if rdf.dimensions == 2 else 4} phi g "
            f"= {plus_minus(z, z_err)}",
        )
        ax.legend()
    except ValueError:  # unequal spheres: no single contact value
        pass
    return _save(fig, path, dpi)


def plot_msd(
    frames: Frames,
    path: str | os.PathLike[str],
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
    msd: MSD | None = None,
) -> Path:
    """Mean squared displacement of a periodic-box trajectory (all origins), with D.

    Uses :class:`hardspheres.analysis.transport.MSD` on the unwrapped
    positions, or ``msd`` if given (computed from ``frames``: the plot
    draws it, and computes nothing).  Returns ``path``.
    """
    from ..analysis.transport import MSD

    msd = MSD().compute(frames) if msd is None else msd
    D, err = msd.diffusion()
    fig = _figure(size, dpi)
    ax = msd.plot(fig.add_subplot())
    title = f"D = {plus_minus(D, err)} (slope over 0.2-0.5 of a fifth of the run)"
    if frames.positions.shape[-1] == 2:  # the 2-D tail: D grows as ln t (analysis.transport)
        title += "\ndisks: D at this time scale and box (it grows as ln t)"
    ax.set_title(title)
    return _save(fig, path, dpi)


# ---- glasses and jamming (hardspheres.analysis.dynamics, .jamming) ----------------------
def _mean_diameter(frames: Frames) -> float:
    r = np.asarray(getattr(frames, "radii", None) if frames is not None else [], float)
    return 2.0 * float(r.mean()) if r.size else 1.0


def plot_fs(
    frames: Frames,
    path: str | os.PathLike[str],
    k: float | None = None,
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """F_s(k, t) of a periodic-box trajectory with tau_alpha marked; ``k`` default ``2 pi / sigma``.

    Uses :class:`hardspheres.analysis.dynamics.SelfIntermediate` (sigma the
    mean diameter; error bars from the spread over time origins).  Returns ``path``.
    """
    from ..analysis.dynamics import INV_E, SelfIntermediate

    k = 2.0 * math.pi / _mean_diameter(frames) if k is None else k
    fs = SelfIntermediate(k=k).compute(frames)
    fig = _figure(size, dpi)
    ax = fs.plot(fig.add_subplot())
    try:
        tau, err = fs.tau_alpha()
    except AnalysisInputError as e:
        _unmarked(ax, "tau_alpha", e)
    else:
        ax.plot([tau], [INV_E], "o", label=f"tau_alpha = {plus_minus(tau, err)}")
        ax.legend()
    return _save(fig, path, dpi)


def _unmarked(ax: Axes, what: str, why: Exception) -> None:
    """Say on the plot, and as a :class:`~hardspheres.errors.ResolutionWarning`, why no ``what``."""
    import textwrap

    ax.set_title(textwrap.fill(f"no {what}: {why}", 90), fontsize="small")
    warnings.warn(ResolutionWarning(f"no {what} marked: {why}"), stacklevel=3)


def plot_chi4(
    frames: Frames,
    path: str | os.PathLike[str],
    a: float | None = None,
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """chi_4(t) = N var Q(t) of a periodic-box trajectory, with its peak; ``a`` default 0.3 sigma.

    Uses :class:`hardspheres.analysis.dynamics.Overlap`.  Returns ``path``.
    """
    from ..analysis.dynamics import Overlap

    ov = Overlap(a=a).compute(frames)
    fig = _figure(size, dpi)
    ax = ov.plot(fig.add_subplot())
    try:
        t, c = ov.peak()
    except AnalysisInputError as e:
        _unmarked(ax, "peak", e)
    else:
        ax.plot([t], [c], "o", label=f"peak chi_4 = {c:.3g} at t = {t:.3g}")
        ax.legend()
    return _save(fig, path, dpi)


def plot_contacts(
    sim: Simulation,
    path: str | os.PathLike[str],
    forces: ContactForces | None = None,
    *,
    size: tuple[int, int] = SIZE,
    dpi: int = 100,
) -> Path:
    """A packing's contacts: the cumulative Z(h) against the gap h, and P(f) of its contact forces.

    Left: twice the pairs with gap below h per sphere (a plateau at z near
    ``2d`` in a jammed packing; Donev, Torquato and Stillinger, PRE 71,
    011105 (2005)).  Right, if ``forces`` are given: the distribution of
    the time-averaged contact forces
    (:func:`hardspheres.analysis.collisions.packing_contact_forces`
    computes them, from a copy of the packing run at fixed radii).  The
    plot runs nothing.  Returns ``path``.
    """
    from ..analysis.dynamics import box_sides
    from ..analysis.jamming import near_pairs

    st = sim.state()
    dim = st.positions.shape[1]
    box = box_sides(sim.container, dim)
    _, h = near_pairs(st.positions, st.radii, box, 0.5)
    h = np.sort(h[h > 0])
    fig = _figure(size, dpi)
    left, right = fig.subplots(1, 2)
    left.semilogx(h, 2.0 * np.arange(1, len(h) + 1) / st.n)
    left.axhline(2 * dim, color="grey", lw=0.5, ls=":", label=f"2d = {2 * dim}")
    left.set_xlabel("gap h = r / (R_i + R_j) - 1")
    left.set_ylabel("Z(h): contacts per sphere with gap below h")
    left.set_ylim(0, 4 * dim)
    left.legend()
    if forces is not None:
        forces.plot(right)
        right.set_title(
            f"{forces.duration:.3g} time units at fixed radii, {int(forces.counts.sum())} collisions"
        )
    else:
        right.set_axis_off()
    return _save(fig, path, dpi)
