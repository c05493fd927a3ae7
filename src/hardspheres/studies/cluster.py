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
    # the group, which Ctrl-C ends, tells it came.  It is asked after the
    # start, and answers only if no Ctrl-C is pending for it: under load it
    # may not yet have run since the Ctrl-C, and "is it still running?"
    # (poll) then lost the Ctrl-C
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
        if sentinel is not None and not _sentinel_answers(sentinel):
            raise KeyboardInterrupt  # Ctrl-C came while the cluster started
        return Client(cluster)
    except BaseException:
        if cluster is not None:
            cluster.close(timeout=10)
        raise
    finally:
        if sentinel is not None:
            if sentinel.poll() is None:
                sentinel.kill()
            sentinel.wait()
            for pipe in (sentinel.stdin, sentinel.stdout):
                try:
                    if pipe is not None:
                        pipe.close()
                except OSError:  # its stdin: the question it did not read (it is gone)
                    pass


def _ctrl_c_sentinel() -> subprocess.Popen[bytes]:
    """A process in this one's group that only Ctrl-C (SIGINT) ends: it tells
    whether Ctrl-C came while this process ignored it (:func:`_sentinel_answers`).

    It answers each line on its stdin with one on its stdout.  Before it
    can answer, a SIGINT sent to the group (pending for it, with the default
    action or Python's KeyboardInterrupt) ends it."""
    code = (
        "import signal, sys; signal.signal(signal.SIGINT, signal.SIG_DFL)\n"
        "for line in sys.stdin.buffer:\n"
        "    sys.stdout.buffer.write(b'alive\\n'); sys.stdout.buffer.flush()"
    )
    return subprocess.Popen(
        [sys.executable, "-S", "-c", code],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
    )


def _sentinel_answers(sentinel: subprocess.Popen[bytes]) -> bool:
    """Whether the sentinel answers now, i.e. no Ctrl-C was sent to the group before this call.

    A signal sent before the question is pending for the sentinel when it
    reads the question, and ends it before it returns to answer: whatever
    the load, the answer cannot come and an empty read (its end) does.
    """
    assert sentinel.stdin is not None and sentinel.stdout is not None
    try:
        sentinel.stdin.write(b"?\n")
        sentinel.stdin.flush()
    except BrokenPipeError:
        return False
    return sentinel.stdout.readline() == b"alive\n"
