"""Studies: parameter sweeps run as independent tasks on Dask, resumable.

Contract: a study is data (a TOML file or a dict) turned into tasks, each a
function of its parameters alone, so that a rerun, a resumed task and a task
on another worker give the same bits.  This family builds simulations and
analyses and writes tables; it imports them and everything below, never the
pictures or the commands (``hardspheres sweep`` lives in :mod:`hardspheres.cli`).
:mod:`hardspheres.studies.validate` holds the validation studies against
published equations of state and transport coefficients.

Modules:
    spec: the study file, its keys checked and completed
        (:func:`~hardspheres.studies.spec.parse_study`,
        :func:`~hardspheres.studies.spec.load_study`) and the grid's
        parameters (:data:`~hardspheres.studies.spec.GRID`).
    measures: what a study measures, by name
        (:data:`~hardspheres.studies.measures.OBSERVABLES`).
    task: one task, from its parameters to its row
        (:func:`~hardspheres.studies.task.tasks`,
        :func:`~hardspheres.studies.task.run_task`).
    files: the output folder's layout, written atomically.
    tables: the results and their summary over seeds
        (:func:`~hardspheres.studies.tables.summarize`).
    cluster: the Dask clients (a scheduler's address, a new LocalCluster).
    dispatch: :func:`~hardspheres.studies.dispatch.sweep`, the tasks sent
        out and the tables written as they end.
    validate: the validation studies.

A study is a grid of runs (packing fraction x N x seeds x size and mass
ratios) described in a TOML file; each point of the grid and each seed is
one *task*, one run of equal-length blocks whose observables are averaged.
Tasks run on a :class:`distributed.LocalCluster` (one worker process per
core) or on an existing Dask cluster, or in this process (``serial=True``).

Study file (every key but ``packing`` and ``n`` is optional)::

    output = "eos-study"        # folder for results, relative to this file
    container = "box"           # "box" (periodic) or "sphere" (hard wall; "circle" in 2-D)
    dimensions = 3              # 3 (spheres) or 2 (disks), or a list [2, 3]
    aspect = [1, 1, 2]          # a box's sides in proportion (d numbers), or a list of them
    packing = [0.1, 0.2, 0.3]   # volume fractions, each in (0, 0.7405); disks: area, up to 0.72
    # pressure = [2.0, 5.0]     # constant pressure(s) beta P sigma^d instead (periodic box)
    n = [256, 1024]             # spheres per run
    seeds = 4                   # 4 seeds (0..3), or a list [1, 5, 9]
    radius_ratio = 1.0          # largest / smallest radius (or a list)
    mass_ratio = 1.0            # largest / smallest mass (or a list)
    # restitution = [0.9, 0.8]  # inelastic collisions: a granular gas that cools (or a list)
    # kicks = 0.5               # ... or driven by white noise of this strength xi_0^2 (or a list)
    # kick_interval = 0.02      # the time between its kicks (or a list)
    # shear_rate = [0.1, 0.5]   # Lees-Edwards shear rate(s) g of the periodic box (or one)
    # rescale_interval = 0.05   # sheared elastic fluid: time between its rescalings to kT = 1
    # well = [1.5, 1.0]         # a square well [lambda, eps] around each sphere (or a list of them)
    equilibrate = 50            # collisions per sphere before measuring
    collisions = 500            # collisions per sphere measured (or: time = 20.0)
    blocks = 10                 # blocks for the error bars within a run
    measure = ["Z", "collision_rate"]

Spheres have mean diameter about 1 (the container is sized for it), mass 1
(or log-uniform up to ``mass_ratio``) and ``kT = 1``, so times are in units
of ``sigma sqrt(m / kT)``.

Space: ``dimensions = 2`` runs disks (``packing`` is then the area
fraction, at most 0.72, the random-disk builder's limit), in a periodic
square box or (``container = "sphere"`` or ``"circle"``) a circle.
``aspect`` shapes the box: ``[1, 0.8660254]`` is the ``sqrt(3)/2`` box a
hexagonal crystal of disks fits, ``[1, 1, 2]`` a 1:1:2 box; its length
gives the dimension (so ``dimensions`` may be left out), and a list of
shapes is a grid over them.  Without ``aspect`` the box is a cube (a
square).  Results hold ``dimensions`` and ``aspect`` (``"1:1:2"``; ``""``
for the cube and for round walls) as grid columns; a 3-D study without
``aspect`` keeps the task keys it had before they existed, so its finished
rows are found again.

Granular gases: with ``restitution`` (one coefficient in (0, 1] or a list,
a grid column) every collision and reflection has that restitution
coefficient, and the gas cools in its homogeneous cooling state (no
driving).  Its ``measure`` defaults to ``cooling_per_collision`` and ``a2``
(Haff's law and the kurtosis of the velocities, per block); ``Z`` and
``pressure``, which divide by one ``kT``, are refused, and so is
``pressure`` (the barostat holds ``kT = 1``).  Studies without the key keep
their tasks' keys.  With ``kicks`` (the strength ``xi_0^2`` of white-noise
driving, :class:`~hardspheres.dense.RandomKicks`) and ``kick_interval``
(the time between kicks; each one value or a list, grid columns) the gas
is driven to a steady state instead: every restitution must be below 1,
each task's kicks are seeded from its seed (a stream apart from the
builder's), ``measure`` defaults to ``temperature`` and ``a2``, and ``Z``,
``pressure`` and the cooling rates are refused.

Shear flow: with ``shear_rate`` (one rate ``g`` other than 0, or a list, a
grid column) each run's periodic box is sheared by Lees-Edwards boundaries
(flow along x, gradient along y; ``container = "box"``, constant volume, no
kicks, ``method = "edmd"``).  An elastic fluid is held at ``kT = 1`` (the
study's unit: no ``kT`` key) by rescaling its peculiar velocities
(:class:`~hardspheres.dense.PeculiarRescale`) every ``rescale_interval``
(default ``min(0.05, 0.02 / g^2)``, a number: the fluid heats by about
``2 eta g^2 V / (d N)`` in kT per unit time between rescalings, so shorten
it for a dense fluid or a high rate); a granular one (``restitution``
below 1) gets no thermostat: its steady state balances the shear's work
against the dissipation.  ``measure`` defaults to ``viscosity`` (``-P_xy /
g`` over each block) and ``temperature`` (the peculiar kT at each block's
end: how far the rescaling lets it rise); ``normal_stress_1`` and (3-D)
``normal_stress_2`` may be measured too.  ``hardspheres plot flow
results.parquet`` draws the flow curve.

Square wells: with ``well`` (``[lambda, eps]``, a width ``lambda > 1`` in
contact distances and a depth ``eps > 0``, or a list of them; grid columns
``well_lambda`` and ``well_eps``) each run's pairs closer than ``lambda``
contact distances have the energy ``-eps`` (elastic spheres at constant
volume: not with ``restitution`` below 1, ``kicks``, ``shear_rate``,
``pressure`` or ``method = "ecmc"``).  ``eps`` is in units of the starting
``kT = 1``; the energy, not the temperature, is held, so ``kT`` moves as
pairs bond.  ``measure`` defaults to ``Z``, ``potential_energy`` (per
sphere, ``U / N``, averaged over each block) and ``mean_temperature`` (the
mean ``kT`` over each block, which ``Z`` divides by); ``energy_drift`` and
``heat_capacity`` (per sphere, from each block's kinetic-energy
fluctuations: 32 samples a block at least) may be measured too.

Constant pressure: with ``pressure`` (``beta P sigma^3``, one or a list) each
run holds it with a :class:`~hardspheres.barostat.Barostat` (isotropic
moves, seeded by the task's seed) in a periodic box, so an equation of
state at fixed pressures is one sweep (measure ``mean_packing``: the mean
over each block's volume moves; ``mean_volume`` likewise); ``packing`` is then optional and is where each
run starts (default: Hansen-Goos's fluid at that pressure,
:func:`~hardspheres.eos.packing_at_pressure`, below freezing's 11.5), and
the results' column ``betaP`` holds it (``pressure`` is the observable: the
virial pressure measured).  ``hardspheres plot sweep --x betaP --y
mean_packing`` draws it against the inverse of Hansen-Goos.

The output folder holds:

* ``rows/KEY.parquet``: each finished task's row, written (atomically) by
  the worker as the task ends; a task whose row exists is never run again.
* ``tasks/KEY/``: the task's checkpoint (``progress.json`` and a
  :meth:`Simulation.save <hardspheres.simulation.Simulation.save>` file,
  written every ``checkpoint_seconds`` of work at a block boundary), from
  which a task whose worker died resumes on another worker, and
  ``attempts.jsonl``, one line per start (process id, block it started at).
* ``results.parquet`` and ``results.csv``: one row per finished task
  (rewritten as each task finishes); ``summary.parquet`` and
  ``summary.csv``: one row per parameter point, the mean over seeds with
  its standard error.

Blocks and checkpoints fall at fixed points of the run (chunk boundaries
fixed by the study, not by the clock) and a checkpoint resumes bit for bit,
so a study's results are the same bits however it was run: serially, on a
LocalCluster, or on a cluster that lost a worker midway.

Example:
    >>> import tempfile, hardspheres as hs
    >>> tmp = tempfile.TemporaryDirectory()
    >>> spec = {"output": tmp.name, "packing": [0.2, 0.3], "n": 64,
    ...         "seeds": 2, "equilibrate": 5, "collisions": 20, "blocks": 4}
    >>> df = hs.sweep(spec, serial=True)
    >>> df.shape[0], sorted(df["packing"].unique().tolist())
    (4, [0.2, 0.3])
    >>> s = summarize(df)
    >>> s[["packing", "seeds"]].values.tolist()
    [[0.2, 2.0], [0.3, 2.0]]
    >>> bool((s["Z"] > 1).all() and (s["Z_err"] > 0).all())
    True
    >>> tmp.cleanup()
"""

# the names users import from hardspheres.studies, each defined in its module
# (no __all__: each is documented once, on its home module's page)
from ..errors import StudyError  # noqa: F401
from .cluster import connect, local_client  # noqa: F401
from .dispatch import sweep  # noqa: F401
from .measures import OBSERVABLES, observable_names  # noqa: F401
from .spec import GRID, GRID_DEFAULTS, MAX_PACKING, aspect_text, load_study, parse_study  # noqa: F401
from .tables import measured, summarize  # noqa: F401
from .task import FREEZING_START, FREEZING_START_2D, STEP, run_task, tasks  # noqa: F401
