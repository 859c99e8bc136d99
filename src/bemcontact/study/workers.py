"""How the local cluster's worker processes start: forks of a
multiprocessing fork server (:func:`start_fork_server`) that has the
environment Dask gives the workers it spawns (one BLAS thread, ...), which
this process does not keep (:func:`environ_kept`): a sweep run from Python
or in a test session leaves ``OMP_NUM_THREADS`` and the others as they were
(left behind, ``OMP_NUM_THREADS=1`` made every process started from this one
afterwards, and any library it loads afterwards, run on one thread).
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator, Mapping

#: How the local cluster starts its worker processes: forks of a server that
#: imports :data:`PRELOAD` once, while the sweep is planned (Dask's default,
#: spawn, starts a fresh interpreter per worker that imports everything again
#: after the cluster has started).
START_METHOD = "forkserver"
#: What the workers import before their first point: Dask, a point's task and
#: what a point's output imports (meshio; matplotlib for frame_tractions.png
#: and sweep.png).  A module that cannot be imported is left out.
PRELOAD = ("distributed", "bemcontact.study.sweep", "meshio", "matplotlib.pyplot")


def worker_environ() -> dict[str, str]:
    """The environment Dask's nanny sets before it spawns a worker
    (``distributed.nanny.pre-spawn-environ``: one BLAS and OpenMP thread, ...;
    a variable already set keeps its value) and its PYTHONHASHSEED."""
    import dask
    import distributed  # noqa: F401  (its configuration)

    env = {k: os.environ.get(k, str(v)) for k, v in
           dask.config.get("distributed.nanny.pre-spawn-environ").items() if v is not None}
    if env.get("PYTHONHASHSEED") in (None, "0"):  # as distributed.nanny.Nanny
        env["PYTHONHASHSEED"] = "6640"
    return env


@contextlib.contextmanager
def environ_kept(names) -> Iterator[None]:
    """The environment variables ``names`` put back on leaving as they were
    on entering (set to their value, or removed): Dask's nanny sets its
    pre-spawn environment in this process, before each worker it starts,
    and leaves it."""
    saved = {k: os.environ.get(k) for k in names}
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


@contextlib.contextmanager
def environ_set(env: Mapping[str, str]) -> Iterator[None]:
    """``env`` in this process's environment (what a process started
    meanwhile inherits), the variables as they were on leaving."""
    with environ_kept(env):
        os.environ.update(env)
        yield


def start_fork_server() -> str:
    """Start the local cluster's fork server now, in the background: it
    imports :data:`PRELOAD` while this process plans the sweep, and the
    workers are forks of it (a server of one thread, unlike this process
    once Dask runs).  It gets the environment Dask gives spawned workers
    (:func:`worker_environ`; set only while it starts: this process keeps
    its own) and ignores SIGINT, as the workers forked from it: a Ctrl-C
    stops this process only, which closes the cluster (spawned workers each
    printed a KeyboardInterrupt traceback).  It ends when this process does.
    Returns the start method: ``spawn`` where there is no fork server
    (Windows)."""
    import multiprocessing
    import multiprocessing.forkserver

    env = worker_environ()
    try:
        ctx = multiprocessing.get_context(START_METHOD)
    except ValueError:
        return "spawn"
    ctx.set_forkserver_preload(list(PRELOAD))
    # an ignored signal stays ignored in a new interpreter, which then installs
    # no KeyboardInterrupt handler, and in the forks of the server
    main = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        with environ_set(env):  # what the Nanny does before spawning a worker
            multiprocessing.forkserver.ensure_running()
    finally:
        if old is not None:
            signal.signal(signal.SIGINT, old)
    return START_METHOD


def stop_fork_server() -> None:
    """End the fork server of a sweep that failed its checks at once: it
    would import for a second more, holding the terminal's streams open
    (a script reading them waited for it).  Uses multiprocessing's own
    (private) stop; without it the server ends by itself."""
    import multiprocessing.forkserver

    server = getattr(multiprocessing.forkserver, "_forkserver", None)
    pid = getattr(server, "_forkserver_pid", None)
    stop = getattr(server, "_stop", None)
    if pid is None or stop is None:
        return
    with contextlib.suppress(OSError):
        os.kill(pid, signal.SIGTERM)
    with contextlib.suppress(Exception):
        stop()
