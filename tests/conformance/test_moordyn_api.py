"""``moorline.moordyn``, the drop-in for MoorDyn's Python API: the same script, word for word, run
once with ``import moordyn`` (MoorDyn-C 2.7.2, live) and once with ``import moorline.moordyn as
moordyn``, on three decks; every value it reads must agree.

* catenary_3line (../shared conformance deck, OC3-Hywind): three coupled fairlead points moved in
  surge and heave, MoorDyn's Init (initial conditions solved by each code);
* a vessel (coupled body) carrying cables on a clamped hang-off rod, a free zero-length joint and a
  zero-length rod (bending stiffness; tests/conformance/test_oracle_zero_length.py), moved in surge,
  heave and pitch;
* a clump on two lines, one broken off the clump by BreakLine at 1 s (free points, a failure).

The script reads: NCoupledDOF, the object counts, Step's returned loads, GetLineFairTen,
GetLineNodePos/Ten/Curv of every node, GetPointPos/Force/Type/NAttached, GetBodyState/Type,
GetRodNodePos/Type, GetFASTtens. Tolerances (measured values next to them) are relative to the
largest magnitude of each quantity over the run.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import moorline.moordyn as ml_api

md_api = pytest.importorskip("moordyn")

from .driver import SHARED  # noqa: E402
from .test_oracle_failure import VEE  # noqa: E402
from .test_oracle_zero_length import DECK as HANGOFF  # noqa: E402

pytestmark = pytest.mark.oracle

CATENARY = SHARED / "conformance" / "inputs" / "catenary_3line" / "lines.txt"
DT = 0.1

#: loads returned by Step, tensions, point forces and GetFASTtens, relative to their largest value
#: over the run (measured: catenary 5.7e-5 / 5.7e-5 / 9.3e-5 / 5.7e-5 / 5.9e-5, the two codes'
#: initial conditions differ by that much; vessel 1.4e-4 / 5.3e-4 / 1.4e-3 / - / 2.8e-4; vee with
#: BreakLine 0 / 1.7e-5 / 3.3e-5 / 1.9e-5 / 3.2e-5)
TOL_LOAD_REL = 2e-3
#: positions [m]: on catenary_3line each code solves the initial conditions its own way
#: (MoorDyn's stationary solver stops at threshIC): 3.5 mm on the 902 m lines; vessel 3.3e-5 m,
#: body and rod poses 5e-6 m; vee 9e-7 m
TOL_POS = 1e-2
#: curvature, relative to its largest value (measured: vessel cables with EI 2.8e-4; lines without
#: EI 2.6e-3 and 2.2e-2: moorline computes their curvature from the node positions at the end of the
#: step, MoorDyn from those of the last stage of the step)
TOL_CURV_REL = 5e-2


def _surge(x0, amp):
    x0 = np.asarray(x0, dtype=float)

    def X(t):
        ramp = min(t / 1.0, 1.0)
        d = np.zeros_like(x0)
        w = 2.0 * math.pi / 4.0
        for k in range(0, len(x0), 3 if len(x0) % 6 else 6):
            d[k] = amp * ramp * math.sin(w * t)
            d[k + 2] = 0.3 * amp * ramp * math.sin(w * t + 1.0)
        return x0 + d

    return X


def script(api, deck: Path, X, n_steps: int, break_at: int | None = None, probe=None) -> dict:
    """A MoorDyn coupling script: every value it reads, per step (and ``probe(instance)``'s)."""
    m = api.Create(str(deck))
    api.SetVerbosity(m, api.LEVEL_ERR)
    n = api.NCoupledDOF(m)
    x0 = X(0.0) if n else np.zeros(0)
    api.Init(m, list(x0), [0.0] * n)
    out: dict = {"n": [n, api.GetNumberLines(m), api.GetNumberPoints(m), api.GetNumberBodies(m),
                       api.GetNumberRods(m)], "f": [], "fair": [], "pos": [], "ten": [], "curv": [], "ppos": [],
                 "pf": [], "ptype": [], "patt": [], "body": [], "btype": [], "rod": [], "rtype": [], "fast": [],
                 "probe": []}
    t = 0.0
    for k in range(n_steps):
        if break_at is not None and k == break_at:
            api.BreakLine(m, api.GetPoint(m, 3), api.GetLine(m, 1))
        x = X(t) if n else np.zeros(0)
        v = (X(t + DT) - x) / DT if n else np.zeros(0)
        out["f"].append(np.array(api.Step(m, list(x), list(v), t, DT)))
        t += DT
        lines = [api.GetLine(m, i) for i in range(1, api.GetNumberLines(m) + 1)]
        out["fair"].append([api.GetLineFairTen(ln) for ln in lines])
        out["pos"].append([np.array([api.GetLineNodePos(ln, j) for j in range(api.GetLineN(ln) + 1)]) for ln in lines])
        out["ten"].append([np.array([api.GetLineNodeTen(ln, j) for j in range(api.GetLineN(ln) + 1)]) for ln in lines])
        out["curv"].append([np.array([api.GetLineNodeCurv(ln, j) for j in range(api.GetLineN(ln) + 1)])
                            for ln in lines])
        points = [api.GetPoint(m, i) for i in range(1, api.GetNumberPoints(m) + 1)]
        out["ppos"].append(np.array([api.GetPointPos(p) for p in points]))
        out["pf"].append(np.array([api.GetPointForce(p) for p in points]))
        out["ptype"].append([api.GetPointType(p) for p in points])
        out["patt"].append([[(api.GetLineID(api.GetPointAttached(p, i)[0]), api.GetPointAttached(p, i)[1])
                             for i in range(api.GetPointNAttached(p))] for p in points])
        bodies = [api.GetBody(m, i) for i in range(1, api.GetNumberBodies(m) + 1)]
        out["body"].append([np.concatenate(api.GetBodyState(b)) for b in bodies])
        out["btype"].append([api.GetBodyType(b) for b in bodies])
        rods = [api.GetRod(m, i) for i in range(1, api.GetNumberRods(m) + 1)]
        out["rod"].append([np.array([api.GetRodNodePos(r, j) for j in range(api.GetRodN(r) + 1)]) for r in rods])
        out["rtype"].append([api.GetRodType(r) for r in rods])
        out["fast"].append(np.array(api.GetFASTtens(m, api.GetNumberLines(m))))
        if probe is not None:
            out["probe"].append(probe(m))
    with pytest.raises(RuntimeError):
        api.GetLine(m, api.GetNumberLines(m) + 1)
    api.Close(m)
    return out


def _rel(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    big = float(np.max(np.abs(b))) or 1.0
    return float(np.max(np.abs(a - b))) / big


def compare(ref: dict, got: dict) -> dict:
    """Largest differences, per quantity; exact equality of counts and type codes is asserted."""
    assert got["n"] == ref["n"]
    for key in ("ptype", "patt", "btype", "rtype"):
        assert got[key] == ref[key], key
    err = {"f": _rel(got["f"], ref["f"]) if ref["n"][0] else 0.0, "fair": _rel(got["fair"], ref["fair"])}
    nl = ref["n"][1]
    err["ten"] = max(_rel([s[i] for s in got["ten"]], [s[i] for s in ref["ten"]]) for i in range(nl))
    err["pos"] = max(float(np.max(np.abs(np.array([s[i] for s in got["pos"]]) - [s[i] for s in ref["pos"]])))
                     for i in range(nl))
    # per step: a failure adds a point
    err["ppos"] = max(float(np.max(np.abs(np.asarray(g) - r))) for g, r in zip(got["ppos"], ref["ppos"], strict=True))
    # MoorDyn reports no force on fixed points (anchors, body points: zero); moorline reports the
    # loads of the lines on them, so only free and coupled points are compared
    big = max(float(np.max(np.abs(r))) for r in ref["pf"]) or 1.0
    err["pf"] = max((float(np.max(np.abs(np.asarray(g)[m] - np.asarray(r)[m]))) / big if m.any() else 0.0)
                    for g, r, m in ((g, r, np.array(k) != md_api.POINT_TYPE_FIXED)
                                    for g, r, k in zip(got["pf"], ref["pf"], ref["ptype"], strict=True)))
    curv_ref = np.concatenate([np.concatenate(s) for s in ref["curv"]])
    curv_got = np.concatenate([np.concatenate(s) for s in got["curv"]])
    err["curv"] = _rel(curv_got, curv_ref) if np.max(np.abs(curv_ref)) > 1e-6 else float(np.max(np.abs(curv_got)))
    if ref["n"][3]:
        err["body"] = float(np.max(np.abs(np.array(got["body"]) - ref["body"])))
    if ref["n"][4]:
        err["rod"] = max(float(np.max(np.abs(np.array([s[i] for s in got["rod"]]) - [s[i] for s in ref["rod"]])))
                         for i in range(ref["n"][4]))
    err["fast"] = _rel(got["fast"], ref["fast"])
    return err


def _check(err: dict) -> None:
    for key in ("f", "fair", "ten", "pf", "fast"):
        assert err[key] <= TOL_LOAD_REL, (key, err)
    for key in ("pos", "ppos", "body", "rod"):
        assert err.get(key, 0.0) <= TOL_POS, (key, err)
    assert err["curv"] <= TOL_CURV_REL, ("curv", err)


def _both(deck: Path, X, n_steps: int, break_at: int | None = None) -> dict:
    return compare(script(md_api, deck, X, n_steps, break_at), script(ml_api, deck, X, n_steps, break_at))


def test_coupled_fairleads():
    if not CATENARY.is_file():
        pytest.skip(f"{CATENARY} not found (../shared absent)")
    x0 = [5.2, 0.0, -70.0, -2.6, 4.5, -70.0, -2.6, -4.5, -70.0]
    _check(_both(CATENARY, _surge(x0, 4.0), 30))


def test_coupled_body_with_rods_and_bending(tmp_path):
    """The loads on the vessel: moorline passes the bending moment of the clamped cable end to the
    hang-off rod (and so to the body), MoorDyn-C does not (docs/moordyn_differences.md): the
    moments differ by exactly that moment (1.7 % of the pitch moment here) and agree with
    ``ClampMoment 0``, MoorDyn's way."""
    deck = tmp_path / "hangoff.txt"
    deck.write_text(HANGOFF)
    X = _surge(np.zeros(6), 2.0)
    ref = script(md_api, deck, X, 30)
    got = script(ml_api, deck, X, 30, probe=lambda m: m.system.lines[0].end_moments()[0])
    clamp = np.array(got["probe"])
    assert np.max(np.abs(clamp)) > 100.0  # the clamp does bend the cable [N m]
    f_ml, f_md = np.array(got["f"]), np.array(ref["f"])
    assert _rel(f_ml[:, :3], f_md[:, :3]) <= TOL_LOAD_REL
    assert _rel(f_ml[:, 3:], f_md[:, 3:]) > 5e-3  # the clamp moment is there
    assert _rel(f_ml[:, 3:] - clamp, f_md[:, 3:]) <= TOL_LOAD_REL
    as_moordyn = tmp_path / "hangoff_md.txt"
    as_moordyn.write_text(HANGOFF.replace("0             TmaxIC", "0             TmaxIC\n0             ClampMoment"))
    _check(compare(ref, script(ml_api, as_moordyn, X, 30)))


def test_break_line(tmp_path):
    deck = tmp_path / "vee.txt"
    deck.write_text(VEE.format(failure=""))
    err = _both(deck, lambda t: np.zeros(0), 25, break_at=10)
    _check(err)


def test_save_and_load_state(tmp_path):
    """SaveState / LoadState (moorline checkpoints): a restored instance continues bitwise."""
    deck = tmp_path / "vee.txt"
    deck.write_text(VEE.format(failure=""))
    a = ml_api.Create(str(deck))
    ml_api.Init(a, [], [])
    for k in range(5):
        ml_api.Step(a, [], [], k * DT, DT)
    ml_api.SaveState(a, tmp_path / "state.npz")
    blob = ml_api.Serialize(a)
    b = ml_api.Create(str(deck))
    ml_api.Init(b, [], [])
    ml_api.LoadState(b, tmp_path / "state.npz")
    c = ml_api.Create(str(deck))
    ml_api.Init(c, [], [])
    ml_api.Deserialize(c, blob)
    for k in range(5, 8):
        fa = [ml_api.Step(x, [], [], k * DT, DT) for x in (a, b, c)]
        assert fa[0] == fa[1] == fa[2]
    pos = [ml_api.GetLineNodePos(ml_api.GetLine(x, 2), 5) for x in (a, b, c)]
    assert pos[0] == pos[1] == pos[2]
