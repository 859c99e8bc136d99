"""The sweep's table: CSV always, Parquet through pyarrow when installed
(here a stand-in module records what would be written)."""

from __future__ import annotations

import sys
import types

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
