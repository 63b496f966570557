"""VTK output (moorline.io.vtk, ``moorline run --vtk``, ``moorline vtk``): the files parse (as XML,
decoded by hand: meshio reads no PolyData), node positions, tensions and the other arrays come back
bit for bit, and the collections list every output time."""

from __future__ import annotations

import base64
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import moorline
from moorline.cli import main as cli_main
from moorline.io.vtk import write_vtk
from moorline.model import Model, rotation_xyz
from moorline.system import System

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "catenary_3line" / "catenary_3line.dat"


def _read_vtp(path: Path) -> dict:
    """Points, cells and data arrays of one of our .vtp files, decoded by hand (XML + base64)."""
    root = ET.parse(path).getroot()
    assert root.get("type") == "PolyData" and root.get("header_type") == "UInt64"
    assert root.get("byte_order") == "LittleEndian" and root.get("compressor") is None
    piece = root.find("PolyData/Piece")

    def decode(el):
        # VTK's layout: the 8-byte header and the data are two base64 blocks (12 characters, then the rest)
        text = el.text.strip()
        head = base64.b64decode(text[:12])
        if len(head) != 8:  # VTK (MoorDyn) writes an empty array as one odd 16-character block
            return np.zeros(0)
        n = int(np.frombuffer(head, "<u8")[0])
        raw = base64.b64decode(text[12:])
        assert n == len(raw)
        a = np.frombuffer(raw, "<f8" if el.get("type") == "Float64" else "<i8")
        nc = int(el.get("NumberOfComponents", "1"))
        return a.reshape(-1, nc) if nc > 1 else a

    out = {"points": decode(piece.find("Points/DataArray"))}
    for tag in ("PointData", "CellData"):
        out[tag] = {el.get("Name"): decode(el) for el in piece.findall(f"{tag}/DataArray")}
    for tag in ("Lines", "Verts"):
        el = piece.find(tag)
        if el is not None:
            conn = decode(el.find("DataArray[@Name='connectivity']"))
            offs = decode(el.find("DataArray[@Name='offsets']"))
            out[tag] = np.split(conn, offs[:-1])
    assert int(piece.get("NumberOfPoints")) == len(out["points"])
    return out


def _collection(path: Path) -> list[tuple[float, str]]:
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


@pytest.fixture(scope="module")
def catenary():
    s = System.from_file(EXAMPLE)
    return moorline.simulate(s, 1.0, dt_out=0.25, progress=False, solve_ic=False)


def test_lines_and_points_round_trip(catenary, tmp_path):
    ds = catenary
    pvd = write_vtk(ds, tmp_path)
    assert pvd == tmp_path / "catenary_3line.pvd"
    entries = _collection(pvd)
    assert [t for t, _ in entries] == ds.time.values.tolist()  # every output time
    for kind in ("lines", "points"):
        assert [t for t, _ in _collection(tmp_path / f"catenary_3line_{kind}.pvd")] == ds.time.values.tolist()
    for k, (_t, vtm) in enumerate(entries):
        blocks = [d.get("file") for d in ET.parse(tmp_path / vtm).getroot().iter("DataSet")]
        assert blocks == [f"catenary_3line_lines_{k}.vtp", f"catenary_3line_points_{k}.vtp"]
        f = _read_vtp(tmp_path / blocks[0])
        np.testing.assert_array_equal(f["points"], ds.node_position.isel(time=k).values)
        np.testing.assert_array_equal(f["PointData"]["tension"], ds.node_tension.isel(time=k).values)
        np.testing.assert_array_equal(f["PointData"]["curvature"], ds.node_curvature.isel(time=k).values)
        np.testing.assert_array_equal(f["PointData"]["line"], ds.node_line.values)
        np.testing.assert_array_equal(f["CellData"]["segment_tension"], ds.segment_tension.isel(time=k).values)
        # one two-point cell per segment, joining consecutive nodes of the same line
        assert len(f["Lines"]) == ds.sizes["segment"]
        for (a, b), n in zip(f["Lines"], ds.segment_line.values, strict=True):
            assert b == a + 1 and ds.node_line.values[a] == ds.node_line.values[b] == n
        p = _read_vtp(tmp_path / blocks[1])
        np.testing.assert_array_equal(p["points"], ds.point_position.isel(time=k).values)
        np.testing.assert_array_equal(p["PointData"]["force"], ds.point_force.isel(time=k).values)
        assert [v.tolist() for v in p["Verts"]] == [[i] for i in range(ds.sizes["point"])]


def test_every_nth_time(catenary, tmp_path):
    write_vtk(catenary, tmp_path, base="run", every=2)
    assert [t for t, _ in _collection(tmp_path / "run.pvd")] == catenary.time.values[::2].tolist()
    assert [f for _, f in _collection(tmp_path / "run_lines.pvd")] == ["run_lines_0.vtp", "run_lines_2.vtp",
                                                                       "run_lines_4.vtp"]
    f = _read_vtp(tmp_path / "run_lines_2.vtp")
    np.testing.assert_array_equal(f["points"], catenary.node_position.isel(time=2).values)
    with pytest.raises(ValueError, match="every"):
        write_vtk(catenary, tmp_path, every=0)


def _rigid_model() -> Model:
    m = Model()
    m.env.depth = 50.0
    m.options.dtM = 1e-3
    m.add_line_type("chain", d=0.1, w=20.0, EA=1e8, BA=-0.8, Cd=1.2, Ca=1.0)
    m.add_rod_type("can", d=1.0, w=200.0, Cd=0.8, Ca=1.0)
    b = m.add_body("coupled", (0.0, 0.0, -5.0), (10.0, 0.0, 30.0))
    _ra, rb = m.add_rod("can", "body", (0.0, 0.0, 0.0), (0.0, 0.0, -4.0), N=2, body=b)
    anchor1 = m.add_point("fixed", (80.0, 0.0, -50.0))
    anchor2 = m.add_point("fixed", (-80.0, 0.0, -50.0))
    fair = m.add_point("body", (2.0, 0.0, 0.0), body=b)
    m.add_line("chain", anchor1, fair, L=95.0, N=6)
    m.add_line("chain", anchor2, rb, L=90.0, N=6)
    return m


def test_rods_and_bodies(tmp_path):
    s = System(_rigid_model())
    ds = moorline.simulate(s, 0.2, dt_out=0.1, progress=False, solve_ic=False)
    write_vtk(ds, tmp_path, base="rig", axis_length=2.0)
    k = 2
    r = _read_vtp(tmp_path / "rig_rods_2.vtp")
    np.testing.assert_array_equal(r["points"], ds.rod_end_position.isel(time=k).values.reshape(-1, 3))
    np.testing.assert_array_equal(r["CellData"]["force"], ds.rod_force.isel(time=k).values[:, :3])
    b = _read_vtp(tmp_path / "rig_bodies_2.vtp")
    pose = ds.body_pose.isel(time=k).values[0]
    R = rotation_xyz(pose[3:])
    np.testing.assert_array_equal(b["points"][0], pose[:3])
    np.testing.assert_allclose(b["points"][1:] - pose[:3], 2.0 * R.T, rtol=0, atol=1e-12)
    assert [c.tolist() for c in b["Lines"]] == [[0, 1], [0, 2], [0, 3]]
    # the deck pose: yaw 30 deg turns body x toward +y
    np.testing.assert_allclose(b["points"][1] - b["points"][0], 2.0 * rotation_xyz(np.radians([10, 0, 30]))[:, 0],
                               atol=1e-9)
    blocks = [d.get("name") for d in ET.parse(tmp_path / "rig_2.vtm").getroot().iter("DataSet")]
    assert blocks == ["lines", "points", "rods", "bodies"]


def test_no_node_data_is_refused(tmp_path):
    s = System.from_file(EXAMPLE)
    ds = moorline.simulate(s, 0.1, dt_out=0.1, progress=False, solve_ic=False, record_nodes=False)
    with pytest.raises(ValueError, match="no node positions"):
        write_vtk(ds, tmp_path)


def test_cli_run_vtk_and_vtk_command(tmp_path):
    deck = tmp_path / EXAMPLE.name
    deck.write_text(EXAMPLE.read_text())
    assert cli_main(["run", str(deck), "--duration", "0.4", "--dt-out", "0.2", "--no-ic", "--vtk",
                     "--quiet-progress"]) == 0
    entries = _collection(tmp_path / "catenary_3line_vtk" / "catenary_3line.pvd")
    assert [t for t, _ in entries] == pytest.approx([0.0, 0.2, 0.4])
    out = tmp_path / "again"
    assert cli_main(["vtk", str(tmp_path / "catenary_3line.nc"), "--out", str(out), "--every", "2"]) == 0
    assert [t for t, _ in _collection(out / "catenary_3line.pvd")] == pytest.approx([0.0, 0.4])
    assert cli_main(["vtk", str(tmp_path / "missing.nc")]) == 2


@pytest.mark.oracle
def test_same_geometry_as_moordyns_own_vtk(tmp_path):
    """The line files hold the nodes where MoorDyn's own SaveLineVTK puts them (same deck, both
    codes from MoorDyn's initial-condition method, ICNewton 0), and decode with the same reader:
    MoorDyn writes the same layout (XML PolyData, base64, UInt64 header, nodes as points)."""
    md = pytest.importorskip("moordyn")
    from moorline.io import read_deck
    from moorline.results import Recorder

    src = Path(__file__).resolve().parents[3] / "shared" / "public_decks" / "FloatingArrayDesign+MoorDyn" / \
        "example" / "lines.txt"
    if not src.is_file():
        pytest.skip("../shared/public_decks not available")
    deck = tmp_path / "lines.txt"
    deck.write_text(src.read_text())
    s = md.Create(str(deck))
    try:
        x0 = np.concatenate([md.GetPointPos(md.GetPoint(s, i)) for i in range(1, md.GetNumberPoints(s) + 1)
                             if md.GetPointType(md.GetPoint(s, i)) == md.POINT_TYPE_COUPLED])
        md.Init(s, x0, np.zeros_like(x0))
        nl = md.GetNumberLines(s)
        for i in range(1, nl + 1):
            assert md.SaveLineVTK(md.GetLine(s, i), str(tmp_path / f"md_line{i}.vtp")) == 0
    finally:
        md.Close(s)
    model = read_deck(deck)
    model.options.ICNewton = 0
    system = System(model)
    system.init(x0, np.zeros_like(x0))
    rec = Recorder(system)
    rec.record()
    ds = rec.to_dataset()
    write_vtk(ds, tmp_path / "ml", base="lines")
    ours = _read_vtp(tmp_path / "ml" / "lines_lines_0.vtp")
    for i in range(1, nl + 1):
        theirs = _read_vtp(tmp_path / f"md_line{i}.vtp")
        mine = ours["points"][ds.node_line.values == i]
        assert theirs["points"].shape == mine.shape
        # the two initial-condition solves stop at the same state (measured 3.7e-7 m; their tensions
        # agree to 5e-8 relative, docs/public_decks.md); 1e-5 m leaves room for round-off in the solves
        np.testing.assert_allclose(mine, theirs["points"], rtol=0, atol=1e-5)
        assert len(theirs["Lines"]) == len(mine) - 1  # MoorDyn: one cell per segment too
