"""The study file: its schema (the keys a study file may hold and their defaults), validation,
and the cases it expands to (:class:`Study`, :class:`CaseSpec`)."""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import __version__
from ..errors import StudyError
from ..io import read_deck
from ..post import (
    ScatterDiagram,
    SNCurve,
    TubeSection,
    api_chain_tn_curve,
    dnv_chain_sn_curve,
)
from .parameters import _apply_parameters, _parameter

log = logging.getLogger("moorline")


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
