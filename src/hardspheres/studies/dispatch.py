"""The sweep: a study's unfinished tasks sent out (in this process, on a
LocalCluster or on a cluster at an address) and the tables written as they end."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from ..errors import StudyError
from .cluster import local_client
from .files import row_path, write_table
from .spec import GRID, load_study, parse_study
from .tables import collect, summarize
from .task import run_task, tasks

if TYPE_CHECKING:
    import pandas as pd
    from distributed import Client

    from .spec import Task


def _describe(task: Task) -> str:
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
        + "".join(f" {k}={_text(task.get(k))}" for k in GRID if k not in _SAID and k in task)
    )


#: The grid's entries :func:`_describe` says in its own words (the others follow as ``key=value``).
_SAID = ("container", "betaP", "packing", "n", "seed", "radius_ratio", "mass_ratio")


def _text(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def sweep(
    spec: str | os.PathLike[str] | dict[str, Any],
    client: Client | None = None,
    *,
    serial: bool = False,
    workers: int | None = None,
    out: TextIO | None = None,
) -> pd.DataFrame:
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
        :func:`~hardspheres.studies.tables.summarize`'s table in ``summary.parquet``/``.csv``).
        ``df.attrs["computed"]`` counts the tasks this call ran.

    Raises:
        StudyError: a bad study, an unreachable cluster, or a failed task
            (the message names it).
    """
    from ..extras import need

    for module in ("pandas", "pyarrow") + (() if serial else ("distributed",)):
        need(module, "a study")
    study = load_study(spec) if isinstance(spec, (str, os.PathLike)) else parse_study(spec)
    all_tasks = tasks(study)
    folder = Path(study["output"])
    try:
        (folder / "rows").mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise OSError(f"cannot create {folder}: {e.strerror or e}") from None
    todo = [t for t in all_tasks if not row_path(t).exists()]
    say = (lambda text: print(text, file=out, flush=True)) if out is not None else (lambda text: None)
    say(
        f"{len(all_tasks)} tasks: {len(all_tasks) - len(todo)} already done, "
        f"{len(todo)} to run; results in {folder}"
    )
    from ..progress import Progress

    bar = Progress(len(todo), stream=out) if out is not None else None
    done = 0

    def finished(task: Task) -> None:
        nonlocal done
        done += 1
        write_table(collect(all_tasks), folder / "results")
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
            on = local_client(workers) if client is None else client
            try:
                import importlib.util

                link = getattr(on, "dashboard_link", None)
                hint = (
                    ""
                    if importlib.util.find_spec("bokeh")
                    else " (its pages need bokeh: pip install 'hardspheres[sweep]')"
                )
                say(f"dashboard: {link}{hint}" if link else "dashboard: none")
                _run_on(on, todo, study["retries"], finished)
            finally:
                if own:
                    cluster = on.cluster  # (local_client's: always set)
                    on.close(timeout=10)
                    if cluster is not None:
                        cluster.close(timeout=10)
    finally:
        if bar is not None and bar.on and done:
            bar.close()
    df = collect(all_tasks)
    write_table(df, folder / "results")
    write_table(summarize(df), folder / "summary")
    df.attrs["computed"] = len(todo)
    return df


def _fail(task: Task, e: BaseException) -> StudyError:
    msg = str(e).splitlines()[0] if str(e) else type(e).__name__
    return StudyError(f"task {_describe(task)} failed: {msg}")


def _run_here(task: Task) -> dict[str, Any]:
    try:
        return run_task(task)
    except (ValueError, ArithmeticError) as e:
        raise _fail(task, e) from None


def _run_on(client: Client, todo: list[Task], retries: int, finished: Callable[[Task], None]) -> None:
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
