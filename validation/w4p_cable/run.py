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
import functools
import logging
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
OUT = HERE  # where results.json and the figures go (--out)
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

import cells  # noqa: E402
import common  # noqa: E402
import w4p  # noqa: E402

from moorline.post import SECONDS_PER_YEAR, ScatterDiagram  # noqa: E402
from moorline.studies.executors import run_dask, run_local  # noqa: E402

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


OLD_CACHE = HERE / "out" / "cases"  # the earlier, uncommitted pickle cache (see migrate_old_cache)


def migrate_old_cache(cases, fingerprint) -> int:
    """Move cases finished by the earlier version of this script (pickles in ``out/cases``, keyed by
    the raw bytes of ``w4p.py``) into the committed cell store, when ``w4p.py`` is byte for byte the
    file that made them and the case's parameters are the same."""
    import hashlib
    import json
    import pickle

    if not OLD_CACHE.is_dir():
        return 0
    src = (HERE / "w4p.py").read_bytes()
    n = 0
    for c in cases:
        sp = c["spec"]
        if cells.read(sp, c["Hs"], c["Tz"], fingerprint) is not None:
            continue
        d = {"design": sp.design, "H": sp.H, "T": sp.T, "duration": sp.duration, "window": sp.window,
             "dtM": sp.dtM, "spp": sp.samples_per_period, "dims": sp.dims}
        k = hashlib.sha256(json.dumps(d, sort_keys=True, default=float).encode() + src).hexdigest()[:20]
        f = OLD_CACHE / f"{k}.pkl"
        if f.exists():
            cells.write(pickle.loads(f.read_bytes()), sp, c["Hs"], c["Tz"], fingerprint)
            n += 1
    return n


def run_cases(pending, *, workers: int, scheduler, deadline, store, fingerprint) -> tuple[dict, list, int]:
    """Run the pending cases through the study runner's executors (local spawned processes, or a
    Dask cluster), storing each in the cell store as it finishes (``store``: the cells' root, or
    None to keep them in memory only). Cases a worker picks up after ``deadline`` are not run.

    Returns the results by case index, the failures and the number left for a later run."""
    done: dict[int, dict] = {}
    errors: list[str] = []
    late = [0]
    by_spec = {id(c["spec"]): c for c in pending}

    def finished(spec, out):
        c = by_spec[id(spec)]
        if out is None:
            late[0] += 1
            return
        if store is not None:
            cells.write(out, spec, c["Hs"], c["Tz"], fingerprint, root=store)
        done[c["i"]] = out

    def failed(spec, e):
        errors.append(f"{spec.label}: {type(e).__name__}: {e}")

    if not pending:
        return done, errors, 0
    runner = functools.partial(cells.run_unless_late, deadline=deadline)
    specs = [c["spec"] for c in pending]
    bar = _Bar(len(specs))
    if scheduler:
        run_dask(runner, specs, scheduler, finished, failed, bar)
    else:
        run_local(runner, specs, max(1, workers), finished, failed, bar)
    return done, errors, late[0]



def spec_for(design, Hs, Tz, *, quick, paper, coeffs, dims, label="", yaw_damping=w4p.YAW_DAMPING):
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
                        window=window, dtM=min(0.1, T / 100.0), coefficients=coeffs, dims=dims,
                        yaw_damping=yaw_damping)


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


def priority(c) -> float:
    """The order of the runs: the cell's probability x Hs^m, its expected share of the damage for a
    response linear in the wave height (the S-N slope m)."""
    return c["p"] * c["Hs"] ** SN_SLOPE


def missing_cells(avail: list[dict], missing: list[dict]) -> dict:
    """What the cells not yet run can add to the damage, from the cells that were.

    ``bound``: each missing cell's damage rate taken equal to that of the run cell of the same Tz
    with the next larger Hs (damage grows with the wave height at a fixed period): an upper bound
    where such a cell exists (``unbounded`` lists the others). ``scaled``: each missing cell scaled
    from the run cell nearest in Tz, then in Hs, as (Hs / Hs_ref)^m (a linear response): an estimate.
    """
    bound, scaled, unbounded = [], [], []
    for c in missing:
        same = [a for a in avail if abs(a["Tz"] - c["Tz"]) < 1e-9]
        above = [a for a in same if a["Hs"] >= c["Hs"] - 1e-9]
        if above:
            ref = min(above, key=lambda a: a["Hs"])
            bound.append((c["p"], ref["out"]["damage_rate"]))
        else:
            unbounded.append(c)
        ref = min(avail, key=lambda a: (abs(a["Tz"] - c["Tz"]), abs(a["Hs"] - c["Hs"])))
        scaled.append((c["p"], ref["out"]["damage_rate"] * (c["Hs"] / ref["Hs"]) ** SN_SLOPE))
    return {"bound": bound, "scaled": scaled, "unbounded": unbounded}


def annual(pairs) -> np.ndarray:
    """Annual damage (node, theta) of (probability, damage rate [1/s]) pairs."""
    return sum(p * r for p, r in pairs) * SECONDS_PER_YEAR


def life_of(dmg: np.ndarray) -> float:
    keep = keep_mask(dmg.shape[0])
    return 1.0 / float(np.max(np.where(keep[:, None], dmg, 0.0)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="single condition only, run afresh (CI)")
    ap.add_argument("--workers", type=int, default=1, help="local worker processes (default 1)")
    ap.add_argument("--scheduler", default=None, help="a Dask scheduler address: run the cases on that cluster")
    ap.add_argument("--paper-length", action="store_true", help="1500 s per case, 900-1500 s analysed")
    ap.add_argument("--yaw-damping", type=float, default=w4p.YAW_DAMPING, metavar="N_M_S_PER_RAD",
                    help=f"linear yaw damping of the buoy (default {w4p.YAW_DAMPING:g}, README 'Yaw damping'; 0: the "
                    "undamped buoy, whose yaw is unstable in long runs); another value keeps its own cell store")
    ap.add_argument("--no-sweep", action="store_true", help="skip the parametric sweep (full mode)")
    ap.add_argument("--no-scatter", action="store_true", help="run only the single condition and the sweep; the "
                    "scatter life is assembled from the cells already stored")
    ap.add_argument("--stop-after", type=float, default=None, metavar="SECONDS",
                    help="start no case after this many seconds; the rest stay pending for the next run")
    ap.add_argument("--assemble-only", action="store_true", help="run nothing: assemble from the stored cells")
    ap.add_argument("--fresh", action="store_true", help="ignore the stored cells (re-run and overwrite them)")
    ap.add_argument("--out", type=Path, default=None, help="folder for results.json and the figures (default: beside "
                    "this script; the cells always go to cells/ beside it)")
    a = ap.parse_args(argv)
    global OUT
    OUT = a.out or HERE
    OUT.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    started = time.perf_counter()
    deadline = None if a.stop_after is None else time.time() + a.stop_after
    scatter = ScatterDiagram.from_csv(common.shared_file("w4p_scatter.csv"))
    dims = w4p.hull_dimensions()
    coeffs = w4p.coefficients(dims)
    fingerprint = cells.model_fingerprint()
    chk = common.Checks()
    in_range = [(ss.Hs, ss.Tz, ss.probability) for ss in scatter.sea_states() if ss.Hs <= HS_MAX]
    excluded = float(scatter.P[scatter.Hs > HS_MAX].sum())
    if not any(abs(h - SINGLE[0]) < 1e-9 and abs(t - SINGLE[1]) < 1e-9 for h, t, _ in in_range):
        raise SystemExit("the single condition is not a cell of the scatter diagram")
    wanted = [c for c in in_range if (c[0], c[1]) == SINGLE] if a.quick else in_range

    # every distinct case (a design in a sea state), the scatter's and the sweep's
    cases: dict[tuple, dict] = {}

    def case(name, design, Hs, Tz, p):
        k = (cells.design_name(design), Hs, Tz)
        if k not in cases:
            cases[k] = {"i": len(cases), "name": name, "design": dict(design), "Hs": Hs, "Tz": Tz, "p": p,
                        "spec": spec_for(design, Hs, Tz, quick=a.quick, paper=a.paper_length, coeffs=coeffs,
                                         dims=dims, label=f"{name} Hs {Hs} Tz {Tz}", yaw_damping=a.yaw_damping)}
        return cases[k]

    scat = {name: [case(name, design, Hs, Tz, p) for Hs, Tz, p in wanted] for name, design in w4p.DESIGNS.items()}
    sweep_designs = [] if a.quick or a.no_sweep else \
        [{"w": w, "EI": ei, "L": L} for w in SWEEP["w"] for ei in SWEEP["EI"] for L in SWEEP["L"]]
    sweep = [case("sweep " + cells.design_name(d), d, *SINGLE, None) for d in sweep_designs]

    # the paper-length cases have their own store (the same cell under another run length is another case)
    root = cells.CELLS_PAPER if a.paper_length else cells.CELLS
    if a.yaw_damping != w4p.YAW_DAMPING:  # another buoy: its own store, the committed cells stay as they are
        root = root.with_name(f"{root.name}_yaw{a.yaw_damping:g}")
    store = None if a.quick else root
    results: dict[int, dict] = {}
    if not a.quick and not a.fresh:
        moved = 0 if a.paper_length else migrate_old_cache(list(cases.values()), fingerprint)
        if moved:
            print(f"    {moved} cases moved from {OLD_CACHE} into {cells.CELLS}", flush=True)
        for c in cases.values():
            r = cells.read(c["spec"], c["Hs"], c["Tz"], fingerprint, root=root)
            if r is not None:
                results[c["i"]] = {**r, "label": c["spec"].label}
    single = [c for c in cases.values() if (c["Hs"], c["Tz"]) == SINGLE and c["name"] in w4p.DESIGNS]
    first = {c["i"] for c in single}
    swept = {c["i"] for c in sweep}
    pending = [c for c in cases.values() if c["i"] not in results and not a.assemble_only]
    if a.no_scatter:
        pending = [c for c in pending if c["i"] in first | swept]
    # the order: the single condition, the sweep, then the scatter by expected damage (both designs
    # of a cell together): an interrupted run has the cells that matter most
    pending.sort(key=lambda c: (c["i"] not in first, c["i"] not in swept, -(priority(c) if c["p"] else 0.0),
                                c["name"]))
    print(f"W4P cable: {len(cases)} distinct cases ({len(wanted)} sea states x 2 designs, {len(sweep)} sweep "
          f"designs), {len(results)} stored, {len(pending)} to run on "
          f"{a.scheduler or f'{a.workers} local worker(s)'}", flush=True)
    t_cases = time.perf_counter()
    got, errors, late = run_cases(pending, workers=a.workers, scheduler=a.scheduler, deadline=deadline, store=store,
                                  fingerprint=fingerprint)
    t_cases = time.perf_counter() - t_cases
    results.update(got)
    if errors:
        print("cases failed (the others are stored):\n  " + "\n  ".join(errors), flush=True)
    for c in single:
        if c["i"] not in results:
            raise SystemExit(f"the single condition of the {c['name']} design has not run: nothing to assemble")

    res: dict = {"hull": dims, "probability_excluded_survival": excluded, "model_fingerprint": fingerprint,
                 "case_settings": {"transient_s": single[0]["spec"].duration - single[0]["spec"].window,
                                   "dtM_s": "min(0.1, T/100)", "periods_analysed": "window / T",
                                   "scheme": "GenAlpha", "paper_length": bool(a.paper_length),
                                   "yaw_damping_n_m_s_per_rad": float(a.yaw_damping)}}
    life, life_lo, life_est, single_lt, per, coverage = {}, {}, {}, {}, {}, {}
    p_range = float(sum(p for *_, p in in_range))
    for name in w4p.DESIGNS:
        avail = [{**c, "out": results[c["i"]]} for c in scat[name] if c["i"] in results]
        miss = [c for c in scat[name] if c["i"] not in results]
        outs = [x["out"] for x in avail]
        lt = lifetime(outs, np.array([x["p"] for x in avail]))
        per[name] = {"outs": outs, "lt": lt, "avail": avail}
        life[name] = lt["life_years"]
        cov = {"cells_in_range": len(in_range), "cells_run": len(avail),
               "probability_in_range": p_range, "probability_run": float(sum(x["p"] for x in avail))}
        cov["probability_run_fraction_of_range"] = cov["probability_run"] / p_range
        if miss and not a.quick:
            mb = missing_cells(avail, miss)
            d_run = lt["damage_per_year"]
            d_bound = d_run + annual(mb["bound"]) if mb["bound"] else d_run
            d_est = d_run + annual(mb["scaled"])
            life_lo[name] = life_of(d_bound)
            life_est[name] = life_of(d_est)
            i, j = lt["critical_node"], int(np.argmax(lt["damage_per_year"][lt["critical_node"]]))
            cov["missing_share_of_damage_bound"] = float(1.0 - d_run[i, j] / d_bound[i, j])
            cov["missing_share_of_damage_scaled"] = float(1.0 - d_run[i, j] / d_est[i, j])
            cov["cells_missing"] = len(miss)
            cov["cells_missing_without_bound"] = [f"Hs {c['Hs']:g} Tz {c['Tz']:g}" for c in mb["unbounded"]]
            cov["probability_missing_without_bound"] = float(sum(c["p"] for c in mb["unbounded"]))
        coverage[name] = cov
        c1 = next(c for c in single if c["name"] == name)
        single_lt[name] = lifetime([results[c1["i"]]], np.array([1.0]))
    complete = all(coverage[n]["cells_run"] == len(in_range) for n in w4p.DESIGNS)
    res["partial"] = bool(a.quick or not complete)
    res["life_years"] = life
    res["scatter_coverage"] = coverage
    if life_lo:
        res["life_years_note"] = ("life_years counts the cells not run as no damage (an upper bound on the life); "
                                  "life_years_lower_bound gives each missing cell the damage rate of the run cell of "
                                  "the same Tz and the next larger Hs (damage grows with the wave height at a fixed "
                                  "period; cells with no such run cell are listed in scatter_coverage and left out); "
                                  "life_years_scaled_estimate scales the nearest run cell as (Hs / Hs_ref)^m")
        res["life_years_lower_bound"] = life_lo
        res["life_years_scaled_estimate"] = life_est
    lt0 = per["initial"]["lt"]
    outs = per["initial"]["outs"] + per["improved"]["outs"]
    clearance = min(o["min_clearance"] for o in outs)
    worst = min(outs, key=lambda o: o["min_clearance"])
    res["single_condition_life_years"] = {k: v["life_years"] for k, v in single_lt.items()}
    res["single_condition_critical_s_m"] = {k: v["critical_s_m"] for k, v in single_lt.items()}
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
    s0 = results[single[0]["i"]]
    res["buoy_single_condition"] = {"surge_mean_m": s0["surge_mean"], "z_mean_m": s0["z_mean"],
                                    "heave_range_m": s0["heave_range"]}
    res["published"] = PUBLISHED
    for name in w4p.DESIGNS:
        chk.compare(f"single-condition life ({name})", single_lt[name]["life_years"],
                    PUBLISHED["single_condition_life_years"][name], "Yang et al. 2018", note="README")
    chk.bound("the improved cable outlives the initial one in the single condition (the paper: by 3700 x)",
              single_lt["improved"]["life_years"] / single_lt["initial"]["life_years"], lo=1.0,
              why="the paper's design conclusion: lighter and more flexible is better")
    if a.quick:
        # the committed cell of the single condition, made from the same inputs, is reproduced
        for c in single:
            ref = cells.read(c["spec"], c["Hs"], c["Tz"], fingerprint, root=root)
            if ref is None:
                print(f"    (no committed cell of the {c['name']} design's single condition with these inputs: "
                      "not compared)", flush=True)
                continue
            chk.bound(f"the {c['name']} design's single-condition life reproduces its committed cell "
                      f"({ref['cell_file']}; ratio)",
                      single_lt[c["name"]]["life_years"] / lifetime([ref], np.array([1.0]))["life_years"],
                      lo=0.99, hi=1.01, why="same inputs and model; 1 % allows another machine's floating point "
                                            "in an implicit time integration with Newton iterations")
    allouts = list(results.values())
    res["tension_min_n"] = min(float(np.min(o["tension_min"])) for o in allouts)
    res["periodicity_worst"] = max(o["periodicity"] for o in allouts)
    # the periodicity check is on the records that set a life: every case but the scatter cells whose
    # share of their design's damage (at its critical point) is below SHARE_MIN. In the smallest waves
    # (Hs 0.5 m) the cable's slow settling after the current ramp is a larger part of a tiny range.
    SHARE_MIN = 1e-3
    minor, minor_sum = {}, {}
    for name in w4p.DESIGNS:
        minor_sum[name] = 0.0
        lt = per[name]["lt"]
        i = lt["critical_node"]
        j = int(np.argmax(lt["damage_per_year"][i]))
        for x in per[name]["avail"]:
            share = x["p"] * x["out"]["damage_rate"][i, j] * SECONDS_PER_YEAR / lt["damage_per_year"][i, j]
            if share < SHARE_MIN and x["i"] not in first:
                minor[x["i"]] = (share, x["out"])
                minor_sum[name] += share
    # the sweep's variants are checked apart: a variant whose record is not periodic is reported
    # (sweep_single_condition[].periodic), its life then indicative, not failed
    in_designs = {x["i"] for name in w4p.DESIGNS for x in per[name]["avail"]}
    major = [o for k, o in results.items() if k not in minor and k in in_designs]
    res["periodicity_worst_damaging"] = max(o["periodicity"] for o in major)
    loose = [(sh, o) for sh, o in minor.values() if o["periodicity"] > 0.05]
    res["periodicity_above_5pc_minor_cells"] = [
        {"case": o["label"], "periodicity": o["periodicity"], "share_of_damage": sh} for sh, o in loose]
    chk.bound("each analysed record that sets a life of the two designs is periodic (largest change of a node "
              f"position over one period / its range; all but the scatter cells with < {SHARE_MIN:g} of their "
              "design's damage)",
              res["periodicity_worst_damaging"], hi=0.05,
              why="the rainflow of a periodic record over whole periods needs the transient gone; 5 % of the range "
                  "changes the stress ranges by a few per cent at most")
    if minor:
        res["damage_share_of_cells_left_out_of_the_periodicity_check"] = minor_sum
        chk.bound("the scatter cells left out of the periodicity check hold less than 1 % of their design's damage "
                  "together (largest over the two designs)", max(minor_sum.values()), hi=0.01,
                  why="a few per cent on the stress ranges of cells that hold 1 % of the damage moves the life by "
                      "well under 1 %")
    # the buoy's yaw mode is unstable without damping (README, "Yaw damping"): the analysed records
    # must have the buoy at rest in yaw and roll (the model is symmetric about y = 0)
    res["buoy_yaw_range_max_deg"] = math.degrees(max(o["yaw_range"] for o in allouts))
    res["buoy_roll_range_max_deg"] = math.degrees(max(o["roll_range"] for o in allouts))
    if a.yaw_damping > 0:
        chk.bound("the buoy stays at rest in yaw in every analysed record (largest yaw range, deg)",
                  res["buoy_yaw_range_max_deg"], hi=0.1,
                  why="waves and current along the symmetry plane excite no yaw; a growing yaw (the undamped buoy's "
                      "instability reaches +-60-70 deg) changes the cable's curvature and life")
    res["cable_z_min_m"] = min(o["cable_z_min"] for o in allouts)
    chk.bound("the cable hangs free of the 50 m deep seabed (lowest node height)", res["cable_z_min_m"],
              lo=-w4p.DEPTH + 2 * w4p.CABLE["d"], why="the paper's free-hanging configuration")

    # the parametric sweep in the single condition
    sw_done = [(c, results[c["i"]]) for c in sweep if c["i"] in results]
    if sweep:
        res["sweep_designs_run"] = f"{len(sw_done)} of {len(sweep)}"
        res["sweep_single_condition"] = []
        for c, o in sw_done:
            lt = lifetime([o], np.array([1.0]))
            res["sweep_single_condition"].append(
                {**c["design"], "life_years": lt["life_years"], "critical_s_m": lt["critical_s_m"],
                 "critical_theta_deg": lt["critical_theta_deg"],
                 "curvature_max_per_m": float(np.max(o["curvature_max"][keep_mask(o["curvature_max"].size)])),
                 "tension_max_n": float(np.max(o["tension_max"])), "tension_min_n": float(np.min(o["tension_min"])),
                 "min_clearance_m": o["min_clearance"], "cable_z_min_m": o["cable_z_min"],
                 "periodicity": o["periodicity"], "periodic": bool(o["periodicity"] <= 0.05),
                 "scheme": o.get("scheme_used", "GenAlpha")})
        res["sweep_not_periodic"] = [f"{r['w']:.2f} kg/m, EI {r['EI']:g}, L {r['L']:g}: {r['periodicity']:.3f}"
                                     for r in res["sweep_single_condition"] if not r["periodic"]]
    res["cases_with_explicit_fallback"] = sorted(o["label"] for o in allouts if o.get("fallback_reason"))
    res["case_time_s"] = {"this_run_wall": t_cases, "cases_run_now": len(got), "cases_left_for_later": late,
                          "mean_case_wall_stored": float(np.mean([o["wall_time_s"] for o in allouts]))}
    res["checks"], res["comparisons"], res["passed"] = chk.items, chk.comparisons, chk.passed
    out = common.write_results(OUT / "results.json", res, quick=a.quick, started=started)
    paths = figures(per, res, a.quick, scatter)
    print(f"W4P cable ({out['mode']}, {out['wall_time_s']} s): hull float radius {dims['float_radius']:.2f} m, float "
          f"draft {dims['float_draft']:.2f} m, tube radius {dims['tube_radius']:.2f} m")
    for name in w4p.DESIGNS:
        cov = coverage[name]
        extra = (f" (lower bound {life_lo[name]:.3g}, scaled estimate {life_est[name]:.3g})" if name in life_lo
                 else "")
        print(f"  {name}: life {life[name]:.3g} years{extra} from {cov['cells_run']} of {cov['cells_in_range']} "
              f"cells ({100 * cov['probability_run_fraction_of_range']:.1f} % of the probability); critical s = "
              f"{per[name]['lt']['critical_s_m']:.2f} m from the WEC; single condition Hs {SINGLE[0]} Tz {SINGLE[1]}: "
              f"{single_lt[name]['life_years']:.3g} years (paper {PUBLISHED['single_condition_life_years'][name]:.2g})")
    if sweep:
        print(f"  sweep: {res['sweep_designs_run']} designs run")
    print(f"  closest approach of the cable to the hull {clearance:.2f} m ({worst.get('label')})")
    if late:
        print(f"  {late} cases left for a later run (--stop-after)")
    print(chk.report())
    for p in paths:
        print(f"  wrote {p}")
    return 0 if chk.passed and not errors else 1



def figures(per, res, quick, scatter) -> list[Path]:
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
        cov = res["scatter_coverage"][name]
        ax2.semilogy(s, np.maximum(d, 1e-30), color=c, label=f"{name}: life {per[name]['lt']['life_years']:.3g} y "
                     f"({cov['cells_run']} of {cov['cells_in_range']} cells)")
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

    if not quick:
        # each cell's share of the annual damage at the critical point, per design; blank: not run
        fig, axes = plt.subplots(1, 2, figsize=(13, 4.6))
        hs = sorted(float(h) for h in scatter.Hs if h <= HS_MAX)
        for ax, name in zip(axes, w4p.DESIGNS, strict=True):
            lt = per[name]["lt"]
            i = lt["critical_node"]
            j = int(np.argmax(lt["damage_per_year"][i]))
            share = np.full((len(hs), len(scatter.Tz)), np.nan)
            for x in per[name]["avail"]:
                r, k = hs.index(x["Hs"]), list(scatter.Tz).index(x["Tz"])
                share[r, k] = x["p"] * x["out"]["damage_rate"][i, j] * SECONDS_PER_YEAR / lt["damage_per_year"][i, j]
            im = ax.pcolormesh(np.arange(len(scatter.Tz) + 1), np.arange(len(hs) + 1),
                               np.log10(np.maximum(share, 1e-8)), cmap="viridis", vmin=-6, vmax=0)
            for r, h in enumerate(hs):
                for k in range(len(scatter.Tz)):
                    p = float(scatter.P[[float(x) for x in scatter.Hs].index(h), k])
                    if p > 0 and np.isnan(share[r, k]):
                        ax.text(k + 0.5, r + 0.5, "x", ha="center", va="center", fontsize=7, color="tab:red")
            ax.set_xticks(np.arange(len(scatter.Tz)) + 0.5, [f"{t:g}" for t in scatter.Tz], fontsize=7)
            ax.set_yticks(np.arange(len(hs)) + 0.5, [f"{h:g}" for h in hs], fontsize=7)
            ax.set_xlabel("Tz [s]")
            ax.set_ylabel("Hs [m]")
            cov = res["scatter_coverage"][name]
            ax.set_title(f"{name}: log10 share of the annual damage at s = {lt['critical_s_m']:.1f} m "
                         f"({cov['cells_run']} of {cov['cells_in_range']} cells run; x: not run)", fontsize=8)
            fig.colorbar(im, ax=ax)
        fig.tight_layout()
        paths.append(OUT / "w4p_scatter_damage.png")
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
                mark = {70.0: "o", 82.0: "^"}.get(row["L"], "s")
                ax.scatter(row[key], row["life_years"], color="tab:blue", marker=mark, s=18)
            ax.set_xlabel(lab)
            ax.set_yscale("log")
            ax.grid(alpha=0.3)
        axes[0].set_ylabel("single-condition life [years]")
        fig.suptitle(f"parametric sweep ({res['sweep_designs_run']} designs) in the single condition Hs {SINGLE[0]} m, "
                     f"Tz {SINGLE[1]} s (o: 70 m, ^: 82 m)", fontsize=10)
        fig.tight_layout()
        paths.append(OUT / "w4p_sweep.png")
        fig.savefig(paths[-1], dpi=90)
        plt.close(fig)
    return paths


if __name__ == "__main__":
    sys.exit(main())
