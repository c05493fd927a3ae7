"""Packaging: the library imports where POSIX-only modules are missing (Windows)."""

import subprocess
import sys
import textwrap

# fcntl (file locks) and resource (peak memory) do not exist on Windows: the
# library must import and run without them, and still write files atomically.
WINDOWS_LIKE = textwrap.dedent(
    """
    import sys
    sys.modules["fcntl"] = None      # `import fcntl` now raises ImportError
    sys.modules["resource"] = None
    import importlib, pkgutil
    import hardspheres as hs
    for name in hs.__all__:
        getattr(hs, name)
    for m in pkgutil.walk_packages(hs.__path__, "hardspheres."):
        importlib.import_module(m.name)   # every module, the commands' too
    from hardspheres import fileio
    assert fileio.fcntl is None
    box = hs.PeriodicBox(6.0)
    sim = hs.Simulation(hs.random_spheres(20, 0.2, box, seed=1), box)
    sim.run(collisions=50)
    sim.save(sys.argv[1])
    with fileio.PathLock(sys.argv[1] + ".x") as lock:
        assert not lock.held           # no advisory lock on this platform
    print(hs.Simulation.load(sys.argv[1]).time == sim.time)
    """
)


def test_imports_and_runs_without_fcntl_and_resource(tmp_path):
    out = subprocess.run(
        [sys.executable, "-c", WINDOWS_LIKE, str(tmp_path / "run.npz")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().endswith("True")


def test_package_data_is_installed():
    """py.typed and the viewer's page and three.js ship with the package (``.ci/run`` runs this
    against the built wheel, outside the checkout)."""
    from importlib import resources

    import hardspheres

    root = resources.files(hardspheres)
    assert root.joinpath("py.typed").is_file()
    static = root.joinpath("viz", "_static")
    for name in ("viewer.html", "three.module.min.js", "three.core.min.js", "OrbitControls.js", "LICENSE"):
        assert static.joinpath(name).is_file(), name


def test_extras_split_the_user_from_the_test_stack():
    """A user installs the library with GSD and plots without pytest (pyproject.toml's extras)."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib
    from pathlib import Path

    meta = tomllib.loads((Path(__file__).resolve().parents[1] / "pyproject.toml").read_text())["project"]
    extras = meta["optional-dependencies"]
    for user in ("io", "plot", "analysis", "sweep", "view", "notebook", "all"):
        assert not any(dep.startswith(("pytest", "hypothesis", "ruff", "mypy")) for dep in extras[user]), user
    assert any(d.startswith("gsd") for d in extras["io"]) and any(
        d.startswith("matplotlib") for d in extras["plot"]
    )
    assert {"Programming Language :: Python :: 3", "Operating System :: Microsoft :: Windows"} <= set(
        meta["classifiers"]
    )


def test_an_installed_wheel_ships_the_compiled_core():
    """``pip install .`` compiles the elastic core and the chains in 3-D and 2-D into the package
    (setup.py's build step), so the first run loads them (``.ci/run`` runs this against the built
    wheel; in a checkout, where the sources change, it is skipped)."""
    import pathlib
    from importlib import metadata

    import pytest

    import hardspheres
    from hardspheres.core import warmup

    checkout = pathlib.Path(__file__).resolve().parents[1] / "src"
    if pathlib.Path(hardspheres.__file__).resolve().is_relative_to(checkout):
        pytest.skip("the package is imported from this checkout, not from an installed wheel")
    shipped = [str(f) for f in metadata.files("hardspheres") or ()]
    for family in ("core", "mc"):  # the event core and the event chains
        assert any(
            f"{family}/__pycache__/numba-" in f and "_core.run-" in f and f.endswith(".nbi") for f in shipped
        ), family
    assert any(f.endswith("compiled-3d") for f in shipped) and any(f.endswith("compiled-2d") for f in shipped)
    assert not warmup.is_cold(3) and not warmup.is_cold(2)
