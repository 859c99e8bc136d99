"""ParaView time series of a large run: PVD+VTU (what bemcontact writes)
against XDMF (meshio) and VTKHDF (VTK's vtkHDFWriter): would either serve
large runs better (docs/benchmarks.md)?

The run: one body, ``bc.box`` with N x N quad4 faces per side (6 N^2 + 2
nodes: N = 100 -> 60,002, N = 160 -> 153,602), and its contact interface (the
``zmax`` face, (N+1)^2 nodes), over S load steps (default 15).  Synthetic
values (this measures I/O, not the solver) with the fields and types a run
writes per step: body: displacement, traction, normal (float64 x 3), weight,
cell data ``region`` (int32) and the region names as field data; interface:
pressure, gap, weight (float64), tangential_traction, slip, displacement,
traction, normal (float64 x 3), state (int8).  Every field is written at every
step in every format (the same content).

Formats, one time series per surface (two series):

* ``pvd``: ``steps/<name>_<k>.vtu`` + ``<name>.pvd`` through the package's own
  writers (``output.vtu.write_vtu``: meshio's VTU, binary, zlib; region field
  data; ``output.vtu.write_pvd``).
* ``xdmf``: ``meshio.xdmf.TimeSeriesWriter`` (mesh once, the fields per step,
  one ``.h5`` + ``.xdmf`` per series; meshio writes HDF5 uncompressed and no
  field data).
* ``vtkhdf``: ``vtkHDFWriter`` with ``WriteAllTimeSteps`` from a temporal
  source (mesh once, as the geometry does not change; one ``.vtkhdf`` per
  series), at its default compression and at compression level 4 (gzip).

Write time: median of R runs (default 3), into a fresh directory each, as
the writer returns (the data may still be in the page cache) and with every
file fsync'ed.
Read-back: every step's arrays of both series into NumPy, median of R, warm
page cache, with meshio (pvd, xdmf) and VTK (every format; xdmf through
vtkXdmfReader, the wheel has no vtkXdmf3Reader).  Every read is checked against the values
written (last step).

Needs (benchmark only, not bemcontact's dependencies): h5py, vtk.
Usage:  python benchmarks/output_formats_N100_160.py [--sizes 100,160] [--steps 15] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import pathlib
import shutil
import statistics
import sys
import tempfile
import time

import numpy as np

FORMATS = ("pvd", "xdmf", "vtkhdf", "vtkhdf_gz4")


# ------------------------------------------------------------------ the data


def build(divisions: int, steps: int) -> dict:
    """Both series: name -> {points, conn (quad4), cell_data, field_data,
    fields: [per step {name: array}]}."""
    import bemcontact as bc
    from bemcontact.output.vtu import region_field_data

    mesh = bc.box((0, 0, 0), (0.02, 0.02, 0.02), int(divisions), "quad4")
    x = mesh.nodes
    series = {}
    # body: the whole surface
    c = x - x.mean(axis=0)
    nrm = c / np.linalg.norm(c, axis=1, keepdims=True)
    w = np.full(len(x), (0.02 / divisions) ** 2)
    body_steps = []
    for k in range(1, steps + 1):
        s = k / steps
        u = 1e-5 * s * np.stack([np.sin(300 * x[:, 1] + s), np.cos(250 * x[:, 0]),
                                 -x[:, 2] * 50 * (1 + 0.1 * np.sin(400 * x[:, 0]))], axis=1)
        t = 1e8 * s * np.stack([np.cos(200 * x[:, 2]), np.sin(150 * x[:, 0] * x[:, 1] * 1e2),
                                np.exp(-1e4 * ((x[:, 0] - 0.01) ** 2 + (x[:, 1] - 0.01) ** 2))],
                               axis=1)
        body_steps.append({"displacement": u, "traction": t, "normal": nrm, "weight": w})
    series["body"] = {
        "points": x, "conn": mesh.elements.astype(np.int64),
        "cell_data": {"region": mesh.element_region.astype(np.int32)},
        "field_data": region_field_data(mesh), "fields": body_steps,
    }
    # interface: the zmax face
    els = mesh.region("zmax")
    nodes, inv = np.unique(mesh.elements[els], return_inverse=True)
    p = x[nodes]
    r2 = (p[:, 0] - 0.01) ** 2 + (p[:, 1] - 0.01) ** 2
    if_steps = []
    for k in range(1, steps + 1):
        s = k / steps
        a2 = (0.008 * s) ** 2
        pr = 1e9 * s * np.sqrt(np.clip(1 - r2 / a2, 0, None))
        q = 0.3 * pr[:, None] * np.stack([np.cos(1e3 * p[:, 0]), np.sin(1e3 * p[:, 1]),
                                          0 * pr], axis=1)
        slip = 1e-7 * s * np.stack([np.sin(900 * p[:, 1]), np.cos(800 * p[:, 0]), 0 * pr], axis=1)
        state = np.where(r2 < 0.5 * a2, 2, np.where(r2 < a2, 1, 0)).astype(np.int8)
        if_steps.append({
            "pressure": pr, "tangential_traction": q, "gap": np.maximum(r2 - a2, 0) * 1e2,
            "slip": slip, "state": state, "displacement": body_steps[k - 1]["displacement"][nodes],
            "traction": q + pr[:, None] * np.array([0.0, 0.0, -1.0]),
            "normal": np.tile([0.0, 0.0, 1.0], (len(p), 1)), "weight": w[nodes],
        })
    series["body_interface"] = {
        "points": p, "conn": inv.reshape(-1, 4).astype(np.int64),
        "cell_data": {"region": np.zeros(len(els), dtype=np.int32)},
        "field_data": {"zmax": np.array([0, 2], dtype=np.int32)}, "fields": if_steps,
    }
    return series


# ------------------------------------------------------------------ writers


def write_pvd(d: pathlib.Path, series: dict) -> None:
    from bemcontact.output.vtu import write_vtu, write_pvd as pvd

    (d / "steps").mkdir()
    for name, s in series.items():
        n = len(s["fields"])
        w = len(str(n))
        for k, f in enumerate(s["fields"], 1):
            write_vtu(d / "steps" / f"{name}_{k:0{w}d}.vtu", s["points"], [("quad", s["conn"])],
                       f, {kk: [v] for kk, v in s["cell_data"].items()}, s["field_data"])
        pvd(d / f"{name}.pvd", [(k, f"steps/{name}_{k:0{w}d}.vtu") for k in range(1, n + 1)])


def write_xdmf(d: pathlib.Path, series: dict) -> None:
    import meshio

    # meshio 5.3 writes the .h5 into the current directory (its stem only), not
    # beside the .xdmf: write from d
    cwd = os.getcwd()
    os.chdir(d)
    try:
        for name, s in series.items():
            with meshio.xdmf.TimeSeriesWriter(f"{name}.xdmf") as w:
                w.write_points_cells(s["points"], [("quad", s["conn"])])
                for k, f in enumerate(s["fields"], 1):
                    w.write_data(k, point_data=f,
                                 cell_data={kk: [v] for kk, v in s["cell_data"].items()})
    finally:
        os.chdir(cwd)


def _vtk_grid(s: dict):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(s["points"]), deep=True))
    g.SetPoints(pts)
    conn = s["conn"]
    ca = vtk.vtkCellArray()
    offsets = np.arange(0, conn.size + 1, conn.shape[1], dtype=np.int64)
    ca.SetData(numpy_to_vtk(offsets, deep=True, array_type=vtk.VTK_ID_TYPE),
               numpy_to_vtk(conn.ravel().copy(), deep=True, array_type=vtk.VTK_ID_TYPE))
    g.SetCells(vtk.VTK_QUAD, ca)
    for kk, v in s["cell_data"].items():
        a = numpy_to_vtk(v, deep=True)
        a.SetName(kk)
        g.GetCellData().AddArray(a)
    for kk, v in s["field_data"].items():
        a = numpy_to_vtk(np.asarray(v), deep=True)
        a.SetName(kk)
        g.GetFieldData().AddArray(a)
    return g


def _temporal_source(s: dict):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase

    sddp = vtk.vtkStreamingDemandDrivenPipeline
    times = [float(k) for k in range(1, len(s["fields"]) + 1)]

    class Source(VTKPythonAlgorithmBase):
        def __init__(self):
            super().__init__(nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid")
            self.grid = _vtk_grid(s)

        def RequestInformation(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            info.Set(sddp.TIME_STEPS(), times, len(times))
            info.Set(sddp.TIME_RANGE(), [times[0], times[-1]], 2)
            return 1

        def RequestData(self, request, inInfo, outInfo):
            info = outInfo.GetInformationObject(0)
            t = info.Get(sddp.UPDATE_TIME_STEP()) if info.Has(sddp.UPDATE_TIME_STEP()) else 1.0
            k = min(range(len(times)), key=lambda i: abs(times[i] - t))
            out = vtk.vtkUnstructuredGrid.GetData(outInfo)
            out.ShallowCopy(self.grid)  # same points and cells: the writer keeps them once
            pd = out.GetPointData()
            for kk, v in s["fields"][k].items():
                a = numpy_to_vtk(np.ascontiguousarray(v), deep=True)
                a.SetName(kk)
                pd.AddArray(a)
            out.GetInformation().Set(vtk.vtkDataObject.DATA_TIME_STEP(), times[k])
            return 1

    return Source()


def write_vtkhdf(d: pathlib.Path, series: dict, level: int | None = None) -> None:
    import vtk

    for name, s in series.items():
        src = _temporal_source(s)  # keep the Python object alive while writing
        w = vtk.vtkHDFWriter()
        w.SetInputConnection(src.GetOutputPort())
        w.SetFileName(os.fspath(d / f"{name}.vtkhdf"))
        w.SetWriteAllTimeSteps(True)
        if level is not None:
            w.SetCompressionLevel(level)
        if not w.Write():
            raise RuntimeError(f"vtkHDFWriter failed on {name}")


WRITERS = {"pvd": write_pvd, "xdmf": write_xdmf, "vtkhdf": write_vtkhdf,
           "vtkhdf_gz4": lambda d, s: write_vtkhdf(d, s, 4)}


# ------------------------------------------------------------------ readers
# each returns {series: {field: last step's array}} after reading every step


def read_pvd_meshio(d: pathlib.Path, series: dict) -> dict:
    import re

    import meshio

    last = {}
    for name in series:
        files = re.findall(r'file="([^"]+)"', (d / f"{name}.pvd").read_text())
        for f in files:
            m = meshio.read(d / f)
        last[name] = m.point_data
    return last


def _vtk_arrays(ds) -> dict:
    from vtk.util.numpy_support import vtk_to_numpy

    pd = ds.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def read_pvd_vtk(d: pathlib.Path, series: dict) -> dict:
    import re

    import vtk

    last = {}
    for name in series:
        for f in re.findall(r'file="([^"]+)"', (d / f"{name}.pvd").read_text()):
            r = vtk.vtkXMLUnstructuredGridReader()
            r.SetFileName(os.fspath(d / f))
            r.Update()
            last[name] = {k: v.copy() for k, v in _vtk_arrays(r.GetOutput()).items()}
    return last


def read_xdmf_meshio(d: pathlib.Path, series: dict) -> dict:
    import meshio

    last = {}
    for name in series:
        with meshio.xdmf.TimeSeriesReader(os.fspath(d / f"{name}.xdmf")) as r:
            r.read_points_cells()
            for k in range(r.num_steps):
                _, pdata, _ = r.read_data(k)
            last[name] = pdata
    return last


def _read_vtk_temporal(reader, path: pathlib.Path) -> dict:
    import vtk

    reader.SetFileName(os.fspath(path))
    reader.UpdateInformation()
    info = reader.GetOutputInformation(0)
    times = info.Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    out = {}
    for t in times:
        reader.UpdateTimeStep(t)
        ds = reader.GetOutputDataObject(0)
        if not isinstance(ds, vtk.vtkUnstructuredGrid):  # composite: first block
            it = ds.NewIterator()
            it.InitTraversal()
            ds = it.GetCurrentDataObject()
        out = {k: v.copy() for k, v in _vtk_arrays(ds).items()}
    return out


def read_vtkhdf_vtk(d: pathlib.Path, series: dict) -> dict:
    import vtk

    return {n: _read_vtk_temporal(vtk.vtkHDFReader(), d / f"{n}.vtkhdf") for n in series}


def read_xdmf_vtk(d: pathlib.Path, series: dict) -> dict:
    import vtk

    # the wheel has VTK's XDMF 2 reader (vtkXdmfReader), not vtkXdmf3Reader
    return {n: _read_vtk_temporal(vtk.vtkXdmfReader(), d / f"{n}.xdmf") for n in series}


READERS = {"pvd": [("meshio", read_pvd_meshio), ("vtk", read_pvd_vtk)],
           "xdmf": [("meshio", read_xdmf_meshio), ("vtk", read_xdmf_vtk)],
           "vtkhdf": [("vtk", read_vtkhdf_vtk)], "vtkhdf_gz4": [("vtk", read_vtkhdf_vtk)]}


try:
    import vtk as _vtk  # noqa: F401

    _HAS_VTK = True
except ImportError:
    _HAS_VTK = False


def _check(last: dict, series: dict, fmt: str, how: str) -> None:
    for name, s in series.items():
        for k, v in s["fields"][-1].items():
            got = np.asarray(last[name][k]).reshape(np.shape(v))
            if not np.array_equal(got, v):
                raise AssertionError(f"{fmt} read with {how}: {name}.{k} differs from what "
                                     "was written")


# ------------------------------------------------------------------ the measurement


def _size(d: pathlib.Path) -> tuple[int, int]:
    files = [p for p in d.rglob("*") if p.is_file()]
    return sum(p.stat().st_size for p in files), len(files)


def _fsync(d: pathlib.Path) -> None:
    """Flush the files written to the disk (the write time alone ends in the
    page cache)."""
    for p in d.rglob("*"):
        if p.is_file():
            fd = os.open(p, os.O_RDONLY)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)


def measure(divisions: int, steps: int = 15, repeat: int = 3, formats=FORMATS,
            root: str | None = None) -> list[dict]:
    series = build(divisions, steps)
    rows = []
    base = pathlib.Path(tempfile.mkdtemp(prefix="bc_outfmt_", dir=root))
    try:
        for fmt in formats:
            wt, st = [], []
            for r in range(max(1, repeat)):
                d = base / f"{fmt}_{r}"
                d.mkdir()
                t0 = time.perf_counter()
                WRITERS[fmt](d, series)
                wt.append(time.perf_counter() - t0)
                _fsync(d)
                st.append(time.perf_counter() - t0)
                if r < repeat - 1:
                    shutil.rmtree(d)
            nbytes, nfiles = _size(d)
            row = {"divisions": divisions, "nodes": len(series["body"]["points"]),
                   "interface_nodes": len(series["body_interface"]["points"]), "steps": steps,
                   "format": fmt, "write_s": statistics.median(wt),
                   "write_fsync_s": statistics.median(st), "bytes": nbytes,
                   "files": nfiles}
            for how, reader in READERS[fmt]:
                if how == "vtk" and not _HAS_VTK:
                    continue
                rt = []
                for _ in range(max(1, repeat)):
                    t0 = time.perf_counter()
                    last = reader(d, series)
                    rt.append(time.perf_counter() - t0)
                _check(last, series, fmt, how)
                row[f"read_{how}_s"] = statistics.median(rt)
            rows.append(row)
            shutil.rmtree(d)
            print(f"  done: N = {divisions}, {fmt}: write {row['write_s']:.2f} s, "
                  f"{nbytes / 1e6:.1f} MB", file=sys.stderr, flush=True)
    finally:
        shutil.rmtree(base, ignore_errors=True)
    return rows


def table(rows: list[dict]) -> str:
    def f(r, k):  # a reader not run: dash
        return f"{r[k]:.2f}" if k in r else "–"

    out = ["| N | body nodes | format | write s | write + fsync s | MB | files | read s (meshio) "
           "| read s (vtk) |", "|---|---:|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['divisions']} | {r['nodes']:,} | {r['format']} | {r['write_s']:.2f} | "
                   f"{r['write_fsync_s']:.2f} | {r['bytes'] / 1e6:.1f} | {r['files']} | "
                   f"{f(r, 'read_meshio_s')} | {f(r, 'read_vtk_s')} |")
    return "\n".join(out)


def _vtk_version() -> str:
    if not _HAS_VTK:
        return "absent"
    import vtk

    return vtk.vtkVersion.GetVTKVersion()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,160", help="quad4 divisions per cube edge")
    ap.add_argument("--steps", type=int, default=15)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--formats", default=",".join(FORMATS))
    a = ap.parse_args(argv)
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from _common import machine_line

    rows = []
    for n in (int(x) for x in a.sizes.split(",")):
        rows += measure(n, a.steps, a.repeat, a.formats.split(","))
    print(machine_line(f"; {a.steps} load steps, two series (body + interface), "
                       f"median of {a.repeat}; meshio, vtk {_vtk_version()}") + "\n")
    print(table(rows))


if __name__ == "__main__":
    main()
