"""What one coupling step costs beyond its compiled work: ``System.step``'s fast path against its
general path, and both against the compiled entry point called directly.

    python benchmarks/bench_step_call.py [--calls 2000] [--rounds 7] [--dt 0.01] [--no-moordyn]
                                         [--loads-at end|last_stage] [--scheme S --dtM DT] [DECK ...]

Default decks: MoorDyn's WD0050_Chain and bench no_waves (../shared/public_decks) and the README
example (examples/catenary_3line). For each deck, four systems are built from it, initialised
alike and driven alike (every coupled ``_x`` DOF surging as in ``bench_public_decks.py``, the
trajectory's x and xd computed before timing), in one process, in interleaved rounds of
``--calls`` calls; the minimum (and median) over the rounds, per call, of the wall time:

- ``general``: ``System._step_general``, the path ``step`` takes where its fast path does not apply
  (and the only path before the fast path was added: its code is that of main at 8006fde);
- ``fast``: ``System.step`` (its fast path, :mod:`moorline.system.stepplan`);
- ``entry``: the time loop's compiled entry point called directly with the fast path's argument
  tuple for the same step, after the same copies of x, xd and t into the trajectory's
  coefficients (what is left when the Python side is removed: the compiled work and the unboxing
  of the arguments); ``entry, no end evaluation``: the same with ``final_eval`` false (the loads
  then describe the last stage: not what ``step`` reports, timed only to measure the cost of the
  end-of-step evaluation);
- ``floor``: the entry point with nothing to integrate and no end evaluation (numba unboxing the
  ~220 arrays of the argument tuple, the call's fixed cost); ``floor + end evaluation``: nothing
  to integrate, the end evaluation done (so the difference of the two is what the evaluation
  ``step`` adds after its last step costs, measured without the noise of the integration);
- ``MoorDyn``: MoorDyn-C 2.7.2's ``Step`` (the ``moordyn`` package) on the same trajectory, when
  the package is installed (``--no-moordyn`` leaves it out), the x and xd lists made before timing;
- ``Python side, general`` and ``Python side, fast``: the two paths with the compiled call
  replaced by a Python function that returns at once what the time loop returns (the kept entry
  point of ``FastCall`` and of the fast path's plan swapped for it after the first real call),
  which measures the Python side alone, without the noise of the compiled work (the stand-in's
  own call, about 0.05 us, included).

``--loads-at last_stage`` builds the systems with MoorDyn's convention (that of
:mod:`moorline.moordyn`): each call then ends with an evaluation at the state reached, over which
the last stage's loads are kept; since 2026-11-26 (session 8) it runs inside the compiled call
(``core.integrate.last_stage_keep``), so the "Python side" columns no longer include it, and the
"end evaluation" columns time it.

Not a test: timings on a shared machine are noisy
(read the load average printed first; the minimum over rounds is the figure least affected).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from bench_public_decks import surge_of  # noqa: E402
from bench_vs_moordyn import moordyn_copy  # noqa: E402

from moorline import System  # noqa: E402
from moorline.core.integrate import FINAL_NONE  # noqa: E402

PUBLIC = HERE.parent.parent / "shared" / "public_decks" / "FloatingArrayDesign+MoorDyn"
DECKS = [PUBLIC / "tests" / "Mooring" / "WD0050_Chain.txt", PUBLIC / "bench" / "Mooring" / "no_waves.txt",
         HERE.parent / "examples" / "catenary_3line" / "catenary_3line.dat"]


def trajectory(s: System, n: int, dt: float):
    X = surge_of(s.coupled_dof_labels, s.deck_coupled_positions())
    xs = [X(k * dt) for k in range(n + 1)]
    return xs, [(xs[k + 1] - xs[k]) / dt for k in range(n)]


def _returns_at_once(y, t, t_end, *rest):
    """Stands in for the compiled time loop when only the Python side is timed."""
    return t_end, -1, 1, 0


COLS = ("general", "fast", "entry", "entry, no end evaluation", "floor", "floor + end evaluation",
        "Python side, general", "Python side, fast")


def bench(deck: Path, calls: int, rounds: int, dt: float, with_moordyn: bool, loads_at: str = "end",
          scheme: str | None = None, dtM: float | None = None) -> dict:
    md = None
    if with_moordyn:
        try:
            import moordyn as md
        except ImportError:
            md = None
    with moordyn_copy(deck) if md else contextlib.nullcontext():
        return _bench(deck, calls, rounds, dt, md, loads_at, scheme, dtM)


def _bench(deck: Path, calls: int, rounds: int, dt: float, md, loads_at: str, scheme, dtM) -> dict:
    systems = {}
    for name in COLS:
        s = System.from_file(deck, loads_at=loads_at, scheme=scheme, dtM=dtM)
        s.init()
        s.warm_up()
        systems[name] = s
    n = s.n_coupled_dof
    xs, vs = trajectory(s, calls * rounds + 1, dt)
    outs = {k: np.empty(n) for k in systems}
    # the first call of each makes the fast path's plan (and of "entry": the argument tuple used below)
    for name, s in systems.items():
        s.step(xs[0], vs[0], 0.0, dt, out=outs[name])
        if name == "Python side, general":
            s._step_general(xs[0], vs[0], 0.0, dt, outs[name])
            assert s._call_advance._fn is not None
            s._call_advance._fn = _returns_at_once
        elif name == "Python side, fast":
            s._plan.fn = _returns_at_once
    times = {k: [] for k in systems}
    if md is not None:
        m = md.Create(deck.name)
        md.Init(m, list(xs[0]), [0.0] * n)
        md.Step(m, list(xs[0]), list(vs[0]), 0.0, dt)
        xl, vl = [list(x) for x in xs], [list(v) for v in vs]
        times["MoorDyn"] = []
    k0 = 1
    for _ in range(rounds):
        if md is not None:
            t0 = time.perf_counter()
            for k in range(k0, k0 + calls):
                md.Step(m, xl[k], vl[k], k * dt, dt)
            times["MoorDyn"].append((time.perf_counter() - t0) / calls * 1e6)
        for name, s in systems.items():
            out = outs[name]
            ks = range(k0, k0 + calls)
            if name in ("general", "Python side, general"):
                step = s._step_general
                t0 = time.perf_counter()
                for k in ks:
                    step(xs[k], vs[k], k * dt, dt, out)
                el = time.perf_counter() - t0
            elif name in ("fast", "Python side, fast"):
                step = s.step
                t0 = time.perf_counter()
                for k in ks:
                    step(xs[k], vs[k], k * dt, dt, out=out)
                el = time.perf_counter() - t0
            else:
                p = s._plan
                fn, y, tk, cx, cxd = p.fn, p.head[0], p.tk, p.cx, p.cxd
                final = p.tail[-1] if name in ("entry", "floor + end evaluation") else (
                    False if p.implicit else FINAL_NONE)
                tail = p.tail[:-1] + (final,)
                h = 0.0 if name.startswith("floor") else dt
                t0 = time.perf_counter()
                for k in ks:
                    cx[...] = xs[k]
                    cxd[...] = vs[k]
                    t = k * dt
                    tk[0] = t
                    tk[1] = t + dt
                    fn(y, t, t + h, *tail)
                el = time.perf_counter() - t0
            times[name].append(el / calls * 1e6)
        k0 += calls
    if md is not None:
        md.Close(m)
    g, f = systems["general"], systems["fast"]
    if not (np.array_equal(g.coupled_forces(), f.coupled_forces()) and np.array_equal(g.y, f.y)):
        raise AssertionError(f"{deck.name}: the fast and general paths differ")
    return {"deck": deck.name, "nodes": int(f.work.r.shape[0]), "scheme": f.scheme_label,
            "dtM": f.dtM, "min": {k: min(v) for k, v in times.items()},
            "median": {k: statistics.median(v) for k, v in times.items()}}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("decks", nargs="*", type=Path)
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--no-moordyn", action="store_true", help="leave MoorDyn out")
    ap.add_argument("--loads-at", default="end", choices=("end", "last_stage"))
    ap.add_argument("--scheme", default=None, help="moorline's scheme instead of the deck's (not MoorDyn's)")
    ap.add_argument("--dtM", type=float, default=None, help="moorline's time step instead of the deck's")
    a = ap.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f}; {a.rounds} rounds of {a.calls} calls, "
          f"dt {a.dt} s, loads_at {a.loads_at}; per call [us], minimum over rounds (median)")
    cols = COLS + (() if a.no_moordyn else ("MoorDyn",))
    print("| deck | nodes | scheme | dtM [s] | " + " | ".join(cols) + " | entry - floor | end evaluation |")
    print("|---|---:|---|---:|" + "---:|" * (len(cols) + 2))
    for deck in a.decks or DECKS:
        r = bench(deck, a.calls, a.rounds, a.dt, not a.no_moordyn, a.loads_at, a.scheme, a.dtM)
        m, md = r["min"], r["median"]
        cells = [f"{m[c]:.2f} ({md[c]:.2f})" if c in m else "-" for c in cols]
        extra = [m["entry"] - m["floor"], m["floor + end evaluation"] - m["floor"]]
        print(f"| {r['deck']} | {r['nodes']} | {r['scheme']} | {r['dtM']:.3g} | " + " | ".join(cells) + " | "
              + " | ".join(f"{v:.2f}" for v in extra) + " |", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
