"""Write surge.csv: the floater's motion imposed on the three coupled fairleads of
catenary_3line.dat (coupled DOF order: P4 x y z, P5 x y z, P6 x y z).

The floater surges 6 m at a 20 s period and heaves 1 m at 10 s, both ramped in over 10 s with a
quintic smoothstep; the fairleads move rigidly with it (no rotation). Sampled every 0.1 s for 120 s.
"""

from pathlib import Path

import numpy as np

FAIRLEADS = np.array([[45.0, 0.0, -14.0], [-22.5, 38.971, -14.0], [-22.5, -38.971, -14.0]])


def floater_offset(t):
    u = np.clip(t / 10.0, 0.0, 1.0)
    ramp = u**3 * (6 * u**2 - 15 * u + 10)
    surge = 6.0 * ramp * np.sin(2 * np.pi * t / 20.0)
    heave = 1.0 * ramp * np.sin(2 * np.pi * t / 10.0)
    return surge, heave


OUT = Path(__file__).with_name("surge.csv")


def main(path=OUT, duration=120.0, dt=0.1):
    t = np.round(np.arange(0.0, duration + 0.5 * dt, dt), 10)
    surge, heave = floater_offset(t)
    cols = [t]
    names = ["t"]
    for k, (x, y, z) in enumerate(FAIRLEADS, start=4):
        cols += [x + surge, np.full_like(t, y), z + heave]
        names += [f"P{k}_x", f"P{k}_y", f"P{k}_z"]
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(names), comments="", fmt="%.6f")
    return path


if __name__ == "__main__":
    print(main())
