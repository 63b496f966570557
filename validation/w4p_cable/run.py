"""The Waves4Power free-hanging power cable on its coupled buoy (Yang, Ringsberg & Johnson 2018,
J. Mar. Sci. Technol. 23:10-29; section 4 of issue 16), reproduced with moorline.

    python validation/w4p_cable/run.py [--quick] [--workers N] [--paper-length] [--no-sweep]

The buoy floats on Capytaine coefficients of an axisymmetric hull matching the paper's draft, mass
and centres (w4p.py), on four chains; the 70 m cable is clamped to a connector on the float's
side and to a fixed connector at the hub (54, 0, -1) m. Every scatter-diagram cell with Hs 0.5 to
7.5 m runs as the regular wave H = Hs/sqrt(2), T = Tz with the 1 m/s current, waves and current
toward -x. Each case: 120 s of transient (current and wave ramps, settling), then 5 periods
analysed (``--paper-length``: the paper's 1500 s with 900-1500 s analysed). Tensile stress at 12
points around the section, rainflow, the copper S-N curve, Miner, probability weighting; the first
two elements at each end excluded.

The cases run through the study runner's executor (:func:`moorline.studies.executors.run_local`,
local processes) with this study's own case function (:func:`w4p.run_case`).

Writes ``results.json`` and ``w4p_*.png`` beside this script; exits 1 when a check fails.
``--quick``: the two designs in the single condition Hs 3.5 m, Tz 7.5 s only (life_years then
covers that one cell only, marked partial).
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE  # where results.json and the figures go (--out)
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import common  # noqa: E402
import w4p  # noqa: E402

from moorline.post import SECONDS_PER_YEAR, ScatterDiagram  # noqa: E402
from moorline.studies.executors import run_local  # noqa: E402

HS_MAX = 7.5  # [m] the paper's simulated range; larger cells are survival mode
SINGLE = (3.5, 7.5)  # Hs [m], Tz [s] of the single-condition lives
SN_SLOPE = 6.238  # m of the copper S-N curve (w4p.SN), for scaling the damage of cells not run
PUBLISHED = {"single_condition_life_years": {"initial": 1.8e6, "improved": 6.7e9},
             "critical_location": "the third element from the WEC (s = 1.4-2.1 m)"}
#: the parametric sweep (mass [kg/m] x EI [N m^2] x length [m]), as examples/w4p_study
SWEEP = {"w": [2.00, 2.75, 6.00], "EI": [50.0, 200.0, 350.0], "L": [70.0, 82.0]}


class _Bar:
    def __init__(self, total):
        self.n, self.total, self.t0 = 0, total, time.perf_counter()

    def update(self, k):
        self.n += k
        print(f"    {self.n}/{self.total} cases, {time.perf_counter() - self.t0:.0f} s", flush=True)


CACHE = HERE / "out" / "cases"  # finished cases (git ignores out/): an interrupted run resumes


def case_key(spec) -> str:
    """Hash of everything that changes a case's answer (not the coefficients object itself: they
    follow from the hull dimensions, which are in the key) and of the model source."""
    import hashlib
    import json

    src = (HERE / "w4p.py").read_bytes()
    d = {"design": spec.design, "H": spec.H, "T": spec.T, "duration": spec.duration, "window": spec.window,
         "dtM": spec.dtM, "spp": spec.samples_per_period, "dims": spec.dims}
    return hashlib.sha256(json.dumps(d, sort_keys=True, default=float).encode() + src).hexdigest()[:20]


def run_all(specs, workers: int) -> list[dict]:
    """Run the cases on local worker processes (the study runner's executor); a failed case stops
    the study with its message. Finished cases are kept in ``out/cases`` and reused."""
    import pickle

    CACHE.mkdir(parents=True, exist_ok=True)
    done: dict[int, dict] = {}
    errors = []
    for s in specs:
        f = CACHE / f"{case_key(s)}.pkl"
        if f.exists():
            done[id(s)] = pickle.loads(f.read_bytes())
    pending = [s for s in specs if id(s) not in done]
    if len(pending) < len(specs):
        print(f"    {len(specs) - len(pending)} cases reused from {CACHE}", flush=True)

    def finished(spec, out):
        done[id(spec)] = out
        tmp = CACHE / f"{case_key(spec)}.part"
        tmp.write_bytes(pickle.dumps(out))
        tmp.replace(CACHE / f"{case_key(spec)}.pkl")

    def failed(spec, e):
        errors.append(f"{spec.label}: {type(e).__name__}: {e}")

    bar = _Bar(len(pending))
    if not pending:
        pass
    elif workers <= 1:
        for s in pending:
            try:
                finished(s, w4p.run_case(s))
            except Exception as e:  # reported with the others
                failed(s, e)
            bar.update(1)
    else:
        run_local(w4p.run_case, pending, workers, finished, failed, bar)
    if errors:
        raise RuntimeError("cases failed:\n  " + "\n  ".join(errors))
    return [done[id(s)] for s in specs]


def spec_for(design, Hs, Tz, *, quick, paper, coeffs, dims, label=""):
    T = Tz
    if paper:
        duration, window = 1500.0, 600.0
    else:
        n_per = 5
        # 120 s: after 90 s (the ramps end at 60 s) the cable's mid-span still settles: the change of a
        # node position over one period is 7.1 %, 2.4 %, 0.5 % of its range in the periods from 90,
        # 97.5 and 105 s (improved cable, Hs 3.5 m, Tz 7.5 s, measured), below 0.5 % after 105 s
        transient = 120.0
        window = n_per * T
        duration = transient + window
    return w4p.CaseSpec(dict(design), Hs / math.sqrt(2.0), T, label=label or f"Hs {Hs} Tz {Tz}", duration=duration,
                        window=window, dtM=min(0.1, T / 100.0), coefficients=coeffs, dims=dims)


def keep_mask(n_nodes: int) -> np.ndarray:
    k = np.arange(n_nodes)
    return (k >= w4p.EXCLUDE_ELEMENTS) & (k <= n_nodes - 1 - w4p.EXCLUDE_ELEMENTS)


def lifetime(outs: list[dict], probs: np.ndarray) -> dict:
    """Probability-weighted annual damage (node, theta), the critical location and the life."""
    rate = np.array([o["damage_rate"] for o in outs])  # (case, node, theta) [1/s]
    dmg = np.tensordot(probs, rate, axes=1) * SECONDS_PER_YEAR  # per year
    keep = keep_mask(dmg.shape[0])
    d = np.where(keep[:, None], dmg, 0.0)
    i, j = np.unravel_index(int(np.argmax(d)), d.shape)
    s = outs[0]["s"]
    return {"damage_per_year": dmg, "damage_max": float(d[i, j]), "life_years": 1.0 / float(d[i, j]),
            "critical_node": int(i), "critical_s_m": float(s[i]), "critical_theta_deg": float(outs[0]["theta"][j]),
            "critical_element": int(i) + 1}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="single condition only (CI)")
    ap.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1), help="local worker processes")
    ap.add_argument("--paper-length", action="store_true", help="1500 s per case, 900-1500 s analysed")
    ap.add_argument("--no-sweep", action="store_true", help="skip the parametric sweep (full mode)")
    ap.add_argument("--hs-min", type=float, default=0.0,
                    help="leave out the cells below this Hs [m] (their damage then counts as zero; say so)")
    ap.add_argument("--out", type=Path, default=None, help="folder for results.json and the figures (default: beside "
                    "this script)")
    a = ap.parse_args(argv)
    global OUT, CACHE
    OUT = a.out or HERE
    CACHE = OUT / "out" / "cases"
    OUT.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    started = time.perf_counter()
    scatter = ScatterDiagram.from_csv(common.shared_file("w4p_scatter.csv"))
    dims = w4p.hull_dimensions()
    coeffs = w4p.coefficients(dims)
    chk = common.Checks()
    if a.quick:
        cells = [(SINGLE[0], SINGLE[1], float(scatter.P[list(scatter.Hs).index(SINGLE[0]),
                                                        list(scatter.Tz).index(SINGLE[1])]))]
    else:
        cells = [(ss.Hs, ss.Tz, ss.probability) for ss in scatter.sea_states()
                 if ss.Hs <= HS_MAX and (ss.Hs >= a.hs_min or (ss.Hs, ss.Tz) == SINGLE)]
    missing = [(ss.Hs, ss.Tz, ss.probability) for ss in scatter.sea_states()
               if ss.Hs <= HS_MAX and not any((ss.Hs, ss.Tz) == (h, t) for h, t, _ in cells)]
    excluded = float(scatter.P[scatter.Hs > HS_MAX].sum())
    if not any(abs(h - SINGLE[0]) < 1e-9 and abs(t - SINGLE[1]) < 1e-9 for h, t, _ in cells):
        raise SystemExit("the single condition is not a cell of the scatter diagram")
    specs, index = [], []
    for name, design in w4p.DESIGNS.items():
        for Hs, Tz, p in cells:
            specs.append(spec_for(design, Hs, Tz, quick=a.quick, paper=a.paper_length, coeffs=coeffs, dims=dims,
                                  label=f"{name} Hs {Hs} Tz {Tz}"))
            index.append((name, Hs, Tz, p))
    sweep_designs = [] if a.quick or a.no_sweep else \
        [{"w": w, "EI": ei, "L": L} for w in SWEEP["w"] for ei in SWEEP["EI"] for L in SWEEP["L"]]
    sweep_specs = [spec_for(d, *SINGLE, quick=False, paper=a.paper_length, coeffs=coeffs, dims=dims,
                            label=f"sweep w {d['w']} EI {d['EI']} L {d['L']}") for d in sweep_designs]
    # one executor call; the single condition first, then the cells from the largest Hs down (the most
    # damaging first: an interrupted run has its cache of those), then the sweep
    order = sorted(range(len(specs)), key=lambda k: (not (index[k][1] == SINGLE[0] and index[k][2] == SINGLE[1]),
                                                    -index[k][1], index[k][2]))
    queue = [specs[k] for k in order[:2]] + [specs[k] for k in order[2:]] + sweep_specs
    print(f"W4P cable: {len(specs)} cases ({len(cells)} sea states x 2 designs) and {len(sweep_specs)} sweep designs "
          f"on {a.workers} workers", flush=True)
    t_cases = time.perf_counter()
    got = run_all(queue, a.workers)
    t_cases = time.perf_counter() - t_cases
    by_id = {id(q): o for q, o in zip(queue, got, strict=True)}
    outs = [by_id[id(sp)] for sp in specs]
    sw = [by_id[id(sp)] for sp in sweep_specs]

    res: dict = {"hull": dims, "cells": len(cells), "probability_simulated": float(sum(p for *_, p in cells)),
                 "probability_excluded_survival": excluded, "partial": bool(a.quick),
                 "case_settings": {"transient_s": specs[0].duration - specs[0].window, "dtM_s": "min(0.1, T/100)",
                                   "periods_analysed": "window / T", "paper_length": bool(a.paper_length)}}
    life, single, per = {}, {}, {}
    for name in w4p.DESIGNS:
        sel = [k for k, ix in enumerate(index) if ix[0] == name]
        o = [outs[k] for k in sel]
        probs = np.array([index[k][3] for k in sel])
        per[name] = {"outs": o, "probs": probs, "lt": lifetime(o, probs)}
        life[name] = per[name]["lt"]["life_years"]
        if missing and not a.quick:
            # cells left out (--hs-min): damage rate scaled from the computed cell of the same design and the
            # nearest Tz with the smallest Hs, as (Hs / Hs_ref)^m (linear response, S-N slope m)
            est = []
            for Hs, Tz, _ in missing:
                cands = [k for k in sel if index[k][1] >= a.hs_min]
                tz_near = min(cands, key=lambda k: (abs(index[k][2] - Tz), index[k][1]))
                ref = min((k for k in cands if index[k][2] == index[tz_near][2]), key=lambda k: index[k][1])
                est.append({**outs[ref], "damage_rate": outs[ref]["damage_rate"] * (Hs / index[ref][1]) ** SN_SLOPE})
            all_probs = np.concatenate([probs, [p for *_, p in missing]])
            per[name]["lt_estimated"] = lifetime(o + est, all_probs)
        k1 = next(k for k in sel if abs(index[k][1] - SINGLE[0]) < 1e-9 and abs(index[k][2] - SINGLE[1]) < 1e-9)
        single[name] = lifetime([outs[k1]], np.array([1.0]))
    lt0 = per["initial"]["lt"]
    clearance = min(o["min_clearance"] for o in outs)
    worst = min(outs, key=lambda o: o["min_clearance"])
    res["life_years"] = life
    if missing and not a.quick:
        res["life_years_note"] = (f"cells with Hs < {a.hs_min} m not run ({len(missing)} cells, probability "
                                  f"{sum(p for *_, p in missing):.3f}): life_years counts them as no damage (an upper "
                                  "bound); life_years_with_scaled_small_cells scales their damage from the computed "
                                  "cells as (Hs / Hs_ref)^m")
        res["life_years_with_scaled_small_cells"] = {k: per[k]["lt_estimated"]["life_years"] for k in per}
        res["cells_not_run"] = len(missing)
    res["single_condition_life_years"] = {k: v["life_years"] for k, v in single.items()}
    res["single_condition_critical_s_m"] = {k: v["critical_s_m"] for k, v in single.items()}
    res["critical_location_s_m"] = lt0["critical_s_m"]
    res["critical_element_from_wec"] = lt0["critical_element"]
    res["critical_theta_deg"] = lt0["critical_theta_deg"]
    res["critical_location_s_m_improved"] = per["improved"]["lt"]["critical_s_m"]
    res["min_clearance_to_buoy_m"] = clearance
    res["min_clearance_case"] = {"label": worst.get("label"), "node": worst["min_clearance_node"]}
    res["curvature_max_per_m"] = {k: float(max(np.max(np.where(keep_mask(o["curvature_max"].size),
                                                                   o["curvature_max"], 0)) for o in per[k]["outs"]))
                                  for k in per}
    res["tension_max_n"] = {k: float(max(np.max(o["tension_max"]) for o in per[k]["outs"])) for k in per}
    res["buoy"] = {"surge_mean_m": outs[0]["surge_mean"], "z_mean_m": outs[0]["z_mean"]}
    res["published"] = PUBLISHED
    for name in w4p.DESIGNS:
        chk.compare(f"single-condition life ({name})", single[name]["life_years"],
                    PUBLISHED["single_condition_life_years"][name], "Yang et al. 2018", note="README")
    chk.bound("the improved cable outlives the initial one in the single condition (the paper: by 3700 x)",
              single["improved"]["life_years"] / single["initial"]["life_years"], lo=1.0,
              why="the paper's design conclusion: lighter and more flexible is better")
    res["tension_min_n"] = min(float(np.min(o["tension_min"])) for o in outs)
    res["periodicity_worst"] = max(o["periodicity"] for o in outs)
    chk.bound("each analysed record is periodic (largest change of a node position over one period / its range)",
              res["periodicity_worst"], hi=0.05,
              why="the rainflow of a periodic record over whole periods needs the transient gone; 5 % of the range "
                  "changes the stress ranges by a few per cent at most")
    res["cable_z_min_m"] = min(o["cable_z_min"] for o in outs)
    chk.bound("the cable hangs free of the 50 m deep seabed (lowest node height)", res["cable_z_min_m"],
              lo=-w4p.DEPTH + 2 * w4p.CABLE["d"], why="the paper's free-hanging configuration")

    # the parametric sweep in the single condition
    if sweep_designs:
        res["sweep_single_condition"] = [{**d, "life_years": lifetime([o], np.array([1.0]))["life_years"],
                                          "critical_s_m": lifetime([o], np.array([1.0]))["critical_s_m"],
                                          "curvature_max_per_m": float(np.max(o["curvature_max"][
                                              keep_mask(o["curvature_max"].size)])),
                                          "min_clearance_m": o["min_clearance"]} for d, o in zip(sweep_designs, sw,
                                                                                                 strict=True)]
    res["case_time_s"] = {"total_wall": t_cases, "sum_of_cases": float(sum(o["wall_time_s"] for o in outs + sw))}
    res["hs_min_m"] = a.hs_min
    res["checks"], res["comparisons"], res["passed"] = chk.items, chk.comparisons, chk.passed
    out = common.write_results(OUT / "results.json", res, quick=a.quick, started=started)
    paths = figures(per, index, outs, res, a.quick)
    print(f"W4P cable ({out['mode']}, {out['wall_time_s']} s): hull float radius {dims['float_radius']:.2f} m, float "
          f"draft {dims['float_draft']:.2f} m, tube radius {dims['tube_radius']:.2f} m")
    for name in w4p.DESIGNS:
        print(f"  {name}: life {life[name]:.3g} years (critical s = {per[name]['lt']['critical_s_m']:.2f} m from the "
              f"WEC), single condition Hs {SINGLE[0]} Tz {SINGLE[1]}: {single[name]['life_years']:.3g} years (paper "
              f"{PUBLISHED['single_condition_life_years'][name]:.2g}) at s = {single[name]['critical_s_m']:.2f} m")
    print(f"  closest approach of the cable to the hull {clearance:.2f} m ({worst.get('label')})")
    print(chk.report())
    for p in paths:
        print(f"  wrote {p}")
    return 0 if chk.passed else 1


def figures(per, index, outs, res, quick) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 4.2))
    for name, c in zip(w4p.DESIGNS, ("tab:blue", "tab:orange"), strict=True):
        o = per[name]["outs"]
        s = o[0]["s"]
        ax1.plot(s, np.max([x["curvature_max"] for x in o], axis=0), color=c, label=f"{name}")
        d = per[name]["lt"]["damage_per_year"].max(axis=1)
        ax2.semilogy(s, np.maximum(d, 1e-30), color=c, label=f"{name}: life {per[name]['lt']['life_years']:.3g} y")
    for ax in (ax1, ax2):
        ax.axvspan(0, w4p.EXCLUDE_ELEMENTS * w4p.SEGMENT, color="0.9")
        ax.axvspan(70 - w4p.EXCLUDE_ELEMENTS * w4p.SEGMENT, 70, color="0.9")
        ax.set_xlabel("arc length from the WEC [m]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax2.axvspan(1.4, 2.1, color="tab:red", alpha=0.2, label="paper: critical (3rd element)")
    ax2.legend(fontsize=8)
    ax1.set_ylabel("largest curvature over the sea states [1/m]")
    ax2.set_ylabel("damage per year (largest around the section)")
    ax1.set_title("curvature envelopes (grey: excluded end elements)", fontsize=9)
    ax2.set_title("annual fatigue damage" + (" (single condition only)" if quick else ""), fontsize=9)
    fig.tight_layout()
    paths.append(OUT / "w4p_envelopes_damage.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4))
    names = list(w4p.DESIGNS)
    x = np.arange(len(names))
    ours = [res["single_condition_life_years"][n] for n in names]
    pub = [PUBLISHED["single_condition_life_years"][n] for n in names]
    ax.bar(x - 0.2, ours, 0.4, label="moorline (coupled buoy)")
    ax.bar(x + 0.2, pub, 0.4, label="Yang et al. 2018")
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{n} design" for n in names])
    ax.set_ylabel(f"life in the single condition Hs {SINGLE[0]} m, Tz {SINGLE[1]} s [years]")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    paths.append(OUT / "w4p_single_condition.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    if "sweep_single_condition" in res:
        sw = res["sweep_single_condition"]
        fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
        for ax, key, lab in zip(axes, ("w", "EI", "L"), ("mass [kg/m]", "EI [N m²]", "length [m]"), strict=True):
            for row in sw:
                ax.scatter(row[key], row["life_years"], color="tab:blue", s=14)
            ax.set_xlabel(lab)
            ax.set_yscale("log")
            ax.grid(alpha=0.3)
        axes[0].set_ylabel("single-condition life [years]")
        fig.suptitle("parametric sweep (18 designs) in the single condition", fontsize=10)
        fig.tight_layout()
        paths.append(OUT / "w4p_sweep.png")
        fig.savefig(paths[-1], dpi=90)
        plt.close(fig)
    return paths


if __name__ == "__main__":
    sys.exit(main())
