"""Wall time of moorline against MoorDyn (the ``moordyn`` package), side by side in one process.

    python benchmarks/bench_vs_moordyn.py [--repeat 3] [--cases example,catenary_3line_surge,...]

Both codes run the same deck with the same time scheme and dtM, driven the same way: outer
coupling steps of ``dt`` with x_k and v_k = (X(t_{k+1}) - X(t_k))/dt (MoorDyn_Step), moorline
through ``System.step`` (the same contract, one call per outer step) and also through one
``advance_to`` call per output interval (its compiled loop over many outer steps). Initial
conditions are solved once and excluded; the first (compiling) moorline call is excluded and
reported separately. Reported: wall time (median of ``--repeat``), real-time factor, node-steps
per second and the ratio moorline / MoorDyn.

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared"))
CONF = SHARED / "conformance"


@contextlib.contextmanager
def quiet_fds():
    """Silence MoorDyn's console output (C-level stdout/stderr)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    try:
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        os.close(devnull)
        os.close(saved[0])
        os.close(saved[1])


def sine_motion(X0, amplitude, period, direction, ramp):
    d = np.tile(np.asarray(direction, dtype=float), len(X0) // 3)

    def X(t):
        u = min(t / ramp, 1.0) if ramp > 0 else 1.0
        s = u**3 * (6 * u * u - 15 * u + 10)
        return X0 + d * (s * amplitude * math.sin(2 * math.pi * t / period))

    return X


def cases():
    """name -> (deck path, motion factory X0 -> X(t), duration [s], outer dt [s]).

    The four cases of the speed issue come first: the OC3 3-line chain catenary (63 nodes), a
    semi-taut chain-polyester system in 600 m (147 nodes), a lazy-wave cable with bending stiffness
    and buoyancy on zero-length rods (140 nodes) and a farm of 20 OC3 moorings (3060 nodes); then
    other systems (the README example, a bridle with clump weight and buoy, a pendulum in RK4)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from make_farm import write_farm

    decks = ROOT / "benchmarks" / "decks"
    out = {}
    surge = lambda X0: sine_motion(X0, 5.0, 20.0, (1, 0, 0), 20.0)  # noqa: E731
    if CONF.exists():
        out["catenary_3line_surge"] = (CONF / "inputs/catenary_3line/lines.txt", surge, 120.0, 0.1)
    out["semitaut_chain_polyester_surge"] = (decks / "semitaut_chain_polyester.dat", surge, 60.0, 0.1)
    out["lazy_wave_cable_heave"] = (decks / "lazy_wave_cable.dat",
                                    lambda X0: sine_motion(X0, 2.0, 8.0, (0, 0, 1), 8.0), 30.0, 0.1)
    farm_dir = Path(tempfile.mkdtemp(prefix="moorline_farm_"))
    out["farm_20x3_lines"] = (write_farm(farm_dir / "farm.dat"), surge, 20.0, 0.1)
    ex = ROOT / "examples" / "catenary_3line" / "catenary_3line.dat"
    out["example_3line_chain"] = (ex, lambda X0: sine_motion(X0, 6.0, 20.0, (1, 0, 0), 10.0), 60.0, 0.1)
    if CONF.exists():
        out["bridle_clump_buoy_surge"] = (CONF / "inputs/bridle_clump_buoy/bridle_clump_buoy.txt",
                                          lambda X0: sine_motion(X0, 8.0, 25.0, (1, 0.25, 0), 25.0), 150.0, 0.1)
        out["pendulum_point_mass_RK4"] = (CONF / "inputs/pendulum/pendulum.txt", None, 100.0, 0.1)
    return out


@contextlib.contextmanager
def quiet_in(folder):
    """Work in ``folder`` (MoorDyn opens the files a deck names relative to the working directory
    and writes its outputs there) with MoorDyn's console output silenced."""
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        with quiet_fds():
            yield
    finally:
        os.chdir(cwd)


@contextlib.contextmanager
def moordyn_copy(deck: Path):
    """Work, silenced, in a scratch copy of the deck's folder, removed afterwards."""
    work = Path(tempfile.mkdtemp(prefix="bench_md_"))
    shutil.copytree(deck.parent, work / "case")
    try:
        with quiet_in(work / "case"):
            yield
    finally:
        shutil.rmtree(work, ignore_errors=True)


def moordyn_coupled_points(md, s) -> list:
    """MoorDyn's coupled points (type -1), in order: their positions are the coupled DOFs."""
    points = (md.GetPoint(s, i) for i in range(1, md.GetNumberPoints(s) + 1))
    return [P for P in points if md.GetPointType(P) == -1]


def moordyn_nodes(md, s) -> int:
    """Number of line nodes of a MoorDyn system."""
    return sum(md.GetLineN(md.GetLine(s, i)) + 1 for i in range(1, md.GetNumberLines(s) + 1))


def run_moordyn(deck: Path, motion, duration, dt, *, x0=None, clock=time.perf_counter, precompute=False):
    """Time MoorDyn_Step calls every ``dt`` along ``motion(X0)`` (X0: ``x0``, or the positions of
    MoorDyn's coupled points); ``clock``: wall (default) or CPU time; ``precompute``: the x and xd
    lists of every call made before the clock starts (the host's motion is then not timed).
    Returns (time, nodes, forces)."""
    import moordyn as md

    with moordyn_copy(deck):
        s = md.Create(deck.name)
        n = md.NCoupledDOF(s)
        if x0 is None:
            X0 = np.concatenate([md.GetPointPos(P) for P in moordyn_coupled_points(md, s)] or [np.zeros(0)])
        else:
            X0 = np.asarray(x0, dtype=float)
        X = motion(X0) if motion else (lambda t: X0)
        md.Init(s, list(X(0.0)), [0.0] * n)
        nsteps = int(round(duration / dt))
        if precompute:
            xs = [X(k * dt) for k in range(nsteps + 1)]
            calls = [(list(xs[k]), list((xs[k + 1] - xs[k]) / dt)) for k in range(nsteps)]
            t0 = clock()
            for k, (xk, vk) in enumerate(calls):
                f = md.Step(s, xk, vk, k * dt, dt)
            wall = clock() - t0
        else:
            t0 = clock()
            for k in range(nsteps):
                xk = X(k * dt)
                vk = (X((k + 1) * dt) - xk) / dt
                f = md.Step(s, list(xk), list(vk), k * dt, dt)
            wall = clock() - t0
        nodes = moordyn_nodes(md, s)
        md.Close(s)
    return wall, nodes, np.asarray(f)


def run_moorline(deck: Path, motion, duration, dt, mode, scheme=None, dtM=None):
    from moorline import System
    from moorline.motion import Trajectory

    s = System.from_file(deck, scheme=scheme, dtM=dtM)
    X0 = s.deck_coupled_positions()
    X = motion(X0) if motion else (lambda t: X0)
    s.init(X(0.0), np.zeros(s.n_coupled_dof))
    nsteps = int(round(duration / dt))
    t0 = time.perf_counter()
    if mode == "step":
        for k in range(nsteps):
            xk = X(k * dt)
            vk = (X((k + 1) * dt) - xk) / dt
            f = s.step(xk, vk, k * dt, dt)
    else:
        traj = Trajectory.from_function(X, nsteps * dt, dt, "linear")
        m = traj.as_motion()
        for k in range(1, int(round(duration)) + 1):
            s.advance_to(float(k), m)
        f = s.coupled_forces()
    wall = time.perf_counter() - t0
    nodes = int(s.layout.lines.node_ptr[-1])
    return wall, nodes, f, s


_FIRST_CALL = """
import time, sys
import numpy as np
t0 = time.perf_counter()
from moorline import System
s = System.from_file(sys.argv[1], scheme=sys.argv[2])
s.init(solve_ic=False)
s.step(s.deck_coupled_positions(), np.zeros(s.n_coupled_dof), 0.0, 0.01)
print(time.perf_counter() - t0)
"""


def compile_times(deck: Path, scheme: str) -> tuple[float, float]:
    """Wall time of a fresh process's first moorline call (import, read, one step) with an empty
    numba cache (everything compiled) and then with that cache filled (loaded from disk)."""
    import subprocess

    with tempfile.TemporaryDirectory(prefix="moorline_numba_cache_") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        times = []
        for _ in range(2):
            out = subprocess.run([sys.executable, "-c", _FIRST_CALL, str(deck), scheme], env=env, check=True,
                                 capture_output=True, text=True)
            times.append(float(out.stdout.strip().splitlines()[-1]))
    return times[0], times[1]


def finish_table(rows: list[str], out) -> None:
    """Print a markdown table after the rows printed as they came, and write it to ``out``."""
    table = "\n".join(rows)
    print()
    print(table)
    if out:
        Path(out).write_text(table + "\n")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cases", help="comma-separated subset")
    ap.add_argument("--no-compile-times", action="store_true", help="skip the cold/cached first-call measurement")
    a = ap.parse_args(argv)
    all_cases = cases()
    names = a.cases.split(",") if a.cases else list(all_cases)
    try:
        import moordyn  # noqa: F401
        have_md = True
    except ImportError:
        have_md = False
        print("moordyn is not installed: moorline timings only")

    # first call compiles (or loads the cache): timed apart, in fresh processes
    from moorline import System

    if not a.no_compile_times:
        for scheme in ("RK2", "GenAlpha"):
            cold, cached = compile_times(all_cases[names[0]][0], scheme)
            print(f"first call in a new process, {scheme}: {cold:.1f} s compiling (empty cache), {cached:.2f} s "
                  "with the cache")

    t0 = time.perf_counter()
    s = System.from_file(all_cases[names[0]][0])
    s.init(solve_ic=False)
    s.step(s.deck_coupled_positions(), np.zeros(s.n_coupled_dof), 0.0, 0.01)
    print(f"first moorline call (load + compile or cache): {time.perf_counter() - t0:.2f} s\n")

    head = (f"{'case':<26}{'nodes':>6} {'scheme':>6} {'dtM':>9} {'sim s':>6} {'code':>22} {'wall s':>8} "
            f"{'x real':>7} {'node-steps/s':>13} {'ratio':>6}")
    print(head)
    print("-" * len(head))
    for name in names:
        deck, motion, duration, dt = all_cases[name]
        md_wall = math.nan
        if have_md:
            md_times = []
            for _ in range(a.repeat):
                w, nodes_md, f_md = run_moordyn(deck, motion, duration, dt)
                md_times.append(w)
            md_wall = statistics.median(md_times)
        for mode in ("step", "advance"):
            times = []
            for _ in range(a.repeat):
                w, nodes, f, s = run_moorline(deck, motion, duration, dt, mode)
                times.append(w)
            wall = statistics.median(times)
            nsteps = duration / s.dtM
            label = "moorline step()" if mode == "step" else "moorline advance_to()"
            print(f"{name:<26}{nodes:>6} {s.scheme_label:>6} {s.dtM:>9.3g} {duration:>6g} {label:>22} {wall:>8.3f} "
                  f"{duration / wall:>7.1f} {nodes * nsteps / wall:>13.3g} {wall / md_wall:>6.2f}")
        if have_md:
            print(f"{name:<26}{nodes_md:>6} {s.scheme_label:>6} {s.dtM:>9.3g} {duration:>6g} {'MoorDyn Step()':>22} "
                  f"{md_wall:>8.3f} {duration / md_wall:>7.1f} {nodes_md * nsteps / md_wall:>13.3g} {1.0:>6.2f}")
            rel = np.max(np.abs(f - f_md)) / max(np.max(np.abs(f_md)), 1e-300) if f.size else 0.0
            print(f"{'':<26}final coupled force: max relative difference moorline/MoorDyn {rel:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
