"""The problem-file schema: every key a problem file may hold, in one place.

Each key is a :class:`Key` with its type, whether it is required, its default,
the allowed range or choices and one line of documentation.  Keys that set a
field of an options dataclass (``SolverOptions``, ``LinearSolverOptions``,
``HMatrixOptions``, ``ContactPair``, ``LoadStep``, ``OutputOptions``,
``LinearElastic``) are that field's own :class:`~bemcontact.settings.Key`
(:func:`~bemcontact.settings.keys_of`), so a range or default is written once.
The reader (:mod:`bemcontact.problemfile.reader`) takes the allowed and
required keys of every table, the numeric ranges and the choices from here, so
a key cannot be accepted without being documented; ``docs/problem-file-reference.md`` is
generated from this module by :func:`reference_markdown` and a test checks
that the page is up to date.

Types (:attr:`Key.type`):

``string``, ``boolean``, ``number`` (int or float, finite), ``integer``,
``vector`` (3 numbers), ``numbers`` (an array of numbers of any length),
``matrix`` (:attr:`Key.length` rows of as many numbers), ``components`` (3 entries, each a number or
``"free"``), ``number-or-vector`` and ``integer-or-vector`` (one value for all
three directions or 3 values), ``number-or-pair`` and ``integer-or-pair`` (one
value for both in-plane directions or 2 values), ``strings`` (an array of strings of fixed
length), ``table`` (fixed keys: :attr:`Key.keys`), ``tables`` (an array of
such tables, ``[[name]]``), ``map`` (a table whose keys are names chosen by the
user — regions, bodies — each holding :attr:`Key.entry`).
"""

from __future__ import annotations

from ..bem.material import LinearElastic
from ..contact.options import CONDENSATION_LINEAR, SolverOptions
from ..contact.rolling import Rolling
from ..contact.pair import FRAME_RULES, ContactPair
from ..contact.history import LoadStep
from ..fem.loads import BodyForce
from ..linalg.options import HMatrixOptions, LinearSolverOptions
from ..mesh.element import ELEMENT_TYPES

#: The volume element types of a finite-element body's mesh.
FEM_ELEMENT_TYPES = ("tet4", "tet10", "hex8", "hex27")
from ..output.write import OutputOptions
from ..stresses.probes import PROBE_KEYS
from ..settings import LARGEST, NO_DEFAULT, SMALLEST, Key, keys_of



def _grading_keys(order_default: int, order_doc: str) -> tuple[Key, ...]:
    return (
        Key("fine_size", "number", "element size (length) in the refined zone", True,
            lo=0, lo_open=True),
        Key("coarse_size", "number", "largest element size (length), >= fine_size", True,
            lo=0, lo_open=True),
        Key("growth", "number", "size gradient away from the refined zone (size added per "
            "unit distance)", default=0.3, lo=0, lo_open=True),
        Key("order", "integer", order_doc, default=order_default, lo=1, hi=2),
    )


BOX = Key(
    "box", "table", "a box meshed by bemcontact (structured quadrilaterals or triangles)",
    section="body.mesh.box",
    notes="Regions `xmin`, `xmax`, `ymin`, `ymax`, `zmin`, `zmax` (the faces).",
    keys=(
        Key("lower", "vector", "lower corner [x, y, z] (length)", True),
        Key("upper", "vector", "upper corner (length), > lower in every component", True),
        Key("divisions", "integer-or-vector", "elements per edge, or [nx, ny, nz]", True, lo=1),
        Key("element_type", "string", "element type (a finite-element body: `tet4`, `tet10`, "
            "`hex8`, `hex27`)", default="quad4", default_text='`"quad4"` (a finite-element '
            'body: `"hex8"`)', choices=ELEMENT_TYPES + FEM_ELEMENT_TYPES),
        Key("grading", "number-or-vector", "ratio of the last to the first element size along "
            "each direction (1: uniform)", default=1.0, lo=0, lo_open=True),
    ),
)

CAP = Key(
    "cap", "table", "a solid spherical cap or hemisphere (a Hertz indenter) meshed by gmsh "
    "with curved triangles graded toward its apex",
    section="body.mesh.cap",
    notes="Regions `contact` (the curved surface) and `base` (the flat disc). Needs the "
    "`gmsh` Python package. Example: `cap = { radius = 10, height = 10, fine_size = 0.1, "
    "coarse_size = 2.5, fine_radius = 0.8 }` is a hemisphere R = 10 resting on z = 0 with "
    "about ten elements across a contact diameter of 1.",
    keys=(
        Key("radius", "number", "sphere radius R (length)", True, lo=0, lo_open=True),
        Key("height", "number", "apex to flat base (length), 0 < height < 2R; = R is a "
            "hemisphere", True, lo=0, lo_open=True),
        Key("fine_radius", "number", "radius of the uniformly fine zone around the apex "
            "(length); take 1.5 to 2 times the expected contact radius", True, lo=0),
        Key("apex", "vector", "the point of the sphere that touches first", default=[0, 0, 0]),
        Key("axis", "integer", "+1: the body lies above its apex (pressing down); -1: below",
            default=1, choices=("1", "-1")),
        *_grading_keys(2, "1: flat 3-node triangles; 2: curved 6-node triangles"),
    ),
)

PUNCH = Key(
    "punch", "table", "a flat-ended cylindrical punch (Boussinesq) meshed by gmsh, graded "
    "toward the rim of its flat end",
    section="body.mesh.punch",
    notes="Regions `contact` (the flat end), `side`, `top`. Needs the `gmsh` Python package.",
    keys=(
        Key("radius", "number", "cylinder radius (length)", True, lo=0, lo_open=True),
        Key("height", "number", "cylinder height (length)", True, lo=0, lo_open=True),
        Key("center_size", "number", "element size at the centre of the flat end (length), "
            "between fine_size and coarse_size", default_text="2 × fine_size", lo=0,
            lo_open=True),
        Key("base_center", "vector", "centre of the flat end", default=[0, 0, 0]),
        Key("axis", "integer", "+1: the body lies above its flat end; -1: below", default=1,
            choices=("1", "-1")),
        *_grading_keys(2, "1: flat 3-node triangles; 2: curved 6-node triangles"),
    ),
)

BALL = Key(
    "ball", "table", "a solid ball meshed by gmsh, graded toward its lowest and highest "
    "points and mirror symmetric in its equator plane (a ball between two bodies)",
    section="body.mesh.ball",
    notes="Regions `bottom` and `top` (the two caps, the contact surfaces) and `band` (within "
    "`band` R of the equator: where a cage or support holds the ball). Needs the `gmsh` "
    "Python package.",
    keys=(
        Key("radius", "number", "ball radius R (length)", True, lo=0, lo_open=True),
        Key("fine_radius", "number", "radius of the uniformly fine zone around each pole "
            "(length); take 1.5 to 2 times the expected contact radius", True, lo=0),
        Key("lowest", "vector", "the ball's lowest point", default=[0, 0, 0]),
        Key("band", "number", "half-height of the `band` region over R", default=0.3, lo=0,
            lo_open=True, hi=0.8, hi_open=True),
        *_grading_keys(1, "1: flat 3-node triangles; 2: curved 6-node triangles"),
    ),
)

GRADED_BOX = Key(
    "graded_box", "table", "a box meshed by gmsh with elements graded toward a point of one "
    "of its faces (the flat counter-body of a Hertz contact or a punch)",
    section="body.mesh.graded_box",
    notes="Regions `xmin`, `xmax`, `ymin`, `ymax`, `zmin`, `zmax`. Needs the `gmsh` Python "
    "package.",
    keys=(
        Key("lower", "vector", "lower corner (length)", True),
        Key("upper", "vector", "upper corner (length), > lower in every component", True),
        Key("focus", "vector", "the point (on a face of the box) the mesh is refined toward",
            True),
        Key("fine_radius", "number", "radius of the uniformly fine zone around focus (length)",
            True, lo=0),
        Key("quads", "boolean", "recombine the triangles into quadrilaterals", default=False),
        Key("seed", "integer", "perturbs gmsh's mesher (two seeds give non-matching meshes)",
            default=0, lo=0),
        Key("layers", "numbers", "a finite-element body: thicknesses (length) of bonded "
            "layers from the face holding focus inward, volume regions `layer1`, `layer2`, "
            "..., then `substrate`", default=[], lo=0, lo_open=True),
        *_grading_keys(1, "1: linear elements; 2: quadratic (tri6 or quad9)"),
    ),
)

MESH = Key(
    "mesh", "table", "the body's closed surface mesh (a finite-element body: its volume "
    "mesh): exactly one of `box`, `file`, `cap`, `punch`, `graded_box`, `ball`", True,
    section="body.mesh",
    notes="The surface must be closed and its normals point outward (checked while "
    "loading; `bemcontact mesh-info MESH` shows what is wrong with a mesh file). Mesh "
    "files are read by meshio: regions are the gmsh physical surface groups by name "
    "(`group<tag>` when unnamed), or `region0`, `region1`, ... for files written by "
    "bemcontact. A finite-element body (`model = \"fem\"`): `box` is a structured mesh "
    "of hexahedra (`hex8`, `hex27`) or tetrahedra (`tet4`, `tet10`); `cap`, `punch`, "
    "`graded_box` and `ball` are the solids meshed with tetrahedra by gmsh under the same "
    "grading (straight-sided: a curved surface is faceted at the element size; `order` 2 "
    "puts quadratic elements on them), with the same boundary regions; a `file` holds "
    "tetrahedra or hexahedra (a gmsh file's physical surface groups are its boundary "
    "regions, its physical volume groups its volume regions; without volume groups the "
    "volume region is `body`).",
    keys=(
        BOX,
        Key("file", "string", "a mesh file any meshio reader takes, relative to the problem "
            "file's directory"),
        Key("element_type", "string", "with `file`: which element type to use when the file "
            "holds several; a finite-element body: the elements on the file's linear cells, "
            "`tet4`/`hex8` (linear) or `tet10`/`hex27` (quadratic)",
            choices=ELEMENT_TYPES + FEM_ELEMENT_TYPES,
            default_text="the file's only surface type (a finite-element body: linear)"),
        CAP,
        PUNCH,
        GRADED_BOX,
        BALL,
    ),
)
#: The mesh generators (one of them, or ``file``, per body).
MESH_SOURCES = ("box", "file", "cap", "punch", "graded_box", "ball")

MATERIAL = Key(
    "material", "table", "the body's linear elastic material: isotropic; a finite-element "
    "body's may be orthotropic or a full 6 × 6 stiffness", section="body.material",
    default_text="**required** (a finite-element body: `material` or `materials`)",
    notes="Give `youngs_modulus` and `poisson_ratio` (isotropic) or, for a finite-element "
    "body, `youngs_moduli`, `poisson_ratios` and `shear_moduli` (orthotropic) or "
    "`stiffness`, with the material axes `axis1` and `axis2`. Conventions: Voigt order "
    "(11, 22, 33, 23, 13, 12) with engineering shear strains; ν_ij is the contraction along j "
    "under a stress along i (ν_ij / E_i = ν_ji / E_j); axis 3 = axis1 × axis2 (axis2 is "
    "made orthogonal to axis1). A stiffness that is not positive definite is refused.",
    keys=(
        *keys_of(LinearElastic, youngs_modulus={"required": False},
                 poisson_ratio={"required": False}),
        Key("youngs_moduli", "vector", "orthotropic: [E1, E2, E3] along the material axes "
            "(stress)"),
        Key("poisson_ratios", "vector", "orthotropic: [ν12, ν13, ν23]"),
        Key("shear_moduli", "vector", "orthotropic: [G12, G13, G23] (stress)"),
        Key("stiffness", "matrix", "anisotropic: the 6 × 6 stiffness in the material axes "
            "(stress), symmetric positive definite", length=6),
        Key("axis1", "vector", "the material's axis 1 in global coordinates", default=[1, 0, 0]),
        Key("axis2", "vector", "the material's axis 2 in global coordinates", default=[0, 1, 0]),
        Key("density", "number", "mass per volume, in units consistent with the rest (mm, N, "
            "MPa, s: tonnes per mm³, steel 7.85e-9); needed by a finite-element body's "
            "`body_force`", lo=0),
    ),
)

MATERIALS = Key(
    "materials", "map", "a finite-element body of several materials: one `material` table "
    "per volume region of its mesh (e.g. `layer1` and `substrate` of a graded_box with "
    "layers), instead of `material`", default={}, section="body.materials",
    notes="Every volume region needs a material; the regions are bonded (one mesh).",
    entry=MATERIAL,
)

CONDITION = Key(
    "<region>", "table", "the conditions of one region of the mesh (regions not listed are "
    "traction free)",
    section="body.boundary_conditions.<region>",
    notes="`displacement`, `traction` and `force` may be combined as long as each component "
    "is prescribed at most once; `pressure` sets all three traction components and stands "
    "alone. A component prescribed by none is traction free. The region must exist in the "
    "body's mesh and must not be the body's contact surface (there the contact decides the "
    "tractions). An empty table is an error.",
    keys=(
        Key("displacement", "components", "prescribed global x, y, z displacement (length)"),
        Key("traction", "components", "prescribed global traction (stress): force per area the "
            "surroundings exert on the body"),
        Key("pressure", "number", "normal pressure (stress), > 0 pushes on the body: t = -p n"),
        Key("force", "components", "force control: the region moves as a rigid platen in these "
            "components and the resultant of its tractions is this force (force); its "
            "translation is reported in summary.json, `control_displacements`"),
    ),
)

BOUNDARY_CONDITIONS = Key(
    "boundary_conditions", "map", "one table per region of the mesh", default={},
    section="body.boundary_conditions", entry=CONDITION,
)

BODY_FORCE = Key(
    "body_force", "table", "a finite-element body's body force: its weight in uniform gravity "
    "and the centrifugal load of a steady rotation, ρ (g + |ω|² r − (ω · r) ω), r from "
    "`center`", section="body.body_force",
    notes="Each volume region's material needs its `density`. The body is at rest in the frame "
    "that rotates with it; the load is on in every load step (ramped with the bodies' "
    "conditions over the first). A BEM body has none (its volume is not meshed): give it "
    '`model = "fem"`.',
    keys=keys_of(BodyForce),
)

BODY = Key(
    "body", "tables", "the bodies, as two or more `[[body]]` sections (an assembly: every "
    "body in a contact pair)", True, section="body",
    keys=(
        Key("name", "string", "a letter, then letters, digits, `_`, `-`; unique; not `frame` or "
            "`summary` (it names the output files)", True),
        Key("model", "string", "how the body is modelled: `bem` (boundary elements on its "
            "surface mesh) or `fem` (finite elements on a volume mesh; needs the `fem` extra: "
            "several materials, anisotropy)", default="bem", choices=("bem", "fem")),
        MESH,
        MATERIAL,
        MATERIALS,
        BOUNDARY_CONDITIONS,
        BODY_FORCE,
    ),
)

CONTACT = Key(
    "contact", "table", "the contact pair: one `[contact]` table, or one `[[contact]]` table "
    "per pair (an assembly: a body may be in several pairs, on different surfaces or on one "
    "surface against several bodies)", True, section="contact",
    keys=(
        Key("bodies", "strings", "body 1 and body 2: the contact normal points from body 1 into "
            "body 2 and `normal_force` is the force body 1 exerts on body 2; needed with more "
            "than two bodies", length=2, default_text="the `[[body]]` order"),
        Key("surfaces", "strings", "the contact surface (a region) of body 1, then of body 2",
            True, length=2),
        *keys_of(ContactPair, "friction_coefficient", "frame", "search_distance",
                 "relative_displacement"),
        Key("frame_on", "string", "where the frame lies (its normals define gap and slip): "
            "`auto` (on the flat surface if exactly one is flat, between two curved ones, on "
            "the coarser of two flat ones), `between` the two surfaces (midway, normals "
            "bisecting theirs), `coarser` or a body name (on that surface)", default="auto"),
        *keys_of(ContactPair, "penalty", "method", "grid_size"),
    ),
)

LINEAR = Key(
    "linear", "table", "how each body's BEM system is stored and solved for the contact "
    "condensation (the fields of `SolverOptions.linear`: `bemcontact.LinearSolverOptions` "
    "and its `HMatrixOptions`)", default={},
    section="solver.linear",
    notes="Compressed operators (H-matrices built by adaptive cross approximation, "
    "factored by an H-LU) need memory and time close to linear in the number of nodes; "
    "the dense path is faster below a few thousand nodes per body (docs/benchmarks.md).",
    keys=(
        *keys_of(LinearSolverOptions, "method", "dense_max_nodes", defaults=CONDENSATION_LINEAR),
        *keys_of(HMatrixOptions, "eps", "eta", "leaf_size", "storage",
                 defaults=CONDENSATION_LINEAR.hmatrix),
        *keys_of(LinearSolverOptions, "accuracy", "check_nodes", defaults=CONDENSATION_LINEAR),
    ),
)

# the keys of [solver.linear] that are HMatrixOptions fields (the rest are
# LinearSolverOptions')
HMATRIX_KEYS = ("eps", "eta", "leaf_size", "storage")

SOLVER = Key(
    "solver", "table", "Newton settings (the fields of `bemcontact.SolverOptions`)",
    default={}, section="solver",
    keys=(
        *keys_of(SolverOptions, "tolerance", "max_iterations", "load_steps", "penalty",
                 "line_search_sigma", "min_step", "watchdog", "newton_steps", "predictor",
                 "closing", "threads"),
        LINEAR,
    ),
)

STEP = Key(
    "step", "tables", "the loading history, as `[[step]]` sections in order", default=[],
    section="step",
    notes="The history starts unloaded; the first step applies the bodies' own conditions "
    "updated by its `boundary_conditions`. A step may change values but not the kind "
    "(displacement, traction, force) of a component: give a component its later kind from "
    "the start (e.g. `force = [0, \"free\", \"free\"]`). Without `[[step]]` sections the "
    "bodies' conditions are applied in `solver.load_steps` increments.",
    keys=(
        *keys_of(LoadStep, "label", "increments"),
        Key("rolling", "table", "the step rolls the bodies: rolling direction, Kalker's "
            "creepages and spin, steady or transient", default=None, section="step.rolling",
            notes="Conventions (docs/theory.md, \"Rolling\"): the contact moves over the "
            "bodies in `direction` (its leading edge is ahead); the creepages ξ (along it), η "
            "(across it, along n × direction, n the contact normal from the first body into "
            "the second) and the spin φ (about n) are the rigid velocity of the second body's "
            "surface relative to the first's divided by the rolling speed, so the rigid slip "
            "per rolled distance is (ξ − φ y, η + φ x). A tangential component the supports "
            "control by force is solved for: its creepage (steady) or its rigid shift "
            "(transient) carries the force. `summary.json` gets per step `rolling`: "
            "`creep_force` [F_x, F_y] on the second body in the rolling frame, "
            "`creep_force_ratio` (over μ F_n), `spin_moment`, `frictional_power` (with "
            "`speed`) and `frictional_work_per_distance`, `adhesion_area`, `slip_area` and the "
            "creepages in effect (an assembly's: the first pair's, and each pair's under "
            "`pairs`). Both paths roll: the contact grid (its rolling direction along "
            "one of its axes) and the full path (an upwind interpolation on the frame nodes).",
            keys=(
                Key("direction", "vector", "the rolling direction (tangent to the contact)",
                    True),
                Key("creepage", "pair", "[ξ, η], Kalker's longitudinal and lateral creepages "
                    "(dimensionless)", default=[0.0, 0.0]),
                *keys_of(Rolling, "spin", "mode", "distance", "speed"),
            )),
        Key("boundary_conditions", "map", "`<body>.<region>` condition tables (as in "
            "`body.boundary_conditions`) that change at this step; all others keep their "
            "values", default={},
            entry=Key("<body>", "map", "the body's changed regions", entry=CONDITION)),
    ),
)

OUTPUT = Key(
    "output", "table", "which result files `bemcontact run` writes", default={},
    section="output",
    notes="`summary.json` is always written. With `steps = \"all\"` each VTU file has one "
    "version per load step (`<name>_<k>.vtu`, k = 1, 2, ...) and a `<name>.pvd` collection "
    "that ParaView opens as a time series (time = step number); the unnumbered `<name>.vtu` "
    "is always the final state.",
    keys=(
        *keys_of(OutputOptions),
        Key("stresses", "tables", "stresses inside a body on a line, a plane or a box of "
            "points, as `[[output.stresses]]` sections", default=(), section="output.stresses",
            notes="Each section names a `body` and exactly one of `line`, `plane`, `box`; its "
            "files are `stresses_<body>_<label>.csv` (columns x, y, z, sxx, syy, szz, sxy, syz, "
            "sxz, von_mises, tresca; stress units of the problem, tension positive, "
            "compression negative; Tresca is the maximum shear stress (σ1 − σ3)/2), `.vtu` "
            "and `.png`, and `summary.json` gets the maximum von Mises and Tresca stresses "
            "and their points, per body and per load step, under `stresses`. Points must lie "
            "inside the body. Without sections, `default_stresses` gives a depth profile "
            "under the peak pressure (label `profile`) and the two planes through it "
            "(`section1` along the tangential force, `section2` across it), from 0.02 to 3 "
            "contact radii deep, in each body at least 8 contact radii across.",
            keys=(
                Key("body", "string", "the body the points lie in", True),
                Key("label", "string", "names the files: letters, digits, `_`, `-`",
                    default_text="the section's number, 1, 2, ..."),
                *PROBE_KEYS.values(),
            )),
    ),
)

SWEEP = Key(
    "sweep", "table", "a parameter study for `bemcontact sweep` (`run` and `check` ignore it)",
    default={}, section="sweep",
    notes='Keys are dotted paths as in error messages, quoted: `"contact.friction_coefficient" '
    '= [0.1, 0.2]`, `"body[1].boundary_conditions.zmax.displacement[2]" = [-0.02, -0.04]`. '
    "A sweep varies values: a point that changes the kind of a boundary condition "
    "(displacement, traction, force) is refused. `bemcontact sweep --vary` replaces this table.",
    keys=(
        Key("vary", "map", '`"<key>" = [values]`: every combination of the values is a point '
            "(full factorial)", default={}),
        Key("points", "tables", "instead of `vary`, the points one by one: each a table of "
            '`"<key>" = value`', default=[]),
    ),
)

ROOT = Key(
    "", "table", "a problem file", section="top level",
    keys=(
        Key("title", "string", "free text, echoed into summary.json", default=""),
        Key("units", "table", "labels for the printed summary and figures: known units, "
            "checked for consistency (stress = force / length²), never converted",
            default={}, section="units",
            keys=tuple(Key(n, "string", f"{n} unit label, e.g. \"{e}\"")
                       for n, e in (("length", "mm"), ("force", "N"), ("stress", "MPa")))),
        SOLVER,
        BODY,
        CONTACT,
        STEP,
        OUTPUT,
        SWEEP,
    ),
)


# ----------------------------------------------------------------------- docs


def _type_text(k: Key) -> str:
    base = {
        "string": "string",
        "boolean": "boolean",
        "number": "number",
        "integer": "integer",
        "vector": "[x, y, z] numbers",
        "components": "[x, y, z], each a number or `\"free\"`",
        "number-or-vector": "number or [x, y, z]",
        "number-or-pair": "number or [u, v]",
        "pair": "[u, v] numbers",
        "integer-or-pair": "integer or [u, v]",
        "integer-or-vector": "integer or [x, y, z]",
        "strings": f"{k.length} strings",
        "numbers": "array of numbers",
        "matrix": f"{k.length} × {k.length} numbers (rows)",
        "table": "table",
        "tables": f"{k.length or 'any number of'} `[[{k.name}]]` tables",
        "map": "table of named tables",
    }[k.type]
    cond = []
    if k.lo is not None:
        cond.append(f"{'>' if k.lo_open else '>='} {k.lo:g}")
    if k.hi is not None:
        cond.append(f"{'<' if k.hi_open else '<='} {k.hi:g}")
    if k.choices:
        cond.append("one of " + ", ".join(f"`{c}`" for c in k.choices))
    return base + (f", {' and '.join(cond)}" if cond else "")


def _default_text(k: Key) -> str:
    if k.required:
        return "**required**"
    if k.default_text:
        return k.default_text
    if k.default is NO_DEFAULT:
        return "none"
    d = k.default
    if isinstance(d, bool):
        return f"`{str(d).lower()}`"
    if isinstance(d, str):
        return f'`"{d}"`'
    if isinstance(d, float) and d and abs(d) < 1e-3:
        return f"`{d:.6g}`"
    if isinstance(d, dict):
        return "empty"
    if isinstance(d, (list, tuple)) and not d:
        return "none"
    return f"`{d}`"


def _anchor(section: str) -> str:
    return "".join(c for c in section.lower().replace(" ", "-") if c.isalnum() or c in "-_")


def _sections(k: Key, out: list[Key]) -> None:
    if k.section and k not in out:
        out.append(k)
    for c in k.keys:
        _sections(c, out)
    if k.entry is not None:
        _sections(k.entry, out)


def reference_markdown() -> str:
    """The problem-file reference page (``docs/problem-file-reference.md``)."""
    lines = [
        "# Problem-file reference",
        "",
        "<!-- Generated from src/bemcontact/problemfile/schema.py by",
        "     python -c 'import bemcontact.problemfile.schema as s; print(s.reference_markdown(), end=\"\")'",
        "     > docs/problem-file-reference.md   (do not edit; a test checks it is current) -->",
        "",
        "Every key a problem file may hold. Unknown keys are errors (with a suggestion when",
        "one is close); integers are accepted where a number is expected, not the reverse;",
        "booleans are never numbers; `nan` and `inf` are rejected, and so is any number other",
        f"than 0 whose magnitude is outside {SMALLEST:g} to {LARGEST:g}. Units are those of the",
        "problem's one consistent set (docs/theory.md). The narrative guide, with examples,",
        "is [Problem files and the command line](problem-file.md).",
        "",
    ]
    sections: list[Key] = []
    _sections(ROOT, sections)
    for s in sections:
        title = "Top level" if s is ROOT else f"`{s.section}`"
        lines += [f"## {title}", "", s.doc[0].upper() + s.doc[1:] + ".", ""]
        children = s.keys if s.keys else ((s.entry,) if s.entry is not None else ())
        if children:
            lines += ["| key | type | default | meaning |", "|---|---|---|---|"]
            for c in children:
                name = f"`{c.name}`"
                if c.section and c is not s:
                    name = f"[`{c.name}`](#{_anchor(c.section)})"
                meaning = c.doc.replace("|", "\\|")
                lines.append(f"| {name} | {_type_text(c)} | {_default_text(c)} | {meaning} |")
            lines.append("")
        if s.notes:
            lines += [s.notes, ""]
    return "\n".join(lines).rstrip() + "\n"


__all__ = ["Key", "ROOT", "reference_markdown", "MESH_SOURCES", "ELEMENT_TYPES", "FRAME_RULES"]
