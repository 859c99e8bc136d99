"""The on-disk cache of condensed bodies: reused across problem objects,
damaged or foreign entries detected and rebuilt, never used."""

from __future__ import annotations

import shutil

import pytest

import bemcontact as bc
from bemcontact.contact import ContactProblem
from bemcontact.study.cache import BodyCache, body_key

from .conftest import tiny_problem
from .test_reuse import _close


def _solve(pf, cache):
    cp = ContactProblem(*pf.bodies, pf.pair)
    cond = cp.condense(pf.options, condense_body=cache.condense)
    return cp.solve(pf.options, condensed=cond)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A fresh solve and the cache entries of its two bodies."""
    tmp = tmp_path_factory.mktemp("cache")
    pf = bc.load_problem(tiny_problem(tmp))
    fresh = ContactProblem(*pf.bodies, pf.pair).solve(pf.options)
    cache = BodyCache(tmp / "cache")
    _close(_solve(pf, cache), fresh)
    assert (cache.misses, cache.hits, cache.rejected) == (2, 0, 0)
    return tmp / "cache", fresh


@pytest.fixture()
def setup(tmp_path, built):
    shutil.copytree(built[0], tmp_path / "cache")
    entries = sorted((tmp_path / "cache").glob("*.condensed"))
    assert len(entries) == 2
    return tmp_path, built[1], entries


def test_second_process_reads_the_bodies(setup):
    tmp_path, fresh, _ = setup
    pf = bc.load_problem(tiny_problem(tmp_path, mu="0.05", top="[0.001, 0, -0.03]",
                                      name="other.toml"))
    cache = BodyCache(tmp_path / "cache")  # a new cache object: only the disk is shared
    r = _solve(pf, cache)
    assert (cache.misses, cache.hits, cache.rejected) == (0, 2, 0)
    _close(r, ContactProblem(*pf.bodies, pf.pair).solve(pf.options))
    assert r.timings["assembly"] == 0.0  # nothing assembled


def _flip(path, where):
    raw = bytearray(path.read_bytes())
    raw[where] ^= 0x01
    path.write_bytes(bytes(raw))


@pytest.mark.parametrize("damage", ["byte", "truncate", "header", "version", "foreign",
                                    "empty"])
def test_damaged_or_foreign_entry_is_rebuilt_not_used(setup, damage):
    tmp_path, fresh, entries = setup
    e = entries[0]
    raw = e.read_bytes()
    if damage == "byte":  # a bit flipped deep inside the arrays
        _flip(e, len(raw) // 2)
    elif damage == "truncate":
        e.write_bytes(raw[: len(raw) - 100])
    elif damage == "header":
        e.write_bytes(b"garbage\n" + raw.partition(b"\n")[2])
    elif damage == "version":
        head, _, rest = raw.partition(b"\n")
        parts = head.split(b" ")
        parts[1] = b"999"
        e.write_bytes(b" ".join(parts) + b"\n" + rest)
    elif damage == "foreign":  # the other body's entry (valid in itself) filed under this key
        e.write_bytes(entries[1].read_bytes())
    else:
        e.write_bytes(b"")
    pf = bc.load_problem(tiny_problem(tmp_path, name="again.toml"))
    cache = BodyCache(tmp_path / "cache")
    _close(_solve(pf, cache), fresh)
    assert (cache.misses, cache.hits, cache.rejected) == (0, 1, 1)
    assert e.read_bytes().split(b" ")[:3] == raw.split(b" ")[:3]  # rebuilt under its key
    again = BodyCache(tmp_path / "cache")
    _solve(pf, again)
    assert (again.misses, again.hits, again.rejected) == (0, 2, 0)


def test_key_covers_the_material_not_the_array_objects(setup):
    """Another material is another key; equal content is the same key."""
    tmp_path, _, _ = setup
    pa = bc.load_problem(tiny_problem(tmp_path, name="a.toml"))
    pb = bc.load_problem(tiny_problem(tmp_path, E="2e4", name="b.toml"))
    cp = pa.contact_problem()
    cond = cp.condense(pa.options)
    body = pa.bodies[0]
    nodes = cond.condensed[0].nodes
    fields = cond.condensed[0].values
    ka = body_key(body, nodes, [body.boundary_conditions], pa.options.linear, None, fields)
    kb = body_key(pb.bodies[0], nodes, [pb.bodies[0].boundary_conditions], pa.options.linear,
                  None, fields)
    assert ka != kb and len(ka) == 64
    assert ka == body_key(body, nodes, [body.boundary_conditions], pa.options.linear, None,
                          fields.copy())
