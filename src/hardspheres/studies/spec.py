"""The study file: its keys checked and completed, and the grid it spans.

:func:`load_study` reads a TOML file, :func:`parse_study` checks a dict of
the keys (:mod:`hardspheres.studies` lists them) and fills in the defaults;
:data:`GRID` names the parameters a study's grid runs over.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypedDict

from ..containers import MAX_PACKING as _MAX_PACKING
from ..errors import StudyError
from .measures import observable_names

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

#: Densest packing of equal spheres (the one constant, re-exported).
MAX_PACKING = _MAX_PACKING

#: Parameters that make the grid, in the order of the results' columns.
#: (``betaP``, the pressure a constant-pressure study holds, only in their
#: tables: ``pressure`` is the observable.)
GRID: tuple[str, ...] = (
    "method",
    "container",
    "dimensions",
    "aspect",
    "betaP",
    "packing",
    "n",
    "radius_ratio",
    "mass_ratio",
    "restitution",
    "kicks",
    "kick_interval",
    "shear_rate",
    "well_lambda",
    "well_eps",
    "seed",
)

#: What a grid column reads in rows written before it existed (3-D, no aspect).
GRID_DEFAULTS: dict[str, Any] = {"method": "edmd", "dimensions": 3, "aspect": ""}

#: What an event-chain study (``method = "ecmc"``) measures.
ECMC_MEASURES = ("Z", "compressibility", "pressure")

#: The densest random disks the builder places (:data:`hardspheres.builders.RANDOM_DISKS_MAX`).
_DISKS_MAX = 0.72

_KEYS: dict[str, str] = {
    "output": "folder for the results (string)",
    "method": '"edmd" (event-driven dynamics, the default) or "ecmc" (event-chain Monte Carlo: a box, '
    "constant volume; collisions and equilibrate count lifting events per sphere; measures Z, pressure)",
    "container": '"box", "sphere" or "circle" (the round wall in 2-D)',
    "dimensions": "3 or 2 (disks), or a list of them",
    "aspect": "a box's sides in proportion, d numbers > 0 (e.g. [1, 1, 2], [1, 0.8660254]), or a list",
    "packing": "packing fraction(s) in (0, 0.7405) (disks: up to 0.72)",
    "pressure": "constant pressure(s) beta P sigma^d, number(s) > 0 (periodic box only)",
    "n": "number(s) of spheres, integers >= 2",
    "seeds": "a count (integer >= 1) or a list of integer seeds",
    "radius_ratio": "largest/smallest radius, number(s) >= 1",
    "mass_ratio": "largest/smallest mass, number(s) >= 1",
    "restitution": "collisions' restitution coefficient(s), number(s) in (0, 1] (below 1: granular)",
    "kicks": "white-noise driving's strength(s) xi_0^2, number(s) > 0 (with restitution below 1)",
    "kick_interval": "time(s) between kicks, number(s) > 0 (a small fraction of the mean free time)",
    "shear_rate": "Lees-Edwards shear rate(s) g, finite number(s) other than 0 (a periodic box)",
    "rescale_interval": "time between rescalings of the peculiar velocities to kT = 1 in a sheared "
    "elastic fluid, a number > 0 (default min(0.05, 0.02 / shear_rate^2))",
    "well": "a square well [lambda, eps] (width lambda > 1 in contact distances, depth eps > 0 in units "
    "of the starting kT), or a list of them",
    "equilibrate": "collisions per sphere before measuring, number >= 0",
    "collisions": "collisions per sphere measured, number > 0",
    "time": "time measured per run, number > 0",
    "blocks": "blocks per run for error bars, integer >= 2",
    "measure": "list of observable names",
    "checkpoint_seconds": "seconds of work between checkpoints, number >= 0",
    "retries": "times a failing task is retried, integer >= 0",
}


class Study(TypedDict):
    """A parsed study: every key of the study file, checked, with its default filled in.

    The grid's keys are lists (``aspect``: box shapes as tuples, or
    ``[None]`` for the cube or a round wall; ``pressure`` and ``packing``:
    ``None`` when not given); ``output`` is an absolute path.
    """

    output: str
    method: str
    container: str
    dimensions: list[int]
    aspect: list[tuple[float, ...] | None]
    pressure: list[float] | None
    packing: list[float] | None
    n: list[int]
    seeds: list[int]
    radius_ratio: list[float]
    mass_ratio: list[float]
    restitution: list[float] | None
    kicks: list[float] | None
    kick_interval: list[float] | None
    shear_rate: list[float] | None
    rescale_interval: float | None
    well: list[tuple[float, float]] | None
    equilibrate: float
    collisions: float | None
    time: float | None
    checkpoint_seconds: float
    blocks: int
    retries: int
    measure: list[str]


class _TaskSpace(TypedDict, total=False):
    # a task's space and pressure, only where they are not the default (so
    # that 3-D constant-volume tasks keep the keys they had before them)
    dimensions: int
    aspect: str
    betaP: float
    method: str
    restitution: float
    kicks: float
    kick_interval: float
    shear_rate: float
    rescale_interval: float
    well_lambda: float
    well_eps: float


class Task(_TaskSpace):
    """One task: a grid point and a seed, the run's length and observables.

    ``key`` hashes every entry that decides the result (those above
    ``key``); ``folder`` is the study's output and ``checkpoint_seconds``
    how often it saves, neither part of the key.  ``dimensions``
    (default 3), ``aspect`` (default ``""``) and ``betaP`` (constant
    volume) appear only when not the default.
    """

    container: str
    packing: float
    n: int
    radius_ratio: float
    mass_ratio: float
    seed: int
    equilibrate: float
    collisions: float | None
    time: float | None
    blocks: int
    measure: list[str]
    key: str
    folder: str
    checkpoint_seconds: float


def _where(source: str | None) -> str:
    return f"{source}: " if source else ""


def _is_number(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _list_of(raw: Any, key: str, check: Callable[[Any], bool], what: str, source: str | None) -> list[Any]:
    values = raw if isinstance(raw, list) else [raw]
    if not values:
        raise StudyError(f"{_where(source)}{key} is an empty list; give {what}")
    for v in values:
        if not check(v):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {what}")
    return values


def parse_study(data: Any, source: str | None = None, base: str | os.PathLike[str] | None = None) -> Study:
    """Check a study (a dict, as from TOML) and return it complete with defaults.

    Longer than 80 lines: one check per key, in the order the module's
    documentation lists the keys, each a few lines.

    Args:
        data: the study's keys (see the module's documentation).
        source: name of the file it came from, for messages.
        base: folder a relative ``output`` is relative to (default: the
            current directory).

    Returns:
        A dict with every key.

    Raises:
        StudyError: an unknown key or a value out of range; the message
            names the key and says what is allowed.

    Example:
        >>> parse_study({"packing": 0.3, "n": 100, "output": "x"})["seeds"]
        [0]
        >>> parse_study({"packing": 0.8, "n": 100})  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        hardspheres.errors.StudyError: packing = 0.8 is not allowed: give packing fraction(s) in (0, 0.74...
    """
    if not isinstance(data, dict):
        raise StudyError(f"{_where(source)}a study is a table of keys, not {type(data).__name__}")
    for key in data:
        if key not in _KEYS:
            raise StudyError(f"{_where(source)}unknown key {key!r} (allowed: {', '.join(sorted(_KEYS))})")
    for key in ("packing", "n"):
        if data.get(key) is None and not (key == "packing" and data.get("pressure") is not None):
            raise StudyError(f"{_where(source)}missing key {key!r}: {_KEYS[key]}")
    out = data.get("output", "study")
    if not isinstance(out, str) or not out:
        raise StudyError(f"{_where(source)}output = {out!r} is not allowed: give a folder name")
    # absolute: workers may run in another folder (on a cluster: the same
    # path on a shared file system)
    output = str((Path(base or ".") / out).resolve())
    method = data.get("method", "edmd")
    if method not in ("edmd", "ecmc"):
        raise StudyError(f'{_where(source)}method = {method!r} is not allowed: give "edmd" or "ecmc"')
    container = data.get("container", "box")
    if container not in ("box", "sphere", "circle"):
        raise StudyError(
            f'{_where(source)}container = {container!r} is not allowed: give "box", "sphere" or "circle"'
        )
    dimensions, aspect = _space(data, container, source)
    disks = 2 in dimensions

    def fits(v: Any) -> bool:
        return _is_number(v) and 0.0 < v and (v <= _DISKS_MAX if disks else v < MAX_PACKING)

    pressure = None
    if data.get("pressure") is not None:  # (None: a parsed study's constant volume)
        pressure = [
            float(v)
            for v in _list_of(
                data["pressure"], "pressure", lambda v: _is_number(v) and v > 0.0, _KEYS["pressure"], source
            )
        ]
        if container != "box":
            raise StudyError(
                f'{_where(source)}pressure needs container = "box" (its volume moves scale the box)'
            )
    packing = (
        None
        if data.get("packing") is None
        else [
            float(v)
            for v in _list_of(
                data["packing"],
                "packing",
                fits,
                f"area fraction(s) in (0, {_DISKS_MAX}] for disks" if disks else _KEYS["packing"],
                source,
            )
        ]
    )
    n = _list_of(
        data["n"],
        "n",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 2,
        _KEYS["n"],
        source,
    )
    raw_seeds = data.get("seeds", 1)
    if isinstance(raw_seeds, int) and not isinstance(raw_seeds, bool):
        if raw_seeds < 1:
            raise StudyError(f"{_where(source)}seeds = {raw_seeds} is not allowed: give {_KEYS['seeds']}")
        seeds = list(range(raw_seeds))
    else:
        seeds = _list_of(
            raw_seeds,
            "seeds",
            lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 0,
            "a count (integer >= 1) or a list of integer seeds >= 0",
            source,
        )
        if len(set(seeds)) != len(seeds):
            raise StudyError(f"{_where(source)}seeds lists a seed twice: {seeds}")
    ratio = {
        key: [
            float(v)
            for v in _list_of(
                data.get(key, 1.0), key, lambda v: _is_number(v) and v >= 1.0, _KEYS[key], source
            )
        ]
        for key in ("radius_ratio", "mass_ratio")
    }
    restitution = None
    if data.get("restitution") is not None:  # (None: elastic, and the tasks' keys are those of before)
        restitution = [
            float(v)
            for v in _list_of(
                data["restitution"],
                "restitution",
                lambda v: _is_number(v) and 0.0 < v <= 1.0,
                _KEYS["restitution"],
                source,
            )
        ]
        if pressure is not None and min(restitution) < 1.0:
            raise StudyError(
                f"{_where(source)}pressure with restitution below 1: a granular gas cools, and the "
                "barostat holds kT = 1; give one or the other"
            )
    kicks, kick_interval = _kicks(data, restitution, source)
    shear_rate, rescale_interval = _shear(data, container, method, pressure, kicks, source)
    well = _well(data, method, pressure, restitution, kicks, shear_rate, source)
    if "collisions" in data and "time" in data:
        raise StudyError(f"{_where(source)}give collisions or time, not both")
    length: dict[str, Any] = {}
    checks: tuple[tuple[str, float | None, Callable[[float], bool]], ...] = (
        ("equilibrate", 50, lambda v: v >= 0),
        ("collisions", None, lambda v: v > 0),
        ("time", None, lambda v: v > 0),
        ("checkpoint_seconds", 120, lambda v: v >= 0),
    )
    for key, default, ok in checks:
        v = data.get(key, default)
        if v is not None and not (_is_number(v) and ok(v)):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {_KEYS[key]}")
        length[key] = v
    if length["collisions"] is None and length["time"] is None:
        length["collisions"] = 200
    counts: dict[str, int] = {}
    for key, low_default, low in (("blocks", 10, 2), ("retries", 2, 0)):
        v = data.get(key, low_default)
        if not (isinstance(v, int) and not isinstance(v, bool) and v >= low):
            raise StudyError(f"{_where(source)}{key} = {v!r} is not allowed: give {_KEYS[key]}")
        counts[key] = v
    granular = restitution is not None and min(restitution) < 1.0
    usual = (
        ["viscosity", "temperature"]
        if shear_rate
        else ["temperature", "a2"]
        if kicks
        else ["cooling_per_collision", "a2"]
        if granular
        else ["Z", "potential_energy", "mean_temperature"]
        if well
        else ["Z"]
    )
    measure = data.get("measure", usual)
    if isinstance(measure, str):
        measure = [measure]
    if not isinstance(measure, list) or not measure or not all(isinstance(m, str) for m in measure):
        raise StudyError(f"{_where(source)}measure = {measure!r} is not allowed: give {_KEYS['measure']}")
    known = observable_names()
    for m in measure:
        if m not in known:
            raise StudyError(f"{_where(source)}measure: unknown observable {m!r} (known: {', '.join(known)})")
        if m in SHEAR_MEASURES and not shear_rate:
            raise StudyError(
                f"{_where(source)}measure: {m} is measured in a sheared box: give shear_rate too"
            )
        if m in WELL_MEASURES and not well:
            raise StudyError(f"{_where(source)}measure: {m} is measured with a well: give well too")
        if m == "normal_stress_2" and 2 in dimensions:
            raise StudyError(f"{_where(source)}measure: normal_stress_2 (P_yy - P_zz) is 3-D only")
        if shear_rate and m in ("cooling_rate", "cooling_per_collision", "a2"):
            raise StudyError(
                f"{_where(source)}measure: {m} is not measured in a sheared gas (the shear heats it, "
                "and its velocities hold the flow); measure viscosity, normal_stress_1, temperature"
            )
        if kicks and m in ("Z", "compressibility", "pressure", "cooling_rate", "cooling_per_collision"):
            raise StudyError(
                f"{_where(source)}measure: {m} is not measured in a gas driven by kicks (its kT is "
                "held only on average, and it does not cool); measure temperature or a2"
            )
        if granular and m in ("Z", "compressibility", "pressure"):
            raise StudyError(
                f"{_where(source)}measure: {m} divides by one kT, and a granular gas (restitution "
                "below 1) cools; measure temperature, cooling_per_collision, cooling_rate or a2"
            )
    if method == "ecmc":
        if container != "box" or pressure is not None or length["time"] is not None:
            raise StudyError(
                f'{_where(source)}method = "ecmc" runs in container = "box" at constant volume, '
                "for so many collisions (lifting events) per sphere: leave out pressure and time"
            )
        if restitution is not None:
            raise StudyError(f'{_where(source)}method = "ecmc" has no collisions: leave out restitution')
        other = [m for m in measure if m not in ECMC_MEASURES]
        if other:
            raise StudyError(
                f'{_where(source)}measure: {other[0]!r} is not measured by method = "ecmc" '
                f"(it measures {', '.join(ECMC_MEASURES)})"
            )
    return Study(
        output=output,
        method=method,
        container=container,
        dimensions=dimensions,
        aspect=aspect,
        pressure=pressure,
        packing=packing,
        n=n,
        seeds=seeds,
        radius_ratio=ratio["radius_ratio"],
        mass_ratio=ratio["mass_ratio"],
        restitution=restitution,
        kicks=kicks,
        kick_interval=kick_interval,
        shear_rate=shear_rate,
        rescale_interval=rescale_interval,
        well=well,
        equilibrate=length["equilibrate"],
        collisions=length["collisions"],
        time=length["time"],
        checkpoint_seconds=length["checkpoint_seconds"],
        blocks=counts["blocks"],
        retries=counts["retries"],
        measure=list(dict.fromkeys(measure)),
    )


def _kicks(
    data: Any, restitution: list[float] | None, source: str | None
) -> tuple[list[float] | None, list[float] | None]:
    """``(kicks, kick_interval)``: the white-noise driving's lists (``None``, ``None``: no driving)."""
    lists: dict[str, list[float] | None] = {}
    for key in ("kicks", "kick_interval"):
        raw = data.get(key)
        lists[key] = (
            None
            if raw is None
            else [
                float(v) for v in _list_of(raw, key, lambda v: _is_number(v) and v > 0.0, _KEYS[key], source)
            ]
        )
    kicks, interval = lists["kicks"], lists["kick_interval"]
    if kicks is None:
        if interval is not None:
            raise StudyError(
                f"{_where(source)}kick_interval is for the kicks: give kicks (their strength) too"
            )
        return None, None
    if interval is None:
        raise StudyError(
            f"{_where(source)}kicks needs kick_interval, the time between kicks: a small fraction "
            "(1/20) of the mean free time"
        )
    if restitution is None or max(restitution) >= 1.0:
        raise StudyError(
            f"{_where(source)}kicks drive a granular gas: give restitution below 1 (every value; "
            "elastic spheres, kicked, heat without end)"
        )
    return kicks, interval


#: What only a sheared study measures (:data:`hardspheres.studies.measures.OBSERVABLES`).
SHEAR_MEASURES = ("viscosity", "normal_stress_1", "normal_stress_2")


def rescale_interval(shear_rate: float) -> float:
    """The default time between rescalings of a sheared elastic task's peculiar velocities [sigma sqrt(m/kT)].

    ``min(0.05, 0.02 / g^2)``: half the mean free time at packing 0.3, and
    shorter at high rates, where the fluid heats by ``2 eta g^2 V / (d N)``
    in kT per unit time (about 2% of kT between rescalings for ``eta`` near
    1, as at packing 0.3).

    Example:
        >>> rescale_interval(0.1), rescale_interval(2.0)
        (0.05, 0.005)
    """
    return min(0.05, 0.02 / (shear_rate * shear_rate))


def _shear(
    data: Any, container: str, method: str, pressure: list[float] | None, kicks: Any, source: str | None
) -> tuple[list[float] | None, float | None]:
    """``(shear_rate, rescale_interval)``: the rates and the rescaling's interval (``None``: no shear)."""
    raw = data.get("shear_rate")
    interval = data.get("rescale_interval")
    if raw is None:
        if interval is not None:
            raise StudyError(f"{_where(source)}rescale_interval is for a sheared box: give shear_rate too")
        return None, None
    sheared = _list_of(raw, "shear_rate", lambda v: _is_number(v) and v != 0.0, _KEYS["shear_rate"], source)
    rates = [float(v) for v in sheared]
    if len(set(rates)) != len(rates):
        raise StudyError(f"{_where(source)}shear_rate lists a rate twice: {rates}")
    if interval is not None and not (_is_number(interval) and interval > 0):
        what = _KEYS["rescale_interval"]
        raise StudyError(f"{_where(source)}rescale_interval = {interval!r} is not allowed: give {what}")
    for bad, why in (
        (container != "box", f'container = "box" (Lees-Edwards boundaries slide; not {container!r})'),
        (method != "edmd", 'method = "edmd" (event-chain Monte Carlo has no flow)'),
        (pressure is not None, "constant volume (leave out pressure: the barostat would move the box)"),
        (kicks is not None, "no kicks (they act on the whole velocity, flow included)"),
    ):
        if bad:
            raise StudyError(f"{_where(source)}shear_rate needs {why}")
    return rates, None if interval is None else float(interval)


#: What only a study with a well measures (:data:`hardspheres.studies.measures.OBSERVABLES`).
WELL_MEASURES = ("potential_energy", "heat_capacity")


def _well(
    data: Any,
    method: str,
    pressure: list[float] | None,
    restitution: list[float] | None,
    kicks: Any,
    shear_rate: Any,
    source: str | None,
) -> list[tuple[float, float]] | None:
    """The square wells ``[(lambda, eps), ...]`` a study runs over (``None``: hard spheres).

    ``well = [1.5, 1.0]`` is one; ``well = [[1.5, 1.0], [1.5, 0.5]]`` a list.
    """
    raw = data.get("well")
    if raw is None:
        return None
    rows = raw if isinstance(raw, list) and raw and all(isinstance(w, list) for w in raw) else [raw]

    def ok(w: Any) -> bool:
        return (
            isinstance(w, list)
            and len(w) == 2
            and all(_is_number(x) for x in w)
            and w[0] > 1.0
            and w[1] > 0.0
        )

    wells = [(float(w[0]), float(w[1])) for w in _list_of(rows, "well", ok, _KEYS["well"], source)]
    if len(set(wells)) != len(wells):
        raise StudyError(f"{_where(source)}well lists a well twice: {[list(w) for w in wells]}")
    for bad, why in (
        (method != "edmd", 'method = "edmd" (event-chain Monte Carlo has no steps yet)'),
        (pressure is not None, "constant volume (leave out pressure: no barostat with steps yet)"),
        (restitution is not None and min(restitution) < 1.0, "elastic collisions (restitution 1)"),
        (kicks is not None, "no kicks (they drive a granular gas)"),
        (shear_rate is not None, "no shear (steps in a sheared box are not built yet)"),
    ):
        if bad:
            raise StudyError(f"{_where(source)}well needs {why}")
    return wells


def _space(data: Any, container: str, source: str | None) -> tuple[list[int], list[tuple[float, ...] | None]]:
    """``(dimensions, aspects)``: the lists a study's grid runs over (``aspects``: tuples or ``None``)."""
    raw = data.get("aspect")
    aspects: list[tuple[float, ...] | None] = [None]
    if raw is not None:
        shapes = raw if isinstance(raw, list) and raw and all(isinstance(a, list) for a in raw) else [raw]
        for a in shapes:
            if not (isinstance(a, list) and len(a) in (2, 3) and all(_is_number(x) and x > 0 for x in a)):
                raise StudyError(f"{_where(source)}aspect = {a!r} is not allowed: give {_KEYS['aspect']}")
        if len({len(a) for a in shapes}) > 1:
            raise StudyError(f"{_where(source)}aspect: the shapes {raw!r} mix dimensions; give one per study")
        if container != "box":
            raise StudyError(f'{_where(source)}aspect is for container = "box", not {container!r}')
        aspects = [tuple(float(x) for x in a) for a in shapes]
    first = aspects[0]
    default = [len(first)] if first is not None else [2] if container == "circle" else [3]
    dims = _list_of(
        data.get("dimensions", default),
        "dimensions",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and v in (2, 3),
        _KEYS["dimensions"],
        source,
    )
    dims = list(dict.fromkeys(dims))
    if first is not None and dims != [len(first)]:
        raise StudyError(
            f"{_where(source)}aspect {list(first)} has {len(first)} sides: not dimensions = {dims!r}"
        )
    if container == "circle" and dims != [2]:
        raise StudyError(f'{_where(source)}container = "circle" is 2-D: not dimensions = {dims!r}')
    return dims, aspects


def aspect_text(aspect: Sequence[float] | None) -> str:
    """A box shape as the results' ``aspect`` column reads it: ``"1:1:2"`` (``""``: none).

    Example:
        >>> aspect_text((1.0, 0.8660254)), aspect_text(None)
        ('1:0.8660254', '')
    """
    return "" if aspect is None else ":".join(f"{x:.10g}" for x in aspect)


def load_study(path: str | os.PathLike[str]) -> Study:
    """Read and check a study file (TOML); ``output`` is relative to its folder.

    Raises:
        StudyError: unreadable TOML or a bad key (the message names it).
        OSError: the file cannot be read.
    """
    file = Path(path)
    try:
        with open(file, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{file}: not valid TOML: {e}") from None
    return parse_study(data, source=str(file), base=file.parent)
