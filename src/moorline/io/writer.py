"""Write MoorDyn decks (:func:`write_deck`): v2 with every section :mod:`moorline.io.deck` reads,
or v1's layout for what v1 can express. Floats are written with ``repr``, so a deck read, written
and read again gives the same model."""

from __future__ import annotations

import logging
import math
import re
import shutil
from pathlib import Path

import numpy as np

from ..model import (
    ELASTIC,
    SYROPE,
    VISCO_CONSTANT,
    VISCO_MEAN,
    BodyKind,
    Curve,
    Environment,
    Model,
    Options,
    PointKind,
    RodKind,
    SyropeCurve,
)
from .columns import (
    BODY_COLUMNS,
    LINE_COLUMNS,
    LINE_COLUMNS_V1,
    LINE_TYPE_COLUMNS,
    LINE_TYPE_COLUMNS_V1,
    OPTION_TABLE,
    POINT_COLUMNS,
    POINT_COLUMNS_F,
    ROD_COLUMNS,
    ROD_TYPE_COLUMNS,
    Column,
)

log = logging.getLogger("moorline.io")


# ---------------------------------------------------------------------------------- writer
_KIND_WORD = {PointKind.FIXED: "Fixed", PointKind.COUPLED: "Coupled", PointKind.FREE: "Free"}
_KIND_WORD_V1 = {PointKind.FIXED: "Fixed", PointKind.COUPLED: "Vessel", PointKind.FREE: "Connect"}
_BODY_WORD = {BodyKind.FIXED: "Fixed", BodyKind.COUPLED: "Coupled", BodyKind.COUPLED_PINNED: "CoupledPinned",
              BodyKind.FREE: "Free"}
_ROD_WORD = {RodKind.FIXED: "Fixed", RodKind.PINNED: "Pinned", RodKind.COUPLED: "Coupled",
             RodKind.COUPLED_PINNED: "CoupledPinned", RodKind.FREE: "Free"}
_SAFE = re.compile(r"[^A-Za-z0-9_.-]")
#: options of moorline's own (MoorDyn warns about them) and the seabed friction keys v1 lacks
_MOORLINE_KEYS = ("FrictionModel", "SeabedContact", "kShear", "ICNewton", "SyropeWorkingCurve", "ClampMoment",
                  "InertialLoads")
_FRICTION_KEYS = ("FrictionCoefficient", "FricDamp", "StatDynFricScale", "mu_kT", "mu_kA", "mc", "cv")
#: water-kinematics option -> the files MoorDyn reads for each value (waterkin.FILES keys)
_WAVE_FILES = {2: ("frequencies", "grid"), 3: ("elevation", "grid"), 7: ("frequencies",)}
_CURRENT_FILES = {1: "profile", 2: "dynamic", 5: "grid4d"}


def _fmt(v) -> str:
    if isinstance(v, int | bool):
        return str(int(v))
    return repr(float(v))


def _bars(values) -> str:
    return "|".join(_fmt(v) for v in values)


def _table(title: str, columns, rows: list[list[str]]) -> list[str]:
    """A dashed header, titles, units and aligned rows."""
    body = [[c.name for c in columns], [c.unit for c in columns], *rows]
    n = max(len(r) for r in body)
    widths = [max(len(r[i]) for r in body if i < len(r)) for i in range(n)]
    out = [f"{'-' * 20} {title} {'-' * max(3, 50 - len(title))}"]
    for r in body:
        out.append("  ".join(s.ljust(w) for s, w in zip(r, widths, strict=False)).rstrip())
    return out


def _write_curve(c: Curve, path: Path, what: str, type_name: str):
    units = {"EA": ("strain (-)", "tension (N)"), "BA": ("strain rate (1/s)", "damping force (N)"),
             "EI": ("curvature (1/m)", "bending moment (N-m)"),
             "OWC": ("strain (-)", "tension (N)")}[what]
    head = [f"{what} curve of line type {type_name} (written by moorline)", f"{units[0]}  {units[1]}",
            "---"]
    rows = [f"{_fmt(x)} {_fmt(y)}" for x, y in zip(c.x, c.y, strict=True)]
    # no trailing newline: MoorDyn-C reads the empty record after it as a bad curve point
    path.write_text("\n".join(head + rows), encoding="utf-8")


def _check_token(text: str, what: str):
    if not text or any(ch.isspace() for ch in text) or "#" in text or "---" in text or "|" in text:
        raise ValueError(f"{what} {text!r} cannot be written to a deck (it must be one token without "
                         "spaces, '#', '|' or '---')")


class _Writer:
    """One deck being written: the model, the target, the version and the side files."""

    def __init__(self, model: Model, path: Path, version: str):
        self.m = model
        self.path = path
        self.v1 = version == "v1"
        self.files: list[Path] = []

    def side_file(self, name: str, what: str) -> tuple[Path, str]:
        fname = f"{self.path.stem}_{_SAFE.sub('_', name)}_{what}.txt"
        return self.path.parent / fname, fname

    def curve_cell(self, value, what, type_name) -> str:
        if not isinstance(value, Curve):
            return _fmt(value)
        target, fname = self.side_file(type_name, what)
        _write_curve(value, target, what, type_name)
        self.files.append(target)
        return fname

    # ----- v2 tables
    def line_types(self) -> list[str]:
        rows = []
        for name, lt in self.m.line_types.items():
            _check_token(name, "line type name")
            if lt.elastic == SYROPE:
                ea = f"SYROPE:{self.syrope_settings(name, lt.syrope)}|{_fmt(lt.EA_D)}|{_fmt(lt.EA_D_Lm)}"
            else:
                ea = self.curve_cell(lt.EA, "EA", name)
                if lt.elastic == VISCO_CONSTANT:
                    ea += f"|{_fmt(lt.EA_D)}"
                elif lt.elastic == VISCO_MEAN:
                    ea += f"|{_fmt(lt.EA_D)}|{_fmt(lt.EA_D_Lm)}"
            ba = self.curve_cell(lt.BA, "BA", name)
            if lt.elastic != ELASTIC:
                ba += f"|{_fmt(lt.BA_D)}"
            cells = [name, _fmt(lt.d), _fmt(lt.w), ea, ba, self.curve_cell(lt.EI, "EI", name),
                     _fmt(lt.Cd), _fmt(lt.Ca), _fmt(lt.CdAx), _fmt(lt.CaAx)]
            if (lt.Cl, lt.dF, lt.cF) != (0.0, 0.0, 0.0):
                cells.append(_fmt(lt.Cl))
                if (lt.dF, lt.cF) != (0.08, 0.18):
                    cells += [_fmt(lt.dF), _fmt(lt.cF)]
            rows.append(cells)
        return _table("LINE TYPES", LINE_TYPE_COLUMNS[:max((len(r) for r in rows), default=10)], rows)

    def syrope_settings(self, type_name: str, sy: SyropeCurve) -> str:
        owc_path, owc_name = self.side_file(type_name, "OWC")
        _write_curve(sy.owc, owc_path, "OWC", type_name)
        target, fname = self.side_file(type_name, "syrope")
        target.write_text(f"{owc_name}  OWC     original working curve file (line type {type_name})\n"
                          f"{sy.wc_type.upper()}  WCType  working curve shape\n"
                          f"{_fmt(sy.k1)}  k1\n{_fmt(sy.k2)}  k2\n", encoding="utf-8")
        self.files += [owc_path, target]
        return fname

    def rod_types(self) -> list[str]:
        rows = []
        for name, rt in self.m.rod_types.items():
            _check_token(name, "rod type name")
            rows.append([name, _fmt(rt.d), _fmt(rt.w), _fmt(rt.Cd), _fmt(rt.Ca), _fmt(rt.CdEnd), _fmt(rt.CaEnd)])
        return _table("ROD TYPES", ROD_TYPE_COLUMNS, rows)

    def bodies(self) -> list[str]:
        rows = []
        for k, b in enumerate(self.m.bodies, 1):
            cg = _fmt(b.rCG[2]) if b.rCG[0] == 0.0 and b.rCG[1] == 0.0 else _bars(b.rCG)
            inertia = _fmt(b.I[0]) if np.all(b.I == b.I[0]) else _bars(b.I)
            cda = b.CdA
            if np.all(cda == cda[0]):
                cda_txt = _fmt(cda[0])
            elif np.all(cda[:3] == cda[0]) and np.all(cda[3:] == cda[3]):
                cda_txt = _bars((cda[0], cda[3]))
            else:
                log.warning("%s: body %d CdA is written as six values, which MoorDyn-C 2.7 misreads (it leaves the "
                            "first at zero); moorline reads them as written", self.path, k)
                cda_txt = _bars(cda)
            ca = _fmt(b.Ca[0]) if np.all(b.Ca == b.Ca[0]) else _bars(b.Ca)
            rows.append([str(k), _BODY_WORD[b.kind], *map(_fmt, b.r), *map(_fmt, b.angles), _fmt(b.m), cg, inertia,
                         _fmt(b.V), cda_txt, ca])
        return _table("BODIES", BODY_COLUMNS, rows)

    def rods(self) -> list[str]:
        rows = []
        for k, r in enumerate(self.m.rods, 1):
            if r.kind == RodKind.BODY:
                word = f"Body{r.body + 1}"
            elif r.kind == RodKind.BODY_PINNED:
                word = f"Body{r.body + 1}Pinned"
            else:
                word = _ROD_WORD[r.kind]
            if r.outputs:
                _check_token(r.outputs, f"rod {k} output flags")
            rows.append([str(k), r.rod_type, word, *map(_fmt, r.rA), *map(_fmt, r.rB), str(int(r.N)),
                         r.outputs or "-"])
        return _table("RODS", ROD_COLUMNS, rows)

    def points(self) -> list[str]:
        v1 = self.v1
        with_force = v1 or any(p.F_ext.any() for p in self.m.points)
        rows = []
        for i, p in enumerate(self.m.points, 1):
            if p.kind == PointKind.BODY:
                if v1:
                    raise ValueError(f"point {i} is fixed to body {p.body + 1}: MoorDyn v1 has no bodies")
                word = f"Body{p.body + 1}"
            else:
                word = (_KIND_WORD_V1 if v1 else _KIND_WORD)[p.kind]
            cells = [str(i), word, *map(_fmt, p.r), _fmt(p.m), _fmt(p.V)]
            if with_force:
                cells += list(map(_fmt, p.F_ext))
            rows.append(cells + [_fmt(p.CdA), _fmt(p.Ca)])
        cols = POINT_COLUMNS_F if with_force else POINT_COLUMNS
        if v1:
            cols = (Column("Node", "(-)", None, ""), Column("Type", "(-)", None, ""), *cols[2:])
        return _table("NODE PROPERTIES" if v1 else "POINTS", cols, rows)

    def lines(self) -> list[str]:
        rows = []
        for k, ln in enumerate(self.m.lines, 1):
            ends = []
            for att in (ln.end_a, ln.end_b):
                if att.kind == "point":
                    ends.append(str(att.index + 1))
                elif self.v1:
                    raise ValueError(f"line {k} is attached to rod end {att}: MoorDyn v1 has no rods")
                else:
                    ends.append(f"R{att.index + 1}{att.end}")
            if ln.outputs:
                _check_token(ln.outputs, f"line {k} output flags")
            if self.v1:
                if ln.L < 0:
                    raise ValueError(f"line {k}: UnstrLen {ln.L:g} (a fraction of the end-to-end distance) is MoorDyn "
                                     "v2 input; v1 needs the length in metres")
                rows.append([str(k), ln.line_type, _fmt(ln.L), str(int(ln.N)), *ends, ln.outputs or "-"])
            else:
                rows.append([str(k), ln.line_type, *ends, _fmt(ln.L), str(int(ln.N)), ln.outputs or "-"])
        if self.v1:
            return _table("LINE PROPERTIES", LINE_COLUMNS_V1, rows)
        return _table("LINES", LINE_COLUMNS, rows)

    def failures(self) -> list[str]:
        """FAILURE rows ``FailureID Point Line(s) FailTime FailTen`` (0 for a trigger that is not set)."""
        rows = []
        for k, f in enumerate(self.m.failures, 1):
            att = f.attachment
            where = str(att.index + 1) if att.kind == "point" else f"R{att.index + 1}{att.end}"
            rows.append([str(k), where, ",".join(str(i + 1) for i in f.lines),
                         _fmt(f.time if math.isfinite(f.time) else 0.0),
                         _fmt(f.tension if math.isfinite(f.tension) else 0.0)])
        if not rows:
            return []
        cols = (Column("FailureID", "(#)", None, ""), Column("Point", "(#)", None, ""),
                Column("Line(s)", "(#)", None, ""), Column("FailTime", "(s)", None, ""),
                Column("FailTen", "(N)", None, ""))
        return _table("FAILURE", cols, rows)

    def syrope_ic(self) -> list[str]:
        rows = []
        for k, ln in enumerate(self.m.lines, 1):
            lt = self.m.line_types.get(ln.line_type)
            if lt is not None and lt.elastic == SYROPE and ln.syrope_ic is not None:
                rows.append([str(k), _fmt(ln.syrope_ic[0]), _fmt(ln.syrope_ic[1])])
        if not rows:
            return []
        cols = (Column("Line(s)", "(#)", None, ""), Column("Tmax0", "(N)", None, ""),
                Column("Tmean0", "(N)", None, ""))
        return _table("SYROPE IC", cols, rows)

    def options(self) -> list[str]:
        m = self.m
        opts = []
        defaults = {"env": Environment(), "options": Options()}
        for key, _aliases, target, attr, _parse in OPTION_TABLE:
            v = getattr(m.env if target == "env" else m.options, attr)
            if v is None:
                continue
            # keys MoorDyn does not know (it warns about each) are left out at their defaults
            if (key in _MOORLINE_KEYS or (self.v1 and key in _FRICTION_KEYS)) and \
                    v == getattr(defaults[target], attr):
                continue
            opts.append((v if isinstance(v, str) else _fmt(v), key))
        written = {k for _v, k in opts}
        if written & {"mu_kT", "mu_kA", "mc", "cv"} and "FrictionModel" not in written:
            # without FrictionModel those keys select the directional model when read back
            opts.append((m.env.friction, "FrictionModel"))
        opts += self.water_options()
        if m.env.bathymetry is not None:
            from .bathymetry import write_seafloor_grid

            grid = write_seafloor_grid(m.env.bathymetry, self.path.with_name(f"{self.path.stem}_seafloor.txt"))
            self.files.append(grid)
            opts.append((grid.name, "SeafloorFile"))
        for key, value in m.options.not_acted_on.items():
            _check_token(str(value), f"option {key} value")
            opts.append((str(value), key))
        width = max((len(v) for v, _ in opts), default=0)
        return [f"{'-' * 20} OPTIONS {'-' * 43}", *(f"{v.ljust(width)}  {k}" for v, k in opts)]

    def water_options(self) -> list[tuple[str, str]]:
        """WaveKin, Currents and dtWave, with the files they name copied beside the deck. Waves or a
        current that did not come from MoorDyn's files cannot be written."""
        from .waterkin import DT_WAVE, FILES

        m = self.m
        o, env = m.options, m.env
        wk, cur = int(o.WaveKin), int(o.Currents)
        if env.waves is not None and not _water_from(env.waves, wk, "waves"):
            raise ValueError("the model's waves were set in Python (not read from MoorDyn's WaveKin files); a MoorDyn "
                             "deck can only name wave files (WaveKin 2, 3, 7): write the sea to a system file instead")
        if env.current is not None and not _water_from(env.current, cur, "current"):
            raise ValueError("the model's current was set in Python (not read from MoorDyn's Currents files); a "
                             "MoorDyn deck can only name current files (Currents 1, 2, 5)")
        if not env.waves_on_lines:
            raise ValueError("waves that act on floating bodies only (waves_on_lines False) are a system-file setting "
                             "that a MoorDyn deck cannot express")
        keys = list(_WAVE_FILES.get(wk, ())) + ([_CURRENT_FILES[cur]] if cur in _CURRENT_FILES else [])
        if keys:
            src_dir = Path(m.source).resolve().parent if m.source is not None else None
            for key in dict.fromkeys(keys):
                name = FILES[key]
                dst = self.path.parent / name
                src = src_dir / name if src_dir is not None else None
                if src is None or not src.is_file():
                    raise ValueError(f"WaveKin {wk} / Currents {cur} need {name}, which is not beside the model's "
                                     f"source deck ({m.source})")
                if src.resolve() != dst.resolve():
                    if dst.exists() and dst.read_bytes() != src.read_bytes():
                        raise ValueError(f"{dst} exists with other content; MoorDyn reads {name} from the deck's "
                                         "folder, so write the deck to another folder")
                    shutil.copyfile(src, dst)
                self.files.append(dst)
        out = []
        if wk:
            out.append((str(wk), "WaveKin"))
        if cur:
            out.append((str(cur), "Currents"))
        if o.dtWave != DT_WAVE:
            out.append((_fmt(o.dtWave), "dtWave"))
        if (env.current is not None and env.waves is not None and env.waves.evaluation == "grid"
                and not env.current.on_wave_grid):
            out.append(("0", "UnifyCurrentGrid"))
        return out

    def options_v1(self) -> list[str]:
        """SOLVER OPTIONS: the v2 options under v1's header (MoorDyn v1 ignores the keys it does not
        know: they are numerical or output settings); physics v1 lacks is refused."""
        env = self.m.env
        for what, present in (("a seabed grid (SeafloorFile)", env.bathymetry is not None),
                              ("wave kinematics (WaveKin)", env.waves is not None or self.m.options.WaveKin),
                              ("a current (Currents)", env.current is not None or self.m.options.Currents),
                              ("seabed friction", env.mu > 0 or env.mu_kT > 0 or env.mu_kA > 0)):
            if present:
                raise ValueError(f"the model has {what}, which MoorDyn v1 cannot express; write a v2 deck")
        lines = self.options()
        lines[0] = f"{'-' * 20} SOLVER OPTIONS {'-' * 36}"
        return [ln.replace("  rho", "  rhoW") if ln.rstrip().endswith("  rho") else ln for ln in lines]

    def line_types_v1(self) -> list[str]:
        rows = []
        for name, lt in self.m.line_types.items():
            _check_token(name, "line type name")
            why = None
            if lt.elastic != ELASTIC:
                why = "a viscoelastic or Syrope axial model"
            elif isinstance(lt.EA, Curve) or isinstance(lt.BA, Curve):
                why = "an EA or BA curve"
            elif lt.has_bending:
                why = "bending stiffness (EI)"
            elif (lt.Cl, lt.dF, lt.cF) != (0.0, 0.0, 0.0):
                why = "VIV coefficients (Cl, dF, cF)"
            if why:
                raise ValueError(f"line type {name!r} has {why}, which MoorDyn v1 cannot express; write a v2 deck")
            rows.append([name, _fmt(lt.d), _fmt(lt.w), _fmt(lt.EA), _fmt(lt.BA), _fmt(lt.Ca), _fmt(lt.CaAx),
                         _fmt(lt.Cd), _fmt(lt.CdAx)])
        return _table("LINE DICTIONARY", LINE_TYPE_COLUMNS_V1, rows)

    def check_expressible(self):
        m = self.m
        if m.floating or m.hydro or m.joints:
            raise ValueError("floating bodies (potential-flow coefficients, joints) are moorline settings that a "
                             "MoorDyn deck cannot express: keep them in a system file (.yaml) that names the deck")
        if self.v1 and getattr(m, "failures", None):
            raise ValueError(f"the model has {len(m.failures)} line failures: MoorDyn v1 has no FAILURE section; "
                             "write a v2 deck")
        if self.v1 and (m.bodies or m.rods or m.rod_types):
            raise ValueError(f"the model has {len(m.bodies)} bodies and {len(m.rods)} rods: MoorDyn v1 has neither; "
                             "write a v2 deck")
        for name in m.outputs:
            _check_token(name, "output channel")

    def write(self) -> Path:
        self.check_expressible()
        m = self.m
        title = "MoorDyn v1 input file" if self.v1 else "MoorDyn v2 input file"
        out = ["-" * 20 + f" {title} " + "-" * 30,
               f"Written by moorline{f' from {Path(m.source).name}' if m.source else ''}"]
        if self.v1:
            out += self.line_types_v1() + self.points() + self.lines() + self.options_v1()
        else:
            if m.line_types:
                out += self.line_types()
            if m.rod_types:
                out += self.rod_types()
            if m.bodies:
                out += self.bodies()
            if m.rods:
                out += self.rods()
            if m.points:
                out += self.points()
            if m.lines:
                out += self.lines()
            out += self.syrope_ic() + self.failures() + self.options()
        out.append(f"{'-' * 20} OUTPUTS {'-' * 43}")
        out += list(m.outputs)
        if self.v1:
            out.append("END")
        out.append("-" * 20 + " need this final dashed line " + "-" * 24)
        self.path.write_text("\n".join(out) + "\n", encoding="utf-8")
        return self.path


def _water_from(obj, option: int, what: str) -> bool:
    """Whether ``obj`` (waves or current) is what the deck option ``option`` reads."""
    from .waterkin import FILES

    src = getattr(obj, "source", "") or ""
    if what == "waves":
        if option == 1:
            return getattr(obj, "evaluation", "") == "external"
        return option in _WAVE_FILES and src.startswith(f"WaveKin {option}")
    return option in _CURRENT_FILES and src.startswith(FILES[_CURRENT_FILES[option]])


def write_deck(model: Model, path, *, version: str = "v2") -> Path:
    """Write ``model`` as a MoorDyn deck that :func:`read_deck` reads back to an equal model.

    v2 (default) writes every section the reader reads, in MoorDyn's build order: LINE TYPES (with
    the viscoelastic ``EA_s|EA_d``, ``EA_s|EA_Dc|EA_D_Lm`` and ``SYROPE:<settings>|EA_Dc|EA_D_Lm``
    fields, ``BA_s|BA_d``, EI and the VIV columns Cl, dF, cF), ROD TYPES, BODIES, RODS, POINTS,
    LINES, SYROPE IC, OPTIONS (every option, the seabed grid as a ``SeafloorFile``, WaveKin,
    Currents and dtWave, and the options read but not acted on) and OUTPUTS. v1 writes MoorDyn v1's
    LINE DICTIONARY (9 columns), NODE PROPERTIES, LINE PROPERTIES (length before the end points),
    SOLVER OPTIONS and OUTPUTS (ending with END), and refuses a model that v1 cannot express
    (bodies, rods, bending, VIV, curves, viscoelastic ropes, a seabed grid, water kinematics, any
    option v1 lacks at a value other than its default) with a message saying what.

    Side files go beside the deck: EA/BA/EI curves as ``<deck stem>_<type>_<EA|BA|EI>.txt``, a
    Syrope type's settings and original working curve as ``<stem>_<type>_syrope.txt`` and
    ``<stem>_<type>_OWC.txt``, the seabed grid as ``<stem>_seafloor.txt``; the wave and current files
    (MoorDyn reads them under fixed names from the deck's folder) are copied from the model's source
    deck folder. Floats are written with ``repr`` so they read back exactly.

    Parameters
    ----------
    model : Model
    path : str or Path
        The deck file to write (overwritten).
    version : {'v2', 'v1'}

    Returns
    -------
    Path
        The path written.

    Raises
    ------
    ValueError
        If the model holds something the deck version cannot express (names with spaces, waves set
        in Python, floating bodies, or for v1 the v2 features above).
    """
    if version not in ("v1", "v2"):
        raise ValueError(f"version must be 'v1' or 'v2', got {version!r}")
    path = Path(path)
    return _Writer(model, path, version).write()
