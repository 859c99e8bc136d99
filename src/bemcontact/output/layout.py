"""The names of a run's result files (written by
:func:`bemcontact.output.write.write_results`; docs/problem-file.md,
"Output files").

Two bodies and one contact pair (the result's ``pairs`` holds at most one):
``<body>.vtu``, ``<body>_interface.vtu``/``.csv``, ``frame.vtu``/``.csv``,
``frame_tractions.png``, ``frame_profile.png``; a body meshed in volume
(a finite-element body) also ``<body>_volume.vtu``.

An assembly (several pairs): every body's surface is ``<body>.vtu`` as
above; everything of a pair is named by the pair's *stem* ``<b1>+<b2>``
(its body 1 and body 2, in the pair's order):

* ``<stem>_frame.vtu``, ``<stem>_frame.csv``: the pair's frame;
* ``<stem>_<body>_interface.vtu``/``.csv`` for each of its two bodies;
* ``<stem>_frame_tractions.png``, ``<stem>_frame_profile.png``;
* PVD collections and ``steps/`` files as for two bodies
  (``<stem>_frame.pvd``, ``steps/<stem>_frame_001.vtu``).

When two pairs join the same two bodies (on different surfaces), both
stems name the surfaces too: ``<b1>.<surface1>+<b2>.<surface2>``
(characters other than letters, digits, ``_`` and ``-`` in a surface name
written as ``_``); if that still does not tell them apart (surface names
differing only in such characters or in case), ``<b1>+<b2>.<k>`` with the
pair's number k (1-based).  Body names cannot hold ``+``, so no pair's file
can be a body's.  File names are compared as a case-insensitive filesystem
would; names that still clash, or are longer than a file name may be
(255 bytes), are refused before anything is written.
"""

from __future__ import annotations

import os
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import ConfigError

#: What a body name must look like to name files.
SAFE_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
#: Joins a pair's two bodies in its files' names (no body name holds it).
PAIR_JOIN = "+"
#: Longest file name (bytes) most filesystems hold.
NAME_MAX = 255


@dataclass(frozen=True)
class PairFiles:
    """The file stems of one contact pair (file names without extension).

    stem: ``"<b1>+<b2>"`` (``""`` for the single pair of a two-body run).
    frame: the frame's VTU/CSV stem (``"frame"``, ``"<stem>_frame"``).
    interfaces: each body's interface stem, in the pair's order
    (``"<body>_interface"``, ``"<stem>_<body>_interface"``).
    figure: prefix of the figures (``""``, ``"<stem>_"``): ``<figure>frame_tractions.png``.
    """

    stem: str
    frame: str
    interfaces: tuple[str, str]
    figure: str


@dataclass(frozen=True)
class Layout:
    """Every file stem of a run: ``bodies`` (one per body, ``<body>``),
    ``pairs`` (:class:`PairFiles`, in the problem's order) and ``volumes``
    (``<body>_volume``, one per body meshed in volume)."""

    bodies: tuple[str, ...]
    pairs: tuple[PairFiles, ...]
    volumes: tuple[str, ...] = ()

    @property
    def assembly(self) -> bool:
        """Several pairs: the pair-prefixed names."""
        return bool(self.pairs) and self.pairs[0].stem != ""

    def series(self) -> list[str]:
        """The VTU stems in the order of the listing: bodies, then (two
        bodies) both interfaces and the frame, or (assembly) per pair its
        interfaces and frame."""
        if not self.assembly:
            return [*self.bodies, *self.volumes, *self.pairs[0].interfaces, "frame"]
        return [*self.bodies, *self.volumes,
                *(s for p in self.pairs for s in (*p.interfaces, p.frame))]

    def csv(self) -> list[str]:
        """The CSV stems: (per pair) the interfaces, then the frame."""
        if not self.assembly:
            return [*self.pairs[0].interfaces, "frame"]
        return [s for p in self.pairs for s in (*p.interfaces, p.frame)]


def _surface_part(surface: str) -> str:
    return re.sub(r"[^A-Za-z0-9_-]", "_", surface) or "_"


def pair_stems(pairs: Sequence[tuple[Sequence[str], Sequence[str]]]) -> list[str]:
    """The stems of an assembly's pairs, given as ((body 1, body 2),
    (surface 1, surface 2)) each (module docstring)."""
    keys = [frozenset(n.casefold() for n in names) for names, _ in pairs]
    stems = []
    for (names, surfaces), key in zip(pairs, keys):
        if keys.count(key) == 1:
            stems.append(PAIR_JOIN.join(names))
        else:
            stems.append(PAIR_JOIN.join(f"{n}.{_surface_part(s)}" for n, s in zip(names, surfaces)))
    folded = [s.casefold() for s in stems]
    return [s if folded.count(s.casefold()) == 1 else f"{PAIR_JOIN.join(p[0])}.{k}"
            for k, (s, p) in enumerate(zip(stems, pairs), start=1)]


def layout(
    names: Sequence[str], pairs: Sequence[tuple[Sequence[str], Sequence[str]]] = (),
    *, where: str = "write_results", volumes: Sequence[str] = (),
) -> Layout:
    """The file stems of a run of bodies ``names`` and contact ``pairs``
    ((body 1, body 2), (surface 1, surface 2)) each; at most one pair: the
    two-body names).  Raises :class:`ConfigError` (prefixed ``where``) if a
    body name cannot name a file, the names clash (compared ignoring case)
    or a file name (``steps/`` ones of up to 999 load steps included) would
    be longer than :data:`NAME_MAX` bytes.  A problem file's reader may call
    it before solving, with the pairs' bodies and surfaces.  ``volumes``:
    the bodies meshed in volume (their ``<body>_volume`` files)."""
    names = list(names)
    for n in names:
        if not isinstance(n, str) or not SAFE_NAME.match(n):
            raise ConfigError(
                f"{where}: body name {n!r} cannot name a file; use letters, digits, "
                "'_', '-' and '.'"
            )
    if len(pairs) <= 1:  # in the bodies' order
        sides = [n for n in names if not pairs or n in pairs[0][0]]
        out = Layout(tuple(names), (PairFiles("", "frame", tuple(
            f"{n}_interface" for n in sides), ""),), _volumes(names, volumes))
    else:
        files = []
        for stem, (bodies, _) in zip(pair_stems(pairs), pairs):
            files.append(PairFiles(stem, f"{stem}_frame",
                                   tuple(f"{stem}_{b}_interface" for b in bodies), f"{stem}_"))
        out = Layout(tuple(names), tuple(files), _volumes(names, volumes))
    stems = out.series()
    folded = [s.casefold() for s in stems]
    clash = sorted({s for s, f in zip(stems, folded) if folded.count(f) > 1})
    if clash:
        raise ConfigError(
            f"{where}: the body names {names} give clashing file names ({', '.join(clash)}, "
            "compared ignoring case); rename the bodies"
        )
    check_files([*(f"{s}.vtu" for s in stems),
                 *(f"{p.figure}frame_tractions.png" for p in out.pairs)], 1, where=where)
    return out


def _volumes(names: Sequence[str], volumes: Sequence[str]) -> tuple[str, ...]:
    return tuple(f"{n}_volume" for n in names if n in set(volumes))


def result_layout(result) -> Layout:
    """The :class:`Layout` of a :class:`~bemcontact.contact.results.ContactResult`
    (a body whose model gives ``volume_fields`` has a volume file)."""
    models = getattr(result, "models", {})
    return layout(result.names, [(p.names, p.surfaces) for p in getattr(result, "pairs", [])],
                  volumes=[n for n in result.names if hasattr(models.get(n), "volume_fields")])


def check_files(files: Sequence[str], steps: int = 0, *, where: str = "write_results") -> None:
    """Refuse file names (relative paths) longer than :data:`NAME_MAX`
    bytes, counting the ``steps/<stem>_<k>.vtu`` names of ``steps`` load
    steps for the VTU files."""
    width = max(3, len(str(steps)))
    for f in files:
        name = f.rsplit("/", 1)[-1]
        longest = name if not (steps and name.endswith(".vtu")) else (
            f"{name[:-4]}_{1:0{width}d}.vtu")
        if len(os.fsencode(longest)) > NAME_MAX:
            raise ConfigError(
                f"{where}: the file name {longest!r} is longer than {NAME_MAX} bytes; use "
                "shorter body (or surface) names"
            )


__all__ = ["Layout", "PairFiles", "layout", "pair_stems", "result_layout", "check_files",
           "PAIR_JOIN", "SAFE_NAME", "NAME_MAX"]
