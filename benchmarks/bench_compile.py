"""First-run (numba compile) and cached start-up time, per deck feature.

    python benchmarks/bench_compile.py [--baseline-src PATH] [--repeat 1] [--out benchmarks/compile.md]

Each case is one ``moorline run`` in a fresh Python process (``python -m moorline.cli run ...``),
first with an empty numba cache (``NUMBA_CACHE_DIR`` set to a new temporary folder: everything the
run needs is compiled) and then again with that cache filled (everything is loaded). Wall time is
measured around the process; CPU time is the user + system time of the process, which on a
machine shared with other work is the steadier figure. ``--baseline-src`` names the ``src``
folder of another moorline (for instance an export of an older commit): each case then runs
baseline and current side by side, alternating, so both see the same machine load. The load
average of the machine (1 minute) is recorded before each case.

Cases (the simulated time is kept short except for the README example, so the figures are mostly
compile and start-up):

* README: the README's first command, 60 s of the three-leg catenary (RK2, lines and points);
* bending: a cable with bending stiffness, no rods (benchmarks/decks/bending_cable.dat, RK4);
* rods+bending: the WEC cable clamped to a rod (examples/wec_cable, RK4, dynamic relaxation);
* bodies: a free buoy (a body with a rod) on three chains (benchmarks/decks/buoy_body.dat);
* seabed grid: a chain on a bathymetry grid with stick-slip friction (examples/slope_friction);
* waves: the README catenary in a JONSWAP sea (``--waves``);
* GenAlpha: the README catenary with the implicit scheme (Newton statics, generalized-alpha);
* BEuler5: the README catenary with MoorDyn's fixed-point implicit scheme;
* floating: the two-body point absorber (examples/point_absorber/system.yaml: two floating bodies
  with state-space radiation, a joint with a PTO, Morison strips, JONSWAP excitation; RK2), 5 s;
  its Capytaine coefficients come from moorline's hydro cache (computed once, before the timing).

Cached start-up is a process that imports moorline, reads the README deck and makes one 0.01 s
step without initial conditions (import + deck + loading the time-loop kernels from the cache).

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"
DECKS = ROOT / "benchmarks" / "decks"
README_DECK = EX / "catenary_3line" / "catenary_3line.dat"
README_MOTION = EX / "catenary_3line" / "surge.csv"

#: (label, moorline run arguments)
CASES = [
    ("README example (60 s)", [str(README_DECK), "--duration", "60", "--motion", str(README_MOTION)]),
    ("bending (cable, EI)", [str(DECKS / "bending_cable.dat"), "--duration", "5"]),
    ("rods + bending (wec_cable)", [str(EX / "wec_cable" / "wec_cable.dat"), "--duration", "5", "--motion",
                                    str(EX / "wec_cable" / "buoy_motion.csv")]),
    ("bodies (free buoy)", [str(DECKS / "buoy_body.dat"), "--duration", "5"]),
    ("seabed grid + stick-slip", [str(EX / "slope_friction" / "slope_chain.dat"), "--duration", "5", "--motion",
                                  str(EX / "slope_friction" / "surge.csv")]),
    ("waves (JONSWAP)", [str(README_DECK), "--duration", "5", "--motion", str(README_MOTION), "--waves",
                         "jonswap:Hs=6,Tp=10,seed=1"]),
    ("implicit GenAlpha", [str(README_DECK), "--duration", "5", "--motion", str(README_MOTION), "--scheme",
                           "GenAlpha"]),
    ("fixed-point BEuler5", [str(README_DECK), "--duration", "5", "--motion", str(README_MOTION), "--scheme",
                             "BEuler5", "--dtM", "0.001"]),
    ("floating (point absorber)", [str(EX / "point_absorber" / "system.yaml"), "--duration", "5"]),
]

#: cached start-up: import, read the deck, one short step (loads the time-loop kernels)
_STARTUP = """
import sys, time
t0 = time.perf_counter()
import numpy as np
import moorline
s = moorline.System.from_file(sys.argv[1])
s.init(solve_ic=False)
s.step(s.deck_coupled_positions(), np.zeros(s.n_coupled_dof), 0.0, 0.01)
print(time.perf_counter() - t0)
"""


def loadavg() -> float:
    try:
        return float(Path("/proc/loadavg").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return float("nan")


def run_process(cmd: list[str], src: Path, cache: Path, out_dir: Path) -> tuple[float, float]:
    """(wall, cpu) seconds of one process running ``cmd`` with moorline from ``src``."""
    env = dict(os.environ, PYTHONPATH=str(src), NUMBA_CACHE_DIR=str(cache))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    res = subprocess.run(cmd, env=env, cwd=out_dir, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if res.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({res.returncode}):\n{res.stdout}\n{res.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def measure(label: str, cmd: list[str], src: Path, tmp: Path) -> dict:
    """Cold and cached (wall, cpu) of ``cmd`` with moorline from ``src``, with a new numba cache."""
    cache = Path(tempfile.mkdtemp(prefix="numba_cache_", dir=tmp))
    out = Path(tempfile.mkdtemp(prefix="out_", dir=tmp))
    load = loadavg()
    cold = run_process(cmd, src, cache, out)
    cached = run_process(cmd, src, cache, out)
    return {"label": label, "load": load, "cold": cold, "cached": cached}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline-src", type=Path, help="src folder of the moorline to compare with")
    ap.add_argument("--repeat", type=int, default=1, help="runs per case and code (the median is reported)")
    ap.add_argument("--cases", nargs="*", help="only the cases whose label starts with one of these")
    ap.add_argument("--out", default=None, help="also write the markdown table here")
    a = ap.parse_args(argv)
    codes = [("current", ROOT / "src")]
    if a.baseline_src:
        codes.insert(0, ("baseline", a.baseline_src.resolve()))
    cases = [c for c in CASES if not a.cases or any(c[0].startswith(p) for p in a.cases)]
    tmp = Path(tempfile.mkdtemp(prefix="moorline_bench_compile_"))
    py = sys.executable
    rows = ["| case | code | load | first run wall [s] | first run CPU [s] | cached run wall [s] | "
            "cached run CPU [s] |", "|---|---|---|---|---|---|---|"]

    def fmt(label, code, results):
        med = {k: tuple(statistics.median(r[k][i] for r in results) for i in range(2)) for k in ("cold", "cached")}
        load = statistics.median(r["load"] for r in results)
        row = (f"| {label} | {code} | {load:.1f} | {med['cold'][0]:.1f} | {med['cold'][1]:.1f} | "
               f"{med['cached'][0]:.1f} | {med['cached'][1]:.1f} |")
        print(row, flush=True)
        return row

    for label, args in cases:
        cmd = [py, "-m", "moorline.cli", "run", *args, "--out", "out", "--quiet-progress"]
        results = {code: [] for code, _ in codes}
        for _ in range(a.repeat):
            for code, src in codes:  # side by side: baseline, current, baseline, current, ...
                results[code].append(measure(label, cmd, src, tmp))
        for code, _ in codes:
            rows.append(fmt(label, code, results[code]))
    # cached start-up
    results = {code: [] for code, _ in codes}
    for _ in range(a.repeat):
        for code, src in codes:
            cache = Path(tempfile.mkdtemp(prefix="numba_cache_", dir=tmp))
            cmd = [py, "-c", _STARTUP, str(README_DECK)]
            run_process(cmd, src, cache, tmp)  # fills the cache
            load = loadavg()
            wall, cpu = run_process(cmd, src, cache, tmp)
            results[code].append((load, wall, cpu))
    for code, _ in codes:
        r = results[code]
        row = (f"| cached start-up (import, deck, load kernels) | {code} | {statistics.median(x[0] for x in r):.1f} | "
               f"- | - | {statistics.median(x[1] for x in r):.2f} | {statistics.median(x[2] for x in r):.2f} |")
        print(row, flush=True)
        rows.append(row)
    table = "\n".join(rows)
    print()
    print(table)
    if a.out:
        Path(a.out).write_text(table + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
