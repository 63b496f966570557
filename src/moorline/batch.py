"""Parametric sweeps: a study file, local processes or a Dask cluster, resumable.

    moorline sweep study.yaml [--workers N] [--scheduler tcp://host:8786] [--out DIR]

or in Python::

    from moorline.batch import Study, run_sweep
    res = run_sweep(Study.from_yaml("study.yaml"))
    res.dataset           # one labelled Dataset, the parameters as dimensions/coordinates
    res.summary           # one row per case (pandas DataFrame), also written as summary.csv

A study file (YAML) names a base deck, the parameters to vary (a full-factorial grid, or an
explicit list of cases), the sea states or motion that drive the coupled points, the simulation
settings, and what to post-process (see ``docs/fatigue.md`` for every key). Each case reads the
deck, applies its parameters through the registry of named setters (:data:`PARAMETERS`), finds
the initial equilibrium once, then runs every sea state from that equilibrium and keeps its
post-processed results: damage rates along the line at points around the section, curvature,
tension and stress envelopes, compression. A finished case is written at once and atomically to
``<out>/cases/case_<key>.nc``, where the key is a hash of the case's parameters, the settings
and the contents of the deck, scatter and motion files; a sweep run again skips the cases whose
files are there, so an interrupted sweep resumes without recomputing them. The cases gather
into ``<out>/results.nc`` and ``<out>/summary.csv``.

Parameters act on the model through :func:`register_parameter` (current_speed and
current_heading make a uniform current); the sea-state parameters (Hs, Tz, wave_heading, gamma,
seed) act on the sea state, which drives the buoy motion (:mod:`moorline.post.seastate`) and,
with ``sea_states: {waves_on_lines: true}``, acts on the lines as waves in phase with it
(:func:`sea_waves`).
"""

from __future__ import annotations

import concurrent.futures as cf
import copy
import hashlib
import itertools
import json
import logging
import math
import multiprocessing
import os
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from . import __version__
from .post import (
    SECONDS_PER_YEAR,
    ScatterDiagram,
    SeaState,
    SNCurve,
    TubeSection,
    api_chain_tn_curve,
    buoy_motion,
    critical_location,
    cross_section_stress,
    dnv_chain_sn_curve,
    envelopes,
    fatigue_damage,
    life_years,
    section_loads,
    wave_components,
    wavenumber,
)

log = logging.getLogger("moorline")

__all__ = ["PARAMETERS", "CaseSpec", "Parameter", "Study", "StudyError", "SweepError", "SweepResult",
           "register_parameter", "run_case", "run_sweep", "sea_waves"]


class StudyError(ValueError):
    """A study file that cannot be run (unknown key or parameter, missing file, bad value)."""


class SweepError(RuntimeError):
    """Some cases of a sweep failed (the others are stored; running the sweep again retries them)."""


# ---------------------------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class Parameter:
    """A parameter a study can vary.

    ``kind`` is 'model' (``setter(model, value, target)`` changes the Model), 'sea_state' (the
    value goes to the :class:`~moorline.post.SeaState` field ``field``) or 'current' (``field``
    'speed' or 'heading' of a uniform current, set together once all parameters of a case are
    read, so their order does not matter).
    """

    name: str
    kind: str
    setter: Callable | None = None
    field: str | None = None
    units: str = ""
    doc: str = ""


#: name -> Parameter. A parameter may be written ``name[target]`` in a study; the target (a line
#: type name for line-type parameters, a line number for line parameters) is passed to the
#: setter, which applies the value to every line type / line when it is None.
PARAMETERS: dict[str, Parameter] = {}


def register_parameter(name: str, setter: Callable, *, units: str = "", doc: str = "") -> None:
    """Register (or replace) a model parameter.

    Parameters
    ----------
    name : str
        Name used in study files.
    setter : callable
        ``setter(model, value, target)``: change the :class:`~moorline.Model` in place; ``target``
        is the text in ``name[target]`` or None.
    units, doc : str
        For reports and error messages.
    """
    PARAMETERS[name] = Parameter(name, "model", setter, None, units, doc)


def _line_types(model, target):
    if target is None:
        return list(model.line_types.values())
    if target not in model.line_types:
        raise StudyError(f"no line type {target!r} in the deck (types: {sorted(model.line_types)})")
    return [model.line_types[target]]


def _lines(model, target):
    if target is None:
        return list(model.lines)
    try:
        k = int(target)
        return [model.lines[k - 1]] if 1 <= k <= len(model.lines) else []
    except ValueError:
        return []


def _line_type_setter(attr: str):
    def setter(model, value, target=None):
        for lt in _line_types(model, target):
            setattr(lt, attr, float(value))
    return setter


def _line_setter(attr: str, cast):
    def setter(model, value, target=None):
        lines = _lines(model, target)
        if not lines:
            raise StudyError(f"no line {target!r} in the deck ({len(model.lines)} lines)")
        for ln in lines:
            setattr(ln, attr, cast(value))
    return setter


def _set_dtM(model, value, target=None):
    model.options.dtM = float(value)


def _set_depth(model, value, target=None):
    model.env.depth = float(value)


for _name, _attr, _units, _doc in (("mass", "w", "kg/m", "mass per unit length in air"),
                                   ("EI", "EI", "N m^2", "bending stiffness"),
                                   ("EA", "EA", "N", "axial stiffness"),
                                   ("diameter", "d", "m", "volume-equivalent diameter"),
                                   ("Cd", "Cd", "-", "transverse drag coefficient"),
                                   ("Ca", "Ca", "-", "transverse added-mass coefficient"),
                                   ("CdAx", "CdAx", "-", "tangential drag coefficient"),
                                   ("CaAx", "CaAx", "-", "tangential added-mass coefficient")):
    register_parameter(_name, _line_type_setter(_attr), units=_units, doc=f"line type {_doc}")
register_parameter("length", _line_setter("L", float), units="m", doc="unstretched line length")
register_parameter("segments", _line_setter("N", int), units="-", doc="number of segments of a line")
register_parameter("dtM", _set_dtM, units="s", doc="internal time step")
register_parameter("depth", _set_depth, units="m", doc="water depth (flat seabed)")
for _name, _field, _units in (("Hs", "Hs", "m"), ("Tz", "Tz", "s"), ("wave_heading", "heading", "deg"),
                              ("gamma", "gamma", "-"), ("seed", "seed", "-")):
    PARAMETERS[_name] = Parameter(_name, "sea_state", None, _field, _units, f"sea state {_field}")
for _name, _field, _units in (("current_speed", "speed", "m/s"), ("current_heading", "heading", "deg")):
    PARAMETERS[_name] = Parameter(_name, "current", None, _field, _units, f"uniform current {_field} "
                                  "(heading: the direction the water flows toward, from +x toward +y)")


def _split_name(key: str) -> tuple[str, str | None]:
    """'mass[cable]' -> ('mass', 'cable')."""
    if key.endswith("]") and "[" in key:
        name, target = key[:-1].split("[", 1)
        return name.strip(), target.strip()
    return key.strip(), None


def _parameter(key: str) -> tuple[Parameter, str | None]:
    name, target = _split_name(key)
    p = PARAMETERS.get(name)
    if p is None:
        raise StudyError(f"unknown parameter {name!r}; known parameters: {', '.join(sorted(PARAMETERS))}")
    return p, target


# ---------------------------------------------------------------------------------------------- study
_TOP_KEYS = {"name", "deck", "line", "fixed", "parameters", "cases", "sea_states", "motion", "simulation", "post",
             "record", "output"}
_SEA_KEYS = {"scatter", "kind", "normalise", "min_probability", "Hs", "Tz", "heading", "gamma", "seed",
             "waves_on_lines"}
_MOTION_KEYS = {"csv", "interpolation"}
_SIM_DEFAULTS = {"dtM": None, "scheme": None, "solve_ic": True, "ramp_periods": 1.0, "settle_periods": 2.0,
                 "analyse_periods": 1, "samples_per_period": 60, "duration": None, "transient": None,
                 "dt_out": None}
_POST_DEFAULTS = {"section": None, "n_theta": 12, "tensile_only": False, "sn": None, "tn": None,
                  "allowable_bend_radius": None, "frame": "reference", "compression_strain": 0.0}
_RECORD_DEFAULTS = {"runs": False}


def _sha256_file(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _check_keys(d, allowed, where):
    if d is None:
        return {}
    if not isinstance(d, dict):
        raise StudyError(f"{where}: expected a mapping, got {type(d).__name__}")
    bad = sorted(set(d) - set(allowed))
    if bad:
        raise StudyError(f"{where}: unknown key(s) {', '.join(bad)}; allowed: {', '.join(sorted(allowed))}")
    return dict(d)


@dataclass(frozen=True)
class CaseSpec:
    """One case: its position in the study, parameter values, key and the resolved settings."""

    index: int
    params: dict
    key: str
    settings: dict

    @property
    def label(self) -> str:
        return ", ".join(f"{k}={v}" for k, v in self.params.items()) or "base"

    @property
    def filename(self) -> str:
        return f"case_{self.key[:16]}.nc"


@dataclass
class Study:
    """A parametric study (see the module docstring and ``docs/fatigue.md`` for the file format).

    Build it with :meth:`from_yaml` or :meth:`from_dict`; paths are resolved against the study
    file's folder. Parameters are checked against the registry and the deck when it is built.
    """

    name: str
    deck: Path
    line: int | None = None
    fixed: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    cases: list | None = None
    sea_states: dict | None = None
    motion: dict | None = None
    simulation: dict = field(default_factory=dict)
    post: dict = field(default_factory=dict)
    record: dict = field(default_factory=dict)
    output: Path | None = None
    source: Path | None = None

    @classmethod
    def from_yaml(cls, path) -> Study:
        """Read a study file."""
        import yaml

        path = Path(path)
        try:
            d = yaml.safe_load(path.read_text())
        except OSError as e:
            raise StudyError(f"cannot read study file {path}: {e.strerror}") from None
        except yaml.YAMLError as e:
            raise StudyError(f"{path}: not valid YAML: {e}") from None
        return cls.from_dict(d, base_dir=path.resolve().parent, source=path.resolve())

    @classmethod
    def from_dict(cls, d: dict, *, base_dir=".", source=None) -> Study:
        """Build a study from a mapping with the keys of a study file."""
        d = _check_keys(d, _TOP_KEYS, "study")
        base = Path(base_dir)
        if "deck" not in d:
            raise StudyError("study: 'deck' (the base MoorDyn deck) is required")
        deck = (base / d["deck"]).resolve()
        if not deck.exists():
            raise StudyError(f"study: deck {deck} not found")
        sea = _check_keys(d.get("sea_states"), _SEA_KEYS, "sea_states") or None
        if sea and sea.get("scatter"):
            sea["scatter"] = str((base / sea["scatter"]).resolve())
            if not Path(sea["scatter"]).exists():
                raise StudyError(f"sea_states: scatter file {sea['scatter']} not found")
        motion = _check_keys(d.get("motion"), _MOTION_KEYS, "motion") or None
        if motion and motion.get("csv"):
            motion["csv"] = str((base / motion["csv"]).resolve())
            if not Path(motion["csv"]).exists():
                raise StudyError(f"motion: csv file {motion['csv']} not found")
        sim = {**_SIM_DEFAULTS, **_check_keys(d.get("simulation"), _SIM_DEFAULTS, "simulation")}
        post = {**_POST_DEFAULTS, **_check_keys(d.get("post"), _POST_DEFAULTS, "post")}
        record = {**_RECORD_DEFAULTS, **_check_keys(d.get("record"), _RECORD_DEFAULTS, "record")}
        params = d.get("parameters") or {}
        if not isinstance(params, dict):
            raise StudyError("parameters: expected a mapping name -> list of values")
        params = {str(k): (list(v) if isinstance(v, (list, tuple)) else [v]) for k, v in params.items()}
        cases = d.get("cases")
        if cases is not None and params:
            raise StudyError("give either 'parameters' (a full-factorial grid) or 'cases' (a list), not both")
        if cases is not None and (not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases)):
            raise StudyError("cases: expected a list of mappings name -> value")
        fixed = d.get("fixed") or {}
        if not isinstance(fixed, dict):
            raise StudyError("fixed: expected a mapping name -> value (parameters set in every case)")
        out = d.get("output")
        st = cls(name=str(d.get("name") or deck.stem), deck=deck, line=d.get("line"), fixed=dict(fixed),
                 parameters=params,
                 cases=cases, sea_states=sea, motion=motion, simulation=sim, post=post, record=record,
                 output=(base / out).resolve() if out else None, source=source)
        st.validate()
        return st

    # ------------------------------------------------------------------ checks
    def parameter_names(self) -> list[str]:
        if self.cases is not None:
            names: list[str] = []
            for c in self.cases:
                names += [k for k in c if k not in names]
            return names
        return list(self.parameters)

    def validate(self) -> None:
        """Raise :class:`StudyError` naming the first problem: unknown parameters,
        parameters that clash with the sea-state source, a missing line, bad post settings."""
        from .io import read_deck

        names = self.parameter_names()
        both = sorted(set(names) & set(self.fixed))
        if both:
            raise StudyError(f"{', '.join(both)}: both fixed and varied")
        sea_params = []
        for key in names + list(self.fixed):
            p, target = _parameter(key)
            if p.kind == "sea_state":
                if target is not None:
                    raise StudyError(f"parameter {key!r}: sea-state parameters take no [target]")
                sea_params.append(p.name)
        if sea_params and self.sea_states and self.sea_states.get("scatter") and \
                {"Hs", "Tz"} & set(sea_params):
            raise StudyError("Hs and Tz come from the scatter diagram; do not also vary them as parameters")
        if self.motion and (self.sea_states or sea_params):
            raise StudyError("give either sea states (scatter, Hs/Tz) or a motion file, not both")
        if self.sea_states or sea_params:
            kind = (self.sea_states or {}).get("kind", "regular")
            if kind not in ("regular", "jonswap"):
                raise StudyError(f"sea_states: kind must be 'regular' or 'jonswap', got {kind!r}")
            has = set(sea_params) | set(self.sea_states or {})
            if not self.sea_states or not self.sea_states.get("scatter"):
                missing = [k for k in ("Hs", "Tz") if k not in has]
                if missing:
                    raise StudyError(f"sea_states: {' and '.join(missing)} needed (or a scatter diagram)")
        elif self.simulation["duration"] is None:
            raise StudyError("simulation: 'duration' [s] is needed when the motion is not a sea state")
        if self.sea_states and self.sea_states.get("scatter"):
            try:
                sc = ScatterDiagram.from_csv(self.sea_states["scatter"],
                                             normalise=bool(self.sea_states.get("normalise", True)))
            except ValueError as e:
                raise StudyError(f"sea_states: {e}") from None
            cut = (sc.P > 0) & (sc.P <= float(self.sea_states.get("min_probability", 0.0)))
            if np.any(cut):
                log.warning("sea_states: %d of %d scatter cells have probability <= %g and are skipped (%.3g of the "
                            "total)", int(cut.sum()), int((sc.P > 0).sum()), self.sea_states["min_probability"],
                            float(sc.P[cut].sum() / sc.P.sum()))
        model = read_deck(self.deck)
        if self.line is not None and not 1 <= int(self.line) <= len(model.lines):
            raise StudyError(f"line {self.line}: the deck has {len(model.lines)} lines")
        if self.line is None and len(model.lines) != 1:
            raise StudyError(f"the deck has {len(model.lines)} lines; say which to post-process with 'line:'")
        for spec in self.case_specs():
            _apply_parameters(copy.deepcopy(model), {**self.fixed, **spec.params})  # bad targets, values
        _curves(self.post)
        _section(self.post)
        if self.post["frame"] not in ("reference", "horizontal"):
            raise StudyError(f"post: frame must be 'reference' or 'horizontal', got {self.post['frame']!r}")

    # ------------------------------------------------------------------ cases
    def settings(self) -> dict:
        """Everything a case needs besides its parameters (JSON-ready, absolute paths)."""
        return {"deck": str(self.deck), "line": self.line, "fixed": self.fixed, "sea_states": self.sea_states,
                "motion": self.motion,
                "simulation": self.simulation, "post": self.post, "record": self.record,
                "output": str(self.output_dir())}

    def _fingerprint(self) -> dict:
        """What the results depend on besides the parameters: settings and file contents."""
        s = copy.deepcopy(self.settings())
        s.pop("output")
        s["deck"] = None  # files count by their contents (below), not by their names or places
        files = {"deck": _sha256_file(self.deck)}
        if self.sea_states and self.sea_states.get("scatter"):
            files["scatter"] = _sha256_file(self.sea_states["scatter"])
            s["sea_states"]["scatter"] = None
        if self.motion and self.motion.get("csv"):
            files["motion"] = _sha256_file(self.motion["csv"])
            s["motion"]["csv"] = None
        return {"settings": s, "files": files, "moorline": __version__}

    def case_specs(self) -> list[CaseSpec]:
        """The cases in order: the full-factorial grid of ``parameters`` (last parameter fastest),
        or the explicit ``cases``."""
        if self.cases is not None:
            combos = [dict(c) for c in self.cases]
        elif self.parameters:
            keys = list(self.parameters)
            combos = [dict(zip(keys, vals, strict=True)) for vals in itertools.product(*self.parameters.values())]
        else:
            combos = [{}]
        fp = self._fingerprint()
        settings = self.settings()
        specs = []
        for i, c in enumerate(combos):
            key = hashlib.sha256(json.dumps({"params": c, **fp}, sort_keys=True, default=str).encode()).hexdigest()
            specs.append(CaseSpec(i, c, key, settings))
        return specs

    def output_dir(self) -> Path:
        if self.output is not None:
            return self.output
        base = self.source.parent if self.source is not None else Path.cwd()
        return base / f"{self.name}_out"

    @property
    def is_grid(self) -> bool:
        return self.cases is None and bool(self.parameters)


# ---------------------------------------------------------------------------------------------- one case
def _apply_parameters(model, params: dict) -> dict:
    """Apply the model parameters in order, then the current; return the sea-state fields set."""
    sea, current = {}, {}
    for key, value in params.items():
        p, target = _parameter(key)
        if p.kind == "sea_state":
            sea[p.field] = value
        elif p.kind == "current":
            if target is not None:
                raise StudyError(f"parameter {key!r}: current parameters take no [target]")
            current[p.field] = value
        else:
            try:
                p.setter(model, value, target)
            except StudyError:
                raise
            except (TypeError, ValueError) as e:
                raise StudyError(f"parameter {key!r} = {value!r}: {e}") from None
    if current:
        _set_current(model, **current)
    return sea


def _set_current(model, speed=None, heading=None) -> None:
    """A uniform current of ``speed`` [m/s] toward ``heading`` [deg]; what is not given is kept
    from the deck's current (which must then be uniform)."""
    from .model.water import Current

    v = np.zeros(3)
    old = model.env.current
    if old is not None:
        vel = np.asarray(old.velocity, dtype=float)
        if vel.size != 3:
            raise StudyError("current_speed and current_heading make a uniform current; the deck's current "
                             "varies in space or time")
        v = vel.reshape(3)
    s = float(speed) if speed is not None else math.hypot(v[0], v[1])
    h = float(heading) if heading is not None else math.degrees(math.atan2(v[1], v[0]))
    try:
        model.env.current = Current.uniform(s, h, vertical=v[2])
    except ValueError as e:
        raise StudyError(f"current: {e}") from None


def _curves(post: dict) -> tuple[SNCurve | None, SNCurve | None]:
    """The S-N curve of the section stress and the T-N curve of the segment tension."""
    sn = tn = None
    if post.get("sn"):
        d = _check_keys(post["sn"], {"alpha", "m", "m2", "knee", "knee_cycles", "endurance", "unit", "name"}, "post.sn")
        try:
            if d.get("m2") is not None:
                sn = SNCurve.two_slope(d["alpha"], d["m"], d["m2"], knee=d.get("knee"),
                                       knee_cycles=d.get("knee_cycles"), endurance=d.get("endurance"),
                                       unit=float(d.get("unit", 1.0)), name=str(d.get("name", "")))
            else:
                sn = SNCurve.one_slope(d["alpha"], d["m"], endurance=d.get("endurance"),
                                       unit=float(d.get("unit", 1.0)), name=str(d.get("name", "")))
        except KeyError as e:
            raise StudyError(f"post.sn: {e.args[0]!r} is required") from None
        except ValueError as e:
            raise StudyError(f"post.sn: {e}") from None
        if not post.get("section"):
            raise StudyError("post.sn needs post.section (do, di) to turn section loads into stress")
    if post.get("tn"):
        d = _check_keys(post["tn"], {"curve", "kind", "mbs", "d", "alpha", "m", "unit"}, "post.tn")
        curve = d.get("curve", "api")
        try:
            if curve == "api":
                tn = api_chain_tn_curve(d.get("kind", "studless"), float(d["mbs"]))
            elif curve == "dnv":
                tn = dnv_chain_sn_curve(d.get("kind", "studless"), float(d["d"]))
            elif curve == "custom":
                tn = SNCurve.one_slope(d["alpha"], d["m"], unit=float(d.get("unit", 1.0)), name="T-N")
            else:
                raise StudyError(f"post.tn: curve must be 'api', 'dnv' or 'custom', got {curve!r}")
        except KeyError as e:
            raise StudyError(f"post.tn: {e.args[0]!r} is required for curve {curve!r}") from None
        except ValueError as e:
            raise StudyError(f"post.tn: {e}") from None
    return sn, tn


def _section(post: dict) -> TubeSection | None:
    if not post.get("section"):
        return None
    d = _check_keys(post["section"], {"do", "di"}, "post.section")
    try:
        return TubeSection(float(d["do"]), float(d.get("di", 0.0)))
    except KeyError:
        raise StudyError("post.section: 'do' (outer diameter [m]) is required") from None
    except ValueError as e:
        raise StudyError(f"post.section: {e}") from None


def _sea_states(settings: dict, sea_fields: dict) -> list[SeaState] | None:
    ss = settings["sea_states"] or {}
    if not ss and not sea_fields:
        return None
    kw = {k: ss[k] for k in ("heading", "gamma", "seed") if k in ss}
    kw.update({k: v for k, v in sea_fields.items() if k in ("heading", "gamma", "seed")})
    kind = ss.get("kind", "regular")
    if ss.get("scatter"):
        sc = ScatterDiagram.from_csv(ss["scatter"], normalise=bool(ss.get("normalise", True)))
        return sc.sea_states(kind=kind, min_probability=float(ss.get("min_probability", 0.0)), **kw)
    Hs = sea_fields.get("Hs", ss.get("Hs"))
    Tz = sea_fields.get("Tz", ss.get("Tz"))
    return [SeaState(float(Hs), float(Tz), kind=kind, **kw)]


def _windows(sea: SeaState | None, sim: dict) -> dict:
    """Ramp, transient, analysed duration and output interval of one run [s]."""
    if sea is None:
        dt_out = sim["dt_out"] or 0.1
        return {"ramp": 0.0, "transient": float(sim["transient"] or 0.0), "duration": float(sim["duration"]),
                "dt_out": float(dt_out), "periodic": False}
    spp = int(sim["samples_per_period"])
    if sea.kind == "regular":
        T = sea.T
        return {"ramp": sim["ramp_periods"] * T, "transient": (sim["ramp_periods"] + sim["settle_periods"]) * T,
                "duration": int(sim["analyse_periods"]) * T, "dt_out": T / spp, "periodic": True}
    Tp = sea.Tp
    ramp = sim["ramp_periods"] * Tp
    transient = sim["transient"] if sim["transient"] is not None else (sim["ramp_periods"] + sim["settle_periods"]) * Tp
    return {"ramp": ramp, "transient": float(max(transient, ramp)), "duration": float(sim["duration"] or 600.0),
            "dt_out": float(sim["dt_out"] or sea.Tz / spp), "periodic": False}


def _post_one(ds: xr.Dataset, model, line: int, post: dict, sn, tn, section, periodic: bool, duration: float):
    """Damage rates and envelopes of one run."""
    an = ds.isel(time=slice(0, -1)) if periodic else ds
    sec = section_loads(an, line, model=model, frame=post["frame"])
    st = cross_section_stress(sec, section, n_theta=int(post["n_theta"]),
                              tensile_only=bool(post["tensile_only"])) if section is not None else None
    out = {}
    if sn is not None:
        out["damage_rate"] = fatigue_damage(st, sn, periodic=periodic) / duration
    if tn is not None:
        seg = np.flatnonzero(an.segment_line.values == line)
        out["tn_damage_rate"] = fatigue_damage(an.segment_tension.isel(segment=seg), tn, periodic=periodic) / duration
    env = envelopes(an, line, sections=sec, stress=st, allowable_bend_radius=post["allowable_bend_radius"],
                    compression_strain=float(post["compression_strain"]), warn=False)
    for k in env.data_vars:
        out[k] = env[k]
    return out


def run_case(spec: CaseSpec) -> xr.Dataset:
    """Run one case: build the model, find its equilibrium, run every sea state, post-process.

    Returns
    -------
    xarray.Dataset
        Dimensions ``sea_state``, ``node``, ``theta``, ``segment`` (of the post-processed line);
        see ``docs/fatigue.md`` for the variables.
    """
    from .coupling import System
    from .errors import SimulationError
    from .io import read_deck
    from .motion import Trajectory
    from .results import write_netcdf
    from .simulate import simulate

    wall0 = time.perf_counter()
    st = spec.settings
    sim, post = st["simulation"], st["post"]
    model = read_deck(Path(st["deck"]))
    sea_fields = _apply_parameters(model, {**st["fixed"], **spec.params})
    line = int(st["line"] or 1)
    sn, tn = _curves(post)
    section = _section(post)
    seas = _sea_states(st, sea_fields)
    kw = {k: sim[k] for k in ("dtM", "scheme") if sim[k] is not None}
    waves_on_lines = bool((st["sea_states"] or {}).get("waves_on_lines", False)) and seas is not None
    if waves_on_lines:
        model.env.waves = None  # the sea states bring their own
    elif seas is not None and model.env.waves is not None:
        log.warning("the deck's waves act on the lines while the buoy follows the study's sea states")
    base = System(model, **kw)
    x0 = base.deck_coupled_positions()
    zero = np.zeros_like(x0)
    labels = base.coupled_dof_labels
    base.init(x0, zero, solve_ic=bool(sim["solve_ic"]))
    ic = dict(base.ic_report)
    y_ic = base.y.copy()  # the equilibrium: every sea state starts from it
    runs_dir = Path(st["output"]) / "runs" / spec.key[:16] if st["record"]["runs"] else None

    entries = seas if seas is not None else [None]
    results, failed, notes = [], [], []
    for k, sea in enumerate(entries):
        w = _windows(sea, sim)
        t_total = w["transient"] + w["duration"]
        system = base
        if sea is not None:
            motion = Trajectory.from_samples(*buoy_motion(sea, x0, duration=t_total + w["dt_out"],
                                                          dt=0.5 * w["dt_out"], depth=model.env.depth,
                                                          ramp=w["ramp"], g=model.env.g, labels=labels))
            if waves_on_lines:
                model.env.waves = sea_waves(sea, x0, labels, depth=model.env.depth, g=model.env.g, ramp=w["ramp"],
                                            duration=t_total + w["dt_out"])
                system = System(model, **kw)
        elif st["motion"] and st["motion"].get("csv"):
            motion = Trajectory.from_csv(st["motion"]["csv"], n_dof=system.n_coupled_dof,
                                         interpolation=st["motion"].get("interpolation", "cubic"))
        else:
            motion = None
        system.init(x0, zero, solve_ic=False)  # time 0, the motion at rest
        if system.y.shape != y_ic.shape:
            raise RuntimeError("the state vector changed size with the sea state")
        system.y[:] = y_ic
        system.set_state()  # re-evaluates the loads, clears the scheme history, relaxes friction springs
        try:
            if w["transient"] > 0:
                simulate(system, w["transient"], motion, dt_out=w["transient"], progress=False)
            ds = simulate(system, w["duration"], motion, dt_out=w["dt_out"], progress=False)
        except SimulationError as e:
            what = f"sea state Hs = {sea.Hs} m, Tz = {sea.Tz} s" if sea is not None else "the run"
            log.warning("case %s: %s failed: %s", spec.label, what, e)
            failed.append(1)
            notes.append(f"{what}: {e}")
            results.append(None)
            continue
        if w["periodic"]:
            dt = np.diff(ds.time.values)
            if not np.allclose(dt, w["dt_out"], rtol=1e-6, atol=1e-9):
                raise RuntimeError(f"the analysis window of case {spec.label} is not sampled uniformly")
        if runs_dir is not None:
            write_netcdf(ds, runs_dir / f"sea_state_{k:03d}.nc")
        results.append(_post_one(ds, model, line, post, sn, tn, section, w["periodic"], w["duration"]))
        failed.append(0)

    out = _assemble(results, entries, failed)
    _summarise(out, post)
    out.attrs.update(case_key=spec.key, case_index=spec.index, parameters=json.dumps(spec.params),
                     ic=json.dumps(ic, default=str), failures=json.dumps(notes),
                     wall_time_s=time.perf_counter() - wall0, moorline_version=__version__, line=line)
    return out


def sea_waves(sea: SeaState, x0, labels, *, depth: float, g: float, ramp: float, duration: float):
    """The waves of a sea state acting on the lines, in phase with :func:`~moorline.post.buoy_motion`:
    the components of :func:`~moorline.post.wave_components` with their phases moved from the
    buoy to the origin (arg A_j = phi_j + k_j (x_b cos(beta) + y_b sin(beta)), x_b, y_b the first
    coupled object's horizontal position), so the elevation at the buoy is the buoy's heave; the
    same ramp.

    Returns
    -------
    moorline.model.water.Waves
    """
    from .model.water import Waves

    a, w, phi = wave_components(sea, duration)
    x0 = np.asarray(x0, dtype=float)
    pos = {lab[-2:]: x0[i] for i, lab in reversed(list(enumerate(labels)))}  # the first object's
    b = math.radians(sea.heading)
    lb = pos.get("_x", 0.0) * math.cos(b) + pos.get("_y", 0.0) * math.sin(b)
    A = a * np.exp(1j * (phi + wavenumber(w, depth, g) * lb))
    return Waves.from_components(w, A, sea.heading, ramp_time=ramp,
                                 source=f"{sea.kind} sea Hs={sea.Hs:g} m Tz={sea.Tz:g} s (moorline.batch)")


def _assemble(results: list, entries: list, failed: list) -> xr.Dataset:
    """Stack the per-run results along ``sea_state`` (NaN for failed runs)."""
    ok = [r for r in results if r is not None]
    if not ok:
        raise SweepError("every run of the case failed")
    names = list(ok[0])
    stacked = {}
    for name in names:
        tmpl = ok[0][name]
        arrs = [(r[name] if r is not None else xr.full_like(tmpl, np.nan, dtype=float)) for r in results]
        da = xr.concat([a.drop_vars([c for c in a.coords if c not in a.dims and c not in ("node_s", "segment_s")],
                                    errors="ignore") for a in arrs], dim="sea_state", coords="minimal",
                       compat="override", join="override")
        stacked[name] = da.assign_attrs(tmpl.attrs)
    ds = xr.Dataset(stacked)
    n = len(entries)
    sea_coords = {"sea_state": np.arange(n), "failed": ("sea_state", np.asarray(failed, dtype=np.int8))}
    if entries[0] is not None:
        sea_coords.update(
            Hs=("sea_state", [s.Hs for s in entries], {"units": "m"}),
            Tz=("sea_state", [s.Tz for s in entries], {"units": "s"}),
            H=("sea_state", [s.H if s.kind == "regular" else np.nan for s in entries], {"units": "m"}),
            T=("sea_state", [s.T if s.kind == "regular" else np.nan for s in entries], {"units": "s"}),
            probability=("sea_state", [s.probability for s in entries]))
    else:
        sea_coords["probability"] = ("sea_state", [1.0])
    ds = ds.assign_coords(sea_coords)
    for dim in ("node", "segment"):
        if dim in ds.dims:
            ds = ds.assign_coords({dim: np.arange(ds.sizes[dim])})
    return ds


def _summarise(ds: xr.Dataset, post: dict) -> None:
    """Add the lifetime results of a case as 0-d variables (in place)."""
    p = ds.probability
    ok = ds.failed == 0
    ds["failed_probability"] = p.where(~ok, 0.0).sum()
    if "damage_rate" in ds:
        dy = (ds.damage_rate * p).sum("sea_state", skipna=True) * SECONDS_PER_YEAR
        ds["damage_per_year"] = dy.assign_attrs(units="1/year", long_name="probability-weighted damage per year")
        crit = critical_location(dy)
        ds["damage_per_year_max"] = crit["damage"]
        ds["life_years"] = life_years(crit["damage"])
        ds["critical_s"] = crit["s"]
        ds["critical_node"] = crit["node"]
        ds["critical_theta"] = crit["theta"]
        at = ds.damage_rate.isel(node=crit["node"]).sel(theta=crit["theta"])
        ds["damage_per_year_by_sea_state"] = (at * p * SECONDS_PER_YEAR).assign_attrs(
            units="1/year", long_name="contribution of each sea state to the damage at the critical location")
        ds["damage_per_year_max"].attrs.update(units="1/year")
        ds["life_years"].attrs.update(units="year")
        ds["critical_s"].attrs.update(units="m", long_name="arc length of the critical location from end A")
        ds["critical_theta"].attrs.update(units="deg")
    if "tn_damage_rate" in ds:
        ty = (ds.tn_damage_rate * p).sum("sea_state", skipna=True) * SECONDS_PER_YEAR
        ds["tn_damage_per_year"] = ty.assign_attrs(units="1/year")
        ds["tn_life_years"] = life_years(float(ty.max()))
    kmax = ds.curvature_max.max("sea_state")
    i = int(np.argmax(kmax.values))
    ds["curvature_max_all"] = float(kmax[i])
    ds["curvature_max_s"] = float(ds.node_s.values[i]) if "node_s" in ds.coords else np.nan
    ds["bend_radius_min_all"] = 1.0 / float(kmax[i]) if kmax[i] > 0 else np.inf
    ds["tension_max_all"] = float(ds.tension_max.max())
    ds["tension_min_all"] = float(ds.tension_min.min())
    if "compressed_fraction" in ds:
        comp = (ds.compressed_fraction > 0).any("segment")
        ds["compression_probability"] = float(p.where(comp, 0.0).sum())
    if post.get("allowable_bend_radius"):
        ds["bend_radius_ok"] = int(ds["bend_radius_min_all"] >= post["allowable_bend_radius"])


# ---------------------------------------------------------------------------------------------- sweep
@dataclass
class SweepResult:
    """What :func:`run_sweep` returns."""

    dataset: xr.Dataset
    summary: object  # pandas.DataFrame
    out_dir: Path
    wall_time: float
    computed: int
    reused: int


_SUMMARY_VARS = ("life_years", "damage_per_year_max", "critical_s", "critical_theta", "curvature_max_all",
                 "curvature_max_s", "bend_radius_min_all", "bend_radius_ok", "tension_max_all", "tension_min_all",
                 "compression_probability", "tn_life_years", "failed_probability")


def _load_case(path: Path, key: str) -> xr.Dataset | None:
    try:
        ds = xr.load_dataset(path, engine="h5netcdf")
    except Exception as e:  # a damaged file is recomputed
        log.warning("cannot read %s (%s); the case is run again", path, e)
        return None
    return ds if ds.attrs.get("case_key") == key else None


def _write_text_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def gather(study: Study, datasets: list[xr.Dataset], specs: list[CaseSpec]) -> tuple[xr.Dataset, object]:
    """Combine case Datasets into one (parameters as dimensions for a grid, else a ``case``
    dimension with the parameters as coordinates) and a summary table (pandas DataFrame)."""
    import pandas as pd

    names = study.parameter_names()
    rows = []
    prepared = []
    for ds, spec in zip(datasets, specs, strict=True):
        vals = {n: spec.params.get(n, np.nan) for n in names}
        row = {"case": spec.index, **vals}
        for v in _SUMMARY_VARS:
            if v in ds:
                row[v] = float(ds[v])
        row["wall_time_s"] = float(ds.attrs.get("wall_time_s", np.nan))
        rows.append(row)
        d = ds.drop_vars([n for n in names if n in ds.variables], errors="ignore")  # e.g. Hs as a parameter
        d = d.expand_dims(case=[spec.index]).assign_coords({n: ("case", [v]) for n, v in vals.items()})
        prepared.append(d)
    combined = xr.concat(prepared, dim="case", coords="different", compat="equals", join="outer",
                         combine_attrs="drop")
    if study.is_grid and len(names) == 1:
        combined = combined.swap_dims(case=names[0]).drop_vars("case")
    elif study.is_grid:
        combined = combined.set_index(case=names).unstack("case").transpose(*names, ...)
    combined.attrs.update(study=study.name, deck=str(study.deck), moorline_version=__version__,
                          parameters=json.dumps(names), settings=json.dumps(study.settings(), default=str))
    return combined, pd.DataFrame(rows)


def run_sweep(study: Study | str | os.PathLike, *, out=None, workers: int | None = None, scheduler=None,
              resume: bool = True, progress: bool | None = None) -> SweepResult:
    """Run every case of a study and gather the results.

    Parameters
    ----------
    study : Study or path
        The study (or its YAML file).
    out : path, optional
        Output folder (default: the study's ``output`` or ``<name>_out`` next to the study file).
    workers : int, optional
        Local worker processes (default: the number of CPUs; 1 runs the cases in this process).
    scheduler : str or distributed.Client, optional
        Address of a Dask scheduler (or a Client): run the cases on that cluster instead.
    resume : bool
        Reuse the stored results of cases already finished (default); False recomputes all.
    progress : bool, optional
        Progress bar over the cases (default: when the output is a terminal).

    Returns
    -------
    SweepResult

    Raises
    ------
    StudyError
        A study that cannot run (checked before any case starts).
    SweepError
        When some cases failed; the finished ones are stored.
    """
    from .results import write_netcdf

    if not isinstance(study, Study):
        study = Study.from_yaml(study)
    if out is not None:
        study.output = Path(out).resolve()
    out_dir = study.output_dir()
    cases_dir = out_dir / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    for stale in cases_dir.glob("*.part"):  # left by a killed run
        stale.unlink(missing_ok=True)
    specs = study.case_specs()
    wall0 = time.perf_counter()
    done: dict[int, xr.Dataset] = {}
    if resume:
        for s in specs:
            p = cases_dir / s.filename
            if p.exists():
                ds = _load_case(p, s.key)
                if ds is not None:
                    done[s.index] = ds
    pending = [s for s in specs if s.index not in done]
    reused = len(done)
    if reused:
        log.info("%s: %d of %d cases already done in %s", study.name, reused, len(specs), cases_dir)
    failures: list[str] = []

    def finished(spec: CaseSpec, ds: xr.Dataset) -> None:
        write_netcdf(ds, cases_dir / spec.filename)
        done[spec.index] = ds
        life = float(ds["life_years"]) if "life_years" in ds else math.nan
        log.info("case %d/%d (%s): life %.4g years, %.3g s", spec.index + 1, len(specs), spec.label, life,
                 ds.attrs.get("wall_time_s", math.nan))

    def failed(spec: CaseSpec, e: BaseException) -> None:
        log.error("case %d (%s) failed: %s: %s", spec.index + 1, spec.label, type(e).__name__, e)
        failures.append(f"case {spec.index + 1} ({spec.label}): {type(e).__name__}: {e}")

    bar = tqdm(total=len(specs), initial=reused, desc=study.name, unit="case",
               disable=(not progress) if progress is not None else None)
    try:
        if not pending:
            pass
        elif scheduler is not None:
            _run_dask(pending, scheduler, finished, failed, bar)
        else:
            n = workers if workers is not None else (os.cpu_count() or 1)
            if n <= 1 or len(pending) == 1:
                for s in pending:
                    try:
                        ds = run_case(s)
                    except Exception as e:  # reported per case; the others go on
                        failed(s, e)
                    else:
                        finished(s, ds)
                    bar.update(1)
            else:
                _run_local(pending, n, finished, failed, bar)
    finally:
        bar.close()
    if failures:
        raise SweepError(f"{len(failures)} of {len(specs)} cases failed (the other results are stored in "
                         f"{cases_dir}; run the sweep again to retry):\n  " + "\n  ".join(failures))
    ordered = [done[s.index] for s in specs]
    dataset, summary = gather(study, ordered, specs)
    wall = time.perf_counter() - wall0
    dataset.attrs.update(sweep_wall_time_s=wall, cases_computed=len(pending), cases_reused=reused)
    write_netcdf(dataset, out_dir / "results.nc")
    _write_text_atomic(out_dir / "summary.csv", summary.to_csv(index=False))
    log.info("%s: %d cases (%d computed, %d reused) in %.1f s; results in %s", study.name, len(specs), len(pending),
             reused, wall, out_dir)
    return SweepResult(dataset, summary, out_dir, wall, len(pending), reused)


def _run_local(pending, n, finished, failed, bar) -> None:
    ctx = multiprocessing.get_context("spawn")  # no fork of a process with threads (tqdm, numba)
    pool = cf.ProcessPoolExecutor(max_workers=min(n, len(pending)), mp_context=ctx)
    try:
        futs = {pool.submit(run_case, s): s for s in pending}
        _gather(futs, cf.as_completed(futs), finished, failed, bar)
    except BaseException:  # interrupted: drop the queued cases, do not wait for the running ones
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()


def _gather(futs, done, finished, failed, bar) -> None:
    """Hand every finished future (local or Dask) to ``finished`` or ``failed`` as it completes."""
    for f in done:
        s = futs[f]
        try:
            ds = f.result()
        except Exception as e:  # reported per case; the others go on
            failed(s, e)
        else:
            finished(s, ds)
        bar.update(1)


def _run_dask(pending, scheduler, finished, failed, bar) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise StudyError("a Dask scheduler was given but dask.distributed is not installed "
                         "(pip install 'moorline[cluster]')") from None
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = {client.submit(run_case, s, pure=False): s for s in pending}
        _gather(futs, as_completed(list(futs)), finished, failed, bar)
    finally:
        if own:
            client.close()
