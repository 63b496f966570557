"""Reading and writing MoorDyn v2 decks (moorline.io): conformance decks and inline decks."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
import pytest

from moorline.errors import DeckError
from moorline.io import read_curve, read_deck, read_deck_text, write_deck
from moorline.io.lexer import lex, parse_number, parse_whole, section_name, tokenize
from moorline.model import Attachment, Bathymetry, BodyKind, Curve, Model, PointKind, RodKind

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
INPUTS = SHARED / "conformance" / "inputs"


def conformance_deck(rel: str) -> Path:
    path = INPUTS / rel
    if not path.is_file():
        pytest.skip(f"conformance deck {path} not available")
    return path


def _same_value(a, b):
    if isinstance(a, Curve) or isinstance(b, Curve):
        return (isinstance(a, Curve) and isinstance(b, Curve) and np.array_equal(a.x, b.x)
                and np.array_equal(a.y, b.y))
    return a == b


def assert_models_equal(a: Model, b: Model):
    """Field-by-field comparison (dataclass == does not work on numpy arrays)."""
    assert list(a.line_types) == list(b.line_types)
    for name, ta in a.line_types.items():
        tb = b.line_types[name]
        for f in ("name", "d", "w", "EA", "BA", "EI", "Cd", "Ca", "CdAx", "CaAx", "Cl", "dF", "cF"):
            assert _same_value(getattr(ta, f), getattr(tb, f)), (name, f, getattr(ta, f), getattr(tb, f))
    assert len(a.points) == len(b.points)
    for pa, pb in zip(a.points, b.points, strict=True):
        assert pa.kind == pb.kind
        assert np.array_equal(pa.r, pb.r)
        assert np.array_equal(pa.F_ext, pb.F_ext)
        assert (pa.m, pa.V, pa.CdA, pa.Ca, pa.body) == (pb.m, pb.V, pb.CdA, pb.Ca, pb.body)
    assert a.lines == b.lines
    ea, eb = vars(a.env).copy(), vars(b.env).copy()
    ba, bb = ea.pop("bathymetry"), eb.pop("bathymetry")
    assert ea == eb
    assert (ba is None) == (bb is None)
    if ba is not None:
        assert all(np.array_equal(getattr(ba, f), getattr(bb, f)) for f in ("x", "y", "z"))
    assert a.options == b.options
    assert a.outputs == b.outputs


# A small deck of our own. Line numbers matter to some tests: keep them stable.
SMALL = """\
Two-segment mooring used by the unit tests
------------------------ LINE TYPES -------------------------
Name   Diam  Mass/m  EA     BA/-zeta  EI   Cd   Ca   CdAx  CaAx
(-)    (m)   (kg/m)  (N)    (N-s)     (-)  (-)  (-)  (-)   (-)
chain  0.1   20.0    1.0e8  -0.8      0    1.2  1.0  0.2   0.0
rope   0.2   10.0    5.0e7  -0.5      0    1.2  1.0  0.2   0.0
------------------------ POINTS -----------------------------
ID  Attachment  X    Y  Z     Mass  Volume  CdA  Ca
(#) (-)         (m)  (m) (m)  (kg)  (m^3)   (m2) (-)
1   Fixed       400  0  -100  0     0       0    0
2   Free        200  0  -80   100   0.5     1.0  1.0
3   Coupled     0    0  -10   0     0       0    0
------------------------ LINES ------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(#) (-)       (-)      (-)      (m)       (-)      (-)
1   chain     1        2        250.0     10       -
2   rope      2        3        210.0     10       pt
------------------------ OPTIONS ----------------------------
0.001   dtM
100     WtrDpth
------------------------ OUTPUTS ----------------------------
FairTen2
------------------------ END --------------------------------
"""


# ============================================================================ conformance decks
SIMPLE_DECKS = {
    # deck: (line types, points, lines, coupled points)
    "catenary_3line/lines.txt": (1, 6, 3, 3),
    "pendulum/pendulum.txt": (1, 2, 1, 0),
    "bridle_clump_buoy/bridle_clump_buoy.txt": (2, 6, 5, 2),
    "chain_wd0050/WD0050_Chain.txt": (1, 2, 1, 1),
    "polyester/simple.txt": (1, 2, 1, 1),
    "seabed_friction/seabed_friction_drag.txt": (1, 2, 1, 1),
}


@pytest.mark.parametrize("rel", sorted(SIMPLE_DECKS))
def test_conformance_decks_read(rel):
    path = conformance_deck(rel)
    m = read_deck(path)
    n_types, n_points, n_lines, n_coupled = SIMPLE_DECKS[rel]
    assert len(m.line_types) == n_types
    assert len(m.points) == n_points
    assert len(m.lines) == n_lines
    assert len(m.coupled_points) == n_coupled
    assert m.source == path


def test_catenary_3line_values():
    m = read_deck(conformance_deck("catenary_3line/lines.txt"))
    assert [ln.N for ln in m.lines] == [20, 20, 20]
    assert all(ln.L == 902.2 for ln in m.lines)
    assert all(ln.line_type == "main" and ln.outputs == "p" for ln in m.lines)
    lt = m.line_types["main"]
    assert lt.EA == 384.243e6
    assert lt.BA == -0.8
    assert (lt.d, lt.w, lt.EI, lt.Cd, lt.Ca, lt.CdAx, lt.CaAx) == (0.09, 77.7066, 0.0, 1.6, 1.0, 0.1, 0.0)
    assert (lt.Cl, lt.dF, lt.cF) == (0.0, 0.0, 0.0)
    assert m.env.depth == 320.0
    assert m.env.rho == 1025.0
    assert m.env.g == 9.80665
    assert (m.env.kBot, m.env.cBot) == (3.0e6, 3.0e5)
    p4 = m.points[3]
    assert p4.kind == PointKind.COUPLED
    np.testing.assert_array_equal(p4.r, [5.2, 0.0, -70.0])
    np.testing.assert_array_equal(m.points[1].r, [-426.94, 739.47, -320.0])
    assert m.points[0].kind == PointKind.FIXED
    assert m.lines[2].end_a == Attachment("point", 2)
    assert m.lines[2].end_b == Attachment("point", 5)
    o = m.options
    assert (o.writeLog, o.dtM, o.dtIC, o.TmaxIC) == (2, 0.002, 1.0, 100.0)
    assert (o.CdScaleIC, o.threshIC) == (4.0, 0.001)
    assert m.outputs == ["FairTen1", "FairTen2", "FairTen3"]
    assert o.not_acted_on == {}  # disableOutTime is neutral


def test_pendulum_values():
    m = read_deck(conformance_deck("pendulum/pendulum.txt"))
    assert m.options.CFL == 0.1  # key written in lower case 'cfl'
    assert m.options.tScheme == "RK4"
    assert m.options.dtM is None
    assert m.options.ICgenDynamic == 0
    assert m.env.rho == 1000.0
    assert m.points[1].kind == PointKind.FREE and m.points[1].m == 1e5
    assert m.lines[0].outputs == ""  # '-' means no flags


def test_polyester_crlf_and_friction():
    m = read_deck(conformance_deck("polyester/simple.txt"))  # CRLF line ends
    assert "Polyester_290mm" in m.line_types
    assert m.env.mu == 0.5
    assert m.env.depth == 372.3
    assert m.points[0].r[2] == -372.192


def test_seabed_friction_options():
    m = read_deck(conformance_deck("seabed_friction/seabed_friction_drag.txt"))
    assert (m.env.mu, m.env.fric_damp, m.env.stat_dyn) == (0.5, 1.0e5, 1.0)
    assert m.options.dtM == 2.5e-4


def test_bridle_clump_buoy_values():
    m = read_deck(conformance_deck("bridle_clump_buoy/bridle_clump_buoy.txt"))
    buoy = m.points[2]
    assert (buoy.kind, buoy.m, buoy.V, buoy.CdA, buoy.Ca) == (PointKind.FREE, 2000.0, 12.0, 6.0, 1.0)
    assert m.options.ICgenDynamic == 1
    assert [ln.line_type for ln in m.lines] == ["chain", "rope", "rope", "rope", "rope"]
    assert m.lines[4].end_a == Attachment("point", 3) and m.lines[4].end_b == Attachment("point", 5)


def test_bodies_and_rods_deck_values():
    m = read_deck(conformance_deck("bodies_and_rods/BodiesAndRods.dat"))
    (b,) = m.bodies
    assert b.kind == BodyKind.FREE and b.m == 1e6 and np.allclose(b.I, 1e10) and np.allclose(b.rCG, 0.0)
    assert [r.kind for r in m.rods] == [RodKind.BODY, RodKind.BODY_PINNED] and [r.body for r in m.rods] == [0, 0]
    assert m.points[0].kind == PointKind.BODY and m.points[0].body == 0
    # rod ends and body points are given in body axes; the body sits at the origin unrotated
    assert np.allclose(m.rod_ends(1)[1], (5.0, 0.0, 15.0))
    assert np.allclose(m.point_position(9), (0.0, 0.0, 0.0))


def test_body_columns_cg_inertia_cda_lists():
    text = ("---- BODIES ----\nID Att X Y Z r p y M CG I V CdA Ca\n(-) (-) (m) (m) (m) (deg) (deg) (deg) (kg) (m) "
            "(kg-m2) (m3) (m2) (-)\n1 coupled 1 2 3 0 0 90 5e3 0|0|-2 1|2|3 4 5|6 0.5|0.6|0.7\n"
            "2 free 0 0 0 10 0 0 1e4 -1 7 8 1|2|3 0.2\n")
    rods = ("---- ROD TYPES ----\nName Diam Mass Cd Ca CdEnd CaEnd\n(-) (m) (kg/m) (-) (-) (-) (-)\n"
            "can 0.5 50 0.6 1.0 0.5 1.0\n---- RODS ----\nID Type Att Xa Ya Za Xb Yb Zb N Out\n"
            "(#) (-) (-) (m) (m) (m) (m) (m) (m) (-) (-)\n1 can Body2Pin 0 0 -1 0 0 -5 4 p\n"
            "2 can free 0 0 -10 0 0 -5 4 -\n")
    deck = SMALL.replace("------------------------ POINTS", text + rods + "------------------------ POINTS", 1)
    m = read_deck_text(deck, path="b.txt")
    b1, b2 = m.bodies
    assert b1.kind == BodyKind.COUPLED and np.allclose(b1.rCG, (0, 0, -2)) and np.allclose(b1.I, (1, 2, 3))
    assert np.allclose(b1.CdA, (5, 5, 5, 6, 6, 6)) and np.allclose(b1.Ca, (0.5, 0.6, 0.7))
    assert b2.kind == BodyKind.FREE and np.allclose(b2.rCG, (0, 0, -1)) and np.allclose(b2.I, 7)
    assert np.allclose(b2.CdA, (1, 2, 3, 1, 2, 3)) and np.allclose(b2.angles, (10, 0, 0))
    assert m.rods[0].kind == RodKind.BODY_PINNED and m.rods[0].body == 1 and m.rods[1].kind == RodKind.FREE
    assert m.n_coupled_dof == 6 + 3 * len(m.coupled_points)


def test_zero_length_rod_ends_at_a_as_in_moordyn(caplog):
    """A rod with NumSegs 0 is zero-length whatever its end B says (MoorDyn puts both ends at end
    A): length 0, both deck-pose ends at A, and a warning naming the file and line."""
    rods = ("---- ROD TYPES ----\nName Diam Mass Cd Ca CdEnd CaEnd\n(-) (m) (kg/m) (-) (-) (-) (-)\n"
            "joint 0.1 0 0 0 0 0\n---- RODS ----\nID Type Att Xa Ya Za Xb Yb Zb N Out\n"
            "(#) (-) (-) (m) (m) (m) (m) (m) (m) (-) (-)\n1 joint fixed 0 0 -10 0 0 -11 0 -\n"
            "2 joint free 5 0 -10 5 0 -10 0 -\n")
    deck = SMALL.replace("------------------------ POINTS", rods + "------------------------ POINTS", 1)
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        m = read_deck_text(deck, path="z.txt")
    assert m.rods[0].length == 0.0 and m.rods[1].length == 0.0
    a, b = m.rod_ends(0)
    np.testing.assert_array_equal(a, (0, 0, -10))
    np.testing.assert_array_equal(b, (0, 0, -10))
    assert "z.txt" in caplog.text and "rod 1 has NumSegs 0" in caplog.text
    assert "rod 2" not in caplog.text  # its ends already coincide


def test_fixed_rod_and_clamped_line():
    m = read_deck(conformance_deck("beam_cantilever/BeamCantilevered.txt"))
    assert len(m.rods) == 1 and m.rods[0].kind.name == "FIXED" and m.rods[0].N == 1
    assert m.rod_types["cantilever"].d == 0.25
    assert m.lines[0].end_a == Attachment("rod", 0, "B")
    assert m.line_types["beam"].EI == 1e7


def test_empty_bodies_section_is_harmless():
    m = read_deck(conformance_deck("current_dynamic/test_dynamic_currents.txt"))
    assert len(m.lines) == 1
    assert m.options.not_acted_on == {}
    assert m.env.current is not None and m.env.waves is None  # Currents 2: current_profile_dynamic.txt
    assert m.options.CdScaleIC == 4.0  # alias ICDfac
    assert (m.env.kBot, m.env.cBot) == (3.0e6, 3.0e5)  # aliases kb, cb


def test_conformance_round_trip(tmp_path):
    m = read_deck(conformance_deck("bridle_clump_buoy/bridle_clump_buoy.txt"))
    out = write_deck(m, tmp_path / "copy.txt")
    assert_models_equal(read_deck(out), m)


# ============================================================================ lexer
def test_tokenize_comments():
    assert tokenize("1  Fixed\t0 0 -10  # anchor") == ("1", "Fixed", "0", "0", "-10")
    assert tokenize("# whole row") == ()
    assert tokenize("1.0#x 2.0") == ()  # the token containing '#' is dropped with the rest
    assert tokenize("  a b#c d") == ("a",)


@pytest.mark.parametrize("header,name", [
    ("----- LINE TYPES -----", "LINE TYPES"),
    ("--- Line Dictionary ---", "LINE TYPES"),
    ("--- LINES ---", "LINES"),
    ("--- line properties ---", "LINES"),
    ("--- LINE LIST ---", "LINES"),
    ("--- ROD TYPES ---", "ROD TYPES"),
    ("--- ROD DICTIONARY ---", "ROD TYPES"),
    ("--- RODS ---", "RODS"),
    ("--- Rod Properties ---", "RODS"),
    ("--- BODIES ---", "BODIES"),
    ("--- BODY LIST ---", "BODIES"),
    ("--- POINTS ---", "POINTS"),
    ("--- POINT PROPERTIES ---", "POINTS"),
    ("--- CONNECTION PROPERTIES ---", "POINTS"),
    ("--- NODE PROPERTIES ---", "POINTS"),
    ("-------------------------- SOLVER    OPTIONS-------", "OPTIONS"),
    ("--- OUTPUTS ---", "OUTPUTS"),
    ("--- Output List ---", "OUTPUTS"),
    ("--- SYROPE IC ---", "SYROPE IC"),
    ("--- FAILURE ---", "FAILURE"),
    ("--- CONTROL ---", "CONTROL"),
    ("--- EXTERNAL LOADS ---", "EXTERNAL LOADS"),
    ("------------------------- need this line ------", None),
    ("--------------------- MoorDyn Input File -------", None),
    ("LINE TYPES without dashes", None),
])
def test_section_names(header, name):
    assert section_name(header) == name


def test_lex_skips_titles_blank_rows_and_front_matter():
    text = ("front matter mentioning LINES and OPTIONS\n"
            "--- LINE TYPES ---\n"
            "titles\n"
            "units\n"
            "\n"
            "# a comment row\n"
            "a 1 2\n"
            "--- OPTIONS ---\n"
            "1 dtM\n"
            "--- nothing ---\n"
            "stray row after a terminator\n")
    secs = lex(text)
    assert [s.name for s in secs] == ["LINE TYPES", "OPTIONS"]
    assert [(r.line, r.tokens) for r in secs[0].rows] == [(7, ("a", "1", "2"))]
    assert [(r.line, r.tokens) for r in secs[1].rows] == [(9, ("1", "dtM"))]
    assert secs[1].line == 8


def test_lex_empty_table_without_titles_does_not_eat_next_header():
    secs = lex("--- BODIES ---\n--- LINES ---\nt\nu\n1 x\n")
    assert [(s.name, len(s.rows)) for s in secs] == [("BODIES", 0), ("LINES", 1)]


def test_lex_warns_when_units_row_looks_like_data(caplog):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        secs = lex("--- POINTS ---\nID Type X Y Z\n1 Fixed 0 0 -10 0 0 0 0\n2 Free 0 0 -5 0 0 0 0\n")
    assert len(secs[0].rows) == 1
    assert "looks like data" in caplog.text


@pytest.mark.parametrize("tok,val", [("1", 1.0), ("-2.5", -2.5), ("1.0E+06", 1e6), (".5", 0.5), ("3.", 3.0),
                                     ("384.243E6", 384.243e6), ("+4e-3", 4e-3)])
def test_parse_number_accepts(tok, val):
    assert parse_number(tok) == val


@pytest.mark.parametrize("tok", ["1.2.3", "1.0D6", "nan", "inf", "1_000", "abc", "", "1e", "--1", "1e999"])
def test_parse_number_rejects(tok):
    assert parse_number(tok) is None


def test_parse_whole():
    assert parse_whole("20") == 20
    assert parse_whole("20.0") == 20
    assert parse_whole("20.5") is None
    assert parse_whole("x") is None


# ============================================================================ inline decks
def test_small_deck(tmp_path):
    path = tmp_path / "small.txt"
    path.write_text(SMALL)
    m = read_deck(path)
    assert m.source == path
    assert list(m.line_types) == ["chain", "rope"]
    assert m.line_types["rope"].EA == 5.0e7
    p2 = m.points[1]
    assert (p2.kind, p2.m, p2.V, p2.CdA, p2.Ca) == (PointKind.FREE, 100.0, 0.5, 1.0, 1.0)
    np.testing.assert_array_equal(p2.F_ext, [0, 0, 0])
    assert [ln.outputs for ln in m.lines] == ["", "pt"]
    assert m.options.dtM == 0.001 and m.env.depth == 100.0
    assert m.outputs == ["FairTen2"]


def test_comments_tabs_and_blank_rows():
    text = SMALL.replace("1   Fixed       400  0  -100  0     0       0    0",
                         "1\tFixed\t400\t0\t-100\t0\t0\t0\t0   # anchor, tab separated\n\n# comment")
    text = text.replace("0.001   dtM", "0.001   dtM   # comment after the key\n#0.5 dtM")
    m = read_deck_text(text)
    np.testing.assert_array_equal(m.points[0].r, [400, 0, -100])
    assert m.options.dtM == 0.001


def test_value_token_containing_hash_is_dropped():
    # "100#x" contains '#', so it is dropped with the rest of the row: only the key is left
    with pytest.raises(DeckError, match="line 20: field 'WtrDpth' of OPTIONS: expected a value"):
        read_deck_text(SMALL.replace("100     WtrDpth", "WtrDpth 100#x"))


def test_sections_in_any_order():
    parts = SMALL.split("------------------------ ")
    head, types, points, lines, options, outputs, end = parts
    shuffled = "------------------------ ".join([head, outputs, lines, options, points, types, end])
    a = read_deck_text(SMALL)
    b = read_deck_text(shuffled)
    assert_models_equal(a, b)


def test_depth_is_not_deepened_by_reader():
    m = read_deck_text(SMALL.replace("100     WtrDpth\n", ""))
    assert m.env.depth == 0.0  # the core, not the reader, applies MoorDyn-C's deepening


def test_line_type_11_and_13_columns():
    text = SMALL.replace("0.2   0.0\nrope", "0.2   0.0  0.8\nrope").replace(
        "rope   0.2   10.0    5.0e7  -0.5      0    1.2  1.0  0.2   0.0",
        "rope   0.2   10.0    5.0e7  -0.5      0    1.2  1.0  0.2   0.0  0.9  0.1  0.2")
    m = read_deck_text(text)
    c, r = m.line_types["chain"], m.line_types["rope"]
    assert (c.Cl, c.dF, c.cF) == (0.8, 0.08, 0.18)
    assert (r.Cl, r.dF, r.cF) == (0.9, 0.1, 0.2)


def test_duplicate_line_type_later_wins(caplog):
    text = SMALL.replace("rope   0.2   10.0    5.0e7", "chain  0.2   10.0    5.0e7").replace(
        "2   rope ", "2   chain")
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        m = read_deck_text(text)
    assert list(m.line_types) == ["chain"] and m.line_types["chain"].d == 0.2
    assert "defined again" in caplog.text


def test_point_12_column_layout_and_words():
    text = SMALL.replace("1   Fixed       400  0  -100  0     0       0    0",
                         "1   anchor      400  0  -100  0     0   0  0  0    0    0").replace(
        "2   Free        200  0  -80   100   0.5     1.0  1.0",
        "2   CONNECT     200  0  -80   100   0.5  10 -20  3.5   1.0  1.0").replace(
        "3   Coupled", "3   vessel ")
    m = read_deck_text(text)
    assert [p.kind for p in m.points] == [PointKind.FIXED, PointKind.FREE, PointKind.COUPLED]
    np.testing.assert_array_equal(m.points[1].F_ext, [10, -20, 3.5])
    assert (m.points[1].CdA, m.points[1].Ca) == (1.0, 1.0)


@pytest.mark.parametrize("word,kind", [
    ("ANCHOR", PointKind.FIXED), ("fixed", PointKind.FIXED), ("Fix", PointKind.FIXED),
    ("Fairlead", PointKind.COUPLED), ("VES", PointKind.COUPLED), ("cpld", PointKind.COUPLED),
    ("Point", PointKind.FREE), ("con", PointKind.FREE), ("Connect", PointKind.FREE),
])
def test_point_attachment_words(word, kind):
    m = read_deck_text(SMALL.replace("3   Coupled", f"3   {word}"))
    assert m.points[2].kind == kind


@pytest.mark.parametrize("a,b", [("P2", "p3"), ("Point2", "POINT3"), ("C2", "con3"), ("2", "3")])
def test_line_attachment_words(a, b):
    m = read_deck_text(SMALL.replace("2   rope      2        3 ", f"2   rope      {a}       {b} "))
    assert m.lines[1].end_a == Attachment("point", 1)
    assert m.lines[1].end_b == Attachment("point", 2)


def test_negative_length_is_kept():
    m = read_deck_text(SMALL.replace("250.0", "-1.05"))
    assert m.lines[0].L == -1.05


def test_option_aliases_and_case():
    opts = """\
0.002   DT
0.3     cfl
rk4     TSCHEME
9.81    gravity
1020    rhoW
120     depth
2e6     kb
2e5     CB
0.5     ICdt
50      ICTmax
3       ICDfac
0.01    ICthresh
1       genDynamicIC
0.3     FrictionCoefficient
150     fricdamp
1.5     StatDynFricScale
0.1     dtOut
0       WriteUnits
1       disableOutput
3       writelog
"""
    text = SMALL.replace("0.001   dtM\n100     WtrDpth\n", opts)
    m = read_deck_text(text)
    e, o = m.env, m.options
    assert (e.g, e.rho, e.depth, e.kBot, e.cBot) == (9.81, 1020.0, 120.0, 2e6, 2e5)
    assert (e.mu, e.fric_damp, e.stat_dyn) == (0.3, 150.0, 1.5)
    assert (o.dtM, o.CFL, o.tScheme, o.dtIC, o.TmaxIC, o.CdScaleIC, o.threshIC) == \
        (0.002, 0.3, "rk4", 0.5, 50.0, 3.0, 0.01)
    assert (o.ICgenDynamic, o.dtOut, o.WriteUnits, o.disableOutput, o.writeLog) == (1, 0.1, 0, 1, 3)
    assert o.not_acted_on == {}


@pytest.mark.parametrize("key", ["rho", "WtrDnsty", "rhoW"])
def test_density_aliases(key):
    assert read_deck_text(SMALL.replace("100     WtrDpth", f"100  WtrDpth\n1000 {key}")).env.rho == 1000.0


@pytest.mark.parametrize("key", ["WtrDpth", "depth", "WaterDepth"])
def test_depth_aliases(key):
    assert read_deck_text(SMALL.replace("100     WtrDpth", f"42 {key}")).env.depth == 42.0


def test_repeated_option_last_wins():
    m = read_deck_text(SMALL.replace("100     WtrDpth", "100     WtrDpth\n0.002 dt\n150 depth"))
    assert m.options.dtM == 0.002
    assert m.env.depth == 150.0


def test_not_acted_on_options_warn_once(caplog):
    extra = """\
x.dat    WaterKin
1        inertialF
2        inertialF    again: one warning per key
"""
    with caplog.at_level(logging.DEBUG, logger="moorline.io"):
        m = read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n" + extra), path="x.txt")
    assert m.options.not_acted_on == {"WaterKin": "x.dat", "inertialF": "2"}
    warnings = [r for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 2
    assert sum("inertialF" in r.getMessage() for r in warnings) == 1
    assert all("x.txt" in r.getMessage() for r in warnings)


def test_file_ic_is_a_path_next_to_the_deck(tmp_path, caplog):
    """fileIC (alias ICfile) names MoorDyn's saved state relative to the deck's folder."""
    (tmp_path / "state.bin").write_bytes(b"MoorDyn")
    deck = tmp_path / "d.txt"
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nstate.bin ICfile\n"))
    assert read_deck(deck).options.fileIC == str(tmp_path / "state.bin")
    # MoorDyn's own test decks name state files they do not ship: a warning, and no state file
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nnone.bin fileIC\n"))
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        assert read_deck(deck).options.fileIC is None
    assert "none.bin, which does not exist" in caplog.text and "d.txt" in caplog.text


def test_wave_and_current_options_need_their_files(tmp_path):
    deck = tmp_path / "w.txt"
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n7        WaveKin\n"))
    with pytest.raises(DeckError, match="WaveKin 7 needs the file wave_frequencies.txt") as ei:
        read_deck(deck)
    assert ei.value.field == "WaveKin" and "w.txt" in str(ei.value)
    (tmp_path / "wave_frequencies.txt").write_text("0 0 0\n0.6 0.5 0.0\n")
    m = read_deck(deck)
    assert m.env.waves is not None and m.env.waves.evaluation == "sum"
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n1        Currents\n"))
    with pytest.raises(DeckError, match="current_profile.txt"):
        read_deck(deck)


def test_unify_current_grid_is_acted_on(tmp_path):
    """UnifyCurrentGrid 0 keeps a grid current apart from the wave grid (MoorDyn's wavekin_3_curr5
    deck; issue 18: read and ignored before, 5e-3 off MoorDyn from the same start, now 1e-10)."""
    data = Path(__file__).resolve().parents[1] / "data" / "waterkin"
    for name in ("wave_frequencies.txt", "water_grid.txt", "current_profile.txt"):
        (tmp_path / name).write_bytes((data / name).read_bytes())
    deck = tmp_path / "u.txt"
    (tmp_path / "w").mkdir()
    base = SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n2 WaveKin\n1 Currents\n")
    for text, on_grid in ((base, True), (base.replace("1 Currents\n", "1 Currents\n1 UnifyCurrentGrid\n"), True),
                          (base.replace("1 Currents\n", "1 Currents\n0 UnifyCurrentGrid\n"), False)):
        deck.write_text(text)
        m = read_deck(deck)
        assert m.env.current.on_wave_grid is on_grid and m.options.not_acted_on == {}
        # and a written deck says so again
        out = tmp_path / "w" / "u.txt"
        write_deck(m, out)
        assert read_deck(out).env.current.on_wave_grid is on_grid
        assert ("UnifyCurrentGrid" in out.read_text()) is (not on_grid)
    deck.write_text(base.replace("1 Currents\n", "1 Currents\nyes UnifyCurrentGrid\n"))
    with pytest.raises(DeckError, match=r"UnifyCurrentGrid.*expected 0 or 1.*'yes'") as ei:
        read_deck(deck)
    assert "u.txt" in str(ei.value)


def test_neutral_not_acted_on_options_do_not_warn(caplog):
    extra = """\
0        WaveKin
0        Currents
1        UnifyCurrentGrid
1        disableOutTime
0.25     dtWave
1        OutSwitch
0        inertialF
"""
    with caplog.at_level(logging.DEBUG, logger="moorline.io"):
        m = read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n" + extra))
    assert m.options.not_acted_on == {}
    assert m.env.waves is None and m.env.current is None
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    assert "disableOutTime" in caplog.text  # still mentioned at debug level


def test_unknown_option_warns_with_file_line_and_key(caplog):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        m = read_deck_text(SMALL.replace("100     WtrDpth", "100     WtrDpth\n7  FooBar  nothing"),
                           path="deck.txt")
    assert m.env.depth == 100.0
    assert "deck.txt, line 21" in caplog.text and "'FooBar'" in caplog.text


def test_outputs_rows_and_v1_end():
    text = SMALL.replace("FairTen2\n", "FairTen1 fairten2  L1N5pz\n\nPoint2FX  # comment\nEND\n")
    assert read_deck_text(text).outputs == ["FairTen1", "fairten2", "L1N5pz", "Point2FX"]


def test_control_section_ignored_with_warning(caplog):
    text = SMALL.replace("------------------------ END",
                         "--- CONTROL ---\nt\nu\n1 2 3\n------------------------ END")
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        read_deck_text(text)
    assert "CONTROL" in caplog.text


def test_free_point_validation_passes_for_connected_massless_point():
    m = read_deck_text(SMALL.replace("200  0  -80   100   0.5", "200  0  -80   0     0.0"))
    assert m.points[1].m == 0.0


# ============================================================================ MoorDyn v1 layouts
V1 = """\
MoorDyn v1 style input file
---------------------- LINE TYPES -----------------------------------
LineType  Diam    MassDenInAir   EA        BA/-zeta    Can   Cat   Cdn   Cdt
(-)       (m)     (kg/m)         (N)       (Pa-s/-)    (-)   (-)   (-)   (-)
main      0.0766  113.35         7.536E8   -1.0        0.8   0.25  2.0   0.4
---------------------- CONNECTION PROPERTIES ------------------------
Node      Type      X        Y         Z        M        V         FX       FY      FZ     CdA   CA
(-)       (-)       (m)      (m)       (m)      (kg)     (m^3)     (kN)     (kN)    (kN)   (m^2) (-)
1         Fixed     418.8    725.383   -200.0   0        0         0        0       0      0     0
2         Vessel    20.434   35.393    -14.0    0        0         0        0       0      0     0
3         Connect   0        0         -100     500      0         0        0       -10    0     0
4         Fixed     -418.8   725.383   -200.0   0        0         0        0       0      0     0
---------------------- LINE PROPERTIES ------------------------------
Line     LineType  UnstrLen  NumSegs   NodeAnch  NodeFair  Flags/Outputs
(-)      (-)       (m)       (-)       (-)       (-)       (-)
1        main      835.35    20        1         2         plt
2        main      500       10        4         3         -
---------------------- SOLVER OPTIONS -------------------------------
0.001    dtM       - time step to use in mooring integration
3.0e6    kBot      - bottom stiffness
3.0e5    cBot      - bottom damping
200      WtrDpth   - water depth
5.0      CdScaleIC - factor by which to scale drag coefficients during dynamic relaxation IC gen
0.001    threshIC  - threshold for IC convergence
-------------------------- OUTPUTS --------------------------------
FairTen1
AnchTen1
END
------------------------- need this line ----------------------------
"""


def test_v1_deck():
    m = read_deck_text(V1)
    lt = m.line_types["main"]
    assert (lt.d, lt.w, lt.EA, lt.BA, lt.EI) == (0.0766, 113.35, 7.536e8, -1.0, 0.0)
    assert (lt.Ca, lt.CaAx, lt.Cd, lt.CdAx) == (0.8, 0.25, 2.0, 0.4)
    assert [p.kind for p in m.points] == [PointKind.FIXED, PointKind.COUPLED, PointKind.FREE, PointKind.FIXED]
    np.testing.assert_array_equal(m.points[2].F_ext, [0, 0, -10])
    l1, l2 = m.lines
    assert (l1.L, l1.N, l1.end_a, l1.end_b, l1.outputs) == (835.35, 20, Attachment("point", 0),
                                                            Attachment("point", 1), "plt")
    assert (l2.L, l2.N, l2.end_a, l2.end_b, l2.outputs) == (500.0, 10, Attachment("point", 3),
                                                            Attachment("point", 2), "")
    assert m.outputs == ["FairTen1", "AnchTen1"]


def test_v1_line_rows_detected_with_v2_line_types():
    # v2 line types, but v1 line rows: column 3 (902.2) is not an attachment, columns 5/6 are points
    m = read_deck_text(SMALL.replace("1   chain     1        2        250.0     10",
                                     "1   chain     250.0    10       1         2"))
    assert (m.lines[0].L, m.lines[0].N) == (250.0, 10)
    assert (m.lines[0].end_a, m.lines[0].end_b) == (Attachment("point", 0), Attachment("point", 1))
    assert m.lines[1].L == 210.0  # the v2 row next to it is still read as v2


def test_v2_row_with_small_whole_numbers_stays_v2():
    # "2 3 3 2": columns 3/4 are valid attachments and the types are v2, so the row is v2:
    # from P2 to P3, length 3 m, 2 segments
    m = read_deck_text(SMALL.replace("2   rope      2        3        210.0     10",
                                     "2   rope      2        3        3         2 "))
    assert (m.lines[1].end_a, m.lines[1].end_b, m.lines[1].L, m.lines[1].N) == \
        (Attachment("point", 1), Attachment("point", 2), 3.0, 2)


def test_v1_rule_uses_line_types_layout_when_ambiguous():
    # same ambiguous row with v1 line types: read as v1 (L=2, N=3, from P3 to P2)
    text = V1.replace("2        main      500       10        4         3",
                      "2        main      2         3         3         2")
    l2 = read_deck_text(text).lines[1]
    assert (l2.L, l2.N, l2.end_a, l2.end_b) == (2.0, 3, Attachment("point", 2), Attachment("point", 1))


def test_v1_deck_converts_to_v2(tmp_path):
    m = read_deck_text(V1)
    out = write_deck(m, tmp_path / "v2.txt")
    text = out.read_text()
    assert "CONNECTION" not in text and "LINE PROPERTIES" not in text
    assert_models_equal(read_deck(out), m)


# ============================================================================ curve files
def _write_curve(path: Path, rows, header=("title", "x y", "(-) (N)")):
    path.write_text("\n".join([*header, *rows]) + "\n")
    return path


def test_read_curve(tmp_path):
    p = _write_curve(tmp_path / "ea.txt", ["0.0 0.0", "", "0.01  1.0e6  extra", "0.02 3.0e6  # c"])
    c = read_curve(p, "EA")
    np.testing.assert_array_equal(c.x, [0.0, 0.01, 0.02])
    np.testing.assert_array_equal(c.y, [0.0, 1e6, 3e6])
    assert c.source == str(p)


def test_read_curve_three_header_lines_always_skipped(tmp_path):
    p = _write_curve(tmp_path / "c.txt", ["0 0", "1 1", "2 4"], header=("0 0", "h2", "h3"))
    assert read_curve(p).x.tolist() == [0.0, 1.0, 2.0]
    p = _write_curve(tmp_path / "d.txt", ["0 0", "1 1", "2 4"], header=("h1", "h2"))
    assert read_curve(p).x.tolist() == [1.0, 2.0]  # like MoorDyn: the first data row is eaten


def test_read_curve_more_than_30_points_warns(tmp_path, caplog):
    p = _write_curve(tmp_path / "long.txt", [f"{i * 0.001} {i * 1e5}" for i in range(40)])
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        c = read_curve(p, "EA")
    assert c.x.size == 40
    assert "at most 30" in caplog.text


def test_ea_ba_ei_curve_files(tmp_path):
    _write_curve(tmp_path / "ea.txt", ["0.0 0.0", "0.01 1.0e6", "0.02 3.0e6"])
    (tmp_path / "sub").mkdir()
    _write_curve(tmp_path / "sub" / "ba.txt", ["-1 -1e4", "1 1e4"])
    _write_curve(tmp_path / "ei.txt", ["0 0", "0.1 500"])
    text = SMALL.replace("chain  0.1   20.0    1.0e8  -0.8      0 ",
                         "chain  0.1   20.0    ea.txt sub/ba.txt ei.txt ")
    path = tmp_path / "deck.txt"
    path.write_text(text)
    lt = read_deck(path).line_types["chain"]
    assert isinstance(lt.EA, Curve) and lt.EA.y.tolist() == [0.0, 1e6, 3e6]
    assert isinstance(lt.BA, Curve) and lt.BA.x.tolist() == [-1.0, 1.0]
    assert isinstance(lt.EI, Curve) and lt.has_bending
    assert lt.EA_ref == 1.5e8
    # base_dir lets text be read from elsewhere
    lt2 = read_deck_text(text, base_dir=tmp_path).line_types["chain"]
    assert lt2.EA.x.tolist() == [0.0, 0.01, 0.02]


# ============================================================================ writer
def test_round_trip_small(tmp_path):
    a = read_deck_text(SMALL)
    out = write_deck(a, tmp_path / "rt.txt")
    assert out == tmp_path / "rt.txt"
    b = read_deck(out)
    assert_models_equal(a, b)
    assert b.source == out


def test_round_trip_everything(tmp_path):
    m = Model()
    m.add_line_type("poly", d=0.2, w=30.0, EA=Curve([0.0, 0.05, 0.1], [0.0, 2e6, 5e6]), BA=-0.7,
                    EI=Curve([0.0, 0.2], [0.0, 1e3]), Cd=1.2, Ca=1.0, CdAx=0.008, CaAx=0.1)
    m.add_line_type("viv", d=0.1 + 0.2, w=1 / 3, EA=1.234567890123e9, BA=Curve([0.0, 1.0], [0.0, 5e4]),
                    Cl=0.8, dF=0.08, cF=0.18)
    m.add_line_type("viv2", d=0.3, w=2.0, EA=1e9, Cl=0.7, dF=0.1, cF=0.25)
    a = m.add_point("fixed", (500.0, 1e-7, -200.0))
    b = m.add_point("free", (250.0, 0.0, -150.0), m=1e4, V=1.3, CdA=2.0, Ca=1.0, F_ext=(0.0, 0.0, -5e3))
    c = m.add_point("coupled", (10.0, 0.0, -5.0))
    m.add_line("poly", a, b, L=-1.02, N=12, outputs="ptU")
    m.add_line("viv", b, c, L=160.5, N=7)
    m.add_line("viv2", c, a, L=700.0, N=30)
    m.env.depth, m.env.mu, m.env.rho = 200.0, 0.4, 1027.5
    m.options.dtM, m.options.tScheme, m.options.ICgenDynamic = 2e-4, "RK4", 1
    m.options.not_acted_on = {"inertialF": "1"}
    m.env.bathymetry = Bathymetry([0.0, 50.0, 100.0], [-5.0, 5.0], [[-40.0, -35.5, -30.25], [-41.0, -36.0, -31.0]])
    m.env.friction, m.env.contact, m.env.kShear = "stickslip", "vertical", 2.5e5
    m.env.depth = m.env.bathymetry.mean_depth  # a deck with a grid has the grid's mean depth
    m.outputs = ["FairTen2", "L1N0PZ", "Point2FZ"]
    out = write_deck(m, tmp_path / "all.dat")
    assert (tmp_path / "all_poly_EA.txt").is_file() and (tmp_path / "all_viv_BA.txt").is_file()
    back = read_deck(out)
    assert_models_equal(back, m)
    assert back.line_types["viv"].w == 1 / 3  # repr() round trip is exact


def test_writer_section_order_and_terminator(tmp_path):
    text = write_deck(read_deck_text(SMALL), tmp_path / "o.txt").read_text()
    names = [section_name(ln) for ln in text.splitlines() if section_name(ln)]
    assert names == ["LINE TYPES", "POINTS", "LINES", "OPTIONS", "OUTPUTS"]
    last = text.rstrip().splitlines()[-1]
    assert "---" in last and section_name(last) is None


def test_writer_rejects_unwritable_names(tmp_path):
    m = read_deck_text(SMALL)
    m.line_types["two words"] = m.line_types.pop("rope")
    with pytest.raises(ValueError, match="two words"):
        write_deck(m, tmp_path / "bad.txt")


@pytest.mark.oracle
def test_moordyn_reads_written_deck(tmp_path):
    moordyn = pytest.importorskip("moordyn")
    _write_curve(tmp_path / "ea.txt", ["0.0 0.0", "0.01 1.0e6", "0.02 3.0e6"])
    text = SMALL.replace("chain  0.1   20.0    1.0e8", "chain  0.1   20.0    ea.txt")
    m = read_deck_text(text, base_dir=tmp_path)
    m.options.writeLog, m.options.disableOutput = 0, 1
    out = write_deck(m, tmp_path / "written.txt")
    system = moordyn.Create(str(out))
    try:
        assert moordyn.GetNumberLines(system) == 2
        assert moordyn.GetNumberPoints(system) == 3
        assert moordyn.NCoupledDOF(system) == 3
        line1 = moordyn.GetLine(system, 1)
        assert moordyn.GetLineN(line1) == 10
        assert moordyn.GetLineUnstretchedLength(line1) == pytest.approx(250.0)
        # the EA curve made it through: MoorDyn reports no constant EA for that line
        assert moordyn.GetLineConstantEA(line1) == 0.0
        assert moordyn.GetLineConstantEA(moordyn.GetLine(system, 2)) == pytest.approx(5.0e7)
        point2 = moordyn.GetPoint(system, 2)
        assert moordyn.GetPointType(point2) == moordyn.POINT_TYPE_FREE
        assert list(moordyn.GetPointPos(point2)) == pytest.approx([200.0, 0.0, -80.0])
        assert moordyn.GetPointM(point2)[0][0] == pytest.approx(100.0)  # mass matrix before Init
    finally:
        moordyn.Close(system)


# ------------------------------------------------------------------------------ seabed options
def test_friction_options_select_the_model():
    m = read_deck_text(SMALL)
    assert m.env.friction == "isotropic"
    m = read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n0.3  mu_kT\n0.1  mu_kA\n2.0  mc\n"))
    assert m.env.friction == "directional"
    assert (m.env.mu_kT, m.env.mu_kA, m.env.mc) == (0.3, 0.1, 2.0)
    assert m.env.friction_coefficients() == (0.3, 0.1, 2.0, 200.0)
    m = read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\n0.4  FrictionCoefficient\n"
                                     "stickslip  FrictionModel\n1e5  kShear\nvertical  SeabedContact\n"))
    assert (m.env.friction, m.env.kShear, m.env.contact) == ("stickslip", 1e5, "vertical")
    assert m.env.friction_coefficients()[:3] == (0.4, 0.4, 1.0)


def test_inertial_loads_option(tmp_path):
    """InertialLoads: 'full' by default, 'moordyn' read and written back, anything else refused
    with the file and line."""
    assert read_deck_text(SMALL).options.InertialLoads == "full"
    m = read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nmoordyn  InertialLoads\n"))
    assert m.options.InertialLoads == "moordyn"
    out = write_deck(m, tmp_path / "w.txt")
    assert "InertialLoads" in out.read_text() and read_deck(out).options.InertialLoads == "moordyn"
    assert "InertialLoads" not in write_deck(read_deck_text(SMALL), tmp_path / "d.txt").read_text()
    with pytest.raises(DeckError) as e:
        read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nsome  InertialLoads\n"), path="f.txt")
    assert "f.txt, line 21" in str(e.value) and "one of full, moordyn" in str(e.value)


def test_bad_friction_model_is_located():
    with pytest.raises(DeckError) as e:
        read_deck_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nsticky  FrictionModel\n"), path="f.txt")
    assert "f.txt, line 21" in str(e.value) and "one of isotropic, directional, stickslip" in str(e.value)


def test_seafloor_file_sets_bathymetry_and_mean_depth(tmp_path):
    (tmp_path / "bed.txt").write_text("2 2\n0 100\n-10 10\n0 -10 -40\n100 -10 -20\n0 10 -40\n100 10 -20\n")
    deck = tmp_path / "d.txt"
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nbed.txt  SeafloorFile\n"))
    m = read_deck(deck)
    assert m.env.bathymetry is not None and m.env.bathymetry.z.shape == (2, 2)
    assert m.env.depth == pytest.approx(30.0)
    assert m.env.bathymetry.height(50.0, 0.0) == pytest.approx(-30.0)


def test_depth_grid_given_as_wtrdpth(tmp_path):
    (tmp_path / "depths.txt").write_text("title\nnGridX 2\nnGridY 2\n 0 100\n-10 40 20\n10 40 20\n")
    deck = tmp_path / "d.txt"
    deck.write_text(SMALL.replace("100     WtrDpth", "depths.txt  WtrDpth"))
    m = read_deck(deck)
    assert m.env.bathymetry.height(100.0, 0.0) == pytest.approx(-20.0)
    assert m.env.depth == pytest.approx(30.0)


def test_missing_seafloor_file_is_located(tmp_path):
    deck = tmp_path / "d.txt"
    deck.write_text(SMALL.replace("100     WtrDpth\n", "100     WtrDpth\nnothere.txt  SeafloorFile\n"))
    with pytest.raises(DeckError) as e:
        read_deck(deck)
    assert "d.txt, line 21" in str(e.value) and "nothere.txt" in str(e.value) and "not found" in str(e.value)
