"""The event chains' compilation at install: ``python -m hardspheres.mc.warmup [D ...]``.

The install's build step (``setup.py``) runs this after the event core's
(:func:`hardspheres.core.warmup.precompile`), so the first
:class:`~hardspheres.mc.chain.EventChain` after ``pip install`` loads machine
code instead of compiling it (about 4 s per dimension otherwise).  The cache
is :mod:`hardspheres._jitcache`'s, valid where pip puts the files.
"""

from __future__ import annotations

import sys
import time
from typing import TextIO


def precompile(dimensions: tuple[int, ...] = (2, 3), stream: TextIO | None = None) -> None:
    """Build a chain (cells, overlap check) and run straight chains once per dimension (compiles them)."""
    from ..builders import random_spheres
    from ..containers import PeriodicBox
    from .chain import EventChain

    for d in dimensions:
        t0 = time.perf_counter()
        box = PeriodicBox((8.0,) * d)
        chain = EventChain(random_spheres(16, 0.2, box, seed=1), box, seed=1)
        chain.run(chains=20)
        if stream is not None:
            seconds = time.perf_counter() - t0
            stream.write(f"hardspheres: compiled the {d}-D event chains in {seconds:.1f} s\n")


if __name__ == "__main__":
    precompile(tuple(int(a) for a in sys.argv[1:]) or (2, 3), stream=sys.stderr)
