"""Faults (issue 9): full disks, two writers, signals, damaged checkpoints, misuse.

Each test here failed before the fix it checks.  Full disks are /dev/full
(ENOSPC on every write), a writer whose file fails after a few frames, or
(as root, where mounting is allowed) a tiny tmpfs; signals and concurrent
writers are real processes.
"""

import errno
import json
import os
import signal
import stat
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest
from helpers import ENV, ROOT, hs_cmd, hs_popen, spheres_cmd

import hardspheres as hs
from hardspheres.core import checkpoint
from hardspheres.core.engine import CheckpointError
from hardspheres.fileio import FileInUseError, PathLock, atomic_write
from hardspheres.io.trajectory import GSDWriter, TruncatedTrajectory, XYZWriter, read_trajectory


def one_line(err, *words, warnings_too=True):
    """The error is one line (besides the compile note and, if allowed, warnings)."""
    assert "Traceback" not in err and err.endswith("\n"), err
    lines = [
        ln
        for ln in err.splitlines()
        if not ln.startswith("compiling the event core") and not (warnings_too and ": warning: " in ln)
    ]
    assert len(lines) == 1, err
    for w in words:
        assert w in lines[0], (w, err)


@pytest.fixture(scope="module")
def scenario(tmp_path_factory):
    d = tmp_path_factory.mktemp("scn")
    (d / "scn.txt").write_text(hs.random_spheres(2000, 0.3, container=20.0, seed=1).to_text())
    return d / "scn.txt"


def run_scenario(scn, until, *extra, cwd, **kw):
    """``hardspheres run SCN --container 20 --until UNTIL EXTRA`` (the scenario fixture's container)."""
    return hs_cmd("run", scn, "--container", "20", "--until", until, *extra, cwd=cwd, **kw)


def start_run(scn, cwd, *extra):
    """A long ``hardspheres run`` in the background, once it is running (checkpoint locked)."""
    proc = hs_popen("run", scn, "--container", "20", "--until", "1e9", *extra, cwd=cwd)
    deadline = time.time() + 600  # a hang guard: a cold numba cache compiles first (minutes under load)
    try:
        while not (cwd / ".c.npz.lock").exists():
            assert proc.poll() is None, proc.communicate()
            assert time.time() < deadline, "the run never locked its checkpoint"
            time.sleep(0.05)
    except BaseException:
        proc.kill()
        proc.communicate()
        raise
    time.sleep(2.0)  # into the run proper
    return proc


def small_sim(n=50, seed=1):
    return hs.Simulation(hs.random_spheres(n, 0.2, container=8.0, seed=seed), hs.SphericalContainer(8.0))


# ---- 1. concurrent writers ----------------------------------------------------------
def test_second_run_on_one_checkpoint_is_refused_and_sigterm_saves(scenario, tmp_path):
    first = start_run(scenario, tmp_path, "--checkpoint", "c.npz")
    try:
        second = run_scenario(scenario, "1e9", "--checkpoint", "c.npz", cwd=tmp_path, timeout=60)
        assert second.returncode == 1
        one_line(second.stderr, "c.npz", "another writer", f"process {first.pid}")
    finally:
        first.send_signal(signal.SIGTERM)  # 4. SIGTERM: checkpoint written, 128 + 15
        out, err = first.communicate(timeout=60)
    assert first.returncode == 143, err
    assert "SIGTERM" in err and "resume with --resume c.npz" in err
    assert hs.Simulation.load(tmp_path / "c.npz").counters["collisions"] > 0
    assert sorted(os.listdir(tmp_path)) == ["c.npz"]  # no .tmp, no lock left behind


def test_two_writers_of_one_trajectory(tmp_path):
    path = tmp_path / "same.gsd"
    with GSDWriter(path, every=0.5) as first:
        assert not path.exists()  # a writer opens its file when attached
        first.attach(small_sim())
        with pytest.raises(FileInUseError, match="same.gsd"):
            GSDWriter(path, every=0.5).attach(small_sim())
        with pytest.raises(FileInUseError):
            XYZWriter(path, every=0.5).attach(small_sim())
        with pytest.raises(FileInUseError):
            small_sim().save(path)
    with GSDWriter(path, every=0.5) as again:  # released on close
        again.attach(small_sim())


def test_lock_survives_the_previous_holder_removing_the_file(tmp_path):
    target = tmp_path / "x.npz"
    a = PathLock(target)
    a.release()
    b = PathLock(target)  # a new lock file, held
    with pytest.raises(FileInUseError):
        PathLock(target)
    b.release()
    assert os.listdir(tmp_path) == []


# ---- 2. short writes ------------------------------------------------------------------
def test_generate_to_a_full_disk(tmp_path):
    with open("/dev/full", "w") as full:
        r = hs_cmd(
            "generate", "--n", "2000", "--container", "20", "--packing", "0.3", cwd=tmp_path, stdout=full
        )
    assert r.returncode == 1
    one_line(r.stderr, "hardspheres", "/dev/full", "No space left on device")


def test_spheres_to_a_full_disk(tmp_path):
    with open("/dev/full", "w") as full:
        with open(ROOT / "examples" / "three.txt") as fh:
            r = spheres_cmd("120", "105", stdin=fh, stdout=full)
    assert r.returncode == 1
    one_line(r.stderr, "spheres:", "/dev/full", "No space left on device")


@pytest.mark.parametrize("unbuffered", ["1", ""])
def test_generate_to_a_disk_that_fills_up(small_disk, tmp_path, unbuffered):
    # PYTHONUNBUFFERED: Python's text layer ignores a short write (the cut the issue saw)
    with open(small_disk / "scn.txt", "w") as fh:
        r = hs_cmd(
            "generate",
            "--n",
            "2000",
            "--container",
            "20",
            "--packing",
            "0.3",
            cwd=tmp_path,
            stdout=fh,
            env={"PYTHONUNBUFFERED": unbuffered},
        )
    assert r.returncode == 1
    one_line(r.stderr, str(small_disk / "scn.txt"), "No space left on device")


# ---- 3. atomic outputs ------------------------------------------------------------------
def test_a_failed_write_keeps_the_old_file_and_leaves_nothing(tmp_path):
    target = tmp_path / "v.html"
    target.write_text("good\n")
    with pytest.raises(OSError) as info:
        with atomic_write(target, "w") as fh:
            fh.write("half")
            raise OSError(errno.ENOSPC, "No space left on device")
    assert info.value.filename == str(target)  # the message names the file
    assert target.read_text() == "good\n"
    assert os.listdir(tmp_path) == ["v.html"]


def test_fifos_are_written_in_place(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # so that opening to write does not block
    try:
        with atomic_write(fifo, "w") as fh:  # never renamed over, never locked
            fh.write("x")
        assert os.read(reader, 16) == b"x"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert os.listdir(tmp_path) == ["pipe"]


@pytest.mark.skipif(
    not stat.S_ISCHR(os.stat("/dev/null").st_mode),
    reason="this machine's /dev/null is not a character device (some sandboxes make it a file)",
)
def test_devices_are_written_in_place():
    with atomic_write("/dev/null", "w") as fh:  # never renamed over, never locked
        fh.write("x")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    assert not os.path.exists("/dev/.null.lock")


class FailingAppend:
    """A GSD file that fills up after ``k`` frames."""

    def __init__(self, real, k):
        self.real, self.k = real, k

    def append(self, frame):
        if self.k == 0:
            raise OSError(errno.ENOSPC, "No space left on device")
        self.k -= 1
        self.real.append(frame)

    def __getattr__(self, name):
        return getattr(self.real, name)


def test_a_gsd_cut_short_warns(tmp_path):
    path = tmp_path / "cut.gsd"
    sim = small_sim()
    w = GSDWriter(path, every=0.1)
    w.attach(sim)  # opens the file and writes the first frame
    w._file = FailingAppend(w._file, 4)
    sim.writers.append(w)
    with pytest.raises(OSError) as info:
        sim.run(until=10.0)
    assert str(path) in str(info.value)
    w.close()
    with pytest.warns(TruncatedTrajectory, match="cut short"):
        frames = read_trajectory(path)
    assert len(frames.times) == 5
    # a complete file reads back without a warning
    sim2 = small_sim()
    with GSDWriter(tmp_path / "whole.gsd", every=0.1) as w2:
        sim2.writers.append(w2)
        sim2.run(until=10.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert read_trajectory(tmp_path / "whole.gsd").times[-1] == pytest.approx(10.0)


def test_an_interrupted_xyz_warns(tmp_path):
    path = tmp_path / "cut.xyz"
    sim = small_sim()
    with XYZWriter(path, every=0.1) as w:
        sim.writers.append(w)
        for k, _ in enumerate(sim.iter_events(until=10.0)):
            if k == 100:
                break
    with pytest.warns(TruncatedTrajectory):
        read_trajectory(path)


def can_mount():
    return os.geteuid() == 0 and subprocess.run(["mount", "--version"], capture_output=True).returncode == 0


@pytest.fixture
def small_disk(tmp_path):
    """A 256 kB tmpfs (root only), unmounted afterwards."""
    d = tmp_path / "disk"
    d.mkdir()
    if (
        not can_mount()
        or subprocess.run(
            ["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(d)], capture_output=True
        ).returncode
    ):
        pytest.skip("cannot mount a tmpfs here")
    yield d
    subprocess.run(["umount", str(d)], check=False)


def test_full_disk_view_keeps_the_old_page(small_disk, scenario, tmp_path):
    (small_disk / "v.html").write_text("good\n")
    r = hs_cmd(
        "view",
        scenario,
        "--container",
        "20",
        "--until",
        "0.2",
        "-o",
        small_disk / "v.html",
        "--overwrite",
        cwd=tmp_path,
    )
    assert r.returncode == 1
    one_line(r.stderr, str(small_disk / "v.html"), "No space left on device")
    assert (small_disk / "v.html").read_text() == "good\n"
    assert os.listdir(small_disk) == ["v.html"]


def test_full_trajectory_disk_still_checkpoints(small_disk, tmp_path):
    # 200 spheres: some 25 frames fit, over several of the run's pieces
    (tmp_path / "s.txt").write_text(hs.random_spheres(200, 0.3, container=9.0).to_text())
    r = hs_cmd(
        "run",
        "s.txt",
        "--container",
        "9",
        "--until",
        "2",
        "--every",
        "0.01",
        "--trajectory",
        small_disk / "t.gsd",
        "--checkpoint",
        tmp_path / "c.npz",
        cwd=tmp_path,
    )
    assert r.returncode == 1
    # the run warned at its start that the file would not fit, then failed as told
    assert "will grow to about" in r.stderr and "is free there" in r.stderr
    one_line(r.stderr, str(small_disk / "t.gsd"), "No space left on device", "--resume")
    sim = hs.Simulation.load(tmp_path / "c.npz")
    assert 0 < sim.time < 2
    with pytest.warns(TruncatedTrajectory):
        read_trajectory(small_disk / "t.gsd")
    r = hs_cmd("plot", "conservation", small_disk / "t.gsd", "-o", tmp_path / "c.png", cwd=tmp_path)
    assert r.returncode == 0
    one_line(r.stderr, "warning", "t.gsd", "cut short", warnings_too=False)


# ---- 4. signals and late checks ----------------------------------------------------------
def test_two_ctrl_c_still_save(scenario, tmp_path):
    proc = start_run(scenario, tmp_path, "--checkpoint", "c.npz")
    proc.send_signal(signal.SIGINT)
    time.sleep(0.4)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    hs.Simulation.load(tmp_path / "c.npz")


@pytest.mark.parametrize("where", ["/nonexistent/c.npz", "folder"])
def test_checkpoint_path_checked_before_the_run(scenario, tmp_path, where):
    (tmp_path / "folder").mkdir()
    # --until 1e9: only a check before the run returns in time
    r = run_scenario(scenario, "1e9", "--checkpoint", where, cwd=tmp_path, timeout=60)
    assert r.returncode == 1 and r.stdout == ""
    one_line(r.stderr, where)
    assert os.listdir(tmp_path / "folder") == []
    assert sorted(os.listdir(tmp_path)) == ["folder"]


# ---- 5. resuming keeps the earlier trajectory -------------------------------------------
@pytest.mark.parametrize("ext", [".gsd", ".xyz"])
def test_resume_continues_the_trajectory(scenario, tmp_path, ext):
    traj = f"seg{ext}"
    r = run_scenario(scenario, "1", "--trajectory", traj, "--checkpoint", "seg.npz", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    first = read_trajectory(tmp_path / traj)
    r = hs_cmd(
        "run",
        "--resume",
        "seg.npz",
        "--until",
        "2",
        "--trajectory",
        traj,
        "--checkpoint",
        "seg.npz",
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    both = read_trajectory(tmp_path / traj)
    n1 = len(first.times)
    assert np.array_equal(both.times[:n1], first.times)
    assert np.array_equal(both.positions[:n1], first.positions)
    assert np.all(np.diff(both.times) > 0) and both.times[-1] == 2.0
    # the frames after the seam are the resumed run's: the same as one run to 2
    r = run_scenario(scenario, "2", "--every", "0.01", "--trajectory", f"whole{ext}", cwd=tmp_path)
    whole = read_trajectory(tmp_path / f"whole{ext}")
    assert np.allclose(whole.positions[-1], both.positions[-1], rtol=0, atol=1e-9)


def test_trajectory_not_clobbered(scenario, tmp_path):
    run_scenario(scenario, "0.5", "--trajectory", "a.gsd", "--checkpoint", "a.npz", cwd=tmp_path)
    before = (tmp_path / "a.gsd").read_bytes()
    r = run_scenario(scenario, "0.5", "--trajectory", "a.gsd", cwd=tmp_path)
    assert r.returncode == 1
    one_line(r.stderr, "a.gsd", "--overwrite")
    # a checkpoint of another run (here: later) does not continue it
    run_scenario(scenario, "0.7", "--checkpoint", "b.npz", cwd=tmp_path)
    r = hs_cmd("run", "--resume", "b.npz", "--until", "1", "--trajectory", "a.gsd", cwd=tmp_path)
    assert r.returncode == 1
    one_line(r.stderr, "a.gsd", "does not end where", "--overwrite")
    assert (tmp_path / "a.gsd").read_bytes() == before
    r = hs_cmd(
        "run", "--resume", "b.npz", "--until", "1", "--trajectory", "a.gsd", "--overwrite", cwd=tmp_path
    )
    assert r.returncode == 0, r.stderr
    assert read_trajectory(tmp_path / "a.gsd").times[0] == pytest.approx(0.7)


# ---- 6. damaged checkpoints -----------------------------------------------------------------
DAMAGE = r"""
import json, sys, numpy as np, hardspheres as hs
from hardspheres.core import _core as core
good = sys.argv[1]
with np.load(good) as z:
    base = {k: z[k] for k in z.files}
def variant(**changes):
    d = {k: v.copy() for k, v in base.items()}
    for k, f in changes.items():
        f(d)
    return d
def heap(d): d["heap"][3] = 10 ** 9
def link(d): d["cell_next"][d["cell_next"] >= 0][:1] = 0; d["cell_next"][5] = -(10 ** 9)
def head(d): d["cell_head"][d["cell_head"] >= 0] = len(d["masses"])
def cells(d): d["counts"][core.C_CELLS] = 10 ** 6
def partner(d):
    k = d["book"]; i = int(np.nonzero(k[:, core.EVENT_KIND] == core.COLLISION)[0][0])
    k[i, core.PARTNER] = 10 ** 9
def code(d): d["book"][0, core.CROSS_FACE] = 77
def nan_pos(d): d["spheres"][7, 0] = np.nan
def neg_mass(d): d["masses"][2] = -1.0
def order(d): d["heap_t"][0] = 1e300
def dtype(d): d["heap"] = d["heap"].astype(np.float64)
def drop(d): del d["book"]
def version(d): d["version"] = np.array(99)
def foreign(d):
    d.clear(); d["x"] = np.arange(3)
cases = {name: f for name, f in globals().items() if callable(f) and name not in
         ("variant", "json") and f.__module__ == "__main__"}
out = {}
for name, f in cases.items():
    path = f"bad_{name}.npz"
    np.savez(path, **variant(x=f))
    try:
        hs.Simulation.load(path).run(until=1e9, events=10000)
        out[name] = "loaded"
    except hs.CheckpointError as e:
        out[name] = "refused: " + str(e)
print(json.dumps(out))
"""


def test_damaged_checkpoints_are_refused(tmp_path):
    sim = small_sim(200)
    sim.run(collisions=2000)
    sim.save(tmp_path / "good.npz")
    # a subprocess: the old code crashed the interpreter on some of these
    r = subprocess.run(
        [sys.executable, "-c", DAMAGE, "good.npz"],
        cwd=tmp_path,
        env=ENV,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    results = json.loads(r.stdout)
    assert len(results) == 13
    for name, result in results.items():
        assert result.startswith("refused: "), (name, result)
        assert "\n" not in result and "bad_" in result


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04garbage", b"not a checkpoint\n", "truncate"])
def test_unreadable_checkpoints_one_line(tmp_path, content):
    sim = small_sim()
    sim.save(tmp_path / "good.npz")
    data = (tmp_path / "good.npz").read_bytes()
    bad = tmp_path / "bad.npz"
    bad.write_bytes(data[: len(data) // 2] if content == "truncate" else content)
    with pytest.raises(CheckpointError, match="bad.npz"):
        hs.Simulation.load(bad)
    r = hs_cmd("run", "--resume", bad, "--until", "5", cwd=tmp_path, timeout=60)
    assert r.returncode == 1
    one_line(r.stderr, "bad.npz")


def test_checkpoint_has_format_and_version(tmp_path):
    small_sim().save(tmp_path / "c.npz")
    with np.load(tmp_path / "c.npz") as z:
        assert str(z["format"]) == "hardspheres-checkpoint" and int(z["version"]) == checkpoint.VERSION


# ---- 11. library input -------------------------------------------------------------------
GOOD = dict(
    masses=[1.0, 1.0], radii=[1.0, 1.0], positions=[[-5, 0, 0], [5, 0, 0]], velocities=[[1, 0, 0], [-1, 0, 0]]
)


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(positions=[[np.nan, 0, 0], [5, 0, 0]]), ["position", "finite"]),
        (dict(velocities=[[np.inf, 0, 0], [-1, 0, 0]]), ["velocity", "finite"]),
        (dict(masses=[1.0, np.nan]), ["mass", "> 0"]),
        (dict(masses=[1.0, -1.0]), ["mass", "> 0"]),
        (dict(masses=[1.0, 0.0]), ["mass", "> 0"]),
        (dict(radii=[1.0, -1.0]), ["radius", ">= 0"]),
        (dict(radii=[1.0, np.nan]), ["radius"]),
        (dict(names=["a", "a"]), ["'a'", "already"]),
        (dict(window=-1.0), ["window", ">= 0"]),
        (dict(window=np.nan), ["window"]),
        (dict(velocities=[[1, 0, 0]]), ["velocities", "shape"]),
    ],
)
def test_from_arrays_refuses(change, words):
    args = {**GOOD, **change}
    with pytest.raises(ValueError) as info:
        hs.Simulation.from_arrays(container=hs.SphericalContainer(100.0), **args)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


@pytest.mark.parametrize(
    "call",
    [
        lambda s: s.run(until=float("nan")),
        lambda s: s.run(until=-1.0),
        lambda s: s.run(collisions=-5),
        lambda s: s.run(events=-1),
        lambda s: s.state(float("nan")),
        lambda s: list(s.iter_events(until=float("inf"), collisions=float("nan"))),
    ],
)
def test_run_and_state_refuse(call):
    sim = hs.Simulation.from_arrays(container=hs.SphericalContainer(100.0), **GOOD)
    sim.run(until=1.0)
    with pytest.raises(ValueError):
        call(sim)
    assert sim.time == 1.0


def test_random_spheres_refuses_negative_temperature():
    with pytest.raises(ValueError, match="kT"):
        hs.random_spheres(10, 0.1, container=10.0, kT=-1.0)


def test_closed_writer(tmp_path):
    sim = small_sim()
    w = GSDWriter(tmp_path / "a.gsd", every=0.5)
    w.close()
    sim.writers.append(w)
    with pytest.raises(ValueError, match="closed"):
        sim.run(until=1.0)


# ---- 12. messages ---------------------------------------------------------------------------
def test_long_tokens_and_control_bytes_are_not_echoed(tmp_path):
    big = b"1" * 10_000_000
    r = spheres_cmd("10", "1", input=b"1 1 0 0 0 " + big + b" 0 0 a\n", text=False)
    assert r.returncode == 1 and len(r.stderr) < 300, r.stderr[:300]
    r = spheres_cmd("10", "1", input=b"1 1 0 0 0 0 0 0 a\x1b[2J\n1 1 5 0 0 0 0 0 a\x1b[2J\n", text=False)
    assert r.returncode == 1 and b"\x1b" not in r.stderr and b"\\x1b" in r.stderr
    r = spheres_cmd("1" * 100_000, "1", text=False)
    assert r.returncode == 1 and len(r.stderr) < 400
