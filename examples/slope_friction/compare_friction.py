"""Run slope_chain.dat with each seabed friction model and draw the figures of docs/seabed.md.

    python examples/slope_friction/compare_friction.py [--img DIR] [--hold S]

For each friction model (isotropic and directional saturated damping, as in MoorDyn-C and
MoorDyn-F, and moorline's stick-slip) the deck is read, its ``FrictionModel`` replaced, and the
leg simulated for the 240 s of surge.csv (3 m surge at a 60 s period); the run then carries on to
the next +3 m crest and holds the fairlead still there for ``--hold`` seconds (default 120).
All runs start from the same state, the frictionless equilibrium on the slope: the stick-slip
springs are off while the initial conditions are found, so that model finds it by itself; the
saturated models' friction would act during the dynamic relaxation (ICgenDynamic 1), so they are
given the same node positions with ``System.set_state``.

Printed, per model:

* the energy the fairlead puts into the leg per cycle, -closed integral of F_x dx over the
  fairlead's horizontal force and offset (mean of the last two cycles; hydrodynamic drag and
  seabed damping included). A fourth run, stick-slip with friction coefficients 100 times larger
  (so that nothing slides), gives the part that is not friction;
* the range of the anchor tension over the last two cycles;
* the tension spread along the part of the leg lying on the seabed, at the two extreme offsets of
  the last cycle and at the end of the hold: the raw spread max(T) - min(T), and the part of it
  that friction carries, the spread of T - w z (w the submerged weight per metre, z the segment's
  height). A frictionless leg on the seabed has dT/ds = w dz/ds exactly (normal contact), so
  T - w z is then uniform and its spread zero.

It also finds the frictionless equilibrium with SeabedContact normal and vertical and prints the
anchor and fairlead tensions and the sideways sag of the lying chain.

Written to docs/img/ (or --img): seabed_hysteresis.png, seabed_tension_profile.png,
seabed_profile.png. About a minute on one core (plus numba compilation on a first run).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import moorline  # noqa: E402
from moorline.io import read_deck  # noqa: E402
from moorline.motion import Trajectory  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import make_motion  # noqa: E402

DECK = HERE / "slope_chain.dat"
MOTION = HERE / "surge.csv"
IMG = HERE.parents[1] / "docs" / "img"

DURATION = 240.0  # s, the length of surge.csv
PERIOD = make_motion.PERIOD  # s
DT_OUT = 0.25  # s
LYING = 0.05  # m: a node counts as lying on the seabed when at most this far above it
ANCHOR = np.array([-400.0, 0.0, -59.876])  # point 1 of the deck

MODELS = {
    "isotropic": ("isotropic saturated", "tab:blue"),
    "directional": ("directional saturated", "tab:orange"),
    "stickslip": ("stick-slip", "tab:green"),
}


# ------------------------------------------------------------------------------------- runs
def load(friction, contact=None, mu_scale=1.0):
    """The deck as a Model with another friction model (and contact mode, friction scale)."""
    model = read_deck(DECK)
    model.env.friction = friction
    if contact is not None:
        model.env.contact = contact
    if mu_scale != 1.0:
        for key in ("mu", "mu_kT", "mu_kA"):
            setattr(model.env, key, getattr(model.env, key) * mu_scale)
    return model


def hold_trajectory(hold):
    """surge.csv's motion continued to the next +3 m crest, then held still for ``hold`` s."""
    t_crest = DURATION + PERIOD / 4
    t = np.arange(DURATION - 10.0, t_crest + hold + 0.5 * DT_OUT, DT_OUT)
    X = np.zeros((t.size, 3)) + make_motion.FAIRLEAD
    X[:, 0] += make_motion.surge(np.minimum(t, t_crest))
    return Trajectory.from_samples(t, X)


def run(model, traj, r_eq=None, hold=0.0):
    """Simulate ``model``; returns (system, dataset of the surge, dataset of the hold or None).
    ``r_eq``: node positions to start from instead of solving the initial conditions."""
    system = moorline.System(model)
    x0, v0 = traj.position(0.0), traj.velocity(0.0)
    if r_eq is None:
        system.init(x0, v0)
    else:
        system.init(x0, v0, solve_ic=False)
        system.set_state(line_positions=[r_eq])
    ds = moorline.simulate(system, DURATION, traj, dt_out=DT_OUT, progress=False)
    held = None
    if hold > 0:
        held = moorline.simulate(system, PERIOD / 4 + hold, hold_trajectory(hold), dt_out=DT_OUT, progress=False)
    return system, ds, held


# ---------------------------------------------------------------------------------- analysis
def submerged_weight(model):
    """Submerged weight per unit length of the deck's only line type [N/m]."""
    (lt,) = model.line_types.values()
    return (lt.w - model.env.rho * np.pi / 4 * lt.d**2) * model.env.g


def lying_segments(ds, k, bathy):
    """Boolean mask of the segments with both nodes on the seabed at output index ``k``."""
    r = ds.node_position.isel(time=k).values
    on = r[:, 2] - bathy.height(r[:, 0], r[:, 1]) < LYING
    return on[:-1] & on[1:]


def spreads(ds, k, bathy, w):
    """(raw spread, friction-carried spread [N], number of lying segments) at output index ``k``."""
    lying = lying_segments(ds, k, bathy)
    r = ds.node_position.isel(time=k).values
    zs = 0.5 * (r[:-1, 2] + r[1:, 2])
    T = ds.segment_tension.isel(time=k).values
    return np.ptp(T[lying]), np.ptp(T[lying] - w * zs[lying]), int(lying.sum())


def last_cycles(ds, n=2):
    """Mask of the output times in the last ``n`` surge cycles of the run."""
    t = ds.time.values
    return t >= t[-1] - n * PERIOD - 1e-9


def dissipated_per_cycle(ds, n=2):
    """Energy [J] the fairlead puts into the leg per cycle: -closed integral of F_x dx, mean of
    the last ``n`` cycles (the fairlead moves in x only)."""
    m = last_cycles(ds, n)
    x = ds.coupled_position.sel(dof="P2_x").values[m]
    fx = ds.coupled_force.sel(dof="P2_x").values[m]
    return -np.sum(0.5 * (fx[1:] + fx[:-1]) * np.diff(x)) / n


def extreme_indices(ds):
    """Output indices of the largest and the smallest offset in the last cycle."""
    x = ds.coupled_position.sel(dof="P2_x").values
    last = np.nonzero(last_cycles(ds, 1))[0]
    return last[np.argmax(x[last])], last[np.argmin(x[last])]


def lateral_sag(r):
    """Largest distance [m] of the line's nodes from the straight anchor-fairlead line, in plan."""
    a, b = r[0, :2], r[-1, :2]
    u = (b - a) / np.linalg.norm(b - a)
    d = r[:, :2] - a
    return float(np.max(np.abs(d[:, 0] * u[1] - d[:, 1] * u[0])))


def contact_modes():
    """Frictionless equilibrium with normal and with vertical contact: {mode: (T_anchor, T_fair,
    sag)}."""
    out = {}
    for contact in ("normal", "vertical"):
        system = moorline.System(load("stickslip", contact))  # stick-slip springs are off in the IC
        system.init()
        line = system.lines[0]
        out[contact] = (line.anchor_tension(), line.fairlead_tension(), lateral_sag(line.node_positions()))
    return out


# ------------------------------------------------------------------------------------- figures
def _arrow(ax, x, y, k, color):
    ax.annotate("", xy=(x[k + 3], y[k + 3]), xytext=(x[k], y[k]),
                arrowprops=dict(arrowstyle="-|>", color=color, lw=1.6, mutation_scale=14))


def fig_hysteresis(results, path):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.9))
    p = None
    for name, (label, color) in MODELS.items():
        ds = results[name]["ds"]
        m = last_cycles(ds)
        x = ds.coupled_position.sel(dof="P2_x").values[m]
        T = ds.line_tension_b.sel(line=1).values[m] / 1e3
        Ta = ds.line_tension_a.sel(line=1).values[m] / 1e3
        axes[0].plot(x, T, color=color, lw=1.3, label=f"{label}: {results[name]['W'] / 1e3:.1f} kJ/cycle")
        if p is None:  # one straight line for all models, so that the loops' widths show
            p = np.polyfit(x, T, 1)
        axes[1].plot(x, T - np.polyval(p, x), color=color, lw=1.3, label=label)
        axes[2].plot(x, Ta, color=color, lw=1.6, label=label)
        # direction of travel, on the last cycle
        m1 = last_cycles(ds, 1)
        x1 = ds.coupled_position.sel(dof="P2_x").values[m1]
        n = len(x1)
        if name == "stickslip":
            T1 = ds.line_tension_b.sel(line=1).values[m1] / 1e3 - np.polyval(p, x1)
            for k in (n // 8, 5 * n // 8):
                _arrow(axes[1], x1, T1, k, color)
        if name == "isotropic":
            Ta1 = ds.line_tension_a.sel(line=1).values[m1] / 1e3
            for k in (n // 8, 5 * n // 8):
                _arrow(axes[2], x1, Ta1, k, color)
    for ax in axes:
        ax.set_xlabel("fairlead offset x [m]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fairlead tension [kN]")
    axes[0].set_title("fairlead tension", fontsize=10)
    axes[0].legend(loc="upper left", fontsize=8, title="energy put in per cycle", title_fontsize=8)
    axes[1].set_ylabel(f"fairlead tension - ({p[0]:.2f} kN/m x + {p[1]:.1f} kN) [kN]")
    axes[1].set_title("fairlead tension minus a common straight line", fontsize=10)
    axes[1].legend(loc="upper center", fontsize=8)
    axes[2].set_ylabel("anchor tension [kN]")
    axes[2].set_title("anchor tension", fontsize=10)
    axes[2].legend(loc="upper left", fontsize=8)
    fig.suptitle("slope_chain.dat: last two cycles of the 3 m, 60 s surge (arrows: direction of travel)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def fig_tension_profile(results, w, path):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.9), sharey=True)
    for ax, (name, (label, color)) in zip(axes, MODELS.items(), strict=True):
        res = results[name]
        ds = res["ds"]
        s = ds.segment_s.values
        ax.plot(s, ds.segment_tension.isel(time=0).values / 1e3, color="0.5", lw=1.1, ls=":",
                label="start (frictionless equilibrium)")
        kp, km = extreme_indices(ds)
        for k, ls, what in ((kp, "-", "offset +3 m"), (km, "--", "offset -3 m")):
            ax.plot(s, ds.segment_tension.isel(time=k).values / 1e3, color=color, ls=ls, lw=1.6,
                    label=f"{what}, moving (t = {ds.time.values[k]:.0f} s)")
        if res["held"] is not None:
            h = res["held"]
            ax.plot(s, h.segment_tension.isel(time=-1).values / 1e3, color="k", lw=1.0,
                    label=f"offset +3 m, held still to t = {h.time.values[-1]:.0f} s")
        lying = lying_segments(ds, kp, res["bathy"])
        ax.axvspan(s[lying].min(), s[lying].max(), color=color, alpha=0.08, lw=0)
        ax.text(0.5 * (s[lying].min() + s[lying].max()), 0.03, "lying on the seabed at +3 m", ha="center",
                va="bottom", transform=ax.get_xaxis_transform(), fontsize=8, color="0.3")
        ax.set_title(label, fontsize=10)
        ax.set_xlabel("arc length from the anchor s [m]")
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=7.5)
    axes[0].set_ylabel("segment tension [kN]")
    axes[0].set_ylim(0, 150)
    fig.suptitle(f"tension along the leg (without friction it rises by w dz along the seabed, w = {w:.0f} N/m)",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def fig_profile(results, path):
    res = results["stickslip"]
    ds, bathy = res["ds"], res["bathy"]
    kp, km = extreme_indices(ds)
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(11, 8.0), height_ratios=(1.0, 0.85))
    xs = np.linspace(-450.0, 50.0, 501)
    r0 = ds.node_position.isel(time=0).values
    # side view: the seabed under the leg (along its plan-view path) and along y = 0
    ax.fill_between(xs, bathy.height(xs, np.interp(xs, r0[:, 0], r0[:, 1])), -70.0, color="tan", alpha=0.6,
                    lw=0, label="seabed under the leg")
    ax.plot(xs, bathy.height(xs, np.zeros_like(xs)), color="sienna", lw=0.9, ls="--", label="seabed at y = 0")
    ax.axhline(0.0, color="tab:blue", lw=0.8)
    ax.text(-200, 0.8, "still-water level", fontsize=8, color="tab:blue")
    for k, style, what in ((0, dict(color="k", lw=1.6, marker=".", ms=3), "start (frictionless equilibrium)"),
                           (kp, dict(color="tab:green", lw=1.1), "offset +3 m"),
                           (km, dict(color="tab:red", lw=1.1, ls="--"), "offset -3 m")):
        r = ds.node_position.isel(time=k).values
        ax.plot(r[:, 0], r[:, 2], label=f"leg, {what}", **style)
    ax.plot(*ANCHOR[[0, 2]], "kv", ms=7)
    ax.annotate("anchor", ANCHOR[[0, 2]], xytext=(-395, -66), fontsize=8)
    ax.annotate("fairlead (surges 3 m)", (0.0, -8.0), xytext=(-110, -14), fontsize=8,
                arrowprops=dict(arrowstyle="->", lw=0.8))
    ax.set_xlim(-450, 50)
    ax.set_ylim(-70, 4)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title("side view (vertical scale exaggerated)", fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(0.0, 0.93), fontsize=8)
    ax.grid(alpha=0.3)
    # plan view with depth contours
    gx, gy = np.meshgrid(np.linspace(-450, 50, 201), np.linspace(-60, 60, 121))
    cs = bx.contourf(gx, gy, -bathy.height(gx, gy), levels=np.arange(34, 66, 2), cmap="YlGnBu")
    fig.colorbar(cs, ax=bx, label="water depth [m]", fraction=0.05, pad=0.02)
    bx.plot(r0[:, 0], r0[:, 1], "k.-", lw=1.4, ms=3, label="leg at the start (frictionless equilibrium)")
    bx.plot([ANCHOR[0], 0.0], [0.0, 0.0], color="0.3", lw=0.9, ls=":", label="straight anchor-fairlead line")
    bx.annotate("", xy=(-250, -48), xytext=(-250, -22), arrowprops=dict(arrowstyle="-|>", color="k", lw=1.0))
    bx.text(-245, -40, "down the 3 % cross-slope", fontsize=8)
    bx.set_xlabel("x [m]")
    bx.set_ylabel("y [m]")
    bx.set_title("plan view over the bathymetry (slope_bathymetry.txt, bilinear)", fontsize=10)
    bx.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


# ------------------------------------------------------------------------------------------ main
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--img", type=Path, default=IMG, help="folder for the PNG files (default docs/img)")
    ap.add_argument("--hold", type=float, default=120.0, help="seconds held still at +3 m after the surge "
                    "(default 120)")
    args = ap.parse_args(argv)
    args.img.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()
    traj = Trajectory.from_csv(MOTION)

    results = {}
    r_eq = None
    for name in ("stickslip", "isotropic", "directional"):  # stick-slip first: it finds the common start
        t0 = time.perf_counter()
        system, ds, held = run(load(name), traj, r_eq, args.hold)
        if r_eq is None:
            r_eq = ds.node_position.isel(time=0).values.copy()
        results[name] = dict(system=system, ds=ds, held=held, bathy=system.model.env.bathymetry,
                             W=dissipated_per_cycle(ds))
        print(f"  {name}: {DURATION + (PERIOD / 4 + args.hold if args.hold > 0 else 0):g} s simulated in "
              f"{time.perf_counter() - t0:.1f} s")
    t0 = time.perf_counter()
    _, ds_stuck, _ = run(load("stickslip", mu_scale=100.0), traj)
    W_stuck = dissipated_per_cycle(ds_stuck)
    print(f"  stickslip, friction x 100: {DURATION:g} s simulated in {time.perf_counter() - t0:.1f} s")
    modes = contact_modes()

    model = results["stickslip"]["system"].model
    w = submerged_weight(model)
    print(f"\nsubmerged weight w = {w:.1f} N/m; w times the rise from anchor to fairlead = "
          f"{w * (make_motion.FAIRLEAD[2] - ANCHOR[2]) / 1e3:.1f} kN")
    print("\nfrictionless equilibrium (initial conditions):")
    for contact, (ta, tf, sag) in modes.items():
        print(f"  SeabedContact {contact:<8}: anchor tension {ta / 1e3:6.1f} kN, fairlead tension {tf / 1e3:6.1f} kN, "
              f"difference {(tf - ta) / 1e3:5.1f} kN, sideways sag of the lying chain {sag:5.1f} m")
    ds0 = results["stickslip"]["ds"]
    raw, fric, n = spreads(ds0, 0, results["stickslip"]["bathy"], w)
    print(f"  normal contact, lying part ({n} segments): tension spread {raw / 1e3:.1f} kN, of which friction "
          f"carries {fric / 1e3:.2f} kN")

    print("\nlast two surge cycles, and the hold at +3 m:")
    head = ("model", "energy in", "anchor tension", "lying-part tension spread, raw / carried by friction [kN]")
    print(f"  {head[0]:<23}{head[1]:>11}{head[2]:>17}   {head[3]}")
    print(f"  {'':<23}{'[kJ/cycle]':>11}{'min-max [kN]':>17}   {'offset +3 m':>17}{'offset -3 m':>17}"
          f"{'held at +3 m':>17}")
    for name, (label, _) in MODELS.items():
        res = results[name]
        ds = res["ds"]
        ta = ds.line_tension_a.sel(line=1).values[last_cycles(ds)] / 1e3
        cols = []
        kp, km = extreme_indices(ds)
        cases = [(ds, kp), (ds, km)] + ([(res["held"], res["held"].time.size - 1)] if res["held"] is not None else [])
        for d, k in cases:
            raw, fric, _ = spreads(d, k, res["bathy"], w)
            cols.append(f"{raw / 1e3:5.1f} / {fric / 1e3:4.1f}")
        print(f"  {label:<23}{res['W'] / 1e3:11.3f}{f'{ta.min():.1f}-{ta.max():.1f}':>17}   "
              + "".join(f"{c:>17}" for c in cols))
    print(f"  {'stick-slip, mu x 100':<23}{W_stuck / 1e3:11.3f}   (nothing slides: drag and seabed damping only)")
    if args.hold > 0:
        after = [0.0, 10.0, 30.0, 60.0, args.hold]
        print("\nlying-part tension spread carried by friction [kN] while held at +3 m, after")
        print(f"  {'':<23}" + "".join(f"{f'{a:g} s':>9}" for a in after) + "   anchor tension at the end [kN]")
        for name, (label, _) in MODELS.items():
            h = results[name]["held"]
            t_crest = DURATION + PERIOD / 4
            vals = [spreads(h, int(np.argmin(np.abs(h.time.values - t_crest - a))), results[name]["bathy"], w)[1]
                    for a in after]
            ta = float(h.line_tension_a.sel(line=1).values[-1])
            print(f"  {label:<23}" + "".join(f"{v / 1e3:9.1f}" for v in vals) + f"   {ta / 1e3:.1f}")
    # which way the fairlead loop runs: tension while moving out minus tension while moving back
    ds = results["stickslip"]["ds"]
    m = last_cycles(ds, 1)
    x = ds.coupled_position.sel(dof="P2_x").values[m]
    T = ds.line_tension_b.sel(line=1).values[m]
    v = np.gradient(x)
    near0 = np.abs(x) < 0.5
    print(f"\nstick-slip fairlead tension near zero offset: {T[near0 & (v > 0)].mean() / 1e3:.1f} kN moving out, "
          f"{T[near0 & (v < 0)].mean() / 1e3:.1f} kN moving back")

    fig_hysteresis(results, args.img / "seabed_hysteresis.png")
    fig_tension_profile(results, w, args.img / "seabed_tension_profile.png")
    fig_profile(results, args.img / "seabed_profile.png")
    print()
    for f in ("seabed_hysteresis.png", "seabed_tension_profile.png", "seabed_profile.png"):
        print(f"wrote {args.img / f}")
    print(f"total wall time {time.perf_counter() - wall:.1f} s")


if __name__ == "__main__":
    main()
