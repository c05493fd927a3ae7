"""Studies: parameter sweeps run as independent tasks on Dask, resumable.

Contract: a study is data (a TOML file or a dict) turned into tasks, each a
function of its parameters alone, so that a rerun, a resumed task and a task
on another worker give the same bits.  This family builds simulations and
analyses and writes tables; it imports them and everything below, never the
pictures or the commands (``hardspheres sweep`` lives in :mod:`hardspheres.cli`).
:mod:`hardspheres.studies.validate` holds the validation studies against
published equations of state and transport coefficients.

A study is a grid of runs (packing fraction x N x seeds x size and mass
ratios) described in a TOML file; each point of the grid and each seed is
one *task*, one run of equal-length blocks whose observables are averaged.
Tasks run on a :class:`distributed.LocalCluster` (one worker process per
core) or on an existing Dask cluster, or in this process (``serial=True``).

Study file (every key but ``packing`` and ``n`` is optional)::

    output = "eos-study"        # folder for results, relative to this file
    container = "box"           # "box" (periodic) or "sphere" (hard wall; "circle" in 2-D)
    dimensions = 3              # 3 (spheres) or 2 (disks), or a list [2, 3]
    aspect = [1, 1, 2]          # a box's sides in proportion (d numbers), or a list of them
    packing = [0.1, 0.2, 0.3]   # volume fractions, each in (0, 0.7405); disks: area, up to 0.72
    # pressure = [2.0, 5.0]     # constant pressure(s) beta P sigma^d instead (periodic box)
    n = [256, 1024]             # spheres per run
    seeds = 4                   # 4 seeds (0..3), or a list [1, 5, 9]
    radius_ratio = 1.0          # largest / smallest radius (or a list)
    mass_ratio = 1.0            # largest / smallest mass (or a list)
    equilibrate = 50            # collisions per sphere before measuring
    collisions = 500            # collisions per sphere measured (or: time = 20.0)
    blocks = 10                 # blocks for the error bars within a run
    measure = ["Z", "collision_rate"]

Spheres have mean diameter about 1 (the container is sized for it), mass 1
(or log-uniform up to ``mass_ratio``) and ``kT = 1``, so times are in units
of ``sigma sqrt(m / kT)``.

Space: ``dimensions = 2`` runs disks (``packing`` is then the area
fraction, at most 0.72, the random-disk builder's limit), in a periodic
square box or (``container = "sphere"`` or ``"circle"``) a circle.
``aspect`` shapes the box: ``[1, 0.8660254]`` is the ``sqrt(3)/2`` box a
hexagonal crystal of disks fits, ``[1, 1, 2]`` a 1:1:2 box; its length
gives the dimension (so ``dimensions`` may be left out), and a list of
shapes is a grid over them.  Without ``aspect`` the box is a cube (a
square).  Results hold ``dimensions`` and ``aspect`` (``"1:1:2"``; ``""``
for the cube and for round walls) as grid columns; a 3-D study without
``aspect`` keeps the task keys it had before they existed, so its finished
rows are found again.

Constant pressure: with ``pressure`` (``beta P sigma^3``, one or a list) each
run holds it with a :class:`~hardspheres.barostat.Barostat` (isotropic
moves, seeded by the task's seed) in a periodic box, so an equation of
state at fixed pressures is one sweep (measure ``mean_packing``: the mean
over each block's volume moves; ``mean_volume`` likewise); ``packing`` is then optional and is where each
run starts (default: Hansen-Goos's fluid at that pressure,
:func:`~hardspheres.eos.packing_at_pressure`, below freezing's 11.5), and
the results' column ``betaP`` holds it (``pressure`` is the observable: the
virial pressure measured).  ``hardspheres plot sweep --x betaP --y
mean_packing`` draws it against the inverse of Hansen-Goos.

The output folder holds:

* ``rows/KEY.parquet``: each finished task's row, written (atomically) by
  the worker as the task ends; a task whose row exists is never run again.
* ``tasks/KEY/``: the task's checkpoint (``progress.json`` and a
  :meth:`Simulation.save <hardspheres.simulation.Simulation.save>` file,
  written every ``checkpoint_seconds`` of work at a block boundary), from
  which a task whose worker died resumes on another worker, and
  ``attempts.jsonl``, one line per start (process id, block it started at).
* ``results.parquet`` and ``results.csv``: one row per finished task
  (rewritten as each task finishes); ``summary.parquet`` and
  ``summary.csv``: one row per parameter point, the mean over seeds with
  its standard error.

Blocks and checkpoints fall at fixed points of the run (chunk boundaries
fixed by the study, not by the clock) and a checkpoint resumes bit for bit,
so a study's results are the same bits however it was run: serially, on a
LocalCluster, or on a cluster that lost a worker midway.

Example:
    >>> import tempfile, hardspheres as hs
    >>> tmp = tempfile.TemporaryDirectory()
    >>> spec = {"output": tmp.name, "packing": [0.2, 0.3], "n": 64,
    ...         "seeds": 2, "equilibrate": 5, "collisions": 20, "blocks": 4}
    >>> df = hs.sweep(spec, serial=True)
    >>> df.shape[0], sorted(df["packing"].unique().tolist())
    (4, [0.2, 0.3])
    >>> s = summarize(df)
    >>> s[["packing", "seeds"]].values.tolist()
    [[0.2, 2.0], [0.3, 2.0]]
    >>> bool((s["Z"] > 1).all() and (s["Z_err"] > 0).all())
    True
    >>> tmp.cleanup()
"""

import hashlib
import itertools
import json
import math
import os
import time
import sys
from pathlib import Path

from ..containers import MAX_PACKING as _MAX_PACKING
from ..errors import StudyError  # noqa: F401 (re-exported)

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

#: Most collisions run between two chances to checkpoint (about a second of work).
STEP = 1 << 20

#: Densest packing of equal spheres (the one constant, re-exported).
MAX_PACKING = _MAX_PACKING


def _packing(sim, obs):
    """The block's mean packing: the barostat's over its moves, else the packing now (constant)."""
    b = sim.barostat
    return b.mean_packing if b is not None and b.samples else sim.packing


def _volume(sim, obs):
    b = sim.barostat
    return b.mean_volume if b is not None and b.samples else sim.container.volume


def _ks(sim, obs):
    """Kolmogorov-Smirnov distance of the reduced speeds ``v sqrt(m/kT)`` from Maxwell-Boltzmann."""
    import numpy as np

    from ..maxwell import ks_distance

    st = sim.state()
    kT = obs.temperature()
    x = np.linalg.norm(st.velocities, axis=1) * np.sqrt(st.masses / kT)
    return ks_distance(x, 1.0, 1.0, st.dimensions)


#: Observables a study can measure: name -> ``f(sim, observables)`` giving a
#: number for one block (the :class:`~hardspheres.observables.Observables`
#: averaged since the block began).  Any other public method of
#: ``Observables`` that takes no argument and returns a number is measured
#: by its own name.
OBSERVABLES = {
    "Z": lambda sim, o: o.compressibility(),
    "compressibility": lambda sim, o: o.compressibility(),
    "pressure": lambda sim, o: o.pressure(),
    "temperature": lambda sim, o: o.temperature(),
    "collision_rate": lambda sim, o: o.collision_rate(),
    "mean_free_time": lambda sim, o: o.mean_free_time(),
    "mean_free_path": lambda sim, o: o.mean_free_path(),
    "mean_speed": lambda sim, o: o.mean_speed(),
    "speeds_ks": _ks,
    "mean_packing": _packing,
    "mean_volume": _volume,
}
_NOT_OBSERVABLES = {"reset", "summary", "speed_histogram", "elapsed"}

#: Parameters that make the grid, in the order of the results' columns.
#: (``betaP``, the pressure a constant-pressure study holds, only in their
#: tables: ``pressure`` is the observable.)
GRID = ("container", "dimensions", "aspect", "betaP", "packing", "n", "radius_ratio", "mass_ratio", "seed")

#: What a grid column reads in rows written before it existed (3-D, no aspect).
GRID_DEFAULTS = {"dimensions": 3, "aspect": ""}

#: The densest random disks the builder places (:data:`hardspheres.builders.RANDOM_DISKS_MAX`).
_DISKS_MAX = 0.72

#: The starting packing of a constant-pressure run is the fluid's at
#: ``min(pressure, FREEZING_START)`` (just below freezing, 11.57; disks:
#: ``FREEZING_START_2D``, below their hexatic's 9.2).
FREEZING_START = 11.5
FREEZING_START_2D = 8.5

_KEYS = {
    "output": "folder for the results (string)",
    "container": '"box", "sphere" or "circle" (the round wall in 2-D)',
    "dimensions": "3 or 2 (disks), or a list of them",
    "aspect": "a box's sides in proportion, d numbers > 0 (e.g. [1, 1, 2], [1, 0.8660254]), or a list",
    "packing": "packing fraction(s) in (0, 0.7405) (disks: up to 0.72)",
    "pressure": "constant pressure(s) beta P sigma^d, number(s) > 0 (periodic box only)",
    "n": "number(s) of spheres, integers >= 2",
    "seeds": "a count (integer >= 1) or a list of integer seeds",
    "radius_ratio": "largest/smallest radius, number(s) >= 1",
    "mass_ratio": "largest/smallest mass, number(s) >= 1",
    "equilibrate": "collisions per sphere before measuring, number >= 0",
    "collisions": "collisions per sphere measured, number > 0",
    "time": "time measured per run, number > 0",
    "blocks": "blocks per run for error bars, integer >= 2",
    "measure": "list of observable names",
    "checkpoint_seconds": "seconds of work between checkpoints, number >= 0",
    "retries": "times a failing task is retried, integer >= 0",
}


def _where(source):
    return f"{source}: " if source else ""


def _is_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _list_of(raw, key, check, what, source):
    values = raw if isinstance(raw, list) else [raw]
    if not values:
        raise StudyError(f"{_where(source)}{key} is an empty list; give {what}")
    for v in values:
        if not check(v):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {what}")
    return values


def observable_names():
    """Names a study's ``measure`` accepts (the registry and ``Observables``' methods)."""
    from ..observables import Observables

    names = set(OBSERVABLES)
    for name in dir(Observables):
        if not name.startswith("_") and name not in _NOT_OBSERVABLES and callable(getattr(Observables, name)):
            names.add(name)
    return sorted(names)


def parse_study(data, source=None, base=None):
    """Check a study (a dict, as from TOML) and return it complete with defaults.

    Longer than 80 lines: one check per key, in the order the module's
    documentation lists the keys, each a few lines.

    Args:
        data: the study's keys (see the module's documentation).
        source: name of the file it came from, for messages.
        base: folder a relative ``output`` is relative to (default: the
            current directory).

    Returns:
        A dict with every key.

    Raises:
        StudyError: an unknown key or a value out of range; the message
            names the key and says what is allowed.

    Example:
        >>> parse_study({"packing": 0.3, "n": 100, "output": "x"})["seeds"]
        [0]
        >>> parse_study({"packing": 0.8, "n": 100})  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        hardspheres.errors.StudyError: packing = 0.8 is not allowed: give packing fraction(s) in (0, 0.74...
    """
    if not isinstance(data, dict):
        raise StudyError(f"{_where(source)}a study is a table of keys, not {type(data).__name__}")
    for key in data:
        if key not in _KEYS:
            raise StudyError(f"{_where(source)}unknown key {key!r} (allowed: {', '.join(sorted(_KEYS))})")
    for key in ("packing", "n"):
        if data.get(key) is None and not (key == "packing" and data.get("pressure") is not None):
            raise StudyError(f"{_where(source)}missing key {key!r}: {_KEYS[key]}")
    s = {}
    out = data.get("output", "study")
    if not isinstance(out, str) or not out:
        raise StudyError(f"{_where(source)}output = {out!r} is not allowed: give a folder name")
    # absolute: workers may run in another folder (on a cluster: the same
    # path on a shared file system)
    s["output"] = str((Path(base or ".") / out).resolve())
    container = data.get("container", "box")
    if container not in ("box", "sphere", "circle"):
        raise StudyError(
            f'{_where(source)}container = {container!r} is not allowed: give "box", "sphere" or "circle"'
        )
    s["container"] = container
    s["dimensions"], s["aspect"] = _space(data, container, source)
    disks = 2 in s["dimensions"]

    def fits(v):
        return _is_number(v) and 0.0 < v and (v <= _DISKS_MAX if disks else v < MAX_PACKING)

    s["pressure"] = None
    if data.get("pressure") is not None:  # (None: a parsed study's constant volume)
        s["pressure"] = [
            float(v)
            for v in _list_of(
                data["pressure"], "pressure", lambda v: _is_number(v) and v > 0.0, _KEYS["pressure"], source
            )
        ]
        if container != "box":
            raise StudyError(
                f'{_where(source)}pressure needs container = "box" (its volume moves scale the box)'
            )
    s["packing"] = (
        None
        if data.get("packing") is None
        else [
            float(v)
            for v in _list_of(
                data["packing"],
                "packing",
                fits,
                f"area fraction(s) in (0, {_DISKS_MAX}] for disks" if disks else _KEYS["packing"],
                source,
            )
        ]
    )
    s["n"] = _list_of(
        data["n"],
        "n",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 2,
        _KEYS["n"],
        source,
    )
    seeds = data.get("seeds", 1)
    if isinstance(seeds, int) and not isinstance(seeds, bool):
        if seeds < 1:
            raise StudyError(f"{_where(source)}seeds = {seeds} is not allowed: give {_KEYS['seeds']}")
        seeds = list(range(seeds))
    else:
        seeds = _list_of(
            seeds,
            "seeds",
            lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0,
            "a count (integer >= 1) or a list of integer seeds >= 0",
            source,
        )
        if len(set(seeds)) != len(seeds):
            raise StudyError(f"{_where(source)}seeds lists a seed twice: {seeds}")
    s["seeds"] = seeds
    for key in ("radius_ratio", "mass_ratio"):
        s[key] = [
            float(v)
            for v in _list_of(
                data.get(key, 1.0), key, lambda v: _is_number(v) and v >= 1.0, _KEYS[key], source
            )
        ]
    if "collisions" in data and "time" in data:
        raise StudyError(f"{_where(source)}give collisions or time, not both")
    for key, default, ok in (
        ("equilibrate", 50, lambda v: v >= 0),
        ("collisions", None, lambda v: v > 0),
        ("time", None, lambda v: v > 0),
        ("checkpoint_seconds", 120, lambda v: v >= 0),
    ):
        v = data.get(key, default)
        if v is not None and not (_is_number(v) and ok(v)):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {_KEYS[key]}")
        s[key] = v
    if s["collisions"] is None and s["time"] is None:
        s["collisions"] = 200
    for key, default, low in (("blocks", 10, 2), ("retries", 2, 0)):
        v = data.get(key, default)
        if not (isinstance(v, int) and not isinstance(v, bool) and v >= low):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {_KEYS[key]}")
        s[key] = v
    measure = data.get("measure", ["Z"])
    if isinstance(measure, str):
        measure = [measure]
    if not isinstance(measure, list) or not measure or not all(isinstance(m, str) for m in measure):
        raise StudyError(f"{_where(source)}measure = {measure!r} is not allowed: give {_KEYS['measure']}")
    known = observable_names()
    for m in measure:
        if m not in known:
            raise StudyError(f"{_where(source)}measure: unknown observable {m!r} (known: {', '.join(known)})")
    s["measure"] = list(dict.fromkeys(measure))
    return s


def _space(data, container, source):
    """``(dimensions, aspects)``: the lists a study's grid runs over (``aspects``: tuples or ``None``)."""
    raw = data.get("aspect")
    aspects = [None]
    if raw is not None:
        shapes = raw if isinstance(raw, list) and raw and all(isinstance(a, list) for a in raw) else [raw]
        for a in shapes:
            if not (isinstance(a, list) and len(a) in (2, 3) and all(_is_number(x) and x > 0 for x in a)):
                raise StudyError(f"{_where(source)}aspect = {a!r} is not allowed: give {_KEYS['aspect']}")
        if len({len(a) for a in shapes}) > 1:
            raise StudyError(f"{_where(source)}aspect: the shapes {raw!r} mix dimensions; give one per study")
        if container != "box":
            raise StudyError(f'{_where(source)}aspect is for container = "box", not {container!r}')
        aspects = [tuple(float(x) for x in a) for a in shapes]
    default = [len(aspects[0])] if aspects[0] is not None else [2] if container == "circle" else [3]
    dims = _list_of(
        data.get("dimensions", default),
        "dimensions",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v in (2, 3),
        _KEYS["dimensions"],
        source,
    )
    dims = list(dict.fromkeys(dims))
    if aspects[0] is not None and dims != [len(aspects[0])]:
        raise StudyError(
            f"{_where(source)}aspect {list(aspects[0])} has {len(aspects[0])} sides: "
            f"not dimensions = {dims!r}"
        )
    if container == "circle" and dims != [2]:
        raise StudyError(f'{_where(source)}container = "circle" is 2-D: not dimensions = {dims!r}')
    return dims, aspects


def aspect_text(aspect):
    """A box shape as the results' ``aspect`` column reads it: ``"1:1:2"`` (``""``: none).

    Example:
        >>> aspect_text((1.0, 0.8660254)), aspect_text(None)
        ('1:0.8660254', '')
    """
    return "" if aspect is None else ":".join(f"{x:.10g}" for x in aspect)


def load_study(path):
    """Read and check a study file (TOML); ``output`` is relative to its folder.

    Raises:
        StudyError: unreadable TOML or a bad key (the message names it).
        OSError: the file cannot be read.
    """
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{path}: not valid TOML: {e}") from None
    return parse_study(data, source=str(path), base=path.parent)


def tasks(study):
    """The study's tasks, one dict per grid point and seed, in a fixed order.

    Each has the grid parameters (:data:`GRID`), the run's length and
    observables, its ``key`` (a hash of everything that decides its
    result) and the study's ``folder``.
    """
    from ..eos import packing_at_pressure

    out = []
    run = {k: study[k] for k in ("equilibrate", "collisions", "time", "blocks", "measure")}
    for pressure, d, aspect, packing, n, rr, mr, seed in itertools.product(
        study.get("pressure") or [None],
        study.get("dimensions", [3]),
        study.get("aspect", [None]),
        study["packing"] or [None],
        study["n"],
        study["radius_ratio"],
        study["mass_ratio"],
        study["seeds"],
    ):
        if packing is None and d == 2:
            from ..eos import kolafa_rottner

            packing = packing_at_pressure(min(pressure, FREEZING_START_2D), kolafa_rottner, (0.0, 0.7), 2)
        elif packing is None:
            packing = packing_at_pressure(min(pressure, FREEZING_START))
        t = {
            "container": study["container"],
            "packing": packing,
            "n": n,
            "radius_ratio": rr,
            "mass_ratio": mr,
            "seed": seed,
            **run,
        }
        # the space only where it is not the default: 3-D studies keep their keys
        if d != 3:
            t["dimensions"] = d
        if aspect is not None:
            t["aspect"] = aspect_text(aspect)
        if pressure is not None:  # (absent otherwise: the keys of constant-volume tasks are unchanged)
            t["betaP"] = pressure
        t["key"] = hashlib.sha256(json.dumps(t, sort_keys=True).encode()).hexdigest()[:16]
        t["folder"] = study["output"]
        t["checkpoint_seconds"] = study["checkpoint_seconds"]
        out.append(t)
    return out


# ---- files ------------------------------------------------------------------
def _atomic(path, write):
    """Call ``write(tmp_path)`` then rename onto ``path`` (:func:`fileio.atomic_path`).

    No lock: a task's files have one writer at a time (Dask reruns a task
    only after its worker is gone).

    Raises:
        OSError: naming ``path``.
    """
    from ..fileio import atomic_path

    with atomic_path(path, lock=False) as tmp:
        write(tmp)


def _write_json(path, obj):
    def w(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(obj, fh)

    _atomic(path, w)


def _write_table(df, stem):
    """``df`` as ``stem.parquet`` and ``stem.csv``, each written atomically."""
    _atomic(f"{stem}.parquet", lambda tmp: df.to_parquet(tmp, index=False))
    _atomic(f"{stem}.csv", lambda tmp: df.to_csv(tmp, index=False))


def _row_path(task):
    return Path(task["folder"]) / "rows" / f"{task['key']}.parquet"


# ---- one task -------------------------------------------------------------------
def _build(task):
    from ..builders import random_spheres
    from ..containers import CircularContainer, PeriodicBox, SphericalContainer
    from ..simulation import Simulation

    n, phi = task["n"], task["packing"]
    d = task.get("dimensions", 3)
    aspect = task.get("aspect") or None
    if task["container"] == "box":
        if aspect is None and d == 2:
            aspect = "1:1"
        sides = None if aspect is None else tuple(float(x) for x in aspect.split(":"))
        container = PeriodicBox.for_packing(n, phi, sides)  # spheres of diameter 1 (equal spheres)
    elif d == 2:
        container = CircularContainer.for_packing(n, phi)
    else:
        container = SphericalContainer.for_packing(n, phi)
    state = random_spheres(
        n,
        phi,
        container,
        seed=task["seed"],
        radius_ratio=task["radius_ratio"],
        mass_ratio=task["mass_ratio"],
    )
    sim = Simulation(state, container)
    if "betaP" in task:
        from ..barostat import Barostat

        sim.set_barostat(Barostat(pressure=task["betaP"], kT=1.0, seed=task["seed"]))
    return sim


def _split(total, parts):
    """``total`` split into ``parts`` integers differing by at most one."""
    q, r = divmod(int(total), parts)
    return [q + (1 if k < r else 0) for k in range(parts)]


def _block_value(name, sim, obs):
    f = OBSERVABLES.get(name)
    value = f(sim, obs) if f is not None else getattr(obs, name)()
    try:
        return float(value)
    except (TypeError, ValueError):
        raise StudyError(
            f"observable {name!r} is not a number (got {type(value).__name__}); a study measures numbers"
        ) from None


def run_task(task):
    """Run one task (or finish it from its checkpoint) and write its row.

    Equilibration runs in ``blocks`` chunks, then the measurement in
    ``blocks`` blocks, each run in steps of at most :data:`STEP` collisions
    (a block of a ``time`` study is one step); after any step, once
    ``checkpoint_seconds`` of work have passed, the simulation (with the
    running block's averages) and the finished blocks' values are saved.
    The steps are fixed by the study, not by the clock, so the results do
    not depend on when checkpoints were taken.  This is what a Dask worker
    runs; a task whose row file exists returns it without running.

    Longer than 80 lines: the task's life in the order it happens (resume or
    build, equilibrate, the blocks with their checkpoints, the row), whose
    steps share the resumable progress record; split, each piece would pass
    the whole record around.

    Returns:
        The row: a dict of the grid parameters, the run's length, each
        observable's mean over blocks and its standard error (``NAME_err``).
    """
    import numpy as np
    import pandas as pd

    from ..simulation import Simulation

    row_path = _row_path(task)
    if row_path.exists():
        return pd.read_parquet(row_path).iloc[0].to_dict()
    tdir = Path(task["folder"]) / "tasks" / task["key"]
    tdir.mkdir(parents=True, exist_ok=True)
    prog_path = tdir / "progress.json"
    blocks, n = task["blocks"], task["n"]
    eq_chunks = _split(task["equilibrate"] * n / 2, blocks)
    prog = None
    if prog_path.exists():
        with open(prog_path, encoding="utf-8") as fh:
            prog = json.load(fh)
        if prog.get("checkpoint") and (tdir / prog["checkpoint"]).exists():
            sim = Simulation.load(tdir / prog["checkpoint"])
        else:
            # its checkpoint is gone (a finished task's row deleted, before
            # progress.json went with it): computed afresh (issue 29)
            prog = None
    if prog is None:
        prog = {
            "chunk": 0,
            "step": 0,
            "values": {m: [] for m in task["measure"]},
            "t0": None,
            "checkpoint": None,
        }
        sim = _build(task)
    with open(tdir / "attempts.jsonl", "a", encoding="utf-8") as fh:
        fh.write(
            json.dumps(
                {
                    "pid": os.getpid(),
                    "chunk": prog["chunk"],
                    "step": prog.get("step", 0),
                    "started": time.time(),
                }
            )
            + "\n"
        )
    per_block = _split(task["collisions"] * n / 2, blocks) if task["collisions"] is not None else None
    last_save = time.monotonic()
    total = 2 * blocks

    def steps(c):
        """Collisions of chunk ``c``'s steps (``[None]``: one step to a time)."""
        if c >= blocks and per_block is None:
            return [None]
        coll = eq_chunks[c] if c < blocks else per_block[c - blocks]
        return _split(coll, max(1, -(-coll // STEP)))

    def checkpoint(c, step):
        nonlocal last_save
        if time.monotonic() - last_save < task["checkpoint_seconds"]:
            return
        old = prog["checkpoint"]
        prog.update(chunk=c, step=step, checkpoint=f"ck-{c}-{step}.npz", pid=os.getpid())
        sim.save(tdir / prog["checkpoint"])
        _write_json(prog_path, prog)
        if old and old != prog["checkpoint"]:
            (tdir / old).unlink(missing_ok=True)
        last_save = time.monotonic()

    c, step = prog["chunk"], prog.get("step", 0)
    while c < total:
        plan = steps(c)
        if c >= blocks and step == 0:  # a block starts (a resumed one keeps its start)
            if prog["t0"] is None:
                prog["t0"] = sim.time
            sim.observables.reset()
            if sim.barostat is not None:
                sim.barostat.reset_averages()
        for k in range(step, len(plan)):
            if plan[k] is not None:
                sim.run(collisions=plan[k])
            else:
                sim.run(until=prog["t0"] + task["time"] * (c - blocks + 1) / blocks)
            if k + 1 < len(plan):
                checkpoint(c, k + 1)
        if c >= blocks:
            for m in task["measure"]:
                prog["values"][m].append(_block_value(m, sim, sim.observables))
        c, step = c + 1, 0
        if c < total:
            checkpoint(c, 0)
    row = {k: task.get(k, GRID_DEFAULTS.get(k)) for k in GRID if k in task or k in GRID_DEFAULTS}
    row.update(
        equilibrate=float(task["equilibrate"]),
        collisions=float(task["collisions"]) if task["collisions"] is not None else float("nan"),
        time=float(sim.time - prog["t0"]),
        blocks=blocks,
    )
    for m in task["measure"]:
        v = np.asarray(prog["values"][m], dtype=float)
        row[m] = float(v.mean())
        row[f"{m}_err"] = float(v.std(ddof=1) / math.sqrt(len(v)))
    row["key"] = task["key"]
    row_path.parent.mkdir(parents=True, exist_ok=True)
    _atomic(row_path, lambda tmp: pd.DataFrame([row]).to_parquet(tmp, index=False))
    for f in tdir.glob("ck-*.npz"):
        f.unlink(missing_ok=True)
    prog_path.unlink(missing_ok=True)  # done: a deleted row is computed afresh
    return row


# ---- aggregation -------------------------------------------------------------------
def measured(df):
    """Observable columns of a results table (those with a ``NAME_err`` beside them)."""
    return [c for c in df.columns if f"{c}_err" in df.columns]


def summarize(df):
    """Mean and standard error over seeds, one row per parameter point.

    For each observable ``X``: ``X`` is the mean over seeds; ``X_err`` its
    standard error, from the spread over seeds (``std / sqrt(seeds)``)
    when there are 2 seeds or more, else from the blocks of the one run;
    ``X_err_blocks`` the standard error from the blocks of the runs
    (``sqrt(sum err_i^2) / seeds``).  ``seeds`` counts the runs.

    Args:
        df: results, one row per task (as :func:`sweep` returns).

    Returns:
        A :class:`pandas.DataFrame` sorted by the grid parameters.
    """
    import numpy as np
    import pandas as pd

    params = [c for c in GRID if c != "seed" and c in df.columns]
    obs = measured(df)
    rows = []
    for point, g in df.groupby(params, sort=True):
        point = point if isinstance(point, tuple) else (point,)
        row = dict(zip(params, point))
        k = len(g)
        row["seeds"] = float(k)
        for m in obs:
            v = g[m].to_numpy(float)
            e = g[f"{m}_err"].to_numpy(float)
            row[m] = float(v.mean())
            blocks_err = float(np.sqrt(np.sum(e * e)) / k)
            row[f"{m}_err"] = float(v.std(ddof=1) / math.sqrt(k)) if k > 1 else blocks_err
            row[f"{m}_err_blocks"] = blocks_err
        rows.append(row)
    return pd.DataFrame(rows)


def _collect(all_tasks):
    import pandas as pd

    frames = [pd.read_parquet(_row_path(t)) for t in all_tasks if _row_path(t).exists()]
    if not frames:
        return pd.DataFrame()
    df = pd.concat(frames, ignore_index=True)
    for k, v in GRID_DEFAULTS.items():  # rows written before the column existed
        df[k] = df[k].fillna(v) if k in df.columns else v
    df["dimensions"] = df["dimensions"].astype(int)
    return df.sort_values([c for c in GRID if c in df.columns], kind="stable").reset_index(drop=True)


# ---- the sweep --------------------------------------------------------------------
def connect(address, timeout=10.0):
    """A :class:`distributed.Client` of the scheduler at ``address``.

    Raises:
        StudyError: the scheduler cannot be reached within ``timeout``
            seconds (the message names the address).
    """
    from distributed import Client

    try:
        return Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as e:
        reason = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise StudyError(
            f"cannot reach the Dask scheduler at {address} (within {timeout:g} s): {reason}"
        ) from None


def local_client(workers=None):
    """A :class:`distributed.Client` of a new LocalCluster: one single-threaded
    worker process per core (or ``workers``), its dashboard on a free port."""
    import logging
    import signal
    import threading

    from distributed import Client, LocalCluster

    # Ctrl-C in a terminal signals the whole process group, the workers too.
    # The workers are started with Ctrl-C ignored (the disposition is
    # inherited): only this process stops, cancels the tasks and closes the
    # cluster, without a traceback from every worker.  A Ctrl-C during the
    # start would be lost with it (the sweep ran on): a sentinel process in
    # the group, which Ctrl-C ends, tells it came (issue 29)
    guard = os.name == "posix" and threading.current_thread() is threading.main_thread()
    sentinel = _ctrl_c_sentinel() if guard else None
    cluster = None
    try:
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if guard else None
        try:
            cluster = LocalCluster(
                n_workers=workers or os.cpu_count() or 1,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
                silence_logs=logging.CRITICAL,  # a failing task is one line (its reason), not worker records
            )
        finally:
            if guard:
                signal.signal(signal.SIGINT, old)
        if sentinel is not None and sentinel.poll() is not None:
            raise KeyboardInterrupt  # Ctrl-C came while the cluster started
        return Client(cluster)
    except BaseException:
        if cluster is not None:
            cluster.close(timeout=10)
        raise
    finally:
        if sentinel is not None and sentinel.poll() is None:
            sentinel.kill()
            sentinel.wait()


def _ctrl_c_sentinel():
    """A process in this one's group that only Ctrl-C (SIGINT) ends: it tells
    whether Ctrl-C came while this process ignored it."""
    import subprocess

    code = "import signal, time; signal.signal(signal.SIGINT, signal.SIG_DFL); time.sleep(86400)"
    return subprocess.Popen(
        [sys.executable, "-c", code],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def _describe(task):
    return (
        f"{task['container']} "
        + (
            f"pressure={task['betaP']:g} (from packing={task['packing']:g})"
            if "betaP" in task
            else f"packing={task['packing']:g}"
        )
        + f" n={task['n']} "
        f"seed={task['seed']}"
        + (f" radius_ratio={task['radius_ratio']:g}" if task["radius_ratio"] != 1 else "")
        + (f" mass_ratio={task['mass_ratio']:g}" if task["mass_ratio"] != 1 else "")
    )


def sweep(spec, client=None, *, serial=False, workers=None, out=None):
    """Run a study: every task not yet finished, then write and return the results.

    Longer than 80 lines with this docstring (about 60 of code).

    Args:
        spec: a study file (path), or a dict of its keys (a relative
            ``output`` is then relative to the current directory).
        client: a :class:`distributed.Client` to run the tasks on; default:
            a LocalCluster made for the sweep (``workers`` processes, one
            per core by default) and closed after it.
        serial: run the tasks one after the other in this process (no Dask).
        workers: worker processes of the default LocalCluster.
        out: a text stream for progress (a bar on a terminal, one line per
            task otherwise); default: none.

    Returns:
        A :class:`pandas.DataFrame`, one row per task, sorted by the grid
        parameters (also written to ``results.parquet``/``.csv``, with
        :func:`summarize`'s table in ``summary.parquet``/``.csv``).
        ``df.attrs["computed"]`` counts the tasks this call ran.

    Raises:
        StudyError: a bad study, an unreachable cluster, or a failed task
            (the message names it).
    """
    study = load_study(spec) if isinstance(spec, (str, os.PathLike)) else parse_study(spec)
    all_tasks = tasks(study)
    folder = Path(study["output"])
    try:
        (folder / "rows").mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise OSError(f"cannot create {folder}: {e.strerror or e}") from None
    todo = [t for t in all_tasks if not _row_path(t).exists()]
    say = (lambda text: print(text, file=out, flush=True)) if out is not None else (lambda text: None)
    say(
        f"{len(all_tasks)} tasks: {len(all_tasks) - len(todo)} already done, "
        f"{len(todo)} to run; results in {folder}"
    )
    from ..progress import Progress

    bar = Progress(len(todo), stream=out) if out is not None else None
    done = 0

    def finished(task):
        nonlocal done
        done += 1
        _write_table(_collect(all_tasks), folder / "results")
        if bar is not None and bar.on:
            bar.update(done, label=f"{done}/{len(todo)} tasks")
        else:
            say(f"[{done}/{len(todo)}] {_describe(task)} done")

    try:
        if todo and serial:
            for t in todo:
                _run_here(t)
                finished(t)
        elif todo:
            own = client is None
            if own:
                client = local_client(workers)
            try:
                import importlib.util

                link = getattr(client, "dashboard_link", None)
                hint = (
                    ""
                    if importlib.util.find_spec("bokeh")
                    else " (its pages need bokeh: pip install 'hardspheres[sweep]')"
                )
                say(f"dashboard: {link}{hint}" if link else "dashboard: none")
                _run_on(client, todo, study["retries"], finished)
            finally:
                if own:
                    cluster = client.cluster
                    client.close(timeout=10)
                    cluster.close(timeout=10)
    finally:
        if bar is not None and bar.on and done:
            bar.close()
    df = _collect(all_tasks)
    _write_table(df, folder / "results")
    _write_table(summarize(df), folder / "summary")
    df.attrs["computed"] = len(todo)
    return df


def _fail(task, e):
    msg = str(e).splitlines()[0] if str(e) else type(e).__name__
    return StudyError(f"task {_describe(task)} failed: {msg}")


def _run_here(task):
    try:
        return run_task(task)
    except (ValueError, ArithmeticError) as e:
        raise _fail(task, e) from None


def _run_on(client, todo, retries, finished):
    from distributed import as_completed

    futures = {
        client.submit(run_task, t, key=f"hardspheres-task-{t['key']}", pure=False, retries=retries): t
        for t in todo
    }
    try:
        for fut in as_completed(list(futures)):
            task = futures[fut]
            try:
                fut.result()
            except Exception as e:  # noqa: BLE001 - the task's error, or KilledWorker
                raise _fail(task, e) from None
            finished(task)
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
