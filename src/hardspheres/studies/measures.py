"""What a study measures: the observables of one block, by name.

:data:`OBSERVABLES` maps a name to ``f(sim, observables)``; any other public
method of :class:`~hardspheres.observables.Observables` that takes no
argument and returns a number is measured by its own name
(:func:`observable_names` lists them all, :func:`block_value` reads one).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ..errors import StudyError

if TYPE_CHECKING:
    from ..observables import Observables
    from ..simulation import Simulation

#: How a study reads one observable, ``f(sim, observables)`` giving a number.
Measure = Callable[["Simulation", "Observables"], float]


def _packing(sim: Simulation, obs: Observables) -> float:
    """The block's mean packing: the barostat's over its moves, else the packing now (constant)."""
    b = sim.barostat
    return b.mean_packing if b is not None and b.samples else sim.packing


def _volume(sim: Simulation, obs: Observables) -> float:
    """The block's mean volume: the barostat's over its moves, else the volume now (constant)."""
    b = sim.barostat
    return b.mean_volume if b is not None and b.samples else sim.container.volume


def _ks(sim: Simulation, obs: Observables) -> float:
    """Kolmogorov-Smirnov distance of the reduced speeds ``v sqrt(m/kT)`` from Maxwell-Boltzmann."""
    import numpy as np

    from ..maxwell import ks_distance

    st = sim.state()
    kT = obs.temperature()
    x = np.linalg.norm(st.velocities, axis=1) * np.sqrt(st.masses / kT)
    return ks_distance(x, 1.0, 1.0, st.dimensions)


#: Observables a study can measure, name -> ``f(sim, observables)`` giving a
#: number for one block (the :class:`~hardspheres.observables.Observables`
#: averaged since the block began).  Any other public method of
#: ``Observables`` that takes no argument and returns a number is measured
#: by its own name.
OBSERVABLES: dict[str, Measure] = {
    "Z": lambda sim, o: o.compressibility(),
    "compressibility": lambda sim, o: o.compressibility(),
    "pressure": lambda sim, o: o.pressure(),
    "temperature": lambda sim, o: o.temperature(),
    "collision_rate": lambda sim, o: o.collision_rate(),
    "mean_free_time": lambda sim, o: o.mean_free_time(),
    "mean_free_path": lambda sim, o: o.mean_free_path(),
    "mean_speed": lambda sim, o: o.mean_speed(),
    "speeds_ks": _ks,
    "mean_packing": _packing,
    "mean_volume": _volume,
    # a sheared box's (Lees-Edwards): eta = -P_xy / g, N1 = P_xx - P_yy, N2 = P_yy - P_zz
    "viscosity": lambda sim, o: o.estimate("viscosity").mean,
    "normal_stress_1": lambda sim, o: o.estimate("normal_stress_1").mean,
    "normal_stress_2": lambda sim, o: o.estimate("normal_stress_2").mean,
    # a square well's: the potential energy per sphere U/N, the heat capacity per sphere C_V/(N k)
    "potential_energy": lambda sim, o: o.potential_energy().mean / sim.n,
    "heat_capacity": lambda sim, o: o.heat_capacity().mean,
}
_NOT_OBSERVABLES = {"reset", "summary", "speed_histogram", "elapsed"}


def observable_names() -> list[str]:
    """Names a study's ``measure`` accepts (the registry and ``Observables``' methods)."""
    from ..observables import Observables

    names = set(OBSERVABLES)
    for name in dir(Observables):
        if not name.startswith("_") and name not in _NOT_OBSERVABLES and callable(getattr(Observables, name)):
            names.add(name)
    return sorted(names)


def block_value(name: str, sim: Simulation, obs: Observables) -> float:
    """The number observable ``name`` reads for the block just ended.

    Raises:
        StudyError: it is not a number.
    """
    f = OBSERVABLES.get(name)
    value = f(sim, obs) if f is not None else getattr(obs, name)()
    try:
        return float(value)
    except (TypeError, ValueError):
        raise StudyError(
            f"observable {name!r} is not a number (got {type(value).__name__}); a study measures numbers"
        ) from None
