"""The package's layout (docs/architecture.md): imports point one way.

Every import of a bemcontact module, at module level or inside a function,
is read from the source with ``ast``.  The packages must follow the layering
of docs/architecture.md (a package imports only packages below it), no two
modules may import each other through any chain, and no module may exceed
600 lines (the size at which a module stops showing one concept).
"""

from __future__ import annotations

import ast
import pathlib

import pytest

SRC = pathlib.Path(__file__).resolve().parents[1] / "src" / "bemcontact"

#: docs/architecture.md from the top down; a unit may import only units of a
#: lower layer or its own package.
LAYERS = [
    {"__main__"},
    {"cli", "__init__"},
    {"study"},
    {"problemfile"},
    {"validation", "output", "bench"},
    {"stresses"},
    {"multiscale"},
    {"contact", "fem"},
    {"bem"},
    {"linalg", "halfspace"},
    {"mesh"},
    {"settings", "progress", "inputs"},
    {"errors", "_native", "_version"},
]
LEVEL = {unit: i for i, layer in enumerate(LAYERS) for unit in layer}


def _module_name(path: pathlib.Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path: pathlib.Path) -> set[str]:
    """Full names of the bemcontact modules ``path`` imports (anywhere in it)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if not mod.startswith("bemcontact"):
                continue
            for alias in node.names:  # "from . import law" imports a module
                sub = f"{mod}.{alias.name}"
                out.add(sub if _exists(sub) else mod)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("bemcontact")}
    out.discard(name)
    return {m for m in out if _exists(m)}


def _exists(module: str) -> bool:
    p = SRC.parent.joinpath(*module.split("."))
    return p.with_suffix(".py").is_file() or (p / "__init__.py").is_file()


def _unit(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


MODULES = {_module_name(p): p for p in SRC.rglob("*.py")}
GRAPH = {m: _imports(p) for m, p in MODULES.items()}


def test_every_unit_has_a_layer():
    units = {_unit(m) for m in MODULES}
    assert units <= set(LEVEL), sorted(units - set(LEVEL))


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_point_down(module):
    unit = _unit(module)
    for target in sorted(GRAPH[module]):
        other = _unit(target)
        if other == unit:
            continue
        assert LEVEL[other] > LEVEL[unit], f"{module} imports {target}: {unit} -> {other} runs up"


def test_no_import_cycles():
    # depth-first search for a back edge; the cycle is reported as a chain
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m):
        state[m] = 1
        stack.append(m)
        for t in sorted(GRAPH[m]):
            if state.get(t) == 1:
                raise AssertionError(" -> ".join(stack[stack.index(t):] + [t]))
            if t not in state:
                visit(t)
        stack.pop()
        state[m] = 2

    for m in sorted(GRAPH):
        if m not in state:
            visit(m)
    assert len(state) == len(MODULES) > 30


@pytest.mark.parametrize("module", sorted(MODULES))
def test_module_size(module):
    lines = MODULES[module].read_text().count("\n")
    assert lines <= 600, f"{module}: {lines} lines"


def test_the_compiled_core_is_loaded_in_one_place():
    loaders = [m for m, p in MODULES.items() if "import_module" in p.read_text()
               or "import _core" in p.read_text()]
    assert loaders == ["bemcontact._native"], loaders


def _private_imports(path: pathlib.Path) -> list[str]:
    """``from X import _name`` in ``path`` (X a bemcontact module, _name not
    a dunder): a private name taken out of its module."""
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith(
                "bemcontact")):
            out += [a.name for a in node.names
                    if a.name.startswith("_") and not a.name.startswith("__")]
    return out


@pytest.mark.parametrize("module", sorted(MODULES))
def test_private_names_stay_in_their_module(module):
    """House style: a name starting with ``_`` is its module's own; no other
    module imports it (``_native``, the one loader of the compiled core, is
    imported as a module, not as a name)."""
    assert _private_imports(MODULES[module]) == [], module
