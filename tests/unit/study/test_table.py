"""The sweep's table: CSV always, Parquet through pyarrow when installed
(here a stand-in module records what would be written)."""

from __future__ import annotations

import sys
import types

import pytest

from bemcontact.study.table import OUTPUTS, read_table, write_table

ROWS = [
    {"point": "p0001", "k": 0.1, "v": [0, 0, -0.02], "status": "ok", "error": "",
     "normal_force": 12.5, "converged": True},
    {"point": "p0002", "k": "text", "v": [0, 0, -0.04], "status": "failed", "error": "boom"},
]


def test_csv_columns_and_values(tmp_path):
    files = write_table(tmp_path, ["k", "v"], ROWS)
    assert [f.name for f in files] == ["table.csv"] or "pyarrow" in sys.modules
    rows = read_table(tmp_path / "table.csv")
    assert list(rows[0]) == ["point", "k", "v", *OUTPUTS]
    assert rows[0]["v"] == "[0, 0, -0.02]" and rows[0]["normal_force"] == "12.5"
    assert rows[0]["converged"] == "true" and rows[1]["converged"] == ""
    assert rows[1]["error"] == "boom" and rows[1]["k"] == "text"


def test_parquet_with_pyarrow(tmp_path, monkeypatch):
    written = {}

    def array(values):
        if len({type(v) for v in values if v is not None}) > 1:
            raise TypeError("mixed types")
        return list(values)

    fake = types.ModuleType("pyarrow")
    fake.array = array
    fake.table = lambda columns: dict(columns)
    parquet = types.ModuleType("pyarrow.parquet")

    def write(table, path):
        written.update(table)
        path.write_bytes(b"PAR1")

    parquet.write_table = write
    fake.parquet = parquet
    monkeypatch.setitem(sys.modules, "pyarrow", fake)
    monkeypatch.setitem(sys.modules, "pyarrow.parquet", parquet)
    files = write_table(tmp_path, ["k", "v"], ROWS)
    assert [f.name for f in files] == ["table.csv", "table.parquet"]
    assert (tmp_path / "table.parquet").read_bytes() == b"PAR1"
    assert list(written) == ["point", "k", "v", *OUTPUTS]
    assert written["normal_force"] == [12.5, None]
    assert written["v"] == ["[0, 0, -0.02]", "[0, 0, -0.04]"]  # vectors as text
    assert written["k"] == ["0.1", "text"]  # mixed types: the column as text


def test_an_assembly_has_columns_per_pair(tmp_path):
    """An assembly's row: the first pair's outputs in the usual columns and
    every pair's in ``pair<k>.*`` columns (the solve's own numbers), and a
    sweep key may index the [[contact]] array."""
    import bemcontact as bc
    from bemcontact.problemfile.checks import Checker
    from bemcontact.study.points import check_key
    from bemcontact.study.table import PAIR_OUTPUTS, outputs

    rollers = {"xmin": bc.Displacement((0, None, None)), "ymin": bc.Displacement((None, 0, None))}
    m = bc.LinearElastic(1e4, 0.3)
    bodies = [
        bc.ElasticBody(bc.box((0, 0, z), (1, 1, z + 1), (n, n, 2)), m,
                       {**rollers, **extra}, name=name)
        for z, n, name, extra in ((0, 3, "a", {"zmin": bc.Displacement((None, None, 0))}),
                                  (1, 4, "b", {}), (2, 2, "c", {"zmax": bc.Pressure(2.0)}))]
    pairs = [bc.ContactPair("zmax", "zmin", bodies=("a", "b")),
             bc.ContactPair("zmax", "zmin", bodies=("b", "c"))]
    res = bc.ContactProblem(bodies=bodies, pairs=pairs).solve()
    row = {"point": "p0001", "status": "ok", **outputs(res)}
    assert row["normal_force"] == res.pairs[0].normal_force
    for k, pr in enumerate(res.pairs, 1):
        assert row[f"pair{k}.normal_force"] == pr.normal_force
        assert row[f"pair{k}.normal_force"] == pytest.approx(2.0, rel=1e-8)
    write_table(tmp_path, [], [row])
    cols = list(read_table(tmp_path / "table.csv")[0])
    assert cols == ["point", *OUTPUTS, *(f"pair{k}.{n}" for k in (1, 2) for n in PAIR_OUTPUTS)]
    assert check_key(Checker("sweep.toml", tmp_path), "contact[1].friction_coefficient") == [
        "contact", 1, "friction_coefficient"]
