"""One task: a grid point and a seed, from its parameters to its row.

:func:`tasks` turns a parsed study into its tasks (each a dict with a
``key`` hashed from what decides its result); :func:`run_task` runs one, in
fixed steps with checkpoints, and writes its row.  This is what a Dask
worker runs.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import StudyError
from .measures import block_value
from .files import atomic, row_path, write_json
from .spec import GRID, GRID_DEFAULTS, Study, Task, aspect_text, rescale_interval

if TYPE_CHECKING:
    from ..containers import Container
    from ..mc.chain import EventChain
    from ..simulation import Simulation

#: Most collisions run between two chances to checkpoint (about a second of work).
STEP = 1 << 20

#: The starting packing of a constant-pressure run is the fluid's at
#: ``min(pressure, FREEZING_START)`` (just below freezing, 11.57; disks:
#: ``FREEZING_START_2D``, below their hexatic's 9.2).
FREEZING_START = 11.5
FREEZING_START_2D = 8.5


def tasks(study: Study) -> list[Task]:
    """The study's tasks, one dict per grid point and seed, in a fixed order.

    Each has the grid parameters (:data:`GRID`), the run's length and
    observables, its ``key`` (a hash of everything that decides its
    result) and the study's ``folder``.
    """

    out = []
    # (.get: a study made by hand before the space and pressure keys existed)
    held, given = study.get("pressure"), study["packing"]
    pressures: list[float | None] = [*held] if held else [None]
    packings: list[float | None] = [*given] if given else [None]
    given_rules = study.get("restitution")
    rules: list[float | None] = [*given_rules] if given_rules else [None]
    strengths, intervals = study.get("kicks"), study.get("kick_interval")
    drives: list[tuple[float, float] | None] = (
        [*itertools.product(strengths, intervals)] if strengths and intervals else [None]
    )
    given_rates = study.get("shear_rate")
    rates: list[float | None] = [*given_rates] if given_rates else [None]
    given_wells = study.get("well")
    wells: list[tuple[float, float] | None] = [*given_wells] if given_wells else [None]
    # (fewer arguments: product's types go to 10)
    driven = [*itertools.product(drives, rates, wells)]
    for pressure, d, aspect, packing, n, rr, mr, e, (drive, g, w), seed in itertools.product(
        pressures,
        study.get("dimensions", [3]),
        study.get("aspect", [None]),
        packings,
        study["n"],
        study["radius_ratio"],
        study["mass_ratio"],
        rules,
        driven,
        study["seeds"],
    ):
        if packing is None:
            packing = _starting_packing(pressure, d)
        t = Task(
            container=study["container"],
            packing=packing,
            n=n,
            radius_ratio=rr,
            mass_ratio=mr,
            seed=seed,
            equilibrate=study["equilibrate"],
            collisions=study["collisions"],
            time=study["time"],
            blocks=study["blocks"],
            measure=study["measure"],
            key="",
            folder=study["output"],
            checkpoint_seconds=study["checkpoint_seconds"],
        )
        # the space only where it is not the default: 3-D studies keep their keys
        if d != 3:
            t["dimensions"] = d
        if aspect is not None:
            t["aspect"] = aspect_text(aspect)
        if pressure is not None:  # (absent otherwise: the keys of constant-volume tasks are unchanged)
            t["betaP"] = pressure
        if study.get("method", "edmd") != "edmd":  # (absent for the default: the keys are unchanged)
            t["method"] = study["method"]
        _add_rule(t, study, e, drive, g, w)
        t["key"] = _key(t)
        out.append(t)
    return out


def _starting_packing(pressure: float | None, d: int) -> float:
    """Where a constant-pressure task without a packing starts: the fluid's packing at ``pressure``."""
    from ..eos import packing_at_pressure

    if pressure is None:
        raise StudyError("a study without packing needs pressure: give one (parse_study checks them)")
    if d == 2:
        from ..eos import kolafa_rottner

        return packing_at_pressure(min(pressure, FREEZING_START_2D), kolafa_rottner, (0.0, 0.7), 2)
    return packing_at_pressure(min(pressure, FREEZING_START))


def _add_rule(
    t: Task,
    study: Study,
    e: float | None,
    drive: tuple[float, float] | None,
    g: float | None,
    w: tuple[float, float] | None,
) -> None:
    """The task's collision rule, driving, shear and well, each only where given.

    Studies without a key keep their tasks' keys: a restitution, the kicks,
    a shear rate (an elastic sheared task also holds kT = 1 by rescaling)
    and a well enter a task only when the study gives them.
    """
    if e is not None:
        t["restitution"] = e
    if drive is not None:
        t["kicks"], t["kick_interval"] = drive
    if g is not None:
        t["shear_rate"] = g
        if e is None or e >= 1.0:
            t["rescale_interval"] = study.get("rescale_interval") or rescale_interval(g)
    if w is not None:
        t["well_lambda"], t["well_eps"] = w


def _key(task: Task) -> str:
    """The hash of what decides a task's result: every entry but its key, folder and checkpoint_seconds."""
    decides = {k: v for k, v in task.items() if k not in ("key", "folder", "checkpoint_seconds")}
    return hashlib.sha256(json.dumps(decides, sort_keys=True).encode()).hexdigest()[:16]


def _build(task: Task) -> Simulation | EventChain:
    """The task's starting simulation (or event chain): random spheres at its packing, seeded by its seed."""
    from ..builders import random_spheres
    from ..containers import CircularContainer, PeriodicBox, SphericalContainer
    from ..simulation import Simulation

    n, phi = task["n"], task["packing"]
    d = task.get("dimensions", 3)
    aspect = task.get("aspect") or None
    container: Container
    if task["container"] == "box":
        if aspect is None and d == 2:
            aspect = "1:1"
        sides = None if aspect is None else tuple(float(x) for x in aspect.split(":"))
        container = PeriodicBox.for_packing(n, phi, sides)  # spheres of diameter 1 (equal spheres)
        if "shear_rate" in task:
            container = container.sheared_by(task["shear_rate"])
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
    if task.get("method") == "ecmc":
        from ..mc.chain import EventChain

        return EventChain(state, container, seed=task["seed"])
    # (a granular gas cools with the builder's total momentum zero: no flow it cannot dissipate)
    steps = [(task["well_lambda"], -task["well_eps"])] if "well_lambda" in task else None
    sim = Simulation(state, container, restitution=task.get("restitution", 1.0), steps=steps)
    if "kicks" in task:
        from ..dense import RandomKicks

        sim.set_thermostat(RandomKicks(task["kicks"], task["kick_interval"], seed=kick_seed(task["seed"])))
    if "rescale_interval" in task:  # a sheared elastic fluid, held at kT = 1 (the builder's)
        from ..dense import PeculiarRescale

        sim.set_thermostat(PeculiarRescale(1.0, task["rescale_interval"]))
    if "betaP" in task:
        from ..barostat import Barostat

        sim.set_barostat(Barostat(pressure=task["betaP"], kT=1.0, seed=task["seed"]))
    return sim


def kick_seed(seed: int) -> int:
    """The seed of a driven task's kicks: a stream of its own, apart from the builder's (seeded ``seed``).

    Example:
        >>> kick_seed(0) != 0 and kick_seed(0) == kick_seed(0)
        True
    """
    import numpy as np

    return int(np.random.SeedSequence([seed, KICKS_STREAM]).generate_state(1)[0])


#: Labels the kicks' stream in :func:`kick_seed` (any fixed number: it only keeps the streams apart).
KICKS_STREAM = 0x6B69636B


def _split(total: float, parts: int) -> list[int]:
    """``total`` split into ``parts`` integers differing by at most one."""
    q, r = divmod(int(total), parts)
    return [q + (1 if k < r else 0) for k in range(parts)]


def run_task(task: Task) -> dict[str, Any]:
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

    from ..mc.chain import EventChain
    from ..simulation import Simulation

    ecmc = task.get("method") == "ecmc"
    row_file = row_path(task)
    if row_file.exists():
        return pd.read_parquet(row_file).iloc[0].to_dict()
    tdir = Path(task["folder"]) / "tasks" / task["key"]
    tdir.mkdir(parents=True, exist_ok=True)
    prog_path = tdir / "progress.json"
    blocks, n = task["blocks"], task["n"]
    # EDMD: collisions per sphere (each collision moves two); ECMC: lifting events per sphere
    per_sphere = n if ecmc else n / 2
    eq_chunks = _split(task["equilibrate"] * per_sphere, blocks)
    prog: dict[str, Any] | None = None
    if prog_path.exists():
        with open(prog_path, encoding="utf-8") as fh:
            prog = json.load(fh)
        if prog.get("checkpoint") and (tdir / prog["checkpoint"]).exists():
            sim = (EventChain if ecmc else Simulation).load(tdir / prog["checkpoint"])
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
    per_block = _split(task["collisions"] * per_sphere, blocks) if task["collisions"] is not None else None
    last_save = time.monotonic()
    total = 2 * blocks

    def steps(c: int) -> Sequence[int | None]:
        """Collisions of chunk ``c``'s steps (``[None]``: one step to a time)."""
        if c < blocks:
            coll = eq_chunks[c]
        elif per_block is None:
            return [None]
        else:
            coll = per_block[c - blocks]
        return _split(coll, max(1, -(-coll // STEP)))

    def checkpoint(c: int, step: int) -> None:
        nonlocal last_save
        if time.monotonic() - last_save < task["checkpoint_seconds"]:
            return
        old = prog["checkpoint"]
        prog.update(chunk=c, step=step, checkpoint=f"ck-{c}-{step}.npz", pid=os.getpid())
        sim.save(tdir / prog["checkpoint"])
        write_json(prog_path, prog)
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
            if isinstance(sim, Simulation) and sim.barostat is not None:
                sim.barostat.reset_averages()
        for k in range(step, len(plan)):
            if isinstance(sim, EventChain):
                sim.run(events=plan[k])
            elif plan[k] is not None:
                sim.run(collisions=plan[k])
            else:
                sim.run(until=prog["t0"] + task["time"] * (c - blocks + 1) / blocks)
            if k + 1 < len(plan):
                checkpoint(c, k + 1)
        if c >= blocks:
            for m in task["measure"]:
                prog["values"][m].append(block_value(m, sim, sim.observables))  # type: ignore[arg-type]
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
    row_file.parent.mkdir(parents=True, exist_ok=True)
    atomic(row_file, lambda tmp: pd.DataFrame([row]).to_parquet(tmp, index=False))
    for f in tdir.glob("ck-*.npz"):
        f.unlink(missing_ok=True)
    prog_path.unlink(missing_ok=True)  # done: a deleted row is computed afresh
    return row
