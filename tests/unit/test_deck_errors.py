"""Malformed decks: every DeckError names the file, the line, the field and what was expected."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import pytest

from moorline.errors import DeckError
from moorline.io import read_curve, read_deck, read_deck_text

# Line numbers are used by the cases below; edit with care.
BASE = """\
Error-case deck for the moorline reader tests
---------------- LINE TYPES ----------------
Name  Diam  Mass/m  EA     BA    EI  Cd   Ca   CdAx  CaAx
(-)   (m)   (kg/m)  (N)    (Ns)  (-) (-)  (-)  (-)   (-)
wire  0.05  12.0    2.0e8  -1.0  0   1.1  0.9  0.3   0.1
poly  0.16  18.0    9.0e7  -0.6  0   1.3  1.0  0.1   0.0
---------------- POINTS --------------------
ID  Attachment  X    Y   Z    Mass  Volume  CdA  Ca
(#) (-)         (m)  (m) (m)  (kg)  (m^3)   (m2) (-)
1   Anchor      300  50  -90  0     0       0    0
2   Free        150  20  -60  40    0.2     0.5  1.0
3   Vessel      5    0   -8   0     0       0    0
---------------- LINES ---------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(#) (-)       (-)      (-)      (m)       (-)      (-)
1   wire      1        2        170.0     12       -
2   poly      2        3        160.0     8        t
---------------- OPTIONS -------------------
5e-4  dtM
90    WtrDpth
1025  rho
---------------- OUTPUTS -------------------
FairTen2
---------------- end -----------------------
"""
DECK = "bad_deck.txt"


def replace_line(n: int, new: str):
    def edit(text):
        rows = text.splitlines()
        rows[n - 1] = new
        return "\n".join(rows) + "\n"
    return edit


def delete_lines(first: int, last: int):
    def edit(text):
        rows = text.splitlines()
        del rows[first - 1:last]
        return "\n".join(rows) + "\n"
    return edit


def insert_after(n: int, new: str):
    def edit(text):
        rows = text.splitlines()
        rows[n:n] = new.splitlines()
        return "\n".join(rows) + "\n"
    return edit


@dataclass
class Case:
    edit: object
    line: int | None           # expected line number (None: the error is about the whole file)
    field: str | None          # expected field name
    expected: tuple[str, ...]  # pieces of text the message must contain
    files: dict[str, str] = field(default_factory=dict)  # extra files next to the deck


CASES = {
    # ---- sections
    "missing LINES": Case(delete_lines(13, 17), None, None, ("no LINES section",)),
    "missing LINE TYPES": Case(delete_lines(2, 6), None, None, ("no LINE TYPES section",)),
    "empty LINES": Case(delete_lines(16, 17), 13, None, ("LINES section has no rows", "at least one line")),
    "unknown rod type": Case(insert_after(6, "---- RODS ----\nID RodType\n(#) (-)\n1 can fixed 0 0 0 0 0 1 2 -"),
                             10, "RodType", ("expected a rod type name from ROD TYPES", "got 'can'")),
    "rod with 10 values": Case(insert_after(6, "---- ROD TYPES ----\nt\nu\ncan 1 10 0 0 0 0\n---- RODS ----\nt\nu\n"
                                                "1 can fixed 0 0 0 0 0 1 2"), 14, "RodOutputs",
                               ("RODS row has 10 values",)),
    "line on a rod end without its letter": Case(
        lambda t: insert_after(6, "---- ROD TYPES ----\nt\nu\ncan 1 10 0 0 0 0\n---- RODS ----\nt\nu\n"
                                  "1 can fixed 0 0 0 0 0 1 2 -")(t).replace("1   wire      1        2",
                                                                            "1   wire      R1       2"),
        24, "AttachA", ("the end letter is mandatory",)),
    "BODIES row too short": Case(insert_after(12, "---- BODIES ----\nt\nu\n1 free 0 0 0 0 0 0 1e5 0 1e6 0 0"),
                                 16, "Ca*", ("BODIES row has 13 values", "14 (ID Attachment")),
    "bad body CdA list": Case(insert_after(12, "---- BODIES ----\nt\nu\n1 free 0 0 0 0 0 0 1e5 0 1e6 0 1|2|3|4 0"),
                              16, "CdA*", ("trans|rot, x|y|z or six values", "got '1|2|3|4'")),
    "FAILURE line not on the point": Case(insert_after(17, "---- FAILURE ----\nt\nu\n1 3 1 10 0"), 21, "Line(s)",
                                          ("line 1 is not attached to 3",)),
    "FAILURE negative time": Case(insert_after(17, "---- FAILURE ----\nt\nu\n1 2 1,2 -1 0"), 21, "FailTime",
                                  ("expected a number >= 0 (0 for none)", "got '-1'")),
    "FAILURE row too short": Case(insert_after(17, "---- FAILURE ----\nt\nu\n1 2 1 10"), 21, "FailTen",
                                  ("FAILURE row has 4 values",)),
    "duplicate OPTIONS": Case(insert_after(21, "---- SOLVER OPTIONS ----\n1 dtM"), 22, None,
                              ("section OPTIONS appears twice", "line 18")),
    # ---- LINE TYPES
    "line type with 8 values": Case(replace_line(5, "wire 0.05 12.0 2.0e8 -1.0 0 1.1 0.9"), 5, "CdAx",
                                    ("10, 11 or 13", "has 8 values")),
    "line type with 12 values": Case(replace_line(6, "poly 0.16 18.0 9.0e7 -0.6 0 1.3 1.0 0.1 0.0 0.5 0.1"),
                                     6, "cF", ("10, 11 or 13", "has 12 values", "dF and cF go together")),
    "line type with 14 values": Case(replace_line(6, "poly 0.16 18 9e7 -0.6 0 1.3 1 0.1 0 0.5 0.1 0.2 7"),
                                     6, "cF", ("10, 11 or 13", "has 14 values", "'7'")),
    "bad number 1.2.3": Case(replace_line(6, "poly 1.2.3 18.0 9.0e7 -0.6 0 1.3 1.0 0.1 0.0"), 6, "Diam",
                             ("expected a number > 0", "got '1.2.3'")),
    "Fortran exponent": Case(replace_line(6, "poly 0.16 18.0 9.0D7 -0.6 0 1.3 1.0 0.1 0.0"), 6, "EA",
                             ("expected a number > 0 or the name of an EA curve file", "'9.0D7'")),
    "negative diameter": Case(replace_line(5, "wire -0.05 12.0 2.0e8 -1.0 0 1.1 0.9 0.3 0.1"), 5, "Diam",
                              ("expected a number > 0", "got '-0.05'")),
    "zero diameter": Case(replace_line(5, "wire 0 12.0 2.0e8 -1.0 0 1.1 0.9 0.3 0.1"), 5, "Diam",
                          ("expected a number > 0", "got '0'")),
    "zero mass per length": Case(replace_line(5, "wire 0.05 0.0 2.0e8 -1.0 0 1.1 0.9 0.3 0.1"), 5, "Mass/m",
                                 ("expected a number > 0", "got '0.0'")),
    "negative Cd": Case(replace_line(6, "poly 0.16 18.0 9.0e7 -0.6 0 -1.3 1.0 0.1 0.0"), 6, "Cd",
                        ("expected a number >= 0", "got '-1.3'")),
    "negative EI": Case(replace_line(6, "poly 0.16 18.0 9.0e7 -0.6 -5 1.3 1.0 0.1 0.0"), 6, "EI",
                        ("expected a number >= 0", "got '-5'")),
    "EA with four bar values": Case(replace_line(5, "wire 0.05 12.0 2.0e8|3.0e8|0.4|5 -1.0 0 1.1 0.9 0.3 0.1"), 5,
                                    "EA", ("at most three bar-separated values", "2.0e8|3.0e8|0.4|5")),
    "Syrope settings missing": Case(replace_line(5, "wire 0.05 12 SYROPE:s.txt|1e8|20 1|2 0 1.1 0.9 0.3 0.1"), 5,
                                    "EA", ("Syrope settings file", "s.txt")),
    "Syrope with two values": Case(replace_line(5, "wire 0.05 12 SYROPE:s.txt|1e8 1|2 0 1.1 0.9 0.3 0.1"), 5,
                                   "EA", ("SYROPE:<settings file>|EA_Dc|EA_D_Lm",)),
    "BA_s|BA_d on an elastic line": Case(replace_line(5, "wire 0.05 12.0 2.0e8 -1.0|5e3 0 1.1 0.9 0.3 0.1"), 5,
                                         "BA/-zeta", ("BA_s|BA_d goes with a viscoelastic",)),
    "negative BA_d": Case(replace_line(5, "wire 0.05 12.0 2.0e8|3.0e8 1e5|-4 0 1.1 0.9 0.3 0.1"), 5, "BA/-zeta",
                          ("BA_d must be a number >= 0", "'-4'")),
    "EA_d equal to EA_s": Case(replace_line(5, "wire 0.05 12.0 2.0e8|2.0e8 1e5|1e3 0 1.1 0.9 0.3 0.1"), 5, None,
                               ("line type 'wire'", "EA_d must be > 0 and differ from the static")),
    "curve file missing": Case(replace_line(5, "wire 0.05 12.0 wire_ea.txt -1.0 0 1.1 0.9 0.3 0.1"), 5, "EA",
                               ("curve file", "no such file", "wire_ea.txt")),
    "curve file with decreasing x": Case(
        replace_line(5, "wire 0.05 12.0 2.0e8 -1.0 bend.txt 1.1 0.9 0.3 0.1"), 5, "EI",
        ("bad EI curve file", "bend.txt, line 6", "strictly increasing", "0.01 after 0.02"),
        {"bend.txt": "EI curve\ncurvature moment\n(1/m) (Nm)\n0.0 0.0\n0.02 2e3\n0.01 1e3\n"}),
    "curve file with a word": Case(
        replace_line(5, "wire 0.05 12.0 tension.txt -1.0 0 1.1 0.9 0.3 0.1"), 5, "EA",
        ("bad EA curve file", "tension.txt, line 5", "expected two numbers", "'lots'"),
        {"tension.txt": "h\nh\nh\n0 0\n0.01 lots\n"}),
    "curve file with one row": Case(
        replace_line(5, "wire 0.05 12.0 tension.txt -1.0 0 1.1 0.9 0.3 0.1"), 5, "EA",
        ("bad EA curve file", "at least two", "got 1"), {"tension.txt": "h\nh\nh\n0.01 1e6\n"}),
    # ---- POINTS
    "point IDs out of order": Case(replace_line(11, "3 Free 150 20 -60 40 0.2 0.5 1.0"), 11, "ID",
                                   ("expected 2", "row order", "got '3'")),
    "point ID not a number": Case(replace_line(10, "one Anchor 300 50 -90 0 0 0 0"), 10, "ID",
                                  ("expected a whole number", "got 'one'")),
    "unknown point type word": Case(replace_line(12, "3 Floating 5 0 -8 0 0 0 0"), 12, "Attachment",
                                    ("expected a point type word", "got 'Floating'")),
    "point on a missing body": Case(replace_line(12, "3 Body1 5 0 -8 0 0 0 0"), 12, "Attachment",
                                    ("a point fixed to body 1, but the deck has 0 bodies", "'Body1'")),
    "point row too short": Case(replace_line(11, "2 Free 150 20 -60 40 0.2 0.5"), 11, "Ca",
                                ("POINTS row has 8 values", "9 (ID Attachment", "is missing")),
    "bad point coordinate": Case(replace_line(11, "2 Free 150 2O -60 40 0.2 0.5 1.0"), 11, "Y",
                                 ("expected a number", "got '2O'")),
    "negative point mass": Case(replace_line(11, "2 Free 150 20 -60 -40 0.2 0.5 1.0"), 11, "Mass",
                                ("expected a number >= 0", "got '-40'")),
    "free point that cannot move": Case(insert_after(12, "4 Free 0 0 -50 0 0 0 0"), 13, None,
                                        ("invalid model", "point 4", "free point")),
    # ---- LINES
    "unknown line type": Case(replace_line(17, "2 Poly 2 3 160.0 8 t"), 17, "LineType",
                              ("expected a line type name from LINE TYPES", "'wire', 'poly'", "got 'Poly'")),
    "unknown attachment word": Case(replace_line(16, "1 wire Q1 2 170.0 12 -"), 16, "AttachA",
                                    ("expected a point (n, Pn, POINTn, Cn, CONn)", "got 'Q1'")),
    "attachment to a nonexistent point": Case(replace_line(17, "2 poly 2 P7 160.0 8 t"), 17, "AttachB",
                                              ("expected a point number from 1 to 3", "no point 7", "'P7'")),
    "attachment to point 0": Case(replace_line(16, "1 wire 0 2 170.0 12 -"), 16, "AttachA",
                                  ("expected a point number from 1 to 3", "got '0'")),
    "attachment to a missing rod": Case(replace_line(17, "2 poly 2 R1B 160.0 8 t"), 17, "AttachB",
                                        ("there is no rod 1", "'R1B'")),
    "both ends on one point": Case(replace_line(17, "2 poly 3 C3 160.0 8 t"), 17, "AttachB",
                                   ("other than end A", "P3 for both ends")),
    "zero segments": Case(replace_line(16, "1 wire 1 2 170.0 0 -"), 16, "NumSegs",
                          ("expected a whole number >= 1", "got '0'")),
    "non-integer segments": Case(replace_line(16, "1 wire 1 2 170.0 20.5 -"), 16, "NumSegs",
                                 ("expected a whole number >= 1", "got '20.5'")),
    "zero length": Case(replace_line(17, "2 poly 2 3 0.0 8 t"), 17, "UnstrLen",
                        ("expected a non-zero number", "got '0.0'")),
    "length with a unit": Case(replace_line(17, "2 poly 2 3 160m 8 t"), 17, "UnstrLen",
                               ("expected a non-zero number", "got '160m'")),
    "line IDs out of order": Case(replace_line(16, "2 wire 1 2 170.0 12 -"), 16, "ID",
                                  ("expected 1", "row order", "got '2'")),
    "line row too short": Case(replace_line(17, "2 poly 2 3 160.0 8"), 17, "LineOutputs",
                               ("LINES row has 6 values", "is missing")),
    # ---- OPTIONS
    "missing value in OPTIONS row": Case(replace_line(19, "dtM"), 19, "dtM",
                                         ("expected a value before the key", "'value key [comment]'")),
    "missing key in OPTIONS row": Case(replace_line(19, "5e-4   # key forgotten"), 19, "key",
                                       ("expected a key after the value '5e-4'",)),
    "key and value swapped": Case(replace_line(20, "WtrDpth 90"), 20, "WtrDpth",
                                  ("expected 'value key'", "key first")),
    "bad option value": Case(replace_line(19, "fast dtM"), 19, "dtM",
                             ("expected a number > 0", "got 'fast'")),
    "alias with bad value": Case(replace_line(21, "heavy WtrDnsty"), 21, "WtrDnsty",
                                 ("expected a number >= 0", "got 'heavy'")),
    # g 0 and rho 0 are valid (weightless, vacuum); negative values are not
    "negative gravity": Case(insert_after(21, "-9.81 g"), 22, "g", ("expected a number >= 0", "got '-9.81'")),
    "negative density": Case(replace_line(21, "-1025 rho"), 21, "rho", ("expected a number >= 0", "got '-1025'")),
    "negative water depth": Case(replace_line(20, "-90 WtrDpth"), 20, "WtrDpth",
                                 ("expected a number >= 0", "got '-90'")),
    "missing depth grid as WtrDpth": Case(replace_line(20, "bathymetry.txt WtrDpth"), 20, "WtrDpth",
                                          ("MoorDyn-F depth grid", "'bathymetry.txt'", "not found")),
    "ICgenDynamic not 0 or 1": Case(insert_after(21, "2 ICgenDynamic"), 22, "ICgenDynamic",
                                    ("expected 0 or 1", "got '2'")),
}


@pytest.mark.parametrize("name", list(CASES))
def test_malformed_deck(tmp_path, name):
    case = CASES[name]
    for fname, content in case.files.items():
        (tmp_path / fname).write_text(content)
    text = case.edit(BASE)
    path = tmp_path / DECK
    path.write_text(text)
    with pytest.raises(DeckError) as ei:
        read_deck(path)
    err = ei.value
    msg = str(err)
    assert DECK in msg and err.file == str(path)
    if case.line is None:
        assert err.line is None
    else:
        assert err.line == case.line, msg
        assert f"line {case.line}:" in msg
    if err.row is not None:
        # the offending row is quoted under the message
        assert msg.splitlines()[-1].strip() == text.splitlines()[case.line - 1].strip()
    if case.field is not None:
        assert err.row is not None
        assert err.field == case.field, msg
        assert f"field {case.field!r}" in msg, msg
    for piece in case.expected:
        assert piece in msg, f"{piece!r} not in:\n{msg}"


def test_base_deck_is_valid(tmp_path):
    """The cases above must fail because of their edit, not because the base deck is bad."""
    path = tmp_path / DECK
    path.write_text(BASE)
    m = read_deck(path)
    assert (len(m.line_types), len(m.points), len(m.lines)) == (2, 3, 2)


def test_enough_cases():
    assert len(CASES) >= 12


def test_missing_deck_file(tmp_path):
    with pytest.raises(DeckError, match="nothere.txt.*cannot read"):
        read_deck(tmp_path / "nothere.txt")


def test_text_without_path_names_placeholder():
    with pytest.raises(DeckError, match=r"<deck>, line 16: field 'NumSegs'"):
        read_deck_text(replace_line(16, "1 wire 1 2 170.0 0 -")(BASE))


def test_read_curve_errors(tmp_path):
    p = tmp_path / "c.txt"
    p.write_text("a\nb\nc\n0 0\n0.5 1\n0.5 2\n")
    with pytest.raises(DeckError) as ei:
        read_curve(p, "EA")
    assert ei.value.line == 6 and "c.txt, line 6" in str(ei.value) and "strictly increasing" in str(ei.value)
    with pytest.raises(DeckError, match="cannot read"):
        read_curve(tmp_path / "none.txt")
    p.write_text("a\nb\nc\n0.5\n")
    with pytest.raises(DeckError, match="line 4.*two numbers"):
        read_curve(p)


def test_curve_file_error_keeps_curve_location(tmp_path):
    """The deck error points at the deck row; its text also names the curve file and line."""
    (tmp_path / "ea.txt").write_text("h\nh\nh\n0 0\n0 1\n")
    path = tmp_path / DECK
    path.write_text(replace_line(6, "poly 0.16 18.0 ea.txt -0.6 0 1.3 1.0 0.1 0.0")(BASE))
    with pytest.raises(DeckError) as ei:
        read_deck(path)
    assert ei.value.line == 6 and ei.value.field == "EA"
    assert f"{Path(tmp_path / 'ea.txt')}, line 5" in str(ei.value)
