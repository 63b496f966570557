"""Run the WEC power-cable example and plot the curvature along the cable.

    python examples/wec_cable/plot_curvature.py [--out docs/img/cable_curvature.png]

Left: cable profiles at eight instants of the last wave period, over the seabed. Right: the
curvature envelope along the arc length (min/max over the last 48 s, and its mean), with the
minimum bend radius reported: the quantity a cable designer checks against the allowable bend
radius. The hub end is clamped to its connector, so the curvature there is not zero.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import moorline  # noqa: E402

HERE = Path(__file__).resolve().parent


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(HERE.parents[1] / "docs" / "img" / "cable_curvature.png"))
    ap.add_argument("--duration", type=float, default=96.0)
    a = ap.parse_args(argv)
    sys = moorline.System.from_file(HERE / "wec_cable.dat")
    motion = moorline.Trajectory.from_csv(HERE / "buoy_motion.csv", n_dof=sys.n_coupled_dof)
    ds = moorline.simulate(sys, a.duration, motion, dt_out=0.1, progress=False)
    last = ds.sel(time=slice(a.duration - 48.0, None))
    s = ds.node_s.values
    kappa = last.node_curvature.values
    kmax = kappa.max(axis=0)
    i = int(np.argmax(kmax))
    print(f"largest curvature {kmax[i]:.4f} 1/m (minimum bend radius {1 / kmax[i]:.2f} m) at s = {s[i]:.1f} m "
          f"from the hub; at the clamped hub end {kmax[0]:.4f} 1/m")
    print(f"tension at the buoy: {last.line_tension_b.min().item() / 1e3:.2f} to "
          f"{last.line_tension_b.max().item() / 1e3:.2f} kN")

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    period = 8.0
    for k, t in enumerate(np.linspace(a.duration - period, a.duration, 8, endpoint=False)):
        r = ds.node_position.sel(time=t, method="nearest").values
        ax1.plot(r[:, 0], r[:, 2], color=plt.cm.viridis(k / 8), lw=1.2)
    ax1.axhline(-50.0, color="saddlebrown", lw=2, label="seabed")
    ax1.axhline(0.0, color="steelblue", lw=1, ls=":", label="still water")
    ax1.set_xlabel("x [m]")
    ax1.set_ylabel("z [m]")
    ax1.set_title("cable profiles over one 8 s wave period")
    ax1.set_aspect("equal")
    ax1.legend(loc="upper right", fontsize=8)
    ax2.fill_between(s, kappa.min(axis=0), kmax, color="tab:orange", alpha=0.35, label="min-max envelope")
    ax2.plot(s, kappa.mean(axis=0), color="tab:orange", lw=1.5, label="mean")
    ax2.plot(s[i], kmax[i], "kv", label=f"max {kmax[i]:.3f} 1/m (R = {1 / kmax[i]:.1f} m)")
    ax2.set_xlabel("arc length from the hub [m]")
    ax2.set_ylabel("curvature [1/m]")
    ax2.set_title("curvature along the cable, last 48 s")
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    out = Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
