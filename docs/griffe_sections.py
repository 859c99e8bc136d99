"""A griffe extension for the API reference (mkdocs.yml): bemcontact's
docstrings write NumPy-style sections with one-line entries ``name: what``
(the signature has the types) and may close a section with a paragraph;
NumPy's parser would read ``what`` as a type and the paragraph as an entry.
This rewrites, inside ``Parameters``/``Attributes``/``Returns`` sections,
``name: what`` as ``name`` with ``what`` indented below it, and ends the
section before a closing paragraph (an unindented line after a blank
line), so the rendered tables have the descriptions in their place; Sphinx
roles (``:class:`~a.B```) become code (``B``)."""

from __future__ import annotations

import re

import griffe

#: Sphinx roles (``:class:`~a.b.C```) in the docstrings, shown as code (``C``).
ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|exc|obj):`(~?)([^`]+)`")
SECTIONS = ("Parameters", "Attributes", "Returns", "Other Parameters")
#: ``name: what`` (names are lowercase identifiers; ``Regions: ...`` is prose)
ENTRY = re.compile(r"^([a-z_]\w*(?:, [a-z_]\w*)*): (.+)$")


def rewrite(text: str) -> str:
    lines = text.split("\n")
    out: list[str] = []
    in_section = False
    i = 0
    while i < len(lines):
        line = lines[i]
        nxt = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() in SECTIONS and set(nxt.strip()) == {"-"}:
            in_section = True
            out += [line, nxt]
            i += 2
            continue
        if in_section:
            if set(line.strip()) == {"-"} and out and out[-1].strip():
                in_section = False  # the next section's underline
            elif not line.strip() and nxt and not nxt.startswith(" ") and not ENTRY.match(nxt):
                nxt_under = lines[i + 2] if i + 2 < len(lines) else ""
                if set(nxt_under.strip()) != {"-"} and not re.match(r"^[a-z_]\w*:?$", nxt.strip()):
                    in_section = False  # a closing paragraph: end the section
                    out += ["", "Notes", "-----"]
                    i += 1
                    continue
            m = ENTRY.match(line)
            if in_section and m:
                out += [m.group(1), "    " + m.group(2)]
                i += 1
                continue
        out.append(line)
        i += 1
    return ROLE.sub(_role, "\n".join(out))


def _role(m: re.Match) -> str:
    target = m.group(2)
    return f"`{target.rsplit('.', 1)[-1] if m.group(1) else target}`"


class NumpyColonEntries(griffe.Extension):
    def on_instance(self, *, obj: griffe.Object, **kwargs) -> None:  # noqa: ARG002
        if obj.docstring is not None:
            obj.docstring.value = rewrite(obj.docstring.value)
