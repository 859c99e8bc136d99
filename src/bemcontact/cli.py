"""The ``bemcontact`` command.  No numerics here: only the public API.

    bemcontact run PROBLEM.toml --out DIR [--threads N] [--quiet] [--progress M] [--debug]
    bemcontact check PROBLEM.toml [--debug]
    bemcontact mesh-info MESH [--debug]
    bemcontact bench one-body --nodes N [--json FILE] [--method M] [--eps E] [--leaf N]
                              [--truncation block|global] [--storage double|mixed] [--threads N]
    bemcontact bench two-cubes --divisions K [--case similar|dissimilar] [--method M] [--eps E]
                               [--json FILE]
    bemcontact sweep PROBLEM.toml --out DIR [--vary KEY=VALUES ...] [--scheduler ADDRESS]
                     [--workers N] [--threads N] [--timeout S] [--quiet] [--debug]
    bemcontact --version

Exit codes: 0 solved; 2 bad input (problem file, meshes, command line) or
results not writable, with one line ``bemcontact: error: ...`` on stderr and
nothing written; 3 the contact solve did not converge: the message with the
residual history and the contact states goes to stderr and a diagnostic
``DIR/summary.json`` (``"converged": false``) is written.  ``--debug`` shows
the traceback instead.

bemcontact's own warnings are one line each on stderr, ``bemcontact: warning:
...``, and do not change the exit code (e.g. figures skipped because
matplotlib is not installed: the other files are written, exit 0).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import pathlib
import sys
import warnings
from collections.abc import Sequence

import numpy as np

from ._version import __version__
from .contact.memory import allowed, available_text, binding_limit, machine_memory
from .errors import BemcontactError, BemcontactWarning, ConvergenceError
from .output.rundir import InterruptGuard, RunDirectory
from .output.write import write_summary
from .problemfile.reader import load_problem
from .output.report import counts, run_report
from .progress import terminal_text
from .settings import MAX_THREADS

EXIT_OK = 0
EXIT_INPUT = 2
EXIT_NOT_CONVERGED = 3
EXIT_INTERRUPTED = 130


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return n


def _threads(text: str) -> int:
    n = _positive_int(text)
    if n > MAX_THREADS:
        raise argparse.ArgumentTypeError(f"must be an integer in [1, {MAX_THREADS}], got {text!r}")
    return n


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="bemcontact",
        description="3D frictional contact between linear elastic bodies (BEM).",
    )
    p.add_argument("--version", action="version", version=f"bemcontact {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    run = sub.add_parser(
        "run", help="solve a problem file and write the results",
        description="Solve a problem file (docs/problem-file.md) and write summary.json, VTU "
        "and CSV files into DIR.",
    )
    run.add_argument("problem", metavar="PROBLEM.toml", type=pathlib.Path)
    run.add_argument("--out", metavar="DIR", required=True,
                     help="output directory: new, empty, or one bemcontact wrote (replaced as a "
                     "whole when the new results are complete)")
    run.add_argument("--force", action="store_true",
                     help="also write into a directory that holds other files: the results "
                     "replace files of the same names, nothing else is touched")
    run.add_argument("--threads", metavar="N", type=_threads,
                     help="threads for assembly, compression and LAPACK (overrides solver.threads; "
                     "default all cores, or OMP_NUM_THREADS)")
    run.add_argument("--quiet", action="store_true",
                     help="print nothing on success (warnings still go to stderr)")
    run.add_argument("--progress", choices=("auto", "live", "lines", "none"), default="auto",
                     help="progress display on stderr: live (rich) when stderr is a terminal, "
                     "lines (one per stage, increment and Newton iteration), none; default auto: "
                     "live on a terminal, none otherwise or with --quiet")
    run.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    check = sub.add_parser(
        "check", help="validate a problem file and print what would be solved",
        description="Read and validate a problem file (no solve): bodies, node counts, regions "
        "and their conditions, the contact pair and frame, load steps, estimated memory.",
    )
    check.add_argument("problem", metavar="PROBLEM.toml", type=pathlib.Path)
    check.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    info = sub.add_parser(
        "mesh-info", help="regions, element type, quality and orientation of a mesh file",
        description="Read a mesh file (any format meshio reads; gmsh physical groups become "
        "regions) and report its regions, element type, element quality, shells and whether it "
        "bounds a solid with outward normals (exit 2 if not).",
    )
    info.add_argument("mesh", metavar="MESH", type=pathlib.Path)
    info.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    bench = sub.add_parser(
        "bench", help="time a benchmark case (speed and accuracy)",
        description="Benchmark cases (docs/benchmarks.md); prints one JSON record and writes "
        "it to FILE with --json.",
    )
    bsub = bench.add_subparsers(dest="bench_case", metavar="CASE", required=True)
    one = bsub.add_parser(
        "one-body", help="a cube with about N nodes and an exact linear solution",
        description="A unit cube of quad4 elements with about N functional nodes, displacement "
        "given on three faces and traction on the others, exact solution linear.",
    )
    one.add_argument("--nodes", metavar="N", type=_positive_int, required=True)
    one.add_argument("--json", metavar="FILE", type=pathlib.Path, help="write the record here")
    one.add_argument("--method", choices=("auto", "dense", "hmatrix"), default="auto",
                     help="linear solver (default: auto, dense for small bodies)")
    one.add_argument("--eps", metavar="E", type=float, default=1e-7,
                     help="H-matrix block accuracy (default 1e-7)")
    one.add_argument("--leaf", metavar="N", type=_positive_int, default=None,
                     help="H-matrix leaf size in nodes (default: HMatrixOptions' own, 48)")
    one.add_argument("--truncation", choices=("block", "global"), default=None,
                     help="H-matrix truncation (default: HMatrixOptions' own)")
    one.add_argument("--storage", choices=("double", "mixed"), default=None,
                     help="H-matrix low-rank storage (default: HMatrixOptions' own)")
    one.add_argument("--threads", metavar="N", type=_threads,
                     help="threads (default: all cores, or OMP_NUM_THREADS)")
    one.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    two = bsub.add_parser(
        "two-cubes", help="the founding paper's two cubes, K x K elements per face",
        description="The paper's two cubes (non-matching interface meshes K and K-1), whole "
        "run timed, normal force reported.",
    )
    two.add_argument("--divisions", metavar="K", type=_positive_int, required=True)
    two.add_argument("--case", choices=("similar", "dissimilar"), default="dissimilar")
    two.add_argument("--method", choices=("auto", "dense", "hmatrix"), default="auto",
                     help="linear solver of the condensation (default: auto, dense for small "
                     "bodies)")
    two.add_argument("--eps", metavar="E", type=float, default=1e-7,
                     help="H-matrix block and H-LU accuracy (default 1e-7)")
    two.add_argument("--json", metavar="FILE", type=pathlib.Path, help="write the record here")
    two.add_argument("--threads", metavar="N", type=_threads,
                     help="threads (default: all cores, or OMP_NUM_THREADS)")
    two.add_argument("--debug", action="store_true", help="show tracebacks of errors")
    _sweep_parser(sub)
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line ``argv`` (default ``sys.argv[1:]``); returns the exit code.
    Ctrl-C ends it with one line and exit code 130 (the output directory as it
    was: :mod:`bemcontact.output.rundir`); a closed pipe (``| head``) ends it
    quietly."""
    guard = InterruptGuard()  # Ctrl-C inside compiled code: see there
    try:
        with guard, warnings.catch_warnings():  # restores the filters and showwarning after
            warnings.simplefilter("default", BemcontactWarning)
            warnings.showwarning = _one_line_warnings(warnings.showwarning)
            return _main(argv, guard)
    except KeyboardInterrupt:
        if guard.claim():
            print("bemcontact: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # the reader went away: nothing more to say, and nothing at exit either
        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK


def _one_line_warnings(show):
    """A ``warnings.showwarning`` printing bemcontact's warnings as one line
    ``bemcontact: warning: ...`` on stderr and others as ``show`` does."""

    def showwarning(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, BemcontactWarning):
            print(terminal_text(f"bemcontact: warning: {' '.join(str(message).split())}"),
                  file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    return showwarning


def _main(argv: Sequence[str] | None, guard: InterruptGuard) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_usage(sys.stderr)
        print("bemcontact: error: a command is required (run, check, mesh-info, bench)",
              file=sys.stderr)
        return EXIT_INPUT
    if args.command == "check":
        return _check(args)
    if args.command == "mesh-info":
        return _mesh_info(args)
    if args.command == "bench":
        return _bench(args)
    if args.command == "sweep":
        return _sweep(args)
    return _run(args, guard)


def _check(args: argparse.Namespace) -> int:
    problem = None
    try:
        problem = load_problem(args.problem)
        text = _describe(problem)
    except (BemcontactError, MemoryError) as exc:
        if args.debug:
            raise
        _error(_out_of_memory(args.problem, problem) if isinstance(exc, MemoryError) else str(exc))
        return EXIT_INPUT
    print(terminal_text(text))
    # what run would refuse before its solve, check refuses too (after the report)
    est = problem.contact_problem().memory_estimate(problem.options, problem.steps or None)
    _, available = machine_memory()
    if est.peak > allowed(available):
        _error(f"{args.problem}: the solve needs about {est.text()}, more than "
               f"{available_text(available)} (run refuses it); use a coarser mesh or smaller "
               "contact surfaces")
        return EXIT_INPUT
    return EXIT_OK


def _mesh_info(args: argparse.Namespace) -> int:
    from .errors import MeshError
    from .mesh import read_mesh

    try:
        mesh = read_mesh(args.mesh)
        q = mesh.quality()
        lines = [
            f"{args.mesh}: {mesh.n_elements} {mesh.element_type} elements, {mesh.n_nodes} nodes, "
            f"area {q['area'].sum():.6g}"
        ]
        for name, els in mesh.regions.items():
            lines.append(f"  region {name}: {els.size} elements, area {q['area'][els].sum():.6g}")
        lines.append(
            f"  edge length: min {q['min_edge'].min():.4g}, median "
            f"{np.median(q['max_edge']):.4g}, max {q['max_edge'].max():.4g}; aspect ratio "
            f"(longest/shortest edge): median {np.median(q['aspect']):.3g}, worst "
            f"{q['aspect'].max():.3g} (element {int(np.argmax(q['aspect']))})"
        )
        shells = mesh.components()
        for i, c in enumerate(shells):
            lines.append(
                f"  shell {i}: {c.size} elements, signed volume {mesh.signed_volume(c):.6g}"
            )
        problem = None
        try:
            mesh.check()
        except MeshError as exc:
            problem = " ".join(str(exc).split())
    except (BemcontactError, MemoryError) as exc:
        if args.debug:
            raise
        _error(_out_of_memory(args.mesh, None) if isinstance(exc, MemoryError) else str(exc))
        return EXIT_INPUT
    if problem is None:
        lines.append("  closed, consistently oriented, normals outward: usable as a body")
    print(terminal_text("\n".join(lines)))
    if problem is not None:
        _error(problem)
        return EXIT_INPUT
    return EXIT_OK


def _describe(problem) -> str:
    """What ``run`` would solve: per body its mesh, nodes, regions and
    conditions; the contact pair and frame; steps; memory of the dense path."""
    cp = problem.contact_problem()
    fs = cp.frames
    lines = [f"{problem.path}: valid" + (f" ({problem.title})" if problem.title else "")]
    compressed: list[str] = []
    for a, body in enumerate(problem.bodies):
        d = body.discretization
        mesh = body.mesh
        n = d.n_points
        mat = body.material
        if hasattr(body, "describe"):  # a finite-element body
            lines.append(f"  body {body.name}: {body.describe()}")
        else:
            lines.append(
                f"  body {body.name}: {mesh.n_elements} {mesh.element_type} elements, {n} "
                f"functional nodes ({3 * n} unknowns), E = {mat.youngs_modulus:g}, "
                f"nu = {mat.poisson_ratio:g}")
        counts = np.bincount(d.region, minlength=len(mesh.region_names))
        contact = {}
        for p, side in fs.pairs_of(a):
            surface = (cp.pairs[p].surface1, cp.pairs[p].surface2)[side]
            contact[surface] = fs.frames[p].nodes(side).size
        for r, name in enumerate(mesh.region_names):
            conds = body.boundary_conditions.get(name, ())
            what = "; ".join(_condition(c) for c in conds) if conds else "traction free"
            if name in contact:
                what = f"contact surface ({contact[name]} candidate nodes)"
            lines.append(f"    region {name}: {counts[r]} nodes, {what}")
        if problem.options.linear.use_hmatrix(n):
            compressed.append(body.name)
    for pair, (i, j), frame in zip(cp.pairs, cp.links, fs.frames):
        lines.append(
            f"  contact: {cp.bodies[i].name}.{pair.surface1} - {cp.bodies[j].name}."
            f"{pair.surface2}, mu = {pair.friction_coefficient:g}, {pair.frame} frame "
            f"{frame.placement} (frame_on = {pair.frame_on}): "
            f"{int(np.count_nonzero(frame.active))} active frame nodes; method = {pair.method}"
        )
    steps = problem.steps
    lines.append(
        f"  load: {len(steps)} step(s), {sum(s.increments for s in steps)} increment(s)"
        if steps else f"  load: one step in {problem.options.load_steps} increment(s)"
    )
    lines += [f"  rolling: step[{k}]{f' ({s.label})' if s.label else ''} {s.rolling.mode} along "
              f"{[round(v, 6) for v in s.rolling.direction]}, creepage "
              f"{list(s.rolling.creepage)}, spin {s.rolling.spin:g}"
              + (f", {s.rolling.distance:g} per increment" if s.rolling.distance else "")
              for k, s in enumerate(steps) if s.rolling is not None]
    out = problem.output
    if out.stresses:
        lines.append("  stresses: " + "; ".join(
            f"{r.label} ({r.kind} in {r.body}, {int(np.prod(r.probe.shape))} points)"
            for r in out.stresses))
    elif out.default_stresses:
        lines.append("  stresses: a depth profile and two sections under the peak pressure, in "
                     "each body the contact is small against (output.default_stresses)")
    est = cp.memory_estimate(problem.options, steps or None)
    total, available = machine_memory()
    lines.append(
        f"  estimated peak memory: {est.text()}; this machine: {available / 1e9:.1f} GB "
        f"available of {total / 1e9:.1f} GB"
        + (f", under {limit.what}" if (limit := binding_limit(available)) else "")
    )
    if compressed:
        lines.append(
            f"  compressed operators (H-matrix, H-LU) for {', '.join(compressed)}: estimated "
            "from the measured compression at their size (docs/benchmarks.md)"
        )
    return "\n".join(lines)


def _bench(args: argparse.Namespace) -> int:
    import json

    from .bench import one_body, two_cubes
    from .output.write import write_json

    try:
        if args.json is not None and not args.json.parent.is_dir():
            _error(f"{args.json}: --json: directory {args.json.parent} does not exist")
            return EXIT_INPUT
        if args.bench_case == "one-body":
            if not (0 < args.eps < 1):
                _error(f"--eps: must be in (0, 1), got {args.eps!r}")
                return EXIT_INPUT
            record = one_body(args.nodes, method=args.method, eps=args.eps, threads=args.threads,
                              leaf_size=args.leaf, truncation=args.truncation,
                              storage=args.storage)
        else:
            if not (0 < args.eps < 1):
                _error(f"--eps: must be in (0, 1), got {args.eps!r}")
                return EXIT_INPUT
            record = two_cubes(args.divisions, args.case, threads=args.threads,
                               method=args.method, eps=args.eps)
        if args.json is not None:
            write_json(args.json, record)
    except (BemcontactError, OSError, MemoryError) as exc:
        if args.debug:
            raise
        _error(_out_of_memory(f"bench {args.bench_case}", None)
               if isinstance(exc, MemoryError) else str(exc))
        return EXIT_INPUT
    print(json.dumps(record, indent=2))
    return EXIT_OK


def _out_of_memory(path, problem) -> str:
    """The one line for an allocation that failed (MemoryError, the compiled
    core's std::bad_alloc): the memory available and, with a problem, the
    solve's estimated peak."""
    total, available = machine_memory()
    limit = binding_limit(available)
    text = (f"{path}: out of memory ({available / 1e9:.1f} GB available of "
            f"{total / 1e9:.1f} GB" + (f", under {limit.what})" if limit else ")"))
    if problem is not None:
        with contextlib.suppress(Exception):
            est = problem.contact_problem().memory_estimate(problem.options,
                                                            problem.steps or None)
            text += f"; the solve's estimated peak memory is {est.text()}"
    return text + "; use a coarser mesh or a machine with more memory"


def _error(message: str) -> None:
    print(terminal_text(f"bemcontact: error: {' '.join(str(message).split())}"), file=sys.stderr)


def _progress(args: argparse.Namespace):
    """The progress reporter and the context it runs in (see ``--progress``)."""
    mode = args.progress
    if mode == "auto":
        mode = "none" if args.quiet or not sys.stderr.isatty() else "live"
    if mode == "live":
        from .progress import LiveProgress

        live = LiveProgress()
        return live, live
    if mode == "lines":
        from .progress import print_lines

        return print_lines, contextlib.nullcontext()
    return None, contextlib.nullcontext()


def _run(args: argparse.Namespace, guard: InterruptGuard) -> int:
    problem = None
    solving = False
    try:
        # the output directory is checked first (reading only), then locked
        # from the solve to the end of the write; bad input touches nothing
        out = RunDirectory(args.out, force=args.force)
        guard.out = out
        problem = load_problem(args.problem)
        with out:
            report, shown = _progress(args)
            try:
                with shown:
                    solving = True
                    result = problem.solve(threads=args.threads, progress=report)
                    solving = False
            except ConvergenceError as exc:
                if args.debug:
                    raise
                return _not_converged(exc, out, problem.echo)
            files = problem.write(result, out)
    except (BemcontactError, OSError, MemoryError) as exc:
        if args.debug:
            raise
        if isinstance(exc, MemoryError):
            _error(_out_of_memory(args.problem, problem))
        elif isinstance(exc, OSError) and not isinstance(exc, BemcontactError):
            where = getattr(exc, "filename", None)
            _error(f"cannot write the results to {args.out}: {exc.strerror or exc}"
                   + (f" ({where})" if where else ""))
        else:
            text = str(exc)
            # what the solve refuses (memory, a body free to move) names the file too
            if solving and not text.startswith(str(args.problem)):
                text = f"{args.problem}: {text}"
            _error(text)
        return EXIT_INPUT
    if not args.quiet:
        print(terminal_text(run_report(problem, result, args.out, files)))
    return EXIT_OK


def _condition(c) -> str:
    """A boundary condition as the problem file writes it: ``displacement
    [0, free, -0.01]``, ``pressure 2``, ``force [free, 0, -400]``."""
    name = type(c).__name__.lower()
    if hasattr(c, "pressure"):
        return f"{name} {c.pressure:g}"
    value = getattr(c, "value", None)
    if callable(value):
        return f"{name} (a function of position)"
    try:
        return f"{name} [" + ", ".join("free" if v is None else f"{v:g}" for v in value) + "]"
    except (TypeError, ValueError):
        return name


def _not_converged(exc: ConvergenceError, out: RunDirectory, echo) -> int:
    _error(str(exc))
    r = exc.result
    if r is not None:
        for pr in r.pairs or [r]:
            which = f" of {pr.label}" if len(r.pairs) > 1 else ""
            for iface in pr.interfaces:
                print(terminal_text(f"  states at the last iterate, {iface.body}{which}: "
                                    f"{counts(iface.counts())}"),
                      file=sys.stderr)
            print(terminal_text(f"  states at the last iterate, frame{which}: "
                                f"{counts(pr.frame.counts())}"), file=sys.stderr)
    data = r if r is not None else {"converged": False}
    try:
        path = write_summary(data, out, echo, error=str(exc))
    except (BemcontactError, OSError) as werr:
        print(terminal_text(f"  could not write the diagnostic summary: {werr}"), file=sys.stderr)
    else:
        print(terminal_text(f"  diagnostic summary: {path}"), file=sys.stderr)
    return EXIT_NOT_CONVERGED



# ------------------------------------------------------------------ sweep


def _sweep_parser(sub) -> None:
    sw = sub.add_parser(
        "sweep", help="a parameter study: many solves of a problem file on Dask",
        description="Solve PROBLEM for every combination of the --vary values (or the points of "
        "its [sweep] table), each point a task on Dask distributed (a local cluster by default); "
        "points that share their bodies reuse the condensed operators. Writes DIR/table.csv, "
        "DIR/sweep.png and each point's results in DIR/points/ (docs/getting-started.md).",
    )
    sw.add_argument("problem", metavar="PROBLEM.toml", type=pathlib.Path)
    sw.add_argument("--vary", metavar="KEY=VALUES", action="append",
                    help="a dotted problem-file key and its values, comma-separated "
                    "(contact.friction_coefficient=0.1,0.2); repeat for a full factorial")
    sw.add_argument("--out", metavar="DIR", required=True,
                    help="output directory: new, empty, or this sweep's (resumed: finished "
                    "points are not computed again)")
    sw.add_argument("--scheduler", metavar="ADDRESS",
                    help="a running Dask scheduler (tcp://host:8786); default: a local cluster")
    sw.add_argument("--workers", metavar="N", type=_positive_int,
                    help="worker processes of the local cluster (default: the cores)")
    sw.add_argument("--threads", metavar="N", type=_threads,
                    help="threads of each point's solve (default 1)")
    sw.add_argument("--timeout", metavar="SECONDS", type=float,
                    help="how long to wait for the scheduler (default 10)")
    sw.add_argument("--quiet", action="store_true", help="print nothing on success")
    sw.add_argument("--debug", action="store_true", help="show tracebacks of errors")


def _sweep(args: argparse.Namespace) -> int:
    from .study import SweepOptions, run_sweep

    quiet = args.quiet

    def started(total, resumed, dashboard):
        if not quiet:
            before = f", {resumed} finished before" if resumed else ""
            link = f"; Dask dashboard {dashboard}" if dashboard else ""
            print(terminal_text(f"sweep of {args.problem}: {total} point(s){before}{link}"),
                  file=sys.stderr)

    def progress(done, total, row):
        if not quiet:
            what = (f"normal force {row['normal_force']:.6g}" if row.get("status") == "ok"
                    else row.get("error", ""))
            print(terminal_text(f"  point {done}/{total} {row['point']}: {row['status']}: {what}"),
                  file=sys.stderr)

    try:
        given = {k: getattr(args, k) for k in ("scheduler", "workers", "threads", "timeout")}
        opts = SweepOptions(**{k: v for k, v in given.items() if v is not None})
        result = run_sweep(args.problem, args.out, vary=args.vary, options=opts,
                           progress=progress, started=started)
    except (BemcontactError, OSError) as exc:
        if args.debug:
            raise
        _error(str(exc))
        return EXIT_INPUT
    if not quiet:
        ok = len(result.rows) - result.failed
        print(terminal_text(
            f"{args.problem}: {len(result.rows)} point(s), {ok} ok, {result.failed} failed "
            f"({result.computed} computed, {result.resumed} finished before); results in "
            f"{args.out}: " + ", ".join(f.name for f in result.files)))
    return EXIT_OK if result.failed == 0 else EXIT_NOT_CONVERGED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
