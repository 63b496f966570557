"""Write surge.csv: the motion imposed on the coupled fairlead (point 2) of slope_chain.dat
(coupled DOF order: P2 x y z).

A slow surge oscillation of 3 m amplitude at a 60 s period, ramped in over the first 30 s with a
quintic smoothstep (so position, velocity and acceleration start at zero); y and z stay at the
deck position. Sampled every 0.25 s for 240 s (four periods; the last two are fully developed).
"""

from pathlib import Path

import numpy as np

FAIRLEAD = np.array([0.0, 0.0, -8.0])
AMPLITUDE = 3.0  # m
PERIOD = 60.0  # s
RAMP = 30.0  # s


OUT = Path(__file__).with_name("surge.csv")


def surge(t):
    u = np.clip(np.asarray(t) / RAMP, 0.0, 1.0)
    ramp = u**3 * (6 * u**2 - 15 * u + 10)
    return AMPLITUDE * ramp * np.sin(2 * np.pi * np.asarray(t) / PERIOD)


def main(path=OUT, duration=240.0, dt=0.25):
    t = np.round(np.arange(0.0, duration + 0.5 * dt, dt), 10)
    x, y, z = FAIRLEAD
    cols = [t, x + surge(t), np.full_like(t, y), np.full_like(t, z)]
    np.savetxt(path, np.column_stack(cols), delimiter=",", header="t,P2_x,P2_y,P2_z", comments="", fmt="%.6f")
    return path


if __name__ == "__main__":
    print(main())
