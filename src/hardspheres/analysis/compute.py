"""The shared base of the analyses' compute objects (freud's contract)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..errors import NotComputedError

if TYPE_CHECKING:
    from matplotlib.axes import Axes


class Compute:
    """The one base of every analysis: freud's contract.

    A subclass sets ``_results`` (the names its ``compute()`` fills) and
    ``_computed = True`` at the end of ``compute()``, which returns ``self``.
    Reading a result before raises :class:`~hardspheres.errors.NotComputedError`;
    ``plot(ax=None)`` draws on :meth:`_axes` and returns the Axes.
    """

    _computed = False
    _results: tuple[str, ...] = ()

    def _need(self) -> None:
        if not self._computed:
            raise NotComputedError(f"{type(self).__name__}: call compute() first")

    def _axes(self, ax: Axes | None) -> Axes:
        """Where :meth:`plot` draws: ``ax``, or a new figure's axes (results computed first)."""
        self._need()
        from ..extras import need

        plt = need("matplotlib.pyplot", f"{type(self).__name__}.plot")

        return plt.figure().add_subplot() if ax is None else ax

    def __getattr__(self, name: str) -> Any:  # only called for attributes not (yet) set
        if name in type(self)._results:
            self._need()
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
