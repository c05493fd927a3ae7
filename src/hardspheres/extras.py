"""The optional packages, each loaded on first use with a one-line error naming its extra.

The library needs only numpy and numba.  Trajectory files, pictures, the
structural analyses and studies need more, installed by the extras of
``pyproject.toml`` (docs/getting-started.md, "Extras").  :func:`need`
imports one and, when it is missing, raises
:class:`~hardspheres.errors.MissingExtraError`, whose message says which
extra installs it.

Example:
    >>> from hardspheres.extras import EXTRAS, need
    >>> EXTRAS["freud"]
    'analysis'
    >>> need("math", "an example").sqrt(4.0)
    2.0
"""

from __future__ import annotations

import importlib
from types import ModuleType

from .errors import MissingExtraError

#: The extra of ``pyproject.toml`` that installs each optional package (by its import name).
EXTRAS = {
    "gsd": "io",
    "matplotlib": "plot",
    "freud": "analysis",
    "scipy": "analysis",
    "playwright": "view",
    "dask": "sweep",
    "distributed": "sweep",
    "pandas": "sweep",
    "pyarrow": "sweep",
    "tomli": "sweep",
}


def need(module: str, what: str) -> ModuleType:
    """Import ``module`` (e.g. ``"gsd.hoomd"``) for ``what``, or say which extra installs it.

    Args:
        module: the dotted module name.
        what: what needs it, for the message (``"RDF"``, ``"a GSD trajectory"``).

    Returns:
        The module.

    Raises:
        MissingExtraError: its package is not installed (an error raised
            inside an installed package passes through unchanged).
    """
    top = module.partition(".")[0]
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as e:
        if e.name is not None and e.name.partition(".")[0] != top:
            raise  # the package is there, and something it imports is not
        raise MissingExtraError(what, top, EXTRAS.get(top, "all")) from None
