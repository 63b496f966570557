"""The column tables of a MoorDyn v2 deck: for every section, the columns of its rows (name, unit,
how the text is parsed and checked, the model attribute it sets), the OPTIONS keys with their
aliases and checks, and the field parsers they use. The builder (:mod:`moorline.io.deck`) reads
rows through these tables, so the format is written down once, here.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

from ..model import (
    BODY_KIND_WORDS,
    CONTACT_MODES,
    ELASTIC,
    FRICTION_MODELS,
    POINT_KIND_WORDS,
    SYROPE,
    VISCO_CONSTANT,
    VISCO_MEAN,
    Attachment,
    BodyKind,
    PointKind,
    RodKind,
)
from .lexer import parse_number, parse_whole

log = logging.getLogger("moorline.io")


class BadField(Exception):
    """A field that cannot be read: ``text`` is what was expected (or, if ``plain``, the whole story)."""

    def __init__(self, text: str, plain: bool = False):
        super().__init__(text)
        self.text = text
        self.plain = plain


class CurveProblem(Exception):
    def __init__(self, message: str, line: int | None = None, row: str | None = None):
        super().__init__(message)
        self.message, self.line, self.row = message, line, row


# ---------------------------------------------------------------------------------- field parsers
# Each parser takes (token, reader) and returns the value or raises BadField(expected).

def _num(tok, rd=None, *, cond=None, what="a number"):
    v = parse_number(tok)
    if v is None or (cond is not None and not cond(v)):
        raise BadField(what)
    return v


def _any(tok, rd=None):
    return _num(tok)


def _pos(tok, rd=None):
    return _num(tok, cond=lambda v: v > 0, what="a number > 0")


def _nonneg(tok, rd=None):
    return _num(tok, cond=lambda v: v >= 0, what="a number >= 0")


def _nonzero(tok, rd=None):
    return _num(tok, cond=lambda v: v != 0,
                what="a non-zero number (a negative value -f means f times the end-to-end distance)")


def _whole(tok, rd=None):
    v = parse_whole(tok)
    if v is None:
        raise BadField("a whole number")
    return v


def _flag01(tok, rd=None):
    v = parse_whole(tok)
    if v not in (0, 1):
        raise BadField("0 or 1")
    return v


def _auto01(tok, rd=None):
    v = parse_whole(tok)
    if v not in (-1, 0, 1):
        raise BadField("-1 (automatic), 0 or 1")
    return v


def _nsegs(tok, rd=None):
    v = parse_whole(tok)
    if v is None or v < 1:
        raise BadField("a whole number >= 1")
    return v


def _word(tok, rd=None):
    return tok


def _state_file(tok, rd=None):
    p = (rd.base_dir if rd is not None else Path.cwd()) / tok
    if not p.is_file():
        # MoorDyn's own test decks name state files they do not ship (and MoorDyn-C 2.7 runs them)
        log.warning("%s: fileIC names %s, which does not exist; the initial conditions are found without it",
                    rd.file if rd is not None else "deck", p)
        return None
    return str(p)


def _flags(tok, rd=None):
    return "" if tok == "-" else tok


class AxialField(NamedTuple):
    """The EA field of LINE TYPES: the stiffness (a number, a curve, or the Syrope original
    working curve), the axial model and its dynamic-stiffness parameters (spec 1.3.1)."""

    EA: Any
    elastic: int
    EA_D: float = 0.0
    EA_D_Lm: float = 0.0
    syrope: Any = None


class DampingField(NamedTuple):
    """The BA field: BA (or -zeta, or a curve) and, for the viscoelastic models, BA_d."""

    BA: Any
    BA_D: float | None = None


def _ea(tok, rd):
    parts = tok.split("|")
    if len(parts) > 3:
        raise BadField(f"{tok!r}: at most three bar-separated values (EA, EA_s|EA_d, EA_s|EA_Dc|EA_D_Lm or "
                       "SYROPE:<settings>|EA_Dc|EA_D_Lm)", plain=True)
    rest = []
    for x in parts[1:]:
        v = parse_number(x)
        if v is None or v < 0:
            raise BadField(f"{tok!r}: the dynamic-stiffness values after '|' must be numbers >= 0, got {x!r}",
                           plain=True)
        rest.append(v)
    head = parts[0]
    if head.upper().startswith("SYROPE:"):
        if len(parts) != 3:
            raise BadField(f"{tok!r}: the Syrope model is SYROPE:<settings file>|EA_Dc|EA_D_Lm (three values)",
                           plain=True)
        syrope = rd.syrope_settings(head[len("SYROPE:"):])
        return AxialField(syrope.owc, SYROPE, rest[0], rest[1], syrope)
    if head.upper().startswith("SYROPE"):
        raise BadField(f"{tok!r}: expected SYROPE:<settings file>|EA_Dc|EA_D_Lm", plain=True)
    EA = rd.number_or_curve(head, "EA", "a number > 0", lambda v: v > 0)
    if len(parts) == 1:
        return AxialField(EA, ELASTIC)
    if len(parts) == 2:
        return AxialField(EA, VISCO_CONSTANT, rest[0])
    return AxialField(EA, VISCO_MEAN, rest[0], rest[1])


def _ba(tok, rd):
    parts = tok.split("|")
    if len(parts) > 2:
        raise BadField(f"{tok!r}: at most two bar-separated values (BA_s|BA_d)", plain=True)
    BA = rd.number_or_curve(parts[0], "BA", "a number (negative = -zeta damping ratio)", None)
    if len(parts) == 1:
        return DampingField(BA)
    v = parse_number(parts[1])
    if v is None or v < 0:
        raise BadField(f"{tok!r}: BA_d must be a number >= 0 (the dynamic damper takes no -zeta ratio), got "
                       f"{parts[1]!r}", plain=True)
    return DampingField(BA, v)


def _ei(tok, rd):
    return rd.number_or_curve(tok, "EI", "a number >= 0", lambda v: v >= 0)


_POINT_KIND_TEXT = "Fixed/Anchor/Fix, Coupled/Vessel/Ves/Cpld/Fairlead, Free/Point/Connect/Con or Body<n>"


def _body_number(up, tok, rd, what):
    """0-based index of the body named by ``Body<n>...`` (checked against the deck's bodies)."""
    n = int(re.match(r"BODY(\d+)", up).group(1))
    nb = len(rd.model.bodies) if rd is not None else 0
    if not 1 <= n <= nb:
        raise BadField(f"{tok!r}: {what} body {n}, but the deck has {nb} bodies (BODIES section)", plain=True)
    return n - 1


def _point_kind(tok, rd=None):
    """(kind, body index or None) of a point attachment word."""
    up = tok.upper()
    if up in POINT_KIND_WORDS:
        return POINT_KIND_WORDS[up], None
    if re.fullmatch(r"BODY\d+", up):
        return PointKind.BODY, _body_number(up, tok, rd, "a point fixed to")
    if re.fullmatch(r"TURBINE\d+", up):
        raise BadField(f"{tok!r}: TURBINE<n> points are a FAST.Farm feature and are not supported", plain=True)
    raise BadField(f"a point type word ({_POINT_KIND_TEXT})")


_POINT_REF = re.compile(r"(?:P|POINT|C|CON)?(\d+)")
_ROD_REF = re.compile(r"(?:R|ROD)(\d+)([AB]?)")


def attachment_of(tok, rd):
    up = tok.upper()
    m = _POINT_REF.fullmatch(up)
    if m:
        n = int(m.group(1))
        if not 1 <= n <= rd.n_points:
            raise BadField(f"a point number from 1 to {rd.n_points} (there is no point {n}; the deck has "
                       f"{rd.n_points} points)")
        return Attachment("point", n - 1)
    m = _ROD_REF.fullmatch(up)
    if m:
        n = int(m.group(1))
        if not m.group(2):
            raise BadField(f"a rod end with its letter, e.g. R{n}A or R{n}B (the end letter is mandatory for rods)")
        if not 1 <= n <= rd.n_rods:
            raise BadField(f"a rod end of a rod from 1 to {rd.n_rods} (there is no rod {n}; the deck has "
                       f"{rd.n_rods} rods)")
        return Attachment("rod", n - 1, m.group(2))
    raise BadField("a point (n, Pn, POINTn, Cn, CONn) or a rod end (RnA, RnB, RODnA, RODnB)")


_ROD_WORDS = {
    "ANCHOR": RodKind.FIXED, "FIXED": RodKind.FIXED, "FIX": RodKind.FIXED,
    "PINNED": RodKind.PINNED, "PIN": RodKind.PINNED,
    "VESSEL": RodKind.COUPLED, "VES": RodKind.COUPLED, "COUPLED": RodKind.COUPLED, "CPLD": RodKind.COUPLED,
    "VESSELPINNED": RodKind.COUPLED_PINNED, "VESPIN": RodKind.COUPLED_PINNED, "CPLDPIN": RodKind.COUPLED_PINNED,
    "COUPLEDPINNED": RodKind.COUPLED_PINNED,
    "POINT": RodKind.FREE, "CON": RodKind.FREE, "FREE": RodKind.FREE,
}


def _rod_kind(tok, rd=None):
    """(kind, body index or None) of a rod attachment word."""
    up = tok.upper()
    if up in _ROD_WORDS:
        return _ROD_WORDS[up], None
    m = re.fullmatch(r"BODY\d+(PINNED|PIN)?", up)
    if m:
        kind = RodKind.BODY_PINNED if m.group(1) else RodKind.BODY
        return kind, _body_number(up, tok, rd, "a rod on")
    raise BadField("a rod attachment word (Fixed/Anchor, Pinned, Body<n>, Body<n>Pinned, Coupled/Vessel, "
               "CoupledPinned/VesPin, Free/Point)")


def _body_kind(tok, rd=None):
    return BODY_KIND_WORDS.get(tok.upper(), BodyKind.FREE)


def _bars(n_allowed, what, nonneg=True):
    """Parser of ``a|b|c`` lists with one of the lengths ``n_allowed``."""
    def parse(tok, rd=None):
        parts = tok.split("|")
        vals = [parse_number(x) for x in parts]
        if any(v is None or (nonneg and v < 0) for v in vals) or len(vals) not in n_allowed:
            raise BadField(what)
        return vals
    return parse


def _segs0(tok, rd=None):
    v = parse_whole(tok)
    if v is None or v < 0:
        raise BadField("a whole number >= 0")
    return v


def is_attachment(tok: str, n_points: int) -> bool:
    up = tok.upper()
    m = _POINT_REF.fullmatch(up)
    if m:
        return 1 <= int(m.group(1)) <= n_points
    return _ROD_REF.fullmatch(up) is not None


# ---------------------------------------------------------------------------------- column tables
@dataclass(frozen=True)
class Column:
    """One column of a table section.

    Attributes
    ----------
    name : str
        Field name as used in messages and in the titles row written by :func:`write_deck`.
    unit : str
        Units text for the units row.
    parse : callable
        ``parse(token, reader) -> value``.
    attr : str
        Keyword of the model object the value goes to.
    """

    name: str
    unit: str
    parse: Callable[[str, Any], Any]
    attr: str


def _c(name, unit, parse, attr=None):
    return Column(name, unit, parse, attr or name)


LINE_TYPE_COLUMNS = (
    _c("TypeName", "(name)", _word, "name"), _c("Diam", "(m)", _pos, "d"), _c("Mass/m", "(kg/m)", _pos, "w"),
    _c("EA", "(N)", _ea), _c("BA/-zeta", "(N-s/-)", _ba, "BA"), _c("EI", "(N-m^2)", _ei),
    _c("Cd", "(-)", _nonneg), _c("Ca", "(-)", _nonneg), _c("CdAx", "(-)", _nonneg),
    _c("CaAx", "(-)", _nonneg), _c("Cl", "(-)", _nonneg), _c("dF", "(-)", _nonneg), _c("cF", "(-)", _nonneg),
)
LINE_TYPE_COLUMNS_V1 = (
    _c("Name", "(name)", _word, "name"), _c("Diam", "(m)", _pos, "d"),
    _c("MassDenInAir", "(kg/m)", _pos, "w"),
    _c("EA", "(N)", _ea), _c("BA/-zeta", "(N-s/-)", _ba, "BA"), _c("Can", "(-)", _nonneg, "Ca"),
    _c("Cat", "(-)", _nonneg, "CaAx"), _c("Cdn", "(-)", _nonneg, "Cd"), _c("Cdt", "(-)", _nonneg, "CdAx"),
)
_POINT_HEAD = (
    _c("ID", "(#)", _whole), _c("Attachment", "(-)", _point_kind, "kind"), _c("X", "(m)", _any),
    _c("Y", "(m)", _any), _c("Z", "(m)", _any), _c("Mass", "(kg)", _nonneg, "m"),
    _c("Volume", "(m^3)", _nonneg, "V"),
)
_POINT_FORCE = (_c("FX", "(N)", _any), _c("FY", "(N)", _any), _c("FZ", "(N)", _any))
_POINT_TAIL = (_c("CdA", "(m^2)", _nonneg), _c("Ca", "(-)", _nonneg))
POINT_COLUMNS = _POINT_HEAD + _POINT_TAIL
POINT_COLUMNS_F = _POINT_HEAD + _POINT_FORCE + _POINT_TAIL
ROD_TYPE_COLUMNS = (
    _c("TypeName", "(name)", _word, "name"), _c("Diam", "(m)", _pos, "d"), _c("Mass/m", "(kg/m)", _nonneg, "w"),
    _c("Cd", "(-)", _nonneg), _c("Ca", "(-)", _nonneg), _c("CdEnd", "(-)", _nonneg), _c("CaEnd", "(-)", _nonneg),
)
ROD_COLUMNS = (
    _c("ID", "(#)", _whole), _c("RodType", "(name)", _word, "rod_type"), _c("Attachment", "(#/key)", _rod_kind, "kind"),
    _c("Xa", "(m)", _any), _c("Ya", "(m)", _any), _c("Za", "(m)", _any), _c("Xb", "(m)", _any), _c("Yb", "(m)", _any),
    _c("Zb", "(m)", _any), _c("NumSegs", "(-)", _segs0, "N"), _c("RodOutputs", "(-)", _flags, "outputs"),
)
BODY_COLUMNS = (
    _c("ID", "(#)", _whole), _c("Attachment", "(-)", _body_kind, "kind"), _c("X0", "(m)", _any),
    _c("Y0", "(m)", _any), _c("Z0", "(m)", _any), _c("r0", "(deg)", _any), _c("p0", "(deg)", _any),
    _c("y0", "(deg)", _any), _c("Mass", "(kg)", _nonneg, "m"),
    _c("CG*", "(m)", _bars((1, 3), "one number (z of the CG) or x|y|z", nonneg=False), "rCG"),
    _c("I*", "(kg-m^2)", _bars((1, 3), "one number >= 0 or Ix|Iy|Iz"), "I"),
    _c("Volume", "(m^3)", _nonneg, "V"),
    _c("CdA*", "(m^2)", _bars((1, 2, 3, 6), "one number >= 0, trans|rot, x|y|z or six values"), "CdA"),
    _c("Ca*", "(-)", _bars((1, 3), "one number >= 0 or Cax|Cay|Caz"), "Ca"),
)
LINE_COLUMNS = (
    _c("ID", "(#)", _whole), _c("LineType", "(name)", _word, "line_type"),
    _c("AttachA", "(#)", attachment_of, "end_a"), _c("AttachB", "(#)", attachment_of, "end_b"),
    _c("UnstrLen", "(m)", _nonzero, "L"), _c("NumSegs", "(-)", _nsegs, "N"),
    _c("LineOutputs", "(-)", _flags, "outputs"),
)
LINE_COLUMNS_V1 = (
    _c("Line", "(#)", _whole, "ID"), _c("LineType", "(name)", _word, "line_type"),
    _c("UnstrLen", "(m)", _nonzero, "L"), _c("NumSegs", "(-)", _nsegs, "N"),
    _c("NodeAnch", "(#)", attachment_of, "end_a"), _c("NodeFair", "(#)", attachment_of, "end_b"),
    _c("Flags/Outputs", "(-)", _flags, "outputs"),
)


# ---------------------------------------------------------------------------------- options
def looks_like_file(tok) -> bool:
    return parse_number(tok) is None and bool(re.search(r"[A-DF-Za-df-z_/\\]", tok))


def _depth(tok, rd=None):
    if looks_like_file(tok):
        # a MoorDyn-F depth grid; read in _Reader.read_seabed, the depth becomes its mean
        return 0.0
    return _nonneg(tok)


def _choice(*words):
    def parse(tok, rd=None):
        if tok.lower() not in words:
            raise BadField(f"one of {', '.join(words)}")
        return tok.lower()

    return parse


#: (canonical key, aliases, target object, attribute, parser). Keys are compared case-insensitively.
OPTION_TABLE = (
    ("writeLog", (), "options", "writeLog", _whole),
    ("dtM", ("dt",), "options", "dtM", _pos),
    ("CFL", (), "options", "CFL", _pos),
    ("tScheme", (), "options", "tScheme", _word),
    # g 0 (weightless) and rho 0 (vacuum) are valid MoorDyn input (its own body tests use them)
    ("g", ("gravity",), "env", "g", _nonneg),
    ("rho", ("WtrDnsty", "rhoW"), "env", "rho", _nonneg),
    ("WtrDpth", ("depth", "WaterDepth"), "env", "depth", _depth),
    ("kBot", ("kb",), "env", "kBot", _nonneg),
    ("cBot", ("cb",), "env", "cBot", _nonneg),
    ("FrictionCoefficient", (), "env", "mu", _nonneg),
    ("FricDamp", (), "env", "fric_damp", _nonneg),
    ("StatDynFricScale", (), "env", "stat_dyn", _pos),
    ("mu_kT", (), "env", "mu_kT", _nonneg),
    ("mu_kA", (), "env", "mu_kA", _nonneg),
    ("mc", (), "env", "mc", _pos),
    ("cv", (), "env", "cv", _nonneg),
    ("FrictionModel", (), "env", "friction", _choice(*FRICTION_MODELS)),
    ("SeabedContact", (), "env", "contact", _choice(*CONTACT_MODES)),
    ("kShear", (), "env", "kShear", _pos),
    ("dtIC", ("ICdt",), "options", "dtIC", _pos),
    ("TmaxIC", ("ICTmax",), "options", "TmaxIC", _nonneg),
    ("CdScaleIC", ("ICDfac",), "options", "CdScaleIC", _pos),
    ("threshIC", ("ICthresh",), "options", "threshIC", _pos),
    ("ICgenDynamic", ("genDynamicIC",), "options", "ICgenDynamic", _flag01),
    ("ICNewton", (), "options", "ICNewton", _auto01),
    ("ClampMoment", (), "options", "ClampMoment", _flag01),
    ("InertialLoads", (), "options", "InertialLoads", _choice("full", "moordyn")),
    ("dtOut", (), "options", "dtOut", _nonneg),
    ("fileIC", ("ICfile",), "options", "fileIC", _state_file),
    ("SyropeWorkingCurve", (), "options", "SyropeWorkingCurve", _choice("segment", "line")),
    ("WriteUnits", (), "options", "WriteUnits", _flag01),
    ("disableOutput", (), "options", "disableOutput", _flag01),
)


def _equals(x):
    return lambda v, opts: parse_number(v) == x


def _always(v, opts):
    return True


def _never(v, opts):
    return False


#: Keys read but not acted on: canonical key -> (aliases, is_neutral(value, options)).
#: A neutral value changes nothing and is only logged at debug level; any other value is stored in
#: ``model.options.not_acted_on`` with one warning.
NOT_ACTED_ON = {
    "disableOutTime": ((), _always),
    "WaterKin": ((), _never),
    "inertialF": ((), _equals(0.0)),
    "inertialF_rampT": ((), _always),
    "OutSwitch": ((), _always),
}

#: keys handled by _Reader.read_seabed (file names)
SEABED_FILE_KEYS = ("SeafloorFile",)

OPTION_KEYS: dict[str, str] = {"seafloorfile": "SeafloorFile", "wavekin": "WaveKin", "currents": "Currents",
                                 "dtwave": "dtWave", "unifycurrentgrid": "UnifyCurrentGrid"}
for _key, _aliases, *_ in OPTION_TABLE:
    for _k in (_key, *_aliases):
        OPTION_KEYS[_k.lower()] = _key
for _key, (_aliases, _) in NOT_ACTED_ON.items():
    for _k in (_key, *_aliases):
        OPTION_KEYS[_k.lower()] = _key


