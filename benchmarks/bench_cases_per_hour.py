"""Many cases at once: cases per hour of a Waves4Power-style cable study on 1 and on N local
worker processes (issue 20).

    python benchmarks/bench_cases_per_hour.py [--cases 32] [--duration 90] [--workers 1,2] [--cold] [--quick]

The cases are those of ``validation/w4p_cable``: the W4P buoy floating on its Capytaine
coefficients, its four chains and the 70 m cable with bending stiffness (GenAlpha, dtM = T/100),
one cable design in one regular sea state per case, post-processed to fatigue damage along the
cable. They run through the executor the study runner uses
(:func:`moorline.studies.executors.run_local`: spawned worker processes, one case at a time per
worker), with that study's case function, shortened to ``--duration`` seconds simulated (the
study runs 120 s of transient and 5 periods). The designs cycle through the study's 18-design
sweep (mass x EI x length) and the sea states through five cells of the scatter diagram, so the
cases differ in cost as a real sweep's do.

Before the batches one case runs in this process: it compiles the kernels (or loads them from
numba's on-disk cache), so every batch starts from a warm cache shared by the worker processes
(the same ``__pycache__`` folders, or ``NUMBA_CACHE_DIR`` with ``--cold``, which every worker
inherits). ``--cold`` measures the one-off compile time first: the same case in a fresh process
with an empty cache (a temporary ``NUMBA_CACHE_DIR``), then again with it filled.

Reported per batch: wall time, cases per hour, speed-up over one worker, the pool's start-up and
shut-down; per worker process: the cases it ran, its busy time, how long it sat idle while
another finished the batch's last case, its first case's wall time against its others' median
(the first pays the imports and the cache load), and the number of numba compilations it did
(from numba's ``numba:compile`` events, which fire only when a kernel is compiled, not when it
is loaded from the cache): 0 means the cache was shared. Wall times: run it on a quiet machine
(the load average is printed; above about 1.5 on 2 cores the timings are not reliable).
Every process runs its BLAS single-threaded (``--blas-threads``): with OpenBLAS's threads a W4P
case spent up to 3.7 s of CPU instead of 0.9 s (its state-space fits' SVDs, 3.97 s against 0.045 s,
load 6-7), which would flatter the speed-up of more workers. ``--quick``: 4 cases of 10 s on 1
and 2 workers, a check that the script works (seconds, once compiled), not a measurement.
"""

from __future__ import annotations

import argparse
import atexit
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
W4P = ROOT / "validation" / "w4p_cable"
sys.path.insert(0, str(W4P.parent))
sys.path.insert(0, str(W4P))

_COMPILES = []  # the kernels numba compiled in this process (see _count_compiles)
#: (moorline.studies.executors.THREAD_VARIABLES, not imported: numpy must not be loaded before they are set)
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                    "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")
_FIRST = [True]

#: the study's sweep of cable designs (validation/w4p_cable/run.py SWEEP) and five scatter cells (Hs, Tz)
DESIGNS = [{"w": w, "EI": ei, "L": L} for w in (2.00, 2.75, 6.00) for ei in (50.0, 200.0, 350.0) for L in (70.0, 82.0)]
SEAS = [(3.5, 7.5), (1.5, 5.5), (2.5, 6.5), (4.5, 8.5), (0.5, 4.5)]


def case_specs(n: int, duration: float) -> list:
    """``n`` cases: design k % 18 in sea state k % 5, ``duration`` seconds each, the last two
    periods (at least one) analysed."""
    import w4p

    dims = w4p.hull_dimensions()
    coeffs = w4p.coefficients(dims)
    out = []
    for k in range(n):
        design = DESIGNS[k % len(DESIGNS)]
        Hs, Tz = SEAS[k % len(SEAS)]
        window = max(1, min(2, int(duration / 2 // Tz))) * Tz
        out.append(w4p.CaseSpec(dict(design), Hs / math.sqrt(2.0), Tz, label=f"case {k} w {design['w']} EI "
                                f"{design['EI']:g} L {design['L']:g} Hs {Hs} Tz {Tz}", duration=duration,
                                window=window, dtM=min(0.1, Tz / 100.0), coefficients=coeffs, dims=dims))
    return out


def _count_compiles() -> None:
    """Count numba's ``numba:compile`` events in this process: one per kernel compiled (a kernel
    loaded from the on-disk cache fires none). Registered on the first case, after the process
    has read ``NUMBA_CACHE_DIR`` (numba reads it once, when first imported)."""
    from numba.core import event

    class Counter(event.Listener):
        def on_start(self, ev):
            _COMPILES.append(ev.data["dispatcher"].py_func.__qualname__)

        def on_end(self, ev):
            pass

    event.register("numba:compile", Counter())


def timed_case(spec) -> dict:
    """Run one case in this (worker) process; return its result with the worker's bookkeeping."""
    import cells

    first = _FIRST[0]
    _FIRST[0] = False
    if first:
        _count_compiles()
    n0 = len(_COMPILES)
    t0, c0 = time.time(), time.process_time()
    out = cells.run_unless_late(spec)
    return {"pid": os.getpid(), "first": first, "start": t0, "end": time.time(), "cpu": time.process_time() - c0,
            "compiles": len(_COMPILES) - n0, "cache_dir": _cache_dir(), "label": spec.label,
            "damage_rate_max": float(out["damage_rate"].max()), "tension_max": float(out["tension_max"].max()),
            "scheme": out.get("scheme_used", "")}


def _cache_dir() -> str:
    from numba.core import config

    return config.CACHE_DIR or "__pycache__ beside the sources"


def run_batch(specs: list, workers: int) -> dict:
    """All cases through :func:`moorline.studies.executors.run_local` on ``workers`` processes
    (``workers == 1``: still one spawned worker, so that it pays what each worker pays)."""
    from moorline.studies.executors import run_local

    got, errors = [], []

    class Bar:
        def update(self, k):
            pass

    t0 = time.time()
    run_local(timed_case, specs, workers, lambda s, r: got.append(r), lambda s, e: errors.append(f"{s.label}: {e}"),
              Bar())
    t1 = time.time()
    if errors:
        raise SystemExit("cases failed:\n  " + "\n  ".join(errors))
    last = max(r["end"] for r in got)  # the batch's last case done (then the pool shuts down: t1)
    per = {}
    for r in got:
        per.setdefault(r["pid"], []).append(r)
    rows = []
    for pid, rs in sorted(per.items(), key=lambda kv: min(r["start"] for r in kv[1])):
        rs.sort(key=lambda r: r["start"])
        walls = [r["end"] - r["start"] for r in rs]
        rows.append({"pid": pid, "cases": len(rs), "busy": sum(walls), "cpu": sum(r["cpu"] for r in rs),
                     "idle_end": last - rs[-1]["end"], "first": walls[0],
                     "others_median": statistics.median(walls[1:]) if len(walls) > 1 else math.nan,
                     "compiles": sum(r["compiles"] for r in rs), "cache_dir": rs[0]["cache_dir"]})
    return {"workers": workers, "wall": t1 - t0, "cases": len(got), "per_worker": rows, "shutdown": t1 - last,
            "startup": min(r["start"] for r in got) - t0,
            "results": {r["label"]: (r["damage_rate_max"], r["tension_max"]) for r in got}}


def cold_compile(duration: float) -> dict:
    """The one-off compile: one case in a fresh process with an empty NUMBA_CACHE_DIR, then again
    (a second fresh process) with that cache filled. The batches then use that cache; it is removed
    when this process ends."""
    cache = tempfile.mkdtemp(prefix="moorline_numba_cache_")
    atexit.register(shutil.rmtree, cache, ignore_errors=True)  # after the batches (their workers have ended)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    out = []
    for _ in range(2):
        p = subprocess.run([sys.executable, __file__, "--one-case", "--duration", repr(duration)], env=env,
                           capture_output=True, text=True, check=True)
        out.append(json.loads(p.stdout.strip().splitlines()[-1]))
    os.environ["NUMBA_CACHE_DIR"] = cache  # this process (numba not imported yet) and the workers use it
    return {"cache_dir": cache, "empty_cache": out[0], "filled_cache": out[1]}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=32)
    ap.add_argument("--duration", type=float, default=90.0, help="simulated seconds per case")
    ap.add_argument("--workers", default="1,2", help="comma-separated worker counts to run the batch on")
    ap.add_argument("--cold", action="store_true", help="measure the one-off compile (an empty numba cache first)")
    ap.add_argument("--quick", action="store_true", help="4 cases of 10 s: checks the script, measures nothing")
    ap.add_argument("--blas-threads", type=int, default=1, help="threads of each process's BLAS/OpenMP (default 1: "
                    "every batch runs the same single-threaded cases; the study runner gives each worker its share "
                    "of the CPUs, so 2 threads with 1 worker on 2 cores)")
    ap.add_argument("--one-case", action="store_true", help=argparse.SUPPRESS)  # (what --cold runs in a new process)
    a = ap.parse_args(argv)
    for k in THREAD_VARIABLES:  # before numpy is imported here, and inherited by the workers
        os.environ.setdefault(k, str(a.blas_threads))
    if a.one_case:
        t, c = time.perf_counter(), time.process_time()
        r = timed_case(case_specs(1, a.duration)[0])
        print(json.dumps({"wall": time.perf_counter() - t, "cpu": time.process_time() - c, "compiles": r["compiles"]}))
        return 0
    if a.quick:
        a.cases, a.duration = 4, 10.0
    workers = [int(w) for w in a.workers.split(",")]
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} CPUs"
          + ("  (above 1.5: timings unreliable)" if load[0] > 1.5 else ""), flush=True)
    if a.cold:
        if "numba" in sys.modules:
            raise RuntimeError("numba was imported before NUMBA_CACHE_DIR was set")
        cc = cold_compile(a.duration)
        e, f = cc["empty_cache"], cc["filled_cache"]
        print(f"one-off compile: first case in a new process {e['wall']:.1f} s wall, {e['cpu']:.1f} s CPU with an "
              f"empty cache ({e['compiles']} kernels compiled), {f['wall']:.1f} s wall, {f['cpu']:.1f} s CPU with it "
              f"filled ({f['compiles']} compiled): compile {e['wall'] - f['wall']:.1f} s wall, "
              f"{e['cpu'] - f['cpu']:.1f} s CPU (NUMBA_CACHE_DIR={cc['cache_dir']})", flush=True)
    specs = case_specs(a.cases, a.duration)
    t = time.perf_counter()
    warm = timed_case(specs[0])
    print(f"warm-up case in this process: {time.perf_counter() - t:.1f} s, {warm['compiles']} kernels compiled "
          f"(cache: {_cache_dir()})", flush=True)
    print(f"{a.cases} cases of {a.duration:g} s simulated (W4P buoy, chains and cable, GenAlpha); BLAS threads "
          f"per process: {os.environ['OPENBLAS_NUM_THREADS']}", flush=True)
    base = None
    ref = None
    for n in workers:
        b = run_batch(specs, n)
        rate = b["cases"] / b["wall"] * 3600.0
        base = base or (b["wall"] if n == 1 else None)
        speed = f", speed-up {base / b['wall']:.2f}x over 1 worker" if base else ""
        print(f"\nworkers {n}: {b['cases']} cases in {b['wall']:.1f} s wall: {rate:.0f} cases/hour{speed}", flush=True)
        print(f"  {'worker pid':>10} {'cases':>5} {'busy s':>7} {'cpu s':>7} {'idle at end s':>13} "
              f"{'first case s':>12} {'others median s':>15} {'compiles':>8}")
        for r in b["per_worker"]:
            print(f"  {r['pid']:>10} {r['cases']:>5} {r['busy']:>7.1f} {r['cpu']:>7.1f} {r['idle_end']:>13.1f} "
                  f"{r['first']:>12.1f} {r['others_median']:>15.1f} {r['compiles']:>8}")
        print(f"  cache: {b['per_worker'][0]['cache_dir']}; pool start-up to first case "
              f"{b['startup']:.1f} s, shut-down {b['shutdown']:.1f} s")
        if ref is None:
            ref = b["results"]
        elif b["results"] != ref:
            print("  RESULTS DIFFER from the first batch's", flush=True)
            return 1
    print("\nresults (largest damage rate and tension of each case) identical across the batches", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
