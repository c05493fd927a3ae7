"""Analyses of frames and runs: structure (g(r), S(k), bond order) and transport.

Contract: each analysis is a compute object in the manner of freud: built
with its parameters, ``compute(source)`` returns ``self``, results read
before ``compute`` raise :class:`~hardspheres.errors.NotComputedError`, and
``plot(ax=None)`` returns the matplotlib Axes.  Analyses read
:class:`~hardspheres.frames.Frames`, a :class:`~hardspheres.State` or a
:class:`~hardspheres.Simulation`; they never change what they read.  They
import the run-loop vocabulary and below, never studies, pictures or commands.

Modules:
    structure: :class:`~hardspheres.analysis.structure.RDF`,
        :class:`~hardspheres.analysis.structure.StructureFactor`,
        :class:`~hardspheres.analysis.structure.BondOrder`.
    transport: :class:`~hardspheres.analysis.transport.MSD`,
        :class:`~hardspheres.analysis.transport.VACF`, the Helfand moments
        (:class:`~hardspheres.analysis.transport.ShearViscosity`,
        :class:`~hardspheres.analysis.transport.ThermalConductivity`) and the
        Enskog and Yeh-Hummer references.
"""
