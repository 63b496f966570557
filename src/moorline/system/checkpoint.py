"""Save and restart a :class:`~moorline.system.System` (MoorDyn's Save/Load): :func:`save` and
:func:`load`, also :meth:`System.save` and :meth:`System.load`.

A checkpoint holds everything the time loop carries from one step to the next, so that a run
restarted from it continues bitwise identically to one that never stopped:

- the state vector ``y`` (whatever blocks it has) and the time;
- the scheme's memory: the scratch rows of the explicit and fixed-point schemes (the fixed-point
  schemes carry the previous derivative there), and every array of the implicit solver's work
  (carried acceleration, factored Jacobian, step size, counters) with its parameters;
- the history of the lines (viscoelastic and Syrope states at the step start, Syrope working
  curves and peak tensions, VIV running means, local-Euler flags);
- the seabed state (stick-slip friction anchors and slip flags) and every ``Work`` array (the loads
  the views report, the coupled kinematics);
- the water kinematics arrays (wave components or grids: a sea drawn with a random seed is
  restored, not drawn again), the wave excitation of floating bodies, and the coupled trajectory
  of the last step;
- floating bodies: their radiation states are part of ``y``; the floating work carries the rest
  (the convolution's velocity history and its cursor, the trapezoid's factored matrices and their
  step, the joints' slide and PTO power);
- the line failures, pending and happened (a checkpoint written after a failure is restored into a
  system built from the deck by releasing the same line ends again, then restoring the state);
- the initial-condition and stability reports, and a caller's ``meta`` (for the command line,
  the sizes of the streamed output files at the moment of the checkpoint).

The arrays are saved by walking the NamedTuples listed in :data:`CARRIERS`, so a new field of
``Work`` or of the implicit solver's work, or a new block of the state vector, is saved without
further work. A fingerprint of the layout (every array that describes the model, the shapes of
everything saved, scheme, time step) is stored with it: a checkpoint of another model is refused
with a message that says what differs.

Not supported: the quasi-static mooring mode (``System(mooring="quasistatic")``), whose
quasi-static line solver keeps a warm start outside these arrays; :func:`save` refuses it.

The file is a numpy ``.npz`` archive written atomically (a temporary file renamed into place).
"""

from __future__ import annotations

import hashlib
import io
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .. import __version__
from ..core.layout import Motion
from ..core.linestates import LINE_HISTORY
from ..errors import CheckpointError
from ..io.atomic import atomic_path
from . import failures

if TYPE_CHECKING:
    from .runtime import System

#: format version of the checkpoint files
VERSION = 1



class _Some:
    """Some fields of a NamedTuple, seen as a NamedTuple (for :data:`CARRIERS`)."""

    def __init__(self, tup, names):
        self._tup = tup
        self._fields = tuple(n for n in names if n in tup._fields)

    def __getattr__(self, name):
        return getattr(self._tup, name)


#: the NamedTuples whose arrays a checkpoint saves and restores: (name, getter)
CARRIERS = (
    ("line_history", lambda s: _Some(s.layout.lines, LINE_HISTORY)),
    ("work", lambda s: s.work),
    ("seabed", lambda s: s.layout.seabed),
    ("water", lambda s: s.layout.env.water),
    ("water_ic", lambda s: s.layout.env_ic.water),
    ("implicit", lambda s: s._imp[1] if s._imp is not None else None),
    ("floating_work", lambda s: s.fwork),
    ("excitation", lambda s: s.layout.env.exc),
)

#: arrays that describe the model (a checkpoint of a model where any differs is refused)
_MODEL_PARTS = ("lines", "rigid", "points", "fl")
#: scalars of the environment that the fingerprint includes
_ENV_SCALARS = ("g", "rho", "depth", "kBot", "cBot", "contact", "fric", "muT", "muA", "mc", "cv", "kshear", "cshear",
                "bed_ramp", "bed_blend")


def _arrays(tup) -> dict[str, np.ndarray]:
    return {f: getattr(tup, f) for f in tup._fields if isinstance(getattr(tup, f), np.ndarray)}


def describe(system: System) -> dict:
    """What a checkpoint must match, in words: counts, scheme, time step, deck."""
    m = system.model
    K = system.layout.env.water
    return {"deck": m.source.name if m.source is not None else "(built in Python)", "lines": len(m.lines),
            "water": f"wave mode {K.wave_mode}, current mode {K.current_mode}, {K.c_omega.size} wave components",
            "points": len(m.points), "rods": len(m.rods), "bodies": len(m.bodies),
            "floating bodies": int(system.layout.fl.body.size), "joints": int(system.layout.fl.jt_child.size),
            "state size": int(system.y.size),
            "scheme": system.scheme_label, "dtM": repr(float(system.dtM)), "loads_at": system.loads_at}


def fingerprint(system: System) -> str:
    """SHA-256 of the layout: every array of lines, rods, bodies and points, the environment's
    scalars, the shapes of every array a checkpoint carries, the scheme and the time step."""
    h = hashlib.sha256()
    lay = system.layout
    h.update(json.dumps(describe(system), sort_keys=True).encode())
    for part in _MODEL_PARTS:
        for name, a in _arrays(getattr(lay, part)).items():
            if part == "lines" and name in LINE_HISTORY:
                continue  # saved (CARRIERS), not compared
            h.update(f"{part}.{name}{a.dtype}{a.shape}".encode())
            h.update(np.ascontiguousarray(a).tobytes())
    h.update(repr([getattr(lay.env, k) for k in _ENV_SCALARS]).encode())
    for name, get in CARRIERS:
        tup = get(system)
        if tup is None:
            continue
        for f, a in _arrays(tup).items():
            h.update(f"{name}.{f}{a.dtype}{a.shape}".encode())
    for name in ("gx", "gy", "gz"):
        h.update(np.ascontiguousarray(getattr(lay.seabed, name)).tobytes())
    return h.hexdigest()


def save(system: System, path, *, meta: dict | None = None) -> Path:
    """Write a checkpoint of ``system`` (initialised) to ``path`` (``.npz``); ``meta``: JSON-ready
    values stored with it and returned by :func:`load`."""
    if not system.initialized:
        raise RuntimeError("call init() before save(): there is no state to save yet")
    if system._qsm is not None:
        raise CheckpointError("checkpoints of the quasi-static mooring mode (mooring='quasistatic') are not "
                              "supported: its quasi-static line solver keeps a warm start that a checkpoint does "
                              "not hold, so a restart would not continue bitwise; run it without --checkpoint-every")
    path = Path(path)
    arrays = {"y": system.y, "S": system._S, "motion_t": system._motion.t, "motion_c": system._motion.c}
    for name, get in CARRIERS:
        tup = get(system)
        if tup is not None:
            arrays.update({f"{name}/{f}": a for f, a in _arrays(tup).items()})
    if system._imp is not None:
        arrays["implicit_par"] = system._imp[0].par
    info = {"version": VERSION, "moorline_version": __version__, "fingerprint": fingerprint(system),
            "describe": describe(system), "t": float(system.t), "ic_report": system.ic_report,
            "stability": system.stability, "grid_warned": system._grid_warned, "meta": meta or {},
            "failures": [failures.to_record(ev) for ev in system.failures]}
    buf = io.BytesIO()
    np.savez(buf, info=np.array(json.dumps(info, default=str)), **arrays)
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        f.write(buf.getvalue())
        f.flush()
        os.fsync(f.fileno())
    return path


def load(system: System, path) -> dict:
    """Restore ``system`` (built from the same model, with the same scheme and time step) to the
    checkpoint at ``path``. Returns the ``meta`` saved with it.

    Raises
    ------
    CheckpointError
        A file that is not a moorline checkpoint, or one written for another model, scheme or
        time step (the message says what differs).
    """
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        info = json.loads(str(data.pop("info")))
    except (OSError, ValueError, KeyError) as e:
        raise CheckpointError(f"{path}: not a readable moorline checkpoint ({e})") from None
    system._drop_step_plan()  # (made again by the next step(): the failures below may replace what it holds)
    if info.get("failures"):
        failures.replay(system, info["failures"])  # the lines released before the checkpoint, released again
    if "implicit_par" in data:
        system._implicit()  # the implicit solver's arrays exist before they are compared and filled
    if info.get("version") != VERSION:
        raise CheckpointError(f"{path}: checkpoint format {info.get('version')}, this moorline reads {VERSION}")
    if info["fingerprint"] != fingerprint(system):
        then, now = info["describe"], describe(system)
        diff = [f"{k}: {then.get(k)} in the checkpoint, {now[k]} here" for k in now if then.get(k) != now[k]]
        raise CheckpointError(f"{path} was written for another model: " + ("; ".join(diff) if diff else
                              "the line, rod, body, point or seabed properties differ") +
                              ". Resume with the deck and settings (--dtM, --scheme, --waves) of the interrupted run")
    if "implicit_par" in data:
        system._imp[0].par[...] = data.pop("implicit_par")
    system.y[...] = data.pop("y")
    system._S[...] = data.pop("S")
    system._motion = Motion(data.pop("motion_t"), data.pop("motion_c"))
    for name, get in CARRIERS:
        tup = get(system)
        if tup is None:
            continue
        for f, a in _arrays(tup).items():
            a[...] = data.pop(f"{name}/{f}")
    system.t = float(info["t"])
    system.ic_report = info["ic_report"]
    system.stability = info["stability"]
    system._grid_warned = bool(info["grid_warned"])
    system.initialized = True
    return info["meta"]
