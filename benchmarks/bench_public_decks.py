"""moorline against MoorDyn on public MoorDyn decks, at each deck's own scheme and time step.

    python benchmarks/bench_public_decks.py [--repeat 3] [--duration 30] [--dt 0.01] [--only SUBSTRING]

The decks are those of ``../shared/public_decks`` (MoorDyn's benchmark and test decks, the IEA
15 MW semisubmersible's, WEC-Sim's RM3 moorings, MoorPy's), as published: scheme, dtM and
discretisation are the deck's. Every coupled object surges 2 m (a 20 s sine, with a smooth 10 s
ramp; heave and the angles of coupled bodies and rods stay put) and both codes are driven as a host
drives them: one ``Step(x_k, v_k, t_k, dt)`` per coupling step ``dt`` (default 0.01 s, what the
speed issue asks for), with v_k = (X(t_{k+1}) - X(t_k)) / dt, the x_k and v_k of every call made
before the clock starts (numpy arrays for moorline, lists for MoorDyn's Python package): the
host's own motion is not timed (evaluating it took some 4 us per call, the same for both codes,
which before 2026-11-26 12:20 UTC was timed with each and pulled the ratios towards 1).
moorline runs the same trajectory a second way, through its compiled loop (``advance_to`` once
per second over the same piecewise linear trajectory), which is what ``moorline run`` does.
Initial conditions are solved once per run and are not timed; moorline's first (compiling) call
is not timed either.

``--loads-at last_stage`` builds moorline's systems with MoorDyn's convention for the loads after
a step (those of the last stage, as ``moorline.moordyn`` does; the default is moorline's, the
loads at the state reached, one evaluation more per call).

Reported per deck: nodes, scheme, dtM, the wall time of the three runs (median of ``--repeat``),
node-steps per second (of the compiled loop) and the ratios moorline / MoorDyn measured side by side in one process
(the runs are interleaved, ``step()``, compiled loop, MoorDyn, ``--repeat`` times, and a ratio is
the median of the rounds' ratios: this virtual machine's speed drifts by up to 1.8x over minutes,
and a ratio of medians taken minutes apart followed the drift), and
the largest difference of the final coupled forces relative to MoorDyn's largest (a check that
both ran the same problem). Times are the process's CPU time (``time.process_time``): both codes
run single-threaded in this one process, so on an idle machine it equals their wall time, and on a
shared machine it is not inflated by other processes' load as wall time is. Not part of the test
suite.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_vs_moordyn import SHARED, finish_table, run_moordyn  # noqa: E402

PUBLIC = SHARED / "public_decks"

#: (label, deck under ../shared/public_decks): decks that run in both codes at their own settings
#: and need no file beside them other than what their folder holds
DECKS = [
    ("MoorDyn bench no_waves", "FloatingArrayDesign+MoorDyn/bench/Mooring/no_waves.txt"),
    ("MoorDyn WD0050_Chain", "FloatingArrayDesign+MoorDyn/tests/Mooring/WD0050_Chain.txt"),
    ("MoorDyn WD0600_Chain", "FloatingArrayDesign+MoorDyn/tests/Mooring/WD0600_Chain.txt"),
    ("MoorDyn example lines", "FloatingArrayDesign+MoorDyn/example/lines.txt"),
    ("MoorDyn lines (tests)", "FloatingArrayDesign+MoorDyn/tests/Mooring/lines.txt"),
    ("MoorDyn BodiesAndRods", "FloatingArrayDesign+MoorDyn/tests/Mooring/BodiesAndRods.dat"),
    ("MoorDyn complex_system (LEuler)", "FloatingArrayDesign+MoorDyn/tests/Mooring/local_euler/complex_system.txt"),
    ("IEA 15 MW UMaine semi", "IEAWindTask37+IEA-15-240-RWT/OpenFAST/IEA-15-240-RWT-UMaineSemi/"
                              "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat"),
    ("WEC-Sim RM3 moorings", "WEC-Sim+WEC-Sim_Applications/Mooring/MoorDyn/Mooring/lines.txt"),
    ("MoorPy volturn_chain", "NREL+MoorPy/examples/volturn_chain.dat"),
    ("MoorPy semi-taut", "NREL+MoorPy/examples/MoordynSemiTautUpd.dat"),
]


def surge_of(labels: list[str], X0: np.ndarray):
    """X(t): every coupled ``_x`` DOF surges 2 m, period 20 s, smooth 10 s ramp; the rest held."""
    d = np.array([1.0 if lab.endswith("_x") else 0.0 for lab in labels])

    def X(t):
        u = min(t / 10.0, 1.0)
        s = u**3 * (6 * u * u - 15 * u + 10)
        return X0 + d * (2.0 * s * math.sin(2 * math.pi * t / 20.0))

    return X


_x0: dict = {}


def run_moorline(deck: Path, duration, dt, mode, loads_at="end"):
    from moorline import System
    from moorline.motion import Trajectory

    s = System.from_file(deck, loads_at=loads_at)
    X0 = s.deck_coupled_positions()
    _x0[deck] = X0
    X = surge_of(s.coupled_dof_labels, X0)
    s.init(X(0.0), np.zeros(s.n_coupled_dof))
    nsteps = int(round(duration / dt))
    out = np.empty(s.n_coupled_dof)
    if mode == "step":
        s.warm_up()  # compiles or loads the loop without integrating
        xs = [X(k * dt) for k in range(nsteps + 1)]
        calls = [(xs[k], (xs[k + 1] - xs[k]) / dt) for k in range(nsteps)]
        t0 = time.process_time()
        for k, (xk, vk) in enumerate(calls):
            s.step(xk, vk, k * dt, dt, out=out)
        wall = time.process_time() - t0
        f = out
    else:
        m = Trajectory.from_function(X, nsteps * dt, dt, "linear").as_motion()
        s.warm_up(m)
        t0 = time.process_time()
        for k in range(1, int(math.ceil(duration)) + 1):
            s.advance_to(min(float(k), nsteps * dt), m)
        wall = time.process_time() - t0
        f = s.coupled_forces()
    nodes = int(s.layout.lines.node_ptr[-1])
    return wall, nodes, f, s


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--duration", type=float, default=30.0, help="simulated seconds per run")
    ap.add_argument("--dt", type=float, default=0.01, help="coupling step [s]")
    ap.add_argument("--only", help="run the decks whose label contains this")
    ap.add_argument("--out", help="also write the table (markdown) here")
    ap.add_argument("--loads-at", default="end", choices=("end", "last_stage"),
                    help="moorline's loads after a step: at the state reached (its default) or MoorDyn's "
                         "convention, the last stage's (what moorline.moordyn uses)")
    a = ap.parse_args(argv)
    if not PUBLIC.exists():
        print(f"{PUBLIC} not found: nothing to run")
        return 0
    import moordyn  # noqa: F401  (the peer; this benchmark means nothing without it)

    rows = ["| deck | nodes | scheme | dtM [s] | MoorDyn [s] | moorline step() [s] | ratio | "
            "moorline compiled loop [s] | ratio | moorline node-steps/s | MoorDyn node-steps/s | final force diff |",
            "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for label, rel in DECKS:
        if a.only and a.only.lower() not in label.lower():
            continue
        deck = PUBLIC / rel
        if not deck.exists():
            continue
        try:
            walls = {"step": [], "advance": [], "moordyn": []}
            for _ in range(a.repeat):
                for mode in ("step", "advance"):
                    w, nodes, f, s = run_moorline(deck, a.duration, a.dt, mode, a.loads_at)
                    walls[mode].append(w)
                    if mode == "step":
                        f_step = f
                w, nodes_md, f_md = run_moordyn(deck, lambda X0, lab=s.coupled_dof_labels: surge_of(lab, X0),
                                                a.duration, a.dt, x0=_x0[deck], clock=time.process_time,
                                                precompute=True)
                walls["moordyn"].append(w)
        except Exception as exc:  # a deck one of the codes cannot run: say so and go on
            print(f"{label}: not timed ({type(exc).__name__}: {exc})")
            continue
        med = {k: statistics.median(v) for k, v in walls.items()}
        ratio = {k: statistics.median([w / m for w, m in zip(walls[k], walls["moordyn"], strict=True)])
                 for k in ("step", "advance")}
        steps = a.duration / s.dtM
        diff = float(np.max(np.abs(f_step - f_md)) / max(np.max(np.abs(f_md)), 1e-300)) if f_step.size else 0.0
        row = (f"| {label} | {nodes} | {s.scheme_label} | {s.dtM:.3g} | {med['moordyn']:.3f} | {med['step']:.3f} | "
               f"{ratio['step']:.2f} | {med['advance']:.3f} | {ratio['advance']:.2f} | "
               f"{nodes * steps / med['advance']:.3g} | {nodes_md * steps / med['moordyn']:.3g} | {diff:.1e} |")
        print(row, flush=True)
        rows.append(row)
    finish_table(rows, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
