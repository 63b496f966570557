"""VTK files for ParaView from a run's results (:func:`write_vtk`).

MoorDyn-C writes one XML PolyData file (``.vtp``) per object and a multiblock file (``.vtm``) per
call of its ``SaveVTK``. moorline writes, for every output time ``k`` of a results Dataset:

* ``<base>_lines_<k>.vtp``: every line node as a point, every segment as a two-point line cell
  (MoorDyn's layout). Point data ``tension`` [N] (node tension, the mean of the adjacent segments),
  ``curvature`` [1/m], ``bending_moment`` [N m], ``velocity`` [m/s], ``line`` (line number),
  ``node`` (node index from end A) and ``s`` [m] (unstretched arc length from end A); cell data
  ``segment_tension`` [N], ``segment_strain`` [-] and ``line``.
* ``<base>_points_<k>.vtp``: every point as a vertex with ``force`` [N] (net force),
  ``velocity`` [m/s], ``point`` (number) and ``kind`` (0 fixed, 1 coupled, 2 free, 3 on a body).
* ``<base>_rods_<k>.vtp``: every rod as a line from end A to end B with cell data ``rod``,
  ``force`` [N] and ``moment`` [N m] (about end A).
* ``<base>_bodies_<k>.vtp``: every body as its reference point and three unit axis lines (body
  x, y, z; MoorDyn draws the same glyph) with point data ``body``; cell data ``axis`` (0, 1, 2) and
  the pose ``roll``, ``pitch``, ``yaw`` [rad].
* ``<base>_<k>.vtm``: a multiblock file holding the four (those the system has).

and the collections ``<base>.pvd`` (the multiblock files) and ``<base>_<kind>.pvd`` (each kind
alone, for readers without multiblock support), each listing every output time. Open
``<base>.pvd`` in ParaView; the time slider steps through the run.

Arrays are written as VTK's own writer does: inline "binary" (the UInt64 byte-count header and the
raw little-endian data, each base64-encoded), float64 and int64, uncompressed; the files read back
bit for bit.
"""

from __future__ import annotations

import base64
import logging
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from ..model.types import rotation_xyz

log = logging.getLogger("moorline.io")

KINDS = ("lines", "points", "rods", "bodies")
_POINT_KIND = {"fixed": 0, "coupled": 1, "free": 2, "body": 3}


def _array(name: str | None, a, ncomp: int = 1) -> str:
    a = np.ascontiguousarray(a)
    if a.dtype.kind == "f":
        a, vt = a.astype("<f8"), "Float64"
    else:
        a, vt = a.astype("<i8"), "Int64"
    raw = a.tobytes()
    head = np.array([len(raw)], dtype="<u8").tobytes()
    # header and data encoded as two base64 blocks, as VTK's own writer (and MoorDyn's) does
    data = (base64.b64encode(head) + base64.b64encode(raw)).decode("ascii")
    nm = f" Name={quoteattr(name)}" if name else ""
    return (f'<DataArray type="{vt}"{nm} NumberOfComponents="{ncomp}" format="binary">\n{data}\n'
            "</DataArray>\n")


def _polydata(points, *, verts=None, lines=None, point_data=None, cell_data=None) -> str:
    """An XML PolyData document. ``verts`` and ``lines`` are lists of point-index lists."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    verts = verts or []
    lines = lines or []
    out = ['<?xml version="1.0"?>\n',
           '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n',
           "<PolyData>\n",
           f'<Piece NumberOfPoints="{len(points)}" NumberOfVerts="{len(verts)}" NumberOfLines="{len(lines)}" '
           'NumberOfStrips="0" NumberOfPolys="0">\n',
           "<Points>\n", _array(None, points, 3), "</Points>\n"]
    for tag, data in (("PointData", point_data), ("CellData", cell_data)):
        if data:
            out.append(f"<{tag}>\n")
            for name, a in data.items():
                a = np.asarray(a)
                out.append(_array(name, a, 1 if a.ndim == 1 else a.shape[1]))
            out.append(f"</{tag}>\n")
    for tag, cells in (("Verts", verts), ("Lines", lines)):
        if cells:
            conn = np.concatenate([np.asarray(c, dtype=np.int64) for c in cells])
            offs = np.cumsum([len(c) for c in cells]).astype(np.int64)
            out += [f"<{tag}>\n", _array("connectivity", conn), _array("offsets", offs), f"</{tag}>\n"]
    out += ["</Piece>\n", "</PolyData>\n", "</VTKFile>\n"]
    return "".join(out)


def _collection(entries: list[tuple[float, str]]) -> str:
    rows = "".join(f'<DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>\n' for t, f in entries)
    return ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            f"<Collection>\n{rows}</Collection>\n</VTKFile>\n")


def _multiblock(files: list[tuple[str, str]]) -> str:
    rows = "".join(f'<DataSet index="{i}" name={quoteattr(n)} file={quoteattr(f)}/>\n'
                   for i, (n, f) in enumerate(files))
    return ('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" version="1.0" byte_order="LittleEndian">\n'
            f"<vtkMultiBlockDataSet>\n{rows}</vtkMultiBlockDataSet>\n</VTKFile>\n")


def _values(ds, name, k):
    return np.asarray(ds[name].isel(time=k).values) if name in ds else None


def _lines(ds, k) -> str:
    r = _values(ds, "node_position", k)
    line = np.asarray(ds.node_line.values)
    node = np.asarray(ds.node_index.values)
    pd = {"line": line, "node": node, "s": np.asarray(ds.node_s.values, dtype=float)}
    for name, key in (("tension", "node_tension"), ("curvature", "node_curvature"),
                      ("bending_moment", "node_bending_moment"), ("velocity", "node_velocity")):
        v = _values(ds, key, k)
        if v is not None:
            pd[name] = v
    # segment j of line n joins its nodes j-1 and j; the nodes of a line are consecutive
    seg_line = np.asarray(ds.segment_line.values)
    seg_index = np.asarray(ds.segment_index.values)
    first = {int(n): int(np.flatnonzero(line == n)[0]) for n in np.unique(line)}
    cells = [[first[int(n)] + int(j) - 1, first[int(n)] + int(j)] for n, j in zip(seg_line, seg_index, strict=True)]
    cd = {"line": seg_line}
    for name, key in (("segment_tension", "segment_tension"), ("segment_strain", "segment_strain")):
        v = _values(ds, key, k)
        if v is not None:
            cd[name] = v
    return _polydata(r, lines=cells, point_data=pd, cell_data=cd)


def _points(ds, k) -> str:
    r = _values(ds, "point_position", k)
    n = r.shape[0]
    kinds = ds.point_kind.values if "point_kind" in ds.coords else np.full(n, "free")
    pd = {"point": np.asarray(ds.point.values), "kind": np.array([_POINT_KIND.get(str(s), -1) for s in kinds])}
    for name, key in (("force", "point_force"), ("velocity", "point_velocity")):
        v = _values(ds, key, k)
        if v is not None:
            pd[name] = v
    return _polydata(r, verts=[[i] for i in range(n)], point_data=pd)


def _rods(ds, k) -> str:
    ends = _values(ds, "rod_end_position", k)  # (rod, 2, 3)
    n = ends.shape[0]
    cd = {"rod": np.asarray(ds.rod.values)}
    f = _values(ds, "rod_force", k)
    if f is not None:
        cd["force"], cd["moment"] = f[:, :3], f[:, 3:]
    return _polydata(ends.reshape(-1, 3), lines=[[2 * i, 2 * i + 1] for i in range(n)],
                     point_data={"rod": np.repeat(cd["rod"], 2), "end": np.tile([0, 1], n)}, cell_data=cd)


def _bodies(ds, k, axis_length: float) -> str:
    pose = _values(ds, "body_pose", k)
    pts, cells, body, axis, ang = [], [], [], [], []
    for b, p in enumerate(pose):
        R = rotation_xyz(p[3:])
        base = len(pts)
        pts.append(p[:3])
        for j in range(3):
            pts.append(p[:3] + axis_length * R[:, j])
            cells.append([base, base + 1 + j])
            axis.append(j)
            ang.append(p[3:])
        body += [b + 1] * 4
    ang = np.asarray(ang).reshape(-1, 3)
    nb = np.asarray(ds.body.values)
    cd = {"body": np.repeat(nb, 3), "axis": np.asarray(axis), "roll": ang[:, 0], "pitch": ang[:, 1], "yaw": ang[:, 2]}
    return _polydata(np.asarray(pts), lines=cells, point_data={"body": np.asarray(body)}, cell_data=cd)


def write_vtk(results, folder, *, base: str | None = None, every: int = 1, axis_length: float = 1.0) -> Path:
    """Write the results of a run as VTK files for ParaView (see the module docstring for the layout).

    Parameters
    ----------
    results : xarray.Dataset or path-like
        What :func:`moorline.simulate` returns (with node data: ``record_nodes=True``, the default),
        or a NetCDF file written by ``moorline run``.
    folder : path-like
        Output folder (created if needed); existing files of the same names are overwritten.
    base : str, optional
        File name stem (default: the deck's stem from the results' ``source``, else ``moorline``).
    every : int
        Write every n-th output time (default all).
    axis_length : float
        Length [m] of the axis lines drawn for each body.

    Returns
    -------
    Path
        The collection file ``<base>.pvd``.

    Raises
    ------
    ValueError
        If the results hold no node positions (a run with ``record_nodes=False`` / ``--no-nodes``).
    """
    import xarray as xr

    if not isinstance(results, xr.Dataset):
        with xr.open_dataset(results, engine="h5netcdf") as f:
            results = f.load()
    ds = results
    if int(every) < 1:
        raise ValueError(f"every must be a whole number >= 1, got {every!r}")
    have_lines = "node" in ds.dims and ds.sizes["node"] > 0
    if have_lines and "node_position" not in ds:
        raise ValueError("the results hold no node positions (run with record_nodes=True, i.e. without --no-nodes) "
                         "so the lines cannot be drawn")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    if base is None:
        src = ds.attrs.get("source", "")
        base = Path(src).stem if src else "moorline"
    writers = []
    if have_lines:
        writers.append(("lines", _lines))
    if "point_position" in ds and ds.sizes.get("point", 0):
        writers.append(("points", _points))
    if "rod_end_position" in ds:
        writers.append(("rods", _rods))
    if "body_pose" in ds:
        writers.append(("bodies", lambda d, k: _bodies(d, k, axis_length)))
    times = np.asarray(ds.time.values, dtype=float)
    idx = range(0, times.size, int(every))
    width = max(len(str(times.size - 1)), 1)
    per_kind: dict[str, list[tuple[float, str]]] = {name: [] for name, _ in writers}
    blocks: list[tuple[float, str]] = []
    for k in idx:
        files = []
        for name, fn in writers:
            fname = f"{base}_{name}_{k:0{width}d}.vtp"
            (folder / fname).write_text(fn(ds, k), encoding="ascii")
            per_kind[name].append((float(times[k]), fname))
            files.append((name, fname))
        mname = f"{base}_{k:0{width}d}.vtm"
        (folder / mname).write_text(_multiblock(files), encoding="utf-8")
        blocks.append((float(times[k]), mname))
    for name, entries in per_kind.items():
        (folder / f"{base}_{name}.pvd").write_text(_collection(entries), encoding="utf-8")
    pvd = folder / f"{base}.pvd"
    pvd.write_text(_collection(blocks), encoding="utf-8")
    log.info("wrote %d VTK time steps of %s to %s", len(blocks), ", ".join(per_kind), folder)
    return pvd
