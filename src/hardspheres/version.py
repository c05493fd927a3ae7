"""The installed distribution's version: pyproject.toml's, the one place it is set."""


def package_version() -> str:
    """``hardspheres``'s version, or ``"0+unknown"`` from a source tree that is not installed."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("hardspheres")
    except PackageNotFoundError:  # run from a source tree that is not installed
        return "0+unknown"
