"""The system file: a small YAML file that points at a MoorDyn deck and adds what MoorDyn has no
words for (DESIGN.md, "The system file"): which deck bodies float and their mass properties, their
hydrodynamic coefficients (a WAMIT run, a Capytaine NetCDF file, or hulls to compute), extra damping,
stiffness and loads, drag-only Morison strips, joints with power take-offs, the sea and the run
settings. One loader turns it into the same model objects the deck builder makes.

Example (``examples/point_absorber/system.yaml``)::

    deck: mooring.dat                 # the lines, points, rods and bodies (MoorDyn v2)
    bodies:
      - body: 1                       # deck body number; becomes a free floating body
        mass: 727010.0                # [kg]; 'displaced' = rho V of the coefficients
        cog: [0, 0, -0.72]            # [m] body axes, from the reference point
        inertia: [2.09e7, 2.13e7, 3.71e7]   # [kg m^2] about the CG (principal)
        quadratic_damping: [0, 0, 5e4, 0, 0, 0]
    hydrodynamics:
      - bodies: [1, 2]
        wamit: ../data/rm3            # or capytaine: coeffs.nc, or capytaine_run: {...}
    joints:
      - {child: 1, parent: 2, axis: [0, 0, 1], pto: {damping: 1.2e6}}
    sea:
      waves: {kind: jonswap, Hs: 2.5, Tp: 8.0, heading: 0, seed: 1}
    run: {duration: 600, dt_out: 0.2, scheme: GenAlpha, dtM: 0.05}

Every key is checked (unknown keys, wrong types, missing files); errors are
:class:`~moorline.errors.DeckError` naming the file and the key path, e.g.
``system.yaml: bodies[0].inertia: expected 3 numbers [kg m^2], got 'big'``.
Relative paths are taken from the system file's folder.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import DeckError
from ..model import BemRun, BodyKind, Hull, Model, ModelError, MorisonStrip
from ..model.water import Current, Waves

#: The schema, in one table: section -> {key: (kind, what is expected)}. Kinds: 'number', 'vector<n>',
#: 'matrix6' (6 numbers or 6x6), 'path', 'str', 'bool', 'int', 'list', 'map'.
SCHEMA = {
    "": {"deck": ("path", "the MoorDyn deck (lines, points, rods, bodies)"),
         "bodies": ("list", "floating bodies"), "hydrodynamics": ("list", "coefficient sets"),
         "joints": ("list", "prismatic joints"), "sea": ("map", "waves and current"),
         "run": ("map", "run settings")},
    "bodies": {"body": ("int", "deck body number (1-based)"),
               "mass": ("number|str", "[kg], or 'displaced' (rho V of the coefficients)"),
               "cog": ("vector3", "[m] body axes, from the reference point"),
               "inertia": ("vector3", "[kg m^2] principal moments about the CG"),
               "drag_area": ("vector6", "CdA per DOF [m^2, m^5] (MoorDyn's body drag, body axes)"),
               "linear_damping": ("matrix6", "[N s/m, N m s/rad]"),
               "quadratic_damping": ("matrix6", "[N s^2/m^2, ...]"),
               "stiffness": ("matrix6", "[N/m, N m/rad]"), "force": ("vector6", "[N, N m]"),
               "morison": ("list", "drag-only strips {rA, rB, d, Cd, n}")},
    "morison": {"rA": ("vector3", "[m] body axes"), "rB": ("vector3", "[m] body axes"), "d": ("number", "[m]"),
                "Cd": ("number", "[-]"), "n": ("int", "sub-strips")},
    "hydrodynamics": {"bodies": ("list", "deck body numbers in the order of the coefficient set"),
                      "wamit": ("path", "WAMIT output stem (without .1/.3/.hst)"),
                      "capytaine": ("path", "Capytaine NetCDF file"),
                      "capytaine_run": ("map", "hulls to compute with Capytaine"),
                      "reference_points": ("list", "[m] where each body's coefficient reference sits"),
                      "radiation": ("str", "state_space or convolution"),
                      "irf_duration": ("number", "[s]"), "irf_dt": ("number", "[s]"),
                      "ss_rtol": ("number", "[-]"), "ss_max_order": ("int", "[-]"),
                      "excitation": ("bool", "apply the wave excitation"),
                      "wamit_options": ("map", "keyword arguments of moorline.hydro.read_wamit")},
    "capytaine_run": {"hulls": ("list", "one per body: {file: mesh} or {shape: ..., <params>}"),
                      "omega": ("vector", "[rad/s] frequencies, or {min, max, n}"),
                      "headings": ("vector", "[deg]"), "water_depth": ("number", "[m] (default: the deck's)"),
                      "lid": ("bool|number", "lid against irregular frequencies"),
                      "cache_dir": ("path", "where results are cached")},
    "hulls": {"file": ("path", "mesh file"), "shape": ("str", "cylinder, hemisphere or axisymmetric"),
              "radius": ("number", "[m]"), "draft": ("number", "[m]"), "profile": ("list", "(r, z) [m]"),
              "offset": ("vector3", "[m]"), "n_theta": ("int", "panels around the axis")},
    "joints": {"child": ("int", "deck body number"), "parent": ("int|str", "deck body number or 'ground'"),
               "axis": ("vector3", "sliding direction in the parent's axes"),
               "pto": ("map", "{stiffness [N/m], damping [N s/m], rest [m]}")},
    "pto": {"stiffness": ("number", "[N/m]"), "damping": ("number", "[N s/m]"), "rest": ("number", "[m]")},
    "sea": {"waves": ("map", "{kind: regular|jonswap|pm, ...}"), "current": ("map", "{speed, heading}"),
            "waves_on_lines": ("bool", "the waves also act on the lines (default true)")},
    "waves": {"kind": ("str", "regular, jonswap or pm"), "H": ("number", "[m]"), "T": ("number", "[s]"),
              "Hs": ("number", "[m]"), "Tp": ("number", "[s]"), "gamma": ("number", "[-]"),
              "heading": ("number", "[deg]"), "seed": ("int", "random phases"), "n": ("int", "components"),
              "ramp": ("number", "[s]"), "phase": ("number", "[rad]")},
    "current": {"speed": ("number", "[m/s]"), "heading": ("number", "[deg]")},
    "run": {"duration": ("number", "[s]"), "dt_out": ("number", "[s]"), "scheme": ("str", "tScheme"),
            "dtM": ("number", "[s]"), "mooring": ("str", "dynamic or quasistatic")},
}


@dataclass
class SystemFile:
    """What a system file holds: the model and the run settings."""

    model: Model
    run: dict = field(default_factory=dict)
    path: Path | None = None


class _Reader:
    def __init__(self, path: Path):
        self.path = path
        self.base = path.parent

    def error(self, where: str, msg: str) -> DeckError:
        return DeckError(f"{where}: {msg}" if where else msg, file=self.path)

    def check_keys(self, d, section: str, where: str, required=()):
        if not isinstance(d, dict):
            raise self.error(where, f"expected a mapping of {', '.join(SCHEMA[section])}, got {d!r}")
        bad = sorted(set(d) - set(SCHEMA[section]))
        if bad:
            raise self.error(where, f"unknown key(s) {', '.join(map(str, bad))}; expected some of "
                             f"{', '.join(SCHEMA[section])}")
        for k in required:
            if k not in d:
                raise self.error(where, f"'{k}' is required ({SCHEMA[section][k][1]})")
        return d

    def number(self, v, where, what="a number", positive=False, nonneg=False) -> float:
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise self.error(where, f"expected {what}, got {v!r}") from None
        if not math.isfinite(x) or (positive and x <= 0) or (nonneg and x < 0):
            cond = " > 0" if positive else (" >= 0" if nonneg else "")
            raise self.error(where, f"expected a finite number{cond}, got {v!r}")
        return x

    def integer(self, v, where, lo=None) -> int:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or (lo is not None and v < lo):
            raise self.error(where, f"expected a whole number{'' if lo is None else f' >= {lo}'}, got {v!r}")
        return int(v)

    def vector(self, v, n, where, what="") -> np.ndarray:
        try:
            a = np.asarray(v, dtype=float).ravel()
        except (TypeError, ValueError):
            a = np.zeros(0)
        if (n is not None and a.size != n) or a.size == 0 or not np.all(np.isfinite(a)):
            count = n if n is not None else "a list of"
            raise self.error(where, f"expected {count} numbers{' ' + what if what else ''}, got {v!r}")
        return a

    def matrix6(self, v, where) -> np.ndarray:
        try:
            a = np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            a = np.zeros(0)
        if a.shape not in ((6,), (6, 6)) or not np.all(np.isfinite(a)):
            raise self.error(where, f"expected 6 numbers (a diagonal) or a 6x6 matrix, got {v!r}")
        return np.diag(a) if a.ndim == 1 else a

    def file(self, v, where, *, stem=False) -> Path:
        if not isinstance(v, str) or not v:
            raise self.error(where, f"expected a file name, got {v!r}")
        p = (self.base / v).resolve()
        if stem:
            if not any(p.with_name(p.name + s).exists() for s in (".1", ".3", ".hst")):
                raise self.error(where, f"no WAMIT files {p}.1 / .3 / .hst")
        elif not p.exists():
            raise self.error(where, f"file not found: {p}")
        return p

    def body(self, v, where, model) -> int:
        n = self.integer(v, where, lo=1)
        if n > len(model.bodies):
            raise self.error(where, f"the deck has {len(model.bodies)} bodies, no body {n}")
        return n - 1


def _omega(r: _Reader, v, where) -> np.ndarray:
    if isinstance(v, dict):
        bad = sorted(set(v) - {"min", "max", "n"})
        if bad or not {"min", "max", "n"} <= set(v):
            raise r.error(where, f"expected {{min, max, n}}, got {v!r}")
        return np.linspace(r.number(v["min"], where + ".min", positive=True),
                           r.number(v["max"], where + ".max", positive=True), r.integer(v["n"], where + ".n", lo=2))
    return r.vector(v, None, where, "[rad/s]")


def _hull(r: _Reader, h, where) -> Hull:
    r.check_keys(h, "hulls", where)
    opts = {}
    if "offset" in h:
        opts["offset"] = r.vector(h["offset"], 3, where + ".offset")
    if "n_theta" in h:
        opts["n_theta"] = r.integer(h["n_theta"], where + ".n_theta", lo=3)
    if "file" in h:
        return Hull(file=r.file(h["file"], where + ".file"), **opts)
    shape = h.get("shape")
    params = {}
    for k in ("radius", "draft"):
        if k in h:
            params[k] = r.number(h[k], f"{where}.{k}", positive=True)
    if "profile" in h:
        prof = np.asarray(h["profile"], dtype=float)
        if prof.ndim != 2 or prof.shape[1] != 2:
            raise r.error(where + ".profile", "expected a list of [r, z] pairs")
        params["profile"] = prof
    try:
        return Hull(shape=shape, params=params, **opts)
    except ModelError as e:
        raise r.error(where, str(e)) from None


def _waves(r: _Reader, w, where) -> Waves:
    r.check_keys(w, "waves", where, required=("kind",))
    kind = str(w["kind"]).lower()
    num = {k: r.number(w[k], f"{where}.{k}") for k in ("H", "T", "Hs", "Tp", "gamma", "heading", "ramp", "phase")
           if k in w}
    opts = {"heading": num.get("heading", 0.0)}
    if "ramp" in num:
        opts["ramp_time"] = num["ramp"]
    try:
        if kind == "regular":
            for k in ("H", "T"):
                if k not in num:
                    raise r.error(where, f"regular waves need '{k}'")
            return Waves.regular(num["H"], num["T"], phase=num.get("phase", 0.0), **opts)
        if kind in ("jonswap", "pm"):
            for k in ("Hs", "Tp"):
                if k not in num:
                    raise r.error(where, f"{kind} waves need '{k}'")
            seed = r.integer(w["seed"], where + ".seed", lo=0) if "seed" in w else None
            n = r.integer(w["n"], where + ".n", lo=1) if "n" in w else None
            gamma = num.get("gamma", 3.3 if kind == "jonswap" else 1.0)
            return Waves.jonswap(num["Hs"], num["Tp"], gamma, seed=seed, n_components=n, **opts)
    except ModelError as e:
        raise r.error(where, str(e)) from None
    raise r.error(where + ".kind", f"expected regular, jonswap or pm, got {w['kind']!r}")


def read_system_file(path) -> SystemFile:
    """Read a system file (see the module docstring) into a :class:`SystemFile`."""
    import yaml

    from .deck import read_deck

    path = Path(path)
    try:
        doc = yaml.safe_load(path.read_text())
    except OSError as e:
        raise DeckError(f"cannot read the system file: {e.strerror or e}", file=path) from e
    except yaml.YAMLError as e:
        raise DeckError(f"not valid YAML: {e}", file=path) from None
    r = _Reader(path)
    r.check_keys(doc, "", "", required=("deck",))
    model = read_deck(r.file(doc["deck"], "deck"))
    # bodies that float
    settings: dict[int, dict] = {}
    for k, b in enumerate(doc.get("bodies") or []):
        where = f"bodies[{k}]"
        r.check_keys(b, "bodies", where, required=("body",))
        i = r.body(b["body"], where + ".body", model)
        if i in settings:
            raise r.error(where + ".body", f"body {i + 1} is listed twice")
        settings[i] = b
        body = model.bodies[i]
        if body.kind != BodyKind.FREE:
            body.kind = BodyKind.FREE  # a coupled deck body (driven by WEC-Sim, say) floats here
        body.V = 0.0
        body.Ca = np.zeros(3)
        if "cog" in b:
            body.rCG = r.vector(b["cog"], 3, where + ".cog", "[m]")
        if "inertia" in b:
            body.I = r.vector(b["inertia"], 3, where + ".inertia", "[kg m^2]")
        if "drag_area" in b:
            body.CdA = r.vector(b["drag_area"], 6, where + ".drag_area")
    # coefficient sets
    for k, h in enumerate(doc.get("hydrodynamics") or []):
        where = f"hydrodynamics[{k}]"
        r.check_keys(h, "hydrodynamics", where, required=("bodies",))
        if not isinstance(h["bodies"], list) or not h["bodies"]:
            raise r.error(where + ".bodies", "expected a list of deck body numbers")
        bodies = [r.body(v, f"{where}.bodies[{j}]", model) for j, v in enumerate(h["bodies"])]
        sources = [s for s in ("wamit", "capytaine", "capytaine_run") if s in h]
        if len(sources) != 1:
            raise r.error(where, "give exactly one of wamit, capytaine, capytaine_run")
        if "wamit" in h:
            coeffs = r.file(h["wamit"], where + ".wamit", stem=True)
        elif "capytaine" in h:
            coeffs = r.file(h["capytaine"], where + ".capytaine")
        else:
            run = r.check_keys(h["capytaine_run"], "capytaine_run", where + ".capytaine_run",
                               required=("hulls", "omega"))
            hulls = [_hull(r, x, f"{where}.capytaine_run.hulls[{j}]") for j, x in enumerate(run["hulls"] or [])]
            try:
                coeffs = BemRun(hulls, _omega(r, run["omega"], where + ".capytaine_run.omega"),
                                wave_direction=r.vector(run.get("headings", [0.0]), None, where + ".headings"),
                                water_depth=None if "water_depth" not in run else
                                r.number(run["water_depth"], where + ".water_depth", positive=True),
                                lid=run.get("lid", False),
                                cache_dir=None if "cache_dir" not in run else (r.base / run["cache_dir"]))
            except ModelError as e:
                raise r.error(where + ".capytaine_run", str(e)) from None
        opts = {}
        for key in ("irf_duration", "irf_dt", "ss_rtol"):
            if key in h:
                opts[key] = r.number(h[key], f"{where}.{key}", positive=True)
        if "ss_max_order" in h:
            opts["ss_max_order"] = r.integer(h["ss_max_order"], where + ".ss_max_order", lo=1)
        if "radiation" in h:
            opts["radiation"] = h["radiation"]
        if "excitation" in h:
            opts["excitation"] = bool(h["excitation"])
        if "reference_points" in h:
            opts["reference_points"] = np.array([r.vector(p, 3, f"{where}.reference_points[{j}]")
                                                 for j, p in enumerate(h["reference_points"])])
        if "wamit_options" in h:
            opts["wamit_options"] = dict(h["wamit_options"])
        try:
            model.add_hydro(bodies, coeffs, **opts)
        except ModelError as e:
            raise r.error(where, str(e)) from None
    # per-body loads (after add_hydro made the default entries)
    for i, b in settings.items():
        where = f"bodies[{list(settings).index(i)}]"
        kw = {name: r.matrix6(b[name], f"{where}.{name}")
              for name in ("linear_damping", "quadratic_damping", "stiffness") if name in b}
        if "force" in b:
            kw["force"] = r.vector(b["force"], 6, where + ".force")
        strips = []
        for j, s in enumerate(b.get("morison") or []):
            w = f"{where}.morison[{j}]"
            r.check_keys(s, "morison", w, required=("rA", "rB", "d", "Cd"))
            strips.append(MorisonStrip(r.vector(s["rA"], 3, w + ".rA"), r.vector(s["rB"], 3, w + ".rB"),
                                       r.number(s["d"], w + ".d", positive=True),
                                       r.number(s["Cd"], w + ".Cd", nonneg=True),
                                       r.integer(s.get("n", 10), w + ".n", lo=1)))
        kw["morison"] = strips
        if model.floating_body(i) is None:
            raise r.error(where, f"body {i + 1} floats but no hydrodynamics entry names it")
        model.add_floating(i, **kw)
    # masses given as 'displaced' need the coefficients' volumes: resolved when the system is built
    for i, b in settings.items():
        where = f"bodies[{list(settings).index(i)}].mass"
        if "mass" not in b:
            continue
        if isinstance(b["mass"], str):
            if b["mass"] != "displaced":
                raise r.error(where, f"expected a number [kg] or 'displaced', got {b['mass']!r}")
            model.floating_body(i).displaced_mass = True
        else:
            model.bodies[i].m = r.number(b["mass"], where, positive=True)
    for k, j in enumerate(doc.get("joints") or []):
        where = f"joints[{k}]"
        r.check_keys(j, "joints", where, required=("child",))
        child = r.body(j["child"], where + ".child", model)
        parent = j.get("parent", "ground")
        parent = None if parent == "ground" else r.body(parent, where + ".parent", model)
        opts = {}
        if "axis" in j:
            opts["axis"] = r.vector(j["axis"], 3, where + ".axis")
        if "pto" in j:
            p = r.check_keys(j["pto"], "pto", where + ".pto")
            for key, name in (("stiffness", "pto_stiffness"), ("damping", "pto_damping"), ("rest", "pto_rest")):
                if key in p:
                    opts[name] = r.number(p[key], f"{where}.pto.{key}", nonneg=key != "rest")
        try:
            model.add_joint(child, parent, **opts)
        except ModelError as e:
            raise r.error(where, str(e)) from None
    sea = doc.get("sea") or {}
    r.check_keys(sea, "sea", "sea")
    if "waves" in sea:
        model.env.waves = _waves(r, sea["waves"], "sea.waves")
    if "waves_on_lines" in sea:
        if not isinstance(sea["waves_on_lines"], bool):
            raise r.error("sea.waves_on_lines", f"expected true or false, got {sea['waves_on_lines']!r}")
        model.env.waves_on_lines = sea["waves_on_lines"]
    if "current" in sea:
        c = r.check_keys(sea["current"], "current", "sea.current", required=("speed",))
        model.env.current = Current.uniform(r.number(c["speed"], "sea.current.speed", nonneg=True),
                                            heading=r.number(c.get("heading", 0.0), "sea.current.heading"))
    run = doc.get("run") or {}
    r.check_keys(run, "run", "run")
    out = {}
    for key in ("duration", "dt_out", "dtM"):
        if key in run:
            out[key] = r.number(run[key], f"run.{key}", positive=True)
    if "scheme" in run:
        out["scheme"] = str(run["scheme"])
    if "mooring" in run:
        if run["mooring"] not in ("dynamic", "quasistatic"):
            raise r.error("run.mooring", f"expected dynamic or quasistatic, got {run['mooring']!r}")
        out["mooring"] = run["mooring"]
    try:
        model.validate()
    except ModelError as e:
        raise DeckError(str(e), file=path) from None
    return SystemFile(model, out, path)
