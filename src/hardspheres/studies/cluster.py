"""The Dask clients a sweep runs on: a scheduler at an address, or a new LocalCluster."""

from __future__ import annotations

import os
import subprocess
import sys
from typing import TYPE_CHECKING

from ..errors import StudyError

if TYPE_CHECKING:
    from distributed import Client


def connect(address: str, timeout: float = 10.0) -> Client:
    """A :class:`distributed.Client` of the scheduler at ``address``.

    Raises:
        StudyError: the scheduler cannot be reached within ``timeout``
            seconds (the message names the address).
    """
    from ..extras import need

    client = need("distributed", "a study on a Dask scheduler").Client
    try:
        return client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as e:
        reason = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise StudyError(
            f"cannot reach the Dask scheduler at {address} (within {timeout:g} s): {reason}"
        ) from None


def local_client(workers: int | None = None) -> Client:
    """A :class:`distributed.Client` of a new LocalCluster: one single-threaded
    worker process per core (or ``workers``), its dashboard on a free port."""
    import logging
    import signal
    import threading

    from distributed import Client, LocalCluster

    # Ctrl-C in a terminal signals the whole process group, the workers too.
    # The workers are started with Ctrl-C ignored (the disposition is
    # inherited): only this process stops, cancels the tasks and closes the
    # cluster, without a traceback from every worker.  A Ctrl-C during the
    # start would be lost with it (the sweep ran on): a sentinel process in
    # the group, which Ctrl-C ends, tells it came (issue 29)
    guard = os.name == "posix" and threading.current_thread() is threading.main_thread()
    sentinel = _ctrl_c_sentinel() if guard else None
    cluster = None
    try:
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if guard else None
        try:
            cluster = LocalCluster(
                n_workers=workers or os.cpu_count() or 1,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
                silence_logs=logging.CRITICAL,  # a failing task is one line (its reason), not worker records
            )
        finally:
            if guard:
                signal.signal(signal.SIGINT, old)
        if sentinel is not None and sentinel.poll() is not None:
            raise KeyboardInterrupt  # Ctrl-C came while the cluster started
        return Client(cluster)
    except BaseException:
        if cluster is not None:
            cluster.close(timeout=10)
        raise
    finally:
        if sentinel is not None and sentinel.poll() is None:
            sentinel.kill()
            sentinel.wait()


def _ctrl_c_sentinel() -> subprocess.Popen[bytes]:
    """A process in this one's group that only Ctrl-C (SIGINT) ends: it tells
    whether Ctrl-C came while this process ignored it."""
    code = "import signal, time; signal.signal(signal.SIGINT, signal.SIG_DFL); time.sleep(86400)"
    return subprocess.Popen(
        [sys.executable, "-c", code],
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
