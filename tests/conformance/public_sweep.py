"""Every public MoorDyn deck in moorline and in MoorDyn 2.7.2, side by side.

For each deck listed in ``../shared/public_decks/decks.txt``: parse it in moorline, run it for
``DURATION`` seconds in both codes with a small imposed surge of every coupled object
(``SURGE`` m, a raised-cosine cycle of ``PERIOD`` s, so the start is at rest), driven as a
MoorDyn coupling program does (outer step ``DT``: ``Step(x(t), xd(t), t, DT)``), and compare the
end tensions of every line (against moorline's ``anchor_tension`` / ``fairlead_tension``):

MoorDyn's end tensions are ``GetLineNodeTen`` at nodes 0 and N (``GetLineFairTen`` is the latter).

* initial: after ``Init``, the largest difference over lines and ends relative to the largest
  tension of the deck;
* dynamic: per line end, the RMS over the outer samples after Init of the difference, relative to
  the RMS of MoorDyn's tension; the worst line end is reported.

Decks are copied to a scratch folder first (MoorDyn writes its outputs next to the deck) and
each run starts in the folder MoorDyn's own tests start in (the one holding ``Mooring/``; else
the deck's folder), since MoorDyn resolves ``SeafloorFile`` from the working directory. Each code
runs in its own subprocess with a time limit, so a crash or a hang in one run loses nothing else.

Run by hand::

    PYTHONPATH=src python tests/conformance/public_sweep.py [--out sweep.json] [--only SUBSTRING] [--icnewton 0]

It prints one line per deck and writes every figure to the JSON file; ``sweep_table.py`` makes the
markdown table of it. ``--icnewton 0`` starts moorline with MoorDyn's initial-condition methods
(which stop where MoorDyn's stop), to compare the dynamics from comparable starts.
``--same-start`` starts moorline from MoorDyn's own state after ``Init`` (MoorDyn's ``SaveState``
file, read as the deck's ``fileIC``, with no IC solve in moorline), so any difference left is in the
dynamics alone. ``--inertial-loads moordyn`` runs moorline with MoorDyn-C's inertial loads of rods
and bodies (the one deliberate difference in their dynamics).
``MOORLINE_ALL_FEATURES=1`` in the environment makes every deck use the one all-features kernel
(compiled once) instead of compiling a specialisation per kind of deck.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared"))
PUBLIC = SHARED / "public_decks"

DURATION = 10.0  # [s]
DT = 0.1  # outer coupling step [s]
SURGE = 1.0  # [m]
PERIOD = 10.0  # [s]
TIMEOUT = 900.0
FLOOR = 0.01  # see compare()  # per code and deck [s]
#: decks that are not valid input as published (decks.txt README): MoorDyn fails on them too
TEMPLATES = ("tests/Mooring/time_schemes.txt",)


def deck_list() -> list[str]:
    return [ln.strip() for ln in (PUBLIC / "decks.txt").read_text().splitlines() if ln.strip()]


def run_dir(deck: Path) -> Path:
    """The folder MoorDyn's own drivers start in: the parent of ``Mooring/`` if the deck is under one."""
    parts = deck.parts
    if "Mooring" in parts:
        i = len(parts) - 1 - parts[::-1].index("Mooring")
        return Path(*parts[:i])
    return deck.parent


def surge(t: float) -> tuple[float, float]:
    """Surge offset [m] and rate [m/s] at time t."""
    w = 2.0 * math.pi / PERIOD
    return 0.5 * SURGE * (1.0 - math.cos(w * t)), 0.5 * SURGE * w * math.sin(w * t)


# ----------------------------------------------------------------------------- the two codes
def _layout_from_moordyn(md, s):
    """Coupled positions and the index of every surge DOF from MoorDyn's own objects."""
    x, surge_idx = [], []
    for i in range(1, md.GetNumberBodies(s) + 1):
        b = md.GetBody(s, i)
        if md.GetBodyType(b) == md.BODY_TYPE_COUPLED:
            surge_idx.append(len(x))
            x += list(md.GetBodyPos(b)) + list(md.GetBodyAngle(b))
    for i in range(1, md.GetNumberRods(s) + 1):
        r = md.GetRod(s, i)
        k = md.GetRodType(r)
        if k in (md.ROD_TYPE_COUPLED, md.ROD_TYPE_CPLDPIN):
            surge_idx.append(len(x))
            x += list(md.GetRodNodePos(r, 0)) + ([0.0, 0.0, 0.0] if k == md.ROD_TYPE_COUPLED else [])
    for i in range(1, md.GetNumberPoints(s) + 1):
        p = md.GetPoint(s, i)
        if md.GetPointType(p) == md.POINT_TYPE_COUPLED:
            surge_idx.append(len(x))
            x += list(md.GetPointPos(p))
    return np.array(x, dtype=float), surge_idx


def run_moordyn(deck: Path) -> dict:
    import moordyn as md

    os.chdir(run_dir(deck))
    t0 = time.perf_counter()
    s = md.Create(str(deck))
    n = md.NCoupledDOF(s)
    x0, idx = _layout_from_moordyn(md, s)
    if x0.size < n:
        # a coupled-pinned body counts 6 in NCoupledDOF, its Init and Step read 3 (spec 3.17)
        x0 = np.concatenate([x0, np.zeros(n - x0.size)])
    if x0.size != n:
        return {"ok": False, "error": f"coupled layout {x0.size} != NCoupledDOF {n}"}
    nl = md.GetNumberLines(s)
    lines = [md.GetLine(s, i) for i in range(1, nl + 1)]

    def tens():
        out = []
        for ln in lines:
            out.append([_node_force(md, ln, 0), md.GetLineFairTen(ln)])
        return out

    v0 = np.zeros(n)
    md.Init(s, x0, v0)
    t_init = time.perf_counter() - t0
    if os.environ.get("MOORLINE_SWEEP_SAME_START"):
        md.SaveState(s, str(_state_file(deck)))
    series = [tens()]
    t = 0.0
    for _k in range(int(round(DURATION / DT))):
        x, v = _motion(x0, idx, t)
        md.Step(s, x, v, t, DT)
        t += DT
        series.append(tens())
    md.Close(s)
    return {"ok": True, "tensions": series, "n_dof": n, "wall": time.perf_counter() - t0, "wall_init": t_init}


def _state_file(deck: Path) -> Path:
    """Where ``--same-start`` keeps MoorDyn's state after Init (beside the scratch copy of the deck)."""
    return deck.with_name(deck.name + ".init_state")


def _node_force(md, ln, j):
    """Tension at node j (GetLineNodeTen; at node N it is GetLineFairTen). Not GetLineNodeForce:
    that is the net force on the node, weight and seabed contact included, which on a slack or
    lying end has nothing to do with the tension."""
    return float(np.linalg.norm(md.GetLineNodeTen(ln, j)))


def _motion(x0, idx, t):
    x = x0.copy()
    v = np.zeros_like(x0)
    ds, dv = surge(t)
    for i in idx:
        x[i] += ds
        v[i] = dv
    return x, v


def run_moorline(deck: Path) -> dict:
    import logging

    from moorline.errors import DeckError, SimulationError
    from moorline.io import read_deck
    from moorline.system import System

    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    os.chdir(run_dir(deck))
    t0 = time.perf_counter()
    try:
        model = read_deck(deck)
    except DeckError as e:
        return {"ok": False, "stage": "parse", "error": str(e)}
    if os.environ.get("MOORLINE_SWEEP_ICNEWTON"):
        model.options.ICNewton = int(os.environ["MOORLINE_SWEEP_ICNEWTON"])
    if os.environ.get("MOORLINE_SWEEP_INERTIA"):
        model.options.InertialLoads = os.environ["MOORLINE_SWEEP_INERTIA"]
    if os.environ.get("MOORLINE_SWEEP_SAME_START"):
        # start from the state MoorDyn's Init handed over (its SaveState file; the deck option fileIC)
        # and solve no initial conditions: the dynamics alone are compared
        model.options.fileIC = str(_state_file(deck))
        model.options.TmaxIC = 0.0
    try:
        sysm = System(model, loads_at="last_stage")
        x0 = sysm.deck_coupled_positions()
        labels = sysm.coupled_dof_labels
        idx = [i for i, lab in enumerate(labels) if lab.endswith("_x")]
        sysm.init(x0, np.zeros_like(x0))
        t_init = time.perf_counter() - t0

        def tens():
            return [[ln.anchor_tension(), ln.fairlead_tension()] for ln in sysm.lines]

        series = [tens()]
        t = 0.0
        for _k in range(int(round(DURATION / DT))):
            x, v = _motion(x0, idx, t)
            sysm.step(x, v, t, DT)
            t += DT
            series.append(tens())
    except (SimulationError, DeckError, ValueError) as e:
        return {"ok": False, "stage": "run", "error": f"{type(e).__name__}: {e}"}
    ic = {k: (v if isinstance(v, (int, float, str, bool, list)) else str(v)) for k, v in sysm.ic_report.items()}
    return {"ok": True, "tensions": series, "n_dof": int(x0.size), "wall": time.perf_counter() - t0,
            "wall_init": t_init, "ic": ic, "scheme": sysm.scheme_label, "dtM": sysm.dtM}


def _child(code: str, deck: str, out: str) -> None:
    try:
        res = (run_moordyn if code == "moordyn" else run_moorline)(Path(deck))
    except Exception as e:  # a crash is a result here
        res = {"ok": False, "stage": "crash", "error": f"{type(e).__name__}: {e}",
               "trace": traceback.format_exc()[-2000:]}
    Path(out).write_text(json.dumps(res))


def run_one(code: str, deck: Path, timeout: float = TIMEOUT) -> dict:
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        out = f.name
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    t0 = time.perf_counter()
    try:
        p = subprocess.run([sys.executable, __file__, "--child", code, str(deck), out], capture_output=True,
                           text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return {"ok": False, "stage": "timeout", "error": f"no result within {timeout:.0f} s"}
    try:
        res = json.loads(Path(out).read_text())
    except (OSError, json.JSONDecodeError):
        tail = (p.stderr or p.stdout or "")[-1500:]
        res = {"ok": False, "stage": "crash", "error": f"process exited {p.returncode}: {tail}"}
    finally:
        Path(out).unlink(missing_ok=True)
    res["elapsed"] = time.perf_counter() - t0
    if code == "moorline":
        res["log"] = [ln for ln in (p.stderr or "").splitlines() if ln.startswith(("WARNING", "ERROR"))][:20]
    return res


def compare(ml: dict, md: dict) -> dict:
    a = np.array(ml["tensions"], dtype=float)  # (n_t, n_lines, 2)
    b = np.array(md["tensions"], dtype=float)
    if a.shape != b.shape:
        return {"error": f"shapes differ {a.shape} vs {b.shape}"}
    # the largest tension of the deck over the run: line ends that carry less than FLOOR of it are
    # judged against FLOOR of it (a slack end's relative error says nothing)
    scale = max(float(np.max(np.abs(b))), 1e-9)
    init = float(np.max(np.abs(a[0] - b[0]) / np.maximum(np.abs(b[0]), FLOOR * scale)))
    # the dynamic measure leaves out the sample at Init: it is the initial measure's, and MoorDyn
    # reports zero tensions there when it did not solve initial conditions (TmaxIC 0)
    rms_d = np.sqrt(np.mean((a[1:] - b[1:]) ** 2, axis=0))
    rms_b = np.sqrt(np.mean(b[1:] ** 2, axis=0))
    rel = rms_d / np.maximum(rms_b, FLOOR * scale)
    worst = np.unravel_index(int(np.argmax(rel)), rel.shape)
    return {"initial": init, "dynamic": float(rel[worst]), "worst": [int(worst[0]) + 1, "AB"[worst[1]]],
            "finite": bool(np.all(np.isfinite(a)))}


def sweep(decks: list[str], scratch: Path) -> list[dict]:
    rows = []
    for name in decks:
        deck = scratch / name
        row = {"deck": name}
        if any(name.endswith(t) for t in TEMPLATES):
            row["template"] = True
            row["moordyn"] = {"ok": False, "error": "a template with @..@ placeholders, not valid input"}
            row["moorline"] = run_one("moorline", deck)
            rows.append(row)
            print(_line(row), flush=True)
            continue
        row["moordyn"] = run_one("moordyn", deck)
        row["moorline"] = run_one("moorline", deck)
        if row["moordyn"].get("ok") and row["moorline"].get("ok"):
            row["cmp"] = compare(row["moorline"], row["moordyn"])
        rows.append(row)
        print(_line(row), flush=True)
    return rows


def moordyn_again(rows: list[dict], scratch: Path) -> list[dict]:
    for row in rows:
        if not row.get("template"):
            row["moordyn"] = run_one("moordyn", scratch / row["deck"])
        row.pop("cmp", None)
        if row["moordyn"].get("ok") and row["moorline"].get("ok"):
            row["cmp"] = compare(row["moorline"], row["moordyn"])
        print(_line(row), flush=True)
    return rows


def _line(row) -> str:
    ml, md = row["moorline"], row["moordyn"]
    s = f"{row['deck']}: MoorDyn {'ok' if md.get('ok') else 'FAIL ' + md.get('error', '')[:120]}; moorline "
    s += "ok" if ml.get("ok") else f"FAIL[{ml.get('stage')}] {ml.get('error', '')[:300]}"
    if "cmp" in row:
        c = row["cmp"]
        s += f"; initial {c.get('initial', float('nan')):.2e}, dynamic {c.get('dynamic', float('nan')):.2e}"
    return s


def copy_decks(dest: Path) -> Path:
    for d in PUBLIC.iterdir():
        if d.is_dir():
            shutil.copytree(d, dest / d.name)
    for p in dest.rglob("*"):
        p.chmod(p.stat().st_mode | 0o200)
    return dest


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", nargs=3, metavar=("CODE", "DECK", "OUT"), help=argparse.SUPPRESS)
    ap.add_argument("--out", default="public_sweep.json")
    ap.add_argument("--only", default="")
    ap.add_argument("--decks-from", metavar="FILE", help="run only the decks listed in FILE (one a line)")
    ap.add_argument("--moordyn-again", metavar="SWEEP_JSON",
                    help="re-run only MoorDyn on every deck of an earlier sweep's JSON and compare again with its "
                    "moorline results (when only the MoorDyn side of the comparison changed)")
    ap.add_argument("--recompare", metavar="SWEEP_JSON",
                    help="compare again the tensions stored in an earlier sweep's JSON (no run)")
    ap.add_argument("--icnewton", type=int, choices=(-1, 0, 1),
                    help="set every deck's ICNewton in moorline (0: MoorDyn's initial-condition methods only)")
    ap.add_argument("--same-start", action="store_true",
                    help="start moorline from MoorDyn's state after Init (MoorDyn's SaveState file read as the "
                    "deck's fileIC, no IC solve in moorline): compares the dynamics alone")
    ap.add_argument("--inertial-loads", choices=("full", "moordyn"),
                    help="set every deck's InertialLoads in moorline (moordyn: MoorDyn-C's inertial loads of rods "
                    "and bodies, docs/moordyn_differences.md)")
    args = ap.parse_args(argv)
    if args.inertial_loads:
        os.environ["MOORLINE_SWEEP_INERTIA"] = args.inertial_loads
    if args.same_start:
        os.environ["MOORLINE_SWEEP_SAME_START"] = "1"
    if args.icnewton is not None:
        os.environ["MOORLINE_SWEEP_ICNEWTON"] = str(args.icnewton)
    if args.child:
        _child(*args.child)
        return 0
    if args.recompare:
        rows = json.loads(Path(args.recompare).read_text())
        for row in rows:
            row.pop("cmp", None)
            if row["moordyn"].get("ok") and row["moorline"].get("ok"):
                row["cmp"] = compare(row["moorline"], row["moordyn"])
        Path(args.out).write_text(json.dumps(rows, indent=1))
        return 0
    decks = [d for d in deck_list() if args.only in d]
    if args.decks_from:
        wanted = {ln.strip() for ln in Path(args.decks_from).read_text().splitlines() if ln.strip()}
        decks = [d for d in decks if d in wanted]
    with tempfile.TemporaryDirectory() as tmp:
        if args.moordyn_again:
            rows = moordyn_again(json.loads(Path(args.moordyn_again).read_text()), copy_decks(Path(tmp)))
        else:
            rows = sweep(decks, copy_decks(Path(tmp)))
    Path(args.out).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
