"""``bemcontact sweep``: a parameter study on Dask distributed.

Every point (:mod:`.points`) is a task on a Dask cluster: a
``LocalCluster`` on this machine by default (one single-threaded worker
process per core, forks of a server that imports what a point needs while
the sweep is planned), or an existing one (``scheduler``).  Points whose bodies
are the same (equal :func:`~.points.group_key`: only friction, penalty,
load values or history or Newton options differ) are sent to the same
worker, which condenses the bodies once (:meth:`ContactProblem.condense`,
through the on-disk :class:`~.cache.BodyCache`) and re-solves for each
point; with fewer groups than workers a group is split over the workers.

The output directory ``OUT``::

    .bemcontact-sweep.json   the sweep's marker: keys, point count, spec hash
    table.csv                one row per point (table.parquet with pyarrow)
    sweep.png                key outputs against each swept parameter (matplotlib)
    points/p0001.toml        each point's problem file (bemcontact run re-runs it)
    points/p0001/            each point's results, as bemcontact run writes them
    records/p0001.json       each finished point's row (the resume state)
    cache/                   condensed bodies (study/cache.py)

A point that fails (no convergence, an error of its own) is a row with its
status and error; the others go on.  A point is finished when its record
holds status ``ok`` for the same point file: a sweep run again into the same
directory (interrupted, or with failed points) computes only the others.
The cluster re-runs the task of a worker that died (Dask's retries and its
scheduler's allowed failures).  The workers must see ``OUT`` at the same
path (the local cluster does; a remote one needs a shared file system).
"""

from __future__ import annotations

import collections
import contextlib
import hashlib
import importlib.util
import json
import math
import os
import pathlib
import secrets
import signal
import threading
import time
import tomllib
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from ..contact.reuse import FRAME_FIELDS
from ..errors import BemcontactError, ConfigError, ConvergenceError, OptionalDependencyWarning
from ..inputs import MAX_PROBLEM_BYTES, check_regular_file
from ..linalg.threads import available_cores
from ..output import write_summary
from ..problemfile import load_problem
from ..problemfile.checks import Checker, a_type, one_line
from ..problemfile.method import method_of, on_grid
from ..settings import Key, check_settings, setting
from .cache import BodyCache
from .points import Point, check_points, parse_values, points_of
from .table import grid_outputs, outputs, write_figure, write_table
from .workers import (START_METHOD, environ_kept, start_fork_server, stop_fork_server,
                      worker_environ)

#: The install command named when Dask is missing.
INSTALL = 'pip install "bemcontact[sweep]"'
MARKER = ".bemcontact-sweep.json"
#: Condensations a worker process keeps in memory (least recently used dropped).
KEEP = 2


@dataclass(frozen=True)
class SweepOptions:
    """How a sweep runs (the ``sweep`` command's options)."""

    scheduler: str = setting(Key(
        "scheduler", "string", "address of a running Dask scheduler (tcp://host:8786); empty: "
        "a local cluster on this machine", default=""))
    workers: int | None = setting(Key(
        "workers", "integer", "worker processes of the local cluster", default=None, lo=1,
        hi=1024, default_text="the usable cores"))
    threads: int = setting(Key(
        "threads", "integer", "threads of each point's solve (unless the problem file sets "
        "solver.threads)", default=1, lo=1, hi=1024))
    retries: int = setting(Key(
        "retries", "integer", "times a point's task is re-run after its worker died",
        default=2, lo=0, hi=100))
    timeout: float = setting(Key(
        "timeout", "number", "seconds to wait for the scheduler", default=10.0, lo=0,
        lo_open=True, hi=3600))
    cache: str = setting(Key(
        "cache", "string", "directory of the condensed bodies", default="",
        default_text="OUT/cache"))

    def __post_init__(self) -> None:
        check_settings(self)


@dataclass
class SweepResult:
    """``rows`` one per point (the table's), ``keys`` the swept keys,
    ``files`` the table and figure written, ``computed`` the points solved
    by this call, ``resumed`` those finished before it, ``dashboard`` the
    Dask dashboard's address."""

    rows: list[dict]
    keys: list[str]
    files: list[pathlib.Path] = field(default_factory=list)
    computed: int = 0
    resumed: int = 0
    dashboard: str = ""

    @property
    def failed(self) -> int:
        return sum(r.get("status") != "ok" for r in self.rows)


# ------------------------------------------------------------------ plan


@dataclass
class _Plan:
    path: pathlib.Path
    out: pathlib.Path
    keys: list[str]
    points: list[Point]
    spec: str
    resume: bool


def _require_dask() -> None:
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise ConfigError("bemcontact sweep runs on Dask distributed, which is not "
                          f"installed; {INSTALL}") from None


def _read(path: pathlib.Path) -> dict:
    load_problem(path)  # every check of a run, with its messages
    check_regular_file(path, "problem file", MAX_PROBLEM_BYTES)
    data = path.read_bytes()
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    return tomllib.loads(data.decode("utf-8"))


def _vary(chk: Checker, texts: Sequence[str]) -> list[tuple[str, list]]:
    out = []
    for t in texts:
        key, eq, values = str(t).partition("=")
        if not eq or not key.strip() or not values.strip():
            chk.fail("--vary", "must be KEY=VALUE,VALUE,...", t,
                     "e.g. --vary contact.friction_coefficient=0.1,0.2,0.3")
        out.append((key.strip(), parse_values(values)))
    return out


def _table_spec(chk: Checker, table: Any) -> tuple[list[tuple[str, list]], list[dict]]:
    if not isinstance(table, dict):
        chk.fail("sweep", f"must be a table, not {a_type(table)}", table)
    for k in table:
        if k not in ("vary", "points"):
            chk.fail(f"sweep.{k}", "unknown key", k, "allowed keys: vary, points")
    vary, listed = table.get("vary", {}), table.get("points", [])
    if not isinstance(vary, dict):
        chk.fail("sweep.vary", f"must be a table of key = [values], not {a_type(vary)}", vary)
    for k, v in vary.items():
        if not isinstance(v, list) or not v:
            chk.fail(f"sweep.vary.{k}", "must be a non-empty array of values", v)
    if not isinstance(listed, list) or not all(isinstance(p, dict) for p in listed):
        chk.fail("sweep.points", "must be an array of tables of key = value", listed)
    if vary and listed:
        chk.fail("sweep", "give vary (every combination) or points (a list), not both",
                 list(table))
    return list(vary.items()), listed


def plan_sweep(problem: str | os.PathLike, out: str | os.PathLike,
               vary: Sequence[str] | None = None) -> _Plan:
    """Check everything before anything is written: the problem file, the
    sweep (``vary``: ``KEY=VALUES`` texts; else the file's ``[sweep]``
    table), every point's problem file, and ``out`` (new, empty, or this
    same sweep's directory to resume)."""
    path = pathlib.Path(problem)
    content = _read(path)
    chk = Checker(os.fspath(path), path.parent)
    if vary:
        spec, listed = _vary(chk, vary), None
    else:
        if "sweep" not in content:
            chk.fail("sweep", "nothing to vary", None,
                     "give --vary KEY=VALUES or a [sweep] table in the problem file")
        spec, listed = _table_spec(chk, content["sweep"])
    points = points_of(chk, content, spec, listed)
    keys = list(dict.fromkeys(k for p in points for k in p.values))
    check_points(chk, path, points)
    digest = hashlib.sha256("\0".join(p.text for p in points).encode()).hexdigest()
    o = pathlib.Path(out)
    resume = False
    if o.exists() or o.is_symlink():
        if not o.is_dir():
            raise ConfigError(f"{o}: exists and is not a directory; choose another --out")
        marker = o / MARKER
        if marker.is_file():
            try:
                old = json.loads(marker.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                old = {}
            if old.get("spec") != digest:
                raise ConfigError(f"{o}: holds another sweep ({old.get('problem', '?')}, "
                                  f"{old.get('points', '?')} points); choose another --out")
            resume = True
        elif any(o.iterdir()):
            raise ConfigError(f"{o}: exists and is not a bemcontact sweep directory; choose "
                              "another --out")
    return _Plan(path, o, keys, points, digest, resume)


# ------------------------------------------------------------------ cluster


@contextlib.contextmanager
def _connect(options: SweepOptions, client=None, start_method: str = "spawn"):
    """A Dask client: the one given, one of the scheduler at
    ``options.scheduler``, or one of a new local cluster whose workers
    start by ``start_method`` (Dask's ``multiprocessing-method``)."""
    if client is not None:
        yield client
        return
    from distributed import Client

    if options.scheduler:
        try:
            c = Client(options.scheduler, timeout=f"{options.timeout}s")
        except (OSError, TimeoutError, ValueError, TypeError) as exc:
            raise ConfigError(f"cannot reach the Dask scheduler at {options.scheduler}: "
                              f"{one_line(str(exc)) or type(exc).__name__}") from None
        with c:
            yield c
        return
    import dask

    # Dask's nannies set the workers' environment in this process before each
    # worker they start (and the marker of their children's process titles),
    # and leave it: put back once the workers have started, and after the
    # cluster (a worker restarted meanwhile set it again)
    names = [*worker_environ(), "__DASK_PARENT_PID"]
    with (dask.config.set({"distributed.worker.multiprocessing-method": start_method}),
          environ_kept(names)):
        with environ_kept(names):
            cluster, c = _local_cluster(options)
        try:
            yield c
        finally:
            _close(cluster, c)


def _warm() -> None:
    """Run on each worker once it starts: the imports of a point's task."""
    from . import sweep  # noqa: F401  (the module of run_point, and what it imports)


def _local_cluster(options: SweepOptions):
    """A new local cluster (one single-threaded worker process per usable
    core, or ``options.workers``) and its client, the workers' imports done."""
    from distributed import Client, LocalCluster

    cores = available_cores()
    workers = options.workers or max(1, cores // options.threads)
    with _interrupt_held() as held:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0", silence_logs=40)
        try:
            c = Client(cluster)
        except BaseException:
            cluster.close()
            raise
    try:
        if held:
            raise KeyboardInterrupt
        c.run(_warm)
    except BaseException:
        _close(cluster, c)
        raise
    return cluster, c


@contextlib.contextmanager
def _interrupt_held():
    """A Ctrl-C while the local cluster starts is held (the list yielded
    holds it) until the start has ended: Dask's start interrupted left a
    half-started cluster that printed tracebacks at exit."""
    held: list[int] = []
    main = threading.current_thread() is threading.main_thread()
    if not main or signal.getsignal(signal.SIGINT) is None:
        yield held
        return
    old = signal.signal(signal.SIGINT, lambda signum, frame: held.append(signum))
    try:
        yield held
    finally:
        signal.signal(signal.SIGINT, old)


def _close(cluster, c) -> None:
    try:
        c.close()
    finally:
        cluster.close()


def _groups(points: list[Point], workers: list[str]) -> dict[str, str]:
    """Point name -> worker: a group's points on one worker; with fewer
    groups than workers each group split into equal runs of points."""
    groups: dict[str, list[Point]] = collections.defaultdict(list)
    for p in points:
        groups[p.group].append(p)
    n = max(1, len(workers))
    chunks = []
    per = max(1, n // max(1, len(groups)))
    for g in groups.values():
        k = min(per, len(g))
        size = math.ceil(len(g) / k)
        chunks += [g[i : i + size] for i in range(0, len(g), size)]
    chunks.sort(key=len, reverse=True)
    load = [0] * n
    out = {}
    for c in chunks:
        w = load.index(min(load))
        load[w] += len(c)
        out.update({p.name: workers[w] if workers else "" for p in c})
    return out


# ------------------------------------------------------------------ a point (on a worker)

_STORE: collections.OrderedDict = collections.OrderedDict()
_STORE_LOCK = threading.Lock()
_GROUP_LOCKS: dict[str, threading.Lock] = {}


def _condensation(group: str, pf, options, cache_dir: str):
    with _STORE_LOCK:
        lock = _GROUP_LOCKS.setdefault(group, threading.Lock())
    with lock:
        with _STORE_LOCK:
            if group in _STORE:
                _STORE.move_to_end(group)
                return _STORE[group]
        cache = BodyCache(cache_dir, [getattr(pf.pair, f) for f in FRAME_FIELDS])
        cond = pf.contact_problem().condense(options, steps=pf.steps or None,
                                             condense_body=cache.condense)
        with _STORE_LOCK:
            _STORE[group] = cond
            while len(_STORE) > KEEP:
                _STORE.popitem(last=False)
        return cond


def run_point(point_file: str, out_dir: str, group: str, cache_dir: str,
              threads: int) -> dict[str, Any]:
    """Solve one point's problem file reusing its group's condensed bodies
    and write its results into ``out_dir`` as ``bemcontact run`` does (the
    same files: ``frame_tractions.png`` too unless the file says ``figures =
    false``); returns its row (status ok / not converged / failed, error,
    outputs)."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {"status": "failed", "error": ""}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", OptionalDependencyWarning)
            pf = load_problem(point_file, check_overlap=False)
        content_threads = "threads" in pf.echo.get("solver", {})
        opt = pf.options if content_threads else replace(pf.options, threads=threads)
        # the pair's method, as `bemcontact run` follows it: a point the contact
        # grid solves needs no condensed bodies
        method = method_of(pf.pairs)
        grid = on_grid(pf.contact_problem(), pf.steps, method, opt)[0] if method != "full" \
            else None
        if grid is not None:
            pf.write(grid, out_dir)
            row.update(grid_outputs(grid), status="ok")
            row["seconds"] = time.perf_counter() - t0
            return row
        cond = _condensation(group, pf, opt, cache_dir)
        # bodies far from the origin: ContactProblem solves relative to their
        # own and returns the results at their position (contact/origin.py)
        try:
            result = pf.contact_problem().solve(opt, steps=pf.steps or None, condensed=cond)
        except ConvergenceError as exc:
            row.update(status="not converged", error=one_line(str(exc)))
            if exc.result is not None:
                r = exc.result
                row.update(outputs(r))
                write_summary(r, out_dir, pf.echo, error=str(exc))
        else:
            from ..output import write_results

            write_results(result, out_dir, pf.echo, pf.output)
            row.update(outputs(result), status="ok")
    except BemcontactError as exc:
        row["error"] = one_line(str(exc))
    except Exception as exc:  # noqa: BLE001 - a point's failure is its row, not the sweep's
        row["error"] = one_line(f"{type(exc).__name__}: {exc}")
    row["seconds"] = time.perf_counter() - t0
    return row


# ------------------------------------------------------------------ the sweep


def _write_atomic(path: pathlib.Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    try:
        tmp.write_text(text, encoding="utf-8")
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _finished(plan: _Plan, p: Point) -> dict | None:
    f = plan.out / "records" / f"{p.name}.json"
    try:
        rec = json.loads(f.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if rec.get("text_sha") != _sha(p.text) or rec.get("row", {}).get("status") != "ok":
        return None
    return rec["row"]


def run_sweep(
    problem: str | os.PathLike, out: str | os.PathLike, *, vary: Sequence[str] | None = None,
    options: SweepOptions | None = None, client=None,
    progress: Callable[[int, int, dict], None] | None = None,
    started: Callable[[int, int, str], None] | None = None,
) -> SweepResult:
    """Run the sweep of ``problem`` (``vary``: ``KEY=VALUES`` texts, else
    its ``[sweep]`` table) into ``out`` (module docstring) on ``client`` (a
    ``distributed.Client``) or as ``options`` say; ``progress(done, total,
    row)`` after each point; ``started(points, finished before, dashboard
    address)`` once connected.  Bad input raises ConfigError before anything
    is written."""
    opt = options or SweepOptions()
    if not isinstance(opt, SweepOptions):
        raise ConfigError(f"options must be SweepOptions, got {type(opt).__name__}")
    _require_dask()
    # the workers' imports run in the fork server while the sweep is planned;
    # the cluster itself starts after: bad input fails before anything is
    # written or started (a cluster started during the planning saved 0.25 s
    # but a Ctrl-C left it half-started, with warnings)
    method = start_fork_server() if client is None and not opt.scheduler else "spawn"
    try:
        plan = plan_sweep(problem, out, vary)
    except BaseException:
        if method == START_METHOD:
            stop_fork_server()
        raise
    with _connect(opt, client, method) as c:
        return _execute(plan, c, opt, progress, started)


def _execute(plan: _Plan, client, opt: SweepOptions, progress, started) -> SweepResult:
    from distributed import as_completed

    out = plan.out
    (out / "points").mkdir(parents=True, exist_ok=True)
    (out / "records").mkdir(exist_ok=True)
    _write_atomic(out / MARKER, json.dumps({
        "problem": str(plan.path), "points": len(plan.points), "keys": plan.keys,
        "spec": plan.spec}, indent=1))
    cache_dir = str(pathlib.Path(opt.cache or out / "cache").resolve())
    rows: dict[str, dict] = {}
    todo = []
    for p in plan.points:
        f = out / "points" / f"{p.name}.toml"
        if not f.is_file() or f.read_text(encoding="utf-8") != p.text:
            _write_atomic(f, p.text)
        row = _finished(plan, p) if plan.resume else None
        if row is not None:
            rows[p.name] = row
        else:
            todo.append(p)
    resumed = len(rows)
    dashboard = getattr(client, "dashboard_link", "") or ""
    if importlib.util.find_spec("bokeh") is None:  # Dask serves no dashboard without it
        dashboard = ""
    if started is not None:
        started(len(plan.points), resumed, dashboard)
    workers = sorted(client.scheduler_info().get("workers", {}))
    where = _groups(todo, workers)
    futures = {}
    for p in todo:
        f = client.submit(
            run_point, str((out / "points" / f"{p.name}.toml").resolve()),
            str((out / "points" / p.name).resolve()), p.group, cache_dir, opt.threads,
            key=f"bemcontact-{p.name}-{secrets.token_hex(4)}", pure=False,
            retries=opt.retries, workers=[where[p.name]] if where.get(p.name) else None,
            allow_other_workers=True,
        )
        futures[f] = p
    done = resumed
    try:
        for f in as_completed(list(futures)):
            p = futures[f]
            try:
                row = f.result()
            except Exception as exc:  # noqa: BLE001 - KilledWorker after the retries, ...
                row = {"status": "failed", "error": one_line(f"{type(exc).__name__}: {exc}")}
            rows[p.name] = row
            _write_atomic(out / "records" / f"{p.name}.json", json.dumps(
                {"point": p.name, "values": p.values, "text_sha": _sha(p.text), "row": row},
                indent=1))
            done += 1
            if progress is not None:
                progress(done, len(plan.points), _row(p, row))
    finally:
        for f in futures:
            f.cancel()
        table = [_row(p, rows[p.name]) for p in plan.points if p.name in rows]
        files = write_table(out, plan.keys, table) if table else []
    fig = write_figure(out, plan.keys, table)
    if fig is None and importlib.util.find_spec("matplotlib") is None:
        warnings.warn('the sweep figure was skipped: matplotlib is not installed (pip install '
                      '"bemcontact[plot]")', OptionalDependencyWarning, stacklevel=3)
    return SweepResult(table, plan.keys, files + ([fig] if fig else []), len(todo), resumed,
                       dashboard)


def _row(p: Point, row: dict) -> dict:
    return {"point": p.name, **p.values, **row, "directory": f"points/{p.name}"}


__all__ = ["INSTALL", "SweepOptions", "SweepResult", "plan_sweep", "run_point", "run_sweep"]
