"""The build step that compiles the event core while the package is installed.

Everything else about the package is in pyproject.toml.  After the files
are laid out for installation (or, for an editable install, in place),
``python -m hardspheres.core.warmup`` compiles the elastic event core in 3-D
and 2-D into the numba cache that ships beside them, and ``python -m
hardspheres.mc.warmup`` the straight event chains, so that the first
simulation after ``pip install`` loads machine code rather than waiting for
it (see docs/getting-started.md).  The cache is keyed to the sources'
content and checked against this machine's CPU and numba's version on
every load; anything that does not match is compiled on first use, as
without this step.  ``HARDSPHERES_PRECOMPILE=0`` skips the step; a failure
of it is reported and does not fail the install.
"""

import os
import shutil
import subprocess
import sys

from setuptools import setup
from setuptools.command.build_py import build_py


class BuildPyCompiled(build_py):
    """``build_py``, then the event core compiled into the laid-out package's cache."""

    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False):
            root = os.path.dirname(os.path.abspath(self.get_package_dir("hardspheres")))
        else:
            root = os.path.abspath(self.build_lib)
            # a build folder reused from an earlier build keeps caches of older sources
            for core in ("core", "mc"):
                cache = os.path.join(root, "hardspheres", core, "__pycache__")
                for name in os.listdir(cache) if os.path.isdir(cache) else ():
                    if name.startswith("numba-"):
                        shutil.rmtree(os.path.join(cache, name), ignore_errors=True)
        if os.environ.get("HARDSPHERES_PRECOMPILE", "1") == "0":
            return
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, os.environ.get("PYTHONPATH")) if p)
        for module, what in (("core", "the event core"), ("mc", "the event chains")):
            command = [sys.executable, "-m", f"hardspheres.{module}.warmup", "3", "2"]
            try:
                done = subprocess.run(command, env=env, cwd=root, check=False).returncode == 0
            except OSError:
                done = False
            if not done:
                print(
                    f"hardspheres: compiling {what} at install failed; it compiles on first use instead",
                    file=sys.stderr,
                )


setup(cmdclass={"build_py": BuildPyCompiled})
