"""Tests of moorline.io.outputs: channel names, channel values, per-line files and .out formatting."""

from __future__ import annotations

import logging
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from moorline.errors import DeckError
from moorline.io import outputs as mo
from moorline.io.outputs import (
    Channel,
    OutputRecorder,
    decompose,
    evaluate,
    has_line_file,
    line_file_columns,
    line_file_values,
    output_due,
    parse_channels,
    write_line_out,
    write_main_out,
)
from moorline.model import Environment, Model

TIME_RE = r"[ ]{1,}-?\d+\.\d{4}"                         # right-aligned %10.4f
VALUE_RE = r"[ -]\d\.\d{7}e[+-]\d{2,3}"                   # %20.7e: 14-15 visible chars


def build_model(flags2: str = "pvtcsdKb") -> Model:
    """Two lines joined by a free clump: fixed P1 -(line 1, N=6)- free P3 -(line 2, N=10)- coupled P2."""
    m = Model(env=Environment(depth=200.0))
    m.add_line_type("rope", d=0.1, w=10.0, EA=1e7, BA=-0.5, Cd=1.2, Ca=1.0, CdAx=0.1, CaAx=0.0)
    a = m.add_point("fixed", (100.0, 0.0, -100.0))
    b = m.add_point("coupled", (0.0, 0.0, -10.0))
    c = m.add_point("free", (60.0, 0.0, -60.0), m=100.0, V=0.05)
    m.add_line("rope", a, c, L=60.0, N=6, outputs="pt")
    m.add_line("rope", c, b, L=80.0, N=10, outputs=flags2)
    return m


@pytest.fixture(scope="module")
def system():
    """An initialised and once-stepped system (so velocities and damping forces are not all zero)."""
    from moorline.system import System

    s = System(build_model(), dtM=0.002)
    s.init()
    s.step(None, np.array([0.5, 0.0, 0.0]), 0.0, 0.1)
    return s


# ------------------------------------------------------------------------------------------ decompose

@pytest.mark.parametrize("word, pieces", [
    ("Body1Pinned", ["BODY", "1", "PINNED"]),
    ("R2A", ["R", "2", "A"]),
    ("L1N5T", ["L", "1", "N", "5", "T"]),
    ("FairTen3", ["FAIRTEN", "3"]),
    ("12", ["", "12"]),
    ("L1N5T2X", ["L", "1", "N", "5", "T2X"]),     # everything after the 4th switch goes to let3
    ("a_b1", ["A_B", "1"]),                        # other characters stay in the current piece
    ("Con3vY", ["CON", "3", "VY"]),
    ("pOiNt12vz", ["POINT", "12", "VZ"]),
])
def test_decompose(word, pieces):
    assert decompose(word) == pieces


# ------------------------------------------------------------------------------------------ parsing

def _one(name, model=None):
    chans = parse_channels([name], model or build_model())
    assert len(chans) == 1, name
    return chans[0]


@pytest.mark.parametrize("name, kind, index, node, quantity, unit", [
    ("FairTen2", "line", 1, 10, "TB", "N"),
    ("AnchTen1", "line", 0, 0, "TA", "N"),
    ("L2N3T", "line", 1, 3, "T", "N"),
    ("Line2N3T", "line", 1, 3, "T", "N"),
    ("L2N3TEN", "line", 1, 3, "T", "N"),
    ("L1NAT", "line", 0, 0, "T", "N"),
    ("L1NBT", "line", 0, 6, "T", "N"),
    ("L1NBPX", "line", 0, 6, "PX", "m"),
    ("L2T", "line", 1, 0, "T", "N"),
    ("L2TenB", "line", 1, 0, "TB", "N"),
    ("L2TENA", "line", 1, 0, "TA", "N"),
    ("L2TA", "line", 1, 0, "TA", "N"),
    ("L2N4TB", "line", 1, 4, "TB", "N"),
    ("L2N10PZ", "line", 1, 10, "PZ", "m"),
    ("L2N0VY", "line", 1, 0, "VY", "m/s"),
    ("L1N2FX", "line", 0, 2, "FX", "N"),
    ("P2PX", "point", 1, None, "PX", "m"),
    ("Point3VZ", "point", 2, None, "VZ", "m/s"),
    ("P3AX", "point", 2, None, "AX", "m/s^2"),
    ("P3AY", "point", 2, None, "AY", "m/s^2"),
    ("P1T", "point", 0, None, "T", "N"),
    ("P1TEN", "point", 0, None, "T", "N"),
    ("P2FZ", "point", 1, None, "FZ", "N"),
])
def test_parse_patterns(name, kind, index, node, quantity, unit):
    ch = _one(name)
    assert ch == Channel(name, unit, kind, index, quantity, node)


@pytest.mark.parametrize("q, unit", [("PX", "m"), ("PY", "m"), ("PZ", "m"), ("VX", "m/s"), ("VY", "m/s"),
                                     ("VZ", "m/s"), ("FX", "N"), ("FY", "N"), ("FZ", "N"), ("T", "N"),
                                     ("TEN", "N"), ("TA", "N"), ("TENA", "N"), ("TB", "N"), ("TENB", "N")])
def test_every_line_quantity(q, unit):
    ch = _one(f"L2N5{q}")
    assert ch.unit == unit and ch.node == 5
    assert ch.quantity == {"TEN": "T", "TENA": "TA", "TENB": "TB"}.get(q, q)


@pytest.mark.parametrize("q, unit", [("PX", "m"), ("PY", "m"), ("PZ", "m"), ("VX", "m/s"), ("VY", "m/s"),
                                     ("VZ", "m/s"), ("AX", "m/s^2"), ("AY", "m/s^2"), ("AZ", "m/s^2"),
                                     ("FX", "N"), ("FY", "N"), ("FZ", "N"), ("T", "N"), ("TEN", "N")])
def test_every_point_quantity(q, unit):
    ch = _one(f"Point3{q}")
    assert ch.unit == unit and ch.kind == "point" and ch.index == 2


def test_case_insensitive_and_name_kept_as_typed():
    chans = parse_channels(["fairten1", "FAIRTEN1", "l2n3t", "LiNe2n3T", "point2fx", "p2Fx"], build_model())
    assert [c.name for c in chans] == ["fairten1", "FAIRTEN1", "l2n3t", "LiNe2n3T", "point2fx", "p2Fx"]
    assert chans[0].quantity == chans[1].quantity == "TB"
    assert (chans[2].node, chans[2].quantity) == (chans[3].node, chans[3].quantity) == (3, "T")
    assert (chans[4].kind, chans[4].quantity) == (chans[5].kind, chans[5].quantity) == ("point", "FX")


def test_parse_accepts_a_system_or_a_model(system):
    assert parse_channels(["L2N3T"], system) == parse_channels(["L2N3T"], system.model)


@pytest.mark.parametrize("name, words", [
    ("FairTen3", ["no line 3", "2 lines"]),
    ("AnchTen0", ["no line 0"]),
    ("L3N1T", ["no line 3"]),
    ("Line9PX", ["no line 9"]),
    ("L1N7T", ["no node 7", "line 1", "0 to 6"]),
    ("L2N11PX", ["no node 11", "line 2"]),
    ("P4PX", ["no point 4", "3 points"]),
    ("Point0VX", ["no point 0"]),
    ("R1PX", ["no rod 1"]),
    ("Rod2NAPX", ["no rod 2"]),
    ("R1N3FX", ["no rod 1"]),
    ("B1PX", ["no body 1"]),
    ("Body2RX", ["no body 2"]),
])
def test_missing_objects_raise_deck_error(name, words):
    with pytest.raises(DeckError) as e:
        parse_channels(["FairTen1", name], build_model())
    assert repr(name) in str(e.value)
    for w in words:
        assert w in str(e.value)


def test_deck_error_names_the_deck_file():
    m = build_model()
    m.source = Path("/some/where/mooring.dat")
    with pytest.raises(DeckError) as e:
        parse_channels(["L5T"], m)
    assert "mooring.dat" in str(e.value) and e.value.file.endswith("mooring.dat")


@pytest.mark.parametrize("name", ["END", "Con3vY", "L1QQ", "L1N2", "XYZ1", "FairTen", "L1TA5", "P1N2T",
                                  "Time"])
def test_uninterpretable_names_are_skipped_with_warning(name, caplog):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        chans = parse_channels(["FairTen1", name, "AnchTen1"], build_model())
    assert [c.name for c in chans] == ["FairTen1", "AnchTen1"]
    assert any(name in r.getMessage() and r.name == "moorline.io" for r in caplog.records)


@pytest.mark.parametrize("name", ["L1N2AX", "L1RX", "P1RX", "P1TA", "P2MX", "P1SUB"])
def test_known_code_undefined_for_object_gives_zero_column(name, caplog, system):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        ch = _one(name)
    assert ch.quantity == "ZERO"
    assert any(name in r.getMessage() for r in caplog.records)
    assert evaluate([ch], system)[0] == 0.0


def test_units_of_undefined_codes():
    assert _one("P1RX").unit == "deg"
    assert _one("P1MX").unit == "N*m"
    assert _one("P1SUB").unit == "(frac)"


# ------------------------------------------------------------------------------------------ values

def test_evaluated_values_match_views(system):
    L1, L2 = system.lines
    P1, P2, P3 = system.points
    names = ["FairTen1", "AnchTen1", "FairTen2", "L2N3T", "L2N0T", "L2NBT", "L2N10T", "L2T", "L2TA", "L2TB",
             "L2N5TB", "L2N4PX", "L2N4PY", "L2N4PZ", "L2N6VX", "L2N6VZ", "L2N7FX", "L2N7FZ", "L1N3FY",
             "P2FX", "P2FY", "P2FZ", "P3PX", "P3PZ", "P3VX", "P3AX", "P3AZ", "P3T", "P1T"]
    v = dict(zip(names, evaluate(parse_channels(names, system), system), strict=True))
    nf = np.linalg.norm
    assert v["FairTen1"] == pytest.approx(nf(L1.end_force("B")), rel=1e-14)
    assert v["AnchTen1"] == pytest.approx(nf(L1.end_force("A")), rel=1e-14)
    assert v["FairTen2"] == pytest.approx(nf(L2.end_force("B")), rel=1e-14)
    assert v["L2N3T"] == pytest.approx(L2.node_tensions()[3], rel=1e-14)
    assert v["L2N0T"] == v["L2T"] == v["L2TA"] == pytest.approx(nf(L2.node_forces()[0]), rel=1e-14)
    assert v["L2NBT"] == v["L2N10T"] == v["L2TB"] == v["L2N5TB"] == pytest.approx(nf(L2.node_forces()[10]),
                                                                                  rel=1e-14)
    r, u, f = L2.node_positions(), L2.node_velocities(), L2.node_forces()
    assert (v["L2N4PX"], v["L2N4PY"], v["L2N4PZ"]) == (r[4, 0], r[4, 1], r[4, 2])
    assert (v["L2N6VX"], v["L2N6VZ"]) == (u[6, 0], u[6, 2])
    assert (v["L2N7FX"], v["L2N7FZ"]) == (f[7, 0], f[7, 2])
    assert v["L1N3FY"] == L1.node_forces()[3, 1]
    assert (v["P2FX"], v["P2FY"], v["P2FZ"]) == tuple(P2.force())
    assert (v["P3PX"], v["P3PZ"]) == (P3.position()[0], P3.position()[2])
    assert v["P3VX"] == P3.velocity()[0]
    assert (v["P3AX"], v["P3AZ"]) == (P3.acceleration()[0], P3.acceleration()[2])
    assert v["P3T"] == pytest.approx(nf(P3.force()), rel=1e-14)
    assert v["P1T"] == pytest.approx(nf(P1.force()), rel=1e-14)
    # sanity: the system is loaded, so the values are not trivially zero
    assert v["FairTen1"] > 10 and v["FairTen2"] > 10 and v["L2N3T"] > 10 and abs(v["P3VX"]) > 0


def test_evaluate_no_channels(system):
    assert evaluate([], system).shape == (0,)


# ------------------------------------------------------------------------------------------ file format

def _rows(path):
    text = Path(path).read_text()
    assert text.endswith("\n")
    return text.split("\n")[:-1]


def test_main_file_exact_text(tmp_path):
    chans = parse_channels(["FairTen1", "P2PX", "L2N3VZ", "P3AX"], build_model())
    p = write_main_out(tmp_path / "x.out", chans, [0.0, 0.125], [[770687.24, -5.0, 3.7963800e-09, 0.0],
                                                                 [1.0, 2.5e-300, -0.0, 12345.678]])
    expected = (
        "      Time            FairTen1                P2PX              L2N3VZ                P3AX\n"
        "       (s)                   N                   m                 m/s               m/s^2\n"
        "    0.0000       7.7068724e+05      -5.0000000e+00       3.7963800e-09       0.0000000e+00\n"
        "    0.1250       1.0000000e+00      2.5000000e-300      -0.0000000e+00       1.2345678e+04\n"
    )
    assert p.read_text() == expected


def test_main_file_widths_by_regex(tmp_path, system):
    names = ["FairTen1", "AnchTen2", "L2N3T", "P3PZ", "P2FX"]
    chans = parse_channels(names, system)
    times = [0.0, 0.5, 12.25, 1234.5]
    vals = np.array([evaluate(chans, system) * (k + 1) for k in range(4)])
    rows = _rows(write_main_out(tmp_path / "m.out", chans, times, vals))
    assert len(rows) == 2 + 4
    assert rows[0] == f"{'Time':>10}" + "".join(f"{n:>20}" for n in names)
    assert rows[1] == f"{'(s)':>10}" + "".join(f"{u:>20}" for u in ["N", "N", "N", "m", "N"])
    row_re = re.compile(r"^(.{10})" + r"(.{20})" * len(names) + r"$")
    for k, row in enumerate(rows[2:]):
        m = row_re.match(row)
        assert m, row
        assert re.fullmatch(TIME_RE, m.group(1)) and float(m.group(1)) == times[k]
        for j in range(len(names)):
            assert re.fullmatch(r" *" + VALUE_RE, m.group(j + 2)), m.group(j + 2)
        np.testing.assert_allclose([float(m.group(j + 2)) for j in range(len(names))], vals[k], rtol=1e-7)


def test_write_units_zero_omits_units_row(tmp_path):
    chans = parse_channels(["FairTen1"], build_model())
    rows = _rows(write_main_out(tmp_path / "a.out", chans, [0.0, 1.0], [[1.0], [2.0]], write_units=False))
    assert len(rows) == 3
    assert rows[0].split() == ["Time", "FairTen1"]
    assert rows[1] == "    0.0000       1.0000000e+00"


def test_no_channels_writes_time_only(tmp_path):
    rows = _rows(write_main_out(tmp_path / "e.out", [], [0.0, 0.1], np.zeros((2, 0))))
    assert rows == ["      Time", "       (s)", "    0.0000", "    0.1000"]


def test_writer_checks_shapes(tmp_path):
    chans = parse_channels(["FairTen1", "AnchTen1"], build_model())
    with pytest.raises(ValueError):
        write_main_out(tmp_path / "bad.out", chans, [0.0, 1.0], [[1.0, 2.0]])
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------------------------------ per-line files

def _expected_line_titles(N, flags):
    nodes = range(N + 1)
    segs = range(1, N + 1)
    blocks = {
        "p": [f"Node{i}p{c}" for i in nodes for c in "xyz"],
        "K": [f"Node{i}Ku" for i in nodes],
        "v": [f"Node{i}v{c}" for i in nodes for c in "xyz"],
        "U": [f"Node{i}U{c}" for i in nodes for c in "xyz"],
        "D": [f"Node{i}D{c}" for i in nodes for c in "xyz"],
        "V": [f"Node{i}V{c}" for i in nodes for c in "xyz"],
        "t": [f"Seg{j}Te" for j in segs],
        "c": [f"Seg{j}c{c}" for j in segs for c in "xyz"],
        "s": [f"Seg{j}St" for j in segs],
        "d": [f"Seg{j}dSt" for j in segs],
        "b": [f"Node{i}b{c}" for i in nodes for c in "xyz"],
    }
    return [t for f in "pKvUDVtcsdb" if f in flags for t in blocks[f]]


def test_line_file_columns_pvtcsdKb():
    m = build_model("pvtcsdKb")
    titles, units = line_file_columns(m, 1)
    N = 10
    counts = {"p": 3 * (N + 1), "K": N + 1, "v": 3 * (N + 1), "t": N, "c": 3 * N, "s": N, "d": N,
              "b": 3 * (N + 1)}
    assert len(titles) == len(units) == sum(counts.values()) == 170
    assert titles == _expected_line_titles(N, "pvtcsdKb")
    # fixed block order p, K, v, t, c, s, d, b
    starts = [titles.index(t) for t in ("Node0px", "Node0Ku", "Node0vx", "Seg1Te", "Seg1cx", "Seg1St",
                                        "Seg1dSt", "Node0bx")]
    assert starts == sorted(starts)
    assert titles[:4] == ["Node0px", "Node0py", "Node0pz", "Node1px"]
    assert titles[-1] == "Node10bz" and "Seg0Te" not in titles and "Seg10Te" in titles
    unit_of = dict(zip(titles, units, strict=True))
    assert (unit_of["Node3py"], unit_of["Node3Ku"], unit_of["Node3vz"], unit_of["Seg2Te"], unit_of["Seg2cy"],
            unit_of["Seg2St"], unit_of["Seg2dSt"], unit_of["Node3bz"]) == \
        ("(m)", "(1/m)", "(m/s)", "(N)", "(N)", "(-)", "(-/s)", "(N)")


def test_line_file_all_flags_and_order_independent():
    a = line_file_columns(build_model("pvUDVKctsdb"), 1)
    b = line_file_columns(build_model("bdstcKVDUvp"), 1)
    assert a == b
    assert a[0] == _expected_line_titles(10, "pvUDVKctsdb")
    assert len(a[0]) == 6 * 3 * 11 + 11 + 3 * 10 + 3 * 10 == 269     # p v U D V b; K; t s d; c
    unit_of = dict(zip(*a, strict=True))
    assert unit_of["Node0Ux"] == "(m/s)" and unit_of["Node0Dx"] == unit_of["Node0Vx"] == "(N)"


@pytest.mark.parametrize("flags, wanted", [("-", False), ("", False), ("b", False), ("P", False),
                                           ("pb", True), ("U", True), ("V", True), ("d", True), ("K", True)])
def test_line_file_created_only_for_trigger_flags(flags, wanted):
    m = build_model(flags)
    assert has_line_file(m, 1) is wanted
    titles, units = line_file_columns(m, 1)
    assert bool(titles) is wanted and len(titles) == len(units)


def test_line_file_values_match_views(system):
    L2 = system.lines[1]
    titles, _ = line_file_columns(system, 1)
    vals = line_file_values(system, 1)
    assert vals.shape == (len(titles),)
    col = dict(zip(titles, vals, strict=True))
    assert col["Node4pz"] == L2.node_positions()[4, 2]
    assert col["Node7Ku"] == L2.node_curvatures()[7]
    assert col["Node2vx"] == L2.node_velocities()[2, 0]
    assert col["Seg3Te"] == L2.segment_elastic_tensions()[2]
    assert col["Seg10cz"] == L2.segment_damping_forces()[9, 2]
    assert col["Seg1St"] == L2.segment_strains()[0]
    assert col["Seg5dSt"] == L2.segment_strain_rates()[4]
    assert col["Node10by"] == L2.node_seabed_forces()[10, 1]
    # line 1 has flags "pt"
    t1, _ = line_file_columns(system, 0)
    v1 = dict(zip(t1, line_file_values(system, 0), strict=True))
    assert len(t1) == 3 * 7 + 6 and v1["Seg6Te"] == system.lines[0].segment_elastic_tensions()[5]


def test_line_file_viv_and_water_columns():
    from moorline.system import System

    m = build_model("UDV")
    s = System(m, dtM=0.002)
    s.init(solve_ic=False)
    titles, _ = line_file_columns(s, 1)
    col = dict(zip(titles, line_file_values(s, 1), strict=True))
    assert all(col[f"Node{i}V{c}"] == 0.0 for i in range(11) for c in "xyz")      # no VIV in this version
    assert col["Node3Dz"] == s.lines[1].node_hydro_forces()[3, 2]
    assert col["Node3Ux"] == s.lines[1].node_water_velocities()[3, 0]


def test_write_line_out_format(tmp_path, system):
    titles, units = line_file_columns(system, 0)
    vals = np.vstack([line_file_values(system, 0)] * 3)
    rows = _rows(write_line_out(tmp_path / "b_Line1.out", titles, units, [0.0, 0.1, 0.2], vals))
    assert rows[0] == f"{'Time':>10}" + "".join(f"{t:>20}" for t in titles)
    assert rows[1] == f"{'(s)':>10}" + "".join(f"{u:>20}" for u in units)
    assert rows[1].split()[1:] == ["(m)"] * 21 + ["(N)"] * 6
    for row in rows[2:]:
        assert len(row) == 10 + 20 * len(titles)
        assert re.fullmatch(TIME_RE + r"(?: *" + VALUE_RE + r")+", row)
    no_units = _rows(write_line_out(tmp_path / "c_Line1.out", titles, units, [0.0], vals[:1],
                                    write_units=False))
    assert len(no_units) == 2 and no_units[1] == rows[2]


# ------------------------------------------------------------------------------------------ recorder

def test_recorder_writes_all_files(tmp_path, system):
    system.model.outputs = ["FairTen1", "END", "L2N3T", "P3PZ"]
    rec = OutputRecorder(system)
    assert [c.name for c in rec.channels] == ["FairTen1", "L2N3T", "P3PZ"]
    assert sorted(rec.line_columns) == [0, 1]
    rec.record()
    rec.record()
    paths = rec.write(tmp_path, "moor")
    assert [p.name for p in paths] == ["moor.out", "moor_Line1.out", "moor_Line2.out"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["moor.out", "moor_Line1.out", "moor_Line2.out"]
    main = _rows(paths[0])
    assert main[0].split() == ["Time", "FairTen1", "L2N3T", "P3PZ"]
    assert main[1].split() == ["(s)", "N", "N", "m"]
    assert len(main) == 4
    fair = np.linalg.norm(system.lines[0].end_force("B"))
    assert float(main[2].split()[1]) == pytest.approx(fair, rel=1e-7)
    l2 = _rows(paths[2])
    assert len(l2[0].split()) == 1 + 170 and len(l2) == 4
    assert rec.main_values.shape == (2, 3) and rec.line_values(1).shape == (2, 170)


def test_recorder_write_units_from_options(tmp_path, system):
    system.model.outputs = ["FairTen1"]
    system.model.options.WriteUnits = 0
    try:
        rec = OutputRecorder(system)
        rec.record()
        paths = rec.write(tmp_path, "nu")
    finally:
        system.model.options.WriteUnits = 1
    for p in paths:
        rows = _rows(p)
        assert len(rows) == 2 and "(s)" not in rows[1]


def test_recorder_bad_channel_raises_at_construction(system):
    system.model.outputs = ["FairTen1", "L7T"]
    with pytest.raises(DeckError, match="no line 7"):
        OutputRecorder(system)


def test_atomic_write_leaves_no_temp_and_keeps_old_file(tmp_path, system, monkeypatch):
    system.model.outputs = ["FairTen1"]
    rec = OutputRecorder(system)
    rec.record()
    rec.write(tmp_path, "at")
    before = {p.name: p.read_text() for p in tmp_path.iterdir()}
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".") or p.suffix == ".tmp"]
    rec.record()

    def boom(src, dst):
        raise OSError("disk full")

    monkeypatch.setattr(mo.os, "replace", boom)
    with pytest.raises(OSError, match="disk full"):
        rec.write(tmp_path, "at")
    after = {p.name: p.read_text() for p in tmp_path.iterdir()}
    assert after == before                                # old complete files untouched, no temp left


def test_written_files_have_normal_permissions(tmp_path, system):
    system.model.outputs = ["FairTen1"]
    rec = OutputRecorder(system)
    rec.record()
    for p in rec.write(tmp_path / "sub", "perm"):
        assert p.stat().st_mode & 0o044                   # readable by others (not mkstemp's 0600)


# ------------------------------------------------------------------------------------------ output interval

def test_output_due():
    assert output_due(0.0, 0.0, 0.0) and output_due(0.3, 0.1, 0.0)
    assert not output_due(0.0, 0.0, 0.5)                  # no t = 0 row with dtOut > 0
    t, rows = 0.0, []
    for _ in range(20):
        t += 0.1
        if output_due(t, 0.1, 0.3):
            rows.append(round(t, 10))
    assert rows == [0.3, 0.6, 0.9, 1.2, 1.5, 1.8]
    assert output_due(1.0, 1.0, 0.25)                     # several multiples in one step: one row
    assert not output_due(0.2, 0.1, 0.25) and output_due(0.3, 0.1, 0.25)


def test_record_if_due(system):
    system.model.outputs = ["FairTen1"]
    system.model.options.dtOut = 0.5
    try:
        rec = OutputRecorder(system)
    finally:
        system.model.options.dtOut = 0.0
    assert system.t == pytest.approx(0.1)
    assert rec.record_if_due(0.1) is False                # (0, 0.1] holds no multiple of 0.5
    assert rec.record_if_due(0.2) is True and len(rec.times) == 1   # (-0.1, 0.1] holds 0


# ------------------------------------------------------------------------------------------ MoorDyn oracle

_DECK = """MoorDyn output-format oracle
---------------------- LINE TYPES -----------------------------------
TypeName   Diam    Mass/m     EA     BA/-zeta    EI    Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)    (N-s/-)   (N-m^2) (-)    (-)    (-)     (-)
rope       0.1     10.0       1e7    -0.5       0      1.2    1.0    0.1     0.0
---------------------- POINTS ---------------------------------------
ID  Attachment  X       Y     Z      Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)   (m)    (kg)   (m^3)   (m^2)  (-)
1     Fixed     100     0     -50    0      0       0      0
2     Coupled   0       0     -10    0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    rope       1        2        100.0     4        pvUDVKctsdb
---------------------- OPTIONS --------------------------------------
0.001    dtM
100      WtrDpth
---------------------- OUTPUTS --------------------------------------
FairTen1
AnchTen1
L1N2T
L1NAT
L1TenB
P2FX
Point1PZ
L1N3PX
Con3vY
END
------------------------- need this line ----------------------------
"""


@pytest.mark.oracle
def test_headers_identical_to_moordyn(tmp_path):
    moordyn = pytest.importorskip("moordyn")
    from moorline.io import read_deck
    from moorline.system import System

    md_dir, ml_dir = tmp_path / "md", tmp_path / "ml"
    md_dir.mkdir()
    (md_dir / "t.txt").write_text(_DECK)
    x, v = np.array([0.0, 0.0, -10.0]), np.zeros(3)
    h = moordyn.Create(str(md_dir / "t.txt"))
    moordyn.Init(h, x, v)
    for k in range(3):
        moordyn.Step(h, x, v, 0.1 * k, 0.1)
    moordyn.Close(h)

    s = System(read_deck(md_dir / "t.txt"))
    s.init()
    rec = OutputRecorder(s)
    rec.record()
    for k in range(3):
        s.step(x, v, 0.1 * k, 0.1)
        rec.record_if_due(0.1)
    rec.write(ml_dir, "t")
    for name in ("t.out", "t_Line1.out"):
        md, ml = _rows(md_dir / name), _rows(ml_dir / name)
        assert md[:2] == ml[:2], name                       # titles and units, byte for byte
        assert len(md) == len(ml) and [len(r) for r in md] == [len(r) for r in ml]
        assert [r[:10] for r in md] == [r[:10] for r in ml]
    a = np.loadtxt(md_dir / "t.out", skiprows=2)
    b = np.loadtxt(ml_dir / "t.out", skiprows=2)
    np.testing.assert_allclose(b[:, 1:6], a[:, 1:6], rtol=1e-3)   # tensions of a static line
    shutil.rmtree(md_dir)


# ------------------------------------------------------------------------------------------ rods and bodies

def build_rigid_model() -> Model:
    """A free body (rotated 30 deg in yaw) carrying a body point, a body-fixed rod through the
    surface with output flags, and a slack line from the body point to an anchor."""
    m = Model(env=Environment(depth=100.0))
    m.add_line_type("rope", d=0.1, w=10.0, EA=1e7, BA=-0.5, Cd=1.2, Ca=1.0, CdAx=0.1, CaAx=0.0)
    m.add_rod_type("can", d=1.0, w=200.0, Cd=0.8, Ca=1.0, CdEnd=0.6, CaEnd=0.5)
    b = m.add_body("free", (0.0, 0.0, -5.0), (0.0, 0.0, 30.0), m=5e3, I=(1e4, 1e4, 2e4), V=6.0, CdA=(4.0,) * 6,
                   Ca=(1.0,) * 3)
    m.add_rod("can", "body", (0.0, 0.0, -1.0), (0.0, 0.0, 7.0), N=4, outputs="pvfWBXYAaPb", body=b)
    fair = m.add_point("body", (2.0, 0.0, -1.0), body=b)
    anchor = m.add_point("fixed", (80.0, 0.0, -100.0))
    m.add_line("rope", anchor, fair, L=125.0, N=10)
    m.outputs = ["Body1PX", "B1RZ", "B1FZ", "B1MY", "B1T", "R1PZ", "R1TB", "R1FZ", "R1RX", "R1SUB", "R1N4PZ",
                 "Rod1NBFX", "R1NAVX"]
    return m


@pytest.fixture(scope="module")
def rigid_system():
    from moorline.system import System

    s = System(build_rigid_model(), dtM=0.001, scheme="RK4")
    s.init(solve_ic=False)
    s.advance_to(0.2, s._motion)
    return s


def test_rod_and_body_channels_match_views(rigid_system):
    s = rigid_system
    ch = parse_channels(s.model.outputs, s)
    assert [(c.kind, c.node) for c in ch][:6] == [("body", None)] * 5 + [("rod", None)]
    assert (ch[10].kind, ch[10].node, ch[11].node, ch[12].node) == ("rod", 4, 4, 0)
    v = evaluate(ch, s)
    b, r = s.bodies[0], s.rods[0]
    want = [b.position()[0], np.degrees(b.angles()[2]), b.force()[2], b.force()[4], np.linalg.norm(b.force()[:3]),
            r.end_positions()[0, 2], r.end_tensions()[1], r.force()[2], np.degrees(r.roll_pitch()[0]),
            r.submergence(), r.node_positions()[4, 2], r.node_forces()[4, 0], r.node_velocities()[0, 0]]
    np.testing.assert_allclose(v, want, rtol=1e-12, atol=1e-12)
    assert v[1] == pytest.approx(30.0, abs=0.5)  # the yaw of the deck pose, barely changed after 0.2 s
    assert 0.5 < v[9] < 1.0  # the rod pierces the surface (z from -6 to +2)


def test_rod_file_columns_and_values(rigid_system):
    s = rigid_system
    titles, units = mo.rod_file_columns(s, 0)
    assert len(titles) == 11 * 3 * 5 and titles[:3] == ["Node0px", "Node0py", "Node0pz"]
    assert titles[15 * 2] == "Node0fx" and units[0] == "(m)" and units[15] == "(m/s)" and units[30] == "(N)"
    vals = mo.rod_file_values(s, 0)
    r = s.rods[0]
    comps = r.node_force_components()
    np.testing.assert_array_equal(vals[:15], r.node_positions().ravel())
    np.testing.assert_array_equal(vals[45:60], comps["weight"].ravel())
    # the node loads sum to the net node force (lines included at the end nodes: none here)
    total = sum(comps.values())
    np.testing.assert_allclose(total, r.node_forces(), rtol=0, atol=1e-9 * np.abs(total).max())


def test_recorder_writes_rod_and_body_files(tmp_path, rigid_system):
    rec = OutputRecorder(rigid_system)
    rec.record()
    files = [p.name for p in rec.write(tmp_path, "rig")]
    assert files == ["rig.out", "rig_Rod1.out", "rig_Body1.out"]
    body = (tmp_path / "rig_Body1.out").read_text().splitlines()
    assert body[0].split("\t") == ["Time", "x", "y", "z", "roll", "pitch", "yaw"]
    row = [float(x) for x in body[2].split("\t")]
    assert row[6] == pytest.approx(np.degrees(rigid_system.bodies[0].angles()[2]), rel=1e-7)
