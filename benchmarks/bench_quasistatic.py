"""Quasi-static solver: moorline against MoorPy, side by side in one run.

    python benchmarks/bench_quasistatic.py [--repeat 5] [--out benchmarks/quasistatic.md]

Cases (decks in tests/quasistatic/data):

1. OC3-Hywind with delta (bridle) connections: 9 lines, 3 free junctions, a coupled body. The
   equilibrium of the junctions from the deck's start positions plus the body's 6x6 coupled stiffness
   (moorline: ``QuasiStaticModel.solve``; MoorPy: ``System.solveEquilibrium`` + ``getCoupledStiffnessA``),
   at MoorPy's default tolerance and at a tight one.
2. The same system in a time-domain coupling loop: a new body pose each call (0.1 m surge steps),
   warm-started equilibrium + stiffness.
3. The OC3 spar on three catenaries (no free points) in the same loop.
4. An offset curve of 100 points of case 1 (surge 0..30 m): moorline's ``offset_curve`` (loads,
   stiffness along the offset and tensions per point) against a MoorPy loop of body position +
   equilibrium + loads.
5. Compile time of the quasi-static kernels: a fresh interpreter with an empty numba cache (cold), and
   again with that cache filled (cached).

Reports wall times (best of ``--repeat``), speed-up and the largest tension difference between the
two codes. Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "quasistatic" / "data"
sys.path.insert(0, str(ROOT / "src"))

from moorline.io import read_deck  # noqa: E402
from moorline.quasistatic import QuasiStaticModel  # noqa: E402
from moorline.quasistatic.studies import offset_curve  # noqa: E402

G, RHO = 9.80665, 1025.0


def best(f, repeat, number=1):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            out = f()
        ts.append((time.perf_counter() - t0) / number)
    return min(ts), out


def moorpy_system(path, depth):
    import moorpy as mp

    with contextlib.redirect_stdout(io.StringIO()):
        ms = mp.System(file=str(path), depth=depth, rho=RHO, g=G)
        ms.initialize()
    return ms


def quiet(f):
    def g(*a, **k):
        with contextlib.redirect_stdout(io.StringIO()):
            return f(*a, **k)
    return g


def case_bridle(repeat):
    path = DATA / "oc3_bridle.dat"
    qs = QuasiStaticModel(read_deck(path))
    qs.solve()  # compile / load the kernels

    def ml():
        qs.reset()
        return qs.solve()

    t_ml, sol = best(ml, repeat, 5)
    ms = moorpy_system(path, 320.0)
    r0 = [p.r.copy() for p in ms.pointList]

    def mp_run(tol):
        def run():
            for p, r in zip(ms.pointList, r0, strict=True):
                if p.type == 0:
                    p.setPosition(r)
            ms.solveEquilibrium(tol=tol, maxIter=5000)
            return ms.getCoupledStiffnessA()
        return quiet(run)

    rows = []
    for tol, label in ((0.05, "MoorPy default tol (0.05)"), (1e-6, "MoorPy tol 1e-6")):
        t_mp, K = best(mp_run(tol), repeat)
        T = np.array([[ln.TA, ln.TB] for ln in ms.lineList])
        dT = float(np.max(np.abs(T / sol.tensions - 1)))
        dK = float(np.max(np.abs(K - sol.stiffness)) / np.max(np.abs(sol.stiffness)))
        rows.append((f"bridle: equilibrium from the deck + 6x6 stiffness ({label})", t_ml, t_mp, dT, dK))
    return rows, qs, ms


def case_loop(name, depth, repeat, n=200):
    path = DATA / f"{name}.dat"
    qs = QuasiStaticModel(read_deck(path))
    x0 = qs.deck_coupled_positions()
    poses = [x0 + np.r_[0.1 * k, 0.0, 0.0, 0.0, 0.0, 0.0] for k in range(n)]

    def ml():
        for x in poses:
            s = qs.solve(x)
        return s

    qs.solve(x0)
    t_ml, sol = best(ml, repeat)
    ms = moorpy_system(path, depth)
    body = ms.bodyList[0]

    @quiet
    def mp_run():
        for x in poses:
            body.setPosition(x)
            ms.solveEquilibrium(tol=1e-6, maxIter=5000)
            K = ms.getCoupledStiffnessA()
        return K

    t_mp, K = best(mp_run, max(1, repeat // 2))
    T = np.array([[ln.TA, ln.TB] for ln in ms.lineList])
    dT = float(np.max(np.abs(T / sol.tensions - 1)))
    dK = float(np.max(np.abs(K - sol.stiffness)) / np.max(np.abs(sol.stiffness)))
    return (f"{name}: coupling loop, new pose + equilibrium + 6x6 stiffness, per call", t_ml / n, t_mp / n, dT, dK)


def case_offset_curve(repeat, qs, ms):
    a = np.linspace(0.0, 30.0, 100)
    qs.reset()
    t_ml, ds = best(lambda: offset_curve(qs, a, heading=0.0), repeat)
    body = ms.bodyList[0]

    @quiet
    def mp_run():
        out = []
        for s in a:
            body.setPosition(np.r_[s, 0.0, 0.0, 0.0, 0.0, 0.0])
            ms.solveEquilibrium(tol=1e-6, maxIter=5000)
            out.append(body.getForces(lines_only=True)[0])
        return np.array(out)

    t_mp, fx = best(mp_run, max(1, repeat // 2))
    dF = float(np.max(np.abs(fx - ds["mooring_load"].sel(dof="x").values)) / np.max(np.abs(fx)))
    return ("bridle: offset curve, 100 points (surge 0-30 m)", t_ml, t_mp, dF, float("nan"))


_COMPILE = """
import time, sys
t0 = time.perf_counter()
sys.path.insert(0, {src!r})
from moorline.io import read_deck
from moorline.quasistatic import QuasiStaticModel
from moorline.quasistatic.studies import offset_curve
t1 = time.perf_counter()
qs = QuasiStaticModel(read_deck({deck!r}))
qs.solve(gradients=True)
offset_curve(qs, [0.0, 1.0])
t2 = time.perf_counter()
print(t1 - t0, t2 - t1)
"""


def compile_times():
    with tempfile.TemporaryDirectory() as d:
        env = dict(os.environ, NUMBA_CACHE_DIR=d)
        code = _COMPILE.format(src=str(ROOT / "src"), deck=str(DATA / "oc3_bridle.dat"))
        out = []
        for _ in range(2):
            r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
            out.append([float(v) for v in r.stdout.split()])
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", help="also write the table to this markdown file")
    args = ap.parse_args(argv)
    rows, qs, ms = case_bridle(args.repeat)
    rows.append(case_loop("oc3_bridle", 320.0, args.repeat))
    rows.append(case_loop("oc3_spar", 320.0, args.repeat))
    rows.append(case_offset_curve(args.repeat, qs, ms))
    (imp_c, comp_c), (imp_w, comp_w) = compile_times()
    lines = ["| case | moorline | MoorPy | speed-up | max tension diff | max stiffness diff |",
             "|---|---|---|---|---|---|"]
    for label, t_ml, t_mp, dT, dK in rows:
        lines.append(f"| {label} | {_fmt(t_ml)} | {_fmt(t_mp)} | {t_mp / t_ml:.0f}x | {dT:.1e} | "
                     f"{'-' if np.isnan(dK) else f'{dK:.1e}'} |")
    lines += ["", f"Compile time of the quasi-static kernels (first solve with stiffness and gradients, plus an "
              f"offset curve, in a fresh interpreter): cold (empty numba cache) {comp_c:.1f} s, cached {comp_w:.2f} s "
              f"(imports {imp_c:.1f} s / {imp_w:.1f} s)."]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    return 0


def _fmt(t: float) -> str:
    if t < 1e-3:
        return f"{t * 1e6:.0f} us"
    if t < 1.0:
        return f"{t * 1e3:.2f} ms"
    return f"{t:.2f} s"


if __name__ == "__main__":
    sys.exit(main())
