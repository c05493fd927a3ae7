"""The event core's one-time compilation, announced and kept out of every timing.

numba compiles the core (:mod:`hardspheres.core._core`) the first time it runs and
caches the machine code on disk; later processes load it in well under a
second.  ``pip install`` compiles the elastic core in 3-D and 2-D into the
installed package (:func:`precompile`, run by ``setup.py``), so a first run
usually finds it there.  Where it does not (another CPU or numba than the
install's, the other collision rules, ``HARDSPHERES_PRECOMPILE=0``), the
first compilation takes a while (about 25 s of one core), so the
commands call :func:`ensure_compiled` before they start any clock: when the
cache is cold it says so once on stderr and compiles the core on a two-sphere
system, so that no rate a command reports includes compilation.

The dimension is a compile-time constant of the core (``_core``, "the
arrays"): 2-D and 3-D each have machine code of their own, compiled on first
use of that dimension and cached side by side.  numba's index files do not
say which were compiled, so after compiling dimension ``d`` a marker file
``compiled-{d}d`` is written beside them (to a temporary, then renamed).
The inelastic collision rule (granular gases) is a compile-time variant
too, with its own marker ``compiled-{d}d-inelastic``.

Example:
    >>> from hardspheres.core.warmup import ensure_compiled
    >>> ensure_compiled(quiet=True) >= 0.0  # compiles silently if needed
    True
"""

from __future__ import annotations

import os
import sys
import time
from typing import TextIO

#: What the first compilation takes on the reference machine [s] (the note quotes it).
TYPICAL_SECONDS = 25

# the core's functions called from Python (each has its own cache index)
_ENTRY_POINTS = ("build", "run", "positions_at", "rebase", "max_overlap")


def _index_paths() -> list[str]:
    """numba's cache index file of each entry point of the core (those it can name)."""
    from . import _core

    paths = []
    for name in _ENTRY_POINTS:
        dispatcher = getattr(_core, name, None)
        cache = getattr(dispatcher, "_cache", None)
        cache_file = getattr(cache, "_cache_file", None)
        path = getattr(cache_file, "_index_path", None)
        if isinstance(path, str):
            paths.append(path)
    return paths


def _marker(
    dimensions: int, inelastic: bool = False, sheared: bool = False, stepped: bool = False
) -> str | None:
    """The file that says the core was compiled for ``dimensions`` (None: numba cannot tell where)."""
    paths = _index_paths()
    name = (
        f"compiled-{dimensions}d"
        + ("-inelastic" if inelastic else "")
        + ("-sheared" if sheared else "")
        + ("-stepped" if stepped else "")
    )
    return os.path.join(os.path.dirname(paths[0]), name) if paths else None


def is_cold(
    dimensions: int = 3, inelastic: bool = False, sheared: bool = False, stepped: bool = False
) -> bool:
    """True when numba's on-disk cache lacks part of the compiled core for ``dimensions`` (2 or 3).

    ``inelastic``: the core's inelastic variant (its own machine code);
    ``sheared``: its Lees-Edwards variant (its own too); ``stepped``: its
    variant with steps (square wells).

    Cheap: looks for the cache's index files and the dimension's marker,
    compiles nothing.  When numba cannot tell (its internals changed),
    answers False: no note is better than a wrong one.
    """
    if os.environ.get("NUMBA_DISABLE_JIT") == "1":
        return False
    paths = _index_paths()
    if not paths:
        return False
    marker = _marker(dimensions, inelastic, sheared, stepped)
    return not all(os.path.exists(p) for p in paths) or not (marker and os.path.exists(marker))


def _compile(
    dimensions: int = 3, inelastic: bool = False, sheared: bool = False, stepped: bool = False
) -> None:
    """Run every entry point of the core once, on two spheres in ``dimensions`` (compiles them)."""
    from ..containers import CircularContainer, PeriodicBox, SphericalContainer
    from .engine import Engine

    d = dimensions
    if sheared:  # two spheres in a sheared box, crossing its faces
        engine = Engine(
            [1.0, 1.0],
            [1.0, 1.0],
            [[-3.0, 0, 0][:d], [3.0, 0.5, 0][:d]],
            [[1.0, 0.7, 0.3][:d], [-1.0, -0.6, 0.2][:d]],
            PeriodicBox((10.0,) * d, shear_rate=0.1),
            restitution=0.9 if inelastic else 1.0,
            tc=1e-3 if inelastic else 0.0,
        )
        engine.max_overlap()
        engine.advance(events=2000)
        engine.positions_at()
        engine.stress_tallies()
        engine.kick(0, engine.time, [0.5, 0.1, 0.0][:d])
        _mark(_marker(d, inelastic, sheared))
        return
    engine = Engine(
        [1.0, 1.0],
        [1.0, 1.0],
        [[-3.0, 0, 0][:d], [3.0, 0, 0][:d]],
        [[1.0, 0, 0][:d], [-1.0, 0, 0][:d]],
        SphericalContainer(10.0) if d == 3 else CircularContainer(10.0),
        restitution=0.9 if inelastic else 1.0,
        tc=1e-3 if inelastic else 0.0,
        steps=[(1.5, -1.0)] if stepped else None,
    )
    engine.max_overlap()
    engine.advance(events=2000)  # past the first rebase of the time origin
    engine.positions_at()
    _mark(_marker(d, inelastic, stepped=stepped))


def _mark(marker: str | None) -> None:
    """Write the marker that says a variant is compiled (nothing if numba cannot tell where)."""
    if marker:
        try:
            tmp = f"{marker}.{os.getpid()}.tmp"
            with open(tmp, "w") as fh:
                fh.write("compiled\n")
            os.replace(tmp, marker)
        except OSError:
            pass  # a read-only cache: the note may come again, nothing else changes


def ensure_compiled(
    quiet: bool = False,
    stream: TextIO | None = None,
    dimensions: int = 3,
    inelastic: bool = False,
    sheared: bool = False,
    stepped: bool = False,
) -> float:
    """Compile the core now if its cache is cold, saying so on ``stream``.

    Args:
        quiet: compile without a word.
        stream: where the one-line note goes (default: ``sys.stderr`` as it
            is when called).
        dimensions: the dimension of space to compile for (2 or 3: each
            has machine code of its own).
        inelastic: the inelastic collision rule's variant (granular gases;
            machine code of its own too).
        sheared: the Lees-Edwards variant (a sheared box; its own too).
        stepped: the variant with steps (square wells; its own too).

    Returns:
        Seconds spent compiling (0.0 when the cache was warm).
    """
    if not is_cold(dimensions, inelastic, sheared, stepped):
        return 0.0
    stream = None if quiet else (sys.stderr if stream is None else stream)
    if stream is not None:
        stream.write(
            f"compiling the event core for {dimensions}-D{', inelastic' if inelastic else ''}"
            f"{', sheared' if sheared else ''}{', with steps' if stepped else ''} "
            "(once per dimension and collision rule, then cached; "
            f"typically {TYPICAL_SECONDS} s) ..."
        )
        stream.flush()
    t0 = time.perf_counter()
    _compile(dimensions, inelastic, sheared, stepped)
    seconds = time.perf_counter() - t0
    if stream is not None:
        stream.write(f" done in {seconds:.1f} s\n")
        stream.flush()
    return seconds


def precompile(dimensions: tuple[int, ...] = (3, 2), stream: TextIO | None = None) -> None:
    """Compile the elastic core for each of ``dimensions`` into its cache, whatever is there.

    The install's build step (``setup.py``) runs this as ``python -m
    hardspheres.core.warmup`` on the files it is about to install, so that
    the first run after ``pip install`` loads machine code instead of
    compiling it (:mod:`hardspheres._jitcache` makes that cache valid where
    pip puts the files).  The other variants (inelastic, sheared, with
    steps) still compile on their first use.
    """
    for d in dimensions:
        t0 = time.perf_counter()
        _compile(d)
        if stream is not None:
            stream.write(f"hardspheres: compiled the {d}-D event core in {time.perf_counter() - t0:.1f} s\n")


if __name__ == "__main__":
    precompile(tuple(int(a) for a in sys.argv[1:]) or (3, 2), stream=sys.stderr)
