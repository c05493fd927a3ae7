"""Sphinx configuration: the hardspheres documentation site.

Build it (warnings are errors) with::

    python -m sphinx -W -b html docs docs/_build/html

Tutorials in ``docs/tutorials/*.md`` are MyST notebooks executed on every
build (myst-nb, cached in ``docs/_build/.jupyter_cache``); a cell that
raises fails the build.
"""

import logging
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# the checkout's sources first (for the notebooks' kernels too), so that the
# pages document this tree even when another copy of the package is installed;
# a copy of docs/ elsewhere (tests/test_docs.py) documents the importable package
if (ROOT / "src" / "hardspheres").is_dir():
    sys.path.insert(0, str(ROOT / "src"))
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT / "src")] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    )
# the notebooks' kernels draw figures inline (matplotlib-inline), never on a display
if os.environ.get("MPLBACKEND", "").lower() == "agg":
    del os.environ["MPLBACKEND"]

from hardspheres.version import package_version  # noqa: E402

# --- a quiet build ---------------------------------------------------------------
# The notebooks' kernels: ipykernel warns on stderr, for every notebook, that it
# talks to the build over local TCP; an IPython profile of the build's own
# (docs/_build/.ipython) sets the kernels' log level to errors.
_IPYTHON = ROOT / "docs" / "_build" / ".ipython"
(_IPYTHON / "profile_default").mkdir(parents=True, exist_ok=True)
(_IPYTHON / "profile_default" / "ipython_kernel_config.py").write_text('c.IPKernelApp.log_level = "ERROR"\n')
os.environ["IPYTHONDIR"] = str(_IPYTHON)
# accessible-pygments (furo's colour schemes) sets the root logger to INFO when
# imported, which prints each notebook client's "Executing notebook" line: back
# to warnings once it is imported
try:
    import a11y_pygments  # noqa: E402, F401
except ImportError:
    pass
logging.getLogger().setLevel(logging.WARNING)

project = "hardspheres"
author = "the hardspheres developers"
copyright = "2026, the hardspheres developers"
release = package_version()
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax 3 from the package (copied to _static/mathjax), not from a CDN:
    # the site is opened from the disk, offline (docs/check_html.py checks it)
    "sphinx-mathjax-offline",
    "sphinx.ext.viewcode",
    "myst_nb",
]

source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
exclude_patterns = ["_build", "**.ipynb_checkpoints", "images/make.sh", "*.csv", "README.md"]
templates_path = ["_templates"]

# --- API reference ------------------------------------------------------------
API_INDEX = """API reference
=============

Every public name, generated from the docstrings (Google style, types from the
annotations).  This page is written by ``docs/conf.py`` from
``hardspheres.__all__`` at every build, so a new name gets its page at once;
``tests/test_docs.py`` checks the built pages (and those of each subpackage's
``__all__``).

The package root
----------------

What ``import hardspheres as hs`` gives (``hs.Simulation``, ``hs.PeriodicBox``, ...):

.. autosummary::
   :toctree: generated

{root}

Modules
-------

Each module and subpackage, with its contract (the ``__init__`` docstring) and
every public function and class:

.. autosummary::
   :toctree: generated
   :recursive:

   hardspheres
"""


def _write_api_index():
    import hardspheres

    names = sorted(hardspheres.__all__, key=str.lower)
    text = API_INDEX.format(root="\n".join(f"   hardspheres.{n}" for n in names))
    path = ROOT / "docs" / "api" / "index.rst"
    path.parent.mkdir(exist_ok=True)
    if not path.exists() or path.read_text() != text:  # unchanged: no rebuild
        path.write_text(text)


# Modules without a page of their own: the commands (documented in the user
# guide, "Commands"), the engine's internals behind ``Simulation``, and helpers
# that only the package itself calls.  Their names are public for the package's
# own imports, not for scripts; a package listed here takes its modules along.
# tests/test_docs.py reads this list (every other public module has a page).
INTERNAL_MODULES = [
    "hardspheres.cli",
    "hardspheres.core.bench",
    "hardspheres.core.contacts",
    "hardspheres.core.engine",
    "hardspheres.core.reference",
    "hardspheres.core.scan",
    "hardspheres.core.warmup",
    "hardspheres.analysis.compute",
    "hardspheres.fileio",
    "hardspheres.messages",
    "hardspheres.progress",
    "hardspheres.studies.cluster",
    "hardspheres.studies.dispatch",
    "hardspheres.studies.files",
    "hardspheres.studies.tables",
    "hardspheres.studies.task",
    "hardspheres.version",
]

_write_api_index()
autosummary_generate = True
autosummary_context = {"internal_modules": INTERNAL_MODULES}
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
# numpy's array-like annotations by their names, not their expansions
# (``_Buffer | _SupportsArray[dtype[Any]] | ...``); applies to modules with
# ``from __future__ import annotations`` (every module of the package)
autodoc_type_aliases = {
    "ArrayLike": "numpy.typing.ArrayLike",
    "DTypeLike": "numpy.typing.DTypeLike",
    "NDArray": "numpy.typing.NDArray",
}
autodoc_typehints_format = "short"
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True
# the subpackages list their modules in a "Modules:" section, the checkpoint its "Versions:"
napoleon_custom_sections = [("Modules", "params_style"), ("Versions", "params_style")]
# names the docstrings use as plain words or that live outside the package
nitpicky = False
suppress_warnings = ["myst.header", "autosummary.import_cycle"]

# --- MyST and notebooks -------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "cache"
nb_execution_cache_path = str(ROOT / "docs" / "_build" / ".jupyter_cache")
nb_execution_timeout = 300
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

# --- HTML -----------------------------------------------------------------------
html_theme = "furo"
html_title = f"hardspheres {release}"
html_static_path = ["_static"]
# wide tables scroll, the validation summary is compact (docs/_static/custom.css)
html_css_files = ["custom.css"]
html_theme_options = {"navigation_with_keys": True}


_documenting = {"module": None}


def _note_module(app, what, name, obj, options, lines):
    if what == "module":
        _documenting["module"] = name


def _public_module(name):
    """A module with an API page of its own: public and not in ``INTERNAL_MODULES``."""
    internal = any(name == m or name.startswith(m + ".") for m in INTERNAL_MODULES)
    private = any(p.startswith("_") for p in name.split("."))
    return name.startswith("hardspheres") and not internal and not private


def _skip_described_elsewhere(app, what, name, obj, skip, options):
    """On a module's page, leave out what has a page elsewhere, so each object is described once.

    * what the package root exports (it has a page of its own), and
    * what a module re-exports from another public module (its home module's page has it),

    so cross-references never find two targets.
    """
    if what != "module":
        return None
    import hardspheres

    if name in hardspheres.__all__ and getattr(hardspheres, name, None) is obj:
        return True
    home = getattr(obj, "__module__", None)
    here = _documenting["module"]
    if isinstance(home, str) and here and home != here and _public_module(home):
        return True
    return None


def setup(app):
    app.connect("autodoc-process-docstring", _note_module)
    app.connect("autodoc-skip-member", _skip_described_elsewhere)
