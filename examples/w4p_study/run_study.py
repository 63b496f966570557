"""The W4P power-cable fatigue study, end to end: 18 cable designs x the Runde scatter diagram.

    python examples/w4p_study/run_study.py [--workers N] [--scheduler ADDRESS] [--out DIR] [--figures DIR]

Runs ``study.yaml`` (the same as ``moorline sweep examples/w4p_study/study.yaml``; an interrupted
run resumes), then prints the lifetime results and draws four figures into ``docs/img``:

- ``w4p_envelopes.png``: curvature and stress envelopes along the cable, per design;
- ``w4p_damage.png``: annual fatigue damage along the cable, per design;
- ``w4p_fatigue_matrix.png``: where in the scatter diagram the baseline's damage comes from, next
  to the probability of each sea state;
- ``w4p_sensitivity.png``: fatigue life against mass, EI and length.

``--quick`` runs a reduced version (two designs, the sea states of probability >= 3 %) in
seconds, into a temporary folder unless ``--out`` is given.
"""

from __future__ import annotations

import argparse
import logging
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from moorline import plot  # noqa: E402
from moorline.post import ScatterDiagram  # noqa: E402
from moorline.studies import Study, run_sweep  # noqa: E402

HERE = Path(__file__).resolve().parent
FIGURES = HERE.parents[1] / "docs" / "img"
BASELINE = {"mass": 2.75, "EI": 350.0, "length": 70.0}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workers", type=int, default=None, help="local worker processes (default: CPUs)")
    ap.add_argument("--scheduler", help="Dask scheduler address")
    ap.add_argument("--out", help="sweep output folder (default: examples/w4p_study/out)")
    ap.add_argument("--figures", default=None, help=f"folder for the figures (default {FIGURES})")
    ap.add_argument("--quick", action="store_true", help="reduced smoke run")
    ap.add_argument("--fresh", action="store_true", help="recompute the designs already stored")
    a = ap.parse_args(argv)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s")

    study = Study.from_yaml(HERE / "study.yaml")
    baseline = dict(BASELINE)
    out = a.out
    if a.quick:
        study.parameters = {"mass": [2.75, 6.0], "EI": [350.0], "length": [70.0]}
        study.sea_states["min_probability"] = 0.03
        out = out or tempfile.mkdtemp(prefix="w4p_quick_")
    figures = Path(a.figures) if a.figures else (Path(out) if a.quick else FIGURES)
    t0 = time.perf_counter()
    res = run_sweep(study, out=out, workers=a.workers, scheduler=a.scheduler, resume=not a.fresh)
    wall = time.perf_counter() - t0
    ds, sm = res.dataset, res.summary
    base = ds.sel(baseline)

    # ------------------------------------------------------------------ report
    def where(row):
        return f"s = {row['critical_s']:.1f} m from the hub, theta = {row['critical_theta']:g} deg"

    r = sm.set_index(list(baseline)).loc[tuple(baseline.values())]
    best = sm.loc[sm.life_years.idxmax()]
    worst = sm.loc[sm.life_years.idxmin()]
    print(f"W4P cable study: {len(sm)} designs x {ds.sizes['sea_state']} sea states; sweep {res.computed} cases "
          f"computed, {res.reused} reused, {wall:.0f} s wall time "
          f"({sm.wall_time_s.sum():.0f} s of case time)")
    print(f"  baseline (mass 2.75 kg/m, EI 350 N m^2, 70 m): damage {r.damage_per_year_max:.3g} per year, "
          f"life {r.life_years:.3g} years, at {where(r)}")
    for label, row in (("longest life", best), ("shortest life", worst)):
        print(f"  {label}: mass {row['mass']:g} kg/m, EI {row['EI']:g} N m^2, length {row['length']:g} m: damage "
              f"{row.damage_per_year_max:.3g} per year, life {row.life_years:.3g} years, at {where(row)}")
    tight = sm.loc[sm.bend_radius_min_all.idxmin()]
    print(f"  smallest bend radius {tight.bend_radius_min_all:.2f} m at s = {tight.curvature_max_s:.1f} m "
          f"(mass {tight['mass']:g}, EI {tight['EI']:g}, length {tight['length']:g}; allowable "
          f"{study.post['allowable_bend_radius']} m, {int((sm.bend_radius_ok == 0).sum())} designs below it); "
          f"largest tension {sm.tension_max_all.max() / 1e3:.2f} kN")
    print(f"  compressed segments (strain < 0) in sea states of {100 * sm.compression_probability.min():.1f} to "
          f"{100 * sm.compression_probability.max():.1f} % of the time, depending on the design")
    contrib = base.damage_per_year_by_sea_state
    k = int(np.argmax(contrib.values))
    print(f"  baseline: the sea state Hs = {float(base.Hs[k]):g} m, Tz = {float(base.Tz[k]):g} s (probability "
          f"{100 * float(base.probability[k]):.2f} %) gives {100 * float(contrib[k] / contrib.sum()):.0f} % "
          "of the damage")

    # ------------------------------------------------------------------ figures
    figures.mkdir(parents=True, exist_ok=True)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(14, 4.8))
    plot.envelopes_along_arc(ds, "curvature_max", ax=ax1, highlight=baseline, legend=False,
                             ylabel="largest curvature over the sea states [1/m]")
    rb = study.post["allowable_bend_radius"]
    limit = ax1.axhline(1.0 / rb, color="tab:red", ls="--", lw=1, label=f"allowable bend radius {rb:g} m")
    ax1.legend(handles=[limit], fontsize=8, loc="upper center")
    ax1.set_title("curvature envelope per design (black: baseline)")
    plot.envelopes_along_arc(ds, "stress_max", ax=ax2, scale=1e-6, highlight=baseline, legend=False,
                             ylabel="largest tensile stress [MPa]")
    ax2.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    ax2.set_title("stress envelope (12 points around the section)")
    for ax in (ax1, ax2):
        ax.set_xlabel("arc length from the hub [m]")
    fig.tight_layout()
    paths = [figures / "w4p_envelopes.png"]
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(10, 4.6))
    plot.damage_along_arc(ds, ax=ax, highlight=baseline, legend=False)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    ax.set_xlabel("arc length from the hub [m]")
    ax.set_title("annual fatigue damage along the cable (largest around the section)")
    fig.tight_layout()
    paths.append(figures / "w4p_damage.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(14, 5.2))
    sc = ScatterDiagram.from_csv(study.sea_states["scatter"])
    plot.scatter_heatmap(base.damage_per_year_by_sea_state, ax=ax1, label="damage per year at the critical point",
                         grid=sc.to_dataarray())
    ax1.set_title(f"baseline: damage by sea state at s = {r['critical_s']:.1f} m, theta = {r['critical_theta']:g} deg")
    plot.scatter_heatmap(sc.to_dataarray(), ax=ax2, label="probability", cmap="Blues", annotate=False)
    ax2.set_title("probability of occurrence (Runde)")
    fig.tight_layout()
    paths.append(figures / "w4p_fatigue_matrix.png")
    fig.savefig(paths[-1], dpi=110)
    plt.close(fig)

    axes = plot.sensitivity(ds, "life_years", label="fatigue life [years]")
    axes[0].figure.suptitle("fatigue life of the 18 designs (grey: one line per combination of the others)")
    axes[0].figure.tight_layout()
    paths.append(figures / "w4p_sensitivity.png")
    axes[0].figure.savefig(paths[-1], dpi=110)
    plt.close(axes[0].figure)
    for p in paths:
        print(f"  wrote {p}")
    return {"result": res, "figures": paths, "wall_time": wall}


if __name__ == "__main__":
    main()
