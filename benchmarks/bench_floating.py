"""Floating bodies in the time loop: a spar on three catenaries in 600 s of irregular sea.

    python benchmarks/bench_floating.py [--repeat 3]

The OC3-Hywind-like spar (Capytaine coefficients of its axisymmetric hull, computed once and cached),
three 902.2 m chains of 20 segments in 320 m of water, a JONSWAP sea (Hs 6 m, Tp 10 s, 200 components)
exciting the hull (the lines in still water, as MoorDyn under WEC-Sim or HydroDyn with WaveKin 0).
Reported, each the median of ``--repeat`` runs after a warm-up run (compile excluded):

- wall time of the 600 s with generalized-alpha at 0.1 s (state-space radiation) and with RK2 at the
  explicit stability limit's step, as multiples of real time;
- the cost of the floating body beside the cost of the lines: the same run with the hull replaced by a
  coupled body held still (lines only), and one derivative evaluation with and without the body;
- state-space radiation against direct convolution of the impulse response (60 s at 0.05 s).

Prints a markdown section (run_all.py collects it into RESULTS.md).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from numba import njit

import moorline
from moorline import hydro
from moorline.core.rhs import rhs
from moorline.model import Model
from moorline.model.water import Waves

DEPTH = 320.0
DURATION = 600.0


def spar_coefficients(cache: Path):
    pts = [(0.0, -120.0)]
    for a, b, n in (((0.0, -120.0), (4.7, -120.0), 3), ((4.7, -120.0), (4.7, -12.0), 27),
                    ((4.7, -12.0), (3.25, -4.0), 4), ((3.25, -4.0), (3.25, 0.0), 2)):
        for s in np.linspace(0.0, 1.0, n + 1)[1:]:
            pts.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    return hydro.compute_coefficients(hydro.mesh_axisymmetric(np.array(pts), n_theta=24),
                                      omega=np.linspace(0.05, 3.0, 40), rho=1025.0, g=9.80665, water_depth=DEPTH,
                                      rotation_center=[0.0, 0.0, 0.0], cache_dir=cache)


def spar_model(ds, scheme, dtM, *, radiation="state_space", floating=True) -> Model:
    m = Model()
    m.env.depth = DEPTH
    m.options.tScheme = scheme
    m.options.dtM = dtM
    m.add_line_type("chain", d=0.09, w=77.7066, EA=384.243e6, BA=-0.8, Cd=1.6, Ca=1.0, CdAx=0.1, CaAx=0.0)
    b = m.add_body("free" if floating else "coupled", (0.0, 0.0, 0.0), m=8.066e6, rCG=(0.0, 0.0, -78.0),
                   I=(6.0e9, 6.0e9, 1.6e8))
    for k in range(3):
        a = np.radians(180.0 + 120.0 * k)
        fl = m.add_point("body", (5.2 * np.cos(a), 5.2 * np.sin(a), -70.0), body=b)
        an = m.add_point("fixed", (853.87 * np.cos(a), 853.87 * np.sin(a), -DEPTH))
        m.add_line("chain", an, fl, L=902.2, N=20)
    if floating:
        m.add_hydro([b], ds, radiation=radiation)
        m.add_floating(b, stiffness=[0, 0, 0, 0, 0, 98.34e6])
    m.env.waves = Waves.jonswap(6.0, 10.0, seed=3)
    m.env.waves_on_lines = False
    return m


def timed_run(model, repeat):
    """Median wall time [s] of DURATION s after init (a first run compiles)."""
    walls = []
    stats = {}
    for _ in range(repeat + 1):
        s = moorline.System(model)
        s.init()
        t0 = time.perf_counter()
        s.step(None, None, 0.0, DURATION)
        walls.append(time.perf_counter() - t0)
        stats = s.solver_stats
    return statistics.median(walls[1:]), stats, s


@njit(cache=True)
def _evals(n, y, dy, L, R, P, E, B, Mo, W, F, FW):
    for i in range(n):
        rhs(1.0 + 1e-3 * i, y, dy, L, R, P, E, B, Mo, W, F, FW, 1.0, -1)


def eval_cost(s, n=20000) -> float:
    """One derivative evaluation [us], timed inside compiled code."""
    L, R, P, E, B, W, F, FW = s._kernel_arrays()
    dy = np.zeros_like(s.y)
    _evals(10, s.y, dy, L, R, P, E, B, s._motion, W, F, FW)
    t0 = time.perf_counter()
    _evals(n, s.y, dy, L, R, P, E, B, s._motion, W, F, FW)
    return (time.perf_counter() - t0) / n * 1e6


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        ds = spar_coefficients(Path(tmp))
    rows = []
    cases = [("GenAlpha 0.1 s, state-space radiation", spar_model(ds, "GenAlpha", 0.1)),
             ("GenAlpha 0.1 s, convolution (60 s at 0.05 s)", spar_model(ds, "GenAlpha", 0.1, radiation="convolution")),
             ("RK2 5 ms, state-space radiation", spar_model(ds, "RK2", 0.005)),
             ("lines only (body held still), GenAlpha 0.1 s", spar_model(ds, "GenAlpha", 0.1, floating=False)),
             ("lines only (body held still), RK2 5 ms", spar_model(ds, "RK2", 0.005, floating=False))]
    systems = {}
    for label, model in cases:
        wall, st, s = timed_run(model, args.repeat)
        systems[label] = s
        steps = st.get("steps") or round(DURATION / s.dtM)
        rows.append((label, wall, DURATION / wall, steps, st.get("evaluations", "")))
        print(f"{label}: {wall:.3f} s", file=sys.stderr)
    ev_float = eval_cost(systems[cases[0][0]])
    ev_lines = eval_cost(systems[cases[3][0]])
    nz = systems[cases[0][0]].layout.n_radiation
    print("## Floating bodies: a spar on three catenaries, 600 s of irregular sea (`bench_floating.py`)\n")
    print("OC3-Hywind-like spar (Capytaine coefficients of the axisymmetric hull), three 902.2 m chains of 20 "
          "segments (63 nodes), 320 m depth, JONSWAP Hs 6 m Tp 10 s (200 components) on the hull, lines in still "
          f"water. Median of {args.repeat} runs after a warm-up run (compile excluded); init excluded.\n")
    print("| case | wall [s] for 600 s | x real time | steps | derivative evaluations |")
    print("|---|---|---|---|---|")
    for label, wall, rt, steps, ev in rows:
        print(f"| {label} | {wall:.3f} | {rt:.0f} | {steps} | {ev} |")
    print(f"\nOne derivative evaluation (inside compiled code): {ev_float:.2f} us with the floating body "
          f"({nz} radiation states), {ev_lines:.2f} us for the lines alone: the body costs "
          f"{ev_float - ev_lines:.2f} us per evaluation beside {ev_lines:.2f} us for the lines.")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
