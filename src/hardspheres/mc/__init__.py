"""Monte Carlo: event-chain sampling of the same spheres, containers and states as the event core.

Contract: this family samples the equilibrium (Boltzmann) distribution of
hard spheres and disks without dynamics.  It takes the same
:class:`~hardspheres.State` and container as :class:`hardspheres.Simulation`
and gives back states, frames (through the same writers, so every analysis
reads its samples unchanged), checkpoints and pressures with error bars in
the form of :class:`hardspheres.Observables`.  Every move is exact (the
roots of :mod:`hardspheres.physics`, no overlap ever); a state moves to the
event core and back in one call.  It sits above the run loop (it hands
states to :class:`~hardspheres.Simulation`) and below the file formats and
analyses, which it does not import.

Modules:
    _core: the numba kernels: cells, the next-lift search (and its
        brute-force twin), the chain loop.
    chain: :class:`~hardspheres.mc.chain.EventChain`, the Python face of the
        loop: runs, writers, checkpoints, the conversion to and from
        :class:`~hardspheres.Simulation`.
    observables: :class:`~hardspheres.mc.observables.ChainObservables`, the
        pressure per axis from the chains, with blocking errors.
    warmup: the chains compiled at install (``python -m hardspheres.mc.warmup``).

Importing this package imports nothing (numba loads with ``chain``).
"""
