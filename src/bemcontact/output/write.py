"""Writing contact results to disk: JSON summary, VTU (ParaView) and CSV.

Files written by :func:`write_results` into ``out_dir`` (``<body>`` is a body
name; columns and units in ``docs/problem-file.md``; which of them are written
is set by :class:`OutputOptions`, the problem file's ``[output]`` table):

* ``summary.json``: :meth:`ContactResult.summary` plus ``version``, ``names``
  (body 1, body 2; every body of an assembly) and ``problem`` (the problem file's echo, if given).
* ``<body>.vtu``: the body's whole surface, with its surface stresses.
* ``<body>_interface.vtu``, ``<body>_interface.csv``: its contact surface.
* ``frame.vtu``, ``frame.csv``: the contact frame nodes.
* ``<name>.pvd`` for each of the VTU files above, with ``steps/<name>_<k>.vtu``
  (k = 001, 002, ...): the state at the end of every load step, a time series
  for ParaView (time = step number).
* ``frame_tractions.png``: contact pressure and tangential traction on the frame,
  zoomed to the contact zone; ``frame_profile.png``: both against the distance
  from the contact's centre, when the contact is axisymmetric (figures need
  matplotlib, ``pip install "bemcontact[plot]"``; figures on by default are
  skipped without it, with an
  :class:`~bemcontact.errors.OptionalDependencyWarning`).

* ``stresses_<body>_<label>.csv``, ``.vtu``, ``.png``: stresses inside the
  bodies (:mod:`bemcontact.output.stresses`).

An assembly (several contact pairs) writes every ``<body>.vtu`` and, per
pair, its frame, interfaces and figures under the pair's names
(``<b1>+<b2>_frame.vtu``, ``<b1>+<b2>_<body>_interface.csv``,
``<b1>+<b2>_frame_tractions.png``, ...: :mod:`bemcontact.output.layout`);
``summary.json`` lists the pairs' forces and states in ``pairs``.

VTU files: the bodies' surfaces at their true geometry (mesh nodes and
elements, region names as field data; also ``regions`` in ``summary.json``),
see :mod:`bemcontact.output.vtu`.

Writing is all or nothing, and never touches a file bemcontact did not write:
the rules of :mod:`bemcontact.output.rundir` (a whole run is written beside
``out_dir`` and swapped in; a directory that is not a bemcontact output
directory, the current directory, a root or an empty path are refused unless
``force``; a lock keeps two runs out of one directory).
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import secrets
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..contact.results import ContactResult
from ..errors import ConfigError, OptionalDependencyWarning
from ..settings import Key, check_settings, setting
from ..stresses.probes import StressRequest
from .layout import Layout, check_files, pair_stems, result_layout
from .rundir import RunDirectory
from .stresses import file_names, stress_fields, stress_summary, write_stress_files
from .tables import write_csv
from .vtu import frame_cells, write_pvd, write_state_vtus

#: Columns of ``<body>_interface.csv``.
INTERFACE_COLUMNS = (
    "x", "y", "z", "pressure", "tx", "ty", "tz", "gap", "slip_x", "slip_y", "slip_z", "state",
    "ux", "uy", "uz",
)  # fmt: skip
#: Columns of ``frame.csv``.
FRAME_COLUMNS = (
    "x", "y", "z", "pressure", "tx", "ty", "tz", "gap", "slip_x", "slip_y", "slip_z", "state",
    "nx", "ny", "nz", "weight",
)  # fmt: skip


# --------------------------------------------------------------------------- public


@dataclass(frozen=True)
class OutputOptions:
    """Which files :func:`write_results` writes (``summary.json`` always).

    Attributes
    ----------
    vtu: ParaView files of the bodies' surfaces, interfaces and the frame.
    csv: CSV tables of the interface and frame nodes.
    figures: ``frame_tractions.png`` (needs matplotlib).
    steps: ``"all"``: VTU files for every load step in ``steps/`` and PVD
        collections; ``"last"``: the final state only.
    """

    vtu: bool = setting(Key(
        "vtu", "boolean", "ParaView files of each body's surface and interface and of the "
        "frame", default=True))
    csv: bool = setting(Key(
        "csv", "boolean", "CSV tables of the interface and frame nodes", default=True))
    figures: bool = setting(Key(
        "figures", "boolean", "PNG figures (contact pressure and tangential traction on the "
        "frame; needs matplotlib)", default=True))
    steps: str = setting(Key(
        "steps", "string", "`all`: VTU files for every load step and PVD collections; "
        "`last`: the final state only", default="all", choices=("all", "last")))
    default_stresses: bool = setting(Key(
        "default_stresses", "boolean", "without `[[output.stresses]]`: the stresses on a depth "
        "profile under the peak pressure and on the two planes through it, in each body the "
        "contact is small against", default=True))
    #: the ``[[output.stresses]]`` requests (:class:`~bemcontact.stresses.StressRequest`)
    stresses: tuple = ()

    def __post_init__(self) -> None:
        check_settings(self)
        if not isinstance(self.stresses, tuple) or not all(
                isinstance(r, StressRequest) for r in self.stresses):
            raise ConfigError(f"OutputOptions.stresses must be a tuple of StressRequest, got "
                              f"{self.stresses!r}")


def summary(
    result: ContactResult | Mapping[str, Any],
    problem_echo: Mapping[str, Any] | None = None,
    error: str | None = None,
) -> dict[str, Any]:
    """The content of ``summary.json``: ``result.summary()`` (or a given dict)
    with ``version``, ``names``, ``regions`` (body -> its region names, in the
    order of the VTU files' ``region`` index; a finite-element body's volume
    regions under ``volume_regions``), ``problem`` and ``error`` added, non-finite
    numbers turned into ``null`` (strict JSON).  An assembly's ``pairs``
    entries get the pair's ``label`` and ``files``, the stem of its files
    (:mod:`bemcontact.output.layout`)."""
    from .._version import __version__

    if isinstance(result, ContactResult):
        s: dict[str, Any] = {**result.summary(), "names": list(result.names), "regions": {
            n: list(sol.discretization.mesh.region_names)
            for n, sol in zip(result.names, result.bodies)
        }}
        volumes = {n: list(m.volume.volume_names) for n, m in result.models.items()
                   if hasattr(m, "volume_fields")}
        if volumes:  # finite-element bodies: the volume regions, as <body>_volume.vtu indexes them
            s["volume_regions"] = volumes
        if "pairs" in s:  # an assembly: each pair's label and the stem of its files
            stems = pair_stems([(p.names, p.surfaces) for p in result.pairs])
            s["pairs"] = [{"label": p.label, "files": stem, **e}
                          for p, stem, e in zip(result.pairs, stems, s["pairs"])]
    elif isinstance(result, Mapping):
        s = dict(result)
    else:
        raise ConfigError(
            f"summary: expected a ContactResult or a dict, got {type(result).__name__}"
        )
    s["version"] = __version__
    s["versions"] = _versions()
    s["provenance"] = provenance()
    if problem_echo is not None:
        s["problem"] = dict(problem_echo)
    if error is not None:
        s["error"] = error
    return _json_ready(s)


def _versions() -> dict[str, str]:
    """Versions of bemcontact, Python, the numerical libraries and of the
    optional ones this run used (gmsh, matplotlib: those imported)."""
    import platform
    import sys

    import scipy

    from .._version import __version__

    out = {"bemcontact": __version__, "python": platform.python_version(),
           "numpy": np.__version__, "scipy": scipy.__version__}
    try:
        import meshio

        out["meshio"] = meshio.__version__
    except (ImportError, AttributeError):  # pragma: no cover - meshio is a dependency
        pass
    for name, attr in (("gmsh", "__version__"), ("matplotlib", "__version__")):
        mod = sys.modules.get(name)
        if mod is not None and isinstance(getattr(mod, attr, None), str):
            out[name] = getattr(mod, attr)
    return out


def _cpu() -> str:
    import platform

    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.partition(":")[2].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _commit() -> str | None:
    """The git commit of bemcontact's source tree when it runs from one (an
    editable install of a clone; None for an installed wheel)."""
    import subprocess

    src = pathlib.Path(__file__).resolve().parents[1]
    try:
        top = subprocess.run(["git", "-C", str(src), "rev-parse", "--show-toplevel", "HEAD"],
                             capture_output=True, text=True, timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    lines = top.stdout.split()
    if top.returncode != 0 or len(lines) != 2:
        return None
    # the tree must be bemcontact's own (a venv inside another repository is not)
    if pathlib.Path(lines[0], "src", "bemcontact").resolve() != src:
        return None
    dirty = subprocess.run(["git", "-C", lines[0], "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True, timeout=5)
    return lines[1] + ("-modified" if dirty.returncode == 0 and dirty.stdout.strip() else "")


def provenance() -> dict[str, Any]:
    """Where and how a run was made: platform, CPU, cores, the compiled
    core's build (native or portable, compiler, flags, OpenMP), the git
    commit of the source when available."""
    import platform

    from .._native import core
    from ..linalg.threads import available_cores

    out: dict[str, Any] = {"platform": platform.platform(), "cpu": _cpu(),
                           "cores": available_cores()}
    try:
        out["build"] = dict(core().build_info())
    except Exception:  # noqa: BLE001 - provenance never fails a run
        pass
    commit = _commit()
    if commit:
        out["commit"] = commit
    return out


def write_results(
    result: ContactResult,
    out_dir: str | os.PathLike | RunDirectory,
    problem_echo: Mapping[str, Any] | None = None,
    options: OutputOptions | None = None,
    *,
    force: bool = False,
) -> list[pathlib.Path]:
    """Write the result files into ``out_dir`` (all or nothing, see the
    module docstring; a :class:`RunDirectory` already locked by the caller
    may be passed) and return their paths (the per-step VTU files in
    ``steps/`` are not listed: the PVD files name them).

    Without ``options``, every file is written, figures only if matplotlib
    is installed (else an :class:`~bemcontact.errors.OptionalDependencyWarning`
    says they were skipped).

    Raises :class:`ConfigError` if a body name cannot name a file (or the
    file names clash or are too long: :mod:`~bemcontact.output.layout`),
    ``options`` asks for figures without matplotlib or ``out_dir`` may not
    be written (``force``: see :class:`RunDirectory`), ``OSError`` if the
    files cannot be written.
    """
    if not isinstance(result, ContactResult):
        raise ConfigError(f"write_results: expected a ContactResult, got {type(result).__name__}")
    opt = OutputOptions(figures=figures_by_default()) if options is None else options
    if not isinstance(opt, OutputOptions):
        raise ConfigError(f"write_results: options must be OutputOptions, got {opt!r}")
    if opt.figures:
        require_matplotlib("write_results: figures")
    names = result_layout(result)
    series = names.series()
    files = ["summary.json"]
    if opt.vtu:
        files += [f"{n}.vtu" for n in series]
        if opt.steps == "all":
            files += [f"{n}.pvd" for n in series]
    if opt.csv:
        files += [f"{n}.csv" for n in names.csv()]
    if opt.figures:
        files += [f"{p.figure}frame_tractions.png" for p in names.pairs]
    fields, skipped = stress_fields(result, opt)  # before anything is written: may refuse
    files += file_names(fields, opt)
    history = list(result.history) or [result]
    check_files(files, len(history) if opt.vtu and opt.steps == "all" else 0)
    rundir = out_dir if isinstance(out_dir, RunDirectory) else RunDirectory(out_dir, force=force)
    with rundir.staging() as tmp:
        data = summary(result, problem_echo)
        data["stresses"] = _json_ready(stress_summary(result, fields, skipped))
        _write_json(tmp / "summary.json", data)
        write_stress_files(tmp, fields, opt, (problem_echo or {}).get("units"))
        if opt.vtu:
            write_state_vtus(tmp, result, "", names)
            if opt.steps == "all":
                (tmp / "steps").mkdir()
                width = max(3, len(str(len(history))))
                for k, state in enumerate(history, start=1):
                    write_state_vtus(tmp / "steps", state, f"_{k:0{width}d}", names)
                for n in series:
                    write_pvd(tmp / f"{n}.pvd", [
                        (k, f"steps/{n}_{k:0{width}d}.vtu") for k in range(1, len(history) + 1)
                    ])  # fmt: skip
        if opt.csv:
            for pair, stems in _pairs(result, names):
                for iface, stem in zip(pair.interfaces, stems.interfaces):
                    _write_interface_csv(tmp / f"{stem}.csv", iface)
                _write_frame_csv(tmp / f"{stems.frame}.csv", pair.frame)
        if opt.figures:
            units = (problem_echo or {}).get("units")
            for pair, stems in _pairs(result, names):
                if _write_figures(tmp, result, units, pair if names.assembly else None,
                                  stems.figure):
                    at = files.index(f"{stems.figure}frame_tractions.png") + 1
                    files.insert(at, f"{stems.figure}frame_profile.png")
    out = pathlib.Path(rundir.given)
    return [out / f for f in files]


def _pairs(result: ContactResult, names: Layout):
    """(pair, its :class:`PairFiles`) for each pair written: the result
    itself (its first pair's fields) for two bodies."""
    if not names.assembly:
        return [(result, names.pairs[0])]
    return list(zip(result.pairs, names.pairs))


def _write_figures(directory: pathlib.Path, result: ContactResult, units, pair=None,
                   prefix: str = "") -> bool:
    """``<prefix>frame_tractions.png``, and ``<prefix>frame_profile.png`` if
    the contact is axisymmetric (:func:`~bemcontact.output.plot.axisymmetry`),
    of ``pair`` (a PairResult; default the result's first pair); units are
    the problem file's labels.  Returns whether the profile was drawn."""
    from .plot import AXISYMMETRIC_SCATTER, axisymmetry, plot_frame_tractions, plot_radial_profile

    u = {k: str(v) for k, v in (units or {}).items()} if isinstance(units, Mapping) else {}
    kw = {"length_unit": u.get("length", ""), "stress_unit": u.get("stress", "")}
    source = result if pair is None else pair
    plot_frame_tractions(source, directory / f"{prefix}frame_tractions.png",
                         cells=frame_cells(result, pair), force_unit=u.get("force", ""), **kw)
    axi = axisymmetry(source.frame)
    if axi is None or axi[1] > AXISYMMETRIC_SCATTER:
        return False
    plot_radial_profile(source.frame, directory / f"{prefix}frame_profile.png", component=None,
                        center=axi[0], title="radial profile (r from the contact's centre)",
                        **kw)
    return True


#: How to get the figures (matplotlib is the ``plot`` extra).
PLOT_INSTALL = 'pip install "bemcontact[plot]"'
#: The one-line warning when figures that are on by default are skipped.
FIGURES_SKIPPED = (
    f"figures skipped (frame_tractions.png): matplotlib is not installed; {PLOT_INSTALL} "
    "to draw them"
)


def has_matplotlib() -> bool:
    """Whether matplotlib (the optional dependency of the figures) can be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def figures_by_default() -> bool:
    """Whether figures that nobody asked for explicitly are drawn: with
    matplotlib yes; without it no, and an :class:`OptionalDependencyWarning`
    (:data:`FIGURES_SKIPPED`) says so.  An explicit request for figures
    without matplotlib is an error instead (:func:`require_matplotlib`)."""
    if has_matplotlib():
        return True
    warnings.warn(FIGURES_SKIPPED, OptionalDependencyWarning, stacklevel=3)
    return False


def require_matplotlib(what: str) -> None:
    """Raise ConfigError naming ``what`` if matplotlib cannot be imported."""
    if not has_matplotlib():
        raise ConfigError(
            f"{what}: needs matplotlib, which is not installed; {PLOT_INSTALL}, or "
            "turn figures off (problem file: [output] figures = false)"
        )


def write_summary(
    result_or_dict: ContactResult | Mapping[str, Any],
    out_dir: str | os.PathLike | RunDirectory,
    problem_echo: Mapping[str, Any] | None = None,
    error: str | None = None,
    *,
    force: bool = False,
) -> pathlib.Path:
    """Write a run of only ``summary.json`` (all or nothing, as
    :func:`write_results`: it replaces an earlier run in ``out_dir`` as a
    whole), e.g. the diagnostic summary of a solve that did not converge
    (``ConvergenceError.result``, with the error message as ``error``).
    Returns its path."""
    data = summary(result_or_dict, problem_echo, error)
    rundir = out_dir if isinstance(out_dir, RunDirectory) else RunDirectory(out_dir, force=force)
    with rundir.staging() as tmp:
        _write_json(tmp / "summary.json", data)
    return pathlib.Path(rundir.given) / "summary.json"


def write_json(path: str | os.PathLike, data: Mapping[str, Any]) -> pathlib.Path:
    """Write ``data`` as JSON to ``path`` atomically (a temporary file in the
    same directory, then a rename): an error never leaves a partial file."""
    path = pathlib.Path(path)
    if not path.parent.is_dir():
        raise ConfigError(f"{path}: directory {path.parent} does not exist")
    tmp = path.parent / f".{path.name}.tmp-{secrets.token_hex(4)}"
    try:
        _write_json(tmp, data)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()
    return path



# --------------------------------------------------------------------------- writers


def _json_ready(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _json_ready(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [_json_ready(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    return obj


def _write_json(path: pathlib.Path, data: Mapping[str, Any]) -> None:
    with open(path, "w") as f:
        json.dump(data, f, indent=2, allow_nan=False)
        f.write("\n")


def _write_interface_csv(path: pathlib.Path, iface) -> None:
    table = np.column_stack([
        iface.points, iface.pressure, iface.tangential_traction, iface.gap, iface.slip,
        iface.state.astype(float), iface.displacement,
    ])  # fmt: skip
    write_csv(path, INTERFACE_COLUMNS, table, ("state",))


def _write_frame_csv(path: pathlib.Path, frame) -> None:
    table = np.column_stack([
        frame.points, frame.pressure, frame.tangential_traction, frame.gap, frame.slip,
        frame.state.astype(float), frame.normals, frame.weights,
    ])  # fmt: skip
    columns = FRAME_COLUMNS
    if frame.microslip is not None:  # a rolling step's
        table = np.column_stack([table, frame.microslip, frame.power_density])
        columns = columns + ("microslip_x", "microslip_y", "microslip_z", "power_density")
    write_csv(path, columns, table, ("state",))


__all__ = [
    "OutputOptions", "write_results", "require_matplotlib", "has_matplotlib",
    "figures_by_default", "FIGURES_SKIPPED", "write_summary", "summary", "INTERFACE_COLUMNS", "FRAME_COLUMNS",
]  # fmt: skip
