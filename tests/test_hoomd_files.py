"""GSD files written by HOOMD-blue (its schema, no hardspheres log): read, viewed, analysed, simulated from.

The files here are written with the ``gsd`` library the way HOOMD-blue's HPMC writes them:
``configuration/step``, ``box``, ``dimensions``, ``particles/position`` (single precision),
``image``, ``typeid``, ``types``, optionally ``type_shapes``; no velocities, and no
``particles/diameter`` unless asked (HOOMD-blue's default, 1, is then the diameter).
"""

import json

import numpy as np
import pytest

import hardspheres as hs
from hardspheres.cli.commands import main
from hardspheres.errors import TrajectoryError

gsd_hoomd = pytest.importorskip("gsd.hoomd")

L = 6.0


def hoomd_file(path, dim=3, frames=6, tilt=(0.0, 0.0, 0.0), type_shapes=None, diameter=None):
    """A HOOMD-blue-like trajectory: a lattice (spacing 1.5 in 3-D, 1.2 in 2-D) whose particles
    random-walk 0.06 per frame and cross the box's sides."""
    rng = np.random.default_rng(7)
    a = 1.5 if dim == 3 else 1.2
    m = int(L / a)
    # a side of the lattice 0.02 from the box's: particles cross it, and images are written
    grid = np.stack(np.meshgrid(*[np.arange(m) * a - L / 2 + 0.02] * dim, indexing="ij"), -1).reshape(-1, dim)
    n = len(grid)
    x = grid.copy()
    with gsd_hoomd.open(path, "w") as f:
        for k in range(frames):
            if k:
                x = x + rng.normal(scale=0.06, size=x.shape)
            image = np.floor((x + L / 2) / L).astype(np.int32)
            wrapped = x - image * L
            fr = gsd_hoomd.Frame()
            fr.configuration.step = 10_000 * k
            fr.configuration.dimensions = dim
            fr.configuration.box = [L, L, L if dim == 3 else 0.0, *tilt]
            fr.particles.N = n
            fr.particles.types = ["A"]
            fr.particles.typeid = np.zeros(n, np.uint32)
            if type_shapes is not None:
                fr.particles.type_shapes = type_shapes
            if diameter is not None:
                fr.particles.diameter = np.full(n, diameter, np.float32)
            fr.particles.position = np.concatenate([wrapped, np.zeros((n, 3 - dim))], 1).astype(np.float32)
            fr.particles.image = np.concatenate([image, np.zeros((n, 3 - dim), np.int32)], 1)
            f.append(fr)
    return path, x


def test_read_trajectory_reads_a_hoomd_file(tmp_path):
    path, last = hoomd_file(tmp_path / "hpmc.gsd")
    fr = hs.read_trajectory(path)
    assert fr.container == hs.PeriodicBox(L) and fr.n == 64 and len(fr.times) == 6
    np.testing.assert_array_equal(fr.times, 10_000.0 * np.arange(6))  # steps: Monte Carlo has no clock
    np.testing.assert_array_equal(fr.radii, 0.5)  # no particles/diameter: HOOMD-blue's default 1
    np.testing.assert_allclose(fr.unwrapped()[-1], last, atol=1e-5)  # images read: single precision
    assert not np.any(fr.velocities)


def test_the_shapes_diameter_decides_and_a_written_diameter_is_read(tmp_path):
    path, _ = hoomd_file(tmp_path / "a.gsd", type_shapes=[{"type": "Sphere", "diameter": 1.2}])
    np.testing.assert_allclose(hs.read_trajectory(path).radii, 0.6)
    path, _ = hoomd_file(tmp_path / "b.gsd", diameter=0.9)
    np.testing.assert_allclose(hs.read_trajectory(path).radii, 0.45, rtol=1e-6)


def test_hoomd_disks_in_2d(tmp_path):
    path, _ = hoomd_file(tmp_path / "disks.gsd", dim=2, type_shapes=[{"type": "Disk", "diameter": 1.0}])
    fr = hs.read_trajectory(path)
    assert fr.container == hs.PeriodicBox((L, L)) and fr.positions.shape == (6, 25, 2)
    psi6 = hs.Hexatic().compute(fr).orders
    assert psi6.shape == (6,) and np.all((0 <= psi6) & (psi6 <= 1))


def test_analyses_of_a_hoomd_file(tmp_path):
    path, x = hoomd_file(tmp_path / "hpmc.gsd")
    fs = hs.SelfIntermediate(k=2 * np.pi, lags=[10_000.0]).compute(str(path))  # the path, read whole
    dx = x - hoomd_file(tmp_path / "again.gsd", frames=5)[1]  # the walk's last step (same seed)
    r = np.linalg.norm(dx, axis=1)
    assert fs.F[0, 0] == pytest.approx(np.mean(np.sinc(2 * r)), abs=0.05)  # one step: sin(kr)/kr
    g = hs.RDF(r_max=2.5).compute(hs.read_trajectory(path))
    assert g.r.size > 0


def test_a_simulation_starts_from_a_hoomd_frame(tmp_path):
    path, _ = hoomd_file(tmp_path / "hpmc.gsd")
    fr = hs.read_trajectory(path)
    sim = hs.Simulation(fr.state(seed=1), fr.container)
    sim.run(collisions=500)
    assert sim.counters["collisions"] == 500
    assert sim.state().kinetic_energy() == pytest.approx(1.5 * (fr.n - 1))  # drawn at kT = 1, conserved


def test_view_and_plot_take_a_hoomd_file(tmp_path, capsys):
    path, _ = hoomd_file(tmp_path / "hpmc.gsd")
    assert main(["view", str(path), "-o", str(tmp_path / "v.html")]) == 0
    assert (tmp_path / "v.html").stat().st_size > 1000
    pytest.importorskip("matplotlib")
    assert main(["plot", "gr", str(path), "-o", str(tmp_path / "g.png")]) == 0


@pytest.mark.parametrize(
    "kwargs, said",
    [
        ({"tilt": (0.2, 0.0, 0.0)}, "a triclinic box (tilt factors xy, xz, yz = 0.2, 0, 0)"),
        (
            {"type_shapes": [{"type": "ConvexPolyhedron", "rounding_radius": 0, "vertices": [[0, 0, 0]]}]},
            "particles of type 'A' are a ConvexPolyhedron (particles/type_shapes)",
        ),
    ],
)
def test_what_cannot_be_read_is_named(tmp_path, capsys, kwargs, said):
    path, _ = hoomd_file(tmp_path / "x.gsd", **kwargs)
    with pytest.raises(TrajectoryError, match=said.replace("(", r"\(").replace(")", r"\)")):
        hs.read_trajectory(path)
    assert main(["view", str(path), "-o", str(tmp_path / "v.html")]) == 1
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and said in err


def test_type_shapes_as_json_strings(tmp_path):
    """gsd stores type_shapes as JSON strings; a reader may meet either."""
    path, _ = hoomd_file(tmp_path / "s.gsd", type_shapes=[json.dumps({"type": "Sphere", "diameter": 1.0})])
    assert hs.read_trajectory(path).radii[0] == 0.5
