"""Problem files: a TOML description of a contact problem (two bodies, or an
assembly of several bodies and contact pairs).

:func:`load_problem` reads and checks a problem file completely (meshes are
built and read, materials and boundary conditions checked, the contact
surfaces located and, by default, the contact frame built) before any BEM
numerics run, and returns a :class:`ProblemFile`.  The format is documented in
``docs/problem-file.md``; in short::

    title = "two cubes"                 # optional
    units = { length = "mm", force = "N", stress = "MPa" }   # optional labels

    [solver]                            # optional: SolverOptions fields
    tolerance = 1e-10

    [[body]]                            # two or more
    name = "lower"
    mesh = { box = { lower = [0, 0, 0], upper = [2, 2, 2], divisions = 6 } }
    material = { youngs_modulus = 1e4, poisson_ratio = 0.3 }
    [body.boundary_conditions.zmin]
    displacement = [0, 0, 0]

    [contact]                           # or several [[contact]] sections
    bodies = ["lower", "upper"]
    surfaces = ["zmax", "zmin"]
    friction_coefficient = 0.1

Every problem in the file is reported as a :class:`~bemcontact.errors.ConfigError`
with a one-line message ``<file>: <field>: <what is wrong>, got <value>`` (plus a
fix where one is obvious).  Field paths are dotted and index the ``[[body]]``
array by position as written in the file, starting at 0: ``body[1].material.
poisson_ratio``, ``body[0].boundary_conditions.zmin.displacement[2]``,
``contact.surfaces[1]``.  Errors that concern the whole file (unreadable, not
valid TOML) have no field part.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import os
import pathlib
import re
import tomllib
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..bem import Displacement, ElasticBody, Force, Pressure, Traction
from ..contact import ContactPair, ContactProblem, ContactResult, LoadStep, SolverOptions
from ..errors import BemcontactError, ConfigError, OptionalDependencyWarning
from ..inputs import MAX_PROBLEM_BYTES, check_regular_file
from ..linalg import HMatrixOptions, LinearSolverOptions
from ..mesh import SurfaceMesh
from ..output.write import (
    FIGURES_SKIPPED,
    PLOT_INSTALL,
    OutputOptions,
    has_matplotlib,
    write_results,
)
from . import schema
from .checks import FREE, Checker, a_type, one_line, suggest
from .method import method_of, on_grid
from .bodies import read_body_force, read_material, read_materials, read_mesh_table, surface_of
from .pairs import read_pairs
from .sizes import check_body_size
from .stresses import stress_requests
from .rolling import step_rolling

#: Body names must be usable as file names (results are written to ``<name>.vtu``).
NAME_PATTERN = re.compile(r"^[A-Za-z][A-Za-z0-9_-]*$")
#: Longest body name (it names output files; file systems allow 255 bytes).
MAX_NAME_LENGTH = 64
#: Body names that would collide with other output files.
RESERVED_NAMES = ("frame", "summary")


@dataclass(frozen=True)
class ProblemFile:
    """A checked problem file.

    Attributes
    ----------
    path: the problem file.
    title: its ``title`` ('' if not given).
    units: its ``units`` labels (e.g. ``{"length": "mm"}``; not used in any
        computation: the numbers must already be in one consistent set).
    bodies: the :class:`~bemcontact.bem.body.ElasticBody` objects: with one
        pair of two bodies in the order of ``contact.bodies`` (body 1 first:
        the contact normal points from body 1 into body 2 and
        ``normal_force`` is the force body 1 exerts on body 2), in an
        assembly in the ``[[body]]`` order.
    pairs: the :class:`~bemcontact.contact.ContactPair` of each ``[contact]``
        (``pair``: the first).
    options: the :class:`~bemcontact.contact.SolverOptions`.
    steps: the :class:`~bemcontact.contact.LoadStep` history of the
        ``[[step]]`` sections (empty: one step to the bodies' conditions).
    output: the :class:`~bemcontact.output.write.OutputOptions` of the ``[output]``
        table (which files ``bemcontact run`` writes).
    echo: ``{"file": str(path), **content, "sha256": {...}}``, the file's
        content as written and the SHA-256 of the problem file
        (``"problem"``) and of every mesh file it names (by the name it
        gives) (JSON-ready; written into ``summary.json``).
    """

    path: pathlib.Path
    title: str
    units: Mapping[str, str]
    bodies: tuple[ElasticBody, ...]
    pairs: tuple[ContactPair, ...]
    options: SolverOptions
    echo: dict[str, Any]
    steps: tuple[LoadStep, ...] = ()
    output: OutputOptions = OutputOptions()
    _contact: ContactProblem = field(init=False, repr=False, compare=False)
    #: the point the bodies are solved relative to when they lie far from the
    #: global origin (None: the global origin; :mod:`bemcontact.contact.origin`)
    origin: np.ndarray | None = field(init=False, repr=False, compare=False)
    #: after :meth:`solve`: how a pair's ``method`` was followed ('' for the
    #: full path asked for), one line
    method_note: str = field(init=False, repr=False, compare=False, default="")

    def __post_init__(self) -> None:
        if len(self.bodies) == 2 and len(self.pairs) == 1:
            contact = ContactProblem(*self.bodies, self.pairs[0])
        else:
            contact = ContactProblem(bodies=self.bodies, pairs=self.pairs)
        object.__setattr__(self, "origin", contact.origin)
        object.__setattr__(self, "_contact", contact)

    @property
    def pair(self) -> ContactPair:
        """The first (in a two-body problem the only) contact pair."""
        return self.pairs[0]

    def solve(self, *, threads: int | None = None, progress=None,
              raise_on_failure: bool = True) -> ContactResult:
        """Solve the file's problem as ``bemcontact run`` does: with its
        ``[solver]`` options (``threads`` overrides ``solver.threads``) and
        its whole loading history (the ``[[step]]`` sections, or
        ``solver.load_steps`` proportional increments without them).
        ``progress`` and ``raise_on_failure``: as
        :meth:`~bemcontact.contact.ContactProblem.solve`."""
        options = self.options
        if threads is not None:
            options = dataclasses.replace(options, threads=threads)
        object.__setattr__(self, "method_note", "")
        method = method_of(self.pairs)
        if method != "full":
            grid, note = on_grid(self._contact, self.steps, method, options)
            object.__setattr__(self, "method_note", note)
            if grid is not None:
                return grid
        return self._contact.solve(options, steps=self.steps or None, progress=progress,
                                   raise_on_failure=raise_on_failure)

    def write(self, result: ContactResult, out_dir, *, force: bool = False) -> list[pathlib.Path]:
        """Write ``result`` into ``out_dir`` as ``bemcontact run`` does: the
        files the ``[output]`` table asks for, the problem file's content in
        ``summary.json`` (all or nothing, and never over files bemcontact did
        not write unless ``force``: :func:`~bemcontact.output.write_results`)."""
        from ..multiscale.assembly import GridAssemblyResult
        from ..multiscale.pair import GridResult

        if isinstance(result, (GridResult, GridAssemblyResult)):
            from ..output.grid import write_grid_results

            return write_grid_results(result, out_dir, self.echo, self.output, force=force)
        return write_results(result, out_dir, self.echo, self.output, force=force)

    def contact_problem(self) -> ContactProblem:
        """The :class:`~bemcontact.contact.ContactProblem` (the same object on
        every call, so a frame built while loading is reused by the solve);
        it solves relative to ``origin`` itself and returns results at the
        bodies' position."""
        return self._contact


# --------------------------------------------------------------------------- reading


def load_problem(path: str | os.PathLike, *, check_overlap: bool = True) -> ProblemFile:
    """Read and check a problem file.

    Parameters
    ----------
    path:
        The TOML file.  Mesh files named in it are relative to its directory.
    check_overlap:
        Also build the contact frame, which finds contact surfaces that do
        not face each other (reported on ``contact.surfaces``); kept and
        reused by the solve (not for a pair with ``method = "multiscale"``).

    Raises
    ------
    ConfigError
        For every problem with the file, the meshes it names, the materials
        or the boundary conditions (one-line message, see the module docstring);
        also for ``[output] figures = true`` without matplotlib.

    Warns
    -----
    OptionalDependencyWarning
        Figures on by default (no ``figures`` key) without matplotlib: they
        are turned off in ``output`` (``pip install "bemcontact[plot]"`` to
        get them).
    """
    p = pathlib.Path(path)
    src = os.fspath(path)
    check_regular_file(p, "problem file", MAX_PROBLEM_BYTES)
    try:
        with open(p, "rb") as f:
            data = f.read(MAX_PROBLEM_BYTES + 1)
        if data.startswith(b"\xef\xbb\xbf"):  # a UTF-8 byte-order mark, as some editors write
            data = data[3:]
        content = tomllib.loads(data.decode("utf-8"))
    except RecursionError:
        raise ConfigError(f"{src}: tables or arrays nested too deeply to be a problem file") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{src}: not a valid TOML file: {one_line(str(exc))}") from None
    except UnicodeDecodeError as exc:
        raise ConfigError(
            f"{src}: not a UTF-8 text file (byte {exc.start}: {exc.reason}); problem files are "
            "TOML, which is UTF-8"
        ) from None
    except IsADirectoryError:
        raise ConfigError(f"{src}: is a directory, not a problem file") from None
    except OSError as exc:
        raise ConfigError(
            f"{src}: cannot read the problem file: {exc.strerror or exc}"
        ) from None
    try:
        reader = _Reader(src, p.parent)
        problem = reader.problem(p, content, check_overlap)
    except RecursionError:
        raise ConfigError(f"{src}: tables or arrays nested too deeply to be a problem file") from None
    problem.echo["sha256"] = {"problem": hashlib.sha256(data).hexdigest(), **reader.hashes}
    return problem


class _Reader(Checker):
    """Reads one file's sections into bodies, a pair, options and steps."""

    #: Figures on by default were turned off (no matplotlib).
    figures_skipped = False

    def __init__(self, src: str, base: pathlib.Path) -> None:
        super().__init__(src, base)
        #: mesh file (as named in the problem file) -> SHA-256 of its content
        self.hashes: dict[str, str] = {}

    # --------------------------------------------------------------- sections
    def problem(self, path: pathlib.Path, content: dict, check_overlap: bool) -> ProblemFile:
        R = schema.ROOT
        self.table("", content, R)
        top = self.fields("", content, R)
        units = self.units(content.get("units", {}))
        options = self.solver(content.get("solver", {}))
        raw_bodies = content["body"]
        if not isinstance(raw_bodies, list) or not all(isinstance(b, dict) for b in raw_bodies):
            self.fail("body", "must be an array of tables", raw_bodies,
                      "write each body as a [[body]] section")
        if len(raw_bodies) < 2:
            self.fail("body", f"at least two [[body]] sections are needed, not {len(raw_bodies)}",
                      [b.get("name") for b in raw_bodies])
        names = [self.body_name(i, b) for i, b in enumerate(raw_bodies)]
        fem = [self.value(f"body[{i}].model", b.get("model", "bem"), schema.BODY.key("model"))
               == "fem" for i, b in enumerate(raw_bodies)]
        self.distinct(names, fem)
        given = [read_mesh_table(self, f"body[{i}].mesh", b["mesh"], fem[i], self.hashes)
                 for i, b in enumerate(raw_bodies)]
        meshes = [surface_of(m) for m in given]
        for i, b in enumerate(raw_bodies):
            if not fem[i]:
                check_body_size(self, f"body[{i}].mesh", meshes[i], b["mesh"])
        materials = [self.material(i, b, given[i], fem[i]) for i, b in enumerate(raw_bodies)]
        loads = [read_body_force(self, f"body[{i}]", b, fem[i], given[i])
                 for i, b in enumerate(raw_bodies)]
        specs = read_pairs(self, content["contact"], names, meshes)
        for sp in specs:
            if sp.pair.method == "multiscale" and any(fem[i] for i in sp.order):
                self.fail(f"{sp.where}.method", "the contact grid takes BEM bodies; a "
                          "finite-element body is solved on the full path", "multiscale",
                          'use method = "full" or "auto"')
        output = self.output(content.get("output", {}), names, meshes)
        # each body's contact surfaces, with the field naming each
        surfaces: list[dict[str, str]] = [{} for _ in names]
        for sp in specs:
            for side, i in enumerate(sp.order):
                s_ = (sp.pair.surface1, sp.pair.surface2)[side]
                surfaces[i].setdefault(s_, sp.surface_where(side))
        bodies = []
        for i, b in enumerate(raw_bodies):
            bcs = self.boundary_conditions(
                f"body[{i}].boundary_conditions", b.get("boundary_conditions", {}), meshes[i],
                surfaces[i],
            )
            where = f"body[{i}].mesh"
            try:
                if fem[i]:
                    from ..fem import FiniteElementBody

                    density, force = loads[i]
                    bodies.append(FiniteElementBody(given[i], materials[i], bcs, name=names[i],
                                                    density=density, body_force=force))
                else:
                    bodies.append(ElasticBody(meshes[i], materials[i], bcs, name=names[i]))
            except BemcontactError as exc:  # the closed/oriented surface check
                self.wrap(where, exc, b["mesh"])
        if len(specs) == 1 and len(bodies) == 2:  # body 1 of the pair first
            ordered = tuple(bodies[i] for i in specs[0].order)
        else:
            ordered = tuple(bodies)
        echo = {"file": str(path), **copy.deepcopy(content)}
        steps = self.steps(content.get("step", []), names, meshes, surfaces)
        problem = ProblemFile(path, top["title"], units, ordered, tuple(sp.pair for sp in specs),
                              options, echo, steps, output)
        if steps:
            try:
                problem.contact_problem().states(steps)
            except ConfigError as exc:
                k = exc.location.get("step", 0)
                self.wrap(f"step[{k}]", exc, content["step"][k].get("label", k))
        # the full path's frame, unless the grid solves the pair (it never uses it)
        grid_only = method_of(problem.pairs) == "multiscale"
        if check_overlap and not grid_only:
            try:  # the frame's memory estimate, before the frame allocates
                problem.contact_problem().check_frame_memory()
            except ConfigError as exc:
                raise ConfigError(f"{path}: {exc}") from None
            try:
                problem.contact_problem().frames
            except ConfigError as exc:
                sp = specs[exc.location.get("pair", 0)]
                self.wrap(f"{sp.where}.surfaces", ConfigError(one_line(exc.detail)),
                          [sp.pair.surface1, sp.pair.surface2])
        if self.figures_skipped:  # stacklevel: the caller of load_problem
            warnings.warn(FIGURES_SKIPPED, OptionalDependencyWarning, stacklevel=3)
        return problem

    def steps(self, value, names, meshes, surfaces) -> tuple[LoadStep, ...]:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            self.fail("step", "must be an array of tables", value,
                      "write each load step as a [[step]] section")
        out = []
        for k, raw in enumerate(value):
            where = f"step[{k}]"
            t = self.table(where, raw, schema.STEP)
            f = self.fields(where, t, schema.STEP)
            bwhere, bcs = f"{where}.boundary_conditions", t.get("boundary_conditions", {})
            if not isinstance(bcs, dict):
                self.fail(bwhere, f"must be a table of bodies, not {a_type(bcs)}", bcs)
            changes = {}
            for name, regions in bcs.items():
                if name not in names:
                    self.fail(f"{bwhere}.{name}", f"no body of that name (bodies: "
                              f"{', '.join(names)})", name, suggest(name, names))
                i = names.index(name)
                changes[name] = self.boundary_conditions(
                    f"{bwhere}.{name}", regions, meshes[i], surfaces[i])
            rolling = step_rolling(self, f"{where}.rolling", t.get("rolling"))
            out.append(LoadStep(changes, f["increments"], f["label"], rolling))
        return tuple(out)

    def units(self, value: Any) -> dict[str, str]:
        key = schema.ROOT.key("units")
        return self.fields("units", self.table("units", value, key), key)

    def output(self, value: Any, names: list[str], meshes: list) -> OutputOptions:
        """The ``[output]`` table.  Figures need matplotlib: asked for with
        ``figures = true`` they are refused here without it (before the solve);
        on by default they are skipped with an OptionalDependencyWarning."""
        key = schema.OUTPUT
        t = self.table("output", value, key)
        f = self.fields("output", t, key)
        if f["figures"] and not has_matplotlib():
            if "figures" in t:
                self.fail("output.figures", "needs matplotlib, which is not installed", True,
                          f"{PLOT_INSTALL}, or set figures = false")
            f["figures"] = False
            self.figures_skipped = True  # said once the whole file is read
        requests = stress_requests(self, t.get("stresses", []), names, meshes)
        return OutputOptions(**f, stresses=requests)

    def solver(self, value: Any) -> SolverOptions:
        key = schema.SOLVER
        t = self.table("solver", value, key)
        kwargs: dict[str, Any] = {}
        if "linear" in t:
            kwargs["linear"] = self.linear(t["linear"])
        for name, given in t.items():
            if name != "linear":  # the ranges are SolverOptions' own (settings.Key)
                kwargs[name] = self.value(f"solver.{name}", given, key.key(name))
        return SolverOptions(**kwargs)

    def linear(self, value: Any) -> LinearSolverOptions:
        key = schema.LINEAR
        f = self.fields("solver.linear", self.table("solver.linear", value, key), key)
        h = HMatrixOptions(**{k: f.pop(k) for k in schema.HMATRIX_KEYS})
        return LinearSolverOptions(hmatrix=h, **f)

    def body_name(self, i: int, b: dict) -> str:
        where = f"body[{i}]"
        self.table(where, b, schema.BODY)
        name = self.string(f"{where}.name", b["name"])
        if not NAME_PATTERN.match(name):
            self.fail(
                f"{where}.name",
                "must start with a letter and hold only letters, digits, '_' and '-' "
                "(it names the output files)",
                name,
            )
        if name.casefold() in RESERVED_NAMES:
            self.fail(f"{where}.name", f"is reserved for an output file ({name.lower()}.*)", name,
                      "choose another name")
        if len(name) > MAX_NAME_LENGTH:
            self.fail(f"{where}.name", f"is longer than {MAX_NAME_LENGTH} characters (it names "
                      "the output files)", name)
        return name

    def material(self, i: int, b: dict, mesh, fem: bool):
        where = f"body[{i}]"
        if fem:
            return read_materials(self, where, b, mesh)
        if "materials" in b:
            self.fail(f"{where}.materials", "needs a finite-element body (a BEM body has one "
                      "material)", b["materials"], 'add model = "fem", or give material')
        if "material" not in b:
            self.fail(f"{where}.material", "missing required key", b, "add material = ...")
        return read_material(self, f"{where}.material", b["material"], False)

    def boundary_conditions(
        self, where: str, value: Any, mesh: SurfaceMesh, contact: Mapping[str, str]
    ) -> dict[str, list]:
        """The conditions of one body; ``contact``: its contact surfaces,
        each with the field that names it."""
        if not isinstance(value, dict):
            self.fail(where, f"must be a table of regions, not {a_type(value)}", value)
        out: dict[str, list] = {}
        for region, spec in value.items():
            rwhere = f"{where}.{region}"
            if region not in mesh.region_names:
                self.fail(
                    rwhere, f"the mesh has no region {region!r} (its regions: "
                    f"{', '.join(mesh.region_names)})", region,
                    suggest(region, mesh.region_names),
                )
            if region in contact:
                self.fail(
                    rwhere, f"region {region!r} is this body's contact surface ({contact[region]}), "
                    "where the contact decides the tractions", spec, "remove this table",
                )
            out[region] = self.condition(rwhere, spec)
        return out

    def condition(self, where: str, value: Any) -> list:
        t = self.table(where, value, schema.CONDITION)
        if not t:
            self.fail(
                where, "no condition given (a region without conditions is traction free)",
                value, "give displacement, traction, pressure or force, or remove the table",
            )
        items: list = []
        if "pressure" in t:
            if len(t) > 1:
                other = next(k for k in t if k != "pressure")
                self.fail(f"{where}.{other}", "cannot be combined with pressure (a pressure "
                          "prescribes all three traction components)", t[other])
            return [Pressure(self.number(f"{where}.pressure", t["pressure"]))]
        given = {}
        for key in ("displacement", "traction", "force"):
            if key in t:
                given[key] = self.vector(f"{where}.{key}", t[key], free=True)
        keys = list(given)
        for i, a in enumerate(keys):
            for b in keys[i + 1 :]:
                for c in range(3):
                    if given[a][c] is not None and given[b][c] is not None:
                        self.fail(
                            f"{where}.{b}[{c}]",
                            f"component {'xyz'[c]} is prescribed by both {a} and {b}",
                            t[b][c], f'set one of them to "{FREE}"',
                        )
        kinds = {"displacement": Displacement, "traction": Traction, "force": Force}
        for key, v in given.items():
            items.append(kinds[key](v))
        return items

    def distinct(self, names: list[str], fem: list[bool]) -> None:
        """Body names unique (compared as a case-insensitive file system
        would: they name output files) and not another body's output file
        (``<name>_interface``; a finite-element body's ``<name>_volume``)."""
        folded = [n.casefold() for n in names]
        for i, f in enumerate(folded):
            for j in range(i):
                if f == folded[j]:
                    self.fail(f"body[{i}].name", f"duplicate body name (body[{j}] is "
                              f"{names[j]!r}; output file names differ only in case)"
                              if names[i] != names[j] else
                              f"duplicate body name (body[{j}] has it too)", names[i],
                              "give each body its own name")
            for j, g in enumerate(folded):
                if j != i and (f == f"{g}_interface" or (fem[j] and f == f"{g}_volume")):
                    self.fail(f"body[{i}].name", f"clashes with the output files of body "
                              f"{names[j]!r} ({names[i]}.vtu)", names[i], "choose another name")


#: The former name of :class:`ProblemFile`, kept for existing scripts.
Problem = ProblemFile

__all__ = ["ProblemFile", "Problem", "load_problem"]
