"""Initial conditions: moorline's Newton statics against MoorDyn's initial-condition solve.

    python benchmarks/bench_init.py [--repeat 3] [--out benchmarks/init.md]

For each deck, the wall time from reading the deck to a system at rest in equilibrium, and the
fairlead tensions found:

- MoorDyn: ``MoorDyn_Create`` + ``MoorDyn_Init`` with the deck's own options (its stationary
  solver or dynamic relaxation, TmaxIC, threshIC);
- moorline with the same method (``ICNewton 0``);
- moorline with Newton statics (``ICNewton 1``, pseudo-transient continuation, with implicit
  dynamic relaxation first when Newton stalls on a slack system).

"diff vs MoorDyn" is the largest fairlead-tension difference over the largest fairlead tension.
The kernels are compiled (or loaded from the cache) before anything is timed.

Not part of the test suite: timings depend on the machine and on what else runs on it.
"""

from __future__ import annotations

import argparse
import logging
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_vs_moordyn import CONF, ROOT, finish_table, moordyn_copy, moordyn_coupled_points  # noqa: E402
from make_farm import write_farm  # noqa: E402


def decks() -> dict[str, Path]:
    out = {}
    if CONF.exists():
        out["catenary_3line (OC3)"] = CONF / "inputs/catenary_3line/lines.txt"
    out["semitaut_chain_polyester"] = ROOT / "benchmarks/decks/semitaut_chain_polyester.dat"
    out["lazy_wave_cable"] = ROOT / "benchmarks/decks/lazy_wave_cable.dat"
    out["farm_20x3_lines"] = write_farm(Path(tempfile.mkdtemp(prefix="moorline_farm_")) / "farm.dat")
    return out


def moordyn_init(deck: Path):
    import moordyn as md

    with moordyn_copy(deck):
        t0 = time.perf_counter()
        s = md.Create(deck.name)
        n = md.NCoupledDOF(s)
        points = moordyn_coupled_points(md, s)
        md.Init(s, [x for P in points for x in md.GetPointPos(P)], [0.0] * n)
        wall = time.perf_counter() - t0
        ten = [np.linalg.norm(md.GetPointForce(P)) for P in points]
        md.Close(s)
    return wall, np.asarray(ten)


def moorline_init(deck: Path, newton: int):
    from moorline import System
    from moorline.io import read_deck

    t0 = time.perf_counter()
    model = read_deck(deck)
    model.options.ICNewton = newton
    s = System(model)
    s.init(s.deck_coupled_positions(), np.zeros(s.n_coupled_dof))
    wall = time.perf_counter() - t0
    ten = np.linalg.norm(s.coupled_forces().reshape(-1, 3), axis=1)
    return wall, ten, dict(s.ic_report)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.ERROR)
    try:
        import moordyn  # noqa: F401
        have_md = True
    except ImportError:
        have_md = False
    all_decks = decks()
    moorline_init(next(iter(all_decks.values())), 1)  # compile or load the cache
    rows = ["| deck | code | method | wall [s] | result | diff vs MoorDyn |", "|---|---|---|---|---|---|"]
    for name, deck in all_decks.items():
        ref = None
        if have_md:
            runs = [moordyn_init(deck) for _ in range(a.repeat)]
            ref = runs[-1][1]
            rows.append(f"| {name} | MoorDyn | deck's own | {statistics.median(r[0] for r in runs):.3f} | - | - |")
            print(rows[-1], flush=True)
        for newton, label in ((0, "deck's own (ICNewton 0)"), (1, "Newton statics (ICNewton 1)")):
            try:
                runs = [moorline_init(deck, newton) for _ in range(a.repeat)]
            except Exception as e:  # a method that fails is reported, not fatal
                rows.append(f"| {name} | moorline | {label} | - | failed: {str(e)[:60]} | - |")
                print(rows[-1], flush=True)
                continue
            rep = runs[-1][2]
            what = rep.get("method", "?")
            if "iterations" in rep:
                what += f", {rep['iterations']} iterations"
            if rep.get("converged") is False:
                what += ", not converged"
            diff = "-"
            ten = runs[-1][1]
            if ref is not None and ref.size == ten.size:
                diff = f"{np.max(np.abs(ten - ref)) / np.max(np.abs(ref)):.1e}"
            rows.append(f"| {name} | moorline | {label} | {statistics.median(r[0] for r in runs):.3f} | {what} | "
                        f"{diff} |")
            print(rows[-1], flush=True)
    finish_table(rows, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
