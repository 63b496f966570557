"""How the cost grows with the size of the system: wall time per simulated second against the
number of line nodes, for moorline's explicit (RK2) and implicit (GenAlpha) paths and MoorDyn.

    python benchmarks/bench_scaling.py [--repeat 3] [--out benchmarks/scaling.md]

Systems: farms of OC3 three-line chain moorings (:mod:`make_farm`), from one turbine with 20
segments per line (63 nodes) to 20 turbines with 50 (3060 nodes), every fairlead in 5 m surge
(period 20 s, 20 s ramp). Explicit runs use the deck's dtM (2 ms) for moorline and MoorDyn alike,
outer coupling steps of 0.1 s; the implicit run uses GenAlpha with a 0.1 s step. Initial
conditions and compilation are excluded (compile time: bench_vs_moordyn.py). Besides the wall time
per simulated second, the table gives it per node, which is constant when the cost is linear in
the number of nodes.

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_vs_moordyn import finish_table, run_moordyn, run_moorline, sine_motion  # noqa: E402
from make_farm import write_farm  # noqa: E402

#: (turbines, segments per line): 63, 153, 612, 1530 and 3060 line nodes
SIZES = [(1, 20), (1, 50), (4, 50), (10, 50), (20, 50)]
DURATION = {"RK2": 10.0, "GenAlpha": 40.0}
IMPLICIT_DT = 0.1


def surge(X0):
    return sine_motion(X0, 5.0, 20.0, (1, 0, 0), 20.0)


def median_wall(fn, repeat):
    runs = [fn() for _ in range(repeat)]
    return statistics.median(r[0] for r in runs), runs[-1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None, help="also write the markdown table here")
    a = ap.parse_args(argv)
    try:
        import moordyn  # noqa: F401
        have_md = True
    except ImportError:
        have_md = False
    tmp = Path(tempfile.mkdtemp(prefix="moorline_scaling_"))
    rows = ["| nodes | code | scheme | dt [s] | simulated [s] | wall [s] | wall per simulated s [s] | "
            "per node [us] |", "|---|---|---|---|---|---|---|---|"]
    # compile (or load the cache) first
    deck0 = write_farm(tmp / "warm" / "farm.dat", 1, 20)
    run_moorline(deck0, surge, 1.0, 0.1, "advance")
    run_moorline(deck0, surge, 1.0, 0.1, "advance", scheme="GenAlpha", dtM=IMPLICIT_DT)
    for turbines, segs in SIZES:
        deck = write_farm(tmp / f"farm_{turbines}_{segs}" / "farm.dat", turbines, segs)
        runs = [("moorline", "RK2", None), ("moorline", "GenAlpha", IMPLICIT_DT)]
        if have_md:
            runs.insert(1, ("MoorDyn", "RK2", None))
        for code, scheme, dt in runs:
            dur = DURATION[scheme]
            if code == "MoorDyn":
                wall, (_, nodes, _) = median_wall(lambda: run_moordyn(deck, surge, dur, 0.1), a.repeat)  # noqa: B023
                dt_used = 0.002
            else:
                wall, (_, nodes, _, s) = median_wall(
                    lambda: run_moorline(deck, surge, dur, 0.1, "advance", scheme=scheme, dtM=dt),  # noqa: B023
                    a.repeat)
                dt_used = s.dtM
            per_s = wall / dur
            rows.append(f"| {nodes} | {code} | {scheme} | {dt_used:g} | {dur:g} | {wall:.3f} | {per_s:.4f} | "
                        f"{1e6 * per_s / nodes:.1f} |")
            print(rows[-1], flush=True)
    finish_table(rows, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
