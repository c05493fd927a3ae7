"""Helpers the test modules share: the command in a subprocess, synthetic frames, the viewer's data.

Imported as ``helpers`` (``pythonpath = ["tests"]`` in pyproject.toml's pytest
options: with ``--import-mode=importlib`` the tests folder is not on
``sys.path`` otherwise).  Fixture factories live in ``conftest.py``; these are
plain functions, for module-level fixtures and helpers as well as tests.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np

import hardspheres as hs
from hardspheres.frames import Frames

ROOT = Path(__file__).resolve().parents[1]

#: Where the package the tests import lives: this tree's ``src``, or the
#: site-packages of an installed wheel (``.ci/run`` tests the wheel too).
PACKAGE_ROOT = Path(hs.__file__).resolve().parents[1]

#: The environment of the commands run: that package first on PYTHONPATH.
ENV = {
    **os.environ,
    "PYTHONPATH": os.pathsep.join(
        [str(PACKAGE_ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    ),
}


def hs_cmd(*args, cwd=ROOT, env=None, timeout=300, stdout=subprocess.PIPE, check=False):
    """``python -m hardspheres ARGS`` in ``cwd``: the completed process (text).

    Args:
        args: the command's arguments (``str()`` of each).
        env: variables to set on top of :data:`ENV`.
        timeout: seconds before the test fails (a hang, not a measurement).
        stdout: where stdout goes (captured by default); stderr is captured.
        check: assert exit status 0 and no traceback.
    """
    res = subprocess.run(
        [sys.executable, "-m", "hardspheres", *map(str, args)],
        cwd=cwd,
        stdout=stdout,
        stderr=subprocess.PIPE,
        text=True,
        env=ENV if env is None else {**ENV, **env},
        timeout=timeout,
    )
    if check:
        assert res.returncode == 0, (args, res.stderr)
        assert "Traceback" not in res.stderr, res.stderr
    return res


def default_sigint() -> None:
    """``preexec_fn`` of a child that a test sends Ctrl-C: SIGINT handled as in a terminal.

    A test run started in the background by a non-interactive shell (``cmd &``)
    inherits SIGINT ignored, and so would every child; Python then installs no
    KeyboardInterrupt handler and a Ctrl-C test hangs (seen 2026-12-02: three
    Ctrl-C tests failed in a backgrounded full run, each passing in the
    foreground)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def hs_popen(*args, cwd=ROOT, env=None):
    """``python -m hardspheres ARGS`` started in the background: the :class:`subprocess.Popen`
    (stdout and stderr piped, text; ``env`` as for :func:`hs_cmd`)."""
    return subprocess.Popen(
        [sys.executable, "-m", "hardspheres", *map(str, args)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=ENV if env is None else {**ENV, **env},
    )


def spheres_cmd(*argv, input=None, text=True, env=None, timeout=300, **kw):
    """``python spheres.py ARGV`` (the assignment's program) in the project's root.

    Args:
        argv: the program's arguments (``str()`` of each).
        input: what it reads on stdin (text, or bytes with ``text=False``);
            without it and without ``stdin=``, an empty stdin.
        env: variables to set on top of :data:`ENV`.
        kw: as for :func:`subprocess.run` (``stdin=``, ``stdout=``, ``check=``);
            stdout and stderr are captured unless given.

    Returns:
        The completed process.
    """
    kw.setdefault("stdout", subprocess.PIPE)
    kw.setdefault("stderr", subprocess.PIPE)
    if input is None:
        kw.setdefault("stdin", subprocess.DEVNULL)
    return subprocess.run(
        [sys.executable, "spheres.py", *map(str, argv)],
        input=input,
        text=text,
        cwd=ROOT,
        env=ENV if env is None else {**ENV, **env},
        timeout=timeout,
        **kw,
    )


def periodic_gas(n, phi, seed, **kw):
    """A :class:`~hardspheres.Simulation` of ``n`` spheres of diameter 1 filling the
    fraction ``phi`` of the periodic box (:func:`hardspheres.random_spheres`, ``kw`` to it)."""
    box = hs.PeriodicBox.for_packing(n, phi)
    return hs.Simulation(hs.random_spheres(n, phi, box, seed=seed, **kw), box)


def synthetic_frames(
    n=40,
    n_frames=12,
    container=10.0,
    box=None,
    seed=5,
    masses=(1.0, 3.0),
    duration=1.0,
    ball=False,
    events=None,
):
    """Spheres on straight lines (velocities Maxwellian at kT = 1) and fake events.

    Args:
        n, n_frames: spheres and frames.
        container, box: the container's radius, or the periodic box's edge.
        seed: random seed.
        masses: the masses drawn from at random; ``None``: all 1.
        duration: the frames span ``[0, duration]``.
        ball: start uniformly in a ball of 0.6 times the container's size
            (else in a cube of edge the size: the radius, or half the box).
        events: how many random events; ``None``: two fixed ones (a
            collision at 0.2, a reflection at 0.5).
    """
    rng = np.random.default_rng(seed)
    radii = rng.uniform(0.4, 1.0, n)
    m = np.ones(n) if masses is None else rng.choice(masses, n)
    size = container if container else 0.5 * box
    if ball:
        direction = rng.normal(size=(n, 3))
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        start = direction * (rng.uniform(0, 1, (n, 1)) ** (1 / 3) * 0.6 * size)
    else:
        start = rng.uniform(-0.5, 0.5, (n, 3)) * size
    velocities = rng.normal(size=(n, 3)) / np.sqrt(m)[:, None]
    times = np.linspace(0.0, duration, n_frames)
    positions = start[None] + times[:, None, None] * velocities[None]
    vel = np.broadcast_to(velocities, (n_frames, n, 3)).copy()
    if events is None:
        event_times = np.array([0.2, 0.5])
        kinds = np.array([1, 0], np.int8)
        ei, ej = np.array([0, 1]), np.array([2, -1])
    else:
        event_times = np.sort(rng.uniform(0.0, duration, events))
        kinds = rng.integers(0, 2, events).astype(np.int8)
        ei = rng.integers(0, n, events)
        ej = np.where(kinds == 1, (ei + 1 + rng.integers(0, n - 1, events)) % n, -1)
    return Frames(
        times=times,
        positions=positions,
        velocities=vel,
        radii=radii,
        masses=m,
        names=[f"s{i}" for i in range(n)],
        container=container,
        box=box,
        event_times=event_times,
        event_kinds=kinds,
        event_i=ei,
        event_j=ej,
    )


def embedded_data(html):
    """The data a viewer page embeds (its ``hs-data`` script), decoded."""
    m = re.search(r'<script id="hs-data" type="application/json">(.*?)</script>', html, re.S)
    assert m, "no frame data in the page"
    return json.loads(m.group(1))
