"""The WEC power cable of ``examples/wec_cable`` in a JONSWAP sea with a current.

Sea: JONSWAP Hs 2.5 m, Tp 8 s, gamma 3.3, heading 0 deg (waves travel toward +x, from the buoy
toward the hub), 80 components with a fixed seed, summed at the nodes; current 1 m/s toward 180 deg (against the
waves). The buoy is a small point absorber taken to follow the surface (heave RAO 1): its heave is
the wave elevation at the buoy, computed from the same sea, so the cable sees waves and buoy motion
that belong together. 150 s are simulated three ways: buoy motion only, plus waves on the cable,
plus the current; the figure compares the curvature envelopes along the cable and the buoy-end
tension.

    python examples/cable_waves/cable_waves.py            # writes docs/img/cable_waves.png
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import moorline  # noqa: E402
from moorline.core.waterkin import build_water_kinematics, fluid_kinematics  # noqa: E402
from moorline.io import read_deck  # noqa: E402
from moorline.model.water import Current, Waves  # noqa: E402
from moorline.motion import Trajectory  # noqa: E402

HERE = Path(__file__).resolve().parent
DECK = HERE.parent / "wec_cable" / "wec_cable.dat"
OUT = HERE.parents[1] / "docs" / "img" / "cable_waves.png"
DURATION = 150.0
T_SKIP = 30.0  # start-up transient left out of the envelopes


def sea(evaluation: str = "sum") -> Waves:
    return Waves.jonswap(Hs=2.5, Tp=8.0, gamma=3.3, heading=0.0, seed=7, n_components=80, evaluation=evaluation)


def buoy_motion(waves: Waves, model) -> Trajectory:
    """The buoy follows the surface at its rest position (x, y) = (0, 0)."""
    K = build_water_kinematics(waves, None, depth=model.env.depth, g=model.env.g, rho=model.env.rho)
    t = np.arange(0.0, DURATION + 0.05, 0.05)
    zeta = np.array([fluid_kinematics(K, ti, (0.0, 0.0, 0.0))[6] for ti in t])
    x0 = model.points[0].r
    X = np.column_stack([np.full_like(t, x0[0]), np.full_like(t, x0[1]), x0[2] + zeta])
    return Trajectory.from_samples(t, X, interpolation="cubic")


def run(waves_on_cable: bool, current: bool, motion: Trajectory):
    model = read_deck(DECK)
    if waves_on_cable:
        model.env.waves = sea()
    if current:
        model.env.current = Current.uniform(1.0, heading=180.0)
    t0 = time.perf_counter()
    ds = moorline.simulate(model, DURATION, motion, dt_out=0.1, progress=False)
    return ds, time.perf_counter() - t0


def main() -> None:
    logging.basicConfig(level=logging.WARNING)
    motion = buoy_motion(sea("sum"), read_deck(DECK))
    cases = {"buoy motion only": (False, False), "+ waves on the cable": (True, False),
             "+ waves + 1 m/s current": (True, True)}
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for label, (w, c) in cases.items():
        ds, wall = run(w, c, motion)
        keep = ds.time >= T_SKIP
        kmax = ds.node_curvature.where(keep, drop=True).max("time")
        s = ds.node_s
        ax1.plot(s, kmax, label=label)
        ax2.plot(ds.time, ds.line_tension_b.sel(line=1) / 1e3, lw=0.8, label=label)
        s_max = float(s[int(np.argmax(kmax.values))])
        print(f"{label:28s} max curvature {float(kmax.max()):.3f} 1/m at s = {s_max:.1f} m, "
              f"buoy tension {float(ds.line_tension_b.where(keep, drop=True).min()) / 1e3:.2f}.."
              f"{float(ds.line_tension_b.where(keep, drop=True).max()) / 1e3:.2f} kN, wall {wall:.1f} s")
    ax1.set(xlabel="arc length from the hub s [m]", ylabel="max curvature [1/m]",
            title="curvature envelope (t > 30 s)")
    ax2.set(xlabel="time [s]", ylabel="buoy-end tension [kN]", title="JONSWAP Hs 2.5 m, Tp 8 s")
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=110)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
