#!/usr/bin/env python3
"""Launcher for the assignment's program from a checkout: ``python spheres.py 120 105 < in.txt``."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "src"))

from hardspheres.cli import spheres_main  # noqa: E402

if __name__ == "__main__":
    spheres_main()
