"""The compiled cores' cache: keyed to the sources' bytes, so it is found wherever the files are.

What makes a cache compiled while the package is built (``setup.py``) load
after ``pip install`` puts the files elsewhere, with other modification
times: :mod:`hardspheres._jitcache`.  Checked on a one-function module of
the same form as the cores, in fresh processes.
"""

import json
import os
import shutil
import subprocess
import sys
import textwrap

import pytest

from hardspheres._jitcache import cache_dir, source_digest

MODULE = textwrap.dedent(
    """
    from hardspheres._jitcache import cached_compiler, source_digest

    DIGEST = source_digest(__file__)
    _jit = cached_compiler(__file__, DIGEST)


    @_jit(nogil=True)
    def twice(x):
        return 2.0 * x
    """
)

CALL = textwrap.dedent(
    """
    import json, sys
    sys.path.insert(0, sys.argv[1])
    import cached_module as m
    assert m.twice(1.5) == 3.0
    s = m.twice.stats
    print(json.dumps({"hits": sum(s.cache_hits.values()), "misses": sum(s.cache_misses.values())}))
    """
)


def _call(folder, **env):
    """Import ``cached_module`` from ``folder`` in a fresh process and call it once: its cache hits and misses."""
    base = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    out = subprocess.run(
        [sys.executable, "-c", CALL, str(folder)],
        env={**base, **env},
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


@pytest.fixture
def built(tmp_path):
    """A module compiled once into its own ``__pycache__/numba-DIGEST`` (as the build step does)."""
    a = tmp_path / "a"
    a.mkdir()
    (a / "cached_module.py").write_text(MODULE)
    assert _call(a) == {"hits": 0, "misses": 1}
    return a


def test_the_cache_is_found_after_the_files_move_and_their_times_change(built, tmp_path):
    b = tmp_path / "b"
    shutil.copytree(built, b)
    for root, _, files in os.walk(b):
        for name in files:
            os.utime(os.path.join(root, name), (1e9, 1e9))  # another install's modification times
    shutil.rmtree(built)
    assert _call(b) == {"hits": 1, "misses": 0}


def test_changed_source_bytes_compile_afresh(built):
    path = built / "cached_module.py"
    path.write_text(MODULE.replace("2.0 * x", "x + x"))  # same answers, other bytes
    assert _call(built) == {"hits": 0, "misses": 1}
    assert len(os.listdir(built / "__pycache__")) >= 2  # one folder per digest, side by side


def test_numba_cache_dir_gets_a_folder_per_core_and_digest(tmp_path):
    a = tmp_path / "a"
    a.mkdir()
    (a / "cached_module.py").write_text(MODULE)
    user = tmp_path / "user-cache"
    assert _call(a, NUMBA_CACHE_DIR=str(user)) == {"hits": 0, "misses": 1}
    assert _call(a, NUMBA_CACHE_DIR=str(user)) == {"hits": 1, "misses": 0}
    digest = source_digest(str(a / "cached_module.py"))
    assert os.listdir(user) == [f"a-{digest}"]
    assert not (a / "__pycache__").exists() or not any(
        n.startswith("numba-") for n in os.listdir(a / "__pycache__")
    )


def test_cache_dir_names_the_digest(monkeypatch, tmp_path):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    path = str(tmp_path / "core" / "_core.py")
    assert cache_dir(path, "0123456789abcdef") == str(
        tmp_path / "core" / "__pycache__" / "numba-0123456789abcdef"
    )
