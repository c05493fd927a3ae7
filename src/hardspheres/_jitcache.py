"""Where numba keeps the compiled cores' machine code: keyed to their source's content, relocatable.

numba's own on-disk cache keys a module's machine code to the source file's
path (its folder's name and a hash of its absolute path) and its stamp
(modification time and size).  Neither suits the compiled cores:

* the loops inline the kernels of :mod:`hardspheres.physics`, so machine
  code compiled with an older ``physics.py`` would be reused after it
  changed (numba checks only the file that defines a function);
* a cache compiled when the package is built (``setup.py``: the build
  step runs :mod:`hardspheres.core.warmup`) would never be found where pip
  puts the files, at another path and with other modification times.

So each core caches in a folder named after a digest of the files its
machine code comes from, and that digest is the stamp numba checks: the
cache is valid wherever the files are, as long as their bytes are the same.
numba still checks, per compiled function, its own version, the Python
version, the function's bytecode and this machine's CPU (name and
features): a cache built elsewhere is ignored and the function compiled
again, never loaded wrongly.

The folder is ``__pycache__/numba-DIGEST`` beside the core's module, or
``NAME-DIGEST`` in ``NUMBA_CACHE_DIR`` when that is set (the user's
choice), or, when the first is not writable, in numba's user-wide cache
folder.

Example:
    >>> from hardspheres._jitcache import source_digest
    >>> len(source_digest(__file__))
    16
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from typing import Any

import numba
from numba.core import caching


def source_digest(*paths: str) -> str:
    """The first 16 hex digits of the SHA-256 of the files' bytes, in order."""
    digest = hashlib.sha256()
    for path in paths:
        with open(path, "rb") as fh:
            digest.update(fh.read())
    return digest.hexdigest()[:16]


def cache_dir(module_file: str, digest: str) -> str:
    """The folder a core's machine code is cached in (see the module's docstring)."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        name = os.path.basename(os.path.dirname(os.path.abspath(module_file)))
        return os.path.join(os.path.abspath(os.environ["NUMBA_CACHE_DIR"]), f"{name}-{digest}")
    return os.path.join(os.path.dirname(os.path.abspath(module_file)), "__pycache__", f"numba-{digest}")


def _user_wide(module_file: str, digest: str) -> str:
    """The fallback folder: numba's user-wide cache, one folder per core and digest."""
    from numba.misc.appdirs import AppDirs

    name = os.path.basename(os.path.dirname(os.path.abspath(module_file)))
    root = AppDirs(appname="numba", appauthor=False).user_cache_dir
    return os.path.join(root, "hardspheres", f"{name}-{digest}")


def cached_compiler(module_file: str, digest: str) -> Callable[..., Callable[[Any], Any]]:
    """A ``compiler(**options)`` whose ``compiler(**options)(fn)`` is ``numba.njit(**options)(fn)``, cached.

    The cache is in :func:`cache_dir` (or the user-wide fallback), stamped
    with ``digest`` rather than the file's modification time.
    """
    folders = (cache_dir(module_file, digest), _user_wide(module_file, digest))

    def locator(folder: str) -> type:
        class _Locator(caching._CacheLocator):
            def __init__(self, py_func: Any, py_file: str) -> None:
                self._lineno = py_func.__code__.co_firstlineno

            def get_cache_path(self) -> str:
                return folder

            def get_source_stamp(self) -> str:
                return digest

            def get_disambiguator(self) -> str:
                return str(self._lineno)

            @classmethod
            def from_function(cls, py_func: Any, py_file: str) -> _Locator:
                return cls(py_func, py_file)

        return _Locator

    class _Impl(caching.CompileResultCacheImpl):
        _locator_classes: list[Any] = [locator(folder) for folder in folders]

    class _Cache(caching.FunctionCache):
        _impl_class = _Impl

    def compiler(**options: Any) -> Callable[[Any], Any]:
        def decorate(fn: Any) -> Any:
            dispatcher = numba.njit(**options)(fn)
            dispatcher._cache = _Cache(dispatcher.py_func)  # what cache=True sets, with our locator
            return dispatcher

        return decorate

    return compiler
