"""``python -m hardspheres ...`` is the ``hardspheres`` command."""

from .cli.commands import hardspheres_main

if __name__ == "__main__":
    hardspheres_main()
