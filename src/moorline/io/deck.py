"""Read MoorDyn v2 (and v1) input decks (line types, points, lines, options, outputs); the writer is
:mod:`moorline.io.writer`.

The reader works in two stages. :func:`moorline.io.lexer.lex` cuts the text into sections and rows
(each row keeps its line number and raw text); the builder here turns rows into a
:class:`~moorline.model.Model` through the column tables of :mod:`moorline.io.columns`, so that
every error can name the file, the line, the row, the field and what was expected. All bad input
raises :class:`~moorline.errors.DeckError`; anything else worth knowing is logged on ``moorline.io``.

Supported: LINE TYPES (also LINE DICTIONARY; 10, 11 or 13 columns; 9-column MoorDyn v1 rows), ROD
TYPES, BODIES, RODS, POINTS (9 or 12 column layouts, also v1 CONNECTION PROPERTIES and NODE
PROPERTIES), LINES (v2 layout and the v1 layout with the length before the end points), OPTIONS
(every MoorDyn-C key and the MoorDyn-F aliases; wave and current kinematics with their files),
OUTPUTS, EA/BA/EI curve files, seabed bathymetry (MoorDyn-C ``SeafloorFile`` grids and MoorDyn-F
depth grids given as ``WtrDpth``), seabed friction of both MoorDyn flavours, and moorline's own
seabed keys (``SeabedContact``, ``FrictionModel``, ``kShear``). The CONTROL and EXTERNAL LOADS
sections (MoorDyn-F only) are skipped with a warning, as MoorDyn-C does. The viscoelastic and Syrope
rope models (bar-separated EA and BA fields, the Syrope settings file and its SYROPE IC section) are
read here too.

MoorDyn v1 LINES rows (``Line LineType UnstrLen NumSegs NodeAnch NodeFair Flags``) are told apart
from v2 rows (``ID LineType AttachA AttachB UnstrLen NumSegs Outputs``) row by row: a row is v1 when
its columns 5 and 6 are plain unsigned integers naming existing points, its column 3 is a number,
and either column 3 or 4 is not a valid v2 attachment or the LINE TYPES section used the 9-column
v1 layout. Every other row is read as v2.
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path

from ..errors import DeckError
from ..model import (
    ELASTIC,
    SYROPE,
    Body,
    BodyKind,
    Curve,
    Failure,
    Line,
    LineType,
    Model,
    ModelError,
    Point,
    Rod,
    RodType,
    SyropeCurve,
)
from .columns import (
    BODY_COLUMNS,
    LINE_COLUMNS,
    LINE_COLUMNS_V1,
    LINE_TYPE_COLUMNS,
    LINE_TYPE_COLUMNS_V1,
    NOT_ACTED_ON,
    OPTION_KEYS,
    OPTION_TABLE,
    POINT_COLUMNS,
    POINT_COLUMNS_F,
    ROD_COLUMNS,
    ROD_TYPE_COLUMNS,
    BadField,
    CurveProblem,
    attachment_of,
    is_attachment,
    looks_like_file,
)
from .lexer import Row, Section, lex, parse_number, parse_whole, split_lines, tokenize
from .writer import write_deck  # noqa: F401  (its old home; moorline.io exports it)

log = logging.getLogger("moorline.io")

#: MoorDyn-C's limit on curve-file rows (more are accepted with a warning).
CURVE_MAX_POINTS = 30

_IGNORED = ("CONTROL", "EXTERNAL LOADS")  # MoorDyn-F only; MoorDyn-C ignores them too


# ---------------------------------------------------------------------------------- reader
class _Reader:
    """State of one deck being read (file name, folder, model under construction, row bookkeeping)."""

    def __init__(self, path, base_dir):
        self.path = Path(path) if path is not None else None
        self.file = str(path) if path is not None else "<deck>"
        if base_dir is not None:
            self.base_dir = Path(base_dir)
        elif self.path is not None:
            self.base_dir = self.path.resolve().parent
        else:
            self.base_dir = Path.cwd()
        self.model = Model()
        self.n_points = 0
        self.v1_types = False
        self.type_rows: dict[str, Row] = {}
        self.rod_type_rows: dict[str, Row] = {}
        self.rod_rows: list[Row] = []
        self.body_rows: list[Row] = []
        self.n_rods = 0
        self.point_rows: list[Row] = []
        self.line_rows: list[Row] = []
        self.option_rows: dict[str, Row] = {}
        self.sections: dict[str, Section] = {}

    # ----- errors
    def error(self, message, row: Row | None = None, field=None, *, line=None) -> DeckError:
        return DeckError(message, file=self.file, line=row.line if row is not None else line,
                         row=row.text if row is not None else None, field=field)

    def field_error(self, section, row, name, tok, bad: BadField) -> DeckError:
        if bad.plain:
            msg = f"field {name!r} of {section}: {bad.text}"
        else:
            msg = f"field {name!r} of {section}: expected {bad.text}, got {tok!r}"
        return self.error(msg, row, name)

    def read_fields(self, section, row, columns) -> dict:
        """Parse ``row.tokens`` against ``columns`` (extra tokens are ignored)."""
        out = {}
        for col, tok in zip(columns, row.tokens, strict=False):
            try:
                out[col.attr] = col.parse(tok, self)
            except BadField as bad:
                raise self.field_error(section, row, col.name, tok, bad) from None
        return out

    def check_count(self, section, row, columns, allowed: str):
        n = len(row.tokens)
        if n < len(columns):
            raise self.error(f"{section} row has {n} values, expected {allowed}: field "
                             f"{columns[n].name!r} is missing", row, columns[n].name)

    def check_id(self, section, row, got: int, want: int, name="ID"):
        if got != want:
            raise self.error(f"field {name!r} of {section}: expected {want} (IDs must read 1, 2, 3, ... in "
                             f"row order), got {row.tokens[0]!r}", row, name)

    # ----- EA / BA / EI
    def number_or_curve(self, tok, what, expected, cond):
        v = parse_number(tok)
        if v is not None:
            if cond is not None and not cond(v):
                raise BadField(expected)
            return v
        p = self.base_dir / tok
        if not p.is_file():
            article = "an" if what[0] in "AEIOU" else "a"
            raise BadField(f"{expected} or the name of {article} {what} curve file (no such file: {p})")
        try:
            return _load_curve(p, what)
        except CurveProblem as e:
            where = f"{p}" + (f", line {e.line}" if e.line is not None else "")
            row = f" (row {e.row.strip()!r})" if e.row is not None else ""
            raise BadField(f"bad {what} curve file {where}: {e.message}{row}", plain=True) from None

    # ----- sections
    def collect(self, sections: list[Section]):
        for sec in sections:
            if sec.name in self.sections:
                first = self.sections[sec.name]
                raise self.error(f"section {sec.name} appears twice (first header on line {first.line})",
                                 line=sec.line)
            self.sections[sec.name] = sec
        for sec in sections:
            if sec.name in _IGNORED:
                if sec.rows:
                    log.warning("%s, line %d: section %s (MoorDyn-F only) is ignored", self.file, sec.line,
                                sec.name)

    def required(self, name, what) -> Section:
        sec = self.sections.get(name)
        if sec is None:
            raise self.error(f"no {name} section: the deck needs a header line containing '---' and "
                             f"'{name}' followed by {what}")
        if not sec.rows:
            raise self.error(f"the {name} section has no rows: expected {what}", line=sec.line)
        return sec

    def read_line_types(self):
        rigid = any(self.sections.get(n) is not None and self.sections[n].rows for n in ("RODS", "BODIES"))
        sec = self.sections.get("LINE TYPES") if rigid else self.required("LINE TYPES", "at least one line type")
        for row in sec.rows if sec is not None else []:
            n = len(row.tokens)
            if n == 9:
                cols = LINE_TYPE_COLUMNS_V1
                if not self.v1_types:
                    log.info("%s, line %d: 9-column LINE TYPES row read as MoorDyn v1 "
                             "(Name Diam MassDenInAir EA BA Can Cat Cdn Cdt)", self.file, row.line)
                self.v1_types = True
            elif n in (10, 11, 13):
                cols = LINE_TYPE_COLUMNS[:n]
            else:
                allowed = "10, 11 or 13 (or 9 for a MoorDyn v1 row)"
                if n < 10:
                    self.check_count("LINE TYPES", row, LINE_TYPE_COLUMNS[:10], allowed)
                missing = "cF" if n == 12 else None
                extra = f"field {missing!r} is missing (dF and cF go together)" if missing else \
                    f"nothing may follow field 'cF' (got {row.tokens[13]!r})"
                raise self.error(f"LINE TYPES row has {n} values, expected {allowed}: {extra}", row,
                                 missing or "cF")
            f = self.read_fields("LINE TYPES", row, cols)
            if n == 11:
                f.update(dF=0.08, cF=0.18)
            self.axial_model(row, f)
            name = f.pop("name")
            if name in self.model.line_types:
                log.warning("%s, line %d: line type %r defined again; the later definition wins", self.file,
                            row.line, name)
            self.model.line_types[name] = LineType(name, **f)
            self.type_rows[name] = row

    def axial_model(self, row: Row, f: dict) -> None:
        """Unpack the EA and BA fields of a LINE TYPES row into the LineType keywords (spec 1.3.1)."""
        ax, ba = f.pop("EA"), f.pop("BA")
        f.update(EA=ax.EA, BA=ba.BA, elastic=ax.elastic, EA_D=ax.EA_D, EA_D_Lm=ax.EA_D_Lm, syrope=ax.syrope)
        if ax.elastic == ELASTIC:
            if ba.BA_D is not None:
                raise self.error("field 'BA/-zeta' of LINE TYPES: expected one value: BA_s|BA_d goes with a "
                                 "viscoelastic or Syrope EA field (EA_s|EA_d, EA_s|EA_Dc|EA_D_Lm, SYROPE:...)", row,
                                 "BA/-zeta")
            return
        if ba.BA_D is None:
            log.info("%s, line %d: no BA_d given for the viscoelastic line type: BA_d = 0 (as MoorDyn)", self.file,
                     row.line)
        f["BA_D"] = ba.BA_D or 0.0

    def syrope_settings(self, tok: str) -> SyropeCurve:
        """The Syrope settings file ``tok`` (relative to the deck's folder; spec 1.11.4): rows
        ``value key [comment]`` with the keys OWC (curve file, relative to the deck's folder), WCType,
        k1 and k2."""
        p = self.base_dir / tok
        try:
            text = p.read_bytes().decode("utf-8", errors="replace")
        except OSError as e:
            raise BadField(f"SYROPE:{tok}: cannot read the Syrope settings file {p}: {e.strerror or e}",
                           plain=True) from None
        got: dict[str, tuple[str, int, str]] = {}
        for lineno, raw in enumerate(split_lines(text), 1):
            toks = tokenize(raw)
            if len(toks) < 2:
                continue
            got[toks[1].upper()] = (toks[0], lineno, raw)
        missing = [k for k in ("OWC", "WCTYPE", "K1", "K2") if k not in got]
        if missing:
            raise BadField(f"Syrope settings file {p}: expected rows 'value key' for OWC, WCType, k1 and k2; "
                           f"missing {', '.join(missing)}", plain=True)
        vals = {}
        for key in ("K1", "K2"):
            v = parse_number(got[key][0])
            if v is None:
                raise BadField(f"Syrope settings file {p}, line {got[key][1]}: expected a number for {key.lower()}, "
                               f"got {got[key][0]!r}", plain=True)
            vals[key] = v
        owc_path = self.base_dir / got["OWC"][0]
        if not owc_path.is_file():
            raise BadField(f"Syrope settings file {p}, line {got['OWC'][1]}: no such original working curve file "
                           f"{owc_path} (relative to the deck's folder, as MoorDyn reads it)", plain=True)
        try:
            owc = _load_curve(owc_path, "Syrope OWC")
        except CurveProblem as e:
            where = f"{owc_path}" + (f", line {e.line}" if e.line is not None else "")
            raise BadField(f"bad Syrope original working curve {where}: {e.message}", plain=True) from None
        curve = SyropeCurve(owc, got["WCTYPE"][0].upper(), vals["K1"], vals["K2"], source=str(p))
        try:
            curve.check()
        except ModelError as e:
            raise BadField(str(e), plain=True) from None
        return curve

    def read_syrope_ic(self):
        """SYROPE IC rows ``Line(s) Tmax0 Tmean0`` (spec 1.9)."""
        sec = self.sections.get("SYROPE IC")
        rows = sec.rows if sec is not None else []
        syrope = {n for n, lt in self.model.line_types.items() if lt.elastic == SYROPE}
        if rows and not syrope:
            raise self.error("section SYROPE IC: no line type uses the Syrope model (SYROPE:<settings>|EA_Dc|EA_D_Lm "
                             "in LINE TYPES)", line=sec.line)
        nl = len(self.model.lines)
        for row in rows:
            if len(row.tokens) < 3:
                raise self.error(f"SYROPE IC row has {len(row.tokens)} values, expected 3 (Line(s) Tmax0 Tmean0)", row,
                                 ("Line(s)", "Tmax0", "Tmean0")[len(row.tokens)])
            ids = []
            for part in row.tokens[0].split(","):
                v = parse_whole(part)
                if v is None or not 1 <= v <= nl:
                    raise self.error(f"field 'Line(s)' of SYROPE IC: expected line numbers from 1 to {nl} separated "
                                     f"by commas, got {row.tokens[0]!r}", row, "Line(s)")
                ids.append(v)
            vals = []
            for name, tok in zip(("Tmax0", "Tmean0"), row.tokens[1:3], strict=True):
                v = parse_number(tok)
                if v is None or v < 0:
                    raise self.error(f"field {name!r} of SYROPE IC: expected a tension >= 0 [N], got {tok!r}", row,
                                     name)
                vals.append(v)
            for k in ids:
                ln = self.model.lines[k - 1]
                if ln.line_type not in syrope:
                    log.warning("%s, line %d: line %d does not use the Syrope model; its SYROPE IC values are ignored",
                                self.file, row.line, k)
                    continue
                ln.syrope_ic = (vals[0], vals[1])

    def read_failures(self):
        """FAILURE rows ``FailureID Point Line(s) FailTime FailTen`` (spec 1.10): the point or rod
        end, the lines released there (comma-separated), the failure time [s] and load [N], each
        0 for none."""
        sec = self.sections.get("FAILURE")
        for k, row in enumerate(sec.rows if sec is not None else [], 1):
            names = ("FailureID", "Point", "Line(s)", "FailTime", "FailTen")
            if len(row.tokens) < 5:
                missing = names[len(row.tokens)]
                raise self.error(f"FAILURE row has {len(row.tokens)} values, expected 5 (FailureID Point Line(s) "
                                 f"FailTime FailTen): field {missing!r} is missing", row, missing)
            fid = parse_whole(row.tokens[0])
            self.check_id("FAILURE", row, fid if fid is not None else -1, k, "FailureID")
            try:
                att = attachment_of(row.tokens[1], self)
            except BadField as bad:
                raise self.field_error("FAILURE", row, "Point", row.tokens[1], bad) from None
            nl = len(self.model.lines)
            ids = []
            for part in row.tokens[2].split(","):
                v = parse_whole(part)
                if v is None or not 1 <= v <= nl:
                    raise self.error(f"field 'Line(s)' of FAILURE: expected line numbers from 1 to {nl} separated "
                                     f"by commas (no spaces), got {row.tokens[2]!r}", row, "Line(s)")
                ln = self.model.lines[v - 1]
                if att not in (ln.end_a, ln.end_b):
                    raise self.error(f"field 'Line(s)' of FAILURE: line {v} is not attached to {row.tokens[1]} (its "
                                     f"ends: {ln.end_a}, {ln.end_b})", row, "Line(s)")
                ids.append(v - 1)
            vals = []
            for name, tok in zip(names[3:], row.tokens[3:5], strict=True):
                v = parse_number(tok)
                if v is None or not v >= 0:
                    raise self.error(f"field {name!r} of FAILURE: expected a number >= 0 (0 for none), got {tok!r}",
                                     row, name)
                vals.append(v if v > 0 else math.inf)
            if vals == [math.inf, math.inf]:
                log.warning("%s, line %d: failure %d has neither a time nor a tension (both 0): it never happens",
                            self.file, row.line, k)
            self.model.failures.append(Failure(att, ids, vals[0], vals[1]))

    def read_bodies(self):
        sec = self.sections.get("BODIES")
        for k, row in enumerate(sec.rows if sec is not None else [], 1):
            self.check_count("BODIES", row, BODY_COLUMNS, "14 (ID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG I Volume "
                             "CdA Ca)")
            f = self.read_fields("BODIES", row, BODY_COLUMNS)
            self.check_id("BODIES", row, f.pop("ID"), k)
            r = (f.pop("X0"), f.pop("Y0"), f.pop("Z0"))
            angles = (f.pop("r0"), f.pop("p0"), f.pop("y0"))
            cg = f.pop("rCG")
            f["rCG"] = (0.0, 0.0, cg[0]) if len(cg) == 1 else cg
            cda = f.pop("CdA")
            # 1 value: all six DOF; 2: translation|rotation; 3: x|y|z for translation and rotation
            # alike (the documented meaning; MoorDyn-C mis-reads 3 and 6 values, spec 1.5); 6: per DOF
            if len(cda) == 1:
                f["CdA"] = cda * 6
            elif len(cda) == 2:
                f["CdA"] = [cda[0]] * 3 + [cda[1]] * 3
            elif len(cda) == 3:
                f["CdA"] = cda * 2
            else:
                f["CdA"] = cda
            if f["kind"] not in (BodyKind.FREE, BodyKind.COUPLED_PINNED) and (
                    f["m"] or f["V"] or any(f["I"]) or any(f["CdA"]) or any(f["Ca"])):
                log.info("%s, line %d: body %d is %s: its own mass, volume, inertia, CdA and Ca are not used (as "
                         "in MoorDyn); only attached rods and points carry mass and loads", self.file, row.line,
                         k, f["kind"].name.lower())
            self.model.bodies.append(Body(r=r, angles=angles, **f))
            self.body_rows.append(row)

    def read_rod_types(self):
        sec = self.sections.get("ROD TYPES")
        for row in sec.rows if sec is not None else []:
            self.check_count("ROD TYPES", row, ROD_TYPE_COLUMNS, "7 (Name Diam Mass/m Cd Ca CdEnd CaEnd)")
            f = self.read_fields("ROD TYPES", row, ROD_TYPE_COLUMNS)
            name = f.pop("name")
            self.model.rod_types[name] = RodType(name, **f)
            self.rod_type_rows[name] = row

    def read_rods(self):
        sec = self.sections.get("RODS")
        for k, row in enumerate(sec.rows if sec is not None else [], 1):
            self.check_count("RODS", row, ROD_COLUMNS, "11 (ID RodType Attachment Xa Ya Za Xb Yb Zb NumSegs "
                             "RodOutputs)")
            f = self.read_fields("RODS", row, ROD_COLUMNS)
            self.check_id("RODS", row, f.pop("ID"), k)
            if f["rod_type"] not in self.model.rod_types:
                known = ", ".join(repr(t) for t in self.model.rod_types) or "none defined"
                raise self.error(f"field 'RodType' of RODS: expected a rod type name from ROD TYPES ({known}), got "
                                 f"{f['rod_type']!r}", row, "RodType")
            rA = (f.pop("Xa"), f.pop("Ya"), f.pop("Za"))
            rB = (f.pop("Xb"), f.pop("Yb"), f.pop("Zb"))
            f["kind"], f["body"] = f["kind"]
            if f["N"] == 0 and rA != rB:
                log.warning("%s, line %d: rod %d has NumSegs 0, so it is a zero-length rod: both its ends are at end "
                            "A (%g, %g, %g) and its axis follows its cables at every step, as in MoorDyn; end B (%g, "
                            "%g, %g) is not used. A cable clamped at a fixed angle needs a rod with segments",
                            self.file, row.line, k, *rA, *rB)
            self.model.rods.append(Rod(rA=rA, rB=rB, **f))
            self.rod_rows.append(row)
        self.n_rods = len(self.model.rods)

    def read_points(self):
        sec = self.sections.get("POINTS")
        rows = sec.rows if sec is not None else []
        for k, row in enumerate(rows, 1):
            if len(row.tokens) >= 12:
                cols = POINT_COLUMNS_F
            else:
                self.check_count("POINTS", row, POINT_COLUMNS, "9 (ID Attachment X Y Z Mass Volume CdA Ca) "
                                 "or 12 (... Volume FX FY FZ CdA Ca)")
                cols = POINT_COLUMNS
            f = self.read_fields("POINTS", row, cols)
            self.check_id("POINTS", row, f.pop("ID"), k)
            r = (f.pop("X"), f.pop("Y"), f.pop("Z"))
            F = (f.pop("FX", 0.0), f.pop("FY", 0.0), f.pop("FZ", 0.0))
            f["kind"], f["body"] = f["kind"]
            self.model.points.append(Point(r=r, F_ext=F, **f))
            self.point_rows.append(row)
        self.n_points = len(self.model.points)

    def is_v1_line(self, toks) -> bool:
        if not all(re.fullmatch(r"\d+", t) and 1 <= int(t) <= self.n_points for t in toks[4:6]):
            return False
        if parse_number(toks[2]) is None:
            return False
        return self.v1_types or not (is_attachment(toks[2], self.n_points)
                                     and is_attachment(toks[3], self.n_points))

    def read_lines(self):
        if self.model.rods or self.model.bodies:
            sec = self.sections.get("LINES")
            rows = sec.rows if sec is not None else []
        else:
            rows = self.required("LINES", "at least one line (or a RODS or BODIES section)").rows
        said_v1 = False
        for k, row in enumerate(rows, 1):
            self.check_count("LINES", row, LINE_COLUMNS,
                             "7 (ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs)")
            cols = LINE_COLUMNS
            if self.is_v1_line(row.tokens):
                cols = LINE_COLUMNS_V1
                if not said_v1:
                    log.info("%s, line %d: LINES row read in the MoorDyn v1 layout "
                             "(Line LineType UnstrLen NumSegs NodeAnch NodeFair Flags)", self.file, row.line)
                    said_v1 = True
            f = self.read_fields("LINES", row, cols)
            self.check_id("LINES", row, f.pop("ID"), k, cols[0].name)
            if f["line_type"] not in self.model.line_types:
                known = ", ".join(repr(t) for t in self.model.line_types)
                raise self.error(f"field 'LineType' of LINES: expected a line type name from LINE TYPES "
                                 f"({known}; names are case-sensitive), got {f['line_type']!r}", row,
                                 "LineType")
            if f["end_a"] == f["end_b"]:
                name = "NodeFair" if cols is LINE_COLUMNS_V1 else "AttachB"
                raise self.error(f"field {name!r} of LINES: expected an attachment other than end A's, got "
                                 f"{f['end_b']} for both ends", row, name)
            self.model.lines.append(Line(**f))
            self.line_rows.append(row)

    def read_options(self):
        sec = self.sections.get("OPTIONS")
        given: dict[str, tuple[str, Row, str]] = {}  # canonical -> (value, row, key as typed)
        for row in sec.rows if sec is not None else []:
            toks = row.tokens
            if len(toks) < 2:
                tok = toks[0]
                if tok.lower() in OPTION_KEYS:
                    raise self.error(f"field {tok!r} of OPTIONS: expected a value before the key (rows are "
                                     f"'value key [comment]'), got only the key", row, tok)
                raise self.error(f"field 'key' of OPTIONS: expected a key after the value {tok!r} (rows are "
                                 "'value key [comment]')", row, "key")
            value, key = toks[0], toks[1]
            canon = OPTION_KEYS.get(key.lower())
            if canon is None:
                if value.lower() in OPTION_KEYS:
                    raise self.error(f"field {value!r} of OPTIONS: expected 'value key', got the key first "
                                     f"({value!r} then {key!r})", row, value)
                log.warning("%s, line %d: unknown option %r ignored", self.file, row.line, key)
                continue
            if canon in given:
                log.debug("%s, line %d: option %s given again; the last value wins", self.file, row.line,
                          canon)
            given[canon] = (value, row, key)
        for key, _aliases, target, attr, parse in OPTION_TABLE:
            if key not in given:
                continue
            value, row, typed = given[key]
            try:
                v = parse(value, self)
            except BadField as bad:
                raise self.field_error("OPTIONS", row, typed, value, bad) from None
            setattr(self.model.env if target == "env" else self.model.options, attr, v)
            self.option_rows[key] = row
        self.read_seabed(given)
        self.read_water(given)
        for key, (_aliases, neutral) in NOT_ACTED_ON.items():
            if key not in given:
                continue
            value, row, typed = given[key]
            self.option_rows[key] = row
            if neutral(value, given):
                log.debug("%s, line %d: option %s = %s has no effect here", self.file, row.line, typed, value)
                continue
            self.model.options.not_acted_on[key] = value
            log.warning("%s, line %d: option %s = %s is read but not acted on by this version of moorline",
                        self.file, row.line, typed, value)

    def read_water(self, given):
        """WaveKin, Currents, dtWave and UnifyCurrentGrid: the waves and current and the files they name
        (spec 4.1, 4.8)."""
        from .waterkin import DT_WAVE, water_from_options

        def whole(key, default):
            if key not in given:
                return default
            value, row, typed = given[key]
            self.option_rows[key] = row
            v = parse_whole(value)
            if v is None:
                v = parse_number(value)
                v = int(v) if v is not None and float(v).is_integer() else None
            if v is None:
                raise self.error(f"field {typed!r} of OPTIONS: expected a whole number, got {value!r}", row, typed)
            return v

        wave_kin = whole("WaveKin", 0)
        currents = whole("Currents", 0)
        dt_wave = DT_WAVE
        if "dtWave" in given:
            value, row, typed = given["dtWave"]
            self.option_rows["dtWave"] = row
            dt_wave = parse_number(value)
            if dt_wave is None or not dt_wave > 0:
                raise self.error(f"field {typed!r} of OPTIONS: expected a number > 0, got {value!r}", row, typed)
        unify = True
        if "UnifyCurrentGrid" in given:
            value, row, typed = given["UnifyCurrentGrid"]
            self.option_rows["UnifyCurrentGrid"] = row
            if value.strip() not in ("0", "1"):
                raise self.error(f"field {typed!r} of OPTIONS: expected 0 or 1 (the only values MoorDyn reads), got "
                                 f"{value!r}", row, typed)
            unify = value.strip() == "1"
        o = self.model.options
        o.WaveKin, o.Currents, o.dtWave = wave_kin, currents, dt_wave
        if wave_kin == 0 and currents == 0:
            return
        try:
            waves, current = water_from_options(wave_kin, currents, self.base_dir, self.model.env.depth or None,
                                                dt_wave=dt_wave, unify_current_grid=unify)
        except DeckError as e:
            key = e.field if e.field in given else ("WaveKin" if "WaveKin" in given else "Currents")
            row = given[key][1] if key in given else None
            if e.file is not None and e.file != self.file:
                raise  # the message names the water-kinematics file and its line
            raise self.error(f"field {key!r} of OPTIONS: {e}", row, key) from None
        self.model.env.waves = waves
        self.model.env.current = current

    def read_seabed(self, given):
        """Bathymetry files and the choice of friction model (after the plain options)."""
        from .bathymetry import find_seafloor_file, read_depth_grid, read_seafloor_grid

        env = self.model.env
        for key, reader, what in (("SeafloorFile", read_seafloor_grid, "MoorDyn-C seafloor grid"),
                                  ("WtrDpth", read_depth_grid, "MoorDyn-F depth grid")):
            if key not in given or not looks_like_file(given[key][0]):
                continue
            value, row, typed = given[key]
            if env.bathymetry is not None:
                raise self.error(f"field {typed!r} of OPTIONS: a bathymetry was already given; expected one "
                                 "SeafloorFile or one WtrDpth file, not both", row, typed)
            try:
                path = find_seafloor_file(value, self.base_dir)
                env.bathymetry = reader(path)
            except DeckError as e:
                raise self.error(f"field {typed!r} of OPTIONS: bad {what} {value!r}: {e}", row, typed) from None
            env.depth = env.bathymetry.mean_depth
            log.info("%s, line %d: seabed from %s (%d x %d grid); water depth for waves = mean depth %.6g m",
                     self.file, row.line, path, env.bathymetry.x.size, env.bathymetry.y.size, env.depth)
        if "FrictionModel" not in given and any(k in given for k in ("mu_kT", "mu_kA", "mc", "cv")):
            env.friction = "directional"

    def read_outputs(self):
        sec = self.sections.get("OUTPUTS")
        for row in sec.rows if sec is not None else []:
            for tok in row.tokens:
                if tok.upper() == "END":
                    log.debug("%s, line %d: v1 END row skipped", self.file, row.line)
                    continue
                self.model.outputs.append(tok)

    def validate(self):
        try:
            self.model.validate()
        except ModelError as e:
            msg = str(e)
            row = self._row_for(msg)
            line = None
            if row is None and "no lines" in msg and "LINES" in self.sections:
                line = self.sections["LINES"].line
            raise self.error(f"invalid model: {msg}", row, line=line) from None

    def _row_for(self, msg) -> Row | None:
        m = re.match(r"line type '([^']*)'", msg)
        if m:
            return self.type_rows.get(m.group(1))
        m = re.match(r"rod type '([^']*)'", msg)
        if m:
            return self.rod_type_rows.get(m.group(1))
        for pattern, rows in ((r"line (\d+)", self.line_rows), (r"point (\d+)", self.point_rows),
                              (r"rod (\d+)", self.rod_rows), (r"body (\d+)", self.body_rows)):
            m = re.match(pattern, msg)
            if m and 1 <= int(m.group(1)) <= len(rows):
                return rows[int(m.group(1)) - 1]
        for word, keys in (("rho", ("rho", "g")), ("water depth", ("WtrDpth",))):
            if word in msg:
                return next((self.option_rows[k] for k in keys if k in self.option_rows), None)
        return None


def read_deck_text(text: str, path=None, base_dir=None) -> Model:
    """Build a :class:`~moorline.model.Model` from the text of a MoorDyn v2 deck.

    Parameters
    ----------
    text : str
        The deck.
    path : str or Path, optional
        File name used in messages and as ``model.source``; its folder is the default ``base_dir``.
    base_dir : str or Path, optional
        Folder that curve file names are relative to (default: the folder of ``path``, else the
        working directory).

    Returns
    -------
    Model
        A validated model.

    Raises
    ------
    DeckError
        For any malformed or unsupported content, naming file, line, row and field.
    """
    rd = _Reader(path, base_dir)
    rd.collect(lex(text, file=rd.file))
    rd.read_options()
    rd.read_line_types()
    rd.read_bodies()
    rd.read_rod_types()
    rd.read_rods()
    rd.read_points()
    rd.read_lines()
    rd.read_syrope_ic()
    rd.read_failures()
    rd.read_outputs()
    rd.model.source = rd.path
    rd.validate()
    return rd.model


def read_deck(path) -> Model:
    """Read a MoorDyn v2 input deck (also the v1 layouts of LINE TYPES and LINE PROPERTIES).

    Parameters
    ----------
    path : str or Path
        The deck file. Curve files named in it are looked up in its folder.

    Returns
    -------
    Model
        A validated model with ``model.source`` set to ``Path(path)``.

    Raises
    ------
    DeckError
        If the file cannot be read or its content is malformed or not supported.
    """
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except OSError as e:
        raise DeckError(f"cannot read the deck: {e.strerror or e}", file=path) from e
    return read_deck_text(text, path=path)


# ---------------------------------------------------------------------------------- curves
def _load_curve(path: Path, what: str) -> Curve:
    try:
        text = path.read_bytes().decode("utf-8", errors="replace")
    except OSError as e:
        raise CurveProblem(f"cannot read the file: {e.strerror or e}") from e
    xs: list[float] = []
    ys: list[float] = []
    last_line = 0
    for lineno, raw in enumerate(split_lines(text), 1):
        if lineno <= 3:
            continue
        toks = tokenize(raw)
        if not toks:
            continue
        if len(toks) < 2:
            raise CurveProblem("expected two numbers 'x y', got one value", lineno, raw)
        x, y = parse_number(toks[0]), parse_number(toks[1])
        if x is None or y is None:
            bad = toks[0] if x is None else toks[1]
            raise CurveProblem(f"expected two numbers 'x y', got {bad!r}", lineno, raw)
        if xs and x <= xs[-1]:
            raise CurveProblem(f"expected x values strictly increasing, got {x:g} after {xs[-1]:g} "
                                f"(line {last_line})", lineno, raw)
        xs.append(x)
        ys.append(y)
        last_line = lineno
    if len(xs) < 2:
        raise CurveProblem(f"expected at least two 'x y' rows after the three header lines, got {len(xs)}")
    if len(xs) > CURVE_MAX_POINTS:
        log.warning("%s: %s curve has %d points; MoorDyn accepts at most %d", path, what, len(xs),
                    CURVE_MAX_POINTS)
    return Curve(xs, ys, source=str(path))


def read_curve(path, what: str = "curve") -> Curve:
    """Read a MoorDyn lookup-table file (EA, BA or EI curve, spec 1.11.1).

    The first three lines are headers; every later non-blank line holds ``x y`` (extra tokens are
    ignored). x must be strictly increasing.

    Parameters
    ----------
    path : str or Path
        The curve file.
    what : str
        What the table is (``"EA"``, ``"BA"``, ``"EI"``), for messages.

    Returns
    -------
    Curve
        With ``source`` set to ``str(path)``.

    Raises
    ------
    DeckError
        Naming the file and line of the first bad row.
    """
    path = Path(path)
    try:
        return _load_curve(path, what)
    except CurveProblem as e:
        raise DeckError(f"{what} curve: {e.message}", file=path, line=e.line, row=e.row) from None
