"""The exact dynamics: the event core, its engine, the reference and the compiler set-up.

Contract: this family knows nothing of :class:`hardspheres.Simulation`, of
files or of commands.  It takes arrays and a container, advances them event
by event, and gives arrays back (positions, velocities, counters, the event
record, a checkpoint's arrays).  It imports only the terms below it
(:mod:`hardspheres.containers`, :mod:`~hardspheres.events`,
:mod:`~hardspheres.physics`, :mod:`~hardspheres.state`,
:mod:`~hardspheres.scenario`, :mod:`~hardspheres.errors`).

Modules:
    _core: the numba kernels and the one compiled event loop.
    engine: :class:`~hardspheres.core.engine.Engine`, the Python face of the loop.
    checkpoint: the checkpoint format and version, the checks of every array
        before the core sees it, and the migrations of older layouts.
    reference: the pure-Python brute-force engine the compiled one must equal bit for bit.
    warmup: compiles the core once (announced on stderr) when numba's cache is cold.
    bench: collisions per second of one system (the ``bench`` command prints them).

Importing this package imports nothing (numba loads with ``engine``).
"""
