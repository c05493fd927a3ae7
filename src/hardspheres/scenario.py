"""Scenarios: spheres as the assignment's input text describes them.

One sphere per line, nine whitespace-separated fields::

    mass radius x y z vx vy vz name

in SI units (kg, m, m/s).  Blank lines are ignored; the name is an ID and
must be unique.  :func:`parse_scenario` reads such text and
:func:`check_scenario` checks it against a container; both raise
:class:`ScenarioError`, whose message names the offending line.

Pure Python (no numpy), so that the assignment's program starts fast.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import IO, TYPE_CHECKING, Any

from .containers import TOUCH_TOL
from .errors import ScenarioError, StuckError  # noqa: F401 (re-exported)
from .messages import quote

if TYPE_CHECKING:
    from .containers import Container

#: Largest magnitude of an input number, so that squares (``|v|^2``, ``|p|^2``) and
#: energies (``m |v|^2``) of numbers up to this stay finite doubles.
MAX_MAGNITUDE = 1e100

FIELDS = ("mass", "radius", "x", "y", "z", "vx", "vy", "vz", "name")


@dataclass
class Scenario:
    """Spheres in input order; plain lists, one entry per sphere.

    Attributes:
        masses: [mass], each > 0.
        radii: [length], each >= 0.
        positions: ``[x, y, z]`` lists [length].
        velocities: ``[vx, vy, vz]`` lists [length/time].
        names: unique IDs.
        lines: input line of each sphere (1-based), for messages.
    """

    masses: list = field(default_factory=list)
    radii: list = field(default_factory=list)
    positions: list = field(default_factory=list)
    velocities: list = field(default_factory=list)
    names: list = field(default_factory=list)
    lines: list = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.masses)


def plain_float(token: str) -> float | None:
    """``float(token)`` if ``token`` is a plain decimal number, else ``None``.

    ``float()`` also takes digit-group underscores (``1_0``) and non-ASCII
    digits, which neither scenarios nor the commands' arguments accept.

    Example:
        >>> plain_float("1e5"), plain_float("1_0"), plain_float("x")
        (100000.0, None, None)
    """
    try:
        x = float(token)
    except ValueError:
        return None
    return None if "_" in token or not token.isascii() else x


def _number(token: str, what: str, lineno: int) -> float:
    x = plain_float(token)
    if x is None:
        raise ScenarioError(f"{what} is not a number: {quote(token)}", lineno)
    if not math.isfinite(x):
        raise ScenarioError(f"{what} is not a finite number: {quote(token)}", lineno)
    if abs(x) > MAX_MAGNITUDE:
        raise ScenarioError(
            f"{what} is too large: {quote(token)} (at most {MAX_MAGNITUDE:g} "
            "in magnitude, so that squares and energies stay finite)",
            lineno,
        )
    return x


def _decode(data: str | bytes) -> str:
    if isinstance(data, str):
        return data.removeprefix("\ufeff")
    try:
        return data.decode("utf-8").removeprefix("\ufeff")  # a BOM from Windows editors
    except UnicodeDecodeError as e:
        lineno = data.count(b"\n", 0, e.start) + 1
        raise ScenarioError(
            f"input is not UTF-8 text (byte 0x{data[e.start]:02x}); save the scenario as UTF-8", lineno
        ) from None


def _stream_lines(stream: Any) -> Iterator[tuple[int, str]]:  # a stream of str or bytes
    """``(line number, text)`` of a stream's lines, read one at a time (UTF-8 if bytes)."""
    for lineno, raw in enumerate(stream, start=1):
        if isinstance(raw, str):
            yield lineno, raw.removeprefix("\ufeff") if lineno == 1 else raw
            continue
        if lineno == 1:
            raw = raw.removeprefix(b"\xef\xbb\xbf")  # a BOM from Windows editors
        try:
            yield lineno, raw.decode("utf-8")
        except UnicodeDecodeError as e:
            raise ScenarioError(
                f"input is not UTF-8 text (byte 0x{raw[e.start]:02x}); save the scenario as UTF-8", lineno
            ) from None


def parse_scenario(data: str | bytes | IO) -> Scenario:
    """Parse scenario text (``str`` or UTF-8 ``bytes``, or a stream of them) into a :class:`Scenario`.

    A stream is read a line at a time, and reading stops at the first bad
    line (endless input, ``yes | spheres 10 1``, is refused at line 1).

    Raises:
        ScenarioError: a line without exactly nine fields, a field that is
            not a finite decimal number of magnitude at most
            :data:`MAX_MAGNITUDE`, mass <= 0, radius < 0, a repeated name, or
            bytes that are not UTF-8.

    Example:
        >>> s = parse_scenario("20 1 0 0 0 0 0 1 one\\n\\n2 5 0 1 100 0 0 0 two\\n")
        >>> s.names, s.lines
        (['one', 'two'], [1, 3])
    """
    if hasattr(data, "readline"):
        lines = _stream_lines(data)
    else:
        lines = enumerate(_decode(data).split("\n"), start=1)
    scn = Scenario()
    seen: dict[str, int] = {}
    for lineno, line in lines:
        tokens = line.split()
        if not tokens:
            continue
        if len(tokens) != 9:
            raise ScenarioError(
                f"expected 9 fields (mass radius x y z vx vy vz name), got {len(tokens)}", lineno
            )
        m, r, x, y, z, vx, vy, vz = (_number(tok, what, lineno) for tok, what in zip(tokens[:8], FIELDS))
        name = tokens[8]
        if m <= 0.0:
            raise ScenarioError(f"mass must be > 0, got {quote(tokens[0])}", lineno)
        if r < 0.0:
            raise ScenarioError(f"radius must be >= 0, got {quote(tokens[1])}", lineno)
        if name in seen:
            raise ScenarioError(
                f"name {quote(name)} is already used on line {seen[name]}; names are IDs", lineno
            )
        seen[name] = lineno
        scn.masses.append(m)
        scn.radii.append(r)
        scn.positions.append([x, y, z])
        scn.velocities.append([vx, vy, vz])
        scn.names.append(name)
        scn.lines.append(lineno)
    return scn


def check_scenario(scn: Scenario, container: Container | float) -> None:
    """Check that every sphere is inside the container and none overlap.

    Args:
        scn: the spheres.
        container: a :class:`hardspheres.containers.Container`, or the
            radius of a spherical container [length].

    Raises:
        ScenarioError: naming the first offending line: a sphere outside,
            a pair overlapping, or a sphere touching the wall and moving
            along it (its reflection would change nothing: see
            :class:`StuckError`).
    """
    from .containers import as_container

    container = as_container(container)
    for i, (p, r, v) in enumerate(zip(scn.positions, scn.radii, scn.velocities)):
        problem = container.check_sphere(p, r, v)
        if problem is not None:
            raise ScenarioError(f"sphere {quote(scn.names[i])} {problem}", scn.lines[i])
    pair = find_overlap(scn.positions, scn.radii)
    if pair is not None:
        i, j = pair
        raise ScenarioError(
            f"sphere {quote(scn.names[j])} overlaps sphere {quote(scn.names[i])} "
            f"(line {scn.lines[i]}); move them apart",
            scn.lines[j],
        )


def find_overlap(positions: Sequence[Sequence[float]], radii: Sequence[float]) -> tuple[int, int] | None:
    """First overlapping pair ``(i, j)`` with ``i < j`` (by ``j``), or ``None``.

    Spheres are hashed into cubic cells as wide as the largest diameter, so
    the check is O(N) for any packing.
    """
    n = len(positions)
    if n < 2:
        return None
    cell = 2.0 * max(radii)
    if cell == 0.0:
        return None  # point particles never overlap
    grid: dict[tuple[int, int, int], list[int]] = {}
    for j in range(n):
        pj, rj = positions[j], radii[j]
        cx, cy, cz = (math.floor(pj[0] / cell), math.floor(pj[1] / cell), math.floor(pj[2] / cell))
        first = None
        for ox in (-1, 0, 1):
            for oy in (-1, 0, 1):
                for oz in (-1, 0, 1):
                    for i in grid.get((cx + ox, cy + oy, cz + oz), ()):
                        pi = positions[i]
                        sigma = (radii[i] + rj) * (1.0 - TOUCH_TOL)
                        dx, dy, dz = pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]
                        if dx * dx + dy * dy + dz * dz < sigma * sigma and (first is None or i < first):
                            first = i
        if first is not None:
            return first, j
        grid.setdefault((cx, cy, cz), []).append(j)
    return None
