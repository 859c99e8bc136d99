"""Property-based fuzzing of the problem-file schema.

A valid two-cube problem (a dict covering every section and most keys) is
mutated at random: a leaf or a whole table replaced by a random value of a
random type (nan, inf, negative, huge, empty string, nested table, array, ...),
a key deleted, an unknown key added, a key renamed.  The result is written as
TOML (by the small writer below: tomllib only reads) and checked with
``bemcontact check``.  Whatever the mutation, the command must either accept
the file (exit 0, nothing on stderr) or reject it with exit 2 and exactly one
line ``bemcontact: error: <file>: ...`` on stderr; no exception may escape.
"""

from __future__ import annotations

import contextlib
import copy
import io
import math
import re
import traceback

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from bemcontact.cli import main
from bemcontact.study.points import toml_text

# Two one-element-per-face cubes: meshing, checking and building the contact
# frame take a few milliseconds.  Every section of docs/problem-file.md appears.
BASE: dict = {
    "title": "fuzz",
    "units": {"length": "mm", "force": "N", "stress": "MPa"},
    "solver": {
        "tolerance": 1e-10, "max_iterations": 30, "load_steps": 1, "penalty": 1.0,
        "line_search_sigma": 1e-4, "min_step": 1e-6, "watchdog": 5, "threads": 1,
    },
    "body": [
        {
            "name": "lower",
            "mesh": {"box": {"lower": [0, 0, 0], "upper": [2, 2, 2], "divisions": 1,
                             "element_type": "quad4", "grading": 1.0}},
            "material": {"youngs_modulus": 1e4, "poisson_ratio": 0.3},
            "boundary_conditions": {"zmin": {"displacement": [0, 0, 0]}},
        },
        {
            "name": "upper",
            "mesh": {"box": {"lower": [0, 0, 2], "upper": [2, 2, 4], "divisions": [1, 1, 1],
                             "grading": [1, 1, 1]}},
            "material": {"youngs_modulus": 2e4, "poisson_ratio": 0.25},
            "boundary_conditions": {
                "zmax": {"displacement": ["free", 0, -0.04], "force": [0, "free", "free"]},
                "xmax": {"pressure": 0.5},
                "ymax": {"traction": [0, 0.1, "free"]},
            },
        },
    ],
    "contact": {
        "bodies": ["lower", "upper"], "surfaces": ["zmax", "zmin"], "friction_coefficient": 0.1,
        "frame": "mortar", "search_distance": 0.5, "frame_on": "coarser", "penalty": 1.0,
    },
    "output": {"vtu": True, "csv": True, "figures": False, "steps": "last"},
    "step": [
        {"label": "P"},
        {"label": "Q", "increments": 2,
         "boundary_conditions": {"upper": {"zmax": {"displacement": ["free", 0, -0.04],
                                                    "force": [1, "free", "free"]}}}},
    ],
}

# ----------------------------------------------------------------------------- TOML writer


# the package's own writer of problem files (bemcontact sweep writes each point with it)
dumps = toml_text


def test_writer_round_trips():
    import tomllib

    doc = copy.deepcopy(BASE)
    doc["odd"] = {"": [1.5, -0.0, 1e300, 5e-324, True, "a\"b\\c\n\x7f\u00e9\U0001f600"],
                  "big": 2**64, "t": {"u": []}}
    assert tomllib.loads(dumps(doc)) == doc
    nan = tomllib.loads(dumps({"x": [math.nan, math.inf, -math.inf]}))["x"]
    assert math.isnan(nan[0]) and nan[1:] == [math.inf, -math.inf]


# ----------------------------------------------------------------------------- mutations

KNOWN_KEYS = [
    "title", "units", "length", "force", "stress", "solver", "tolerance", "max_iterations",
    "load_steps", "penalty", "line_search_sigma", "min_step", "watchdog", "threads", "progress",
    "body", "name", "mesh", "box", "file", "element_type", "lower", "upper", "divisions",
    "grading", "material", "youngs_modulus", "poisson_ratio", "boundary_conditions",
    "displacement", "traction", "pressure", "contact", "bodies", "surfaces",
    "friction_coefficient", "frame", "search_distance", "frame_on", "step", "label",
    "increments", "output", "vtu", "csv", "figures", "steps", "cap", "punch", "graded_box",
    "xmin", "xmax", "ymin", "ymax", "zmin", "zmax",
]
WORDS = [
    "", " ", "free", "fre", "FREE", "zmax", "zmin", "xmin", "lower", "upper", "frame", "summary",
    "quad4", "quad9", "tri6", "mortar", "collocation", "coarser", "../x", "a b", "mesh.msh",
    "nan", "1e4", "\u00e9", "\x00", "all", "last",
]
# Integers: small ones, and extremes that must be rejected.  Integers between
# 5 and 2**62 are left out on purpose: as box divisions they are valid input
# that builds a mesh of up to 6 * (2**62)**2 elements (there is no size limit),
# which would hang or exhaust the memory of the test run instead of failing.
INTEGERS = st.integers(-3, 4) | st.sampled_from(
    [2**62, 2**63 - 1, -(2**63), 2**64, 10**30, -(10**30), 10**400]
)
FLOATS = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [0.0, -0.0, 0.5, -1.0, 1.5, 1e-320, 1e308, -1e308, 2.5]
)
# numbers twice: most fields are numbers
SCALARS = st.one_of(
    INTEGERS, FLOATS, INTEGERS, FLOATS, st.booleans(), st.sampled_from(WORDS), st.text(max_size=8),
)
KEYS = st.sampled_from(KNOWN_KEYS) | st.text(min_size=0, max_size=6)
VALUES = st.recursive(
    SCALARS,
    lambda children: st.lists(children, max_size=4)
    | st.dictionaries(KEYS, children, max_size=3),
    max_leaves=6,
)


def _paths(node, prefix=()):
    """Paths (tuples of keys and indices) to every value below ``node``."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield (*prefix, k)
            yield from _paths(v, (*prefix, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield (*prefix, i)
            yield from _paths(v, (*prefix, i))


def _get(doc, path):
    for p in path:
        doc = doc[p]
    return doc


def _typo(key: str, draw, rnd) -> str:
    if not key:
        return draw(KEYS)
    how = rnd.choice(["drop", "double", "swap", "case", "other"])
    i = rnd.randrange(len(key))
    if how == "drop":
        return key[:i] + key[i + 1 :]
    if how == "double":
        return key[:i] + key[i] + key[i:]
    if how == "swap" and len(key) > 1:
        j = min(i + 1, len(key) - 1)
        chars = list(key)
        chars[i], chars[j] = chars[j], chars[i]
        return "".join(chars)
    if how == "case":
        return key.upper()
    return draw(KEYS)


def mutate(doc: dict, draw, rnd) -> str:
    """Apply one random mutation to ``doc`` in place; returns what it did.
    Where (``rnd``, uniform over the document) and what (``draw``, values
    of every type and their extremes)."""
    kind = rnd.choice(["replace", "replace", "replace", "delete", "add", "rename"])
    paths = list(_paths(doc))
    if kind == "add":
        tables = [()] + [p for p in paths if isinstance(_get(doc, p), dict)]
        where = rnd.choice(tables)
        key, value = draw(KEYS), draw(VALUES)
        _get(doc, where)[key] = value
        return f"add {where}[{key!r}] = {value!r}"
    if not paths:
        doc["x"] = draw(VALUES)
        return "add x to an empty file"
    if kind == "rename":
        keyed = [p for p in paths if isinstance(p[-1], str)]
        path = rnd.choice(keyed)
        parent = _get(doc, path[:-1])
        new = _typo(path[-1], draw, rnd)
        items = [(new if k == path[-1] else k, v) for k, v in parent.items()]
        parent.clear()
        parent.update(items)  # same position; a clash with an existing key drops one
        return f"rename {path} -> {new!r}"
    path = rnd.choice(paths)
    parent = _get(doc, path[:-1])
    if kind == "delete":
        del parent[path[-1]]
        return f"delete {path}"
    value = draw(VALUES)
    parent[path[-1]] = value
    return f"replace {path} = {value!r}"


# ----------------------------------------------------------------------------- the property


def _check(path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["check", str(path)])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


def test_base_problem_is_valid(workdir):
    path = workdir / "base.toml"
    path.write_text(dumps(BASE), encoding="utf-8")
    code, out, err = _check(path)
    assert (code, err) == (0, ""), err
    assert "valid" in out


@settings(
    max_examples=1000,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
@given(data=st.data())
def test_mutated_problem_is_accepted_or_rejected_in_one_line(workdir, data):
    doc = copy.deepcopy(BASE)
    rnd = data.draw(st.randoms(use_true_random=False), label="where")
    n = rnd.choice([1, 1, 1, 2, 3])
    done = [mutate(doc, data.draw, rnd) for _ in range(n)]
    text = dumps(doc)
    path = workdir / "mutated.toml"
    path.write_text(text, encoding="utf-8")
    where = "mutations:\n  " + "\n  ".join(done) + f"\nproblem file:\n{text}"
    try:
        code, out, err = _check(path)
    except BaseException as exc:  # noqa: BLE001
        raise AssertionError(
            f"bemcontact check raised {type(exc).__name__}: {exc}\n{where}\n"
            + "".join(traceback.format_exception(exc)[-4:])
        ) from None
    assert "Traceback" not in out + err, where
    # statistics (pytest --hypothesis-show-statistics): which field rejected the file
    field = re.sub(r"\[[0-9]+\]", "[]", err.split(": ")[3]) if err.count(": ") > 3 else ""
    event(f"exit {code}: {field}" if field else f"exit {code}")
    if code == 0:
        assert err == "", f"exit 0 with stderr {err!r}\n{where}"
        return
    lines = err.splitlines()
    assert code == 2, f"exit code {code}, stderr {err!r}\n{where}"
    assert len(lines) == 1 and err.endswith("\n"), f"stderr {err!r}\n{where}"
    assert lines[0].startswith(f"bemcontact: error: {path}: "), f"stderr {err!r}\n{where}"
    assert out == "", f"stdout {out!r}\n{where}"
