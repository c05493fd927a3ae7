"""Analyses of frames and runs: structure, transport, glassy dynamics, collisions, jamming.

Contract: each analysis is a compute object in the manner of freud: built
with its parameters, ``compute(source)`` returns ``self``, results read
before ``compute`` raise :class:`~hardspheres.errors.NotComputedError`, and
``plot(ax=None)`` returns the matplotlib Axes.  Analyses read
:class:`~hardspheres.frames.Frames`, a :class:`~hardspheres.State` or a
:class:`~hardspheres.Simulation`; they never change what they read.  They
import the run-loop vocabulary and below, never studies, pictures or commands.

Modules:
    compute: :class:`~hardspheres.analysis.compute.Compute`, the shared base.
    structure: :class:`~hardspheres.analysis.structure.RDF`,
        :class:`~hardspheres.analysis.structure.StructureFactor`,
        :class:`~hardspheres.analysis.structure.BondOrder`.
    transport: :class:`~hardspheres.analysis.transport.MSD`,
        :class:`~hardspheres.analysis.transport.VACF`, the Helfand moments
        (:class:`~hardspheres.analysis.transport.ShearViscosity`,
        :class:`~hardspheres.analysis.transport.ThermalConductivity`) and the
        Enskog and Yeh-Hummer references.
    dynamics: the correlators of glass formers, in any dimension:
        :class:`~hardspheres.analysis.dynamics.SelfIntermediate` (F_s(k, t),
        tau_alpha), :class:`~hardspheres.analysis.dynamics.CollectiveIntermediate`
        (F(k, t)), :class:`~hardspheres.analysis.dynamics.NonGaussian`
        (alpha_2), :class:`~hardspheres.analysis.dynamics.VanHove` (G_s(r, t)),
        :class:`~hardspheres.analysis.dynamics.Overlap` (Q(t), chi_4).
    collisions: the event record:
        :class:`~hardspheres.analysis.collisions.EventRecorder` (a writer),
        :class:`~hardspheres.analysis.collisions.FreeFlights`,
        :class:`~hardspheres.analysis.collisions.Recollisions`,
        :class:`~hardspheres.analysis.collisions.ContactForces`.
    jamming: packings: :class:`~hardspheres.analysis.jamming.Contacts`
        (network, rattlers, z, g(h)), the force exponent, and
        :class:`~hardspheres.analysis.jamming.JammingPoint` (phi_J).
    granular: clustering of granular gases:
        :class:`~hardspheres.analysis.granular.LowKStructureFactor` (S(k) at
        the box's smallest wave vectors, per frame) and
        :class:`~hardspheres.analysis.granular.LocalDensity` (local packing
        fractions and their histogram).
"""
