"""Every exception and warning of hardspheres, in one place.

Each is a :class:`ValueError` subclass (or a :class:`UserWarning`) whose
message is one line that names what is wrong (a line, an option, a file, an
argument) and says what to do.  They are re-exported where users have always
imported them (``hardspheres.ScenarioError``, ``hardspheres.containers.ContainerError``, ...).

This module imports nothing of hardspheres but :mod:`hardspheres.messages`:
any module may raise these.
"""

from __future__ import annotations

from collections.abc import Sequence

from .messages import quote


class BuildError(ValueError):
    """The requested scenario cannot be built; the message says what to change."""


class ContainerError(ValueError):
    """A container cannot be built or read back; the message says why."""


class BoxShapeError(ContainerError):
    """A box shape that cannot be simulated (sides, dimension); the message says what is allowed."""


class ShearError(ContainerError):
    """A Lees-Edwards shear that cannot be set up or run here (a bad rate, an engine without it); the
    message says why and what to do."""


class PeriodicBoxRequired(ValueError):
    """Images, unwrapped positions and transport need a :class:`PeriodicBox`."""


class CompressionError(ValueError):
    """A compression that cannot be run; the message names the option."""


class FileInUseError(ValueError):
    """Another writer (this process or another) holds the file's lock."""


class NoMeasurementError(ValueError):
    """Results were asked for before anything was measured."""


class ScenarioError(ValueError):
    """A scenario that cannot be simulated; the message says where and why.

    Attributes:
        line: 1-based input line the problem is on, or ``None``.
    """

    def __init__(self, message: str, line: int | None = None) -> None:
        self.line = line
        super().__init__(f"line {line}: {message}" if line is not None else message)


class StuckError(ScenarioError):
    """A run that cannot go on: its next event would repeat without end.

    Raised by both engines, with the run stopped before that event (the
    spheres stay where they are, at the last event's time).

    Attributes:
        reason: ``"sliding"`` (a sphere touching the wall moves along it: its
            reflection would change nothing and come again at once) or
            ``"frozen"`` (the clock stopped advancing: more than
            :func:`hardspheres.physics.frozen_limit` collisions and
            reflections in a row without the clock advancing).
        time: the instant [time].
        sphere: index of a sphere involved (the one at the wall).
        inelastic: the run's collisions are inelastic (restitution below 1):
            a frozen clock is then most likely an inelastic collapse, and
            the message says how to resolve it (the TC model).
    """

    def __init__(
        self,
        reason: str,
        time: float,
        sphere: int,
        names: Sequence[str] | None = None,
        inelastic: bool = False,
    ) -> None:
        self.reason, self.time, self.sphere, self.inelastic = reason, time, sphere, inelastic
        who = quote(names[sphere]) if names is not None else f"#{sphere}"
        if reason == "sliding" and inelastic:
            message = (
                f"at t = {time:.6g} sphere {who} touches the container wall and moves "
                "along it: inelastic reflections took its speed off the wall, and point "
                "reflections cannot model sliding; give the TC model's tc (a small "
                "fraction of the mean free time) or a wall restitution of 1"
            )
        elif reason == "sliding":
            message = (
                f"at t = {time:.6g} sphere {who} touches the container wall and moves "
                "along it: it would slide along the wall, which point reflections "
                "cannot model (its reflection would change nothing and repeat "
                "forever); give it a velocity component off the wall"
            )
        elif inelastic:
            message = (
                f"the clock is stuck at t = {time:.6g} (sphere {who} and others): "
                "an inelastic collapse, infinitely many collisions in a finite time; "
                "give the TC model's tc (a small fraction of the mean free time) to resolve it"
            )
        else:
            message = (
                f"the clock is stuck at t = {time:.6g} (sphere {who} and others): "
                "collisions and reflections at that instant do not end, as for a "
                "light sphere trapped between the wall and a far heavier sphere; "
                "outside what the model resolves"
            )
        super().__init__(message)

    def named(self, names: Sequence[str]) -> StuckError:
        """The same error, naming the sphere by ``names``."""
        return StuckError(self.reason, self.time, self.sphere, names, self.inelastic)


class NotComputedError(ValueError):
    """A result was read before :meth:`compute` was called."""


class AnalysisInputError(ValueError):
    """An analysis cannot be computed from its input or options (bare positions without radii, too few
    frames, a fit window with no points); the message names the input and says what to pass or record."""


class ArgumentError(ValueError):
    """An argument a library call cannot use (out of range, of the wrong kind, a time before the clock);
    the message names the argument and says what it must be."""


class TrajectoryError(ValueError):
    """A trajectory file that cannot be read or written (not GSD or XYZ, not of hardspheres, no frames,
    a closed writer); the message names the file and says what to do."""


class PictureError(ValueError):
    """A picture, movie, page or plot that cannot be made (a bad option, no frames, a missing program);
    the message names the option and says what to change."""


class UsageError(ValueError):
    """Bad command-line arguments; the message names the option and says what to give."""


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed (damaged, truncated, foreign); the message says why."""


class TruncatedTrajectory(UserWarning):
    """A trajectory file ends before the run that wrote it meant to (cut short)."""


class NotAContinuation(ValueError):
    """An ``append=True`` writer's file does not end where the simulation is."""


class StudyError(ValueError):
    """A study file or option is wrong, or a task failed; the message says which."""


class BarostatError(ValueError):
    """Constant pressure that cannot be held here (not a periodic box, a bad option); the message says why."""


class MissingExtraError(ModuleNotFoundError):
    """A feature needs an optional package that is not installed; the message names the extra to install.

    A :class:`ModuleNotFoundError` (an :class:`ImportError`), so ``except ImportError`` still catches it.

    Attributes:
        extra: the extra of ``pyproject.toml`` that installs the package (``"analysis"``, ``"io"``, ...).
    """

    def __init__(self, what: str, module: str, extra: str) -> None:
        self.extra = extra
        super().__init__(
            f'{what} needs {module}, which is not installed: pip install "hardspheres[{extra}]" '
            f'(from a checkout: pip install ".[{extra}]")',
            name=module,
        )


class ResolutionWarning(UserWarning):
    """An estimate at the edge of what the data resolve (a crossing or a peak at the last lag); the
    message says what to record instead."""


class DriftWarning(UserWarning):
    """A time average over a run whose state drifts (a sheared fluid heating up without a thermostat);
    the message says by how much and what to do."""
