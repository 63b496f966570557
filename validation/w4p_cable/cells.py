"""The W4P study's committed case store: one small JSON file per finished case (a cable design in
one sea state), under ``validation/w4p_cable/cells/<design>/Hs<Hs>_Tz<Tz>.json``.

A case is run only when its file is absent or was made from other inputs: each file carries a
key, the hash of the case's parameters (design, wave, run length, time step, output rate, hull
dimensions) and of the model's fingerprint (the syntax tree of ``w4p.py`` without comments,
docstrings or formatting: its constants, the model it builds and the post-processing it runs).
Changing any of those re-runs the case; editing a comment does not. Changes inside moorline
itself are not in the key (``run.py --fresh`` re-runs everything).

The design folder is named by the design's parameters (``w2.75_EI350_L70``), so a sweep variant
equal to one of the two designs shares its cells.
"""

from __future__ import annotations

import ast
import hashlib
import json
import math
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CELLS = HERE / "cells"  # the study's run length: 120 s of transient, 5 periods analysed
CELLS_PAPER = HERE / "cells_1500s"  # --paper-length: 1500 s, 900-1500 s analysed
#: the per-node arrays kept (node order from the WEC), and the scalar statistics
ARRAYS = ("s", "theta", "damage_rate", "curvature_max", "curvature_min", "tension_max", "tension_min")
SCALARS = ("min_clearance", "min_clearance_node", "heave_range", "surge_range", "surge_mean", "pitch_range", "z_mean",
           "roll_range", "yaw_range",
           "cable_z_min", "periodicity", "wall_time_s", "H", "T")
OPTIONAL = ("scheme_used", "fallback_reason")  # text, when the case says how it was run
DIGITS = 6  # significant digits stored (the life moves by < 1e-5 relative)


def model_fingerprint(path: Path = HERE / "w4p.py") -> str:
    """Hash of ``w4p.py``'s syntax tree with docstrings dropped (comments and layout are not in it)."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) and \
                isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
            node.body = body[1:] or [ast.Pass()]
    return hashlib.sha256(ast.dump(tree, annotate_fields=False).encode()).hexdigest()[:16]


def design_name(design: dict) -> str:
    return f"w{design['w']:.2f}_EI{design['EI']:g}_L{design['L']:g}"


def inputs(spec, Hs: float, Tz: float) -> dict:
    """The parameters of a case that change its answer (besides the model's fingerprint)."""
    return {"design": {k: float(v) for k, v in sorted(spec.design.items())}, "Hs": float(Hs), "Tz": float(Tz),
            "H": float(spec.H), "T": float(spec.T), "duration": float(spec.duration), "window": float(spec.window),
            "dtM": float(spec.dtM), "samples_per_period": int(spec.samples_per_period),
            "dims": {k: float(v) for k, v in sorted(spec.dims.items())}, "yaw_damping": float(spec.yaw_damping)}


def key(spec, Hs: float, Tz: float, fingerprint: str) -> str:
    blob = json.dumps({"inputs": inputs(spec, Hs, Tz), "model": fingerprint}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()[:20]


def path(design: dict, Hs: float, Tz: float, root: Path = CELLS) -> Path:
    return root / design_name(design) / f"Hs{Hs:g}_Tz{Tz:g}.json"


def _round(a):
    a = np.asarray(a, dtype=float)
    if a.ndim == 0:
        v = float(a)
        return v if not math.isfinite(v) or v == 0.0 else float(f"{v:.{DIGITS}g}")
    return [_round(x) for x in a]


def write(out: dict, spec, Hs: float, Tz: float, fingerprint: str, root: Path = CELLS) -> Path:
    """Store one finished case (written to a temporary file, then renamed: never half a file)."""
    p = path(spec.design, Hs, Tz, root)
    p.parent.mkdir(parents=True, exist_ok=True)
    res = {k: _round(out[k]) for k in ARRAYS}
    res.update({k: (int(out[k]) if k == "min_clearance_node" else _round(out[k])) for k in SCALARS})
    res.update({k: str(out[k]) for k in OPTIONAL if k in out})
    doc = {"study": "w4p_cable", "key": key(spec, Hs, Tz, fingerprint), "model_fingerprint": fingerprint,
           "inputs": inputs(spec, Hs, Tz), "finished_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
           "result": res}
    tmp = p.with_suffix(".part")
    tmp.write_text(json.dumps(doc, separators=(",", ":")) + "\n")
    tmp.replace(p)
    return p


def read(spec, Hs: float, Tz: float, fingerprint: str, root: Path = CELLS) -> dict | None:
    """The stored result of this case, or None when it is absent or was made from other inputs."""
    p = path(spec.design, Hs, Tz, root)
    if not p.exists():
        return None
    doc = json.loads(p.read_text())
    if doc.get("key") != key(spec, Hs, Tz, fingerprint):
        return None
    r = doc["result"]
    out = {k: np.asarray(r[k], dtype=float) for k in ARRAYS}
    out.update({k: r[k] for k in SCALARS})
    out.update({k: r[k] for k in OPTIONAL if k in r})
    out["label"] = f"{design_name(spec.design)} Hs {Hs:g} Tz {Tz:g}"
    out["design"] = dict(spec.design)
    out["cell_file"] = str(p.relative_to(HERE)) if p.is_relative_to(HERE) else str(p)
    return out


#: the fallback of a case whose implicit step fails: explicit RK2 at this dtM [s] (stable below
#: about 0.46 ms here; on the single condition it gives the life of the implicit run within 0.54 %)
FALLBACK_SCHEME, FALLBACK_DTM = "RK2", 4.0e-4


def run_unless_late(spec, deadline: float | None = None):
    """Run one case (:func:`w4p.run_case`) unless the wall clock is past ``deadline`` (epoch
    seconds) when a worker picks it up: then None, and the case stays pending for the next run.

    When the implicit solver fails (its Newton iterations stall: seen for the light 82 m designs,
    whose cable goes slack and snaps near the buoy), the case is run again with explicit RK2 at
    FALLBACK_DTM, and the result says so (``scheme_used``, ``fallback_reason``)."""
    import dataclasses

    import w4p

    from moorline.errors import SimulationError

    if deadline is not None and time.time() > deadline:
        return None
    try:
        out = w4p.run_case(spec)
        out["scheme_used"] = f"GenAlpha dtM {spec.dtM:g}"
        return out
    except SimulationError as e:
        reason = str(e).splitlines()[0]
    build = w4p.build

    def explicit(sp, *, sea=True):
        m = build(sp, sea=sea)
        m.options.tScheme = FALLBACK_SCHEME
        return m

    w4p.build = explicit
    try:
        out = w4p.run_case(dataclasses.replace(spec, dtM=FALLBACK_DTM))
    finally:
        w4p.build = build
    out["scheme_used"] = f"{FALLBACK_SCHEME} dtM {FALLBACK_DTM:g}"
    out["fallback_reason"] = reason
    return out
