"""File formats: trajectories (GSD, extended XYZ) and the assignment's report.

Contract: writers in this family observe a simulation and never change it
(no event, no clock, no state is touched by a write).  Everything written goes
to a temporary file renamed into place, or to a file held under a lock;
every OSError becomes one line naming the file; everything read back is
checked before it reaches the engine.  This family imports the run-loop
vocabulary (:mod:`hardspheres.writers`, :mod:`hardspheres.frames`) and below,
never analyses, studies, pictures or commands.

Modules:
    trajectory: :class:`~hardspheres.io.trajectory.GSDWriter`,
        :class:`~hardspheres.io.trajectory.XYZWriter` and
        :func:`~hardspheres.io.trajectory.read_trajectory`.
    report: the assignment's text and JSON-lines reports (numpy-free).
"""
